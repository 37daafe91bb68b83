"""What the live commands (``node odom|ik|robot``, ``drive``) share: the options every one takes
and running a node until a signal, with a status line on a terminal."""

from __future__ import annotations

import sys
from collections.abc import Callable
from typing import TYPE_CHECKING

import click

from diffbot.commands.options import POSITIVE, F

if TYPE_CHECKING:
    from diffbot.live.transport import Node

__all__ = ["announce_option", "duration_option", "run_node"]


def duration_option(command: F) -> F:
    """``--duration S``: stop by itself after S seconds (default: run until Ctrl-C)."""
    return click.option(
        "--duration",
        type=POSITIVE,
        metavar="S",
        help="Stop after this many seconds (default: run until Ctrl-C, SIGTERM or SIGHUP).",
    )(command)


def announce_option(command: F) -> F:
    """``--announce``: list the node on ``ros_discovery_info`` so that ``ros2 node list`` names
    it (GID layout of ``ROS_DISTRO``, default jazzy)."""
    return click.option(
        "--announce",
        is_flag=True,
        help="Publish the node on ros_discovery_info, so that 'ros2 node list' names it "
        "(the layout of ROS_DISTRO's, default jazzy).",
    )(command)


def run_node(
    node: Node,
    label: str,
    status: Callable[[], str],
    *,
    quiet: bool,
    duration: float | None,
    announce: bool = False,
) -> None:
    """Spin ``node`` until Ctrl-C, SIGTERM, SIGHUP or ``duration`` seconds, then destroy it and
    print its final ``status()`` on stderr (refreshed every second on a terminal meanwhile);
    with ``announce``, list it on ``ros_discovery_info`` first."""
    if announce:
        node.announce()
    live = not quiet and sys.stderr.isatty()
    if live:
        node.create_timer(
            1.0, lambda: click.echo(f"\r{label}: {status()}\x1b[K", err=True, nl=False)
        )
    try:
        node.spin(duration)
    except (KeyboardInterrupt, SystemExit):
        pass  # a signal is how a node is asked to end: a normal end
    finally:
        node.destroy_node()
        click.echo(f"{chr(13) if live else ''}{label}: {status()}", err=True)
