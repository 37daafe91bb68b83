"""Motion plans: straight lines, arcs and turns in place, as velocity commands and exact poses.

A plan is a list of segments (:class:`Straight`, :class:`Arc`, :class:`Spin`), each held at one
constant body velocity for its duration. :func:`plan` turns them into a :class:`Plan`: per segment
the Twist (m/s, rad/s), both wheel speeds (rad/s), the share of the motor limit the faster wheel
uses, and the pose at its end, in closed form (no numerical integration). The robot starts at the
origin of the odom frame, heading along x (REP-103/105).

Plans are written as text (:func:`parse_plan`, :func:`format_plan`)::

    ccw 0.25 180 10s; straight 1 10s; cw 0.25 180 10s; straight 1 10s

or as YAML/JSON files (:func:`load_plan`). Lengths are in metres and angles in degrees unless a
unit says otherwise (``25cm``, ``250mm``, ``3.14rad``); durations are in seconds (``10s``).
"""

from __future__ import annotations

import bisect
import functools
import math
import os
import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Literal

from diffbot.errors import PlanError
from diffbot.kinematics import (
    LIMIT_TOLERANCE,
    DiffDriveParams,
    Pose,
    Twist,
    WheelSpeeds,
    inverse,
    joint_from_wheel,
    limit_fraction,
    norm_angle,
    rpm_from_rad_s,
)
from diffbot.textfile import read_text

if TYPE_CHECKING:
    from typing import TypeAlias

    import numpy as np
    from numpy.typing import ArrayLike, NDArray

__all__ = [
    "DEFAULT_SPEED",
    "DEFAULT_SPIN_RATE",
    "EXAMPLES",
    "Arc",
    "Plan",
    "PlannedSegment",
    "Segment",
    "Spin",
    "Straight",
    "Violation",
    "describe_segment",
    "format_plan",
    "format_segment",
    "load_plan",
    "parse_plan",
    "plan",
    "pose_at",
    "segments_from_data",
    "wheel_positions",
]

#: Cruise path speed (m/s) of segments without a duration: the seed's 1 m in 10 s.
DEFAULT_SPEED = 0.1
#: Turn rate (rad/s) of spins without a duration. 0.5 rad/s (about 28.6 deg/s) turns the bundled
#: robot's wheels at 0.96 rad/s (9.2 rpm): a quarter turn takes about 3.1 s.
DEFAULT_SPIN_RATE = 0.5

#: The seed's Figure 1 paths. A: a counter-clockwise half circle of radius 0.25 m, 1 m, a clockwise
#: half circle, 1 m; B: the same pieces starting with a straight. Both end at (0, 1) heading x.
EXAMPLES: dict[str, str] = {
    "A": "ccw 0.25 180 10s; straight 1 10s; cw 0.25 180 10s; straight 1 10s",
    "B": "straight 1 10s; ccw 0.25 180 10s; straight 1 10s; cw 0.25 180 10s",
}


def _as_float(value: object) -> float:
    """``float(value)``, or NaN for what is not a number (a string, None, an int too large)."""
    if isinstance(value, bool):
        return math.nan
    try:
        return float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError, OverflowError):
        return math.nan


def _short(value: object, limit: int = 60) -> str:
    """``repr(value)`` for an error message, cut to ``limit`` characters (``...`` marks a cut).

    Built with :mod:`reprlib` limits, so a huge entry is never written out whole first.
    """
    import reprlib

    brief = reprlib.Repr()
    brief.maxlevel = 3
    brief.maxstring = brief.maxother = brief.maxlong = limit
    brief.maxlist = brief.maxtuple = brief.maxdict = brief.maxset = 8
    try:
        text = brief.repr(value)
    except ValueError:  # an int with more digits than Python converts to text
        text = "<an integer too long to show>"
    return text if len(text) <= limit else f"{text[: limit - 3]}..."


def _positive(value: float, what: str) -> float:
    number = _as_float(value)
    if not math.isfinite(number) or number <= 0.0:
        raise PlanError(f"{what} must be a positive finite number, got {_short(value)}")
    return number


def _optional_duration(value: float | None) -> float | None:
    return None if value is None else _positive(value, "a segment duration (s)")


@dataclass(frozen=True)
class Straight:
    """Drive straight ahead.

    Attributes:
        length: distance (m), > 0.
        duration: time to take (s), > 0; None to run at the plan's cruise speed.
    """

    length: float
    duration: float | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "length", _positive(self.length, "a straight's length (m)"))
        object.__setattr__(self, "duration", _optional_duration(self.duration))


@dataclass(frozen=True)
class Arc:
    """Drive along a circular arc.

    Attributes:
        radius: radius of the path of the robot's centre (m), > 0.
        angle: heading change along the arc (rad), > 0; the direction says which way.
        direction: ``"ccw"`` turns left (positive angular.z), ``"cw"`` turns right.
        duration: time to take (s), > 0; None to run at the plan's cruise speed.
    """

    radius: float
    angle: float
    direction: Literal["cw", "ccw"]
    duration: float | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "radius", _positive(self.radius, "an arc's radius (m)"))
        object.__setattr__(self, "angle", _positive(self.angle, "an arc's angle (rad)"))
        if self.direction not in ("cw", "ccw"):
            raise PlanError(
                f"an arc's direction must be 'cw' or 'ccw', got {_short(self.direction)}"
            )
        object.__setattr__(self, "duration", _optional_duration(self.duration))


@dataclass(frozen=True)
class Spin:
    """Turn in place.

    Attributes:
        angle: heading change (rad), positive counter-clockwise, not zero.
        duration: time to take (s), > 0; None to turn at the plan's spin rate.
    """

    angle: float
    duration: float | None = None

    def __post_init__(self) -> None:
        angle = _as_float(self.angle)
        if not math.isfinite(angle) or angle == 0.0:
            raise PlanError(
                f"a spin's angle (rad) must be finite and not zero, got {_short(self.angle)}"
            )
        object.__setattr__(self, "angle", angle)
        object.__setattr__(self, "duration", _optional_duration(self.duration))


Segment: TypeAlias = Straight | Arc | Spin


def _geometry(segment: Segment) -> tuple[float, float]:
    """Path length of the robot's centre (m, >= 0) and signed heading change (rad)."""
    if isinstance(segment, Straight):
        return segment.length, 0.0
    if isinstance(segment, Arc):
        turn = segment.angle if segment.direction == "ccw" else -segment.angle
        return segment.radius * segment.angle, turn
    return 0.0, segment.angle


def _kind(segment: Segment) -> str:
    if isinstance(segment, Arc):
        return segment.direction
    return "straight" if isinstance(segment, Straight) else "spin"


# --------------------------------------------------------------------------------------------
# Planning


@dataclass(frozen=True)
class Violation:
    """A wheel over the motor limit in one segment.

    Attributes:
        index: position of the segment in the plan (0-based).
        wheel: ``"left"`` or ``"right"``.
        rpm: the wheel's speed (rpm, magnitude).
        shortest_duration: the shortest duration of the segment that keeps both wheels within the
            limit (s).
    """

    index: int
    wheel: Literal["left", "right"]
    rpm: float
    shortest_duration: float


@dataclass(frozen=True)
class PlannedSegment:
    """One segment of a plan with its commands and poses.

    Attributes:
        segment: the segment as given.
        index: its position in the plan (0-based).
        twist: the body velocity held during it (m/s, rad/s).
        duration: how long it is held (s).
        wheels: wheel-ground speeds (rad/s; positive rolls the robot forward).
        joints: joint velocity commands (rad/s), the description's direction signs applied.
        fraction: the share of the motor limit the faster wheel uses (1.0 = at the limit), or None
            without a limit.
        start_pose: pose at its start (m, m, rad in (-pi, pi]).
        end_pose: pose at its end (m, m, rad in (-pi, pi]).
        end_heading: heading at its end, not wrapped (rad): the total turn since the start.
    """

    segment: Segment
    index: int
    twist: Twist
    duration: float
    wheels: WheelSpeeds
    joints: WheelSpeeds
    fraction: float | None
    start_pose: Pose
    end_pose: Pose
    end_heading: float

    @property
    def kind(self) -> str:
        """``"straight"``, ``"ccw"``, ``"cw"`` or ``"spin"``."""
        return _kind(self.segment)


@dataclass(frozen=True)
class Plan:
    """A planned sequence of constant body velocities, starting at pose (0, 0, 0).

    Attributes:
        segments: the planned segments, in order.
        params: the robot planned for.
        limit: the motor limit checked against (rad/s), or None.
        duration: total time (s).
        final_pose: pose at the end (m, m, rad in (-pi, pi]).
        within_limit: True when no wheel of any segment exceeds the limit (or there is none).
    """

    segments: tuple[PlannedSegment, ...]
    params: DiffDriveParams
    limit: float | None
    duration: float
    final_pose: Pose
    within_limit: bool

    def violations(self) -> list[Violation]:
        """Every wheel over the limit, segment by segment (left before right)."""
        found: list[Violation] = []
        if self.limit is None:
            return found
        bound = self.limit * (1.0 + LIMIT_TOLERANCE)
        for planned in self.segments:
            fraction = planned.fraction or 0.0
            for wheel, speed in (("left", planned.wheels.left), ("right", planned.wheels.right)):
                if abs(float(speed)) > bound:
                    found.append(
                        Violation(
                            planned.index,
                            "left" if wheel == "left" else "right",
                            abs(rpm_from_rad_s(float(speed))),
                            # speeds scale as 1/duration, so this brings the faster wheel to 1.0
                            planned.duration * fraction,
                        )
                    )
        return found


def _sinc(x: float) -> float:
    return 1.0 if x == 0.0 else math.sin(x) / x


def _advance(x: float, y: float, heading: float, ds: float, turn: float) -> Pose:
    """Move along an arc of length ``ds`` (m) turning by ``turn`` (rad); heading not wrapped.

    The chord of the arc is ``ds sinc(turn / 2)`` long and points along the mean heading; this
    form has no singularity at ``turn = 0`` (a straight line), unlike ``R (sin(th + dth) - ...)``.
    """
    half = 0.5 * turn
    chord = ds * _sinc(half)
    mean = heading + half
    return Pose(x + chord * math.cos(mean), y + chord * math.sin(mean), heading + turn)


def _finite(*values: float) -> bool:
    return all(math.isfinite(value) for value in values)


def _overflow(segment: Segment, index: int, what: str) -> PlanError:
    given = "" if segment.duration is None else f", {segment.duration:.6g} s"
    return PlanError(
        f"segment {index + 1} ({describe_segment(segment)}{given}): its {what} cannot be "
        "computed: the numbers are too large (or the duration too short) for floating point"
    )


def _pose(x: float, y: float, heading: float) -> Pose:
    """A reported pose: heading wrapped to (-pi, pi], and no ``-0.0``."""
    return Pose(x + 0.0, y + 0.0, norm_angle(heading) + 0.0)


def plan(
    segments: Iterable[Segment],
    params: DiffDriveParams,
    speed: float = DEFAULT_SPEED,
    spin_rate: float = DEFAULT_SPIN_RATE,
    fastest: bool = False,
    limit: float | None = None,
) -> Plan:
    """Plan the velocity commands of a sequence of segments.

    Args:
        segments: the path, starting at pose (0, 0, 0).
        params: the robot.
        speed: cruise path speed (m/s) of straights and arcs without a duration.
        spin_rate: turn rate (rad/s) of spins without a duration (default 0.5 rad/s).
        fastest: give every segment the shortest duration that keeps its wheels within the limit
            (its faster wheel then runs exactly at the limit); given durations are ignored.
        limit: motor limit (rad/s) to check against instead of ``params.max_wheel_speed``.

    Returns:
        The plan. A wheel over the limit is not an error: see :attr:`Plan.within_limit` and
        :meth:`Plan.violations`.

    Raises:
        PlanError: no segments, a cruise speed or spin rate that is not positive, a negative or
            zero limit (no duration satisfies it), ``fastest`` without a limit, or a segment whose
            duration, velocity, wheel speeds, end pose or end time overflow (not finite, or a
            duration that rounds to zero); the message names the segment.
    """
    items = list(segments)
    if not items:
        raise PlanError("empty plan: no segments")
    for item in items:
        if not isinstance(item, Straight | Arc | Spin):
            raise PlanError(f"not a plan segment: {_short(item)}")
    speed = _positive(speed, "the cruise speed (m/s)")
    spin_rate = _positive(spin_rate, "the spin rate (rad/s)")
    lim = params.max_wheel_speed if limit is None else _as_float(limit)
    if lim is not None and (not math.isfinite(lim) or lim < 0.0):
        raise PlanError(
            f"the motor limit must be a finite number >= 0 (rad/s), got {_short(limit)}"
        )
    if lim == 0.0:
        raise PlanError("the motor limit is zero: no duration keeps a moving wheel within it")
    if fastest and lim is None:
        raise PlanError(
            "a fastest plan needs a motor limit, and the robot has none "
            "(give one with limit=, or a max_wheel_speed in the parameters)"
        )

    planned: list[PlannedSegment] = []
    x, y, heading, elapsed = 0.0, 0.0, 0.0, 0.0
    for index, segment in enumerate(items):
        ds, turn = _geometry(segment)
        if fastest:
            assert lim is not None
            # Wheel angles travelled (rad) over the segment; their peak at the limit sets the time.
            travel = inverse(params, ds, turn)
            duration = max(abs(float(travel.left)), abs(float(travel.right))) / lim
        elif segment.duration is not None:
            duration = segment.duration
        elif isinstance(segment, Spin):
            duration = abs(turn) / spin_rate
        else:
            duration = ds / speed
        if not (math.isfinite(duration) and duration > 0.0):
            raise _overflow(segment, index, f"duration ({duration:g} s)")
        twist = Twist(ds / duration, turn / duration)
        wheels = inverse(params, twist.linear, twist.angular)
        wheels = WheelSpeeds(float(wheels.left), float(wheels.right))
        joints = joint_from_wheel(params, wheels)
        fraction = limit_fraction(params, wheels, lim)
        if not _finite(float(twist.linear), float(twist.angular)):
            raise _overflow(segment, index, "velocity")
        if not _finite(*(rpm_from_rad_s(float(w)) * duration for w in wheels)):
            raise _overflow(segment, index, "wheel speeds or wheel turns")
        if fraction is not None and not _finite(float(fraction) * duration):
            raise _overflow(segment, index, "share of the motor limit")
        elapsed += duration
        if not _finite(elapsed, heading + turn):
            raise _overflow(segment, index, "end time or heading")
        start = _pose(x, y, heading)
        x, y, heading = _advance(x, y, heading, ds, turn)
        if not _finite(x, y):
            raise _overflow(segment, index, "end pose")
        planned.append(
            PlannedSegment(
                segment=segment,
                index=index,
                twist=twist,
                duration=duration,
                wheels=wheels,
                joints=WheelSpeeds(float(joints.left), float(joints.right)),
                fraction=None if fraction is None else float(fraction),
                start_pose=start,
                end_pose=_pose(x, y, heading),
                end_heading=heading + 0.0,
            )
        )
    within = lim is None or all((p.fraction or 0.0) <= 1.0 + LIMIT_TOLERANCE for p in planned)
    try:
        total = math.fsum(p.duration for p in planned)
    except OverflowError:
        total = math.inf
    if not math.isfinite(total):
        raise _overflow(items[-1], len(items) - 1, "end time")
    return Plan(
        segments=tuple(planned),
        params=params,
        limit=lim,
        duration=total,
        final_pose=planned[-1].end_pose,
        within_limit=within,
    )


def _start_times(p: Plan) -> list[float]:
    starts = [0.0]
    for planned in p.segments[:-1]:
        starts.append(starts[-1] + planned.duration)
    return starts


def pose_at(p: Plan, t: float) -> Pose:
    """The pose (m, m, rad in (-pi, pi]) that the plan reaches at time ``t`` (s), in closed form.

    Times before 0 give the start pose, times after the plan's duration its final pose.
    """
    t = float(t)
    if math.isnan(t):
        raise PlanError("pose_at: the time is NaN")
    starts = _start_times(p)
    i = max(0, bisect.bisect_right(starts, t) - 1)
    planned = p.segments[i]
    heading = p.segments[i - 1].end_heading if i > 0 else 0.0
    elapsed = min(max(t - starts[i], 0.0), planned.duration)
    if i == len(p.segments) - 1 and elapsed >= planned.duration:
        return p.final_pose
    start = planned.start_pose
    pose = _advance(
        start.x,
        start.y,
        heading,
        float(planned.twist.linear) * elapsed,
        float(planned.twist.angular) * elapsed,
    )
    return _pose(pose.x, pose.y, pose.theta)


def wheel_positions(p: Plan, times: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Joint positions the plan commands: the integral of its joint velocity commands.

    Args:
        p: the plan.
        times: times since the start of the plan (s), any shape; clamped to [0, duration].

    Returns:
        Left and right joint angles (rad, the description's direction signs applied, both 0 at
        the start), each shaped like ``times``.
    """
    import numpy as np

    t = np.clip(np.asarray(times, dtype=np.float64), 0.0, p.duration)
    durations = np.array([s.duration for s in p.segments], dtype=np.float64)
    starts = np.concatenate(([0.0], np.cumsum(durations)[:-1]))
    index = np.clip(np.searchsorted(starts, t, side="right") - 1, 0, len(durations) - 1)
    elapsed = t - starts[index]
    out: list[NDArray[np.float64]] = []
    for side in ("left", "right"):
        rates = np.array([float(getattr(s.joints, side)) for s in p.segments], dtype=np.float64)
        at_start = np.concatenate(([0.0], np.cumsum(rates * durations)[:-1]))
        out.append(at_start[index] + rates[index] * elapsed)
    return out[0], out[1]


# --------------------------------------------------------------------------------------------
# Text form

# ASCII digits only (float() would also take other scripts' digits and underscores); the unit
# follows at once, in files as in text (where a space would split the token).
_NUMBER = re.compile(r"([+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?)(.*)", re.DOTALL)
_DIVISORS: dict[str, dict[str, float]] = {
    # Dividing by an exact power of ten rounds once, so 25cm is exactly 0.25.
    "length": {"": 1.0, "m": 1.0, "cm": 100.0, "mm": 1000.0},
    "duration": {"": 1.0, "s": 1.0},
}
_ANGLE_UNITS = {"": True, "deg": True, "rad": False}
_ALL_UNITS = {unit for units in _DIVISORS.values() for unit in units if unit} | {"deg", "rad"}
_UNIT_HELP = {"length": "m, cm or mm", "angle": "deg or rad", "duration": "s"}

Dimension = Literal["length", "angle", "duration"]


class _BadValueError(Exception):
    """A value that cannot be read; the caller adds where it was."""


def _quantity(text: str, dimension: Dimension) -> float:
    """An SI value (m, rad or s) from a number with an optional unit (default m, deg, s)."""
    match = _NUMBER.fullmatch(text.strip())
    if match is None:
        if text.strip().lower().lstrip("+-") in ("nan", "inf", "infinity"):
            raise _BadValueError("not a finite number")
        raise _BadValueError("not a number")
    number = float(match.group(1))
    if not math.isfinite(number):
        raise _BadValueError("not a finite number")
    if match.group(2)[:1].isspace():
        raise _BadValueError(
            f"write the unit attached to its number, as in {match.group(1)}{match.group(2).strip()}"
        )
    unit = match.group(2).lower()
    if dimension == "angle":
        if unit not in _ANGLE_UNITS:
            raise _BadValueError(
                f"unknown unit {_short(match.group(2))} for an angle (use deg or rad)"
            )
        value = math.radians(number) if _ANGLE_UNITS[unit] else number
    else:
        divisors = _DIVISORS[dimension]
        if unit not in divisors:
            raise _BadValueError(
                f"unknown unit {_short(match.group(2))} for a {dimension} "
                f"(use {_UNIT_HELP[dimension]})"
            )
        value = number / divisors[unit]
    if not math.isfinite(value):
        raise _BadValueError("not a finite number")
    return value


@dataclass(frozen=True)
class _Token:
    text: str
    line: int
    column: int


# One entry per argument: (role, dimension, rule) where rule is "positive" or "nonzero".
_SIGNATURES: dict[str, tuple[tuple[str, Dimension, str], ...]] = {
    "straight": (("length", "length", "positive"),),
    "ccw": (("radius", "length", "positive"), ("angle", "angle", "positive")),
    "cw": (("radius", "length", "positive"), ("angle", "angle", "positive")),
    "spin": (("angle", "angle", "nonzero"),),
}
_USAGE = {
    "straight": "straight LENGTH [DURATION]",
    "ccw": "ccw RADIUS ANGLE [DURATION]",
    "cw": "cw RADIUS ANGLE [DURATION]",
    "spin": "spin ANGLE [DURATION]",
}


def _segments_of(text: str) -> list[list[_Token]]:
    """Split plan text into segments of tokens, dropping comments and empty segments."""
    segments: list[list[_Token]] = []
    for line_number, line in enumerate(text.splitlines() or [""], start=1):
        code = line.split("#", 1)[0]
        start = 0
        for piece in code.split(";"):
            tokens = [
                _Token(m.group(), line_number, start + m.start() + 1)
                for m in re.finditer(r"\S+", piece)
            ]
            if tokens:
                segments.append(tokens)
            start += len(piece) + 1
    return segments


def _segment_from_tokens(tokens: list[_Token], number: int, multiline: bool) -> Segment:
    def where(token: _Token) -> str:
        if multiline:
            return f"line {token.line}, column {token.column}"
        return f"column {token.column}"

    def error(token: _Token, message: str) -> PlanError:
        return PlanError(f"segment {number}: {message} ({where(token)})")

    head = tokens[0]
    kind = head.text.lower()
    if kind not in _SIGNATURES:
        hint = " (arcs are written ccw/cw RADIUS ANGLE)" if kind == "arc" else ""
        raise error(
            head,
            f"unknown segment kind {_short(head.text)}: expected straight, ccw, cw or spin{hint}",
        )
    signature = _SIGNATURES[kind]
    args = tokens[1:]
    for token in args:
        if token.text.lower() in _ALL_UNITS:
            raise error(
                token,
                f"{_short(token.text)} is a unit: write it attached to its number, as in 25cm",
            )
    if len(args) < len(signature):
        missing = " and ".join(role.upper() for role, _, _ in signature[len(args) :])
        last = args[-1] if args else head
        raise error(
            last, f"{_short(head.text)} needs {missing} after {_short(last.text)}: {_USAGE[kind]}"
        )
    if len(args) > len(signature) + 1:
        extra = args[len(signature) + 1]
        raise error(extra, f"unexpected {_short(extra.text)}: {_USAGE[kind]}")
    values: list[float] = []
    for token, (role, dimension, rule) in zip(args, signature, strict=False):
        try:
            value = _quantity(token.text, dimension)
        except _BadValueError as err:
            raise error(token, f"{role} {_short(token.text)}: {err}") from None
        if rule == "positive" and value <= 0.0:
            hint = ""
            if kind in ("ccw", "cw") and role == "angle":
                hint = f" (the direction is in the kind: {'cw' if kind == 'ccw' else 'ccw'})"
            raise error(token, f"{role} {_short(token.text)} must be > 0{hint}")
        if rule == "nonzero" and value == 0.0:
            raise error(token, f"{role} {_short(token.text)} must not be zero")
        values.append(value)
    duration: float | None = None
    if len(args) > len(signature):
        token = args[-1]
        try:
            duration = _quantity(token.text, "duration")
        except _BadValueError as err:
            raise error(token, f"duration {_short(token.text)}: {err}") from None
        if duration <= 0.0:
            raise error(token, f"duration {_short(token.text)} must be > 0")
    if kind == "straight":
        return Straight(values[0], duration)
    if kind == "spin":
        return Spin(values[0], duration)
    return Arc(values[0], values[1], "ccw" if kind == "ccw" else "cw", duration)


def parse_plan(text: str) -> list[Segment]:
    """Read a plan written as text.

    Segments are separated by ``;`` or newlines; ``#`` starts a comment. Each is one of
    ``straight LENGTH [DURATION]``, ``ccw RADIUS ANGLE [DURATION]``, ``cw RADIUS ANGLE
    [DURATION]``, ``spin ANGLE [DURATION]`` (positive = counter-clockwise). Lengths are in m
    unless suffixed ``cm``/``mm``/``m``, angles in degrees unless suffixed ``rad``/``deg``,
    durations in s (suffix ``s``).

    Args:
        text: the plan, e.g. ``"ccw 0.25 180 10s; straight 1 10s"``.

    Returns:
        The segments (SI units).

    Raises:
        PlanError: empty plan, unknown kind or unit, missing or extra values, a value that is not
            a finite number, or not positive (not zero, for spins); the message quotes the token
            and gives the segment number and column (and line, when the text has several).
    """
    return _parse_text(text, lines=len(text.splitlines()) > 1)


def _parse_text(text: str, *, lines: bool) -> list[Segment]:
    """:func:`parse_plan`; ``lines``: give line numbers in errors (not only columns)."""
    pieces = _segments_of(text)
    if not pieces:
        raise PlanError("empty plan: no segments (write for example 'straight 1 10s')")
    return [
        _segment_from_tokens(tokens, number, lines) for number, tokens in enumerate(pieces, start=1)
    ]


def _number_text(value: float) -> str:
    text = repr(float(value))
    return text[:-2] if text.endswith(".0") else text


def _angle_text(angle: float) -> str:
    degrees = math.degrees(angle)
    if math.isfinite(degrees) and math.radians(degrees) == angle:
        return _number_text(degrees)
    return f"{_number_text(angle)}rad"


def format_segment(segment: Segment) -> str:
    """The text form of one segment; :func:`parse_plan` reads it back exactly."""
    if isinstance(segment, Straight):
        words = ["straight", _number_text(segment.length)]
    elif isinstance(segment, Arc):
        words = [segment.direction, _number_text(segment.radius), _angle_text(segment.angle)]
    else:
        words = ["spin", _angle_text(segment.angle)]
    if segment.duration is not None:
        words.append(f"{_number_text(segment.duration)}s")
    return " ".join(words)


def format_plan(segments: Iterable[Segment]) -> str:
    """The text form of a plan (one line, ``;``-separated); :func:`parse_plan` reads it back
    exactly: numbers keep every digit, and angles are written in degrees only when that converts
    back to the same radians (otherwise in ``rad``)."""
    return "; ".join(format_segment(segment) for segment in segments)


def describe_segment(segment: Segment) -> str:
    """A short description of a segment for people (6 significant digits, degrees)."""

    def short(value: float) -> str:
        text = f"{value:.6g}"
        return "0" if text == "-0" else text

    if isinstance(segment, Straight):
        return f"straight {short(segment.length)} m"

    def angle(value: float) -> str:
        degrees = math.degrees(value)
        return f"{short(degrees)} deg" if math.isfinite(degrees) else f"{short(value)} rad"

    if isinstance(segment, Arc):
        return f"{segment.direction} arc r {short(segment.radius)} m {angle(segment.angle)}"
    return f"spin {angle(segment.angle)}"


# --------------------------------------------------------------------------------------------
# Files

_ENTRY_KEYS = {
    "straight": {"straight", "duration"},
    "arc": {"arc", "radius", "angle", "duration"},
    "spin": {"spin", "duration"},
}


def _entry_value(value: object, dimension: Dimension, what: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float | str):
        raise _BadValueError(
            f"{what} {_short(value)}: expected a number or a string such as '25cm'"
        )
    if isinstance(value, str):
        try:
            return _quantity(value, dimension)
        except _BadValueError as err:
            raise _BadValueError(f"{what} {_short(value)}: {err}") from None
    number = _as_float(value)
    if not math.isfinite(number):
        raise _BadValueError(f"{what} {_short(value)}: not a finite number")
    return math.radians(number) if dimension == "angle" else number


def _segment_from_entry(entry: object) -> Segment:
    if isinstance(entry, str):
        segments = parse_plan(entry)
        if len(segments) != 1:
            raise _BadValueError(f"{_short(entry)} holds {len(segments)} segments, expected one")
        return segments[0]
    if not isinstance(entry, Mapping):
        raise _BadValueError(
            f"expected a mapping such as {{straight: 1.0, duration: 10}}, got {_short(entry)}"
        )
    kinds = [kind for kind in _ENTRY_KEYS if kind in entry]
    if len(kinds) != 1:
        found = "none" if not kinds else " and ".join(kinds)
        raise _BadValueError(
            f"expected exactly one of 'straight', 'arc', 'spin' as a key, got {found}"
        )
    kind = kinds[0]
    unknown = [key for key in entry if key not in _ENTRY_KEYS[kind]]
    if unknown:
        allowed = ", ".join(sorted(_ENTRY_KEYS[kind]))
        raise _BadValueError(f"unknown key {_short(unknown[0])} for a {kind} (allowed: {allowed})")

    def get(key: str, dimension: Dimension, rule: str = "positive") -> float:
        if key not in entry:
            raise _BadValueError(f"a {kind} needs {key!r}")
        value = _entry_value(entry[key], dimension, key)
        if rule == "positive" and value <= 0.0:
            raise _BadValueError(f"{key} {_short(entry[key])} must be > 0")
        if rule == "nonzero" and value == 0.0:
            raise _BadValueError(f"{key} {_short(entry[key])} must not be zero")
        return value

    duration = get("duration", "duration") if entry.get("duration") is not None else None
    if kind == "straight":
        return Straight(get("straight", "length"), duration)
    if kind == "spin":
        return Spin(get("spin", "angle", "nonzero"), duration)
    arc = entry["arc"]
    direction = arc.lower() if isinstance(arc, str) else None  # case as free as in text
    if direction not in ("ccw", "cw"):
        raise _BadValueError(f"arc {_short(arc)}: expected 'ccw' or 'cw'")
    return Arc(
        get("radius", "length"),
        get("angle", "angle"),
        "ccw" if direction == "ccw" else "cw",
        duration,
    )


def _looks_structured(text: str) -> bool:
    for line in text.splitlines():
        stripped = line.strip()
        if stripped and not stripped.startswith("#"):
            return stripped[0] in "[{-"
    return False


def segments_from_data(data: object, source: str = "plan") -> list[Segment]:
    """Segments from parsed YAML/JSON: a list of entries, or a mapping with only a ``segments``
    list.

    Entries are mappings such as ``{straight: 1.0, duration: 10}``, ``{arc: ccw, radius: 0.25,
    angle: 180, duration: 10}`` (``ccw``/``cw`` in any case) or ``{spin: 90}`` (numbers in m,
    degrees and s; strings may carry a unit attached to the number: ``"25cm"``, ``"1.5rad"``,
    ``"10s"``), or text segments such as ``"straight 1 10s"``.

    Raises:
        PlanError: naming the source and the entry (counted from 1), quoting at most 60
            characters of it.
    """
    if isinstance(data, Mapping) and "segments" in data:
        others = [key for key in data if key != "segments"]
        if others:
            raise PlanError(
                f"{source}: unknown top-level key {_short(others[0])} (a plan file holds a list "
                "of segments, or a mapping with only 'segments')"
            )
        data = data["segments"]
    if not isinstance(data, list):
        raise PlanError(f"{source}: expected a list of segments, got {type(data).__name__}")
    if not data:
        raise PlanError(f"{source}: empty plan: no segments")
    segments: list[Segment] = []
    for number, entry in enumerate(data, start=1):
        try:
            segments.append(_segment_from_entry(entry))
        except (_BadValueError, PlanError) as err:
            raise PlanError(f"{source}: entry {number}: {err}") from None
    return segments


def load_plan(path: str | os.PathLike[str]) -> list[Segment]:
    """Read a plan file.

    ``.json`` files are JSON, ``.yaml``/``.yml`` files YAML (see :func:`segments_from_data` for
    the entries), ``.txt`` files the text form (see :func:`parse_plan`); other files are read as
    YAML when they start with ``[``, ``{`` or ``-``, else as text. Files are UTF-8 (a byte order
    mark is skipped). Duplicate keys in a mapping are errors, and so are YAML aliases (``*name``):
    a plan never needs them, and nested ones grow exponentially.

    Args:
        path: the file.

    Returns:
        The segments (SI units).

    Raises:
        PlanError: the file cannot be read or parsed, or an entry is bad (the message names it).
    """
    source = os.fspath(path)
    text = read_text(source, PlanError, "a plan file")
    suffix = os.path.splitext(source)[1].lower()
    if suffix == ".json":
        return segments_from_data(_load_json(text, source), source)
    if suffix in (".yaml", ".yml") or (suffix != ".txt" and _looks_structured(text)):
        return segments_from_data(_load_yaml(text, source), source)
    try:
        return _parse_text(text, lines=True)
    except PlanError as err:
        raise PlanError(f"{source}: {err}") from None


def _load_json(text: str, source: str) -> Any:
    import json

    def reject(constant: str) -> float:
        raise PlanError(f"{source}: {constant} is not a finite number")

    def unique(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
        mapping: dict[str, Any] = {}
        for key, value in pairs:
            if key in mapping:
                raise PlanError(f"{source}: duplicate key {_short(key)} in a JSON object")
            mapping[key] = value
        return mapping

    try:
        return json.loads(text, parse_constant=reject, object_pairs_hook=unique)
    except json.JSONDecodeError as err:
        raise PlanError(
            f"{source}: malformed JSON: {err.msg} (line {err.lineno}, column {err.colno})"
        ) from None
    except ValueError as err:  # a number with more digits than Python reads
        raise PlanError(f"{source}: a value cannot be read: {str(err).split(':')[0]}") from None


class _AliasError(Exception):
    """A YAML alias in a plan file; ``where`` is the mark's text."""

    def __init__(self, where: str) -> None:
        super().__init__(where)
        self.where = where


@functools.cache
def _plan_loader() -> type[Any]:
    """A safe YAML loader for plan files: no aliases (a plan never needs them, and nested ones
    expand exponentially), and no duplicate keys in a mapping (YAML forbids them; PyYAML would
    keep the last)."""
    import yaml
    from yaml.nodes import MappingNode, Node

    class PlanLoader(yaml.SafeLoader):
        def compose_node(self, parent: Node | None, index: int) -> Node | None:
            if self.check_event(yaml.AliasEvent):
                mark = self.peek_event().start_mark  # type: ignore[no-untyped-call,unused-ignore]
                raise _AliasError(f"line {mark.line + 1}, column {mark.column + 1}")
            return super().compose_node(parent, index)

        def construct_mapping(self, node: MappingNode, deep: bool = False) -> dict[Any, Any]:
            seen: set[Any] = set()
            for key_node, _ in node.value:
                key = self.construct_object(key_node, deep=True)
                try:
                    duplicate = key in seen
                except TypeError:  # unhashable: the SafeLoader reports it
                    continue
                if duplicate:
                    raise yaml.constructor.ConstructorError(
                        None, None, f"duplicate key {_short(key)}", key_node.start_mark
                    )
                seen.add(key)
            return super().construct_mapping(node, deep)

    return PlanLoader


def _load_yaml(text: str, source: str) -> Any:
    import yaml

    try:
        return yaml.load(text, Loader=_plan_loader())  # a SafeLoader
    except _AliasError as err:
        raise PlanError(
            f"{source}: YAML aliases (*name) are not allowed in a plan file, write each entry "
            f"out ({err.where})"
        ) from None
    except yaml.YAMLError as err:
        mark = getattr(err, "problem_mark", None)
        problem = getattr(err, "problem", None) or "malformed YAML"
        where = f" (line {mark.line + 1}, column {mark.column + 1})" if mark is not None else ""
        raise PlanError(f"{source}: malformed YAML: {problem}{where}") from None
    except ValueError as err:  # a number with more digits than Python reads, a bad date
        raise PlanError(f"{source}: a value cannot be read: {str(err).split(':')[0]}") from None
