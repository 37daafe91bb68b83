"""Least-squares calibration: the wheel radii and separation that make odometry match a
ground-truth pose track (motion capture, a simulator).

The motion over short windows, each in its own start frame, is compared between the odometry
(:func:`diffbot.batch_odometry.integrate`, exact arcs, a radius per wheel) and the truth, so
that the drift of the odometry does not pile up into the residuals; ``scipy.optimize.
least_squares`` minimises the errors. The derivation is in ``docs/calibration.md``.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, NamedTuple

from diffbot.calibration.checks import positive, vector
from diffbot.errors import CalibrationError, ParameterError
from diffbot.kinematics import DiffDriveParams, norm_angle
from diffbot.numbers import WHEEL_SIZE_RANGE
from diffbot.samples import NS_PER_S

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import ArrayLike, NDArray


__all__ = [
    "DEFAULT_WINDOW",
    "SCIPY_INSTALL_HINT",
    "FitResult",
    "fit",
    "require_scipy",
]

#: Sample intervals per window of :func:`fit` when no window is given.
DEFAULT_WINDOW = 50
#: What to install for the least-squares fit.
SCIPY_INSTALL_HINT = (
    "pip install scipy (a dependency of diffbot-kinematics: the environment lacks it)"
)

#: Smallest ratio of the Jacobian's singular values (parameters scaled to 1) that :func:`fit`
#: accepts: below it one combination of the parameters does not change the residuals.
_OBSERVABLE = 1e-7
#: Below this total turn (rad) over all windows a recording says nothing about the separation.
_MIN_TURN = 1e-3
#: How far from its starting value the fit may move a parameter (as a factor): far beyond any
#: real calibration, and it keeps every trial robot physical.
_SCALE_BOUNDS = (0.01, 100.0)
#: Steps integrated at a time by each residual evaluation (a multiple of the integrator's
#: block): the work arrays stay near two megabytes however long the recording.
CHUNK = 1 << 16
#: Samples at a time of the one-pass conversions of whole columns (stamps to seconds, the
#: unwrapped heading): their temporaries stay under a megabyte each.
_PASS = 1 << 16


def require_scipy() -> None:
    """Raise a CalibrationError saying what to install when SciPy is missing.

    SciPy is found here, not loaded: its optimiser weighs some 45 MB, loaded only once the
    recordings are read and reduced to what the fit needs (see :func:`fit_recordings`).
    """
    from importlib.util import find_spec

    try:
        found = find_spec("scipy") is not None
    except ValueError:  # a module without a spec stands in for it
        found = False
    if not found:
        raise CalibrationError(f"the least-squares fit needs SciPy: {SCIPY_INSTALL_HINT}")


def _least_squares() -> Any:
    """SciPy's ``least_squares``, or the CalibrationError of :func:`require_scipy`."""
    try:
        from scipy.optimize import least_squares
    except ImportError:
        raise CalibrationError(f"the least-squares fit needs SciPy: {SCIPY_INSTALL_HINT}") from None
    return least_squares


# --------------------------------------------------------------------------------------------
# Least-squares fit


@dataclass(frozen=True)
class FitResult:
    """A least-squares calibration.

    Attributes:
        left_wheel_radius: estimated left wheel radius (m).
        right_wheel_radius: estimated right wheel radius (m).
        wheel_separation: estimated wheel separation (m).
        left_wheel_radius_stderr: its standard error (m), from ``s² (JᵀJ)⁻¹`` at the solution.
        right_wheel_radius_stderr: standard error of the right radius (m).
        wheel_separation_stderr: standard error of the separation (m).
        position_rms_before: RMS of the windows' position errors (m) with the initial values.
        heading_rms_before: RMS of the windows' heading errors (rad) with the initial values.
        position_rms_after: RMS of the position errors (m) with the estimates.
        heading_rms_after: RMS of the heading errors (rad) with the estimates.
        windows: how many windows were compared.
    """

    left_wheel_radius: float
    right_wheel_radius: float
    wheel_separation: float
    left_wheel_radius_stderr: float
    right_wheel_radius_stderr: float
    wheel_separation_stderr: float
    position_rms_before: float
    heading_rms_before: float
    position_rms_after: float
    heading_rms_after: float
    windows: int


def check_increasing(name: str, stamps: NDArray[np.float64]) -> None:
    # One comparison array (a byte a sample), not the differences (eight).
    if stamps.size < 2 or not (stamps[1:] > stamps[:-1]).all():
        raise ParameterError(f"{name} must be at least two strictly increasing times (s)")


def unwrapped(theta: NDArray[np.float64]) -> NDArray[np.float64]:
    """``numpy.unwrap(theta)``, equal value for value, worked out :data:`_PASS` samples at a
    time: its differences, corrections and their running sum are never as long as the track."""
    import numpy as np

    out = np.empty_like(theta)
    if theta.size == 0:
        return out
    out[0] = theta[0]
    total = np.zeros(1)
    for i in range(1, theta.size, _PASS):
        j = min(i + _PASS, theta.size)
        dd = theta[i:j] - theta[i - 1 : j - 1]
        # As numpy.unwrap: the step brought into [-pi, pi), +pi where a step of +pi lands on -pi,
        # no correction where the step is under pi already.
        ddmod = np.mod(dd + math.pi, 2.0 * math.pi) - math.pi
        np.copyto(ddmod, math.pi, where=(ddmod == -math.pi) & (dd > 0))
        ddmod -= dd
        np.copyto(ddmod, 0.0, where=np.abs(dd) < math.pi)
        # The corrections' running sum goes on from the last chunk's, in the same order.
        running = np.cumsum(np.concatenate((total, ddmod)))[1:]
        np.add(theta[i:j], running, out=out[i:j])
        total[0] = running[-1]
    return out


def seconds_since(stamps_ns: NDArray[np.int64], origin: int) -> NDArray[np.float64]:
    """``(stamps_ns - origin) / NS_PER_S``, value for value, with no int64 array as long as
    the stamps (the caller has checked that the differences fit in int64)."""
    import numpy as np

    out = np.empty(stamps_ns.size)
    for i in range(0, stamps_ns.size, _PASS):
        np.true_divide(stamps_ns[i : i + _PASS] - origin, NS_PER_S, out=out[i : i + _PASS])
    return out


def window_bounds(
    stamps: NDArray[np.float64],
    window: int | None,
    window_duration: float | None,
    segments: Sequence[int] = (),
) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """First and last sample index of each window (consecutive windows share a sample); no
    window spans the start of a segment (another recording)."""
    import numpy as np

    if segments:
        spans = [(a, b) for a, b in itertools.pairwise([0, *segments, stamps.size]) if b - a >= 2]
        parts = [window_bounds(stamps[a:b], window, window_duration) for a, b in spans]
        offsets = [a for a, _ in spans]
        return (
            np.concatenate([p[0] + a for p, a in zip(parts, offsets, strict=True)]),
            np.concatenate([p[1] + a for p, a in zip(parts, offsets, strict=True)]),
        )
    n = stamps.size
    if window is not None and window_duration is not None:
        raise ParameterError("give window or window_duration, not both")
    if window_duration is not None:
        step = positive("window_duration", window_duration)
        count = (stamps[-1] - stamps[0]) / step
        if count > n - 1:  # more windows than sample intervals: most would be empty
            raise ParameterError(
                f"{{window_duration}} {step:.6g} s is shorter than the recording's mean sample "
                f"interval: give at least {(stamps[-1] - stamps[0]) / (n - 1):.6g} s"
            )
        marks = stamps[0] + step * np.arange(1, math.floor(count) + 1)
        cuts = np.unique(np.concatenate(([0], np.searchsorted(stamps, marks), [n - 1])))
    else:
        size = DEFAULT_WINDOW if window is None else window
        if isinstance(size, bool) or not isinstance(size, int) or size < 1:
            raise ParameterError(
                f"{{window}} must be an integer >= 1 (sample intervals), got {window!r}"
            )
        cuts = np.unique(np.concatenate((np.arange(0, n - 1, size), [n - 1])))
    return cuts[:-1], cuts[1:]


def _relative(
    x: NDArray[np.float64],
    y: NDArray[np.float64],
    theta: NDArray[np.float64],
    starts: NDArray[np.intp],
    ends: NDArray[np.intp],
) -> NDArray[np.float64]:
    """Motion over each window in its start frame: rows (dx, dy, dtheta), shape (3, windows)."""
    import numpy as np

    ex = x[ends] - x[starts]
    ey = y[ends] - y[starts]
    c = np.cos(theta[starts])
    s = np.sin(theta[starts])
    return np.stack((c * ex + s * ey, c * ey - s * ex, theta[ends] - theta[starts]))


def _poses_at(
    params: DiffDriveParams,
    left: NDArray[np.float64],
    right: NDArray[np.float64],
    index: NDArray[np.intp],
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """The odometry's pose (x, y, unwrapped heading) at the sorted sample indices ``index``,
    as :func:`diffbot.batch_odometry.integrate` from the origin gives it, to the last bit.

    The recording is integrated :data:`CHUNK` steps at a time, each chunk continuing from the
    last pose of the one before, so that no array as long as the recording is made: a fit
    evaluates its residuals dozens of times.

    Raises:
        ParameterError: the pose overflows to infinity (wheel angles too large).
    """
    import numpy as np

    from diffbot.batch_odometry import advance

    n = left.shape[0]
    px = np.empty(index.size)
    py = np.empty(index.size)
    pth = np.empty(index.size)
    size = max(1, min(CHUNK, n - 1))
    x = np.empty(size + 1)
    y = np.empty(size + 1)
    theta = np.empty(size + 1)
    x[0] = y[0] = theta[0] = 0.0
    baseline = (float(left[0]), float(right[0]), 0.0)
    lo = 0
    for i in range(0, max(n - 1, 1), size):
        j = min(i + size, n - 1)
        m = j - i
        advance(params, x[: m + 1], y[: m + 1], theta[: m + 1], left[i : j + 1],
                right[i : j + 1], baseline)  # fmt: skip
        hi = int(np.searchsorted(index, j, side="right"))
        local = index[lo:hi] - i
        px[lo:hi] = x[local]
        py[lo:hi] = y[local]
        pth[lo:hi] = theta[local]
        x[0], y[0], theta[0] = x[m], y[m], theta[m]
        lo = hi
    if not (math.isfinite(x[0]) and math.isfinite(y[0]) and math.isfinite(theta[0])):
        raise ParameterError(
            "wheel positions too large: a displacement or the pose overflows to infinity"
        )
    return px, py, pth


def fit(
    stamps: ArrayLike,
    left_positions: ArrayLike,
    right_positions: ArrayLike,
    truth_stamps: ArrayLike,
    truth_x: ArrayLike,
    truth_y: ArrayLike,
    truth_theta: ArrayLike,
    params: DiffDriveParams,
    *,
    window: int | None = None,
    window_duration: float | None = None,
    heading_weight: float | None = None,
    max_relative_stderr: float = 0.01,
    segments: Sequence[int] = (),
) -> FitResult:
    """Wheel radii and separation that make odometry match a ground-truth pose track.

    The truth is interpolated linearly at the wheel stamps (its heading unwrapped first, so
    the interpolation never goes the long way round); wheel samples outside the truth's time span
    are dropped. The samples are cut into windows, and for each the motion from its first to its
    last sample, in the frame of its first, is compared between the odometry (exact arcs) and
    the truth; ``scipy.optimize.least_squares`` minimises the sum of squares of these errors.

    Args:
        stamps: times of the wheel samples (s), strictly increasing, shape (n,).
        left_positions: the left wheel joint's absolute angles (rad), shape (n,).
        right_positions: the right wheel joint's angles (rad), shape (n,).
        truth_stamps: times of the ground-truth poses (s), strictly increasing, shape (m,).
        truth_x: ground-truth x (m), shape (m,).
        truth_y: ground-truth y (m), shape (m,).
        truth_theta: ground-truth heading (rad, wrapped or not), shape (m,).
        params: the nominal robot: its radii and separation are the starting values, its
            direction signs say which way each joint rolls the robot forward.
        window: sample intervals per window (default :data:`DEFAULT_WINDOW`); consecutive
            windows share their boundary sample.
        window_duration: length of a window (s) instead of a number of intervals.
        heading_weight: how many metres of position error one radian of heading error weighs
            (m/rad); default half the initial separation, the wheel travel of a turn.
        max_relative_stderr: the largest standard error, relative to its estimate, that any
            parameter may have; beyond it the data do not determine the robot.
        segments: the indices where another recording starts, when the arrays hold several
            one after another (every sample within the truth's span): no window spans one.

    Returns:
        The estimates, their standard errors and the residuals before and after.

    Raises:
        ParameterError: malformed arrays or stamps, a bad window or both ``window`` and
            ``window_duration``.
        CalibrationError: SciPy is not installed (the message says what to install), fewer
            than two windows, or motion that cannot determine all three
            parameters (no translation, no turning, or only one kind of curve, which noise
            shows as a standard error over ``max_relative_stderr``); the message says what to
            drive.
    """
    import numpy as np

    require_scipy()
    t = vector("stamps", stamps)
    left = vector("left_positions", left_positions)
    right = vector("right_positions", right_positions)
    if not t.size == left.size == right.size:
        raise ParameterError(
            f"stamps, left_positions and right_positions must have equal lengths, got "
            f"{t.size}, {left.size} and {right.size}"
        )
    tt = vector("truth_stamps", truth_stamps)
    tx = vector("truth_x", truth_x)
    ty = vector("truth_y", truth_y)
    tth = vector("truth_theta", truth_theta)
    if not tt.size == tx.size == ty.size == tth.size:
        raise ParameterError(
            f"truth_stamps, truth_x, truth_y and truth_theta must have equal lengths, got "
            f"{tt.size}, {tx.size}, {ty.size} and {tth.size}"
        )
    check_increasing("stamps", t)
    check_increasing("truth_stamps", tt)
    weight, limit = weights(params, heading_weight, max_relative_stderr)

    inside = (t >= tt[0]) & (t <= tt[-1])
    if not inside.all():
        t, left, right = t[inside], left[inside], right[inside]
    enough_samples(t.size, f" ({tt[0]:.6g} s to {tt[-1]:.6g} s)")
    starts, ends = window_bounds(t, window, window_duration, segments if inside.all() else ())
    bounds = bound_samples(starts, ends)
    at = t[bounds.samples]
    truth = (np.interp(at, tt, tx), np.interp(at, tt, ty), np.interp(at, tt, unwrapped(tth)))
    return solve(params, left, right, bounds, truth, weight, limit)


def weights(
    params: DiffDriveParams, heading_weight: float | None, max_relative_stderr: float
) -> tuple[float, float]:
    """The heading weight (m/rad) and the largest relative standard error, checked."""
    weight = (
        0.5 * params.wheel_separation
        if heading_weight is None
        else positive("heading_weight", heading_weight)
    )
    return weight, positive("max_relative_stderr", max_relative_stderr)


def enough_samples(count: int, span: str = "") -> None:
    if count < 3:
        raise CalibrationError(
            f"only {count} wheel samples fall within the ground truth's time span{span}"
        )


class SampleBounds(NamedTuple):
    """The samples at the windows' bounds, in order (``samples``; the poses are needed there
    only), and where each window's ``first`` and ``last`` sample lie in ``samples``."""

    samples: NDArray[np.intp]
    first: NDArray[np.intp]
    last: NDArray[np.intp]


def bound_samples(starts: NDArray[np.intp], ends: NDArray[np.intp]) -> SampleBounds:
    """The samples at the bounds of the windows from ``starts`` to ``ends`` (sample indices).

    Raises:
        CalibrationError: fewer than two windows.
    """
    import numpy as np

    if starts.size < 2:
        raise CalibrationError(
            f"the recording makes {starts.size} window: at least two are needed (shorten "
            "{window})"
        )
    index = np.unique(np.concatenate((starts, ends)))
    return SampleBounds(index, np.searchsorted(index, starts), np.searchsorted(index, ends))


def solve(
    params: DiffDriveParams,
    left: NDArray[np.float64],
    right: NDArray[np.float64],
    bounds: SampleBounds,
    truth_at: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]],
    weight: float,
    limit: float,
) -> FitResult:
    """The least-squares fit once the problem is set: the wheel angles, the samples at the
    windows' bounds (:func:`bound_samples`) and the truth's x, y and unwrapped heading there.
    """
    import numpy as np

    index, first, last = bounds
    start = np.array([*params.radii, params.wheel_separation])
    truth = _relative(*truth_at, first, last)
    if np.hypot(truth[0], truth[1]).sum() < 1e-9:
        raise CalibrationError(
            "the ground truth does not move: wheel radii need driving (straights or arcs)"
        )
    if np.abs(truth[2]).sum() < _MIN_TURN:
        raise CalibrationError(
            "the ground truth does not turn: straight driving cannot determine wheel_separation; "
            "record turns or arcs as well"
        )

    def errors(scale: NDArray[np.float64]) -> NDArray[np.float64]:
        # The bounds of the scale reach past the sizes a robot may have from a start near
        # their ends: such trial robots are held at the end of the range.
        rl, rr, b = (
            min(max(float(v), WHEEL_SIZE_RANGE[0]), WHEEL_SIZE_RANGE[1]) for v in scale * start
        )
        robot = params.replace(
            left_wheel_radius=rl, right_wheel_radius=rr, wheel_separation=b, max_wheel_speed=None
        )
        odo = _relative(*_poses_at(robot, left, right, index), first, last)
        diff = odo - truth
        diff[2] = weight * norm_angle(diff[2])
        return diff.ravel()

    before = errors(np.ones(3)).reshape(3, -1)
    solution = _least_squares()(
        errors,
        np.ones(3),
        jac="3-point",
        bounds=_SCALE_BOUNDS,
        method="trf",
        xtol=1e-15,
        ftol=1e-15,
        gtol=1e-15,
    )
    after = solution.fun.reshape(3, -1)
    jac = np.asarray(solution.jac)
    singular = np.linalg.svd(jac, compute_uv=False)
    if singular[0] == 0.0 or singular[-1] < _OBSERVABLE * singular[0]:
        raise CalibrationError(
            "the recording cannot tell the left wheel_radius, right wheel_radius and "
            "wheel_separation apart (the motion has one kind of curve only): drive turns both "
            "ways and straights"
        )
    dof = max(jac.shape[0] - 3, 1)
    variance = 2.0 * float(solution.cost) / dof
    stderr = np.sqrt(np.diag(variance * np.linalg.inv(jac.T @ jac))) * start
    estimate = solution.x * start
    relative = stderr / np.abs(estimate)
    worst = int(np.argmax(relative))
    if not relative[worst] <= limit:
        name = ("the left wheel_radius", "the right wheel_radius", "wheel_separation")[worst]
        raise CalibrationError(
            f"the recording determines {name} only to {100.0 * relative[worst]:.2g} % "
            f"(standard error; {{max_relative_stderr}} is {100.0 * limit:.2g} %): drive turns both "
            "ways and straights, or record for longer"
        )

    def rms(residual: NDArray[np.float64]) -> tuple[float, float]:
        position = float(np.sqrt(np.mean(residual[0] ** 2 + residual[1] ** 2)))
        return position, float(np.sqrt(np.mean(residual[2] ** 2))) / weight

    position_before, heading_before = rms(before)
    position_after, heading_after = rms(after)
    return FitResult(
        left_wheel_radius=float(estimate[0]),
        right_wheel_radius=float(estimate[1]),
        wheel_separation=float(estimate[2]),
        left_wheel_radius_stderr=float(stderr[0]),
        right_wheel_radius_stderr=float(stderr[1]),
        wheel_separation_stderr=float(stderr[2]),
        position_rms_before=position_before,
        heading_rms_before=heading_before,
        position_rms_after=position_after,
        heading_rms_after=heading_after,
        windows=int(first.size),
    )
