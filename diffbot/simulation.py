"""Simulated wheel encoders: the joint states that executing a plan would produce.

The drive wheel joints follow the plan's commands exactly (their angles are the integral of the
joint velocity commands, direction signs applied, both 0 at the start), sampled at a fixed rate
and at every segment boundary. Optionally the angles get Gaussian noise and are then quantised to
an encoder's resolution. The caster joints (``caster_rotation_joint``, ``caster_wheel_joint`` on
the bundled robot) are reported at 0: the caster is not modelled.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Final, Protocol

from diffbot.errors import ParameterError
from diffbot.kinematics import DiffDriveParams

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import ArrayLike, NDArray

    from diffbot.trajectory import Plan

__all__ = [
    "MAX_RATE",
    "MAX_SAMPLES",
    "MAX_TICKS",
    "JointStates",
    "Motion",
    "quantise",
    "sample_count",
    "sample_times",
    "simulate",
]

#: Highest sampling rate (Hz): samples stay a microsecond apart, far more than the nanosecond
#: resolution of stamps needs, and no encoder is read faster.
MAX_RATE: Final = 1e6
#: Most samples one simulation makes (about 0.3 GB of joint angles for the bundled robot).
MAX_SAMPLES: Final = 10_000_000
#: Highest encoder resolution (counts per revolution).
MAX_TICKS: Final = 2**32

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

    if not math.isfinite(duration) or duration < 0.0:
        raise ParameterError(f"duration must be finite and >= 0, got {duration!r}")
    if not math.isfinite(rate) or not 0.0 < rate <= MAX_RATE:
        raise ParameterError(
            f"rate must be a positive number up to {MAX_RATE:g} (Hz), got {rate!r}"
        )
    count = sample_count(duration, rate, len(boundaries))
    if count > max_samples:
        raise ParameterError(
            f"{duration:g} s at {rate:g} Hz would take {count:.4g} samples, more than "
            f"{max_samples}: lower the rate or shorten the duration"
        )
    exact = [0.0]
    for boundary in sorted(b for b in boundaries if 0.0 < b < duration - _SAME_TIME):
        if boundary - exact[-1] > _SAME_TIME:
            exact.append(boundary)
    if duration > _SAME_TIME:
        if duration - exact[-1] <= _SAME_TIME:
            exact.pop()  # the end replaces a boundary within a nanosecond of it
        exact.append(duration)
    fixed = np.array(exact)
    grid = np.arange(math.ceil(duration * rate) + 1, dtype=np.float64) / rate
    grid = grid[grid < duration]
    after = np.searchsorted(fixed, grid).clip(max=fixed.size - 1)
    before = (after - 1).clip(min=0)
    distance = np.minimum(np.abs(fixed[after] - grid), np.abs(grid - fixed[before]))
    return np.sort(np.concatenate((grid[distance > _SAME_TIME], fixed)))


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


def _check_ticks(ticks: int) -> None:
    if not isinstance(ticks, int) or not 0 < ticks <= MAX_TICKS:
        raise ParameterError(
            f"ticks per revolution must be an integer from 1 to 2**32, got {ticks!r}"
        )


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

    _check_ticks(ticks)
    step = 2.0 * math.pi / ticks
    return np.round(angles / step) * step


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

    from diffbot import trajectory

    if not math.isfinite(noise) or noise < 0.0:
        raise ParameterError(f"noise must be a finite number >= 0 (rad), got {noise!r}")
    if seed is not None and (not isinstance(seed, int) or seed < 0):
        raise ParameterError(f"seed must be an integer >= 0, got {seed!r}")
    if ticks is not None:
        _check_ticks(ticks)
    times = sample_times(plan.duration, rate, boundaries(plan), max_samples=max_samples)
    left, right = (
        trajectory.wheel_positions(plan, times)
        if isinstance(plan, trajectory.Plan)
        else plan.wheel_positions(times)
    )
    wheels = np.vstack((left, right))
    if noise > 0.0:
        wheels += np.random.default_rng(seed).normal(0.0, noise, wheels.shape)
    if ticks is not None:
        wheels = quantise(wheels, ticks)
    extra = params.passive_joints if extra_joints is None else extra_joints
    sides = np.repeat(wheels, (len(params.left_joints), len(params.right_joints)), axis=0)
    positions = np.vstack((sides, np.zeros((len(extra), times.size))))
    names = (*params.left_joints, *params.right_joints, *extra)
    return JointStates(times, names, positions)
