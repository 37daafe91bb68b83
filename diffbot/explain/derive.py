"""Worked derivations of the kinematics, a plan and an odometry step, with their numbers.

Every result is the library's own: :func:`~diffbot.kinematics.inverse`,
:func:`~diffbot.kinematics.forward`, :func:`~diffbot.trajectory.plan` and
:class:`~diffbot.odometry.Odometry` compute it, and the derivation only shows how it follows from
the formula. Wheel speeds are also given in rpm, to compare with the motor limit as the class
does (50 rpm for the bundled robot).
"""

from __future__ import annotations

import math

from diffbot.errors import ParameterError
from diffbot.explain.model import Derivation, Quantity, Section, Step, Text
from diffbot.formats.text import ceil_text
from diffbot.kinematics import (
    DiffDriveParams,
    Pose,
    WheelSpeeds,
    forward,
    inverse,
    limit_fraction,
    rpm_from_rad_s,
)
from diffbot.numbers import MAX_RECORDED_ANGLE, finite_in_range
from diffbot.odometry import Odometry
from diffbot.trajectory import Arc, Plan, PlannedSegment, Spin, Straight

__all__ = ["explain_fk", "explain_ik", "explain_odom", "explain_plan"]

#: The pose an odometry step starts from unless told otherwise.
ORIGIN = Pose(0.0, 0.0, 0.0)

#: Significant digits of values in rad/s, m, s... and of values in rpm and percent.
DIGITS = 4
RPM_DIGITS = 3


def _finite(value: float, name: str) -> float:
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be a finite number, got {value!r}") from None
    if not math.isfinite(number):
        raise ParameterError(f"{name} must be a finite number, got {value!r}")
    return number


def _q(value: float, unit: str) -> Quantity:
    return Quantity(float(value) + 0.0, unit, DIGITS)


def _coordinate(value: float) -> Quantity:
    """A pose coordinate (m); below a picometre it is rounding noise (cos(pi/2) is 6e-17), so 0."""
    return _q(0.0 if abs(value) < 1e-12 else value, "m")


def _rpm(speed: float) -> Quantity:
    return Quantity(float(rpm_from_rad_s(speed)) + 0.0, "rpm", RPM_DIGITS)


def _deg(angle: float) -> Quantity:
    return Quantity(math.degrees(angle) + 0.0, "deg", DIGITS)


def _given(label: str, symbol: str, value: Quantity, also: Quantity | None = None) -> Step:
    return Step(Text(label), symbol, value, also=also)


#: The label of each wheel radius symbol.
_RADIUS_LABELS = {
    "r": "label.wheel_radius",
    "rL": "label.left_wheel_radius",
    "rR": "label.right_wheel_radius",
}


def _radii(params: DiffDriveParams) -> tuple[dict[str, Quantity], str]:
    """The wheel radii to show, by symbol, and the suffix of the formulas that use them: one
    radius r when both sides roll with the same, else r_L and r_R (``_sides`` formulas)."""
    left, right = params.radii
    if left == right:
        return {"r": _q(left, "m")}, ""
    return {"rL": _q(left, "m"), "rR": _q(right, "m")}, "_sides"


def _robot(params: DiffDriveParams) -> list[Step]:
    steps = [
        *(_given(_RADIUS_LABELS[symbol], symbol, r) for symbol, r in _radii(params)[0].items()),
        _given("label.wheel_separation", "b", _q(params.wheel_separation, "m")),
    ]
    if params.max_wheel_speed is not None:
        steps.append(
            _given(
                "label.motor_limit",
                "wmax",
                _q(params.max_wheel_speed, "rad/s"),
                _rpm(params.max_wheel_speed),
            )
        )
    return steps


def _wheel_steps(params: DiffDriveParams, v: float, w: float, speeds: WheelSpeeds) -> list[Step]:
    radii, sides = _radii(params)
    values = {
        "v": _q(v, "m/s"),
        "w": _q(w, "rad/s"),
        "b": _q(params.wheel_separation, "m"),
        **radii,
    }
    left, right = float(speeds.left), float(speeds.right)
    return [
        Step(
            Text("label.left_speed"),
            "wL",
            _q(left, "rad/s"),
            f"ik_left{sides}",
            values,
            _rpm(left),
        ),
        Step(
            Text("label.right_speed"),
            "wR",
            _q(right, "rad/s"),
            f"ik_right{sides}",
            values,
            _rpm(right),
        ),
    ]


def _mirrored(params: DiffDriveParams, side: str) -> bool:
    """Whether the joint(s) of a side (``"left"`` or ``"right"``) have a mirrored axis."""
    return (params.left_sign if side == "left" else params.right_sign) == -1


def _from_joint(label: Text, joint: str, wheel: str, value: float, unit: str) -> list[Step]:
    """A mirrored joint's value as given (symbol ``joint``), then the wheel-ground value
    (symbol ``wheel``) it stands for: the same with the sign changed."""
    return [
        Step(Text("label.joint", {"what": label}), joint, _q(value, unit)),
        Step(label, wheel, _q(-value, unit), f"mirror_{joint}", {joint: _q(value, unit)}),
    ]


def _joint_steps(params: DiffDriveParams, speeds: WheelSpeeds) -> list[Step]:
    """The velocity command of each joint whose axis is mirrored: ``q = -ω``."""
    steps = []
    for side, symbol, speed in (("left", "L", speeds.left), ("right", "R", speeds.right)):
        if _mirrored(params, side):
            value = -float(speed)
            steps.append(
                Step(
                    Text("label.joint", {"what": Text(f"label.{side}_speed")}),
                    f"q{symbol}",
                    _q(value, "rad/s"),
                    f"mirror_w{symbol}",
                    {f"w{symbol}": _q(float(speed), "rad/s")},
                    _rpm(value),
                )
            )
    return steps


def _limit_step(
    params: DiffDriveParams, speeds: WheelSpeeds, shortest: float | None = None
) -> list[Step]:
    """The check of the faster wheel against the motor limit; none without a limit."""
    limit = params.max_wheel_speed
    fraction = limit_fraction(params, speeds)
    if limit is None or fraction is None:
        return []
    share = float(fraction)
    peak = max(abs(float(speeds.left)), abs(float(speeds.right)))
    over = share > 1.0
    args = {"peak": _rpm(peak), "limit": _rpm(limit)}
    if over and shortest is not None:
        # Rounded up, as diffbot plan shows it: a duration rounded down would not fit.
        fits = _q(float(ceil_text(shortest, DIGITS)), "s")
        note = Text("check.over_plan", {**args, "duration": fits})
    else:
        note = Text("check.over" if over else "check.within", args)
    return [
        Step(
            Text("label.limit_share"),
            "f",
            _q(share, ""),
            "limit",
            {
                "wL": _q(float(speeds.left), "rad/s"),
                "wR": _q(float(speeds.right), "rad/s"),
                "wmax": _q(limit, "rad/s"),
            },
            Quantity(100.0 * share, "%", RPM_DIGITS),
            note,
        )
    ]


def explain_ik(
    params: DiffDriveParams, linear: float, angular: float, *, joints: bool = False
) -> Derivation:
    """The wheel speeds for a body velocity, worked out step by step.

    Args:
        params: the robot.
        linear: forward speed v (m/s).
        angular: yaw rate ω (rad/s), positive counter-clockwise.

    Returns:
        The given values, each wheel's speed (rad/s and rpm) from
        ``ω_L,R = (v ∓ ω·b/2) / r``, and the check against the motor limit when the robot has one.
        With ``joints``, also the velocity command of each joint whose axis is mirrored
        (``q = -ω``), as ``diffbot ik`` prints it.

    Raises:
        ParameterError: ``linear`` or ``angular`` is not a finite number.
    """
    v = _finite(linear, "linear")
    w = _finite(angular, "angular")
    speeds = inverse(params, v, w)
    given = [
        *_robot(params),
        _given("label.linear", "v", _q(v, "m/s")),
        _given("label.angular", "w", _q(w, "rad/s")),
    ]
    wheels = _wheel_steps(params, v, w, speeds)
    if joints:
        wheels.extend(_joint_steps(params, speeds))
    sections = [
        Section(Text("section.given"), tuple(given)),
        Section(Text("section.wheels"), tuple(wheels)),
    ]
    check = _limit_step(params, speeds)
    if check:
        sections.append(Section(Text("section.limit"), tuple(check)))
    title = Text("title.ik", {"v": _q(v, "m/s"), "w": _q(w, "rad/s")})
    return Derivation(title, tuple(sections))


def explain_fk(
    params: DiffDriveParams, left: float, right: float, *, joints: bool = False
) -> Derivation:
    """The body velocity for two wheel speeds, worked out step by step.

    Args:
        params: the robot.
        left: left wheel-ground angular speed ω_L (rad/s); with ``joints``, the left joint's
            velocity as ``diffbot fk`` takes it (its direction sign undone first).
        right: right wheel-ground angular speed ω_R (rad/s); likewise.
        joints: ``left`` and ``right`` are joint velocities.

    Returns:
        The given values, ``v = r·(ω_L + ω_R)/2`` (m/s), ``ω = r·(ω_R - ω_L)/b`` (rad/s), and the
        check of the wheels against the motor limit when the robot has one.

    Raises:
        ParameterError: ``left`` or ``right`` is not a finite number.
    """
    wl = _finite(left, "left")
    wr = _finite(right, "right")
    given_speeds: list[Step] = []
    for side, symbol, value in (("left", "L", wl), ("right", "R", wr)):
        label = Text(f"label.{side}_speed")
        if joints and _mirrored(params, side):
            given_speeds.extend(_from_joint(label, f"q{symbol}", f"w{symbol}", value, "rad/s"))
        else:
            given_speeds.append(Step(label, f"w{symbol}", _q(value, "rad/s"), also=_rpm(value)))
    if joints:
        wl, wr = params.left_sign * wl, params.right_sign * wr
    twist = forward(params, wl, wr)
    radii, sides = _radii(params)
    values = {
        **radii,
        "wL": _q(wl, "rad/s"),
        "wR": _q(wr, "rad/s"),
        "b": _q(params.wheel_separation, "m"),
    }
    given = [*_robot(params), *given_speeds]
    linear, angular = float(twist.linear), float(twist.angular)
    body = [
        Step(Text("label.linear"), "v", _q(linear, "m/s"), f"fk_linear{sides}", values),
        Step(Text("label.angular"), "w", _q(angular, "rad/s"), f"fk_angular{sides}", values),
    ]
    sections = [
        Section(Text("section.given"), tuple(given)),
        Section(Text("section.body"), tuple(body)),
    ]
    check = _limit_step(params, WheelSpeeds(wl, wr))
    if check:
        sections.append(Section(Text("section.limit"), tuple(check)))
    title = Text("title.fk", {"left": _q(wl, "rad/s"), "right": _q(wr, "rad/s")})
    return Derivation(title, tuple(sections))


def _kind(planned: PlannedSegment) -> Text:
    segment = planned.segment
    if isinstance(segment, Straight):
        return Text("kind.straight", {"length": _q(segment.length, "m")})
    if isinstance(segment, Arc):
        return Text(
            f"kind.{segment.direction}",
            {"radius": _q(segment.radius, "m"), "angle": _deg(segment.angle)},
        )
    return Text("kind.spin", {"angle": _deg(segment.angle)})


def _signed_radius(arc: Arc) -> float:
    """The arc's radius signed as v/ω (m): negative when clockwise forwards or counter-clockwise
    backwards, so that ``s = R·Δθ`` and ``v = ω·R`` hold with the signed s and v."""
    sign = 1.0 if arc.direction == "ccw" else -1.0
    return -sign * arc.radius if arc.reverse else sign * arc.radius


def _geometry(planned: PlannedSegment) -> tuple[list[Step], float, float]:
    """Steps giving the segment's path length s (m, negative backwards) and heading change Δθ
    (rad), and both."""
    segment = planned.segment
    if isinstance(segment, Arc):
        radius = _signed_radius(segment)
        turn = (1.0 if segment.direction == "ccw" else -1.0) * segment.angle
        length = radius * turn  # negative only when driving backwards
        steps = [
            _given("label.radius", "R", _q(radius, "m")),
            _given("label.heading_change", "dtheta", _q(turn, "rad"), _deg(turn)),
            Step(
                Text("label.path_length"),
                "s",
                _q(length, "m"),
                "arc_length",
                {"R": _q(radius, "m"), "dtheta": _q(turn, "rad")},
            ),
        ]
        return steps, length, turn
    if isinstance(segment, Straight):
        length, turn = segment.length, 0.0
    else:
        assert isinstance(segment, Spin)
        length, turn = 0.0, segment.angle
    steps = [
        _given("label.path_length", "s", _q(length, "m")),
        _given("label.heading_change", "dtheta", _q(turn, "rad"), _deg(turn)),
    ]
    return steps, length, turn


def _end_pose(end: Pose, formulas: str, values: dict[str, Quantity]) -> list[Step]:
    """The steps of an end pose: x, y and the heading (rad and degrees), each from the formula
    ``{formulas}_x``, ``{formulas}_y`` or ``{formulas}_theta`` with ``values`` substituted."""
    return [
        Step(Text("label.end_x"), "x1", _coordinate(end.x), f"{formulas}_x", values),
        Step(Text("label.end_y"), "y1", _coordinate(end.y), f"{formulas}_y", values),
        Step(
            Text("label.end_heading"),
            "th1",
            _q(end.theta, "rad"),
            f"{formulas}_theta",
            values,
            _deg(end.theta),
        ),
    ]


def _segment_section(p: Plan, planned: PlannedSegment, shortest: float | None) -> Section:
    params = p.params
    geometry, length, turn = _geometry(planned)
    v, w = float(planned.twist.linear), float(planned.twist.angular)
    t = planned.duration
    steps = [*geometry, _given("label.duration", "t", _q(t, "s"))]
    steps.append(
        Step(
            Text("label.linear"),
            "v",
            _q(v, "m/s"),
            "speed",
            {"s": _q(length, "m"), "t": _q(t, "s")},
        )
    )
    steps.append(
        Step(
            Text("label.angular"),
            "w",
            _q(w, "rad/s"),
            "turn_rate",
            {"dtheta": _q(turn, "rad"), "t": _q(t, "s")},
        )
    )
    if isinstance(planned.segment, Arc):
        radius = _signed_radius(planned.segment)
        steps.append(
            Step(
                Text("label.arc_speed"),
                "v",
                _q(v, "m/s"),
                "arc_speed",
                {"w": _q(w, "rad/s"), "R": _q(radius, "m")},
            )
        )
    steps.extend(_wheel_steps(params, v, w, planned.wheels))
    steps.extend(_joint_steps(params, planned.wheels))
    if p.limit is not None:
        steps.extend(_limit_step(params.replace(max_wheel_speed=p.limit), planned.wheels, shortest))
    start, end = planned.start_pose, planned.end_pose
    pose_values = {
        "x0": _coordinate(start.x),
        "y0": _coordinate(start.y),
        "th0": _q(start.theta, "rad"),
        "s": _q(length, "m"),
        "dtheta": _q(turn, "rad"),
    }
    steps.extend(_end_pose(end, "pose", pose_values))
    title = Text("section.segment", {"number": planned.index + 1, "kind": _kind(planned)})
    return Section(title, tuple(steps))


def explain_plan(p: Plan) -> Derivation:
    """A plan worked out segment by segment.

    Per segment: its path length s (m; ``R·Δθ`` for arcs, with R negative clockwise) and heading
    change Δθ (rad), ``v = s/t``, ``ω = Δθ/t``, for arcs the check ``v = ω·R``, each wheel's speed
    ``(v ∓ ω·b/2)/r`` (rad/s and rpm), the check against the motor limit, and the end pose from
    the closed form ``x₁ = x₀ + s·sinc(Δθ/2)·cos(θ₀ + Δθ/2)`` (likewise y).

    Args:
        p: the plan (see :func:`diffbot.trajectory.plan`); its limit is the one checked.

    Returns:
        The derivation: the robot, then one section per segment.
    """
    robot = _robot(p.params.replace(max_wheel_speed=p.limit))
    sections = [Section(Text("section.given"), tuple(robot))]
    shortest: dict[int, float] = {}
    for found in p.violations() if p.limit is not None else ():
        shortest.setdefault(found.index, found.shortest_duration)
    sections.extend(
        _segment_section(p, planned, shortest.get(planned.index)) for planned in p.segments
    )
    title = Text("title.plan", {"count": len(p.segments), "duration": _q(p.duration, "s")})
    return Derivation(title, tuple(sections))


#: The order the wheel angles are given in: left before and after, then right.
_ANGLE_ORDER = ("L0", "L1", "R0", "R1")


def explain_odom(
    params: DiffDriveParams,
    left0: float,
    right0: float,
    left1: float,
    right1: float,
    dt: float,
    *,
    start: Pose = ORIGIN,
    joints: bool = False,
) -> Derivation:
    """One odometry step worked out: wheel arcs, ds, dθ, the sinc chord and the new pose.

    Args:
        params: the robot (its radius and separation; wheel angles are taken as wheel-ground
            angles, positive rolling forward, so the joints' direction signs do not apply).
        left0: left wheel angle before the step (rad).
        right0: right wheel angle before the step (rad).
        left1: left wheel angle after the step (rad).
        right1: right wheel angle after the step (rad).
        dt: duration of the step (s), > 0.
        start: the pose before the step (m, m, rad).
        joints: the four angles are joint positions, as a recording holds them (and as
            ``diffbot odom`` reads them): the direction signs are undone first.

    Returns:
        The derivation; the new pose and the velocities are those of
        :class:`~diffbot.odometry.Odometry` fed the two samples.

    Raises:
        ParameterError: a value that is not finite, a wheel angle beyond
            :data:`~diffbot.numbers.MAX_RECORDED_ANGLE` (rad), or ``dt`` not > 0.
    """
    # Wheel angles as a recording may hold them (up to MAX_RECORDED_ANGLE): every arc, heading
    # change and degree figure derived from them stays finite.
    angles = [
        finite_in_range(value, name, -MAX_RECORDED_ANGLE, MAX_RECORDED_ANGLE, unit="rad")
        for value, name in (
            (left0, "left0"),
            (right0, "right0"),
            (left1, "left1"),
            (right1, "right1"),
        )
    ]
    step_time = _finite(dt, "dt")
    if step_time <= 0.0:
        raise ParameterError(f"dt must be > 0 (s), got {dt!r}")
    angle_steps: list[Step] = []
    for k, (side, symbol, when) in enumerate(
        (("left", "L", "0"), ("right", "R", "0"), ("left", "L", "1"), ("right", "R", "1"))
    ):
        label = Text(f"label.{side}_{'before' if when == '0' else 'after'}")
        if joints and _mirrored(params, side):
            angle_steps.extend(
                _from_joint(label, f"q{symbol}{when}", f"phi{symbol}{when}", angles[k], "rad")
            )
            angles[k] = -angles[k]
        else:
            angle_steps.append(Step(label, f"phi{symbol}{when}", _q(angles[k], "rad")))
    robot = params.replace(left_sign=1, right_sign=1)
    odom = Odometry(robot, start.x, start.y, start.theta)
    odom.update(angles[0], angles[1], stamp=0.0)
    odom.update(angles[2], angles[3], stamp=step_time)
    pose, twist = odom.pose, odom.twist
    left_radius, right_radius = params.radii
    arc_left = left_radius * (angles[2] - angles[0])
    arc_right = right_radius * (angles[3] - angles[1])
    # From the wheel arcs, as Odometry computes them (and as the formulas show).
    ds = 0.5 * (arc_left + arc_right)
    dth = (arc_right - arc_left) / params.wheel_separation
    half = 0.5 * dth
    chord = ds * (math.sin(half) / half if half != 0.0 else 1.0)
    given = [
        *_robot(params.replace(max_wheel_speed=None)),
        *sorted(angle_steps, key=lambda step: _ANGLE_ORDER.index(step.symbol[-2:])),
        _given("label.time_step", "dt", _q(step_time, "s")),
        _given("label.start_x", "x0", _q(start.x, "m")),
        _given("label.start_y", "y0", _q(start.y, "m")),
        _given("label.start_heading", "th0", _q(start.theta, "rad"), _deg(start.theta)),
    ]
    radii, sides = _radii(params)
    travel = [
        Step(
            Text("label.left_arc"),
            "dL",
            _q(arc_left, "m"),
            f"wheel_arc_left{sides}",
            {**radii, "phiL0": _q(angles[0], "rad"), "phiL1": _q(angles[2], "rad")},
        ),
        Step(
            Text("label.right_arc"),
            "dR",
            _q(arc_right, "m"),
            f"wheel_arc_right{sides}",
            {**radii, "phiR0": _q(angles[1], "rad"), "phiR1": _q(angles[3], "rad")},
        ),
        Step(
            Text("label.distance"),
            "ds",
            _q(ds, "m"),
            "odom_ds",
            {"dL": _q(arc_left, "m"), "dR": _q(arc_right, "m")},
        ),
        Step(
            Text("label.heading_change"),
            "dth",
            _q(dth, "rad"),
            "odom_dth",
            {
                "dL": _q(arc_left, "m"),
                "dR": _q(arc_right, "m"),
                "b": _q(params.wheel_separation, "m"),
            },
            _deg(dth),
        ),
        Step(
            Text("label.chord"),
            "c",
            _q(chord, "m"),
            "chord",
            {"ds": _q(ds, "m"), "dth": _q(dth, "rad")},
        ),
    ]
    pose_values = {
        "x0": _coordinate(start.x),
        "y0": _coordinate(start.y),
        "th0": _q(start.theta, "rad"),
        "c": _q(chord, "m"),
        "dth": _q(dth, "rad"),
        "ds": _q(ds, "m"),
        "dt": _q(step_time, "s"),
    }
    new_pose = [
        *_end_pose(pose, "odom", pose_values),
        Step(Text("label.linear"), "v", _q(float(twist.linear), "m/s"), "odom_v", pose_values),
        Step(Text("label.angular"), "w", _q(float(twist.angular), "rad/s"), "odom_w", pose_values),
    ]
    sections = (
        Section(Text("section.given"), tuple(given)),
        Section(Text("section.travel"), tuple(travel)),
        Section(Text("section.pose"), tuple(new_pose)),
    )
    return Derivation(Text("title.odom", {"dt": _q(step_time, "s")}), sections)
