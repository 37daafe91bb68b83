"""Options of closing the loop and of disturbed simulated robots, shared by ``simulate``,
``node robot`` and ``drive``."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, TypeVar

import click

from diffbot.closed_loop import POSE_SOURCES
from diffbot.commands.options import MIN_COMMAND_RATE, FiniteFloat, NumberPair
from diffbot.commands.shown_defaults import choice_option, name_option
from diffbot.follow import MAX_LEAD
from diffbot.simulation import MAX_DELAY

F = TypeVar("F", bound=Callable[..., Any])

__all__ = ["Fraction", "disturbance_options", "follow_options", "live_follow_options"]


class Fraction(FiniteFloat):
    """A share from 0 up to, but not including, 1."""

    name = "fraction"

    def __init__(self) -> None:
        super().__init__(0.0)

    def convert(
        self, value: Any, param: click.Parameter | None, ctx: click.Context | None
    ) -> float:
        number = super().convert(value, param, ctx)
        if number >= 1.0:
            self.fail(f"{value!r} must be below 1 (a share of all)", param, ctx)
        return number


def disturbance_options(command: F) -> F:
    """``--motor-lag S``, ``--latency S``, ``--drop FRACTION``, ``--slip FRACTION``: what a
    simulated base does besides what it is told, for ``simulate`` and ``node robot`` alike
    (seeded by ``--seed``)."""
    for name, meta, text, kind in reversed(
        (
            (
                "--motor-lag",
                "S",
                "Time constant of each wheel's first-order velocity response (s).",
                FiniteFloat(0.0, maximum=MAX_DELAY),
            ),
            (
                "--latency",
                "S",
                "Delay from a command to the motors (s).",
                FiniteFloat(0.0, maximum=MAX_DELAY),
            ),
            (
                "--drop",
                "FRACTION",
                "Share of commands lost, below 1 (seeded by --seed).",
                Fraction(),
            ),
            (
                "--slip",
                "FRACTION",
                "Mean share of each wheel's travel lost to slip, below 1 (seeded by --seed).",
                Fraction(),
            ),
        )
    ):
        command = click.option(name, type=kind, default=0.0, metavar=meta, help=text)(command)
    return command


def _lead_option(default: float | None, text: str) -> Callable[[F], F]:
    return click.option(
        "--lead",
        type=FiniteFloat(0.0, maximum=MAX_LEAD),
        default=default,
        show_default=default is not None,
        metavar="S",
        help=text,
    )


def follow_options(command: F) -> F:
    """``--follow [tracking|pure-pursuit]``, ``--lead S``, ``--control-rate HZ``,
    ``--pose-source odom|truth``, ``--pose-noise M,DEG``: a simulated run closed by a
    follower."""
    command = click.option(
        "--pose-noise",
        type=NumberPair("M,DEG", "m, degrees", bounds=(0.0, 1e3)),
        default=None,
        metavar="M,DEG",
        help="Standard deviations of the noise on the true pose given to the follower with "
        "--pose-source truth (m, degrees); default none.",
    )(command)
    command = choice_option(
        "--pose-source",
        choices=POSE_SOURCES,
        default="odom",
        help="What the follower is given: the robot's wheel odometry, or its true pose (with "
        "--pose-noise), as motion capture or localization gives it.",
    )(command)
    command = click.option(
        "--control-rate",
        type=FiniteFloat(MIN_COMMAND_RATE),
        default=20.0,
        show_default=True,
        metavar="HZ",
        help="Commands per second of the follower or of the open-loop commands on a disturbed "
        "robot (Hz), at most --rate.",
    )(command)
    command = _lead_option(
        None,
        "With --follow tracking: act on the pose predicted this far ahead (s) from the commands "
        f"not yet carried out, against the plan this far ahead; 0 to {MAX_LEAD:g}. Default: "
        "the simulated robot's delay, --latency plus --motor-lag plus half a control period.",
    )(command)
    return _follow_option(
        "Close the loop: follow the plan from the pose (tracking: the timed plan, the default, "
        "predicted --lead ahead; pure-pursuit: its path, untimed)."
    )(command)


def _follow_option(text: str) -> Callable[[F], F]:
    return click.option(
        "--follow",
        type=click.Choice(["tracking", "pure-pursuit"]),
        is_flag=False,
        flag_value="tracking",
        default=None,
        help=text,
    )


def live_follow_options(command: F) -> F:
    """``--follow [tracking|pure-pursuit]``, ``--lead S``, ``--odom-topic``, ``--pose-topic``,
    ``--pose-timeout S``: a live drive closed by a follower on the robot's pose."""
    command = _lead_option(
        0.0,
        "With --follow tracking: act on the pose predicted this far ahead (s) from the commands "
        f"not yet carried out, against the plan this far ahead; 0 to {MAX_LEAD:g}. Give about "
        "the robot's command latency plus its motor lag plus half a control period.",
    )(command)
    command = click.option(
        "--pose-timeout",
        type=FiniteFloat(0.0, open_min=True, maximum=MAX_DELAY),
        default=0.5,
        show_default=True,
        metavar="S",
        help="With --follow: command zero while no pose came for this long (s).",
    )(command)
    command = click.option(
        "--pose-topic",
        default=None,
        metavar="TOPIC",
        help="With --follow: take the pose from this geometry_msgs/PoseStamped or "
        "PoseWithCovarianceStamped topic (localization, motion capture) instead of --odom-topic.",
    )(command)
    command = name_option(
        "--odom-topic",
        None,
        "With --follow: the nav_msgs/Odometry topic of the robot's pose [the controllers file's "
        "diff-drive controller's /<name>/odom, else the description's Gazebo classic diff-drive "
        "plugin's, else odom].",
    )(command)
    return _follow_option(
        "Close the loop: follow the plan from the robot's pose, published on --cmd-vel at --rate "
        "(tracking: the timed plan, the default; pure-pursuit: its path, untimed). The plan "
        "starts at the first pose received."
    )(command)
