"""The options that say which plan to make, shared by ``plan`` and ``simulate``."""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import click

from diffbot.commands.options import POSITIVE, fail, option_group
from diffbot.kinematics import DiffDriveParams, rad_s_from_rpm
from diffbot.planfile import load_plan, parse_plan
from diffbot.trajectory import EXAMPLES, Plan, Segment
from diffbot.trajectory import plan as make_plan

__all__ = [
    "PLAN_FORMATS",
    "PLAN_SUFFIXES",
    "PlanInput",
    "PlanOptions",
    "check_topic",
    "join_plan_arguments",
    "plan_input",
    "plan_input_options",
]

#: File name endings read as plan files rather than plan text.
PLAN_SUFFIXES = (".yaml", ".yml", ".json", ".txt")
PLAN_FORMATS = ("table", "json", "csv", "twist", "wheels", "ros2")
_TOPIC_NAME = r"(~/|/)?[A-Za-z_][A-Za-z0-9_]*(/[A-Za-z_][A-Za-z0-9_]*)*"


@dataclass(frozen=True)
class PlanInput:
    """The plan a command was given: its segments, a label for people, its file if any."""

    segments: list[Segment]
    label: str
    path: Path | None


def plan_input(tokens: Sequence[str], example: str | None) -> PlanInput:
    """The plan named by positional tokens (text or a file) or ``--example``."""
    for token in tokens:
        if token.startswith("--") or (
            token.startswith("-") and len(token) > 1 and not token[1].isdigit() and token[1] != "."
        ):
            fail(f"no such option: {token}")
    if example is not None:
        if tokens:
            fail(f"give a plan (SPEC or FILE) or --example, not both (got {' '.join(tokens)!r})")
        return PlanInput(
            parse_plan(EXAMPLES[example.upper()]), f"Trajectory {example.upper()}", None
        )
    if not tokens:
        return PlanInput(parse_plan(EXAMPLES["A"]), "Trajectory A", None)
    if len(tokens) == 1:
        token = tokens[0]
        path = Path(token)
        named_file = bool(token.strip()) and path.exists()
        file_like = path.suffix.lower() in PLAN_SUFFIXES and not any(c.isspace() for c in token)
        if named_file or file_like:
            return PlanInput(load_plan(path), str(path), path)
    return PlanInput(parse_plan(join_plan_arguments(tokens)), "plan", None)


def join_plan_arguments(tokens: Sequence[str]) -> str:
    """One plan text from several arguments: each starts a new segment (``'straight 1' 'spin
    90'`` is ``straight 1; spin 90``), unless it starts with a number, which continues the
    segment before it (``straight 1 10s`` typed unquoted, ``spin -90deg``)."""
    text = ""
    for token in tokens:
        continues = re.match(r"\s*[+-]?[0-9.]", token) is not None
        text = token if not text else f"{text}{' ' if continues else '; '}{token}"
    return text


def check_topic(option: str, name: str) -> str:
    """``name`` when it is a valid ROS topic name, else a bad-input error naming ``option``."""
    if not re.fullmatch(_TOPIC_NAME, name):
        fail(f"{option} {name!r} is not a valid ROS topic name")
    return name


@dataclass(frozen=True)
class PlanOptions:
    """What the plan options say: the example, cruise speeds, --fastest and the limit."""

    example: str | None
    speed: float
    spin_rate: float
    fastest: bool
    rpm_limit: float | None

    @property
    def limit(self) -> float | None:
        """The motor limit to check against (rad/s), when --rpm-limit gives one."""
        return None if self.rpm_limit is None else rad_s_from_rpm(self.rpm_limit)

    def make(self, segments: Sequence[Segment], params: DiffDriveParams) -> Plan:
        """The plan of ``segments`` for the robot, as these options ask."""
        return make_plan(
            segments,
            params,
            speed=self.speed,
            spin_rate=self.spin_rate,
            fastest=self.fastest,
            limit=self.limit,
        )


#: The cruise options, by name: (default, metavar, help).
_CRUISE = {
    "--speed": (
        0.1,
        "M/S",
        "Cruise path speed of straights and arcs without a duration (m/s).",
    ),
    "--spin-rate": (
        0.5,
        "RAD/S",
        "Turn rate of spins without a duration (rad/s; 0.5 rad/s = 28.6 deg/s).",
    ),
}


#: Add the options that say which plan to make; the command receives them as
#: ``plan_options: PlanOptions``.
plan_input_options = option_group(
    [
        click.option(
            "--example",
            type=click.Choice(["A", "B"], case_sensitive=False),
            metavar="A|B",
            help="One of the seed's Figure 1 paths (A is used when nothing is given).",
        ),
        *(
            click.option(
                name, type=POSITIVE, default=default, show_default=True, metavar=unit, help=text
            )
            for name, (default, unit, text) in _CRUISE.items()
        ),
        click.option(
            "--fastest",
            is_flag=True,
            help="Give every segment the shortest duration that keeps its wheels within the "
            "limit (durations given in the plan are ignored).",
        ),
        click.option(
            "--rpm-limit",
            type=POSITIVE,
            metavar="RPM",
            help="Motor limit to check against (rpm), instead of the description's (or --max-rpm).",
        ),
    ],
    "plan_options",
    lambda kw: PlanOptions(
        *(kw.pop(name) for name in ("example", "speed", "spin_rate", "fastest", "rpm_limit"))
    ),
)
