"""Body velocity limits: the highest linear (m/s) and angular (rad/s) velocity a robot is sent.

ros2_controllers' diff_drive_controller reads them as ``linear.x.max_velocity`` /
``linear.x.min_velocity`` and ``angular.z.max_velocity`` / ``angular.z.min_velocity`` (its
``diff_drive_controller_parameter.yaml``; a ``min_velocity`` left out is ``-max_velocity``), and
its update step runs two separate ``SpeedLimiter`` s, ``limiter_linear_`` on linear.x and
``limiter_angular_`` on angular.z (``diff_drive_controller.cpp``): each axis is clamped into its
own range, without regard to the other, so a command over one limit bends the path instead of
slowing down along it. :func:`clamp` does the same; :func:`diffbot.kinematics.saturate` then
keeps the turning radius for the motor limit, which the controller does not know.

A plan keeps within these limits by taking longer: :meth:`BodyLimits.shortest_duration` is the
least time a segment may take, and :func:`violations` lists the segments whose given duration is
shorter.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal

from diffbot.controller_config import AxisLimits
from diffbot.errors import ParameterError, PlanError
from diffbot.kinematics import LIMIT_TOLERANCE, Twist
from diffbot.numbers import (
    as_number,
    finite_in_range,
    positive_finite,
    shown,
    sized,
    store_checked,
)

if TYPE_CHECKING:
    from diffbot.kinematics import DiffDriveParams
    from diffbot.trajectory import Plan

__all__ = [
    "UNLIMITED",
    "BodyLimits",
    "BodyViolation",
    "axis_with_velocity",
    "body_limits",
    "clamp",
    "violations",
    "with_velocity_limits",
]

Range = tuple[float, float]


def _range_check(name: str, unit: str) -> Callable[[object], Range]:
    """The check of a velocity range of :class:`BodyLimits`: (lowest <= 0, highest >= 0),
    finite."""
    expected = f"(lowest <= 0, highest >= 0), finite numbers in {unit}, or None for no limit"

    def check(value: object) -> Range:
        refused = ParameterError(f"{name} must be {expected}, got {shown(value)}")
        pair = sized(value, 2)
        if pair is None:
            raise refused
        try:
            return (
                finite_in_range(pair[0], name, high=0.0),
                finite_in_range(pair[1], name, low=0.0),
            )
        except ParameterError:
            raise refused from None

    return check


@dataclass(frozen=True)
class BodyLimits:
    """The (lowest, highest) linear velocity (m/s) and angular velocity (rad/s); None where
    there is no limit (:data:`UNLIMITED`: on neither axis). Each range holds 0, its bounds
    finite: an infinite one is refused, as no limit is None."""

    linear: Range | None = None
    angular: Range | None = None

    def __post_init__(self) -> None:
        store_checked(self, "linear", _range_check("linear", "m/s"), optional=True)
        store_checked(self, "angular", _range_check("angular", "rad/s"), optional=True)

    @property
    def unlimited(self) -> bool:
        """True when neither axis has a limit."""
        return self.linear is None and self.angular is None

    def shortest_duration(self, distance: float, turn: float) -> float:
        """The least time (s) to drive ``distance`` (m, signed) while turning by ``turn`` (rad,
        signed) at one constant twist within the limits; 0 without limits.

        Raises:
            PlanError: the motion needs a direction the limits forbid (a lowest linear velocity
                of 0 and a backward distance, say).
        """
        least = 0.0
        for value, bounds, what in (
            (distance, self.linear, "linear"),
            (turn, self.angular, "angular"),
        ):
            if bounds is None or value == 0.0:
                continue
            bound = bounds[1] if value > 0.0 else -bounds[0]
            if bound <= 0.0:
                ways = ("forward", "backward") if what == "linear" else ("left", "right")
                way = ways[0] if value > 0.0 else ways[1]
                unit = "m/s" if what == "linear" else "rad/s"
                raise PlanError(
                    f"the {what} velocity limits ({bounds[0]:g} to {bounds[1]:g} {unit}) allow "
                    f"no {way} motion"
                )
            least = max(least, abs(value) / bound)
        return least


#: No body velocity limit at all.
UNLIMITED = BodyLimits()


def _axis(axis: AxisLimits, override: float | None, name: str) -> Range | None:
    """The velocity range of ``axis`` (NaN is unset), its highest replaced by ``override`` and
    its lowest then no lower than ``-override``, after the controller's sign checks (highest
    >= 0, lowest <= 0)."""
    high = axis.max_velocity if override is None else override
    if override is not None:
        high = positive_finite(override, name, ParameterError)
    low = axis.min_velocity
    values = []
    for value, what in ((high, "max_velocity"), (low, "min_velocity")):
        if value is not None:
            value = as_number(value, f"{name}.{what}", ParameterError, "a number or unset")
            value = None if math.isnan(value) else value
        values.append(value)
    high, low = values
    if high is not None and high < 0.0:
        raise ParameterError(f"{name}: max_velocity must be >= 0 or unset, got {high!r}")
    if low is not None and low > 0.0:
        raise ParameterError(f"{name}: min_velocity must be <= 0 or unset, got {low!r}")
    if override is not None and low is not None and high is not None:
        low = max(low, -high)
    return dataclasses.replace(AxisLimits(), max_velocity=high, min_velocity=low).velocity_range


def body_limits(
    params: DiffDriveParams,
    max_linear: float | None = None,
    max_angular: float | None = None,
) -> BodyLimits:
    """The body velocity limits of a robot: the controller's ``linear.x`` and ``angular.z``
    velocity limits (when its configuration has them), each ``max_velocity`` replaced by
    ``max_linear`` (m/s) or ``max_angular`` (rad/s) when given. An override bounds the speed
    both ways: the lowest velocity is then ``-max_linear`` (or ``-max_angular``), or the file's
    ``min_velocity`` where that is closer to 0 (a controller that never reverses stays so).
    Without an override, a ``min_velocity`` left out is ``-max_velocity``, as in the controller.

    Raises:
        ParameterError: an override that is not a positive finite number, or a file's limits
            with the wrong signs.
    """
    controller = params.controller
    linear = AxisLimits() if controller is None else controller.linear
    angular = AxisLimits() if controller is None else controller.angular
    return BodyLimits(
        _axis(linear, max_linear, "max_linear_velocity"),
        _axis(angular, max_angular, "max_angular_velocity"),
    )


def clamp(twist: Twist, limits: BodyLimits) -> Twist:
    """``twist`` with linear and angular velocity each clamped into its own range, apart, as
    diff_drive_controller's two speed limiters do (the turning radius changes when one is
    clamped)."""
    linear, angular = float(twist.linear), float(twist.angular)
    if limits.linear is not None:
        linear = min(max(linear, limits.linear[0]), limits.linear[1])
    if limits.angular is not None:
        angular = min(max(angular, limits.angular[0]), limits.angular[1])
    return Twist(linear, angular)


def over(twist: Twist, limits: BodyLimits) -> list[Literal["linear", "angular"]]:
    """The axes of ``twist`` beyond their limits (beyond the tolerance of motor checks)."""
    found: list[Literal["linear", "angular"]] = []
    pairs: tuple[tuple[Literal["linear", "angular"], float, Range | None], ...] = (
        ("linear", float(twist.linear), limits.linear),
        ("angular", float(twist.angular), limits.angular),
    )
    for name, value, bounds in pairs:
        if bounds is None:
            continue
        slack = 1.0 + LIMIT_TOLERANCE
        if not bounds[0] * slack <= value <= bounds[1] * slack:
            found.append(name)
    return found


@dataclass(frozen=True)
class BodyViolation:
    """A segment whose body velocity is over a limit.

    Attributes:
        index: position of the segment in the plan (0-based).
        axis: ``"linear"`` (m/s) or ``"angular"`` (rad/s).
        value: the segment's velocity on that axis.
        bounds: the (lowest, highest) velocity allowed.
        shortest_duration: the least duration of the segment within both limits (s).
    """

    index: int
    axis: Literal["linear", "angular"]
    value: float
    bounds: Range
    shortest_duration: float


def violations(plan: Plan, limits: BodyLimits) -> list[BodyViolation]:
    """Every segment axis of ``plan`` over ``limits``, in order (linear before angular)."""
    found: list[BodyViolation] = []
    for planned in plan.segments:
        axes = over(planned.twist, limits)
        if not axes:
            continue
        distance = float(planned.twist.linear) * planned.duration
        turn = float(planned.twist.angular) * planned.duration
        least = limits.shortest_duration(distance, turn)
        for axis in axes:
            value = float(getattr(planned.twist, axis))
            bounds = limits.linear if axis == "linear" else limits.angular
            assert bounds is not None
            found.append(BodyViolation(planned.index, axis, value, bounds, least))
    return found


def with_velocity_limits(params: DiffDriveParams, limits: BodyLimits) -> DiffDriveParams:
    """``params`` whose controller configuration's velocity limits are ``limits`` (the given
    ones replace the file's, so that its speed limiter clamps where the plan was bounded);
    unchanged without a controller configuration."""
    controller = params.controller
    if controller is None:
        return params
    return params.replace(
        controller=dataclasses.replace(
            controller,
            linear=axis_with_velocity(controller.linear, limits.linear),
            angular=axis_with_velocity(controller.angular, limits.angular),
        )
    )


def axis_with_velocity(axis: AxisLimits, bounds: Range | None) -> AxisLimits:
    """``axis`` with its velocity limits set to ``bounds`` (lowest, highest), when given."""
    if bounds is None:
        return axis
    return dataclasses.replace(axis, min_velocity=bounds[0], max_velocity=bounds[1])
