"""Options whose default ``--help`` shows: one of a few choices, or a name (a topic, a frame)."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import TypeVar

import click

__all__ = ["choice_option", "name_option"]

_F = TypeVar("_F", bound=Callable[..., object])


def choice_option(
    *decls: str, choices: Sequence[str], default: str, help: str
) -> Callable[[_F], _F]:
    """An option taking one of ``choices`` (as spelled), ``default`` when not given.

    Args:
        decls: the option's flag, and the parameter's name when it is not the flag's.
        choices: the words it takes.
        default: the word it has when not given, one of ``choices``.
        help: its help text.
    """
    if default not in choices:
        raise ValueError(f"the default {default!r} is not one of {list(choices)}")
    return click.option(
        *decls, type=click.Choice(list(choices)), default=default, show_default=True, help=help
    )


def name_option(
    flag: str, default: str | None, help: str, *, metavar: str = "TOPIC"
) -> Callable[[_F], _F]:
    """An option taking a name, ``default`` when not given.

    Args:
        flag: the option's flag.
        default: the name it has when not given (None: the command finds it, and ``help``
            says how).
        help: its help text.
        metavar: what ``--help`` calls the value (TOPIC, FRAME).
    """
    return click.option(flag, default=default, show_default=True, metavar=metavar, help=help)
