"""The sums of a rolling window: those of its last steps, exactly zero over steps of zero, at a
bounded cost per step whatever the window's size."""

from __future__ import annotations

import math
import time

import pytest
from hypothesis import given
from hypothesis import strategies as st

from diffbot.window_sums import WindowSums

steps = st.tuples(st.floats(-1e3, 1e3), st.floats(-1e3, 1e3), st.floats(1e-6, 1.0)).map(
    lambda step: (float(step[0]), float(step[1]), float(step[2]))
)


@given(st.integers(1, 12), st.lists(steps, max_size=60))
def test_the_sums_are_those_of_the_last_steps(
    size: int, pushed: list[tuple[float, float, float]]
) -> None:
    window = WindowSums(size)
    for k, step in enumerate(pushed):
        sums = window.push(step)
        last = pushed[max(0, k + 1 - size) : k + 1]
        assert len(window) == len(last)
        for i in range(3):
            values = [s[i] for s in last]
            want = math.fsum(values)
            slack = 1e-12 * math.fsum(abs(v) for v in values)
            assert sums[i] == pytest.approx(want, abs=slack)
    if not pushed:
        assert window.sums() == (0.0, 0.0, 0.0)


@given(st.integers(1, 12), st.lists(steps, max_size=40))
def test_a_window_of_zero_steps_sums_to_exactly_zero(
    size: int, moving: list[tuple[float, float, float]]
) -> None:
    # A robot that moved, then stood still for a whole window: no residue of the motion.
    window = WindowSums(size)
    for step in moving:
        window.push(step)
    for _ in range(size):
        distance, turn, elapsed = window.push((0.0, 0.0, 0.5))
    assert (distance, turn) == (0.0, 0.0)
    assert elapsed == 0.5 * size


def test_clear_forgets_every_step() -> None:
    window = WindowSums(3)
    for k in range(5):
        window.push((1.0, 2.0, float(k)))
    window.clear()
    assert len(window) == 0
    assert window.sums() == (0.0, 0.0, 0.0)
    assert window.push((1.0, 1.0, 1.0)) == (1.0, 1.0, 1.0)


def cost(size: int, pushes: int) -> float:
    window = WindowSums(size)
    started = time.process_time()
    for k in range(pushes):
        window.push((1.0, 0.5, 0.001 * (k % 7 + 1)))
    return time.process_time() - started


def test_a_step_costs_the_same_in_a_window_of_ten_or_of_a_million() -> None:
    # Summing the window again at each step made a window of 100,000 cost 100,000 times more.
    small = min(cost(10, 200_000) for _ in range(3))
    large = min(cost(1_000_000, 200_000) for _ in range(3))
    assert large < 3.0 * small + 0.05, (small, large)
