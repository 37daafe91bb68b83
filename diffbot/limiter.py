"""The speed limiter of ros2_controllers' diff_drive_controller, and the commands it executes.

diff_drive_controller limits linear.x and angular.z separately, each with a
``control_toolbox::RateLimiter``: on every update it limits jerk, then acceleration, then
velocity, from the two commands it executed before (both 0 after activation). This module ports
those semantics so a plan can be checked against what the controller will really command.

Parameter names are those of the controller (``linear.x.max_acceleration`` and so on); the
limits of one axis are a :class:`diffbot.controller_config.AxisLimits`, as a controllers file
gives them. A limit of None (or NaN, as the controller's YAML writes it) is no limit. The
acceleration limits depend on the sign of the previous command: forward (> 0) uses
``max_acceleration`` / ``max_deceleration``, reverse (< 0) ``max_acceleration_reverse`` /
``max_deceleration_reverse``, and standing (== 0) ``max_acceleration_reverse`` /
``max_acceleration``. The jerk limit only acts when the command would increase the acceleration
in the direction of the velocity change (``(dv - dv0)·dv > 0``); easing off is never
jerk-limited, as in the controller.
"""

from __future__ import annotations

import math
from array import array
from dataclasses import fields
from typing import TYPE_CHECKING

import numpy as np

from diffbot.controller_config import AxisLimits
from diffbot.errors import ParameterError
from diffbot.numbers import as_number, positive_finite

if TYPE_CHECKING:
    from numpy.typing import ArrayLike, NDArray

__all__ = ["MAX_UPDATES", "LimiterError", "checked", "execute", "limit"]

#: Longest run of controller updates :func:`execute` simulates before giving up.
MAX_UPDATES = 50_000_000

# Which limits must be >= 0 and which <= 0, as the controller's parameter validation demands.
_NON_NEGATIVE = ("max_velocity", "max_acceleration", "max_deceleration_reverse", "max_jerk")


class LimiterError(ParameterError):
    """A speed limiter's limits are invalid (wrong sign, min above max), or its input is bad."""


def _clamp(value: float, low: float, high: float) -> float:
    return min(max(value, low), high)


def checked(axis: AxisLimits, name: str = "limits") -> AxisLimits:
    """``axis`` with NaN limits unset, after the controller's sign checks.

    The upper limits (``max_velocity``, ``max_acceleration``, ``max_deceleration_reverse``,
    ``max_jerk``) must be >= 0, the lower ones (``min_velocity``, ``min_acceleration``,
    ``max_acceleration_reverse``, ``max_deceleration``, ``min_jerk``) <= 0.

    Raises:
        LimiterError: a limit that is not a number, or has the wrong sign (the message names it).
    """
    values: dict[str, float | None] = {}
    for item in fields(axis):
        value = getattr(axis, item.name)
        if value is not None:
            value = as_number(value, f"{name}.{item.name}", LimiterError, "a number or unset")
            value = None if math.isnan(value) else value
        values[item.name] = value
    for key, value in values.items():
        if value is None:
            continue
        if key in _NON_NEGATIVE and value < 0.0:
            raise LimiterError(f"{name}.{key} must be >= 0 or unset, got {value!r}")
        if key not in _NON_NEGATIVE and value > 0.0:
            raise LimiterError(f"{name}.{key} must be <= 0 or unset, got {value!r}")
    return AxisLimits(**values)


def limit(axis: AxisLimits, v: float, v0: float, v1: float, dt: float) -> float:
    """The command the controller executes: jerk, then acceleration, then velocity limited.

    The jerk limit only acts on a change that grows the acceleration in the direction the
    velocity moves (the controller's rule, which avoids oscillating in closed loop).

    Args:
        axis: the limits (as from :func:`checked`).
        v: the command (m/s, or rad/s).
        v0: the command executed last.
        v1: the command executed before ``v0``.
        dt: the controller's period (s).

    Returns:
        The limited command.
    """
    jerk = axis.jerk_range
    if jerk is not None:
        dv, dv0 = v - v0, v0 - v1
        if (dv - dv0) * dv > 0.0:
            v = v0 + dv0 + _clamp(dv - dv0, jerk[0] * dt * dt, jerk[1] * dt * dt)
    acceleration = axis.acceleration_range(v0)
    if acceleration is not None:
        v = v0 + _clamp(v - v0, acceleration[0] * dt, acceleration[1] * dt)
    velocity = axis.velocity_range
    return v if velocity is None else _clamp(v, *velocity)


def _share(limited: float, last: float, command: float) -> float:
    """How much of the way from ``last`` to ``command`` the limited value went (0 to 1)."""
    if command == last:
        return 1.0
    return min(max((limited - last) / (command - last), 0.0), 1.0)


def _settled(axis: AxisLimits, command: float, v0: float, v1: float, dt: float) -> bool:
    """Whether holding ``command`` keeps the executed velocity at ``v0`` for ever."""
    return v0 == v1 and limit(axis, command, v0, v0, dt) == v0


def _vector(values: ArrayLike, name: str) -> NDArray[np.float64]:
    try:
        array = np.asarray(values, dtype=np.float64)
    except (TypeError, ValueError):
        raise LimiterError(f"{name} must be a sequence of numbers") from None
    if array.ndim != 1 or array.size == 0:
        raise LimiterError(f"{name} must be a non-empty 1-D sequence, got shape {array.shape}")
    return array


def execute(
    times: ArrayLike,
    linear: ArrayLike,
    angular: ArrayLike,
    *,
    linear_limits: AxisLimits,
    angular_limits: AxisLimits,
    rate_hz: float,
    end: float | None = None,
    preserve_turning_radius: bool = False,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """The commands a diff_drive_controller running at ``rate_hz`` executes for a command stream.

    Command ``i`` (``linear[i]`` m/s, ``angular[i]`` rad/s) arrives at ``times[i]`` (s) and holds
    until the next. The controller updates at ``times[0] + k/rate_hz``; an update at the same
    instant as a command (to 1e-9 of a period) sees it. A command with a NaN or infinite part is
    ignored, as the controller does: the previous one stays in force (zero before the first).
    The controller's ``cmd_vel_timeout`` is not modelled: commands hold until replaced.

    Args:
        times: arrival times (s), non-decreasing, finite.
        linear: linear.x commands (m/s), one per time.
        angular: angular.z commands (rad/s), one per time.
        linear_limits: the controller's ``linear.x`` limits.
        angular_limits: the controller's ``angular.z`` limits.
        rate_hz: the controller's update rate (Hz), > 0.
        end: time (s) of the last update; None to run until the executed commands stop changing
            after the last command.
        preserve_turning_radius: after limiting each axis, move both the same share of the
            way from the last executed command to the new one, the smaller share either axis
            allows, so that a turn keeps its radius while it speeds up or slows down (what the
            forks that offer ``preserve_turning_radius`` intend; a model, not their code).

    Returns:
        Update times (s), executed linear (m/s) and angular (rad/s) velocities, one per update.

    Raises:
        LimiterError: bad times, commands, rate or end, or a run longer than ``MAX_UPDATES``.
    """
    stamps = _vector(times, "times")
    lin = _vector(linear, "linear")
    ang = _vector(angular, "angular")
    if not lin.size == ang.size == stamps.size:
        raise LimiterError(
            f"times, linear and angular must have the same length, got "
            f"{stamps.size}, {lin.size} and {ang.size}"
        )
    if not np.isfinite(stamps).all() or (np.diff(stamps) < 0.0).any():
        raise LimiterError("times must be finite and non-decreasing")
    rate = positive_finite(rate_hz, "rate_hz", LimiterError)
    linear_limits = checked(linear_limits, "linear")
    angular_limits = checked(angular_limits, "angular")
    dt = 1.0 / rate
    # Arrivals counted in periods from the first, so update k sees command i when k >= that.
    arrivals = (stamps - stamps[0]) * rate - 1e-9
    last_update: int | None = None
    if end is not None:
        end_time = float(end)
        if not math.isfinite(end_time) or end_time < stamps[0]:
            raise LimiterError(f"end must be finite and >= times[0], got {end!r}")
        last_update = math.floor((end_time - stamps[0]) * rate + 1e-9)
        if last_update >= MAX_UPDATES:
            raise LimiterError(f"end {end!r} needs more than {MAX_UPDATES} updates")
    finite = np.isfinite(lin) & np.isfinite(ang)
    # 8 bytes a value (a list of floats takes 32): a long execution stays small.
    out_v = array("d")
    out_w = array("d")
    v0 = v1 = w0 = w1 = 0.0
    ref_v = ref_w = 0.0
    index = 0
    k = 0
    while True:
        while index < stamps.size and arrivals[index] <= k:
            if finite[index]:
                ref_v, ref_w = float(lin[index]), float(ang[index])
            index += 1
        v = limit(linear_limits, ref_v, v0, v1, dt)
        w = limit(angular_limits, ref_w, w0, w1, dt)
        if preserve_turning_radius:
            # Both axes go the same share of the way to the command, the share the tighter one
            # allows: the executed pair stays on the line from the last one to the command.
            share = min(_share(v, v0, ref_v), _share(w, w0, ref_w))
            v, w = v0 + share * (ref_v - v0), w0 + share * (ref_w - w0)
        out_v.append(v)
        out_w.append(w)
        v1, v0, w1, w0 = v0, v, w0, w
        if last_update is not None:
            if k >= last_update:
                break
        elif (
            index == stamps.size
            and _settled(linear_limits, ref_v, v0, v1, dt)
            and (_settled(angular_limits, ref_w, w0, w1, dt))
        ):
            break
        k += 1
        if k >= MAX_UPDATES:
            raise LimiterError(f"the executed commands did not settle within {MAX_UPDATES} updates")
    t = stamps[0] + np.arange(len(out_v), dtype=np.float64) * dt
    return t, np.frombuffer(out_v, dtype=np.float64).copy(), np.frombuffer(out_w).copy()
