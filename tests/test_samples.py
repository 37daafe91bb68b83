"""Wheel samples' bounds: one value or a whole array, the same answer."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from diffbot.numbers import MAX_RECORDED_ANGLE, MAX_WHEEL_SPEED
from diffbot.samples import (
    beyond_range,
    beyond_ranges,
    each_side,
    later_than_before,
    side_means,
    wheel_limit,
)

#: Values about the bounds, their negatives, the infinities and NaN, and anything else.
values = st.one_of(
    st.sampled_from([MAX_RECORDED_ANGLE, MAX_WHEEL_SPEED]).flatmap(
        lambda bound: st.sampled_from(
            [bound, math.nextafter(bound, math.inf), math.nextafter(bound, 0.0), 1.01 * bound]
        )
    ),
    st.sampled_from([0.0, -0.0, math.inf, -math.inf, math.nan]),
    st.floats(allow_nan=True, allow_infinity=True),
).flatmap(lambda v: st.sampled_from([v, -v]))


def test_each_field_has_its_bound() -> None:
    assert wheel_limit("position") == MAX_RECORDED_ANGLE
    assert wheel_limit("velocity") == MAX_WHEEL_SPEED


@pytest.mark.parametrize("limit", [MAX_RECORDED_ANGLE, MAX_WHEEL_SPEED])
def test_only_finite_values_beyond_the_bound_are_beyond_it(limit: float) -> None:
    assert beyond_range(math.nextafter(limit, math.inf), limit)
    assert beyond_range(-math.nextafter(limit, math.inf), limit)
    for value in (limit, -limit, 0.0, math.inf, -math.inf, math.nan):
        assert not beyond_range(value, limit)


@given(
    arrays(np.float64, st.tuples(st.integers(0, 4), st.integers(0, 3)), elements=values),
    st.sampled_from([MAX_RECORDED_ANGLE, MAX_WHEEL_SPEED]),
)
def test_an_array_is_judged_as_each_of_its_values(table: np.ndarray, limit: float) -> None:
    judged = beyond_ranges(table, limit)
    assert judged.shape == table.shape
    assert judged.tolist() == [[beyond_range(v, limit) for v in row] for row in table.tolist()]


def test_the_bound_of_counts_is_that_of_the_radians_they_convert_to() -> None:
    # 2 pi counts a revolution: a count is a radian.
    assert wheel_limit("velocity", 2 * math.pi) == pytest.approx(MAX_WHEEL_SPEED, rel=1e-15)
    # 40960 counts a revolution: 1e4 rad/s is 65,189,864.69 counts/s.
    assert wheel_limit("velocity", 40960) == pytest.approx(65_189_864.69, abs=0.01)
    assert wheel_limit("position", 40960) == pytest.approx(6.518986469e15, rel=1e-9)


@given(st.lists(st.lists(st.booleans(), min_size=3, max_size=3), max_size=20), st.integers(1, 2))
def test_each_side_is_a_joint_of_the_left_and_one_of_the_right(
    rows: list[list[bool]], left_count: int
) -> None:
    present = np.array(rows, dtype=np.bool_).reshape(len(rows), 3)
    got = each_side(present, left_count)
    assert got.tolist() == [any(r[:left_count]) and any(r[left_count:]) for r in rows]
    # side_means says the same of the samples it averages
    assert side_means(np.zeros(present.shape), present, left_count)[2].tolist() == got.tolist()


@given(
    st.lists(st.integers(-(2**62), 2**62), max_size=30)
    | st.lists(st.floats(-1e9, 1e9), max_size=30),
    st.sampled_from([None, 0, -5, 10**6]),
)
def test_later_than_before_is_later_than_every_stamp_before(
    values: list[float], prior: int | None
) -> None:
    floats = any(isinstance(v, float) for v in values)
    array = np.array(values, dtype=np.float64 if floats else np.int64)
    least = -math.inf if floats else int(np.iinfo(np.int64).min)
    start = least if prior is None else prior
    expected, latest = [], start
    for value in values:
        expected.append(value > latest)
        latest = max(latest, value)
    assert later_than_before(array, start).tolist() == expected
