"""Numbers as the text outputs write them (``diffbot.formats.text``)."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from diffbot.formats.text import fixed, fmt


@pytest.mark.parametrize(
    ("value", "decimals", "text"),
    [
        (27.2837, 2, "27.28"),
        (-0.0001, 2, "0.00"),
        (-0.0, 4, "0.0000"),
        (-1.5, 1, "-1.5"),
        (999999999999999.9, 1, "999999999999999.9"),
        (1e15, 1, "1e+15"),
        (-100000000000000.0, 1, "-1e+14"),
        (-99999999999999.96, 1, "-1e+14"),
        (2.7283704530039208e303, 1, "2.72837e+303"),
        (-1.7976931348623157e308, 2, "-1.79769e+308"),
    ],
)
def test_fixed_known_values(value: float, decimals: int, text: str) -> None:
    assert fixed(value, decimals) == text


@given(st.floats(allow_nan=False, allow_infinity=False), st.integers(min_value=0, max_value=6))
def test_fixed_is_short_and_reads_back_close(value: float, decimals: int) -> None:
    text = fixed(value, decimals)
    # A 1e308 written with every digit is 309 characters; a table cell stays short.
    assert len(text) <= 16 + decimals
    assert float(text) == pytest.approx(value, rel=1e-5, abs=0.51 * 10.0**-decimals)
    assert not text.startswith("-0") or float(text) != 0.0


def test_fmt_has_no_negative_zero() -> None:
    assert fmt(-0.0) == "0"
    assert fmt(-1e-300) == "-1e-300"
