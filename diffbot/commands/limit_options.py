"""The body velocity limit options, ``--max-linear`` and ``--max-angular``, for every command
that makes a plan or a command."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import click

from diffbot.commands.options import POSITIVE

__all__ = ["body_limit_option", "body_limit_options"]

#: --max-linear and --max-angular; the command receives ``max_linear`` and ``max_angular``.
body_limit_options = [
    click.option(
        "--max-linear",
        type=POSITIVE,
        metavar="M/S",
        help="Highest linear velocity (m/s), as the controller's linear.x.max_velocity (read "
        "from the controllers file when not given; its min_velocity bounds reverse motion).",
    ),
    click.option(
        "--max-angular",
        type=POSITIVE,
        metavar="RAD/S",
        help="Highest angular velocity (rad/s), as the controller's angular.z.max_velocity.",
    ),
]


def body_limit_option(index: int) -> Callable[[Callable[..., Any]], Callable[..., Any]]:
    """--max-linear (``index`` 0) or --max-angular (1), to decorate a command with."""
    option: Callable[[Callable[..., Any]], Callable[..., Any]] = body_limit_options[index]
    return option
