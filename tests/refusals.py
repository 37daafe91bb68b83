"""What a library boundary owes a bad value: the project's own error, whose message opens with
the name of the parameter that was given it."""

from __future__ import annotations

from collections.abc import Callable, Mapping

import pytest

from diffbot.errors import DiffbotError, ParameterError


def assert_refused(
    make: Callable[..., object],
    given: Mapping[str, object],
    named: str,
    error: type[DiffbotError] = ParameterError,
) -> None:
    """``make(**given)`` raises ``error`` with a message that starts with ``named``."""
    with pytest.raises(error) as caught:
        make(**given)
    assert str(caught.value).startswith(named), str(caught.value)
