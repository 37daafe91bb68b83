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
from collections.abc import Iterable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal, TypeVar

from diffbot.errors import PlanError
from diffbot.formats.text import brief
from diffbot.kinematics import (
    LIMIT_TOLERANCE,
    DiffDriveParams,
    Pose,
    Twist,
    WheelSpeeds,
    norm_angle,
    rpm_from_rad_s,
    sinc,
)
from diffbot.numbers import MAX_COORDINATE, MAX_PLAN_TIME, MAX_TURN, flag
from diffbot.segments import (
    Arc,
    Segment,
    Spin,
    Straight,
    as_float,
    describe_segment,
    geometry,
    kind,
    positive,
    up_to_the_limit,
)

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import ArrayLike, NDArray

    from diffbot.body_limits import BodyLimits

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
    "advance",
    "as_float",
    "built",
    "clipped_times",
    "geometry",
    "plan",
    "plan_time",
    "pose_at",
    "reported_pose",
    "wheel_positions",
]

#: Cruise path speed (m/s) of segments without a duration: 1 m in 10 s, as in the course's paths.
DEFAULT_SPEED = 0.1
#: Turn rate (rad/s) of spins without a duration. 0.5 rad/s (about 28.6 deg/s) turns the bundled
#: robot's wheels at 0.96 rad/s (9.2 rpm): a quarter turn takes about 3.1 s.
DEFAULT_SPIN_RATE = 0.5

#: The course's two example paths. A: a counter-clockwise half circle of radius 0.25 m, 1 m, a
#: clockwise half circle, 1 m; B: the same pieces starting with a straight. Both end at (0, 1)
#: heading x.
EXAMPLES: dict[str, str] = {
    "A": "ccw 0.25 180 10s; straight 1 10s; cw 0.25 180 10s; straight 1 10s",
    "B": "straight 1 10s; ccw 0.25 180 10s; straight 1 10s; cw 0.25 180 10s",
}

_T = TypeVar("_T")


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
        return kind(self.segment)


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

    @functools.cached_property
    def _starts(self) -> list[float]:
        """Start time of each segment (s), computed once: :func:`pose_at` is called per sample."""
        starts = [0.0]
        for planned in self.segments[:-1]:
            starts.append(starts[-1] + planned.duration)
        return starts

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


def advance(x: float, y: float, heading: float, ds: float, turn: float) -> Pose:
    """Move along an arc of length ``ds`` (m) turning by ``turn`` (rad); heading not wrapped.

    The chord of the arc is ``ds sinc(turn / 2)`` long and points along the mean heading; this
    form has no singularity at ``turn = 0`` (a straight line), unlike ``R (sin(th + dth) - ...)``.
    """
    half = 0.5 * turn
    chord = ds * sinc(half)
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


def _check_segment(
    segment: Segment, index: int, values: tuple[float, float, float, float, float, float | None]
) -> None:
    """Raise for the first of a segment's velocity, wheel turns or share of the limit that is not
    finite (the sum of finite ones may overflow: then nothing is raised)."""
    linear, angular, left, right, duration, fraction = values
    if not _finite(linear, angular):
        raise _overflow(segment, index, "velocity")
    if not _finite(rpm_from_rad_s(left) * duration, rpm_from_rad_s(right) * duration):
        raise _overflow(segment, index, "wheel speeds or wheel turns")
    if fraction is not None and not _finite(fraction * duration):
        raise _overflow(segment, index, "share of the motor limit")


def _check_extent(planned: list[PlannedSegment], total: float) -> None:
    """Refuse a plan no robot drives: one reaching beyond :data:`MAX_COORDINATE` from its start,
    turning more than :data:`MAX_TURN` in all or lasting ``total`` (s) more than
    :data:`MAX_PLAN_TIME`. Such numbers are unit mistakes or hostile input, and the poses
    printed for them are rounding noise (a heading of 1e18 rad has no digit left below a turn;
    a speed of 1e-300 m/s prints as 0)."""
    for entry in planned:
        end = entry.end_pose
        if max(abs(end.x), abs(end.y)) > MAX_COORDINATE:
            where = f"ends more than {MAX_COORDINATE:g} m from its start"
        elif abs(entry.end_heading) > MAX_TURN:
            where = f"turns more than {MAX_TURN:g} rad from its start heading"
        else:
            continue
        raise PlanError(
            f"segment {entry.index + 1} ({describe_segment(entry.segment)}): the plan {where}, "
            "beyond any drive: a unit mistake?"
        )
    if total > MAX_PLAN_TIME:
        raise PlanError(
            f"the plan takes {total:.6g} s, more than the {MAX_PLAN_TIME:.6g} s (about 292 "
            "years) a ROS time stamp holds: a speed or limit too small, or a duration too long "
            "(a unit mistake?)"
        )


def reported_pose(x: float, y: float, heading: float) -> Pose:
    """A reported pose: heading wrapped to (-pi, pi], and no ``-0.0``."""
    return Pose(x + 0.0, y + 0.0, norm_angle(heading) + 0.0)


def plan(
    segments: Iterable[Segment],
    params: DiffDriveParams,
    speed: float = DEFAULT_SPEED,
    spin_rate: float = DEFAULT_SPIN_RATE,
    fastest: bool = False,
    limit: float | None = None,
    *,
    body: BodyLimits | None = None,
) -> Plan:
    """Plan the velocity commands of a sequence of segments.

    Args:
        segments: the path, starting at pose (0, 0, 0): at most
            :data:`~diffbot.numbers.MAX_SEGMENTS` of them.
        params: the robot.
        speed: cruise path speed (m/s) of straights and arcs without a duration.
        spin_rate: turn rate (rad/s) of spins without a duration (default 0.5 rad/s).
        fastest: give every segment the shortest duration that keeps its wheels within the limit
            (its faster wheel then runs exactly at the limit); given durations are ignored.
        limit: motor limit (rad/s) to check against instead of ``params.max_wheel_speed``.
        body: body velocity limits (:func:`diffbot.body_limits.body_limits`): a segment timed by
            the plan (``fastest``, or at the cruise speeds) takes at least the time that keeps
            its linear and angular velocity within them; a given duration is kept (see
            :func:`diffbot.body_limits.violations`).

    Returns:
        The plan. A wheel over the limit is not an error: see :attr:`Plan.within_limit` and
        :meth:`Plan.violations`.

    Raises:
        PlanError: no segments or more than :data:`~diffbot.numbers.MAX_SEGMENTS` (an endless
            iterable is refused there, not read to its end), a cruise speed or spin rate that
            is not positive, a negative or zero limit (no duration satisfies it), ``fastest``
            without a limit, or a segment whose duration, velocity, wheel speeds, end pose or
            end time overflow (not finite, or a duration that rounds to zero); the message
            names the segment.
    """
    if isinstance(segments, str):
        raise PlanError(
            f"plan() takes segments, not plan text ({brief(segments)}): "
            "read the text with diffbot.parse_plan first"
        )
    fastest = flag(fastest, "fastest", PlanError)
    items = up_to_the_limit(segments)
    if not items:
        raise PlanError("empty plan: no segments")
    for item in items:
        if not isinstance(item, Straight | Arc | Spin):
            raise PlanError(f"not a plan segment: {brief(item)}")
    speed = positive(speed, "the cruise speed (m/s)")
    spin_rate = positive(spin_rate, "the spin rate (rad/s)")
    lim = params.max_wheel_speed if limit is None else as_float(limit)
    if lim is not None and (not math.isfinite(lim) or lim < 0.0):
        raise PlanError(f"the motor limit must be a finite number >= 0 (rad/s), got {brief(limit)}")
    if lim == 0.0:
        raise PlanError("the motor limit is zero: no duration keeps a moving wheel within it")
    if fastest and lim is None:
        raise PlanError(
            "a fastest plan needs a motor limit, and the robot has none "
            "(give one with limit=, or a max_wheel_speed in the parameters)"
        )

    return _planned(items, params, speed, spin_rate, fastest, lim, body)


def built(cls: type[_T], **fields: object) -> _T:
    """An instance of the frozen dataclass ``cls`` with ``fields`` set as given, without its
    ``__init__`` and checks: for segments and plans valid by construction only (a goal plan
    builds thousands; the checks would cost more than the planning).
    """
    instance = object.__new__(cls)
    # The dataclass __init__ sets each frozen field through object.__setattr__: filling the
    # instance's dict at once builds the same object in a fraction of the time.
    instance.__dict__.update(fields)
    return instance


def _planned(
    items: list[Segment],
    params: DiffDriveParams,
    speed: float,
    spin_rate: float,
    fastest: bool,
    lim: float | None,
    body: BodyLimits | None = None,
) -> Plan:
    """The plan of checked arguments: segments, positive finite speeds, a limit above zero or
    None (not None when ``fastest``)."""
    # The loop is the cost of every plan (goal plans build thousands): it works on floats with
    # the same operations, in the same order, as inverse(), limit_fraction() and advance(), and
    # checks the results' finiteness once, naming the failing quantity only when one is not.
    half_separation = 0.5 * params.wheel_separation
    left_radius, right_radius = params.radii
    left_sign, right_sign = params.left_sign, params.right_sign
    # Joint commands are the wheel speeds themselves when both signs are +1 (the usual case).
    same_signs = left_sign == 1 and right_sign == 1
    rpm = rpm_from_rad_s(1.0)  # rpm per rad/s
    isfinite, sin, cos, remainder = math.isfinite, math.sin, math.cos, math.remainder
    new, pi, two_pi = tuple.__new__, math.pi, 2.0 * math.pi
    planned: list[PlannedSegment] = []
    x, y, heading, elapsed = 0.0, 0.0, 0.0, 0.0
    bound = 1.0 + LIMIT_TOLERANCE
    within = True
    start = Pose(0.0, 0.0, 0.0)
    for index, segment in enumerate(items):
        if isinstance(segment, Straight):
            ds, turn = segment.length, 0.0
        elif isinstance(segment, Arc):
            turn = segment.angle if segment.direction == "ccw" else -segment.angle
            ds = segment.radius * segment.angle
            if segment.reverse:
                ds = -ds
        else:
            ds, turn = 0.0, segment.angle
        if fastest:
            assert lim is not None
            # Wheel angles travelled (rad) over the segment; their peak at the limit sets the time.
            track = half_separation * turn
            travel_left, travel_right = (ds - track) / left_radius, (ds + track) / right_radius
            duration = max(abs(travel_left), abs(travel_right)) / lim
        elif segment.duration is not None:
            duration = segment.duration
        elif isinstance(segment, Spin):
            duration = abs(turn) / spin_rate
        else:
            duration = abs(ds) / speed
        if body is not None and (fastest or segment.duration is None):
            duration = max(duration, body.shortest_duration(ds, turn))
        if not (isfinite(duration) and duration > 0.0):
            raise _overflow(segment, index, f"duration ({duration:g} s)")
        linear, angular = ds / duration, turn / duration
        track = half_separation * angular
        left, right = (linear - track) / left_radius, (linear + track) / right_radius
        fraction: float | None = None
        if lim is not None:
            # max() without its call, NaN kept (max(abs(nan), 1.0) would be nan, max(1.0, ...) not)
            a, b = abs(left), abs(right)
            fraction = (a if a > b or a != a else b) / lim
            if not fraction <= bound:
                within = False
        elapsed += duration
        end_heading = heading + turn
        if not isfinite(elapsed + end_heading):
            _check_segment(segment, index, (linear, angular, left, right, duration, fraction))
            if not _finite(elapsed, end_heading):
                raise _overflow(segment, index, "end time or heading")
        half = 0.5 * turn
        chord = ds * (sin(half) / half if half != 0.0 else 1.0)
        mean = heading + half
        end_x, end_y = x + chord * cos(mean), y + chord * sin(mean)
        # One sum is finite exactly when all its terms are (or it overflowed: checked then).
        checked = linear + angular + left * rpm * duration + right * rpm * duration + end_x + end_y
        if fraction is not None:
            checked += fraction * duration
        if not isfinite(checked):
            _check_segment(segment, index, (linear, angular, left, right, duration, fraction))
            if not _finite(end_x, end_y):
                raise _overflow(segment, index, "end pose")
        x, y, heading = end_x, end_y, end_heading
        wrapped = remainder(heading, two_pi)
        # The named tuples' own __new__ is a Python function: tuple.__new__ builds the same.
        end = new(Pose, (x + 0.0, y + 0.0, (pi if wrapped == -pi else wrapped) + 0.0))
        wheels = new(WheelSpeeds, (left, right))
        entry = object.__new__(PlannedSegment)
        entry.__dict__.update(
            segment=segment,
            index=index,
            twist=new(Twist, (linear, angular)),
            duration=duration,
            wheels=wheels,
            joints=wheels
            if same_signs
            else new(WheelSpeeds, (left_sign * left, right_sign * right)),
            fraction=fraction,
            start_pose=start,
            end_pose=end,
            end_heading=heading + 0.0,
        )
        planned.append(entry)
        start = end
    try:
        total = math.fsum([p.duration for p in planned])
    except OverflowError:
        total = math.inf
    if not isfinite(total):
        raise _overflow(items[-1], len(items) - 1, "end time")
    _check_extent(planned, total)
    return built(
        Plan,
        segments=tuple(planned),
        params=params,
        limit=lim,
        duration=total,
        final_pose=start,
        within_limit=within,
    )


def pose_at(p: Plan, t: float) -> Pose:
    """The pose (m, m, rad in (-pi, pi]) that the plan reaches at time ``t`` (s), in closed form.

    Times before 0 give the start pose, times after the plan's duration its final pose.
    """
    t = plan_time(t)
    starts = p._starts
    i = max(0, bisect.bisect_right(starts, t) - 1)
    planned = p.segments[i]
    heading = p.segments[i - 1].end_heading if i > 0 else 0.0
    elapsed = min(max(t - starts[i], 0.0), planned.duration)
    if i == len(p.segments) - 1 and elapsed >= planned.duration:
        return p.final_pose
    start = planned.start_pose
    pose = advance(
        start.x,
        start.y,
        heading,
        float(planned.twist.linear) * elapsed,
        float(planned.twist.angular) * elapsed,
    )
    return reported_pose(pose.x, pose.y, pose.theta)


def _no_time(given: object) -> PlanError:
    return PlanError(f"times must be numbers (s), not NaN, got {brief(given)}")


def plan_time(t: object) -> float:
    """``t`` (s) as a float.

    Raises:
        PlanError: a time that is NaN or no number: it has no place on a plan.
    """
    try:
        number = float(t)  # type: ignore[arg-type]
    except (TypeError, ValueError, OverflowError):
        raise _no_time(t) from None
    if math.isnan(number):
        raise _no_time(t)
    return number


def clipped_times(times: ArrayLike, duration: float) -> NDArray[np.float64]:
    """``times`` (s) as floats clamped to ``[0, duration]``.

    Raises:
        PlanError: a time that is NaN or no number: it has no place on a plan (clamping would
            have turned NaN into poses and angles of NaN).
    """
    import numpy as np

    try:
        t = np.asarray(times, dtype=np.float64)
    except (TypeError, ValueError, OverflowError):
        raise _no_time(times) from None
    if np.isnan(t).any():
        raise _no_time(times)
    return np.clip(t, 0.0, duration)


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

    t = clipped_times(times, p.duration)
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
