"""Options that reach a command as one object (the robot options, the output options)."""

from __future__ import annotations

import functools
from collections.abc import Callable, Sequence
from typing import Any, TypeVar

__all__ = ["F", "option_group"]

F = TypeVar("F", bound=Callable[..., Any])


def option_group(
    options: Sequence[Callable[[Any], Any]], name: str, build: Callable[[dict[str, Any]], object]
) -> Callable[[F], F]:
    """A decorator adding ``options`` to a command, which receives them as one object.

    ``build`` takes the options' values out of the keyword arguments (popping them) and
    returns the object, passed to the command as ``name``.
    """

    def decorate(command: F) -> F:
        def wrapper(**kwargs: Any) -> Any:
            return command(**{name: build(kwargs)}, **kwargs)

        functools.update_wrapper(wrapper, command)  # keeps options declared below this one
        decorated: Any = wrapper
        for option in reversed(options):
            decorated = option(decorated)
        return decorated  # type: ignore[no-any-return]

    return decorate
