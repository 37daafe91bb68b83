"""What a :class:`diffbot.follow.Follower` takes from its plan: the timed reference as pieces
of a polynomial path coordinate, and the acceleration and jerk limits its commands keep."""

from __future__ import annotations

from typing import TYPE_CHECKING

from diffbot.kinematics import range_share

if TYPE_CHECKING:
    from diffbot.body_limits import BodyLimits
    from diffbot.controller_config import AxisLimits
    from diffbot.kinematics import DiffDriveParams
    from diffbot.ramps import RampedPlan
    from diffbot.trajectory import Plan

__all__ = ["axis_brakes", "axis_limits", "body_share", "controller_limits", "pieces"]


def pieces(plan: Plan | RampedPlan) -> list[tuple[float, ...]]:
    """The plan as pieces ``(t0, x0, y0, h0, linear_gain, angular_gain, p, v, a, j)``: from
    time ``t0`` (s) the path coordinate is ``s = p + v tau + a tau²/2 + j tau³/6`` (tau = t -
    t0) and the pose is ``advance(x0, y0, h0, linear_gain s, angular_gain s)``."""
    from diffbot.trajectory import Plan

    pieces: list[tuple[float, ...]] = []
    if isinstance(plan, Plan):
        elapsed, heading = 0.0, 0.0
        for planned in plan.segments:
            start = planned.start_pose
            v, w = float(planned.twist.linear), float(planned.twist.angular)
            pieces.append((elapsed, start.x, start.y, heading, v, w, 0.0, 1.0, 0.0, 0.0))
            elapsed += planned.duration
            heading = planned.end_heading
        return pieces
    for run in plan.runs:
        x0, y0, h0 = run.start_pose
        for phase in run.profile.phases:
            pieces.append(
                (
                    run.start + phase.start,
                    x0,
                    y0,
                    h0,
                    run.linear_gain,
                    run.angular_gain,
                    phase.position,
                    phase.velocity,
                    phase.acceleration,
                    phase.jerk,
                )
            )
    return pieces


def axis_limits(plan: Plan | RampedPlan, params: DiffDriveParams) -> tuple[AxisLimits, ...]:
    """The (linear, angular) limits pure pursuit's commands keep besides the motor limit: the
    ramped plan's (an untimed law has no other way to keep its ramps), else the controller's,
    else none (an empty tuple)."""
    from diffbot.controller_config import AxisLimits
    from diffbot.trajectory import Plan

    if not isinstance(plan, Plan):
        axes = []
        for path in (plan.limits.linear, plan.limits.angular):
            jerk = path.jerk
            axes.append(
                AxisLimits(
                    max_velocity=path.velocity,
                    max_acceleration=path.acceleration,
                    max_jerk=jerk,
                )
            )
        if any(a.max_acceleration is not None or a.max_jerk is not None for a in axes):
            return tuple(axes)
    return controller_limits(params)


def controller_limits(params: DiffDriveParams) -> tuple[AxisLimits, ...]:
    """The (linear, angular) limits of the robot's own controller, which every command meets
    (the tracking law's too), or none (an empty tuple). A ramped plan's limits are the
    reference's: its feed-forward keeps them, and the feedback that brings the robot back
    onto it must not be held to them, for the reference uses all of them on its ramps."""
    controller = params.controller
    if controller is None:
        return ()
    from diffbot.limiter import checked

    linear, angular = checked(controller.linear, "linear"), checked(controller.angular, "angular")
    if any(
        a.max_acceleration is not None or a.max_jerk is not None or a.max_velocity is not None
        for a in (linear, angular)
    ):
        return linear, angular
    return ()


def axis_brakes(axes: tuple[AxisLimits, ...]) -> tuple[tuple[float | None, float | None], ...]:
    """The (acceleration, jerk) magnitudes (unit/s², unit/s³; None: unlimited) of each axis
    of ``axes``, the tightest of its forward, braking and reverse limits; two unlimited axes
    for none."""
    if not axes:
        return ((None, None), (None, None))

    def tightest(*values: float | None) -> float | None:
        given = [abs(v) for v in values if v is not None and v == v and v != 0.0]
        return min(given) if given else None

    return tuple(
        (
            tightest(
                a.max_acceleration,
                a.min_acceleration,
                a.max_deceleration,
                a.max_acceleration_reverse,
                a.max_deceleration_reverse,
            ),
            tightest(a.max_jerk, a.min_jerk),
        )
        for a in axes
    )


def body_share(v: float, w: float, body: BodyLimits | None) -> float:
    """The share (0 to 1) of ``(v, w)`` (m/s, rad/s) that lies within the body velocity limits
    ``body``: both axes scaled by it keep the command's curvature, as the motor limit does."""
    if body is None:
        return 1.0
    return min(range_share(v, body.linear), range_share(w, body.angular))
