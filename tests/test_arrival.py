"""The arrival phase: past the plan's end, the final pose held and a lateral error the tracking
law leaves corrected."""

from __future__ import annotations

import math

import pytest
from robots import BOT_50_RPM

from diffbot.arrival import Arrival
from diffbot.follow import Follower, default_gains
from diffbot.kinematics import Pose
from diffbot.planfile import parse_plan
from diffbot.trajectory import plan

ROBOT = BOT_50_RPM
GAINS = default_gains(ROBOT)


def wrap(angle: float) -> float:
    return math.remainder(angle, 2.0 * math.pi)


def test_near_the_goal_it_aligns_on_the_spot():
    arrival = Arrival(1.0, 0.0, 0.0, GAINS, 0.005)
    # 2 mm short and 0.1 rad to the left of the goal heading: on along, back to the heading.
    v, w = arrival.command(0.998, 0.0, 0.1)
    assert not arrival.approach
    assert v == pytest.approx(GAINS.kx * 0.002 * math.cos(0.1))
    assert w == pytest.approx(GAINS.kspin * math.sin(-0.1))


def test_a_lateral_error_past_the_tolerance_turns_toward_the_goal_first():
    arrival = Arrival(1.0, 0.0, 0.0, GAINS, 0.005)
    v, w = arrival.command(1.0, 0.03, 0.0)  # 3 cm to the left, heading along
    assert arrival.approach
    assert v == 0.0  # the goal lies 90 degrees off: it turns in place
    assert w < 0.0


def test_arrival_corrects_a_lateral_error_kanayamas_law_leaves():
    p = plan(parse_plan("straight 0.5 5s"), ROBOT)
    follower = Follower(ROBOT, p)
    # Past the end, 3 cm to the side of the goal and heading along the path.
    x, y, heading = 0.5, 0.03, 0.0
    t, dt = p.duration, 0.01
    while not follower.done(t, Pose(x, y, heading)) and t < p.duration + 30.0:
        v, w = follower.command(t, Pose(x, y, heading))
        x += v * dt * math.cos(heading + 0.5 * w * dt)
        y += v * dt * math.sin(heading + 0.5 * w * dt)
        heading += w * dt
        t += dt
    assert follower.done(t, Pose(x, y, heading))
    assert math.hypot(x - 0.5, y) <= follower.xy_tolerance
    assert abs(wrap(heading)) <= follower.yaw_tolerance
