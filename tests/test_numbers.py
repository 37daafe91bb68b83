"""The one boundary check of numbers: finite, in range, or an error naming where it came from."""

from __future__ import annotations

import math
import re
import sys

import pytest
from hypothesis import given
from hypothesis import strategies as st

from diffbot.errors import ParameterError, RecordingError
from diffbot.numbers import (
    as_number,
    finite_in_range,
    flag,
    motor_limits,
    positive_finite,
    positive_written,
    reads_as_number,
    shorten_numerals,
    shown,
    sized,
    whole_number,
    written_form,
    written_number,
)


@given(st.floats(allow_nan=False, allow_infinity=False), st.floats(0.0, 1e300))
def test_a_finite_number_within_its_range_passes_unchanged(value: float, width: float) -> None:
    low, high = value - width, value + width
    assert finite_in_range(value, "x", low, high) == value


@pytest.mark.parametrize(
    ("value", "low", "high", "message"),
    [
        (math.nan, -math.inf, math.inf, "x must be a finite number, got nan"),
        (math.inf, -math.inf, math.inf, "x must be a finite number, got inf"),
        (1e-5, 1e-4, 1e3, "x must be a finite number >= 0.0001 and <= 1000 m, got 1e-05"),
        (2000, 1e-4, 1e3, "got 2000"),
        (int("1" * 400), -math.inf, math.inf, "got an integer of about 400 digits"),
        (True, -math.inf, math.inf, "got True"),
        ([1.0], -math.inf, math.inf, "got [1.0]"),
        ("1e999", -math.inf, math.inf, "got '1e999'"),
    ],
)
def test_anything_else_is_an_error_naming_where_it_came_from(
    value: object, low: float, high: float, message: str
) -> None:
    with pytest.raises(RecordingError, match=rf"^run\.csv: line 3: x: .*{re.escape(message[-9:])}"):
        finite_in_range(value, "run.csv: line 3: x:", low, high, error=RecordingError, unit="m")
    with pytest.raises(ParameterError) as caught:
        finite_in_range(value, "x", low, high, unit="m")
    assert message in str(caught.value)


def test_an_open_lower_bound_excludes_it() -> None:
    assert finite_in_range(1e-300, "x", 0.0, open_low=True) == 1e-300
    with pytest.raises(ParameterError, match=r"x must be a finite number > 0, got 0\.0"):
        finite_in_range(0.0, "x", 0.0, open_low=True)


def test_integers_too_long_to_print_are_described_not_shown() -> None:
    # Python refuses str() of an integer of more than 4300 digits: shown() must not need it.
    assert shown(10**5000) == "an integer of about 5001 digits"
    assert shown(12345) == "12345"
    assert shown("x" * 100) == "'" + "x" * 36 + "..."
    with pytest.raises(ParameterError, match="about 5001 digits"):
        as_number(10**5000, "x")
    with pytest.raises(ParameterError, match="about 5001 digits"):
        positive_finite(-(10**5000), "x")
    assert shown((-0.2, 10**5000)) == "a tuple holding an integer too long to print"


@pytest.mark.parametrize("value", [5e-324, 1e-310, sys.float_info.min / 2])
def test_a_positive_number_too_small_to_compute_with_is_refused(value: float) -> None:
    # Half of it rounds to 0 (or its reciprocal overflows): a wheel separation of 5e-324 made
    # a goal plan divide by zero.
    with pytest.raises(ParameterError, match=r"^x must be a positive finite number, got .*small"):
        positive_finite(value, "x")
    assert positive_finite(sys.float_info.min, "x") == sys.float_info.min
    assert positive_finite(1e-300, "x") == 1e-300


@pytest.mark.parametrize("text", ["0", "-1.5", " 2e3 ", "inf", "-Infinity", "nan", "+7"])
def test_text_written_as_a_number_is_one(text: str) -> None:
    assert reads_as_number(text)


@pytest.mark.parametrize(
    "text", ["", "x", "1,5", "0x10", "1e", "--1", "left_wheel", "1_000", "\u0661\u0665"]
)
def test_other_text_is_not_a_number(text: str) -> None:
    assert not reads_as_number(text)


@given(st.floats() | st.integers(-(10**30), 10**30))
def test_every_printed_number_reads_as_one(value: float) -> None:
    assert reads_as_number(repr(value))


def test_shorten_numerals_cuts_only_runs_of_more_than_40_digits() -> None:
    assert shorten_numerals("x " + "1" * 40 + " y") == "x " + "1" * 40 + " y"
    assert shorten_numerals("1" * 41) == "1" * 18 + "..." + "1" * 18
    digits = "".join(str(i % 10) for i in range(400))
    cut = f"'{digits[:18]}...{digits[-18:]}' and 1e400"
    assert shorten_numerals(f"'{digits}' and 1e400") == cut
    # Every long run is cut, each keeping its own ends; a short run between stays whole.
    text = shorten_numerals("2" * 50 + "-7-" + "3" * 60)
    assert text == "2" * 18 + "..." + "2" * 18 + "-7-" + "3" * 18 + "..." + "3" * 18


def test_motor_limits_keep_those_a_wheel_can_have_and_name_placeholders_once() -> None:
    warnings: list[str] = []
    limits = [("a", 30.0), ("b", 1e6), ("c", 0.0), ("d", 1e4), ("e", 1e6), ("f", 1.7e307)]
    assert motor_limits("the velocity limit of", limits, warnings) == [30.0, 1e4]
    assert warnings == [
        "the velocity limit of joints 'b', 'e', 'f': 1e+06, 1.7e+307 rad/s are faster than any "
        "wheel turns (over 10000 rad/s): taken for a placeholder, not a motor limit"
    ]
    one: list[str] = []
    assert motor_limits("max of", [("w", 2e4), ("v", 5e-324)], one) == []
    assert one == [
        "max of joint 'w': 20000 rad/s is faster than any wheel turns (over 10000 rad/s): "
        "taken for a placeholder, not a motor limit"
    ]
    assert motor_limits("x", [], one) == []
    assert len(one) == 1


@given(st.floats(allow_nan=False) | st.integers(-(10**30), 10**30))
def test_a_number_written_as_files_write_it_reads_as_float_reads_it(value: float) -> None:
    for text in (repr(value), str(value), f"{value:e}" if isinstance(value, float) else str(value)):
        assert written_number(text) == float(text)
    assert math.isnan(written_number("nan"))
    assert written_number(" -inf ") == -math.inf


@pytest.mark.parametrize("text", ["1_0", "1_0e-2", "0.1_5", "\u0661\u0660", "1\u0660", "\uff11"])
def test_spellings_of_python_alone_are_no_written_number(text: str) -> None:
    float(text)  # Python reads each
    with pytest.raises(ValueError, match="could not convert"):
        written_number(text)


#: Digits that are not ASCII: Arabic-Indic, Devanagari, full-width, mathematical bold.
_OTHER_DIGITS = st.sampled_from("\u0663\u0969\uff13\U0001d7d1")


@given(st.floats(allow_nan=False) | st.integers(-(10**30), 10**30), _OTHER_DIGITS, st.data())
def test_a_text_with_another_scripts_digit_or_an_underscore_is_no_number_anywhere(
    value: float, digit: str, data: st.DataObject
) -> None:
    text = repr(value)
    at = data.draw(st.integers(0, len(text)))
    for spelled in (text[:at] + digit + text[at:], text.replace("1", digit), f"1_{abs(value)!r}"):
        if spelled == text:
            continue
        assert not written_form(spelled)
        assert not reads_as_number(spelled)
        with pytest.raises(ValueError, match="could not convert"):
            written_number(spelled)
        with pytest.raises(ParameterError, match="must be a number"):
            as_number(spelled, "x")
    assert written_form(text)
    assert as_number(text, "x") == float(text)


@pytest.mark.parametrize(
    ("text", "value"),
    [
        ("0.05", 0.05),
        ("1e-3", 1e-3),
        ("0", None),
        ("-1", None),
        ("nan", None),
        ("inf", None),
        ("1e400", None),
        ("abc", None),
        ("", None),
        ("1_0", None),
    ],
)
def test_a_positive_written_number_or_none(text: str, value: float | None) -> None:
    assert positive_written(text) == value


@pytest.mark.parametrize("value", [True, False])
def test_a_flag_is_a_bool_as_given(value: bool) -> None:
    assert flag(value, "trust") is value


@pytest.mark.parametrize("value", ["false", "no", "", 0, 1, 0.0, None, [], "True"])
def test_a_flag_is_never_taken_by_truthiness(value: object) -> None:
    """``"false"`` is truthy: taken as a switch it would turn on what it says off."""
    with pytest.raises(ParameterError, match=r"^trust must be True or False, got "):
        flag(value, "trust")


@pytest.mark.parametrize("value", [0, 7, 2**32])
def test_a_whole_number_in_range_is_kept(value: int) -> None:
    assert whole_number(value, "ticks", 0, 2**32) == value


@pytest.mark.parametrize(
    ("value", "high", "said"),
    [
        (-1, math.inf, "seed must be an integer >= 0, got -1"),
        (True, math.inf, "seed must be an integer >= 0, got True"),
        (3.0, 10, "seed must be an integer from 0 to 10, got 3.0"),
        ("3", 10, "seed must be an integer from 0 to 10, got '3'"),
        (11, 10, "seed must be an integer from 0 to 10, got 11"),
    ],
)
def test_anything_but_a_whole_number_in_range_is_refused(
    value: object, high: float, said: str
) -> None:
    with pytest.raises(ParameterError) as caught:
        whole_number(value, "seed", 0, high)
    assert str(caught.value) == said


def test_sized_takes_sequences_of_the_count_and_not_text() -> None:
    assert sized((1.0, 2.0), 2) == (1.0, 2.0)
    assert sized([1, 2, 3], 2) is None
    assert sized("ab", 2) is None
    assert sized(b"ab", 2) is None
    assert sized(None, 2) is None
    assert sized({1, 2}, 2) is None
