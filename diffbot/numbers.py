"""Reading numbers from callers: one conversion and one positivity check, each error naming the
quantity and the value given."""

from __future__ import annotations

import math

from diffbot.errors import DiffbotError, ParameterError

__all__ = ["as_number", "positive_finite"]


def as_number(
    value: object,
    what: str,
    error: type[DiffbotError] = ParameterError,
    expected: str = "a number",
) -> float:
    """``float(value)``, or ``error("WHAT must be EXPECTED, got VALUE")`` when it is not one.

    NaN and infinities pass: the caller decides what they mean.
    """
    try:
        return float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError, OverflowError):
        raise error(f"{what} must be {expected}, got {value!r}") from None


def positive_finite(value: object, what: str, error: type[DiffbotError] = ParameterError) -> float:
    """``value`` as a float when it is finite and > 0, else ``error`` naming ``what``."""
    expected = "a positive finite number"
    number = as_number(value, what, error, expected)
    if not math.isfinite(number) or number <= 0.0:
        raise error(f"{what} must be {expected}, got {value!r}")
    return number
