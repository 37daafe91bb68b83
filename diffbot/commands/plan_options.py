"""The options that say which plan to make, shared by ``plan`` and ``simulate``."""

from __future__ import annotations

import dataclasses
import math
import re
import sys
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import click

from diffbot.body_limits import UNLIMITED, BodyLimits
from diffbot.commands.limit_options import body_limit_options
from diffbot.commands.options import (
    POSITIVE,
    F,
    Names,
    RobotOptions,
    exists,
    fail,
    no_such_option,
    option_group,
    robot_options,
    split_xacro_args,
)
from diffbot.commands.paths import InputPath, input_path
from diffbot.commands.shown_defaults import choice_option, name_option
from diffbot.formats.text import fmt
from diffbot.goals import SHAPES
from diffbot.kinematics import DiffDriveParams, Pose, norm_angle
from diffbot.planfile import load_plan, parse_plan
from diffbot.trajectory import EXAMPLES, Plan, Segment
from diffbot.trajectory import plan as make_plan

if TYPE_CHECKING:
    from diffbot.ramps import RampedPlan

__all__ = [
    "PLAN_FORMATS",
    "PLAN_SUFFIXES",
    "GoalOptions",
    "MadePlan",
    "PlanInput",
    "PlanOptions",
    "PlanRequest",
    "check_topic",
    "frame_id_option",
    "join_plan_arguments",
    "plan_arguments",
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
    #: What the table adds below the plan (a goal plan's shape and why).
    note: str = ""
    #: A goal plan's start pose (m, m, rad), which its poses are relative to; None for a plan
    #: of segments, which starts at its own origin.
    start: Pose | None = None


@dataclass(frozen=True)
class PlanRequest:
    """What a plan command was asked, before any work: the plan input and the robot options
    with the command line's ``NAME:=VALUE`` xacro arguments merged in (for the checks a command
    makes before the robot is loaded)."""

    source: PlanInput
    robot: RobotOptions


@dataclass(frozen=True)
class MadePlan:
    """The plan a command was given, made for its robot.

    Attributes:
        source: the plan input, a goal plan's segments resolved.
        params: the robot.
        made: the plan, ramped when the options or the controller ask for it.
    """

    source: PlanInput
    params: DiffDriveParams
    made: Plan | RampedPlan
    #: The body velocity limits the plan was made within.
    body: BodyLimits = UNLIMITED

    @property
    def steps(self) -> Plan:
        """The step plan: the cruise speeds, the motor limit check, the exact poses."""
        return self.made if isinstance(self.made, Plan) else self.made.steps

    def limit_lines(self) -> list[str]:
        """One ``error:`` line per segment over the motor limit, then per segment over a body
        velocity limit; empty when the plan keeps within every limit."""
        from diffbot.formats.plan_table import body_violation_lines, violation_lines

        steps = self.steps
        lines = [] if steps.within_limit else violation_lines(steps)
        return lines + body_violation_lines(steps, self.body)


def plan_input(
    tokens: Sequence[str],
    example: str | None,
    *,
    side: float | None = None,
    clockwise: bool = False,
) -> PlanInput:
    """The plan named by positional tokens (text or a file) or ``--example``; the UMBmark
    square (``--example umbmark``) has a ``side`` (m) and turns ``clockwise`` or not."""
    if (side is not None or clockwise) and (example or "").lower() != "umbmark":
        fail("--side, --cw and --ccw shape the UMBmark square: give --example umbmark")
    for token in tokens:
        if token.startswith("--") or (
            token.startswith("-") and len(token) > 1 and not token[1].isdigit() and token[1] != "."
        ):
            no_such_option(token)
    if example is not None:
        if tokens:
            fail(f"give a plan (SPEC or FILE) or --example, not both (got {' '.join(tokens)!r})")
        if example.lower() == "umbmark":
            return _umbmark_input(side, clockwise)
        return PlanInput(
            parse_plan(EXAMPLES[example.upper()]), f"Trajectory {example.upper()}", None
        )
    if not tokens:
        return PlanInput(parse_plan(EXAMPLES["A"]), "Trajectory A", None)
    if len(tokens) == 1:
        token = tokens[0]
        path = Path(token)
        named_file = bool(token.strip()) and exists(path)
        file_like = path.suffix.lower() in PLAN_SUFFIXES and not any(c.isspace() for c in token)
        if named_file or file_like:
            input_path(token)
            return PlanInput(load_plan(path), str(path), path)
    return PlanInput(parse_plan(join_plan_arguments(tokens)), "plan", None)


def _umbmark_input(side: float | None, clockwise: bool) -> PlanInput:
    from diffbot.calibration.umbmark import umbmark_segments

    if side is None:
        fail("--example umbmark needs --side M, the side of the square (m)")
    direction: Literal["cw", "ccw"] = "cw" if clockwise else "ccw"
    segments: list[Segment] = list(umbmark_segments(side, direction))
    return PlanInput(segments, f"UMBmark {direction} square, side {side:g} m", None)


def join_plan_arguments(tokens: Sequence[str]) -> str:
    """One plan text from several arguments: each starts a new segment (``'straight 1' 'spin
    90'`` is ``straight 1; spin 90``), unless it starts with a number, which continues the
    segment before it (``straight 1 10s`` typed unquoted, ``spin -90deg``), and the kind after
    ``reverse`` (``reverse ccw 0.25 90``)."""
    text = ""
    for token in tokens:
        continues = re.match(r"\s*[+-]?[0-9.]", token) is not None
        # 'reverse' is followed by the kind of the segment it reverses.
        continues = continues or text.split()[-1:] == ["reverse"]
        text = token if not text else f"{text}{' ' if continues else '; '}{token}"
    return text


#: The frame of TwistStamped commands, for the commands that send or write them.
frame_id_option = name_option(
    "--frame-id", "base_link", "The frame of --stamped commands.", metavar="FRAME"
)


def check_topic(option: str, name: str) -> str:
    """``name`` when it is a valid ROS topic name, else a bad-input error naming ``option``."""
    if not re.fullmatch(_TOPIC_NAME, name):
        fail(f"{option} {name!r} is not a valid ROS topic name")
    return name


@dataclass(frozen=True)
class GoalOptions:
    """What the goal options say: --to (each a waypoint), --from, --waypoints, --shape,
    --min-radius, --forward-only."""

    targets: tuple[str, ...] = ()
    start: str | None = None
    waypoints: str | None = None
    shape: str = "fastest"
    min_radius: float | None = None
    forward_only: bool = False

    def points(self) -> list[tuple[float, float, float | None]]:
        """The waypoints: the file's, then each --to."""
        from diffbot.io.waypoints import parse_pose, read_waypoints

        points = [] if self.waypoints is None else read_waypoints(self.waypoints)
        points += [parse_pose(text, f"--to {text}") for text in self.targets]
        return points

    def start_pose(self) -> tuple[float, float, float]:
        """The --from pose (m, m, rad); the origin heading x without it."""
        from diffbot.io.waypoints import parse_pose

        if self.start is None:
            return 0.0, 0.0, 0.0
        x, y, heading = parse_pose(self.start, f"--from {self.start}")
        return x, y, 0.0 if heading is None else heading


def _pose_text(x: float, y: float, heading: float | None) -> str:
    if heading is None:
        return f"({fmt(x)}, {fmt(y)})"
    return f"({fmt(x)}, {fmt(y)}, {fmt(math.degrees(heading))} deg)"


@dataclass(frozen=True)
class PlanOptions:
    """What the plan options say: the example, cruise speeds, --fastest, the limit, and the
    acceleration and jerk limits of ramps."""

    example: str | None
    speed: float
    spin_rate: float
    fastest: bool
    max_accel: float | None = None
    max_angular_accel: float | None = None
    max_wheel_accel: float | None = None
    max_jerk: float | None = None
    steps: bool = False
    side: float | None = None
    clockwise: bool = False
    goal: GoalOptions | None = None
    max_linear: float | None = None
    max_angular: float | None = None
    #: The cruise options given on the command line (not their defaults), by option name.
    given: tuple[str, ...] = ()

    def source(self, tokens: Sequence[str]) -> PlanInput:
        """The plan that positional ``tokens`` or these options name (see :func:`plan_input`);
        with --to or --waypoints, a goal plan whose segments :meth:`resolve` fills in."""
        if self.goal is None:
            return plan_input(tokens, self.example, side=self.side, clockwise=self.clockwise)
        if tokens or self.example is not None:
            fail("give a plan (SPEC, FILE or --example) or a goal (--to, --waypoints), not both")
        path = None if self.goal.waypoints is None else Path(self.goal.waypoints)
        return PlanInput([], "goal plan", path)

    def request(self, robot: RobotOptions, tokens: Sequence[str]) -> PlanRequest:
        """The plan and robot that a command's positional ``tokens`` (a plan, ``NAME:=VALUE``
        xacro arguments) and these options name; nothing is loaded yet."""
        rest, xacro_args = split_xacro_args(tokens)
        return PlanRequest(self.source(rest), robot.with_path(None, xacro_args))

    def build(self, request: PlanRequest, *, writes: bool = False) -> MadePlan:
        """Load the robot and make the plan: a goal plan's segments resolved, ramped when
        :meth:`ramped` says so. --fastest for a robot without a motor limit is an error that
        names the option that gives one. ``writes``: the command's output is asked for (a file,
        a format for programs), so a goal at the start, which has none, is an error."""
        params = request.robot.load()
        if self.fastest and params.max_wheel_speed is None:
            fail(
                "--fastest needs a motor limit, and the robot description has none: "
                "give one with --max-rpm RPM"
            )
        body = self.body_limits(params)
        source = self.resolve(request.source, params, body, writes=writes)
        return MadePlan(source, params, self.make(source.segments, params, body), body)

    def body_limits(self, params: DiffDriveParams) -> BodyLimits:
        """The body velocity limits: --max-linear and --max-angular, else the controller's."""
        from diffbot.body_limits import body_limits

        return body_limits(params, self.max_linear, self.max_angular)

    @property
    def cruise(self) -> bool:
        """Whether a goal plan is timed at the cruise speeds: --speed or --spin-rate given."""
        return any(option in self.given for option in _CRUISE)

    def at_limit(self, params: DiffDriveParams) -> bool:
        """Whether segments run at the motor limit: --fastest, or a fastest goal plan for a
        robot with a limit when no cruise speed is given."""
        if self.fastest:
            return True
        has_limit = params.max_wheel_speed is not None
        fastest_goal = self.goal is not None and self.goal.shape == "fastest"
        return fastest_goal and has_limit and not self.cruise

    def resolve(
        self,
        source: PlanInput,
        params: DiffDriveParams,
        body: BodyLimits | None = None,
        *,
        writes: bool = False,
    ) -> PlanInput:
        """The plan input with a goal plan's segments and its note; a plan input without a goal
        as it is. A goal at the start is no plan: said so, and the command ends with exit code
        0; when ``writes``, an error (exit code 2), so that nothing stale is taken for it."""
        goal = self.goal
        if goal is None:
            return source
        from diffbot.goals import plan_through, shape_times

        points, start = goal.points(), goal.start_pose()
        options: dict[str, Any] = {
            "start": start,
            "min_radius": goal.min_radius,
            "forward_only": goal.forward_only,
            "speed": self.speed,
            "spin_rate": self.spin_rate,
            "fastest": self.fastest,
            "body": body,
            "cruise": self.cruise,
        }
        made = plan_through(points, params, shape=goal.shape, **options)
        where = " then ".join(_pose_text(*p) for p in points)
        if not made.segments:
            if writes:
                fail(f"the goal {where} is the start: an empty plan, nothing to write")
            click.echo(f"the goal {where} is the start: an empty plan, nothing to drive")
            sys.exit(0)
        segments = [s.segment for s in made.segments]
        # Every shape timed as this plan is (at the motor limit or at the cruise speeds), so
        # that the time said for the shape asked is the plan's.
        at_limit = self.at_limit(params)
        timing = {"fastest": at_limit, "cruise": not at_limit}
        times: dict[str, float | None] = {
            t.shape: t.duration for t in shape_times(points, params, **(options | timing))
        }
        others = ", ".join(
            f"{shape} {fmt(t, 4)} s" if t is not None else f"{shape} (needs --min-radius)"
            for shape, t in times.items()
            if shape != goal.shape
        )
        at = "at the motor limit" if at_limit else "at the cruise speeds"
        if body is not None and not body.unlimited:
            at += " within the body velocity limits"
        chosen = f"{fmt(times[goal.shape] or 0.0, 4)} s"
        if goal.shape == "fastest":
            note = f"shape fastest (the least time {at}): {chosen}; {others}\n"
        else:
            note = f"shape {goal.shape} (as asked); {at} it takes {chosen}, {others}\n"
        if start != (0.0, 0.0, 0.0):
            note += f"poses are relative to the start {_pose_text(*start)}\n"
        label = f"to {where}" + (f" from {_pose_text(*start)}" if goal.start else "")
        x, y, heading = start
        return PlanInput(segments, label, source.path, note, Pose(x, y, norm_angle(heading)))

    @property
    def ramp_options(self) -> dict[str, float | None]:
        """The acceleration and jerk limits given, by library name."""
        return {
            "linear_accel": self.max_accel,
            "angular_accel": self.max_angular_accel,
            "wheel_accel": self.max_wheel_accel,
            "linear_jerk": self.max_jerk,
        }

    def ramped(self, params: DiffDriveParams) -> bool:
        """Whether the plan is ramped: an acceleration or jerk limit is given, or the
        controller configuration has one (unless --steps)."""
        if self.steps:
            return False
        controller = params.controller
        axes = () if controller is None else (controller.linear, controller.angular)
        from_controller = any(
            value is not None
            for axis in axes
            for value in (axis.max_acceleration, axis.max_jerk, axis.min_acceleration)
        )
        return from_controller or any(v is not None for v in self.ramp_options.values())

    def make(
        self, segments: Sequence[Segment], params: DiffDriveParams, body: BodyLimits | None = None
    ) -> Plan | RampedPlan:
        """The plan of ``segments`` for the robot, as these options ask: ramped when
        :meth:`ramped` says so, else a step plan. Warns about cruise options that change
        nothing, and cruise speeds over the body limits."""
        from diffbot.commands.cruise_warnings import warn_over_body, warn_unused

        unused = warn_unused(self, segments)
        if body is not None:
            warn_over_body(self, body, unused)
        steps = make_plan(
            segments,
            params,
            speed=self.speed,
            spin_rate=self.spin_rate,
            fastest=self.at_limit(params),
            body=body,
        )
        if not self.ramped(params):
            return steps
        from diffbot.profiles import ProfileError
        from diffbot.ramps import controller_limits, ramp

        try:
            ramped = ramp(steps, controller_limits(params.controller, **self.ramp_options), body)
        except ProfileError as err:
            fail(f"{err} (limits from {self._limit_sources(params)})")
        from diffbot.commands.cruise_warnings import warn_slowed_runs

        warn_slowed_runs(ramped)
        return ramped

    def _limit_sources(self, params: DiffDriveParams) -> str:
        """Where the limits of a ramped plan come from: the cruise speeds, the options given,
        the controller."""
        flags = dict(zip(self.ramp_options, _RAMPS, strict=True))
        given = [f"--speed {self.speed:g}", f"--spin-rate {self.spin_rate:g}"]
        given += [f"{flags[name]} {value:g}" for name, value in self.ramp_options.items() if value]
        controller = params.controller
        if controller is not None:
            given.append(f"the controller {controller.name!r} in {controller.source}")
        return ", ".join(given)


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


#: The goal options: plan to a pose, or through waypoints.
_GOAL_OPTIONS = [
    click.option(
        "--to",
        "targets",
        multiple=True,
        metavar="X,Y[,HEADING]",
        help="Plan to this pose (m, m, degrees, or 1.57rad); repeat for waypoints. Without a "
        "heading, a waypoint faces the next leg.",
    ),
    click.option(
        "--from",
        "start",
        metavar="X,Y,HEADING",
        help="Start pose of a goal plan (default 0,0,0); the plan's poses are relative to it.",
    ),
    click.option(
        "--waypoints",
        type=InputPath(dir_okay=False),
        metavar="FILE",
        help="Plan through the waypoints of a CSV (x,y[,heading] rows), YAML or JSON file.",
    ),
    choice_option(
        "--shape",
        choices=SHAPES,
        default="fastest",
        help="fastest: the least time at the whole motor limit (turns in place and straights; "
        "at --speed and --spin-rate when either is given, and within --max-linear and "
        "--max-angular); "
        "spin-straight-spin; dubins (forwards) and reeds-shepp (both ways): the shortest path "
        "with arcs of --min-radius.",
    ),
    click.option(
        "--min-radius",
        type=POSITIVE,
        metavar="M",
        help="Turning radius of the dubins and reeds-shepp shapes (m).",
    ),
    click.option("--forward-only", is_flag=True, help="A goal plan never drives backwards."),
]

#: The ramp options, by name: (metavar, help).
_RAMPS = {
    "--max-accel": (
        "M/S2",
        "Path acceleration limit (m/s²): drive each run of equal curvature with a speed ramp.",
    ),
    "--max-angular-accel": ("RAD/S2", "Angular acceleration limit (rad/s²)."),
    "--max-wheel-accel": ("RAD/S2", "Each wheel's angular acceleration limit (rad/s²)."),
    "--max-jerk": ("M/S3", "Path jerk limit (m/s³): S-curve ramps."),
}


_GOAL_NAMES = ("targets", "start", "waypoints", "shape", "min_radius", "forward_only")


def _goal_options(kw: dict[str, Any]) -> GoalOptions | None:
    goal = GoalOptions(**{name: kw.pop(name) for name in _GOAL_NAMES})
    if goal.targets or goal.waypoints is not None:
        return goal
    if goal != GoalOptions():
        fail("--from, --shape, --min-radius and --forward-only shape a goal plan: give --to")
    return None


def _plan_options(kw: dict[str, Any]) -> PlanOptions:
    names = ("example", "speed", "spin_rate", "fastest")
    ramps = ("max_accel", "max_angular_accel", "max_wheel_accel", "max_jerk", "steps")
    keywords = (*ramps, "side", "clockwise", "max_linear", "max_angular")
    ctx = click.get_current_context(silent=True)
    given = tuple(
        option
        for option in _CRUISE
        if ctx is not None
        and ctx.get_parameter_source(option[2:].replace("-", "_"))
        == click.core.ParameterSource.COMMANDLINE
    )
    named: dict[str, Any] = {name: kw.pop(name) for name in keywords}
    named["goal"] = _goal_options(kw)
    options = PlanOptions(*(kw.pop(name) for name in names), **named)
    options = dataclasses.replace(options, given=given)
    if options.steps and any(v is not None for v in options.ramp_options.values()):
        fail("--steps plans velocity steps: give it without --max-accel, --max-jerk and the like")
    return options


#: Add the options that say which plan to make; the command receives them as
#: ``plan_options: PlanOptions``.
plan_input_options = option_group(
    [
        click.option(
            "--example",
            type=Names(["A", "B", "umbmark"]),
            metavar="A|B|umbmark",
            help="An example path: A or B, the course's two paths (A is used when nothing is "
            "given), or the UMBmark square of --side M (first leg along +x, turns in place).",
        ),
        click.option("--side", type=POSITIVE, metavar="M", help="Side of the UMBmark square (m)."),
        click.option(
            "--cw/--ccw",
            "clockwise",
            default=False,
            help="Drive the UMBmark square clockwise or counter-clockwise (the default).",
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
            "whole motor limit and its body within --max-linear and --max-angular (durations "
            "given in the plan are ignored).",
        ),
        *(
            click.option(name, type=POSITIVE, metavar=unit, help=text)
            for name, (unit, text) in _RAMPS.items()
        ),
        *body_limit_options,
        click.option(
            "--steps",
            is_flag=True,
            help="Plan velocity steps even when the controller configuration has acceleration "
            "limits (to see what its limiter makes of them in simulate).",
        ),
        *_GOAL_OPTIONS,
    ],
    "plan_options",
    _plan_options,
)


def plan_arguments(command: F) -> F:
    """Add what says which plan to make, for which robot: the SPEC | FILE and NAME:=VALUE
    arguments (``tokens``), the robot options (``robot``) and the plan options
    (``plan_options``)."""
    decorated = plan_input_options(robot_options(command))
    return click.argument("tokens", nargs=-1, metavar="[SPEC | FILE] [NAME:=VALUE]...")(decorated)
