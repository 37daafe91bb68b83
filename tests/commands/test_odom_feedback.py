"""``diffbot odom --feedback velocity`` and ``--open-loop``: the odometry a diff_drive_controller
computes with ``position_feedback: false`` or ``open_loop: true``, from a recording."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest
from bags import joint_state, odometry_message, twist_message, write_bag, write_topics
from cli_results import assert_one_error_line
from click.testing import CliRunner

from diffbot.cli import main

S = 1_000_000_000
#: A robot shaped like a small real one: r = 0.05 m, b = 0.2 m, its wheels named as
#: articubot-style descriptions name them, driven by a diff_drive_controller.
ROBOT = """<?xml version="1.0"?>
<robot name="scout">
  <link name="base_link"/>
  <link name="chassis"><visual><geometry><box size="0.3 0.3 0.15"/></geometry></visual></link>
  <joint name="chassis_joint" type="fixed"><parent link="base_link"/><child link="chassis"/>
    <origin xyz="-0.1 0 0"/></joint>
  <joint name="left_wheel_joint" type="continuous"><parent link="base_link"/>
    <child link="left_wheel"/><origin xyz="0 0.1 0" rpy="-1.5707963 0 0"/><axis xyz="0 0 1"/>
  </joint>
  <link name="left_wheel"><collision><geometry><cylinder radius="0.05" length="0.04"/>
    </geometry></collision></link>
  <joint name="right_wheel_joint" type="continuous"><parent link="base_link"/>
    <child link="right_wheel"/><origin xyz="0 -0.1 0" rpy="1.5707963 0 0"/>
    <axis xyz="0 0 -1"/></joint>
  <link name="right_wheel"><collision><geometry><cylinder radius="0.05" length="0.04"/>
    </geometry></collision></link>
</robot>
"""
CONTROLLERS = """controller_manager:
  ros__parameters:
    update_rate: 30
    diff_cont:
      type: diff_drive_controller/DiffDriveController
diff_cont:
  ros__parameters:
    publish_rate: 50.0
    base_frame_id: base_link
    left_wheel_names: ["left_wheel_joint"]
    right_wheel_names: ["right_wheel_joint"]
    wheel_separation: 0.2
    wheel_radius: 0.05
    use_stamped_vel: false
    position_feedback: FEEDBACK
"""
NAMES = ["left_wheel_joint", "right_wheel_joint"]


@pytest.fixture
def robot(tmp_path: Path) -> Path:
    path = tmp_path / "scout" / "urdf" / "scout.urdf"
    path.parent.mkdir(parents=True)
    path.write_text(ROBOT)
    return path


def controllers(tmp_path: Path, position_feedback: bool) -> Path:
    path = tmp_path / "my_controllers.yaml"
    path.write_text(CONTROLLERS.replace("FEEDBACK", "true" if position_feedback else "false"))
    return path


def velocity_bag(tmp_path: Path, *, odom: bool = False) -> Path:
    """2 s at 0.1 m/s, then a quarter turn in place in 1 s, reported as wheel velocities only
    (positions stuck at 0) at 10 Hz; with ``odom``, a cmd_vel topic and the robot's own odometry
    too."""
    v = 0.1 / 0.05  # wheel rad/s
    spin = (math.pi / 2) * 0.1 / 0.05  # w b/2 / r for a quarter turn in 1 s
    messages = []
    for k in range(31):
        left, right = (v, v) if 0 < k <= 20 else (-spin, spin) if k > 20 else (0.0, 0.0)
        stamp = 100 * S + k * S // 10
        raw = joint_state(stamp, NAMES, [0.0, 0.0], velocities=[left, right])
        messages.append((stamp, raw))
    topics = {"/joint_states": ("sensor_msgs/msg/JointState", messages)}
    if odom:
        commands = [(100 * S, twist_message(0.1, 0.0)), (102 * S, twist_message(0.0, math.pi / 2))]
        commands.append((103 * S, twist_message(0.0, 0.0)))
        topics["/cmd_vel"] = ("geometry_msgs/msg/Twist", commands)
        poses = [(100 * S, 0.0, 0.0, 0.0), (102 * S, 0.2, 0.0, 0.0), (103 * S, 0.2, 0.0, 1.5)]
        topics["/odom"] = (
            "nav_msgs/msg/Odometry",
            [(stamp, odometry_message(stamp, x, y, t)) for stamp, x, y, t in poses],
        )
    return write_topics(tmp_path / "run", topics)


def odom_json(runner: CliRunner, *args: str) -> dict[str, object]:
    result = runner.invoke(main, ["odom", *args, "--json"])
    assert result.exit_code == 0, result.output
    data: dict[str, object] = json.loads(result.stdout)
    return data


def final(data: dict[str, object]) -> tuple[float, float, float]:
    pose = data["final_pose"]
    assert isinstance(pose, dict)
    return pose["x"], pose["y"], pose["theta"]


def test_velocity_feedback_of_a_bag_integrates_the_joint_states_velocities(
    runner: CliRunner, tmp_path: Path, robot: Path
) -> None:
    data = odom_json(
        runner, str(velocity_bag(tmp_path)), "--robot", str(robot), "--feedback", "velocity"
    )
    assert data["feedback"] == "velocity"
    assert final(data) == pytest.approx((0.2, 0.0, math.pi / 2), abs=1e-12)
    assert data["distance"] == pytest.approx(0.2, abs=1e-12)


def test_a_velocity_only_bag_read_for_positions_is_one_error_naming_the_option(
    runner: CliRunner, tmp_path: Path, robot: Path
) -> None:
    result = runner.invoke(main, ["odom", str(velocity_bag(tmp_path)), "--robot", str(robot)])
    assert_one_error_line(
        result, "positions never change while the wheel velocities do", "--feedback velocity"
    )


def test_the_controllers_position_feedback_false_chooses_velocity_feedback(
    runner: CliRunner, tmp_path: Path, robot: Path
) -> None:
    bag = str(velocity_bag(tmp_path))
    yaml = str(controllers(tmp_path, position_feedback=False))
    data = odom_json(runner, bag, "--robot", str(robot), "--controllers", yaml)
    assert data["feedback"] == "velocity"
    assert final(data) == pytest.approx((0.2, 0.0, math.pi / 2), abs=1e-12)
    result = runner.invoke(main, ["odom", bag, "--robot", str(robot), "--controllers", yaml])
    assert result.exit_code == 0, result.output
    assert "feedback    wheel velocities" in result.stdout
    # --feedback overrides the file; position_feedback: true keeps positions.
    refused = runner.invoke(
        main, ["odom", bag, "--robot", str(robot), "--controllers", yaml, "--feedback", "position"]
    )
    assert_one_error_line(refused, "--feedback velocity")
    yaml = str(controllers(tmp_path, position_feedback=True))
    assert_one_error_line(
        runner.invoke(main, ["odom", bag, "--robot", str(robot), "--controllers", yaml]),
        "--feedback velocity",
    )


def test_a_controller_with_open_loop_odometry_is_named_when_the_wheels_are_read(
    runner: CliRunner, tmp_path: Path, robot: Path
) -> None:
    bag = str(velocity_bag(tmp_path, odom=True))
    yaml = tmp_path / "open_controllers.yaml"
    yaml.write_text(CONTROLLERS.replace("FEEDBACK", "false") + "    open_loop: true\n")
    args = ["odom", bag, "--robot", str(robot), "--controllers", str(yaml)]
    result = runner.invoke(main, args)
    assert result.exit_code == 0, result.output
    warnings = [line for line in result.stderr.splitlines() if "open_loop: true" in line]
    assert len(warnings) == 1
    assert warnings[0].startswith(f"warning: {yaml}: diff_cont computes its odometry from")
    assert "--open-loop" in warnings[0]
    # Said once for the file; asked for, the commands are integrated and nothing is said.
    for extra in ([], ["--open-loop"]):
        again = runner.invoke(main, [*args, *extra])
        assert again.exit_code == 0, again.output
        assert "open_loop: true" not in again.stderr
    # -q silences it, and a quieted run does not count as shown.
    other = tmp_path / "other_controllers.yaml"
    other.write_bytes(yaml.read_bytes())
    args[-1] = str(other)
    quiet = runner.invoke(main, [*args, "-q"])
    assert quiet.exit_code == 0, quiet.output
    assert "open_loop: true" not in quiet.stderr
    assert "open_loop: true" in runner.invoke(main, args).stderr
    plain = tmp_path / "closed_controllers.yaml"
    plain.write_text(CONTROLLERS.replace("FEEDBACK", "false") + "    open_loop: false\n")
    closed = runner.invoke(main, ["odom", bag, "--robot", str(robot), "--controllers", str(plain)])
    assert closed.exit_code == 0, closed.output
    assert "open_loop" not in closed.stderr


def test_a_wrap_is_refused_with_velocities(runner: CliRunner, tmp_path: Path, robot: Path) -> None:
    args = ["--robot", str(robot), "--feedback", "velocity", "--wrap", "65536"]
    result = runner.invoke(main, ["odom", str(velocity_bag(tmp_path)), *args])
    assert_one_error_line(result, "--wrap", "do not wrap")
    assert not list(tmp_path.glob("*.csv"))


def test_velocity_columns_of_a_csv_by_joint_and_by_option(
    runner: CliRunner, tmp_path: Path, robot: Path
) -> None:
    rows = ["time,/js/left_wheel_joint/velocity,/js/right_wheel_joint/velocity,wl,wr"]
    for k in range(11):
        v = 2.0 if k else 0.0
        rows.append(f"{k / 10},{v},{v},{v},{v}")
    path = tmp_path / "vel.csv"
    path.write_text("\n".join(rows) + "\n")
    by_joint = odom_json(runner, str(path), "--robot", str(robot), "--feedback", "velocity")
    assert final(by_joint) == pytest.approx((0.1, 0.0, 0.0), abs=1e-12)
    named = odom_json(
        runner,
        str(path),
        "--robot",
        str(robot),
        "--feedback",
        "velocity",
        "--left-column",
        "wl",
        "--right-column",
        "wr",
    )
    assert final(named) == pytest.approx((0.1, 0.0, 0.0), abs=1e-12)


def test_a_csv_without_velocity_columns_says_which_it_wants(
    runner: CliRunner, tmp_path: Path, robot: Path
) -> None:
    path = tmp_path / "pos.csv"
    path.write_text("time,left_wheel_joint,right_wheel_joint\n0,0,0\n1,1,-1\n")
    result = runner.invoke(
        main, ["odom", str(path), "--robot", str(robot), "--feedback", "velocity"]
    )
    assert_one_error_line(result, "no column for the left wheel joint", "/<joint>/velocity")


def test_a_velocity_column_that_is_not_a_number_is_one_error(
    runner: CliRunner, tmp_path: Path, robot: Path
) -> None:
    path = tmp_path / "vel.csv"
    path.write_text("time,wl,wr\n0,fast,slow\n1,fast,slow\n")
    args = ["--feedback", "velocity", "--left-column", "wl", "--right-column", "wr"]
    result = runner.invoke(main, ["odom", str(path), "--robot", str(robot), *args])
    assert_one_error_line(result, "no usable sample", "unreadable value")


def test_open_loop_integrates_the_commands_and_compares_them_with_the_reference(
    runner: CliRunner, tmp_path: Path, robot: Path
) -> None:
    bag = str(velocity_bag(tmp_path, odom=True))
    data = odom_json(runner, bag, "--robot", str(robot), "--open-loop", "--reference", "/odom")
    assert data["feedback"] == "open-loop"
    assert final(data) == pytest.approx((0.2, 0.0, math.pi / 2), abs=1e-12)
    reference = data["reference"]
    assert isinstance(reference, dict)
    assert reference["samples"] == 3
    assert reference["final_heading_error"] == pytest.approx(math.pi / 2 - 1.5, abs=1e-9)
    result = runner.invoke(main, ["odom", bag, "--robot", str(robot), "--open-loop"])
    assert result.exit_code == 0, result.output
    assert "feedback    open loop" in result.stdout
    assert "topic /cmd_vel" in result.stdout


def test_open_loop_of_a_csv_writes_the_poses(runner: CliRunner, tmp_path: Path) -> None:
    path = tmp_path / "cmd.csv"
    path.write_text("t,v,w\n0,0.5,0\n2,0,0\n")
    out = tmp_path / "poses.csv"
    result = runner.invoke(main, ["odom", str(path), "--open-loop", "-o", str(out)])
    assert result.exit_code == 0, result.output
    assert "final pose  x 1 m, y 0 m" in result.stdout
    last = out.read_text().splitlines()[-1].split(",")
    assert float(last[1]) == pytest.approx(1.0, abs=1e-12)


@pytest.mark.parametrize("json_lines", [False, True])
def test_open_loop_commands_beyond_the_wheels_name_no_encoder_option(
    runner: CliRunner, tmp_path: Path, json_lines: bool
) -> None:
    # 1 m/s asks the bundled robot's wheels for 28.6 rad/s, over 4 times its 5.24 rad/s: the
    # pose is flagged, but the encoder options the warning named are refused with --open-loop.
    path = tmp_path / "cmd.csv"
    path.write_text("t,v,w\n0,1,0\n1,0,0\n")
    args = ["odom", str(path), "--open-loop"]
    # two inputs take the per-row path, which warns as well
    args += [str(path), "--json"] if json_lines else []
    result = runner.invoke(main, args)
    assert result.exit_code == 1, result.output
    warnings = [line for line in result.stderr.splitlines() if "implausible step (" in line]
    assert len(warnings) == (2 if json_lines else 1)
    for line in warnings:
        assert "--counts-per-rev" not in line
        assert "--wrap" not in line
        assert line.endswith("the pose is not to be trusted (commands the wheels cannot follow)")


@pytest.mark.parametrize(
    ("args", "fragments"),
    [
        (["--topic", "/joint_states"], ("carries sensor_msgs/msg/JointState, not", "--topic")),
        (["--feedback", "velocity"], ("--open-loop", "--feedback")),
        (["--wrap", "4096"], ("--open-loop", "--wrap")),
    ],
)
def test_open_loop_bad_input_is_one_error(
    runner: CliRunner, tmp_path: Path, robot: Path, args: list[str], fragments: tuple[str, ...]
) -> None:
    bag = str(velocity_bag(tmp_path, odom=True))
    result = runner.invoke(main, ["odom", bag, "--robot", str(robot), "--open-loop", *args])
    assert_one_error_line(result, *fragments)


def test_open_loop_csv_with_a_non_numeric_command_is_one_error(
    runner: CliRunner, tmp_path: Path
) -> None:
    path = tmp_path / "cmd.csv"
    path.write_text("t,v,w\n0,0.5,left\n2,0,0\n")
    result = runner.invoke(main, ["odom", str(path), "--open-loop"])
    assert_one_error_line(result, "not a number")


def test_bad_feedback_value_is_one_error(runner: CliRunner, tmp_path: Path) -> None:
    bag = write_bag(tmp_path / "b", [(S, S, NAMES, [0.0, 0.0])])
    result = runner.invoke(main, ["odom", str(bag), "--feedback", "effort"])
    assert_one_error_line(result, "--feedback")


def test_velocity_feedback_reads_a_csv_on_stdin(runner: CliRunner, robot: Path) -> None:
    text = "t,/js/left_wheel_joint/velocity,/js/right_wheel_joint/velocity\n0,0,0\n2,1,1\n"
    result = runner.invoke(
        main, ["odom", "-", "--robot", str(robot), "--feedback", "velocity", "--json"], input=text
    )
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert data["feedback"] == "velocity"
    assert final(data) == pytest.approx((0.1, 0.0, 0.0), abs=1e-12)


def test_open_loop_names_the_command_topic_it_chose(runner: CliRunner, tmp_path: Path) -> None:
    commands = [(S, twist_message(0.2, 0.0)), (2 * S, twist_message(0.0, 0.0))]
    topics = {"/diff_cont/cmd_vel_unstamped": ("geometry_msgs/msg/Twist", commands)}
    bag = write_topics(tmp_path / "bag", topics)
    result = runner.invoke(main, ["odom", str(bag), "--open-loop"])
    assert result.exit_code == 0, result.output
    assert "topic /diff_cont/cmd_vel_unstamped (its only command topic)" in result.stdout


def test_velocity_columns_named_by_the_bundled_robots_joints_need_no_robot(
    runner: CliRunner, tmp_path: Path
) -> None:
    left, right = "/js/front_left_wheel_joint/velocity", "/js/front_right_wheel_joint/velocity"
    path = tmp_path / "v.csv"
    speed = 0.1 / 0.035  # the bundled robot's wheels at 0.1 m/s, within its motor limit
    path.write_text(f"t,{left},{right}\n0,0,0\n1,{speed!r},{speed!r}\n")
    args = ["--feedback", "velocity", "--left-column", left, "--right-column", right]
    data = odom_json(runner, str(path), *args)
    assert final(data) == pytest.approx((0.1, 0.0, 0.0), abs=1e-12)


def test_wheel_velocities_in_counts_are_bounded_once_converted(
    runner: CliRunner, tmp_path: Path
) -> None:
    # 0.1 rev/s, 0.5 rev/s for 10 s (20480 counts/s: 3.14 rad/s), 0.1 rev/s, on the bundled
    # robot's 35 mm wheels.
    rows = ["time,/a/front_left_wheel_joint/velocity,/a/front_right_wheel_joint/velocity"]
    rows += [f"{k},{v},{v}" for k, v in ((k, 20480 if 10 < k <= 20 else 4096) for k in range(31))]
    path = tmp_path / "counts.csv"
    path.write_text("\n".join(rows) + "\n")
    data = odom_json(runner, str(path), "--feedback", "velocity", "--counts-per-rev", "40960")
    assert data["skipped"] == {}
    assert data["distance"] == pytest.approx(1.5393804, abs=1e-7)
