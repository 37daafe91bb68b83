"""Batch odometry: a whole recording of wheel angles integrated at once with NumPy.

The same exact step as :class:`diffbot.odometry.Odometry` (each step along its arc: the chord
``ds·sinc(dθ/2)`` along ``θ + dθ/2``), vectorised over blocks of samples; both agree to the last
bit wherever ``math`` and NumPy agree on sin and cos.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, NamedTuple

from diffbot.errors import ParameterError
from diffbot.kinematics import DiffDriveParams
from diffbot.numbers import MAX_COORDINATE, MAX_RECORDED_ANGLE, finite_in_range

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import ArrayLike, NDArray

__all__ = ["BLOCK", "PoseSeries", "advance", "initial_pose", "integrate"]


class PoseSeries(NamedTuple):
    """Poses along a recording, one per sample: x, y (m) and the *unwrapped* heading (rad).

    Each field is a float64 array of shape (n,).
    """

    x: NDArray[np.float64]
    y: NDArray[np.float64]
    theta: NDArray[np.float64]


#: Steps integrated per block by :func:`integrate`: small enough that the work arrays stay in the
#: CPU cache, large enough that NumPy's per-call overhead vanishes.
BLOCK = 32768


def integrate(
    params: DiffDriveParams,
    left_positions: ArrayLike,
    right_positions: ArrayLike,
    x0: float = 0.0,
    y0: float = 0.0,
    theta0: float = 0.0,
) -> PoseSeries:
    """Integrate a whole recording of wheel joint angles at once (vectorised).

    Equal to feeding the samples one by one to :class:`Odometry`: the same formulas, with sums
    in the same order; any difference comes from NumPy's and libm's sin and cos (an ulp or so).

    A side of several wheels is given as one column per wheel, shape (n, k): each sample's side
    angle is then the mean of its k wheels, as :meth:`Odometry.update_joint_state` takes a side
    (every wheel present here; :mod:`diffbot.side_angles`).

    Args:
        params: the robot.
        left_positions: the left wheel joint's absolute angles (rad), shape (n,), or the left
            wheels' angles, shape (n, k).
        right_positions: the right wheel joint's angles (rad), shape (n,) or (n, k).
        x0: x (m) at the first sample, which sets the encoder baseline; within
            ±:data:`~diffbot.numbers.MAX_COORDINATE`.
        y0: y (m) at the first sample, likewise.
        theta0: heading (rad) at the first sample, within
            ±:data:`~diffbot.numbers.MAX_RECORDED_ANGLE`.

    Returns:
        The pose at every sample, as float64 arrays of shape (n,). ``theta`` is the *unwrapped*
        heading (it counts whole turns); wrap it with :func:`diffbot.norm_angle` if needed.

    Raises:
        ParameterError: the arrays are not of shape (n,) or (n, k) with one n, hold something
            other than real numbers (complex, text), or a value is NaN or infinite (the message
            names the first such sample) or so large that a displacement overflows; a starting
            pose that is no number, not finite or out of its range.
    """
    import numpy as np

    left = _wheel_array(left_positions, "left")
    right = _wheel_array(right_positions, "right")
    shapes = (left.shape, right.shape)
    left, right = _side_mean(left), _side_mean(right)
    if left.ndim != 1 or right.ndim != 1 or left.shape != right.shape:
        raise ParameterError(
            f"wheel positions must be two arrays of n samples, shape (n,) or (n, wheels), "
            f"got shapes {shapes[0]} and {shapes[1]}"
        )
    start = initial_pose(x0, y0, theta0, ("x0", "y0", "theta0"))
    n = left.shape[0]
    x = np.empty(n)
    y = np.empty(n)
    theta = np.empty(n)
    if n == 0:
        return PoseSeries(x, y, theta)
    x[0], y[0], theta[0] = start
    advance(params, x, y, theta, left, right, (float(left[0]), float(right[0]), start[2]))
    finite = math.isfinite(x[-1]) and math.isfinite(y[-1]) and math.isfinite(theta[-1])
    if n == 1 or not finite:
        # A NaN or infinity anywhere reaches the last pose (through the cumulative sums, or
        # the heading for the first and last samples) unless there is no step at all, so the
        # arrays are searched only then.
        _check_finite(left, right)
    if not finite:
        raise ParameterError(
            "wheel positions too large: a displacement or the pose overflows to infinity"
        )
    return PoseSeries(x, y, theta)


def initial_pose(
    x: object, y: object, theta: object, names: tuple[str, str, str]
) -> tuple[float, float, float]:
    """A starting pose as floats: x and y (m) within ±:data:`~diffbot.numbers.MAX_COORDINATE`
    (a pose beyond lies past any drive), the heading (rad) within
    ±:data:`~diffbot.numbers.MAX_RECORDED_ANGLE` (the largest a recording or message gives);
    ParameterError naming the parameter (``names``) otherwise."""
    return (
        finite_in_range(x, names[0], -MAX_COORDINATE, MAX_COORDINATE, unit="m"),
        finite_in_range(y, names[1], -MAX_COORDINATE, MAX_COORDINATE, unit="m"),
        finite_in_range(theta, names[2], -MAX_RECORDED_ANGLE, MAX_RECORDED_ANGLE, unit="rad"),
    )


def advance(
    params: DiffDriveParams,
    x: NDArray[np.float64],
    y: NDArray[np.float64],
    theta: NDArray[np.float64],
    left: NDArray[np.float64],
    right: NDArray[np.float64],
    baseline: tuple[float, float, float],
    *,
    ds: NDArray[np.float64] | None = None,
    half: NDArray[np.float64] | None = None,
) -> None:
    """Integrate steps in place, continuing from a state: the one vectorised integrator that
    :func:`integrate` and :class:`diffbot.chunk_odometry.ChunkOdometry` both run.

    Index 0 of every array is the state before the first step (the previous sample's wheel
    angles and the pose after it); index k >= 1 gets the pose after step k. The heading is
    computed from the wheel angles travelled since the run's first sample (``baseline``), as
    :class:`diffbot.odometry.Odometry` computes it; x and y are running sums in the streaming
    order, so the result is that of feeding the samples one by one, to the last bit wherever
    NumPy's sin and cos equal libm's.

    Args:
        params: the robot.
        x: x (m), shape (k + 1,); x[0] given, the rest written.
        y: y (m), likewise.
        theta: the unwrapped heading (rad), likewise.
        left: the left side's wheel angles (rad), shape (k + 1,): the previous one first.
        right: the right side's, likewise.
        baseline: the run's first left and right angles (rad) and the heading there (rad).
        ds: if given, shape (k,): each step's path length (m).
        half: if given, shape (k,): each step's half turn (rad).
    """
    import numpy as np

    n = left.shape[0]
    if n < 2:
        return
    left_radius, right_radius = params.radii
    left_scale = params.left_sign * left_radius
    right_scale = params.right_sign * right_radius
    turn = 1.0 / params.wheel_separation
    half_turn = 0.5 / params.wheel_separation
    left0, right0, theta0 = baseline

    block = max(1, min(BLOCK, n - 1))
    dl = np.empty(block)
    dr = np.empty(block)
    along = np.empty(block)
    zero = np.empty(block, dtype=bool)
    # x + iy: one cumulative sum moves both coordinates (each sum is as in the streaming order).
    xy = np.empty(block + 1, dtype=np.complex128)
    with np.errstate(all="ignore"):
        for i in range(0, n - 1, block):
            j = min(i + block, n - 1)
            m = j - i
            dl_, dr_, along_, zero_ = dl[:m], dr[:m], along[:m], zero[:m]
            xy_ = xy[: m + 1]
            chord = xy_.real[1:]
            dy = xy_.imag[1:]
            # The heading is linear in the wheel angles, so it comes from them directly (as in
            # Odometry.update): no cumulative sum, no rounding error growing with the length.
            th = theta[i + 1 : j + 1]
            np.subtract(right[i + 1 : j + 1], right0, out=th)
            th *= right_scale
            np.subtract(left[i + 1 : j + 1], left0, out=along_)
            along_ *= left_scale
            th -= along_
            th *= turn
            th += theta0
            np.subtract(left[i + 1 : j + 1], left[i:j], out=dl_)
            dl_ *= left_scale
            np.subtract(right[i + 1 : j + 1], right[i:j], out=dr_)
            dr_ *= right_scale
            np.add(dl_, dr_, out=chord)
            chord *= 0.5  # ds
            if ds is not None:
                ds[i:j] = chord
            turned = dr_
            turned -= dl_
            turned *= half_turn
            if half is not None:
                half[i:j] = turned
            np.add(theta[i:j], turned, out=along_)
            # chord = ds * sinc(half), sinc(0) = 1 (kinematics.sinc: why sin(h)/h is accurate).
            np.equal(turned, 0.0, out=zero_)
            sinc = dl_
            np.sin(turned, out=sinc)
            sinc /= turned
            np.copyto(sinc, 1.0, where=zero_)
            chord *= sinc
            np.sin(along_, out=dy)
            dy *= chord
            dx = chord
            np.cos(along_, out=along_)
            dx *= along_
            xy_[0] = complex(x[i], y[i])
            np.cumsum(xy_, out=xy_)
            x[i + 1 : j + 1] = xy_.real[1:]
            y[i + 1 : j + 1] = xy_.imag[1:]


def _wheel_array(values: ArrayLike, side: str) -> NDArray[np.float64]:
    """``values`` as a float64 array; ParameterError for anything but real numbers."""
    import numpy as np

    try:
        array = np.asarray(values)
        if array.dtype.kind not in "biuf":
            if array.dtype.kind != "O":
                raise TypeError(f"{array.dtype} values")  # complex, strings, dates, ...
            # Objects such as Decimal or Fraction convert; complex numbers, text and None (which
            # NumPy would turn into NaN) do not.
            if any(v is None or isinstance(v, (complex, str, bytes)) for v in array.flat):
                raise TypeError("complex, text or None values")
        return np.asarray(array, dtype=np.float64)
    except (TypeError, ValueError) as err:
        raise ParameterError(
            f"{side} wheel positions must be real numbers (rad): {' '.join(str(err).split())}"
        ) from None


def _side_mean(wheels: NDArray[np.float64]) -> NDArray[np.float64]:
    """A side's angle per sample from one column per wheel (shape (n, k)); 1-D arrays as given.

    As :meth:`Odometry.update_joint_state` takes it (:mod:`diffbot.side_angles`), in the same
    order and rounding, so both agree to the last bit: every wheel present, the mean of their
    angles.
    """
    if wheels.ndim != 2 or wheels.shape[1] == 0:
        return wheels
    import numpy as np

    from diffbot.side_angles import SideOffsets

    return SideOffsets(wheels.shape[1]).chunk(wheels, np.ones(wheels.shape, dtype=np.bool_))


def _check_finite(left: NDArray[np.float64], right: NDArray[np.float64]) -> None:
    """ParameterError naming the first sample where a wheel position is NaN or infinite."""
    import numpy as np

    bad = ~(np.isfinite(left) & np.isfinite(right))
    if bad.any():
        k = int(np.argmax(bad))
        raise ParameterError(
            f"wheel positions must be finite: sample {k} has left {float(left[k])!r}, "
            f"right {float(right[k])!r}"
        )
