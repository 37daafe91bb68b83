"""Settings objects made from the running command's own options, named once."""

from __future__ import annotations

from collections.abc import Callable
from typing import TypeVar

import click

__all__ = ["from_options"]

T = TypeVar("T")


def from_options(make: Callable[..., T], names: str, **values: object) -> T:
    """``make(**values)``, given besides each option of the running command named in ``names``
    (space-separated) under its own name, as the command parsed it: for settings whose fields
    are the command's options."""
    params = click.get_current_context().params
    missing = [name for name in names.split() if name not in params]
    if missing:
        raise LookupError(f"the command has no option {' or '.join(missing)}")
    return make(**{name: params[name] for name in names.split()}, **values)
