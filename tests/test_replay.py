"""The odometry of recordings by path: velocity feedback, and the recordings whose positions
never move while their velocities do."""

from __future__ import annotations

from pathlib import Path

import pytest
from bags import joint_state, velocity_bag, write_bag
from robots import BOT

import diffbot
from diffbot.replay import recording_odometry, velocities_move

LEFT, RIGHT = BOT.left_joint, BOT.right_joint
S = 1_000_000_000


def test_positions_that_never_move_beside_velocities_that_do_are_refused(tmp_path: Path) -> None:
    bag = velocity_bag(tmp_path / "bag")
    with pytest.raises(diffbot.RecordingError, match="never change") as raised:
        recording_odometry(bag, BOT)
    assert "read the velocities with feedback= velocity" in str(raised.value)
    # Without any position at all, the error that no sample was usable says it too.
    empty = velocity_bag(tmp_path / "empty", positions=False)
    with pytest.raises(diffbot.RecordingError, match=r"no usable sample.*feedback= velocity"):
        recording_odometry(empty, BOT)


def test_a_robot_standing_still_is_not_mistaken_for_velocity_feedback(tmp_path: Path) -> None:
    still = [
        (k * 10**8, joint_state(k * 10**8, [LEFT, RIGHT], [1.0, 2.0], "", [0.0, 0.0]))
        for k in range(1, 11)
    ]
    bag = write_bag(tmp_path / "bag", still)
    assert not velocities_move(bag, BOT)
    assert recording_odometry(bag, BOT).summary.distance == 0.0
    assert velocities_move(velocity_bag(tmp_path / "moving"), BOT)


def test_velocity_feedback_of_messages_without_velocities_says_to_read_positions(
    tmp_path: Path,
) -> None:
    names = [LEFT, RIGHT]
    bag = write_bag(tmp_path / "bag", [(k * S, k * S, names, [0.1 * k, 0.2 * k]) for k in range(5)])
    with pytest.raises(diffbot.RecordingError, match=r"no velocity .*feedback= position"):
        recording_odometry(bag, BOT, feedback="velocity")


def test_velocity_feedback_of_a_bag_and_a_csv_ends_where_trajectory_a_does(
    tmp_path: Path,
) -> None:
    from wheel_motion import assert_pose_close, trajectory_a_velocities

    bag = recording_odometry(velocity_bag(tmp_path / "bag"), BOT, feedback="velocity")
    assert_pose_close(bag.summary.final_pose, diffbot.Pose(0.0, 1.0, 0.0), 1e-9)
    lines = [f"time,/js/{LEFT}/velocity,/js/{RIGHT}/velocity"]
    lines += [f"{s / S!r},{left!r},{right!r}" for s, left, right in trajectory_a_velocities()]
    path = tmp_path / "v.csv"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    csv = recording_odometry(path, BOT, feedback="velocity")
    assert_pose_close(csv.summary.final_pose, diffbot.Pose(0.0, 1.0, 0.0), 1e-9)
    assert (bag.summary.samples, csv.summary.samples) == (401, 401)


def test_joints_found_that_are_none_of_the_robots_ask_for_its_description() -> None:
    from diffbot.replay import _joints_text

    params = diffbot.DiffDriveParams(0.05, 0.3, left_joints=("l",), right_joints=("r",))
    other = _joints_text(params, [("wheel_left_joint", "wheel_right_joint")])
    assert other.endswith("another robot's recording? give its description ({robot})")
    # One of its wheels there (the other side published apart, say): its own recording.
    own = _joints_text(params, [("l",), ("wheel_right_joint",)])
    assert "another robot" not in own
    assert own.endswith("(each message must hold a joint of each side)")
