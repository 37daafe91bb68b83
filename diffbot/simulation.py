"""Simulated wheel encoders: the joint states that executing a plan would produce.

The drive wheel joints follow the plan's commands exactly (their angles are the integral of the
joint velocity commands, direction signs applied, both 0 at the start), sampled at a fixed rate
and at every segment boundary. Optionally the angles get Gaussian noise and are then quantised to
an encoder's resolution. The caster joints (``caster_rotation_joint``, ``caster_wheel_joint`` on
the bundled robot) are reported at 0: the caster is not modelled.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING, Final, NamedTuple, Protocol

from diffbot.errors import ParameterError
from diffbot.kinematics import DiffDriveParams
from diffbot.numbers import (
    MAX_COUNT,
    as_number,
    encoder_noise,
    encoder_ticks,
    noise_seed,
    store_checked,
    store_number,
)

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import ArrayLike, NDArray

    from diffbot.trajectory import Plan

__all__ = [
    "CHUNK_SAMPLES",
    "MAX_RATE",
    "MAX_SAMPLES",
    "MAX_TICKS",
    "JointStateChunks",
    "JointStates",
    "Motion",
    "quantise",
    "sample_count",
    "sample_time_chunks",
    "sample_times",
    "simulate",
    "simulate_chunks",
]

#: Highest sampling rate (Hz): samples stay a microsecond apart, far more than the nanosecond
#: resolution of stamps needs, and no encoder is read faster.
MAX_RATE: Final = 1e6
#: Most samples one simulation makes (about 0.3 GB of joint angles for the bundled robot).
MAX_SAMPLES: Final = 10_000_000
#: Highest encoder resolution (counts per revolution).
MAX_TICKS: Final = MAX_COUNT

#: Grid times closer than this to a segment boundary (s) give way to the boundary: stamps are in
#: nanoseconds, and two samples within one would share a stamp.
_SAME_TIME = 1e-9


class Motion(Protocol):
    """A motion the wheels follow other than a step plan's: a ramped plan, or what a controller
    executed. Its wheel angles are exact at any time; odometry of samples is exact when every
    time where the path's curvature changes is among them (its ``boundaries``)."""

    @property
    def duration(self) -> float:
        """Its duration (s)."""

    @property
    def boundaries(self) -> tuple[float, ...]:
        """The times (s) where its curvature may change."""

    def wheel_positions(self, times: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Left and right joint angles (rad, signs applied, 0 at the start) at ``times`` (s)."""


@dataclass(frozen=True)
class JointStates:
    """A series of joint states.

    Attributes:
        times: sample times (s) since the start of the plan, increasing, shape (n,).
        names: the joint names.
        positions: joint angles (rad), one row per joint, shape (len(names), n).
    """

    times: NDArray[np.float64]
    names: tuple[str, ...]
    positions: NDArray[np.float64]


def sample_count(duration: float, rate: float, boundaries: int = 0) -> float:
    """At most how many samples :func:`sample_times` makes (a float, as it may be huge).

    Args:
        duration: the end time (s), >= 0.
        rate: samples per second (Hz), > 0.
        boundaries: how many extra times are asked for.
    """
    return duration * rate + 2.0 + boundaries


def sample_times(
    duration: float,
    rate: float,
    boundaries: tuple[float, ...] = (),
    *,
    max_samples: int = MAX_SAMPLES,
) -> NDArray[np.float64]:
    """Times (s) from 0 to ``duration``: every 1/rate s, at each boundary, and at the end.

    Args:
        duration: the end time (s), >= 0.
        rate: samples per second (Hz), > 0 and at most :data:`MAX_RATE`.
        boundaries: extra times (s) to sample at, such as segment ends.
        max_samples: refuse to make more samples than this.

    Returns:
        Increasing times, shape (n,), starting at 0 and ending at ``duration`` (just 0 for a
        duration under 1 ns). A grid time within 1 ns of a boundary or of the end is replaced by
        it, and grid times are at least 1 µs apart, so that no two samples share a nanosecond
        stamp.

    Raises:
        ParameterError: a non-finite or negative duration, a rate that is not positive or over
            :data:`MAX_RATE`, or more than ``max_samples`` samples.
    """
    import numpy as np

    return np.concatenate(
        list(sample_time_chunks(duration, rate, boundaries, max_samples=max_samples))
    )


def boundaries(plan: Plan | Motion) -> tuple[float, ...]:
    """The times (s) a simulation samples besides its grid: where the curvature may change."""
    from diffbot import trajectory

    if not isinstance(plan, trajectory.Plan):
        return tuple(plan.boundaries)
    ends: list[float] = []
    elapsed = 0.0
    for planned in plan.segments:
        elapsed += planned.duration
        ends.append(elapsed)
    return tuple(ends)


def quantise(angles: NDArray[np.float64], ticks: int) -> NDArray[np.float64]:
    """Angles (rad) as an encoder with ``ticks`` counts per revolution reports them.

    Args:
        angles: joint angles (rad).
        ticks: counts per revolution, from 1 to :data:`MAX_TICKS`.

    Returns:
        Each angle rounded to the nearest multiple of 2 pi / ticks.

    Raises:
        ParameterError: ``ticks`` out of range.
    """
    import numpy as np

    encoder_ticks(ticks)
    step = 2.0 * math.pi / ticks
    return np.round(angles / step) * step


#: Samples per chunk of :func:`simulate_chunks`: a few MB of joint angles, whatever the length.
CHUNK_SAMPLES: Final = 65536


def _fixed_times(duration: float, boundaries: tuple[float, ...]) -> list[float]:
    """0, the boundaries and the end, a nanosecond apart at least (see :func:`sample_times`)."""
    exact = [0.0]
    for boundary in sorted(b for b in boundaries if 0.0 < b < duration - _SAME_TIME):
        if boundary - exact[-1] > _SAME_TIME:
            exact.append(boundary)
    if duration > _SAME_TIME:
        if duration - exact[-1] <= _SAME_TIME:
            exact.pop()  # the end replaces a boundary within a nanosecond of it
        exact.append(duration)
    return exact


def sample_time_chunks(
    duration: float,
    rate: float,
    boundaries: tuple[float, ...] = (),
    *,
    max_samples: int = MAX_SAMPLES,
    chunk: int = CHUNK_SAMPLES,
) -> Iterator[NDArray[np.float64]]:
    """The times of :func:`sample_times`, equal value for value, in chunks of about ``chunk``
    grid times: memory does not grow with the duration.

    Raises:
        ParameterError: as :func:`sample_times`.
    """
    import numpy as np

    duration = as_number(duration, "duration", expected="finite and >= 0")
    if not math.isfinite(duration) or duration < 0.0:
        raise ParameterError(f"duration must be finite and >= 0, got {duration!r}")
    expected = f"a positive number up to {MAX_RATE:g} (Hz)"
    rate = as_number(rate, "rate", expected=expected)
    if not math.isfinite(rate) or not 0.0 < rate <= MAX_RATE:
        raise ParameterError(f"rate must be {expected}, got {rate!r}")
    count = sample_count(duration, rate, len(boundaries))
    if count > max_samples:
        raise ParameterError(
            f"{duration:g} s at {rate:g} Hz would take {count:.4g} samples, more than "
            f"{max_samples}: lower the rate or shorten the duration"
        )
    fixed = np.array(_fixed_times(duration, boundaries))
    grid_count = math.ceil(duration * rate) + 1
    for start in range(0, grid_count, chunk):
        stop = min(start + chunk, grid_count)
        grid = np.arange(start, stop, dtype=np.float64) / rate
        grid = grid[grid < duration]
        after = np.searchsorted(fixed, grid).clip(max=fixed.size - 1)
        before = (after - 1).clip(min=0)
        distance = np.minimum(np.abs(fixed[after] - grid), np.abs(grid - fixed[before]))
        low = -math.inf if start == 0 else start / rate
        high = math.inf if stop == grid_count else stop / rate
        mine = fixed[(fixed >= low) & (fixed < high)]
        yield np.sort(np.concatenate((grid[distance > _SAME_TIME], mine)))


class JointStateChunks(NamedTuple):
    """The joint states of :func:`simulate_chunks`.

    Attributes:
        names: the joint names.
        samples: how many samples there are in all.
        chunks: (times (s), positions (rad), one row per joint) chunk by chunk.
    """

    names: tuple[str, ...]
    samples: int
    chunks: Iterator[tuple[NDArray[np.float64], NDArray[np.float64]]]


@dataclass(frozen=True)
class Sampling:
    """How joint states are sampled: see :func:`simulate` for each field."""

    rate: float = 50.0
    ticks: int | None = None
    noise: float = 0.0
    seed: int | None = None


def simulate_chunks(
    plan: Plan | Motion,
    params: DiffDriveParams,
    sampling: Sampling,
    *,
    extra_joints: tuple[str, ...] | None = None,
    max_samples: int = MAX_SAMPLES,
    chunk: int = CHUNK_SAMPLES,
) -> JointStateChunks:
    """The joint states of :func:`simulate`, equal value for value (noise included), made a
    chunk at a time so that memory does not grow with the number of samples.

    Raises:
        ParameterError: as :func:`simulate`.
    """
    import numpy as np

    from diffbot import trajectory

    rate, ticks, noise, seed = sampling.rate, sampling.ticks, sampling.noise, sampling.seed
    noise = encoder_noise(noise)
    if seed is not None:
        noise_seed(seed)
    if ticks is not None:
        encoder_ticks(ticks)
    ends = boundaries(plan)

    def times() -> Iterator[NDArray[np.float64]]:
        return sample_time_chunks(plan.duration, rate, ends, max_samples=max_samples, chunk=chunk)

    samples = sum(t.size for t in times())
    extra = params.passive_joints if extra_joints is None else extra_joints
    repeats = (len(params.left_joints), len(params.right_joints))
    names = (*params.left_joints, *params.right_joints, *extra)

    def chunks() -> Iterator[tuple[NDArray[np.float64], NDArray[np.float64]]]:
        # simulate() drew the noise as one (2, count) array: every left value, then every
        # right one. A second generator, moved past the left values, gives the right ones.
        left_noise = right_noise = None
        if noise > 0.0:
            left_noise = np.random.default_rng(seed)
            right_noise = np.random.default_rng(seed)
            for start in range(0, samples, chunk):
                right_noise.normal(0.0, noise, min(chunk, samples - start))
        for t in times():
            left, right = (
                trajectory.wheel_positions(plan, t)
                if isinstance(plan, trajectory.Plan)
                else plan.wheel_positions(t)
            )
            wheels = np.vstack((left, right))
            if left_noise is not None and right_noise is not None:
                wheels[0] += left_noise.normal(0.0, noise, t.size)
                wheels[1] += right_noise.normal(0.0, noise, t.size)
            if ticks is not None:
                wheels = quantise(wheels, ticks)
            sides = np.repeat(wheels, repeats, axis=0)
            yield t, np.vstack((sides, np.zeros((len(extra), t.size))))

    return JointStateChunks(names, samples, chunks())


def simulate(
    plan: Plan | Motion,
    params: DiffDriveParams,
    rate: float = 50.0,
    *,
    ticks: int | None = None,
    noise: float = 0.0,
    seed: int | None = None,
    extra_joints: tuple[str, ...] | None = None,
    max_samples: int = MAX_SAMPLES,
) -> JointStates:
    """The joint states a robot executing ``plan`` would report.

    Args:
        plan: the plan (from :func:`diffbot.trajectory.plan`), or another motion (a ramped plan,
            the commands a controller executed).
        params: the robot, for the wheel joint names (every drive wheel of each side turns as
            that side's wheels do).
        rate: sampling rate (Hz); a sample is added at every segment boundary and at the end, so
            that odometry of the result reproduces the plan exactly.
        ticks: encoder resolution (counts per revolution), or None for exact angles.
        noise: standard deviation (rad) of Gaussian noise added to each wheel angle (before
            quantisation), 0 for none.
        seed: seed of the noise generator (an integer >= 0), for reproducible runs.
        extra_joints: joints reported at 0 after the wheels; by default the robot's
            ``passive_joints`` (a caster's).
        max_samples: refuse to make more samples than this.

    Returns:
        Times (s) from 0 to the plan's duration, and the joint angles (rad): the left wheels, the
        right wheels, then ``extra_joints``.

    Raises:
        ParameterError: a bad rate, resolution, noise level or seed, or too many samples.
    """
    import numpy as np

    sampling = Sampling(rate, ticks, noise, seed)
    states = simulate_chunks(
        plan, params, sampling, extra_joints=extra_joints, max_samples=max_samples
    )
    parts = list(states.chunks)
    times = np.concatenate([t for t, _ in parts]) if parts else np.empty(0)
    positions = np.hstack([p for _, p in parts]) if parts else np.empty((len(states.names), 0))
    return JointStates(times, states.names, positions)


# --------------------------------------------------------------------------------------------
# A robot that does not do what it is told


#: Longest motor lag or command latency a simulated robot may have (s).
MAX_DELAY: Final = 60.0
#: How often a slipping wheel's loss of traction changes (s).
SLIP_PERIOD: Final = 0.1
#: Longest step of the wheels' integration (s): short beside any turn of the path.
MAX_STEP: Final = 0.001
#: Longest advance (s) over which the slip redraws are placed on the millisecond steps' grid
#: as they fell when every step was one; over a longer one they fall on SLIP_PERIOD's.
_GRID_WALK: Final = 1.0


@dataclass(frozen=True)
class Disturbances:
    """What a real base does besides what it is told.

    Attributes:
        motor_lag: time constant (s) of each wheel's first-order velocity response, >= 0.
        latency: delay (s) from a command to the motors, >= 0.
        drop: share of commands lost, in [0, 1).
        slip: mean share of each wheel's travel lost to slip, in [0, 1): every
            :data:`SLIP_PERIOD` each wheel draws a loss of traction uniformly in
            ``[0, 2 slip]`` (capped below 1); the encoder counts the wheel's turn, the ground
            sees less.
        seed: seed (an integer >= 0) of the drops and the slip, for reproducible runs.
    """

    motor_lag: float = 0.0
    latency: float = 0.0
    drop: float = 0.0
    slip: float = 0.0
    seed: int | None = None

    def __post_init__(self) -> None:
        for name in ("motor_lag", "latency"):
            store_number(self, name, 0.0, MAX_DELAY, unit="s")
        for name in ("drop", "slip"):
            store_number(self, name, 0.0, 1.0)
            if getattr(self, name) >= 1.0:
                raise ParameterError(
                    f"{name} must be a fraction below 1, got {getattr(self, name)!r}"
                )
        store_checked(self, "seed", noise_seed, optional=True)

    @property
    def any(self) -> bool:
        """Whether the robot is disturbed at all."""
        return bool(self.motor_lag or self.latency or self.drop or self.slip)


class DisturbedRobot:
    """A differential-drive base stepped in time: commands in, wheel angles and true pose out.

    Commanded wheel-ground speeds (rad/s) arrive ``latency`` s after :meth:`command` (or never,
    a ``drop`` share of them); each wheel's speed approaches the last arrived command with the
    first-order ``motor_lag``, clamped to the motor limit whatever it is told. The wheels turn
    the encoders; the ground moves by the real radii and separation, less the slip.

    Args:
        params: the robot as described (its motor limit, direction signs).
        disturbances: the disturbances.
        true_params: the real robot (:func:`diffbot.calibration.truth.true_robot`); ``params``
            when None.
    """

    def __init__(
        self,
        params: DiffDriveParams,
        disturbances: Disturbances,
        true_params: DiffDriveParams | None = None,
    ) -> None:
        import random
        from collections import deque

        self.params = params
        self.disturbances = disturbances
        real = params if true_params is None else true_params
        self._radii = real.radii
        self._separation = real.wheel_separation
        self._limit = params.max_wheel_speed
        self._random = random.Random(disturbances.seed)
        self._slip_random = random.Random(
            None if disturbances.seed is None else disturbances.seed + 1
        )
        self._pending: deque[tuple[float, float, float]] = deque()
        self.time = 0.0
        #: Each wheel's speed (rad/s, wheel-ground) and its target.
        self.speeds = [0.0, 0.0]
        self._target = (0.0, 0.0)
        #: Each wheel's angle (rad, wheel-ground: positive rolls forward).
        self.angles = [0.0, 0.0]
        #: The true pose: x, y (m), heading (rad, not wrapped).
        self.pose = [0.0, 0.0, 0.0]
        self._traction = (1.0, 1.0)
        self._next_slip = 0.0

    def command(self, left: float, right: float) -> None:
        """Command wheel-ground speeds (rad/s) now (it arrives after the latency, if at all)."""
        if self.disturbances.drop and self._random.random() < self.disturbances.drop:
            return
        self._pending.append((self.time + self.disturbances.latency, left, right))

    def halt(self) -> None:
        """Stop the motors' own way, as a base's command watchdog does: what is still to
        arrive is forgotten and the wheels slow to rest with the motor lag (no latency, never
        dropped)."""
        self._pending.clear()
        self._target = (0.0, 0.0)

    @property
    def stopped(self) -> bool:
        """Whether nothing moves or is still to arrive (speeds under 1e-6 rad/s)."""
        return (
            not self._pending
            and self._target == (0.0, 0.0)
            and max(abs(self.speeds[0]), abs(self.speeds[1])) < 1e-6
        )

    def advance(self, until: float) -> None:
        """Step the robot to time ``until`` (s).

        The wheels' speeds and travel are exact over a step of any length; the pose's chord is
        exact while the path's curvature holds, that is while both wheels' speeds stay in
        proportion (both at their targets, or both approaching targets in proportion, as from
        rest or to a stop). Such steps run to the next event: a command's arrival, ``until``
        or, while a wheel turns on slipping ground, the next slip redraw, so that a run costs
        its events, not its seconds. Other steps are at most :data:`MAX_STEP`.
        """
        pending = self._pending
        slip = self.disturbances.slip
        while self.time < until:
            while pending and pending[0][0] <= self.time + 1e-12:
                _, left, right = pending.popleft()
                lim = self._limit
                if lim is not None:
                    left, right = min(max(left, -lim), lim), min(max(right, -lim), lim)
                self._target = (left, right)
            if slip and self.time >= self._next_slip:
                self._traction = self._draw_traction()
                self._next_slip += SLIP_PERIOD
            still = self._target == (0.0, 0.0) and self.speeds == [0.0, 0.0]
            event = min(until, pending[0][0]) if pending else until
            if still and slip and event - self.time > SLIP_PERIOD:
                self._skip_slip(event)
                self.time = max(event, self.time)
                continue
            steady = still or self._steady()
            if slip and steady:
                end = (
                    self._slip_step_end(until)
                    if until - self.time <= _GRID_WALK
                    else max(self.time, min(until, self._next_slip))
                )
            elif steady:
                end = event
            else:
                end = min(until, self.time + MAX_STEP)
            if pending and pending[0][0] < end:
                end = max(pending[0][0], self.time)
            if not still:
                self._step(end - self.time)
            self.time = end

    def _steady(self) -> bool:
        """Whether the wheels' speeds stay in proportion until the next command: both approach
        their targets by one factor, so they do when their gaps are in the proportion of the
        targets (to rounding), or when they reach the targets at once, without a lag."""
        if self.disturbances.motor_lag == 0.0:
            return True
        (left, right), (speed_left, speed_right) = self._target, self.speeds
        one, other = left * (speed_right - right), right * (speed_left - left)
        return abs(one - other) <= 1e-15 * (abs(one) + abs(other))

    def _slip_step_end(self, until: float) -> float:
        """Where millisecond steps from now would first meet a command's arrival, ``until`` or
        the next slip redraw: the long step ends there, so that the redraws fall at the same
        times, to the bit, as when the robot is stepped a millisecond at a time (a redraw is at
        most SLIP_PERIOD / MAX_STEP steps away)."""
        pending = self._pending
        at = self.time
        while True:
            end = min(until, at + MAX_STEP)
            if pending and pending[0][0] < end:
                end = max(pending[0][0], at)
            if end == at:  # a millisecond lost in the rounding of so late a time
                return until
            at = end
            if at >= until or at >= self._next_slip or (pending and pending[0][0] <= at + 1e-12):
                return at

    def _skip_slip(self, end: float) -> None:
        """A robot at rest until ``end`` loses no travel to slip: the redraws that fall before
        ``end`` are skipped but the last, which is drawn, due, before the robot moves again;
        the next ones stay on the grid of :data:`SLIP_PERIOD`."""
        if end - self._next_slip >= SLIP_PERIOD:
            self._next_slip += math.floor((end - self._next_slip) / SLIP_PERIOD) * SLIP_PERIOD

    def _draw_traction(self) -> tuple[float, float]:
        high = min(2.0 * self.disturbances.slip, 0.999)
        uniform = self._slip_random.uniform
        return 1.0 - uniform(0.0, high), 1.0 - uniform(0.0, high)

    def _step(self, dt: float) -> None:
        if dt <= 0.0:
            return
        lag = self.disturbances.motor_lag
        travel = [0.0, 0.0]
        decay = math.exp(-dt / lag) if lag > 0.0 else 0.0
        for side in (0, 1):
            target, speed = self._target[side], self.speeds[side]
            gap = speed - target
            travel[side] = target * dt + gap * lag * (1.0 - decay)
            speed = target + gap * decay
            # A gap under 1e-15 of the target moves the wheel less, over the rest of its
            # approach, than rounding moves its angle; a subnormal one has lost its precision
            # and would take hundreds of time constants to reach 0: either ends the approach.
            left_over = abs(speed - target)
            if left_over <= 1e-15 * abs(target) or left_over < sys.float_info.min:
                speed = target
            self.speeds[side] = speed
            self.angles[side] += travel[side]
        left = travel[0] * self._radii[0] * self._traction[0]
        right = travel[1] * self._radii[1] * self._traction[1]
        ds, turn = 0.5 * (left + right), (right - left) / self._separation
        half = 0.5 * turn
        chord = ds * (math.sin(half) / half) if half != 0.0 else ds
        x, y, heading = self.pose
        mean = heading + half
        self.pose = [x + chord * math.cos(mean), y + chord * math.sin(mean), heading + turn]
