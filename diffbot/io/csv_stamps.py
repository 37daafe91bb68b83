"""Time cells of a recording CSV to integer nanoseconds, exactly: one cell as decimal text, or a
whole column of plain digits at once by integer arithmetic on its bytes; and a stamp's unit
judged by its size.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Final

import numpy as np

from diffbot.samples import INT64, ns_from_seconds

if TYPE_CHECKING:
    from numpy.typing import NDArray

__all__ = [
    "TIME_UNITS",
    "UNIT_NAMES",
    "stamp_ns_from_text",
    "stamps_from_digits",
    "unit_by_magnitude",
]

#: Time units of a time column, as the power of ten that turns each into nanoseconds.
TIME_UNITS: Final = {"s": 9, "ms": 6, "us": 3, "ns": 0}
#: Names of the time units for people.
UNIT_NAMES: Final = {
    "s": "seconds",
    "ms": "milliseconds",
    "us": "microseconds",
    "ns": "nanoseconds",
}
_POW10: Final = np.array([10**k for k in range(19)], dtype=np.uint64)


def stamp_ns_from_text(text: str, decimals: int = 9) -> int | None:
    """A time cell (decimal seconds, or the unit ``decimals`` says: see
    :func:`diffbot.samples.ns_from_seconds`) as integer ns, exactly rounded (ties to even).

    Returns:
        The stamp (ns), or None when the text is NaN or infinite.

    Raises:
        ValueError: not a plain decimal number (digit grouping ``1_0`` included).
    """
    whole, _, frac = text.strip().partition(".")
    # The usual forms ("12", "1700000000.123456789") without Decimal's cost per cell.
    if (
        whole.isdigit()
        and whole.isascii()
        and len(whole) <= 21 - decimals
        and len(frac) <= decimals
        and (not frac or (frac.isdigit() and frac.isascii()))
    ):
        return int(whole + frac.ljust(decimals, "0"))  # whole * 10**decimals + frac
    return ns_from_seconds(text, decimals)


def stamps_from_digits(
    cells: NDArray[np.bytes_], decimals: int = 9
) -> tuple[NDArray[np.int64], NDArray[np.bool_]]:
    """Time cells of plain digits (``12``, ``1700000000.123``) as ns, by integer arithmetic.

    Args:
        cells: the cells as bytes, shape (n,).
        decimals: the unit of the cells as the power of ten that makes it ns (9: seconds).

    Returns:
        The stamps (ns) and whether each cell was of that form (at most ``19 - decimals``
        digits before the point, at most ``decimals`` after, in int64); the stamps of the
        others are 0.
    """
    unit = decimals
    n = cells.shape[0]
    width = cells.dtype.itemsize
    if n == 0 or width == 0:
        return np.zeros(n, dtype=np.int64), np.zeros(n, dtype=np.bool_)
    chars = np.ascontiguousarray(cells).view(np.uint8).reshape(n, width)
    used = np.flatnonzero(chars.any(axis=0))
    # One row per character position, so that each step below reads contiguous memory.
    columns = np.ascontiguousarray(chars[:, : (int(used[-1]) + 1 if used.size else 1)].T)
    value = np.zeros(n, dtype=np.uint64)
    digits = np.zeros(n, dtype=np.uint8)
    places = np.zeros(n, dtype=np.uint8)
    dots = np.zeros(n, dtype=np.uint8)
    padded = np.zeros(n, dtype=np.bool_)
    bad = np.zeros(n, dtype=np.bool_)
    ten = np.uint64(10)
    for column in columns:
        digit = column - np.uint8(ord("0"))
        is_digit = digit < 10
        is_dot = column == ord(".")
        is_nul = column == 0
        bad |= ~(is_digit | is_dot | is_nul) | (padded & ~is_nul)
        padded |= is_nul
        dots += is_dot
        digits += is_digit
        places += is_digit & (dots > 0)
        value = np.where(is_digit, value * ten + digit, value)
    whole = digits - places
    ok = ~bad & (dots <= 1) & (whole >= 1) & (whole <= 19 - unit) & (places <= unit)
    scale = _POW10[unit - np.minimum(places, unit)]
    total = value * scale
    ok &= total < np.uint64(INT64)
    stamps = np.where(ok, total, np.uint64(0)).astype(np.int64)
    return stamps, ok


def unit_by_magnitude(value: float) -> str:
    """The time unit of a stamp judged by its size: a time since 1970 in seconds is below
    1e11 until the year 5138; in ms, us and ns it is a thousand, a million, a billion times
    larger."""
    size = abs(value)
    if size >= 1e17:
        return "ns"
    if size >= 1e14:
        return "us"
    if size >= 1e11:
        return "ms"
    return "s"
