"""Checks of the numbers the calibration functions take: one message for each kind of mistake."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Protocol

from diffbot.errors import CalibrationError, ParameterError
from diffbot.numbers import WHEEL_SIZE_RANGE, positive_finite

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import ArrayLike, NDArray

__all__ = ["WheelGeometry", "check_geometry", "positive", "vector"]


class WheelGeometry(Protocol):
    """What calibrated results share: wheel radii and separation (m)."""

    @property
    def left_wheel_radius(self) -> float: ...
    @property
    def right_wheel_radius(self) -> float: ...
    @property
    def wheel_separation(self) -> float: ...


def check_geometry(result: WheelGeometry, cause: str) -> None:
    """CalibrationError unless the calibrated radii and separation are finite and within the
    sizes a robot may have (:data:`~diffbot.numbers.WHEEL_SIZE_RANGE`); ``cause`` says what
    gave them (``"the runs give"``)."""
    low, high = WHEEL_SIZE_RANGE
    for name in ("left_wheel_radius", "right_wheel_radius", "wheel_separation"):
        value = float(getattr(result, name))
        if not (math.isfinite(value) and low <= value <= high):
            raise CalibrationError(
                f"{cause} a {name.replace('_', ' ')} of {value:.6g} m, outside "
                f"{low:g}..{high:g} m: the measurements cannot be right (units? sign?)"
            )


def positive(name: str, value: float) -> float:
    """``value`` as a float; ParameterError naming ``name`` unless it is positive and finite
    (the check the robot's parameters get)."""
    return positive_finite(value, name)


def vector(name: str, values: ArrayLike) -> NDArray[np.float64]:
    """``values`` as a finite 1-D float64 array; ParameterError naming ``name`` otherwise."""
    import numpy as np

    try:
        array = np.asarray(values, dtype=np.float64)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be real numbers") from None
    if array.ndim != 1:
        raise ParameterError(f"{name} must be one-dimensional, got shape {array.shape}")
    if not np.isfinite(array).all():
        k = int(np.argmax(~np.isfinite(array)))
        raise ParameterError(f"{name} must be finite: sample {k} is {float(array[k])!r}")
    return array
