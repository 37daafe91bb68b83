"""Plans to a goal pose and through waypoints, in one of four shapes.

- ``fastest``: the time-optimal path of a differential drive whose wheels share one speed bound
  (Balkcom and Mason 2002; :mod:`diffbot.planning.balkcom_mason`): turns in place and straights,
  backwards too unless ``forward_only``; it runs at the whole motor limit, unless ``cruise``
  asks for the cruise speeds (and never beyond the body velocity limits ``body``).
- ``spin-straight-spin``: turn to face the goal, drive to it, turn to the goal heading.
- ``dubins``: the shortest forward path whose arcs have the radius ``min_radius``
  (:mod:`diffbot.planning.dubins`).
- ``reeds-shepp``: the same driving both ways (:mod:`diffbot.planning.reeds_shepp`).

The result is an ordinary :class:`~diffbot.trajectory.Plan` of ``spin``, ``straight`` and arc
segments (``reverse`` ones driving backwards). A plan starts at its own origin: its poses are
relative to the start pose, so the plan's final pose is the goal seen from the start. Positions
in metres, headings in radians; pure functions, no I/O.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Literal, get_args

from diffbot.errors import PlanError
from diffbot.formats.text import brief
from diffbot.kinematics import DiffDriveParams, Pose
from diffbot.numbers import MAX_COORDINATE, MAX_WAYPOINTS, WHEEL_SIZE_RANGE
from diffbot.planning import ROUNDING, Piece, balkcom_mason, dubins, reeds_shepp
from diffbot.trajectory import (
    DEFAULT_SPEED,
    DEFAULT_SPIN_RATE,
    Arc,
    Plan,
    Segment,
    Spin,
    Straight,
    as_float,
    built,
    plan,
)

if TYPE_CHECKING:
    from diffbot.body_limits import BodyLimits

__all__ = [
    "OPTIONS",
    "ORIGIN",
    "SHAPES",
    "Shape",
    "ShapeTime",
    "Waypoint",
    "plan_through",
    "plan_to",
    "relative_pose",
    "shape_times",
    "waypoint_poses",
]

Shape = Literal["fastest", "spin-straight-spin", "dubins", "reeds-shepp"]
SHAPES: tuple[Shape, ...] = get_args(Shape)
#: The origin, heading along x.
ORIGIN = (0.0, 0.0, 0.0)
_ORIGIN = Pose(*ORIGIN)
#: A waypoint: x, y (m) and a heading (rad), or None for the direction of the next leg.
Waypoint = tuple[float, float, float | None]


def _number(value: object, what: str) -> float:
    """A coordinate (m) or heading (rad) within ±1e9: beyond, no robot drives, and a heading
    keeps no digit below a turn."""
    if type(value) is float and -MAX_COORDINATE <= value <= MAX_COORDINATE:
        return value
    number = as_float(value)
    if not (math.isfinite(number) and abs(number) <= MAX_COORDINATE):
        raise PlanError(
            f"{what} must be a finite number within ±{MAX_COORDINATE:g}, got {brief(value)}"
        )
    return number


def _count(value: object, what: str, expected: str) -> int:
    """How many items ``value`` holds; not a sequence (None, a number), a :class:`PlanError`."""
    try:
        return len(value)  # type: ignore[arg-type]
    except TypeError:
        raise PlanError(f"{what} must be {expected}, got {brief(value)}") from None


def _pose(value: Sequence[float], what: str) -> Pose:
    if value is ORIGIN:
        return _ORIGIN
    if _count(value, what, "x, y and a heading") != 3:
        raise PlanError(f"{what} must be x, y and a heading, got {brief(value)}")
    x, y, heading = value
    # The named tuple's own __new__ is a Python function: tuple.__new__ builds the same.
    return tuple.__new__(Pose, (_number(x, what), _number(y, what), _number(heading, what)))


def _waypoint(value: Sequence[float | None], number: int) -> Waypoint:
    what = f"waypoint {number}"
    if _count(value, what, "x, y and an optional heading") not in (2, 3):
        raise PlanError(f"{what} must be x, y and an optional heading, got {brief(value)}")
    heading = value[2] if len(value) == 3 else None
    x, y = (_number(v, what) for v in value[:2])
    return x, y, None if heading is None else _number(heading, what)


def relative_pose(start: Pose, goal: Pose) -> Pose:
    """The goal seen from the start: its position in the start's frame (m) and the heading
    change (rad, not wrapped)."""
    c, s = math.cos(start.theta), math.sin(start.theta)
    dx, dy = goal.x - start.x, goal.y - start.y
    return Pose(c * dx + s * dy, -s * dx + c * dy, goal.theta - start.theta)


def _check_shape(shape: str, min_radius: float | None, forward_only: bool) -> float | None:
    if shape not in SHAPES:
        raise PlanError(f"unknown shape {brief(shape)}: give one of {', '.join(SHAPES)}")
    if min_radius is not None:
        radius = as_float(min_radius)
        low = WHEEL_SIZE_RANGE[0]
        if not (math.isfinite(radius) and low <= radius <= MAX_COORDINATE):
            raise PlanError(
                f"{{min_radius}} (the minimum turning radius) must be a positive finite number "
                f"from {low:g} to "
                f"{MAX_COORDINATE:g} (m), got {brief(min_radius)}"
            )
        min_radius = radius
    if shape in ("dubins", "reeds-shepp") and min_radius is None:
        raise PlanError(f"the {shape} shape needs a minimum turning radius: give {{min_radius}}")
    if shape == "reeds-shepp" and forward_only:
        raise PlanError("reeds-shepp drives both ways: with {forward_only}, the shape is dubins")
    return min_radius


def _joined(pieces: list[Piece], unit: float) -> list[Piece]:
    """The pieces without those too short to drive (turns in rad, straights in metres, ``unit``
    metres per unit of a straight's length), the neighbours such a piece parted joined: a turn
    and the turn back a sliver of a straight apart (a goal 1e-18 m to the side) are no turn at
    all, not two."""
    out: list[Piece] = []
    for kind, length in pieces:
        scale = unit if kind == "S" else 1.0
        if abs(length) * scale <= ROUNDING:
            continue
        if out and out[-1].kind == kind:
            length += out.pop().length
            if abs(length) * scale <= ROUNDING:
                continue  # they undo each other
        out.append(Piece(kind, length))
    return out


def _arcs(pieces: list[Piece], radius: float) -> list[Segment]:
    """Reeds-Shepp or Dubins pieces (radii) as arcs and straights (m)."""
    # The segments are valid by construction (a positive finite radius, angles and lengths
    # above the rounding, as _joined leaves them): built as built() builds them, without their
    # checks, inline (a goal plan's segments cost more than its path otherwise).
    new = object.__new__
    out: list[Segment] = []
    for kind, length in _joined(pieces, radius):
        segment: Segment
        if kind == "S":
            segment = new(Straight)
            segment.__dict__.update(length=length * radius, duration=None)
        else:
            # A left turn driven backwards turns the heading clockwise (and a right one, ccw).
            reverse = length < 0.0
            segment = new(Arc)
            segment.__dict__.update(
                radius=radius,
                angle=-length if reverse else length,
                direction="cw" if (kind == "L") == reverse else "ccw",
                duration=None,
                reverse=reverse,
            )
        out.append(segment)
    return out


def _turns(pieces: list[Piece], half_track: float) -> list[Segment]:
    """Time-optimal pieces (turns in rad, straights in half tracks) as spins and straights."""
    return [
        built(Spin, angle=length, duration=None)
        if kind == "T"
        else built(Straight, length=length * half_track, duration=None)
        for kind, length in _joined(pieces, half_track)
    ]


def _leg(
    start: Pose, goal: Pose, half: float, shape: Shape, radius: float | None, forward_only: bool
) -> list[Segment]:
    """The segments of the path of ``shape`` from ``start`` to ``goal`` (m, rad) for a robot of
    half wheel separation ``half`` (m); empty when the goal is the start."""
    # relative_pose() without its Pose.
    c, s = math.cos(start.theta), math.sin(start.theta)
    dx, dy = goal.x - start.x, goal.y - start.y
    x, y = c * dx + s * dy, -s * dx + c * dy
    turn = math.remainder(goal.theta - start.theta, 2.0 * math.pi)
    if x == 0.0 and y == 0.0 and turn == 0.0:
        return []
    if shape == "fastest":
        return _turns(balkcom_mason.path(x / half, y / half, turn, forward_only), half)
    if shape == "spin-straight-spin":
        distance = math.hypot(x, y)
        if distance == 0.0:
            return [Spin(turn)]
        facing = math.atan2(y, x)
        pieces = [
            Piece("T", facing),
            Piece("S", distance),
            Piece("T", math.remainder(turn - facing, 2.0 * math.pi)),
        ]
        return _turns(pieces, 1.0)
    assert radius is not None
    if shape == "dubins":
        return _arcs(dubins.path(x / radius, y / radius, turn), radius)
    return _arcs(reeds_shepp.path(x / radius, y / radius, turn), radius)


def _empty(params: DiffDriveParams, limit: float | None) -> Plan:
    lim = params.max_wheel_speed if limit is None else limit
    return built(
        Plan,
        segments=(),
        params=params,
        limit=lim,
        duration=0.0,
        final_pose=Pose(0.0, 0.0, 0.0),
        within_limit=True,
    )


def _timing(shape: Shape, params: DiffDriveParams, fastest: bool, limit: float | None) -> bool:
    """Whether the plan runs at the motor limit: asked for, or the fastest shape with a limit."""
    has_limit = limit is not None or params.max_wheel_speed is not None
    return fastest or (shape == "fastest" and has_limit)


def plan_to(
    goal: Sequence[float],
    params: DiffDriveParams,
    *,
    start: Sequence[float] = ORIGIN,
    shape: Shape = "fastest",
    min_radius: float | None = None,
    forward_only: bool = False,
    speed: float = DEFAULT_SPEED,
    spin_rate: float = DEFAULT_SPIN_RATE,
    fastest: bool = False,
    limit: float | None = None,
    body: BodyLimits | None = None,
    cruise: bool = False,
) -> Plan:
    """The plan that drives from ``start`` to ``goal`` along the path of ``shape``.

    Args:
        goal: x, y (m) and heading (rad) to reach.
        params: the robot.
        start: x, y (m) and heading (rad) to start from (default the origin, heading x).
        shape: ``fastest``, ``spin-straight-spin``, ``dubins`` or ``reeds-shepp``.
        min_radius: turning radius of the dubins and reeds-shepp arcs (m), > 0.
        forward_only: never drive backwards (fastest; dubins always drives forwards).
        speed, spin_rate: cruise speeds (m/s, rad/s) of the segments, as in
            :func:`~diffbot.trajectory.plan`; the fastest shape runs at the whole motor limit
            when the robot has one, unless ``cruise``.
        fastest: run every segment at the motor limit.
        limit: motor limit (rad/s) instead of ``params.max_wheel_speed``.
        body: body velocity limits (m/s, rad/s) no segment exceeds: segments timed at the motor
            limit or the cruise speeds take longer where these ask for it.
        cruise: time the fastest shape at ``speed`` and ``spin_rate`` too, not at the motor
            limit (the shape stays the least-time path of the wheels).

    Returns:
        The plan; its poses are relative to ``start``, so its final pose is the goal seen from
        the start. A goal equal to the start gives a plan without segments (duration 0).

    Raises:
        PlanError: a number that is not finite, an unknown shape, a minimum radius that is not
            positive, dubins or reeds-shepp without one, reeds-shepp with ``forward_only``.
    """
    there = _pose(goal, "the goal")
    here = _pose(start, "the start")
    forward_only = bool(forward_only)
    radius = _check_shape(shape, min_radius, forward_only)
    return _legs(
        here,
        [there],
        params,
        shape,
        radius,
        forward_only,
        speed,
        spin_rate,
        fastest,
        limit,
        body,
        cruise,
    )


def _legs(
    here: Pose,
    poses: list[Pose],
    params: DiffDriveParams,
    shape: Shape,
    radius: float | None,
    forward_only: bool,
    speed: float,
    spin_rate: float,
    fastest: bool,
    limit: float | None,
    body: BodyLimits | None,
    cruise: bool,
) -> Plan:
    """The plan from ``here`` through ``poses`` (checked): one leg of ``shape`` to each; forward
    only when the body limits allow no backward motion."""
    if body is not None and body.linear is not None and body.linear[0] >= 0.0:
        if shape == "reeds-shepp":
            raise PlanError(
                f"the linear velocity limits ({body.linear[0]:g} to {body.linear[1]:g} m/s) "
                "allow no backward motion, and reeds-shepp drives both ways: the shape is dubins"
            )
        forward_only = True
    segments: list[Segment] = []
    half = 0.5 * params.wheel_separation
    for pose in poses:
        segments += _leg(here, pose, half, shape, radius, forward_only)
        here = pose
    if not segments:
        return _empty(params, limit)
    at_limit = fastest or (not cruise and _timing(shape, params, fastest, limit))
    return plan(
        segments,
        params,
        speed=speed,
        spin_rate=spin_rate,
        fastest=at_limit,
        limit=limit,
        body=body,
    )


def waypoint_poses(
    waypoints: Sequence[Sequence[float | None]], start: Sequence[float] = ORIGIN
) -> list[Pose]:
    """The waypoints as poses: one without a heading takes the direction of the next leg (the
    last one, of the leg that reaches it; where a leg has no length, the heading before)."""
    if _count(waypoints, "waypoints", "a sequence of (x, y[, heading])") == 0:
        raise PlanError("no waypoints: give at least one")
    if len(waypoints) > MAX_WAYPOINTS:
        raise PlanError(
            f"{len(waypoints)} waypoints, more than the {MAX_WAYPOINTS} a plan may go through: "
            "split the route into several plans"
        )
    points = [_waypoint(w, i + 1) for i, w in enumerate(waypoints)]
    previous = _pose(start, "the start")
    poses: list[Pose] = []
    for i, (x, y, heading) in enumerate(points):
        if heading is None:
            if i + 1 < len(points):
                leg = (points[i + 1][0] - x, points[i + 1][1] - y)
            else:
                leg = (x - previous.x, y - previous.y)
            heading = math.atan2(leg[1], leg[0]) if leg != (0.0, 0.0) else previous.theta
        previous = Pose(x, y, heading)
        poses.append(previous)
    return poses


#: The keyword options of :func:`plan_to` that :func:`plan_through` and :func:`shape_times` take.
OPTIONS = (
    "start",
    "shape",
    "min_radius",
    "forward_only",
    "speed",
    "spin_rate",
    "fastest",
    "limit",
    "body",
    "cruise",
)


def _check_options(options: dict[str, Any], function: str) -> None:
    unknown = sorted(set(options) - set(OPTIONS))
    if unknown:
        raise TypeError(f"{function}() got unexpected keyword arguments: {', '.join(unknown)}")


def plan_through(
    waypoints: Sequence[Sequence[float | None]], params: DiffDriveParams, **options: Any
) -> Plan:
    """The plan through every waypoint in turn, consecutive legs joined with ``shape``.

    Args:
        waypoints: x, y (m) and optionally a heading (rad, or None): one without a heading takes
            the direction of the next leg (see :func:`waypoint_poses`).
        params: the robot.
        **options: ``start``, ``shape``, ``min_radius``, ``forward_only``, ``speed``,
            ``spin_rate``, ``fastest``, ``limit``, ``body``, ``cruise``: as in :func:`plan_to`.

    Returns:
        One plan of every leg's segments, poses relative to ``start``; without segments when
        every waypoint is where the robot already is.

    Raises:
        PlanError: no waypoints, a waypoint that is not two or three finite numbers, and what
            :func:`plan_to` raises.
    """
    _check_options(options, "plan_through")
    here = _pose(options.get("start", ORIGIN), "the start")
    shape: Shape = options.get("shape", "fastest")
    forward_only = bool(options.get("forward_only", False))
    radius = _check_shape(shape, options.get("min_radius"), forward_only)
    return _legs(
        here,
        waypoint_poses(waypoints, here),
        params,
        shape,
        radius,
        forward_only,
        options.get("speed", DEFAULT_SPEED),
        options.get("spin_rate", DEFAULT_SPIN_RATE),
        options.get("fastest", False),
        options.get("limit"),
        options.get("body"),
        bool(options.get("cruise", False)),
    )


@dataclass(frozen=True)
class ShapeTime:
    """How long one shape takes through the same poses.

    Attributes:
        shape: the shape.
        duration: its time (s), or None when it cannot be planned (no minimum radius; reeds-shepp
            with forward only).
        segments: how many segments it has (0 when None).
    """

    shape: Shape
    duration: float | None
    segments: int


def shape_times(
    waypoints: Sequence[Sequence[float | None]], params: DiffDriveParams, **options: Any
) -> list[ShapeTime]:
    """Every shape's time through the same waypoints (``options`` as in :func:`plan_through`,
    without ``shape``), timed alike: at the motor limit when the robot has one (or ``fastest``
    asks for it) unless ``cruise``, else at the cruise speeds."""
    _check_options(options, "shape_times")
    limit = options.get("limit")
    has_limit = limit is not None or params.max_wheel_speed is not None
    at_limit = options.get("fastest", False) or (has_limit and not options.get("cruise", False))
    out: list[ShapeTime] = []
    for shape in SHAPES:
        arcs = shape in ("dubins", "reeds-shepp")
        if (arcs and options.get("min_radius") is None) or (
            shape == "reeds-shepp" and options.get("forward_only", False)
        ):
            out.append(ShapeTime(shape, None, 0))
            continue
        p = plan_through(waypoints, params, **{**options, "shape": shape, "fastest": at_limit})
        out.append(ShapeTime(shape, p.duration, len(p.segments)))
    return out
