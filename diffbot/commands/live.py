"""What the live commands (``node odom|ik|robot``, ``drive``) share: the options every one takes
and running a node until a signal, with a status line on a terminal."""

from __future__ import annotations

import sys
from collections.abc import Callable
from typing import TYPE_CHECKING

import click

from diffbot.commands.options import (
    MAX_PUBLISH_RATE,
    MIN_COMMAND_RATE,
    F,
    FiniteFloat,
    fail,
)
from diffbot.numbers import MAX_PLAN_DURATION, shown

if TYPE_CHECKING:
    from diffbot.live.transport import Node

#: A live node's rate (Hz): from one update per longest plan to the fastest publisher's.
RATE = FiniteFloat(MIN_COMMAND_RATE, maximum=MAX_PUBLISH_RATE)
#: How often odometry may be published (Hz): at least once per longest plan, at most as often
#: as a node runs its timer (an open loop publishes on one).
PUBLISH_RATE = RATE
#: A time a live command waits (s): up to the longest plan.
WAIT = FiniteFloat(0.0, maximum=MAX_PLAN_DURATION)
#: How long a live command runs before it stops by itself (s): up to the longest plan.
DURATION = FiniteFloat(0.0, open_min=True, maximum=MAX_PLAN_DURATION)

__all__ = [
    "PUBLISH_RATE",
    "RATE",
    "WAIT",
    "checked_frame",
    "checked_topic",
    "checked_topics",
    "duration_option",
    "run_node",
]


def checked_topic(option: str, name: str) -> str:
    """``name`` when a live node can use it as a topic (ROS name rules, length, encoding),
    else one error naming ``option``."""
    from diffbot.live.names import topic_problem

    problem = topic_problem(name)
    if problem is not None:
        fail(f"{option} {shown(name)} is not a valid ROS topic name: it {problem}")
    return name


def checked_topics(**given: str | None) -> None:
    """Each topic given, by its option's name (``left_topic`` for ``--left-topic``), as
    :func:`checked_topic` checks it; None: not given, found later."""
    for name, topic in given.items():
        if topic is not None:
            checked_topic("--" + name.replace("_", "-"), topic)


def checked_frame(option: str, name: str | None) -> str | None:
    """``name`` (None passes) when it is a usable frame id (length, encoding), else one error
    naming ``option``."""
    from diffbot.live.names import frame_problem

    problem = None if name is None else frame_problem(name)
    if problem is not None:
        fail(f"{option} {shown(name)} is not a usable frame id: it {problem}")
    return name


def duration_option(command: F) -> F:
    """``--duration S``: stop by itself after S seconds (default: run until Ctrl-C)."""
    return click.option(
        "--duration",
        type=DURATION,
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
    make: Callable[[], Node],
    label: str,
    *,
    quiet: bool,
    duration: float | None,
    announce: bool = False,
) -> None:
    """Make a node with ``make()``, say on stderr what it reads, publishes and serves, and spin
    it until Ctrl-C, SIGTERM, SIGHUP or ``duration`` seconds, then destroy it and print its
    final status on stderr (refreshed every second on a terminal meanwhile); with ``announce``,
    list it on ``ros_discovery_info`` first. ``quiet``: neither line but the final status.

    From the node's making to the status line, an ending signal only asks the node to stop
    (:mod:`diffbot.live.signals`): the node ends cleanly wherever the signal comes, and a
    signal is the normal end of a node's run (exit code 0). From then on the command line's
    process only exits, with ending signals ignored.
    """
    from diffbot.live.signals import deferred

    with deferred(deliver=False, ends_run=True):
        node = make()
        try:
            if announce:
                node.announce()
            if not quiet:
                click.echo(f"{label}: {node.describe()}", err=True)
            live = not quiet and sys.stderr.isatty()
            if live:
                node.create_timer(
                    1.0,
                    lambda: click.echo(f"\r{label}: {node.status()}\x1b[K", err=True, nl=False),
                )
            node.spin(duration)
        finally:
            node.destroy_node()
        click.echo(f"{chr(13) if live else ''}{label}: {node.status()}", err=True)
