"""Commands held until the next one or their timeout, integrated exactly: the open loop of
diff_drive_controller on a clock of nanoseconds."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from robots import BOT

from diffbot.kinematics import DiffDriveParams
from diffbot.live.held_commands import HeldCommands
from diffbot.odometry import Odometry
from diffbot.open_loop import command_angles

T0 = 1_700_000_000 * 10**9
S = 10**9


def held(params: DiffDriveParams = BOT, timeout: float = 0.0) -> HeldCommands:
    return HeldCommands(params, Odometry(params), timeout)


def pose(commands: HeldCommands) -> tuple[float, float, float]:
    x, y, theta = commands.odometry.pose
    return x, y, theta


def test_a_straight_then_a_spin_end_where_they_should() -> None:
    commands = held()
    commands.command(0.1, 0.0, T0)
    commands.command(0.0, 0.5, T0 + S)
    assert commands.advance(T0 + 2 * S)
    assert pose(commands) == pytest.approx((0.1, 0.0, 0.5), abs=1e-12)
    assert commands.odometry.twist.linear == pytest.approx(0.0, abs=1e-12)
    assert commands.odometry.twist.angular == pytest.approx(0.5, abs=1e-12)
    assert commands.held == (0.0, 0.5)


def test_the_controller_s_own_open_loop_known_value() -> None:
    # ros2_controllers' diff_drive_controller/test/test_odometry.cpp, TestOpenLoopUpdate: wheels
    # of radius 1 m, 1 m apart; v = 2 m/s, w = 0.5 rad/s for 1 s.
    robot = DiffDriveParams(wheel_radius=1.0, wheel_separation=1.0)
    commands = held(robot)
    commands.command(2.0, 0.5, T0)
    commands.advance(T0 + S)
    assert pose(commands) == pytest.approx(
        (4.0 * math.sin(0.5), -4.0 * (math.cos(0.5) - 1.0), 0.5), abs=1e-12
    )
    assert commands.odometry.twist.linear == pytest.approx(2.0, abs=1e-12)
    assert commands.odometry.twist.angular == pytest.approx(0.5, abs=1e-12)


@pytest.mark.parametrize(
    "robot",
    [
        BOT,
        BOT.replace(left_sign=-1),
        BOT.replace(right_sign=-1, left_wheel_radius=0.03, right_wheel_radius=0.04),
    ],
)
def test_a_held_command_drives_its_exact_arc_on_any_wheels(robot: DiffDriveParams) -> None:
    # Signs and unequal radii turn into other wheel angles, never into another motion.
    commands = held(robot)
    commands.command(0.3, 0.6, T0)
    commands.advance(T0 + S // 2)
    commands.advance(T0 + 2 * S)
    turn = 0.6 * 2.0
    radius = 0.3 / 0.6
    assert pose(commands) == pytest.approx(
        (radius * math.sin(turn), radius * (1.0 - math.cos(turn)), turn), abs=1e-12
    )


def test_a_command_stops_holding_at_its_timeout() -> None:
    commands = held(timeout=0.5)
    commands.command(0.2, 0.0, T0)
    assert commands.advance(T0 + 2 * S)
    assert pose(commands) == pytest.approx((0.1, 0.0, 0.0), abs=1e-12)
    assert commands.held == (0.0, 0.0)
    assert commands.odometry.twist.linear == 0.0  # standing since the timeout
    # A command before the timeout holds on from its own arrival.
    again = held(timeout=0.5)
    again.command(0.2, 0.0, T0)
    again.command(0.2, 0.0, T0 + 4 * S // 10)
    again.advance(T0 + 8 * S // 10)
    assert pose(again) == pytest.approx((0.16, 0.0, 0.0), abs=1e-12)
    assert again.held == (0.2, 0.0)
    # The timeout falls between two advances: the motion up to it, none after.
    late = held(timeout=0.5)
    late.command(0.0, 1.0, T0)
    late.advance(T0 + 3 * S // 10)
    late.advance(T0 + 3 * S)
    assert pose(late) == pytest.approx((0.0, 0.0, 0.5), abs=1e-12)


def test_the_timeout_s_own_moment_is_no_sample_twice() -> None:
    # An advance at the very moment of the timeout, and one after it: each moment is taken
    # once, and the clock goes on after the stop.
    commands = held(timeout=0.5)
    commands.command(0.2, 0.0, T0)
    assert commands.advance(T0 + S // 2)
    assert commands.advance(T0 + S)
    assert commands.advance(T0 + 2 * S)
    assert pose(commands) == pytest.approx((0.1, 0.0, 0.0), abs=1e-12)
    assert commands.odometry.skipped == {}
    assert commands.odometry.samples == 4
    # The shortest timeout there is still stops the command; a shorter one is not "never".
    brief = held(timeout=1e-9)
    brief.command(1.0, 0.0, T0)
    brief.advance(T0 + S)
    assert pose(brief) == pytest.approx((1e-9, 0.0, 0.0), abs=1e-15)
    briefer = held(timeout=4e-10)
    briefer.command(1.0, 0.0, T0)
    briefer.advance(T0 + S)
    assert pose(briefer) == pytest.approx((1e-9, 0.0, 0.0), abs=1e-15)


def test_without_a_timeout_a_command_holds_for_good() -> None:
    commands = held(timeout=0.0)
    commands.command(0.2, 0.0, T0)
    commands.advance(T0 + 100 * S)
    assert pose(commands) == pytest.approx((20.0, 0.0, 0.0), abs=1e-9)


def test_the_first_time_starts_the_clock_and_time_never_runs_back() -> None:
    commands = held()
    assert commands.held == (0.0, 0.0)
    assert commands.advance(T0)  # the baseline: taken, no motion
    assert commands.odometry.samples == 1
    commands.command(1.0, 0.0, T0 + S)
    assert not commands.advance(T0 + S)  # no later than the last: nothing to do
    assert not commands.advance(T0)
    assert commands.advance(T0 + 2 * S)
    assert pose(commands) == pytest.approx((1.0, 0.0, 0.0), abs=1e-12)
    assert commands.odometry.skipped == {}


@settings(max_examples=60, deadline=None)
@given(
    st.lists(
        st.tuples(
            st.integers(1, 2 * S),
            st.floats(-2.0, 2.0, allow_nan=False),
            st.floats(-3.0, 3.0, allow_nan=False),
        ),
        min_size=1,
        max_size=8,
    )
)
def test_held_commands_end_where_a_recording_of_them_does(
    steps: list[tuple[int, float, float]],
) -> None:
    # The same commands, once as they come and once as a recording (diffbot.open_loop's wheel
    # angles through the exact integrator): one pose.
    commands = held()
    stamps = [T0]
    for gap, linear, angular in steps:
        commands.command(linear, angular, stamps[-1])
        stamps.append(stamps[-1] + gap)
    commands.advance(stamps[-1])
    linear = np.array([v for _, v, _ in steps] + [0.0])
    angular = np.array([w for _, _, w in steps] + [0.0])
    left, right = command_angles(np.array(stamps, dtype=np.int64), linear, angular, BOT)
    recorded = Odometry(BOT)
    for k, stamp in enumerate(stamps):
        recorded.update(float(left[k]), float(right[k]), stamp_ns=stamp)
    x, y, theta = recorded.pose
    live = pose(commands)
    assert live[0] == pytest.approx(x, abs=1e-9)
    assert live[1] == pytest.approx(y, abs=1e-9)
    assert math.remainder(live[2] - theta, math.tau) == pytest.approx(0.0, abs=1e-9)
