"""The ground truth of a simulated robot whose real geometry differs from its description."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from robots import BOT
from wheel_motion import angle_error

from diffbot.calibration import ground_truth, true_robot
from diffbot.calibration.truth import TRUTH_COLUMNS, truth_rows
from diffbot.errors import ParameterError
from diffbot.planfile import parse_plan
from diffbot.trajectory import plan


def test_true_robot_keeps_the_joints_and_takes_the_real_geometry() -> None:
    robot = true_robot(BOT, (0.0352, 0.0348), 0.138)
    assert robot.radii == (0.0352, 0.0348)
    assert robot.wheel_separation == 0.138
    assert robot.wheel_radius == pytest.approx(0.035, rel=1e-15)
    assert (robot.left_joint, robot.right_joint) == (BOT.left_joint, BOT.right_joint)
    assert true_robot(BOT) == BOT.replace(max_wheel_speed=None)


def test_true_robot_rejects_a_radius_that_is_not_positive() -> None:
    with pytest.raises(
        ParameterError, match=r"left_wheel_radius must be a finite number >= 0\.0001"
    ):
        true_robot(BOT, (-0.03, 0.035))


@settings(max_examples=30, deadline=None)
@given(length=st.floats(0.1, 5.0), turn=st.floats(-170.0, 170.0).filter(lambda a: abs(a) > 1))
def test_the_truth_of_the_described_robot_ends_where_the_plan_does(
    length: float, turn: float
) -> None:
    p = plan(parse_plan(f"straight {length}; spin {turn}; ccw 0.3 45"), BOT)
    times = np.linspace(0.0, p.duration, 37)
    ends = np.cumsum([s.duration for s in p.segments])  # exact arcs between boundaries
    x, y, theta = ground_truth(p, np.union1d(times, ends), BOT)
    end = p.final_pose
    assert x[-1] == pytest.approx(end.x, abs=1e-9)
    assert y[-1] == pytest.approx(end.y, abs=1e-9)
    assert angle_error(theta[-1], end.theta) <= 1e-9


@pytest.mark.parametrize("samples", [2, 8, 101])
def test_equal_wheel_turns_of_unequal_wheels_follow_a_circle(samples: int) -> None:
    # A 1 m straight: both wheels turn alike; the right one is 1 % larger, so the robot curves
    # left on a circle whatever the sampling.
    p = plan(parse_plan("straight 1"), BOT)
    robot = true_robot(BOT, (0.0348, 0.03515), 0.135)
    x, y, theta = ground_truth(p, np.linspace(0.0, p.duration, samples), robot)
    angle = 1.0 / 0.035  # rad, each wheel
    turn = (0.03515 - 0.0348) * angle / 0.135
    radius = 0.5 * (0.0348 + 0.03515) * angle / turn
    assert theta[-1] == pytest.approx(turn, rel=1e-12)
    assert x[-1] == pytest.approx(radius * math.sin(turn), rel=1e-10)
    assert y[-1] == pytest.approx(radius * (1.0 - math.cos(turn)), rel=1e-8)


def test_truth_rows_wrap_the_heading() -> None:
    p = plan(parse_plan("spin 270 3s"), BOT)
    rows = truth_rows(p, [0.0, 3.0], BOT)
    assert rows.shape == (len(TRUTH_COLUMNS), 2)
    assert rows[2, -1] == pytest.approx(-0.5 * math.pi, abs=1e-12)
