"""Pure pursuit follows the whole path in the plan's order and way: a leg that ends where it
starts is driven, a spin turns its signed angle however many turns, and it arrives only once
the path is driven."""

from __future__ import annotations

import json
import math
from pathlib import Path

import follow_ramps
import numpy as np
import pytest
from click.testing import CliRunner
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from path_pieces import plan_segments
from robots import BOT_50_RPM

from diffbot.arrival import stopping_speed
from diffbot.body_limits import BodyLimits
from diffbot.cli import main
from diffbot.closed_loop import LoopSettings, run
from diffbot.follow import Follower
from diffbot.kinematics import Pose
from diffbot.planfile import parse_plan
from diffbot.profiles import PathLimits
from diffbot.pursuit import Pursuit, legs
from diffbot.simulation import Disturbances, simulate
from diffbot.trajectory import Plan, Spin, geometry, plan

ROBOT = BOT_50_RPM.replace(left_joints=("l",), right_joints=("r",), left_joint="l", right_joint="r")
RADIUS, SEPARATION = 0.035, 0.135
#: A wheel's angle for one turn of the robot in place (rad): its share of the circle, b/2 · 2π.
TURN_WHEEL = 2.0 * math.pi * (SEPARATION / 2.0) / RADIUS
DISTURBED = Disturbances(motor_lag=0.15, latency=0.04, drop=0.05, slip=0.02, seed=3)


def made(text: str) -> Plan:
    return plan(parse_plan(text), ROBOT)


def wheels_at_the_end(text: str, disturbances: Disturbances | None = None):
    """The plan followed by pure pursuit on the simulated robot: the run, the final wheel angles
    (rad) and the open-loop wheel angles of the plan itself."""
    p = made(text)
    setting = (
        LoopSettings(seed=3, ticks=4096)
        if disturbances is None
        else LoopSettings(seed=3, ticks=4096, disturbances=disturbances)
    )
    result = run(p, ROBOT, setting, Follower(ROBOT, p, law="pure-pursuit"))
    planned = simulate(p, ROBOT).positions[:2, -1]
    return result, result.positions[:2, -1], planned


def turned(left: float, right: float) -> float:
    """The robot's heading (rad, not wrapped) from its wheel angles."""
    return (right - left) * RADIUS / SEPARATION


def driven(result) -> float:
    """The path length (m) the robot's centre rolled, from the wheel angles."""
    centre = 0.5 * (result.positions[0] + result.positions[1]) * RADIUS
    return float(np.sum(np.abs(np.diff(centre))))


@pytest.mark.parametrize("text", ["ccw 0.3 360", "spin 360", "spin 270", "spin 360; straight 0.5"])
def test_a_closed_leg_and_multi_turn_spins_end_with_the_plans_wheel_angles(text):
    result, final, planned = wheels_at_the_end(text)
    assert result.arrived
    # Within the arrival's tolerances (5 mm, 0.5 deg) of the plan's own wheel angles.
    assert final == pytest.approx(planned, abs=0.15)
    assert turned(*final) == pytest.approx(turned(*planned), abs=math.radians(0.6))


def test_the_numbers_of_the_four_plans():
    _, final, _ = wheels_at_the_end("spin 360")
    assert final == pytest.approx([-TURN_WHEEL, TURN_WHEEL], abs=0.02)  # ±12.117 rad
    _, final, _ = wheels_at_the_end("spin 270")
    assert final == pytest.approx([-0.75 * TURN_WHEEL, 0.75 * TURN_WHEEL], abs=0.02)
    assert turned(*final) > 0.0
    result, final, _ = wheels_at_the_end("ccw 0.3 360")
    assert driven(result) == pytest.approx(2.0 * math.pi * 0.3, rel=0.01)
    assert turned(*final) == pytest.approx(2.0 * math.pi, abs=math.radians(0.6))
    result, final, _ = wheels_at_the_end("spin 360; straight 0.5")
    assert driven(result) == pytest.approx(0.5, abs=0.01)
    assert turned(*final) == pytest.approx(2.0 * math.pi, abs=math.radians(0.6))


@pytest.mark.parametrize("text", ["ccw 0.3 360", "spin 270", "spin 360; straight 0.5"])
def test_the_disturbed_robot_still_drives_the_whole_path(text):
    # Lag, latency, lost commands and slip: the odometry counts the wheels, so the wheels
    # end where the plan's do.
    result, final, planned = wheels_at_the_end(text, DISTURBED)
    assert result.arrived
    assert final == pytest.approx(planned, abs=0.3)
    assert turned(*final) == pytest.approx(turned(*planned), abs=math.radians(1.0))


def test_simulate_drives_a_loop_with_pure_pursuit(runner: CliRunner, tmp_path: Path):
    out = tmp_path / "loop.csv"
    args = ["simulate", "ccw 0.3 360", "--follow", "pure-pursuit", "-o", str(out), "--json"]
    result = runner.invoke(main, args)
    assert result.exit_code == 0, result.output + result.stderr
    summary = json.loads(result.output)
    assert summary["arrived"] is True
    assert summary["duration"] > 15.0  # 1.885 m at no more than the plan's 0.1 m/s
    assert summary["final_position_error"] < 0.005
    header, *_, last = out.read_text().splitlines()
    row = dict(zip(header.split(","), (float(v) for v in last.split(",")), strict=True))
    left, right = row["front_left_wheel_joint"], row["front_right_wheel_joint"]
    # A full circle of 0.3 m: the wheels roll 2π (0.3 ∓ b/2) / r.
    assert left == pytest.approx(2.0 * math.pi * (0.3 - SEPARATION / 2) / RADIUS, abs=0.15)
    assert right == pytest.approx(2.0 * math.pi * (0.3 + SEPARATION / 2) / RADIUS, abs=0.15)


def test_a_closed_leg_is_not_done_at_its_start_nor_the_follower_arrived():
    p = made("ccw 0.3 360")
    pursuit = Pursuit(p, Follower(ROBOT, p).gains, 0.15, 0.005)
    assert not pursuit.update(0.0, 0.0, 0.0)
    follower = Follower(ROBOT, p, law="pure-pursuit")
    start = Pose(0.0, 0.0, 0.0)
    for k in range(400):  # 40 s standing at the start, which is the goal pose
        t = 0.1 * k
        assert not follower.done(t, start)
        follower.command(t, start)


def test_each_spin_is_a_turn_of_its_own_in_the_plans_order():
    found = legs(made("spin 90; spin -90; straight 0.2; spin 400"), 0.01)
    assert [leg.moves for leg in found] == [False, False, True, False]
    assert [leg.start_heading for leg in found] == pytest.approx(
        [math.pi / 2, 0.0, 0.0, math.radians(400.0)]
    )


def drive_wrapped(follower: Follower, *, dt: float = 0.02, extra: float = 60.0):
    """An ideal unicycle driven by the follower, which is given the heading wrapped as an
    odometry pose is; the final pose with the heading not wrapped, and the distance rolled."""
    x = y = heading = 0.0
    rolled, t = 0.0, 0.0
    while t < follower.duration + extra:
        pose = Pose(x, y, math.remainder(heading, 2.0 * math.pi))
        if follower.done(t, pose):
            break
        v, w = follower.command(t, pose)
        ds, turn = v * dt, w * dt
        half = 0.5 * turn
        chord = ds * (math.sin(half) / half if half else 1.0)
        x, y = x + chord * math.cos(heading + half), y + chord * math.sin(heading + half)
        heading += turn
        rolled += abs(ds)
        t += dt
    return Pose(x, y, heading), rolled


@settings(max_examples=30, deadline=None)
@given(st.floats(-720.0, 720.0).filter(lambda d: abs(d) >= 0.01))
def test_a_spin_turns_the_plans_signed_angle(degrees):
    p = plan([Spin(math.radians(degrees))], ROBOT)
    follower = Follower(ROBOT, p, law="pure-pursuit")
    final, _ = drive_wrapped(follower)
    assert follower.done(follower.duration + 1e3, final)
    assert final.theta == pytest.approx(math.radians(degrees), abs=math.radians(0.6))
    assert math.hypot(final.x, final.y) <= follower.xy_tolerance


pieces = plan_segments(
    length=(0.1, 0.6),
    radius=(0.2, 0.5),
    angle=(math.radians(30.0), math.radians(400.0)),
    spin=(0.05, 4.0 * math.pi),
)


@settings(max_examples=25, deadline=None)
@given(st.lists(pieces, min_size=1, max_size=4))
def test_any_plan_ends_with_the_plans_turns_and_its_path_driven(items):
    p = plan(items, ROBOT)
    follower = Follower(ROBOT, p, law="pure-pursuit")
    final, rolled = drive_wrapped(follower, extra=120.0)
    goal = p.final_pose
    assert follower.done(1e6, final)
    assert math.hypot(final.x - goal.x, final.y - goal.y) <= follower.xy_tolerance
    assert final.theta == pytest.approx(p.segments[-1].end_heading, abs=math.radians(0.6))
    assert rolled >= 0.9 * sum(abs(geometry(s.segment)[0]) for s in p.segments)


@settings(max_examples=30, deadline=None)
@given(follow_ramps.PLANS, follow_ramps.LINEAR, follow_ramps.ANGULAR)
def test_pure_pursuit_follows_any_ramped_plan_it_can_stop_on_a_perfect_robot(text, linear, angular):
    made = follow_ramps.drawn(text, linear, angular)
    # An untimed law turns in place between legs: it must be able to stop the plan's speed
    # within its lookahead (at a jerk of 0.001 m/s³ a stop from 0.1 m/s takes a metre; the
    # tracking law, whose reference brakes in time, follows those: the test beside this one).
    cruise = max(abs(s.twist.linear) for s in made.steps.segments)
    lookahead = Follower(ROBOT, made, law="pure-pursuit").lookahead
    ramps = made.limits.linear
    assume(stopping_speed(lookahead, (ramps.acceleration, ramps.jerk)) >= cruise)
    assert follow_ramps.within(follow_ramps.followed(made, "pure-pursuit")), (text, linear, angular)


@pytest.mark.parametrize("known", [k for k in follow_ramps.KNOWN if k[1] == "pure-pursuit"])
def test_pure_pursuit_brings_a_perfect_robot_to_a_ramped_plans_end(known):
    # Its turns in place and its approach asked speeds the limits could not take back in
    # time: 'spin 90' at 0.1 rad/s² overshot to 160.9 degrees and swung on.
    assert follow_ramps.known_arrives(known)


@pytest.mark.parametrize("law", ["pure-pursuit", "tracking"])
def test_every_command_keeps_the_body_limits_the_plan_was_made_within(law: str) -> None:
    # Pure pursuit spun at the motor limit (2.7 rad/s) where --max-angular asked 0.01 rad/s.
    body = BodyLimits(linear=(-0.05, 0.05), angular=(-0.01, 0.01))
    p = plan(parse_plan("straight 0.3; spin 90"), ROBOT, body=body)
    follower = Follower(ROBOT, p, law=law, body=body)
    result = run(p, ROBOT, LoopSettings(rate=20.0, control_rate=20.0), follower)
    assert result.arrived
    rates = np.abs(np.diff(np.unwrap(result.truth[2])) / np.diff(result.times))
    speeds = np.hypot(*np.diff(result.truth[:2], axis=1)) / np.diff(result.times)
    assert rates.max() <= 0.01 * (1 + 1e-9)
    assert speeds.max() <= 0.05 * (1 + 1e-9)
    assert rates.max() > 0.0099  # at the limit, not held far below it


def test_a_stop_is_not_held_back_by_a_turn_under_a_tight_angular_limit() -> None:
    # The limiter model moved both axes the same share: at a leg's end the turn's 1 rad/s²
    # held the braking back, the robot overshot the straight by 10.5 mm and swung around the
    # goal until the time cap. Braking now keeps the speed's own limit.
    made = follow_ramps.ramped(
        "ccw 0.188 84.0; straight 0.125; spin -16.0", PathLimits(), PathLimits(None, 1.0, None)
    )
    result = run(made, ROBOT, LoopSettings(), Follower(ROBOT, made, law="pure-pursuit"))
    goal = made.steps.final_pose
    reached = np.hypot(result.truth[0] - goal.x, result.truth[1] - goal.y)
    assert result.arrived
    first = int(np.argmax(reached < 0.005))  # the first sample within the tolerance
    assert reached[first:].max() < 0.005  # never out of it again
    assert result.duration < made.duration + 10.0  # within the cap, without its grace
