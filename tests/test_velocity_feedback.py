"""Wheel angles from wheel velocities: each sample's velocity over the interval that ends at it."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from robots import BOT
from wheel_motion import assert_pose_close

import diffbot
from diffbot.errors import ParameterError
from diffbot.numbers import MAX_WHEEL_SPEED
from diffbot.odometry import Odometry
from diffbot.simulation import simulate
from diffbot.trajectory import Arc, Plan, Spin, Straight
from diffbot.velocity_feedback import FEEDBACKS, VelocityAngles, check_feedback

S = 1_000_000_000


def test_each_velocity_holds_over_the_interval_that_ends_at_its_sample() -> None:
    # As diff_drive_controller: the velocity read at t_k times (t_k - t_(k-1)).
    stamps = np.array([0, 1 * S, 3 * S, 3 * S + S // 2])
    velocities = np.array([[9.0], [2.0], [-1.0], [4.0]])
    angles = VelocityAngles(1).feed(stamps, velocities, np.ones((4, 1), bool))
    # The first velocity (9) only starts the clock.
    assert angles[:, 0].tolist() == [0.0, 2.0, 0.0, 2.0]


def test_a_chunk_continues_from_where_the_last_one_left_each_wheel() -> None:
    stamps = np.arange(7, dtype=np.int64) * (S // 4)
    velocities = np.column_stack((np.linspace(-1.0, 2.0, 7), np.linspace(3.0, 0.5, 7)))
    present = np.ones((7, 2), bool)
    whole = VelocityAngles(2).feed(stamps, velocities, present)
    split = VelocityAngles(2)
    parts = [split.feed(stamps[a:b], velocities[a:b], present[a:b]) for a, b in ((0, 3), (3, 7))]
    np.testing.assert_allclose(np.vstack(parts), whole, rtol=0, atol=1e-15)


def test_a_nan_or_missing_velocity_leaves_the_gap_to_the_next_one() -> None:
    stamps = np.array([0, S, 2 * S, 3 * S])
    velocities = np.array([[0.0, 0.0], [1.0, math.nan], [1.0, 1.0], [1.0, 1.0]])
    present = np.array([[1, 1], [1, 1], [0, 1], [1, 1]], bool)
    angles = VelocityAngles(2).feed(stamps, velocities, present)
    assert angles[:, 0].tolist() == [0.0, 1.0, 0.0, 3.0]  # row 2 absent: 1 + 1 x 2 s
    assert math.isnan(angles[1, 1])  # passed on, for the integrator to skip as not finite
    assert angles[2:, 1].tolist() == [2.0, 3.0]  # 1 rad/s over the 2 s since row 0


def test_a_stamp_not_after_the_last_usable_one_keeps_the_wheel_where_it_was() -> None:
    stamps = np.array([0, 2 * S, S, 2 * S, 3 * S])
    velocities = np.array([[1.0], [1.0], [50.0], [50.0], [1.0]])
    angles = VelocityAngles(1).feed(stamps, velocities, np.ones((5, 1), bool))
    assert angles[:, 0].tolist() == [0.0, 2.0, 2.0, 2.0, 3.0]


def test_a_chunk_whose_samples_all_go_back_in_time_keeps_the_wheel_where_it_was() -> None:
    # A recording of two runs, the second's clock restarted: a chunk of it holds no sample
    # after the wheel's last usable one.
    angles = VelocityAngles(1)
    first = angles.feed(np.array([0, S, 2 * S]), np.array([[1.0], [1.0], [1.0]]), np.ones((3, 1)))
    assert first[:, 0].tolist() == [0.0, 1.0, 2.0]
    late = angles.feed(np.array([0, S]), np.array([[5.0], [5.0]]), np.ones((2, 1), bool))
    assert late[:, 0].tolist() == [2.0, 2.0]
    after = angles.feed(np.array([3 * S]), np.array([[1.0]]), np.ones((1, 1), bool))
    assert after[:, 0].tolist() == [3.0]  # 1 rad/s over the second since the last usable


def test_odom_of_velocities_reads_a_restarted_clock_in_chunks_as_whole(tmp_path: Path) -> None:
    import io

    from diffbot.reading import Reading
    from diffbot.replay import csv_odometry

    rows = [f"{t / 10!r},1.0,{0.5 + t / 100!r}" for t in [*range(20), *range(20)]]
    text = "time,/left_wheel_joint/velocity,/right_wheel_joint/velocity\n" + "\n".join(rows)
    robot = BOT.replace(left_joint="left_wheel_joint", right_joint="right_wheel_joint")
    velocity = Reading(feedback="velocity")
    whole = csv_odometry(io.StringIO(text, newline=""), robot, velocity).summary
    chunked = csv_odometry(io.StringIO(text, newline=""), robot, velocity, chunk_bytes=64).summary
    # Each chunk's sums start from the last one's angle: equal to rounding.
    assert tuple(chunked.final_pose) == pytest.approx(tuple(whole.final_pose), abs=1e-12)
    assert chunked.skipped == whole.skipped


def test_feedback_names_are_checked() -> None:
    assert FEEDBACKS == ("position", "velocity")
    assert check_feedback("velocity") == "velocity"
    with pytest.raises(ParameterError, match=r"feedback= 'effort'"):
        check_feedback("effort")


# --------------------------------------------------------------------------------------------
# The law: velocity feedback of a plan's wheel velocities ends where the plan does

positive = st.floats(0.05, 3.0)
angles = st.floats(0.1, 2 * math.pi)
#: Whole milliseconds: the segment boundaries fall on whole nanoseconds, as stamps do.
durations = st.integers(200, 20_000).map(lambda ms: ms / 1000)
segments = st.one_of(
    st.builds(Straight, st.floats(-3.0, 3.0).filter(lambda v: abs(v) > 1e-3), durations),
    st.builds(Arc, positive, angles, st.sampled_from(["cw", "ccw"]), durations),
    st.builds(Spin, st.floats(-6.0, 6.0).filter(lambda v: abs(v) > 1e-3), durations),
)
robots = st.builds(
    diffbot.DiffDriveParams,
    wheel_radius=st.floats(0.02, 0.5),
    wheel_separation=st.floats(0.1, 2.0),
    left_sign=st.sampled_from([1, -1]),
    right_sign=st.sampled_from([1, -1]),
)


def plan_velocities(plan: Plan, times: np.ndarray) -> np.ndarray:
    """Each sample's joint velocities (rad/s): the segment's over the interval ending at it.

    The simulation gives joint positions only; the velocities are the plan's own (its segments'
    joint speeds), not differences of the simulated positions.
    """
    ends = np.cumsum([segment.duration for segment in plan.segments])
    middle = np.concatenate(([0.0], 0.5 * (times[1:] + times[:-1])))
    index = np.minimum(np.searchsorted(ends, middle), len(plan.segments) - 1)
    speeds = np.array([(s.joints.left, s.joints.right) for s in plan.segments], dtype=float)
    return speeds[index]


@settings(max_examples=60, deadline=None)
@given(st.lists(segments, min_size=1, max_size=6), robots, st.floats(2.0, 60.0))
def test_velocity_feedback_of_a_plans_wheel_velocities_ends_at_its_exact_final_pose(
    pieces: list[Straight | Arc | Spin], robot: diffbot.DiffDriveParams, rate: float
) -> None:
    plan = diffbot.plan(pieces, robot)
    states = simulate(plan, robot, rate)
    velocities = plan_velocities(plan, states.times)
    stamps_ns = np.round(states.times * S).astype(np.int64)
    scale = max(1.0, *(abs(s.end_pose.x) + abs(s.end_pose.y) for s in plan.segments))
    # The streaming integrator, fed velocities ...
    odom = Odometry(robot, feedback="velocity")
    for t, (left, right) in zip(states.times.tolist(), velocities.tolist(), strict=True):
        odom.update(left, right, t)
    assert_pose_close(odom.pose, plan.final_pose, 1e-9 * scale)
    # ... and the angles they integrate to, fed as positions (stamped in ns: the boundaries
    # fall on whole ns, and within a segment the rounding of a stamp moves nothing).
    wheels = VelocityAngles(2).feed(stamps_ns, velocities, np.ones(velocities.shape, bool))
    angles = Odometry(robot)
    for stamp, (left, right) in zip(stamps_ns.tolist(), wheels.tolist(), strict=True):
        angles.update(left, right, stamp_ns=stamp)
    assert_pose_close(angles.pose, plan.final_pose, 1e-9 * scale)


def test_the_bundled_robots_square_from_velocities_closes() -> None:
    plan = diffbot.plan([Straight(1.0, 5.0), Spin(math.pi / 2, 2.0)] * 4, BOT)
    states = simulate(plan, BOT, 20.0)
    velocities = plan_velocities(plan, states.times)
    odom = Odometry(BOT, feedback="velocity")
    for t, (left, right) in zip(states.times.tolist(), velocities.tolist(), strict=True):
        odom.update(left, right, t)
    assert_pose_close(odom.pose, diffbot.Pose(0.0, 0.0, 0.0), 1e-9)
    assert odom.distance == pytest.approx(4.0, abs=1e-9)


# --- velocities too large to compute with are skipped as velocities ---------------------------

#: Two rows beyond the wheel velocity bound that messages have too (1 % past it, and far).
HUGE = [[0.0, 0.0], [1.01 * MAX_WHEEL_SPEED, 0.1], [-1e308, 2.0], [0.1, 0.1]]


def _velocity_csv(tmp_path: Path, quoted: bool) -> Path:
    """A CSV of wheel velocities with two rows beyond range; ``quoted`` sends it through the
    reader's row-by-row path (a quoted cell) rather than its bulk one."""
    header = "time,/left_wheel_joint/velocity,/right_wheel_joint/velocity"
    rows = [f"{k},{left!r},{right!r}" for k, (left, right) in enumerate(HUGE)]
    if quoted:
        rows[0] = '"0",0.0,0.0'
    path = tmp_path / "velocities.csv"
    path.write_text("\n".join([header, *rows]) + "\n")
    return path


def _velocity_bag(tmp_path: Path) -> Path:
    from bags import joint_state, write_bag

    names = ["left_wheel_joint", "right_wheel_joint"]
    second = 1_000_000_000
    messages = [
        (k * second, joint_state(k * second, names, [0.0, 0.0], velocities=v))
        for k, v in enumerate(HUGE, start=1)
    ]
    return write_bag(tmp_path / "velocities", messages)


@pytest.mark.parametrize("source", ["csv", "quoted csv", "bag"])
def test_velocities_beyond_range_are_skipped_as_velocities(tmp_path: Path, source: str) -> None:
    path = (
        _velocity_bag(tmp_path) if source == "bag" else _velocity_csv(tmp_path, "quoted" in source)
    )
    params = BOT.replace(left_joints=("left_wheel_joint",), right_joints=("right_wheel_joint",))
    want = {"velocity out of range": 2}
    whole = diffbot.read_recording(path, params, feedback="velocity")
    assert dict(whole.skipped) == want
    assert len(whole.samples) == 2
    from diffbot.replay import recording_odometry

    streamed = recording_odometry(path, params, feedback="velocity")
    assert dict(streamed.summary.skipped) == want
    # The two usable samples at 0 s and 3 s: 0.1 rad/s held over the gap on both wheels.
    assert streamed.summary.final_pose.x == pytest.approx(0.1 * 3.0 * 0.035, rel=1e-12)


#: An encoder of 40960 counts per revolution at 0.1 rev/s, then 0.5 rev/s for 10 s (20480
#: counts/s, 3.14 rad/s), then 0.1 rev/s again, one sample a second; the last sample is 1 %
#: past the wheel velocity bound once converted to rad/s.
COUNTS_PER_REV = 40960
COUNT_SPEEDS = [20480.0 if 10 < k <= 20 else 4096.0 for k in range(31)]
COUNT_SPEEDS.append(1.01 * MAX_WHEEL_SPEED * COUNTS_PER_REV / (2 * math.pi))


def _counts_recording(tmp_path: Path, source: str) -> Path:
    if source == "bag":
        from bags import joint_state, write_bag

        names = ["left_wheel_joint", "right_wheel_joint"]
        messages = [
            (k * S, joint_state(k * S, names, [0.0, 0.0], velocities=[v, v]))
            for k, v in enumerate(COUNT_SPEEDS, start=1)
        ]
        return write_bag(tmp_path / "counts", messages)
    header = "time,/left_wheel_joint/velocity,/right_wheel_joint/velocity"
    rows = [f"{k},{v!r},{v!r}" for k, v in enumerate(COUNT_SPEEDS)]
    if source == "quoted csv":
        rows[0] = '"0",4096,4096'
    path = tmp_path / "counts.csv"
    path.write_text("\n".join([header, *rows]) + "\n")
    return path


@pytest.mark.parametrize("source", ["csv", "quoted csv", "bag"])
def test_the_velocity_bound_holds_for_counts_once_converted_to_radians(
    tmp_path: Path, source: str
) -> None:
    from diffbot.conditioning import Conditioning
    from diffbot.replay import recording_odometry

    path = _counts_recording(tmp_path, source)
    params = BOT.replace(left_joints=("left_wheel_joint",), right_joints=("right_wheel_joint",))
    counts = Conditioning(counts_per_rev=COUNTS_PER_REV, wrap=0)
    # 2 revolutions at 0.1 rev/s and 5 at 0.5 rev/s of a 35 mm wheel.
    distance = (20 * 0.1 + 10 * 0.5) * 2 * math.pi * 0.035
    assert distance == pytest.approx(1.5393804, abs=1e-7)
    want = {"velocity out of range": 1}
    streamed = recording_odometry(path, params, conditioning=counts, feedback="velocity")
    assert dict(streamed.summary.skipped) == want
    assert streamed.summary.distance == pytest.approx(distance, rel=1e-12)
    assert streamed.summary.final_pose.x == pytest.approx(distance, rel=1e-12)
    whole = diffbot.read_recording(path, params, conditioning=counts, feedback="velocity")
    assert dict(whole.skipped) == want
    assert len(whole.samples) == 31
    left = whole.samples[-1].positions[0]
    assert left * 0.035 == pytest.approx(distance, rel=1e-12)
