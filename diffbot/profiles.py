"""Time-optimal 1-D motion profiles along a path, with speed, acceleration and jerk limits.

A profile moves a path coordinate ``s`` from 0 to ``length``: metres along a straight or an arc,
radians of heading for a spin in place. It is an exact piecewise polynomial (degree 2 for a
trapezoid, 3 for an S-curve), so poses along a segment can be integrated in closed form.

Limits on the robot (linear and angular speed, wheel speed, their accelerations and jerks) become
limits on the path coordinate through :func:`path_limits`; :func:`time_optimal` then gives the
fastest profile that respects them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields
from typing import TYPE_CHECKING, NamedTuple, TypeVar

import numpy as np

from diffbot.errors import PlanError
from diffbot.kinematics import DiffDriveParams
from diffbot.numbers import MAX_PLAN_DURATION, as_number

if TYPE_CHECKING:
    from numpy.typing import NDArray

    from diffbot.trajectory import Segment

__all__ = [
    "UNBOUNDED",
    "Limits",
    "PathLimits",
    "Phase",
    "Profile",
    "ProfileError",
    "path_limits",
    "scurve",
    "segment_limits",
    "time_optimal",
    "trapezoid",
]


#: A time or an array of times; the profile's values come back in the same form.
_Time = TypeVar("_Time", float, "NDArray[np.float64]")


class ProfileError(PlanError):
    """A profile cannot be built: a bad length or limit, or boundary speeds it cannot join."""


class Phase(NamedTuple):
    """One polynomial piece of a profile, with the state it starts from.

    Attributes:
        start: start time (s) from the beginning of the profile.
        duration: length of the piece (s), > 0.
        jerk: constant jerk over the piece (unit/s³; unit is m or rad).
        acceleration: acceleration at its start (unit/s²).
        velocity: velocity at its start (unit/s).
        position: position at its start (unit).
    """

    start: float
    duration: float
    jerk: float
    acceleration: float
    velocity: float
    position: float


def _number(value: float, what: str) -> float:
    number = as_number(value, what, ProfileError)
    if math.isnan(number):
        raise ProfileError(f"{what} must be a number, got {value!r}")
    return number


def _limit(value: float | None, what: str) -> float:
    """A limit as a float: positive, +inf for None (no limit)."""
    if value is None:
        return math.inf
    number = _number(value, what)
    if number <= 0.0:
        raise ProfileError(f"{what} must be positive (no motion is possible at 0), got {value!r}")
    return number


@dataclass(frozen=True)
class Profile:
    """A motion profile: position, velocity and acceleration along the path as functions of time.

    Built by :func:`trapezoid`, :func:`scurve` or :func:`time_optimal`. Outside ``[0, duration]``
    every function returns its value at the nearest end (the time is clamped).

    Attributes:
        length: distance to travel (m, or rad for a spin), >= 0.
        phases: the polynomial pieces in time order; pieces that vanish are left out.
    """

    length: float
    phases: tuple[Phase, ...]
    _starts: NDArray[np.float64] = field(init=False, repr=False, compare=False)
    _table: NDArray[np.float64] = field(init=False, repr=False, compare=False)
    _lengths: NDArray[np.float64] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        starts = np.array([p.start for p in self.phases], dtype=np.float64)
        table = np.array(
            [(p.position, p.velocity, p.acceleration, p.jerk) for p in self.phases],
            dtype=np.float64,
        ).reshape(-1, 4)
        object.__setattr__(self, "_starts", starts)
        object.__setattr__(self, "_table", table)
        object.__setattr__(
            self, "_lengths", np.array([p.duration for p in self.phases], dtype=np.float64)
        )

    @property
    def duration(self) -> float:
        """Total time (s)."""
        if not self.phases:
            return 0.0
        last = self.phases[-1]
        return last.start + last.duration

    def _locate(
        self, t: float | NDArray[np.float64]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        times = np.clip(np.asarray(t, dtype=np.float64), 0.0, self.duration)
        index = np.clip(np.searchsorted(self._starts, times, side="right") - 1, 0, None)
        # start + duration rounds, so the end is found by comparison, not by subtraction.
        tau = np.where(
            times >= self.duration,
            self._lengths[index],
            np.minimum(times - self._starts[index], self._lengths[index]),
        )
        return tau, self._table[index]

    def position(self, t: _Time) -> _Time:
        """Position along the path (m or rad) at time ``t`` (s; a float or an array)."""
        if not self.phases:
            return _like(t, 0.0)
        tau, c = self._locate(t)
        value = c[..., 0] + tau * (c[..., 1] + tau * (c[..., 2] / 2.0 + tau * c[..., 3] / 6.0))
        return _out(t, value)

    def velocity(self, t: _Time) -> _Time:
        """Velocity along the path (m/s or rad/s) at time ``t`` (s; a float or an array)."""
        if not self.phases:
            return _like(t, 0.0)
        tau, c = self._locate(t)
        return _out(t, c[..., 1] + tau * (c[..., 2] + tau * c[..., 3] / 2.0))

    def acceleration(self, t: _Time) -> _Time:
        """Acceleration along the path (m/s² or rad/s²) at time ``t`` (s; a float or an array).

        Where a trapezoid's acceleration jumps, the value is the one of the phase that starts
        there.
        """
        if not self.phases:
            return _like(t, 0.0)
        tau, c = self._locate(t)
        return _out(t, c[..., 2] + tau * c[..., 3])


def _like(t: _Time, value: float) -> _Time:
    return _out(t, np.full(np.shape(t), value, dtype=np.float64))


def _out(t: _Time, value: NDArray[np.float64]) -> _Time:
    """``value`` shaped as the time asked for: an array for an array, a float for a float."""
    if isinstance(t, np.ndarray):
        return value
    return float(value)


def _build(length: float, v_start: float, pieces: list[tuple[float, float, float]]) -> Profile:
    """Chain (duration, jerk, start acceleration) pieces into a profile, dropping empty ones.

    Start accelerations are given, not integrated, so the plateaus hold their exact limit.
    """
    phases: list[Phase] = []
    start = position = 0.0
    velocity = v_start
    for duration, jerk, acceleration in pieces:
        if duration <= 0.0:
            continue
        phases.append(Phase(start, duration, jerk, acceleration, velocity, position))
        t = duration
        position += t * (velocity + t * (acceleration / 2.0 + t * jerk / 6.0))
        velocity += t * (acceleration + t * jerk / 2.0)
        start += duration
    return Profile(length, tuple(phases))


def _check_length(length: float) -> float:
    number = _number(length, "length")
    if not math.isfinite(number) or number < 0.0:
        raise ProfileError(f"length must be a finite number >= 0, got {length!r}")
    return number


def trapezoid(
    length: float,
    v_max: float,
    a_max: float | None,
    *,
    v_start: float = 0.0,
    v_end: float = 0.0,
) -> Profile:
    """The fastest profile with bounded speed and acceleration (a trapezoid or a triangle).

    From rest to rest the duration is ``length/v_max + v_max/a_max`` when ``length >=
    v_max²/a_max`` (the cruise speed is reached), else ``2·sqrt(length/a_max)``.

    Args:
        length: distance (m, or rad for a spin), >= 0.
        v_max: speed limit (unit/s), > 0.
        a_max: acceleration limit (unit/s²), > 0; None for none (speed steps).
        v_start: speed at the start (unit/s), in ``[0, v_max]``.
        v_end: speed at the end (unit/s), in ``[0, v_max]``.

    Returns:
        The profile.

    Raises:
        ProfileError: a bad number, or a length too short to change from ``v_start`` to ``v_end``
            within ``a_max``.
    """
    length = _check_length(length)
    v_max = _limit(v_max, "v_max")
    if math.isinf(v_max):
        raise ProfileError("v_max must be finite")
    a_max = _limit(a_max, "a_max")
    v_start = _boundary_speed(v_start, "v_start", v_max)
    v_end = _boundary_speed(v_end, "v_end", v_max)
    _check_duration(length, v_max, a_max)
    if math.isinf(a_max):
        return _build(length, v_max, [(length / v_max, 0.0, 0.0)])
    least = abs(v_end * v_end - v_start * v_start) / (2.0 * a_max)
    if length < least * (1.0 - 1e-12):
        raise ProfileError(
            f"length {length!r} is too short to go from v_start {v_start!r} to v_end {v_end!r} "
            f"at a_max {a_max!r}: it needs at least {least!r}"
        )
    peak_squared = a_max * length + (v_start**2 + v_end**2) / 2.0
    if peak_squared >= v_max * v_max:
        peak = v_max
        up, down = v_max - v_start, v_max - v_end
        ramps = (up * (v_max + v_start) + down * (v_max + v_end)) / (2.0 * a_max)
        cruise = _snap(length - ramps, length) / v_max
    elif peak_squared == 0.0:
        peak = up = down = cruise = 0.0
    else:
        peak = math.sqrt(peak_squared)
        # peak - v = (peak² - v²)/(peak + v): no cancellation when peak is close to v.
        half = a_max * length / 2.0
        up = max(half + (v_end - v_start) * (v_end + v_start) / 4.0, 0.0) / (peak + v_start)
        down = max(half + (v_start - v_end) * (v_start + v_end) / 4.0, 0.0) / (peak + v_end)
        up, down, cruise = 2.0 * up, 2.0 * down, 0.0
    return _build(
        length,
        v_start,
        [
            (up / a_max, 0.0, a_max),
            (cruise, 0.0, 0.0),
            (down / a_max, 0.0, -a_max),
        ],
    )


def _boundary_speed(value: float, what: str, v_max: float) -> float:
    number = _number(value, what)
    if not 0.0 <= number <= v_max:
        raise ProfileError(f"{what} must be within [0, v_max = {v_max!r}], got {value!r}")
    return number


def scurve(length: float, v_max: float, a_max: float | None, j_max: float) -> Profile:
    """The fastest rest-to-rest profile with bounded speed, acceleration and jerk.

    Up to seven phases of constant jerk ``+j, 0, -j, 0, -j, 0, +j``; the constant-acceleration
    phases vanish when ``a_max`` is not reached, the cruise when ``v_max`` is not.

    Args:
        length: distance (m, or rad for a spin), >= 0.
        v_max: speed limit (unit/s), > 0.
        a_max: acceleration limit (unit/s²), > 0; None for none.
        j_max: jerk limit (unit/s³), > 0.

    Returns:
        The profile.

    Raises:
        ProfileError: a bad number.
    """
    length = _check_length(length)
    v_max = _limit(v_max, "v_max")
    if math.isinf(v_max):
        raise ProfileError("v_max must be finite")
    a_max = _limit(a_max, "a_max")
    j_max = _limit(j_max, "j_max")
    if math.isinf(j_max):
        return trapezoid(length, v_max, a_max)
    if length == 0.0:
        return Profile(0.0, ())
    _check_duration(length, v_max, a_max, j_max)
    # An acceleration above sqrt(v_max·j_max) is never reached (the speed limit comes first):
    # the profile is the same with it lowered to that, and the powers below stay finite.
    a_max = min(a_max, math.sqrt(v_max) * math.sqrt(j_max))
    # Speed gained by a jerk-up, jerk-down pair that just touches a_max: above it, a plateau.
    knee = a_max * (a_max / j_max)
    if _ramp_length(v_max, a_max, j_max) * 2.0 <= length:
        peak = v_max
    elif length >= 2.0 * a_max * (a_max / j_max) ** 2:
        peak = (math.sqrt(knee * knee + 4.0 * a_max * length) - knee) / 2.0
    else:
        peak = (length * length * j_max / 4.0) ** (1.0 / 3.0)
    if peak >= knee:
        t_jerk = a_max / j_max
        t_acc = _snap(peak / a_max - t_jerk, t_jerk)
        a_peak = a_max
    else:
        t_jerk = math.sqrt(peak / j_max)
        t_acc = 0.0
        a_peak = j_max * t_jerk
    t_cruise = 0.0
    if peak == v_max:
        t_cruise = _snap(length - 2.0 * _ramp_length(peak, a_max, j_max), length) / peak
    j = j_max
    return _build(
        length,
        0.0,
        [
            (t_jerk, j, 0.0),
            (t_acc, 0.0, a_peak),
            (t_jerk, -j, a_peak),
            (t_cruise, 0.0, 0.0),
            (t_jerk, -j, 0.0),
            (t_acc, 0.0, -a_peak),
            (t_jerk, j, -a_peak),
        ],
    )


def _check_duration(length: float, v_max: float, a_max: float, j_max: float = math.inf) -> None:
    """Refuse limits under which ``length`` takes longer than :data:`MAX_PLAN_DURATION`.

    Each limit alone bounds the fastest rest-to-rest time from below: ``length/v_max``,
    ``2·sqrt(length/a_max)`` and ``(32·length/j_max)^(1/3)``; the profile takes at least the
    largest of them.
    """
    names = ("speed", "acceleration", "jerk")
    limits = (v_max, a_max, j_max)
    least = (
        length / v_max,
        2.0 * math.sqrt(length / a_max),
        (32.0 * (length / j_max)) ** (1.0 / 3.0),
    )
    longest = max(range(3), key=lambda k: least[k])
    if least[longest] > MAX_PLAN_DURATION:
        raise ProfileError(
            f"at a {names[longest]} limit of {limits[longest]:.6g}, a run of {length:.6g} "
            f"(m, or rad for a spin) takes more than {MAX_PLAN_DURATION:g} s: the limits are "
            "too small (a unit mistake?)"
        )


def _snap(value: float, scale: float) -> float:
    """``value``, or 0 when it is rounding noise next to ``scale`` (a phase that vanishes)."""
    return 0.0 if value <= 1e-13 * scale else value


def _ramp_length(speed: float, a_max: float, j_max: float) -> float:
    """Distance to go from rest to ``speed`` as fast as the limits allow (symmetric in time)."""
    if speed >= a_max * a_max / j_max:
        ramp_time = speed / a_max + a_max / j_max
    else:
        ramp_time = 2.0 * math.sqrt(speed / j_max)
    return speed * ramp_time / 2.0


class PathLimits(NamedTuple):
    """Bounds on a path coordinate's speed (unit/s), acceleration (unit/s²), jerk (unit/s³).

    The unit is m for straights and arcs, rad of heading for spins; None means unbounded.
    """

    velocity: float | None = None
    acceleration: float | None = None
    jerk: float | None = None


#: No bound on anything.
UNBOUNDED = PathLimits()


@dataclass(frozen=True)
class Limits:
    """Limits of the robot's motion, each as a :class:`PathLimits` triple (speed, acceleration,
    jerk); None means no limit, and every given limit is > 0.

    Attributes:
        linear: |v| (m/s), |dv/dt| (m/s²), |d²v/dt²| (m/s³).
        angular: |ω| (rad/s), |dω/dt| (rad/s²), |d²ω/dt²| (rad/s³).
        wheel: each wheel's |angular speed| (rad/s), acceleration (rad/s²) and jerk (rad/s³).
    """

    linear: PathLimits = UNBOUNDED
    angular: PathLimits = UNBOUNDED
    wheel: PathLimits = UNBOUNDED

    def __post_init__(self) -> None:
        for item in fields(self):
            triple = PathLimits(*getattr(self, item.name))
            checked = {
                key: None if value is None else _limit(value, f"{item.name}.{key}")
                for key, value in triple._asdict().items()
            }
            object.__setattr__(self, item.name, PathLimits(**checked))


def _tightest(*bounds: float | None) -> float | None:
    given = [b for b in bounds if b is not None and math.isfinite(b)]
    return min(given) if given else None


def _over(limit: float | None, gain: float) -> float | None:
    """The bound on the path quantity q such that gain·|q| <= limit."""
    if limit is None or gain == 0.0:
        return None
    return limit / gain


def path_limits(
    params: DiffDriveParams,
    limits: Limits,
    curvature: float = 0.0,
    *,
    spin: bool = False,
    left_wheel_radius: float | None = None,
    right_wheel_radius: float | None = None,
) -> PathLimits:
    """The tightest bounds on a path coordinate that keep every robot limit.

    Along a path of constant curvature κ (1/m) at path speed v, ω = κ·v and the wheels turn at
    ``v·(1 ∓ κ·b/2)/r`` (b the separation, r each wheel's radius), so every limit scales the same
    way on speed, acceleration and jerk. For a spin (``spin=True``) the coordinate is the heading
    and the wheels turn at ``∓ω·b/(2r)``; linear limits do not apply.

    Args:
        params: the robot (its separation and wheel radius; its ``max_wheel_speed`` is not used,
            give it as ``limits.wheel_speed``).
        limits: the robot's limits.
        curvature: signed curvature of the path (1/m), 0 for a straight; ignored for a spin.
        spin: turn in place; the coordinate is then the heading (rad).
        left_wheel_radius: the left wheel's radius (m) when it differs from ``params``'.
        right_wheel_radius: the right wheel's radius (m) when it differs from ``params``'.

    Returns:
        The bounds (m or rad, per s, s², s³); None where nothing bounds the coordinate.

    Raises:
        ProfileError: a non-finite curvature or a non-positive wheel radius.
    """
    # Each side's own radius (a controller's multipliers applied), not the mean of the two.
    left_default, right_default = params.radii
    left_r = _radius(left_wheel_radius, left_default, "left_wheel_radius")
    right_r = _radius(right_wheel_radius, right_default, "right_wheel_radius")
    half = params.wheel_separation / 2.0
    if spin:
        # Heading rate ω drives the wheels at ω·b/(2r); the slower-radius wheel turns faster.
        wheel_gain = max(half / left_r, half / right_r)
        return PathLimits(
            *(
                _tightest(w, _over(wheel, wheel_gain))
                for w, wheel in zip(limits.angular, limits.wheel, strict=True)
            )
        )
    kappa = _number(curvature, "curvature")
    if not math.isfinite(kappa):
        raise ProfileError(
            f"curvature must be finite (use spin=True to turn in place), got {kappa}"
        )
    turn = abs(kappa)
    wheel_gain = max(abs(1.0 - kappa * half) / left_r, abs(1.0 + kappa * half) / right_r)
    return PathLimits(
        *(
            _tightest(v, _over(w, turn), _over(wheel, wheel_gain))
            for v, w, wheel in zip(limits.linear, limits.angular, limits.wheel, strict=True)
        )
    )


def _radius(value: float | None, default: float, what: str) -> float:
    if value is None:
        return default
    number = _number(value, what)
    if not math.isfinite(number) or number <= 0.0:
        raise ProfileError(f"{what} must be a positive finite number, got {value!r}")
    return number


def segment_limits(
    segment: Segment,
    params: DiffDriveParams,
    limits: Limits,
    *,
    left_wheel_radius: float | None = None,
    right_wheel_radius: float | None = None,
) -> tuple[float, PathLimits]:
    """The path coordinate's length and bounds for a plan segment.

    Args:
        segment: a Straight, an Arc or a Spin.
        params: the robot.
        limits: the robot's limits.
        left_wheel_radius: the left wheel's radius (m) when it differs from ``params``'.
        right_wheel_radius: the right wheel's radius (m) when it differs from ``params``'.

    Returns:
        The length (m; rad of heading for a spin, >= 0) and the bounds from :func:`path_limits`.
    """
    from diffbot.trajectory import Spin, geometry

    spin = isinstance(segment, Spin)
    ds, turn = geometry(segment)
    # Along the path the wheels turn at s'·(1 ∓ (turn/ds)·b/2)/r: ds carries the direction.
    length, curvature = (abs(turn), 0.0) if spin else (abs(ds), turn / ds)
    bounds = path_limits(
        params,
        limits,
        curvature,
        spin=spin,
        left_wheel_radius=left_wheel_radius,
        right_wheel_radius=right_wheel_radius,
    )
    return length, bounds


def time_optimal(length: float, bounds: PathLimits) -> Profile:
    """The fastest rest-to-rest profile within path bounds.

    A trapezoid when there is no jerk bound, an S-curve otherwise. It never exceeds a bound and
    reaches at least one of them.

    Args:
        length: distance (m, or rad for a spin), >= 0.
        bounds: the path bounds, as from :func:`path_limits`; a speed bound is needed.

    Returns:
        The profile.

    Raises:
        ProfileError: no speed bound (the motion would take no time), or a bad number.
    """
    if bounds.velocity is None:
        raise ProfileError("the path speed is unbounded: give a speed limit to plan a profile")
    if bounds.jerk is None:
        return trapezoid(length, bounds.velocity, bounds.acceleration)
    return scurve(length, bounds.velocity, bounds.acceleration, bounds.jerk)
