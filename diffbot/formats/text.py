"""Numbers and names as text for people: significant digits, no ``-0``, lists cut short."""

from __future__ import annotations

from collections.abc import Iterable
from typing import Final

__all__ = [
    "brief",
    "ceil_text",
    "fixed",
    "fmt",
    "listing",
    "one_line",
    "plain_number",
    "seconds_decimal",
]

#: Names listed in a message at most; the rest are counted.
MAX_LISTED: Final = 30


def fmt(value: float, digits: int = 6) -> str:
    """A number for people: ``digits`` significant digits, no ``-0``."""
    text = f"{value:.{digits}g}"
    return "0" if text in ("-0", "0") else text


def fixed(value: float, decimals: int) -> str:
    """``value`` with ``decimals`` decimals, no ``-0``; from 1e15 on (where a float has no digit
    left below the point), or where the text would pass 16 + ``decimals`` characters (a sign,
    or rounding up to 1e15), 6 significant digits, as :func:`fmt` writes them."""
    if abs(value) >= 1e15:
        return fmt(value)
    text = f"{value:.{decimals}f}"
    if len(text) > 16 + decimals:
        return fmt(value)
    return text.lstrip("-") if float(text) == 0.0 else text


def ceil_text(value: float, digits: int = 4) -> str:
    """``value`` (> 0) rounded up to ``digits`` significant digits (a duration that still fits).

    Written like ``%g``: plainly from 1e-4 to 10**digits (``5.457``, ``1235``), in scientific
    notation beyond (``5.457e+05``); trailing zeros are kept, so every result shows ``digits``.
    """
    from decimal import ROUND_CEILING, Decimal

    shortest = Decimal(repr(float(value)))  # reads back as value, so rounding it up still fits
    if not shortest.is_finite() or shortest <= 0:
        return fmt(value)
    quantum = Decimal(1).scaleb(shortest.adjusted() - digits + 1)
    rounded = shortest.quantize(quantum, rounding=ROUND_CEILING)  # at most digits + 1 digits
    exponent = rounded.adjusted()
    if -4 <= exponent < digits:
        return f"{rounded:.{max(0, digits - 1 - exponent)}f}"
    mantissa, _, power = f"{rounded:.{digits - 1}e}".partition("e")
    return f"{mantissa}e{int(power):+03d}"


def one_line(text: str) -> str:
    """Text folded onto one line (runs of white space become one space)."""
    return " ".join(str(text).split())


def seconds_decimal(duration: float) -> str:
    """A duration (s) for ``sleep``: plain decimals (no exponent), to the nanosecond."""
    text = f"{duration:.9f}".rstrip("0").rstrip(".")
    return text or "0"


def plain_number(value: float) -> str:
    """Every digit of a float, without a trailing ``.0`` (``10.0`` -> ``10``)."""
    text = repr(float(value))
    return text[:-2] if text.endswith(".0") else text


def listing(names: Iterable[str]) -> str:
    """Names quoted and comma-separated, at most :data:`MAX_LISTED` of them; ``none`` if empty."""
    names = list(names)
    if not names:
        return "none"
    shown = ", ".join(repr(n) for n in names[:MAX_LISTED])
    more = len(names) - MAX_LISTED
    return f"{shown}, and {more} more" if more > 0 else shown


def brief(value: object, limit: int = 60) -> str:
    """``repr(value)`` for an error message, cut to ``limit`` characters (``...`` marks a cut).

    Built with :mod:`reprlib` limits, so a huge entry is never written out whole first.
    """
    import reprlib

    brief = reprlib.Repr()
    brief.maxlevel = 3
    brief.maxstring = brief.maxother = brief.maxlong = limit
    brief.maxlist = brief.maxtuple = brief.maxdict = brief.maxset = 8
    try:
        text = brief.repr(value)
    except ValueError:  # an int with more digits than Python converts to text
        text = "<an integer too long to show>"
    return text if len(text) <= limit else f"{text[: limit - 3]}..."
