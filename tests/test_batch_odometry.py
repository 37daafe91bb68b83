"""The one vectorised integrator (diffbot.batch_odometry.advance) continues a run exactly."""

from __future__ import annotations

import numpy as np
from hypothesis import given
from hypothesis import strategies as st
from robots import BOT

from diffbot.batch_odometry import advance, integrate

angles = st.lists(st.tuples(st.floats(-50, 50), st.floats(-50, 50)), min_size=2, max_size=40)


@given(angles, st.integers(1, 39), st.floats(-3, 3))
def test_a_run_continued_from_its_state_is_the_whole_run_to_the_bit(
    samples: list[tuple[float, float]], cut: int, theta0: float
) -> None:
    left = np.array([s[0] for s in samples])
    right = np.array([s[1] for s in samples])
    whole = integrate(BOT, left, right, 0.5, -0.25, theta0)
    cut = min(cut, left.size - 1)
    x, y, theta = (np.empty(left.size) for _ in range(3))
    x[0], y[0], theta[0] = 0.5, -0.25, theta0
    baseline = (float(left[0]), float(right[0]), theta0)
    # The first part, then the rest from the state the first left (index cut).
    advance(
        BOT,
        x[: cut + 1],
        y[: cut + 1],
        theta[: cut + 1],
        left[: cut + 1],
        right[: cut + 1],
        baseline,
    )
    ds = np.empty(left.size - 1 - cut)
    advance(BOT, x[cut:], y[cut:], theta[cut:], left[cut:], right[cut:], baseline, ds=ds)
    np.testing.assert_array_equal(x, whole.x)
    np.testing.assert_array_equal(y, whole.y)
    np.testing.assert_array_equal(theta, whole.theta)
    # Each step's path length, the mean of the wheels' travel (BOT: both radii 0.035 m).
    expected = 0.5 * (np.diff(left[cut:]) * 0.035 + np.diff(right[cut:]) * 0.035)
    np.testing.assert_allclose(ds, expected, rtol=1e-12, atol=1e-12)
