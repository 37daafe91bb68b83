"""Least-squares calibration over recordings: wheel joint samples as read from a file and a
ground-truth pose track, reduced one recording at a time to what :mod:`diffbot.calibration.fit`
solves for (the wheel angles, the windows' bounds and the truth there).
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from diffbot.calibration.fit import (
    FitResult,
    bound_samples,
    enough_samples,
    require_scipy,
    seconds_since,
    solve,
    unwrapped,
    weights,
    window_bounds,
)
from diffbot.errors import CalibrationError, ParameterError
from diffbot.kinematics import DiffDriveParams
from diffbot.samples import INT64, NS_PER_S, ColumnSamples, Recording, side_means

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray

    from diffbot.io.poses import PoseTrack

__all__ = ["fit_recording", "fit_recordings"]


def _wheel_series(
    recording: Recording, params: DiffDriveParams
) -> tuple[NDArray[np.int64], NDArray[np.float64], NDArray[np.float64]]:
    """Stamps (ns) and the two sides' wheel angles (rad) of the samples that the odometry uses
    (a joint of each side, every value finite): views of a CSV's columns when every sample is,
    copies otherwise.

    A side with several joints moves by the mean of its joints that a sample holds, as the
    odometry takes it (:func:`~diffbot.samples.side_means`; a joint's first occurrence in a
    sample's names); a sample holding a NaN or infinite value is left out, as the odometry
    skips it.
    """
    import numpy as np

    samples = recording.samples
    if isinstance(samples, ColumnSamples):
        stamps = np.frombuffer(samples.stamps_ns, dtype=np.int64)
        left = np.frombuffer(samples.left, dtype=np.float64)
        right = np.frombuffer(samples.right, dtype=np.float64)
        keep = np.frombuffer(samples.present, dtype=np.uint8) == 3
        keep &= np.isfinite(left)
        keep &= np.isfinite(right)
        if keep.all():
            return stamps, left, right
        return stamps[keep], left[keep], right[keep]
    joints = (*params.left_joints, *params.right_joints)
    column = {joint: j for j, joint in reversed(list(enumerate(joints)))}
    n = len(samples)
    stamps = np.empty(n, dtype=np.int64)
    positions = np.zeros((n, len(joints)))
    present = np.zeros((n, len(joints)), dtype=np.bool_)
    for k, (stamp_ns, names, values) in enumerate(samples):
        stamps[k] = stamp_ns
        # A joint named without a value (an empty velocity field) is absent, as the odometry
        # counts it; a joint named twice holds its first value.
        for name, value in reversed(list(zip(names, values, strict=False))):
            j = column.get(name)
            if j is not None:
                positions[k, j] = value
                present[k, j] = True
    left, right, keep = side_means(positions, present, len(params.left_joints))
    keep &= np.isfinite(positions).all(axis=1)
    return stamps[keep], left[keep], right[keep]


def fit_recording(
    recording: Recording,
    truth: PoseTrack,
    params: DiffDriveParams,
    *,
    time_offset: float | str = 0.0,
    **options: Any,
) -> FitResult:
    """:func:`fit` of a recording of wheel joint states against a ground-truth pose track.

    Samples without both wheel joints are left out; stamps become seconds from the earlier of
    the two first stamps, so that stamps since 1970 keep their precision.

    Args:
        recording: the wheel joint samples (:func:`diffbot.recordings.read_recording`).
        truth: the ground truth (:func:`diffbot.io.poses.read_pose_track`).
        params: the nominal robot.
        time_offset: how late the wheel stamps are against the truth (s), or ``"auto"`` to
            find it by aligning heading rates (:func:`diffbot.conditioning.
            estimate_time_offset`).
        **options: ``window``, ``window_duration``, ``heading_weight``,
            ``max_relative_stderr``, as for :func:`fit`.

    Raises:
        CalibrationError: fewer than two samples with both wheels, or what :func:`fit` raises.
    """
    result, _ = fit_recordings([(recording, truth)], params, time_offset=time_offset, **options)
    return result


@dataclass(frozen=True)
class _Part:
    """What the fit keeps of one recording: its wheel angles, its windows' bounds (sample
    indices within it) and the truth's x, y (m) and unwrapped heading (rad) at those."""

    left: NDArray[np.float64]
    right: NDArray[np.float64]
    starts: NDArray[np.intp]
    ends: NDArray[np.intp]
    truth_at: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]


def fit_recordings(
    pairs: Iterable[tuple[Recording, PoseTrack]],
    params: DiffDriveParams,
    *,
    time_offset: float | str = 0.0,
    window: int | None = None,
    window_duration: float | None = None,
    heading_weight: float | None = None,
    max_relative_stderr: float = 0.01,
) -> tuple[FitResult, list[float]]:
    """:func:`fit` over several recordings at once, each against its own ground truth.

    Each recording's windows stay within it; the truth is interpolated at its wheel stamps once
    they are moved back by the time offset. The recordings are taken one at a time and only
    what the fit needs is kept of each (the wheel angles, the truth at the windows' bounds):
    given as a generator that reads them, a recording and its truth are let go before the next
    one is read, and SciPy is loaded only then.

    Args:
        pairs: the recordings and their ground truths.
        params: the nominal robot.
        time_offset: how late the wheel stamps are (s), the same for all, or ``"auto"`` to find
            it for each recording by aligning heading rates.
        window: as for :func:`fit`.
        window_duration: as for :func:`fit`.
        heading_weight: as for :func:`fit`.
        max_relative_stderr: as for :func:`fit`.

    Returns:
        The fit, and the time offset (s) used for each recording.

    Raises:
        CalibrationError: no recording, fewer than two samples with both wheels in one, stamps
            that cannot be aligned, or what :func:`fit` raises.
    """
    import numpy as np

    require_scipy()
    if isinstance(time_offset, str) and time_offset != "auto":
        raise ParameterError(f"time_offset must be seconds or 'auto', got {time_offset!r}")
    weight, limit = weights(params, heading_weight, max_relative_stderr)
    if window is not None and window_duration is not None:
        raise ParameterError("give window or window_duration, not both")
    parts: list[_Part] = []
    offsets: list[float] = []
    clock = 0.0
    remaining = iter(pairs)
    while (
        taken := _part(remaining, params, time_offset, clock, window, window_duration)
    ) is not None:
        part, offset, clock = taken
        parts.append(part)
        offsets.append(offset)
    if not parts:
        raise CalibrationError("no recording to fit")
    enough_samples(sum(part.left.size for part in parts))
    # One recording's columns are used as they are; several are joined one at a time.
    sizes = np.cumsum([0] + [part.left.size for part in parts])
    starts = np.concatenate([p.starts + n for p, n in zip(parts, sizes, strict=False)])
    ends = np.concatenate([p.ends + n for p, n in zip(parts, sizes, strict=False)])
    bounds = bound_samples(starts, ends)
    del starts, ends
    truth_at = (
        np.concatenate([p.truth_at[0] for p in parts]),
        np.concatenate([p.truth_at[1] for p in parts]),
        np.concatenate([p.truth_at[2] for p in parts]),
    )
    left = parts[0].left if len(parts) == 1 else np.concatenate([p.left for p in parts])
    right = parts[0].right if len(parts) == 1 else np.concatenate([p.right for p in parts])
    del parts
    result = solve(params, left, right, bounds, truth_at, weight, limit)
    return result, offsets


def _part(
    pairs: Iterator[tuple[Recording, PoseTrack]],
    params: DiffDriveParams,
    time_offset: float | str,
    clock: float,
    window: int | None,
    window_duration: float | None,
) -> tuple[_Part, float, float] | None:
    """The next recording reduced to what the fit keeps, the time offset used, and where the
    next recording's clock starts (1 s after this one ends: no window spans two recordings);
    None when there is none left.

    The pair is taken from the iterator here, so that nothing else holds a generator's
    recording and truth: each array is let go as soon as it has served. No array as long as
    the recording is kept but the wheel angles, and few are made.
    """
    import numpy as np

    from diffbot.conditioning import estimate_time_offset

    pair = next(pairs, None)
    if pair is None:
        return None
    recording, truth = pair
    del pair
    source, truth_source = recording.source, truth.source
    stamps_ns, left, right = _wheel_series(recording, params)
    del recording
    if stamps_ns.size < 2:
        raise CalibrationError(
            f"{source}: {stamps_ns.size} samples hold both wheel joints "
            f"({params.left_joint!r}, {params.right_joint!r}): at least two are needed"
        )
    origin = min(int(stamps_ns[0]), int(truth.stamps_ns[0]))
    end = max(int(stamps_ns[-1]), int(truth.stamps_ns[-1]))
    if end - origin >= INT64:  # the int64 differences below would wrap around
        raise CalibrationError(
            f"{source} and {truth_source} lie {(end - origin) / NS_PER_S:.3g} s "
            "apart: their times cannot be the same clock's"
        )
    t = seconds_since(stamps_ns, origin)
    del stamps_ns
    tt = seconds_since(truth.stamps_ns, origin)
    if not (truth.stamps_ns[1:] > truth.stamps_ns[:-1]).all():
        # The interpolation below would read an unordered track as garbage, and nothing would
        # say so.
        raise CalibrationError(
            f"{truth_source}: the ground truth's stamps repeat or go back (two publishers, or "
            "rows out of order): a fit needs them increasing"
        )
    tx, ty, tth = truth.x, truth.y, truth.theta
    del truth
    if time_offset == "auto":
        try:
            offset = estimate_time_offset(t, left, right, tt, tth, params)
        except ParameterError as err:
            # The template, not str(err): its parameter markers stay for the caller to spell.
            raise CalibrationError(f"{source}: {err.template}") from None
    else:
        offset = float(time_offset)
    t -= offset
    inside = (t >= tt[0]) & (t <= tt[-1])
    if not inside.all():
        t, left, right = t[inside], left[inside], right[inside]
    del inside
    if t.size < 2:
        raise CalibrationError(
            f"{source}: only {t.size} wheel samples fall within the ground truth's time span"
        )
    shift = clock - t[0]
    shifted = t + shift
    if not (shifted[1:] > shifted[:-1]).all():
        raise CalibrationError(
            f"{source}: the wheel samples' stamps repeat or go back (two publishers on the "
            "topic, or rows out of order): a fit needs them increasing"
        )
    starts, ends = window_bounds(shifted, window, window_duration)
    clock = float(shifted[-1]) + 1.0
    del shifted
    # The truth is needed at the windows' bounds only.
    at = t[np.unique(np.concatenate((starts, ends)))]
    del t
    x_at = np.interp(at, tt, tx)
    del tx
    y_at = np.interp(at, tt, ty)
    del ty
    truth_at = (x_at, y_at, np.interp(at, tt, unwrapped(tth)))
    return _Part(left, right, starts, ends, truth_at), float(offset), clock
