"""Checks of the numbers the calibration functions take: one message for each kind of mistake."""

from __future__ import annotations

from typing import TYPE_CHECKING

from diffbot.errors import ParameterError
from diffbot.numbers import positive_finite

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import ArrayLike, NDArray

__all__ = ["positive", "vector"]


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
