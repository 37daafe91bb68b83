"""The controller's own rules, as the robots run them: ROS 1's URDF look-ups and multipliers,
``$(arg)`` substitutions, deliberate multipliers in ``check``, mirrored wheels, chained and
non-differential controllers, ros2_control velocity limits, wheels of several cylinders."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest
from cli_results import assert_one_error_line
from click.testing import CliRunner

import diffbot
from diffbot.cli import main
from diffbot.kinematics import inverse
from diffbot.urdf.controllers import ControllerConfigError, read_controllers

XACRO_NS = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'


def wheel(name: str, xyz: str, radius: float = 0.098, parent: str = "chassis_link") -> str:
    return (
        f'<link name="{name}_link"><collision><origin rpy="1.5707963 0 0"/><geometry>'
        f'<cylinder radius="{radius}" length="0.04"/></geometry></collision></link>'
        f'<joint name="{name}" type="continuous"><parent link="{parent}"/>'
        f'<child link="{name}_link"/><origin xyz="{xyz}"/><axis xyz="0 1 0"/></joint>'
    )


#: Shaped like a Jackal: four wheels on a chassis, 0.37559 m between the sides' joints.
JACKAL = (
    '<?xml version="1.0"?>\n<robot name="jackal">'
    '<link name="base_link"/><link name="chassis_link"/>'
    '<joint name="chassis_joint" type="fixed"><parent link="base_link"/>'
    '<child link="chassis_link"/></joint>'
    + wheel("front_left_wheel", "0.131 0.187795 0.0345")
    + wheel("front_right_wheel", "0.131 -0.187795 0.0345")
    + wheel("rear_left_wheel", "-0.131 0.187795 0.0345")
    + wheel("rear_right_wheel", "-0.131 -0.187795 0.0345")
    + "</robot>\n"
)

#: A ROS 1 control.yaml as the Jackal's: no separation nor radius, a skid-steer correction.
JACKAL_ROS1 = """jackal_velocity_controller:
  type: "diff_drive_controller/DiffDriveController"
  left_wheel: ['front_left_wheel', 'rear_left_wheel']
  right_wheel: ['front_right_wheel', 'rear_right_wheel']
  publish_rate: 50
  wheel_separation_multiplier: 1.5
  cmd_vel_timeout: 0.25
  linear:
    x:
      has_velocity_limits: true
      max_velocity: 2.0
"""


def files(tmp_path: Path, robot: str, controllers: str | None = None) -> tuple[Path, Path]:
    path = tmp_path / "robot.urdf"
    path.write_text(robot, encoding="utf-8")
    yaml = tmp_path / "control.yaml"
    if controllers is not None:
        yaml.write_text(controllers, encoding="utf-8")
    return path, yaml


def test_ros1_takes_absent_values_from_the_urdf_then_applies_the_multiplier(
    tmp_path: Path,
) -> None:
    robot, yaml = files(tmp_path, JACKAL, JACKAL_ROS1)
    params = diffbot.load_params(robot, controllers=yaml)
    # ros_controllers: |front_left - front_right| joint origins = 0.37559 m, times 1.5
    assert params.wheel_separation == pytest.approx(0.563385, abs=1e-12)
    assert params.wheel_radius == pytest.approx(0.098, abs=1e-12)
    assert params.sources["wheel_separation"] == f"controllers:{yaml}"
    assert params.left_joints == ("front_left_wheel", "rear_left_wheel")
    assert params.disagreements == ()
    assert any("has no wheel_separation: taken from the URDF" in w for w in params.warnings)


def test_check_reports_a_deliberate_multiplier_as_a_setting_and_exits_0(tmp_path: Path) -> None:
    robot, yaml = files(tmp_path, JACKAL, JACKAL_ROS1)
    result = CliRunner().invoke(main, ["check", str(robot), "--controllers", str(yaml)])
    assert result.exit_code == 0, result.output
    assert "wheel_separation_multiplier 1.5" in result.stdout
    assert "all sources agree" in result.stdout
    data = json.loads(
        CliRunner().invoke(main, ["check", str(robot), "--controllers", str(yaml), "--json"]).stdout
    )
    assert data["agree"] is True
    assert data["multipliers"]["wheel_separation_multiplier"] == 1.5


def test_check_exits_1_when_the_base_values_disagree(tmp_path: Path) -> None:
    wrong = JACKAL_ROS1.replace("publish_rate: 50", "publish_rate: 50\n  wheel_separation: 0.42")
    robot, yaml = files(tmp_path, JACKAL, wrong)
    result = CliRunner().invoke(main, ["check", str(robot), "--controllers", str(yaml)])
    assert result.exit_code == 1, result.output
    assert "DISAGREE          wheel_separation:" in result.stdout


def test_ros1_common_radius_multiplier_wins_over_the_sides() -> None:
    text = JACKAL_ROS1 + "  wheel_radius_multiplier: 1.02\n  left_wheel_radius_multiplier: 0.9\n"
    (config,) = read_controllers(text, "c.yaml")
    assert config.left_wheel_radius_multiplier == config.right_wheel_radius_multiplier == 1.02


SUMMIT = f"""<?xml version="1.0"?>
<robot name="summit" {XACRO_NS}>
  <xacro:arg name="prefix" default="robot_"/>
  <xacro:property name="p" value="$(arg prefix)"/>
  <link name="${{p}}base_link"/>
  {wheel("${p}front_left_wheel_joint", "0.2225 0.2045 0", 0.117, "${p}base_link")}
  {wheel("${p}front_right_wheel_joint", "0.2225 -0.2045 0", 0.117, "${p}base_link")}
</robot>
"""

SUMMIT_ROS1 = """robotnik_base_control:
  type: diff_drive_controller/DiffDriveController
  left_wheel: ['$(arg prefix)front_left_wheel_joint']
  right_wheel: ['$(arg prefix)front_right_wheel_joint']
  wheel_separation: 0.409
  wheel_radius: 0.117
"""


def test_ros1_arg_substitutions_take_the_xacro_arguments(tmp_path: Path) -> None:
    robot = tmp_path / "summit.urdf.xacro"
    robot.write_text(SUMMIT, encoding="utf-8")
    yaml = tmp_path / "control.yaml"
    yaml.write_text(SUMMIT_ROS1, encoding="utf-8")
    params = diffbot.load_params(robot, {"prefix": "robot_"}, controllers=yaml)
    assert params.left_joints == ("robot_front_left_wheel_joint",)
    assert params.disagreements == ()


def test_an_arg_without_a_value_is_left_and_said() -> None:
    (config,) = read_controllers(SUMMIT_ROS1, "c.yaml", {})
    assert config.left_wheel_names == ("$(arg prefix)front_left_wheel_joint",)
    assert any("$(arg prefix) has no value: give it as prefix:=VALUE" in w for w in config.warnings)


TWO = (
    '<?xml version="1.0"?>\n<robot name="two"><link name="base_link"/>'
    + wheel("left_wheel_joint", "0 0.15 0", 0.05, "base_link")
    + wheel("right_wheel_joint", "0 -0.15 0", 0.05, "base_link")
    + "BODY</robot>\n"
)

MIRRORED = """controller_manager:
  ros__parameters:
    diff_cont: {type: diff_drive_controller/DiffDriveController}
diff_cont:
  ros__parameters:
    left_wheel_names: [left_wheel_joint]
    right_wheel_names: [right_wheel_joint]
    wheel_separation: 0.3
    wheel_radius: 0.05
    right_wheel_radius_multiplier: -1.0
"""


def test_a_negative_radius_multiplier_is_a_direction_flip(tmp_path: Path) -> None:
    robot, yaml = files(tmp_path, TWO.replace("BODY", ""), MIRRORED)
    plain = diffbot.load_params(robot, no_controllers=True)
    params = diffbot.load_params(robot, controllers=yaml)
    assert params.right_sign == -plain.right_sign
    assert params.radii == pytest.approx((0.05, 0.05), abs=1e-15)
    assert any("right_wheel_radius_multiplier is negative" in w for w in params.warnings)
    # the controller commands the right joint with the opposite sign for the same motion
    wheels = inverse(params, 0.2, 0.0)
    assert float(wheels.right) == pytest.approx(float(inverse(plain, 0.2, 0.0).right), abs=1e-12)


def test_a_zero_multiplier_is_still_refused() -> None:
    with pytest.raises(ControllerConfigError, match=r"a finite number other than 0"):
        read_controllers(MIRRORED.replace("-1.0", "0.0"), "c.yaml")


def test_no_controllers_ignores_the_file_the_description_names(tmp_path: Path) -> None:
    broken = tmp_path / "broken.yaml"
    broken.write_text(MIRRORED.replace("wheel_radius: 0.05", "wheel_radius: -1"), encoding="utf-8")
    plugin = (
        '<gazebo><plugin filename="gz_ros2_control-system" name="c">'
        f"<parameters>{broken}</parameters></plugin></gazebo>"
    )
    robot, _ = files(tmp_path, TWO.replace("BODY", plugin))
    refused = CliRunner().invoke(main, ["params", str(robot)])
    assert_one_error_line(refused, "wheel_radius must be a positive finite number")
    result = CliRunner().invoke(main, ["params", str(robot), "--no-controllers", "--json"])
    assert result.exit_code == 0, result.output
    assert json.loads(result.stdout)["wheel_separation"] == pytest.approx(0.3, abs=1e-12)
    both = CliRunner().invoke(
        main, ["params", str(robot), "--no-controllers", "--controllers", str(broken)]
    )
    assert_one_error_line(both, "--controllers and --no-controllers")


#: Shaped like ros2_control_demos' example 16: a PID controller chained before each wheel.
CHAINED = """controller_manager:
  ros__parameters:
    update_rate: 100
    pid_controller_left_wheel_joint: {type: pid_controller/PidController}
    pid_controller_right_wheel_joint: {type: pid_controller/PidController}
    diffbot_base_controller: {type: diff_drive_controller/DiffDriveController}
pid_controller_left_wheel_joint:
  ros__parameters:
    dof_names: [left_wheel_joint]
    command_interface: velocity
pid_controller_right_wheel_joint:
  ros__parameters:
    dof_names: [right_wheel_joint]
    command_interface: velocity
diffbot_base_controller:
  ros__parameters:
    left_wheel_names: ["pid_controller_left_wheel_joint/left_wheel_joint"]
    right_wheel_names: ["pid_controller_right_wheel_joint/right_wheel_joint"]
    wheel_separation: 0.30
    wheel_radius: 0.05
"""


def test_chained_controllers_are_followed_to_their_joints(tmp_path: Path) -> None:
    robot, yaml = files(tmp_path, TWO.replace("BODY", ""), CHAINED)
    params = diffbot.load_params(robot, controllers=yaml)
    assert params.left_joints == ("left_wheel_joint",)
    assert params.right_joints == ("right_wheel_joint",)
    assert params.disagreements == ()
    assert any("followed to joint 'left_wheel_joint'" in w for w in params.warnings)


def test_a_reference_to_another_joint_is_not_followed() -> None:
    text = CHAINED.replace("dof_names: [left_wheel_joint]", "dof_names: [elbow]")
    (config,) = read_controllers(text, "c.yaml")
    assert config.left_wheel_names == ("pid_controller_left_wheel_joint/left_wheel_joint",)


MECANUM = """controller_manager:
  ros__parameters:
    joint_state_broadcaster: {type: joint_state_broadcaster/JointStateBroadcaster}
    drive_controller: {type: mecanum_drive_controller/MecanumDriveController}
drive_controller:
  ros__parameters:
    front_left_wheel_command_joint_name: fl_wheel_joint
"""


def test_a_robot_driven_by_non_differential_controllers_is_refused_naming_them(
    tmp_path: Path,
) -> None:
    # Its four lateral wheels look like a skid steer's, but the robot runs a mecanum drive:
    # taken for a skid steer, its odometry would be wrong.
    robot, yaml = files(tmp_path, JACKAL)
    yaml.write_text(MECANUM, encoding="utf-8")
    plugin = (
        '<gazebo><plugin filename="gz_ros2_control-system" name="c">'
        f"<parameters>{yaml}</parameters></plugin></gazebo>"
    )
    robot.write_text(JACKAL.replace("</robot>", plugin + "</robot>"), encoding="utf-8")
    with pytest.raises(diffbot.NotDifferentialError) as raised:
        diffbot.load_params(robot)
    message = str(raised.value)
    assert "not a differential drive" in message
    assert "'drive_controller' (mecanum_drive_controller/MecanumDriveController" in message
    assert "joint_state_broadcaster" not in message
    assert "no_controllers=True" in message
    # Reading no controllers file is the way to take its wheels all the same.
    params = diffbot.load_params(robot, no_controllers=True)
    assert params.controller is None
    assert len(params.left_joints) == 2


def test_a_velocity_command_interface_max_is_the_motor_limit(tmp_path: Path) -> None:
    tags = "".join(
        f'<joint name="{side}_wheel_joint"><command_interface name="velocity">'
        '<param name="min">-25</param><param name="max">25</param></command_interface>'
        '<state_interface name="position"/></joint>'
        for side in ("left", "right")
    )
    body = f'<ros2_control name="warthog" type="system">{tags}</ros2_control>'
    robot, _ = files(tmp_path, TWO.replace("BODY", body))
    params = diffbot.load_params(robot)
    assert params.max_wheel_speed == 25.0
    assert params.sources["max_wheel_speed"] == "description"


@pytest.mark.parametrize(("joint", "interface"), [("1.7e307", None), ("1e6", None), (None, "1e5")])
def test_a_velocity_limit_faster_than_any_wheel_is_a_placeholder_not_a_limit(
    tmp_path: Path, joint: str | None, interface: str | None
) -> None:
    # Real descriptions write 1e6 for "no limit"; 1.7e307 rad/s left the plot no axis.
    text = TWO.replace("BODY", "")
    if joint is not None:
        limit = f'<axis xyz="0 1 0"/><limit velocity="{joint}" effort="1"/>'
        text = text.replace('<axis xyz="0 1 0"/>', limit)
    if interface is not None:
        tags = "".join(
            f'<joint name="{side}_wheel_joint"><command_interface name="velocity">'
            f'<param name="max">{interface}</param></command_interface></joint>'
            for side in ("left", "right")
        )
        text = TWO.replace("BODY", f'<ros2_control name="r" type="system">{tags}</ros2_control>')
    robot, _ = files(tmp_path, text)
    params = diffbot.load_params(robot)
    assert params.max_wheel_speed is None
    placeholders = [w for w in params.warnings if "taken for a placeholder" in w]
    value = f"{float(joint or interface or 0):g}"
    assert placeholders == [
        f"the {'velocity limit' if joint else 'ros2_control velocity command interface max'} "
        f"of joints 'left_wheel_joint', 'right_wheel_joint': {value} rad/s are faster than "
        "any wheel turns (over 10000 rad/s): taken for a placeholder, not a motor limit"
    ]
    # a limit a wheel can have is still the limit, beside a placeholder on the other wheel
    both = text.replace(f'velocity="{joint}"', 'velocity="30"', 1) if joint else None
    if both is not None:
        robot.write_text(both, encoding="utf-8")
        assert diffbot.load_params(robot).max_wheel_speed == 30.0


def test_the_lower_of_joint_limit_and_interface_max_is_taken(tmp_path: Path) -> None:
    limited = TWO.replace(
        '<axis xyz="0 1 0"/>', '<axis xyz="0 1 0"/><limit velocity="30" effort="1"/>'
    )
    body = (
        '<ros2_control name="r" type="system"><joint name="left_wheel_joint">'
        '<command_interface name="velocity"><param name="max">20</param></command_interface>'
        "</joint></ros2_control>"
    )
    robot, _ = files(tmp_path, limited.replace("BODY", body))
    params = diffbot.load_params(robot)
    assert params.max_wheel_speed == 20.0
    assert any(
        "allow 20 rad/s, less than the joints' velocity limit 30" in w for w in params.warnings
    )


#: Shaped like a Leo Rover wheel: a hub cylinder written before the tyre.
LEO_WHEEL = (
    '<link name="{side}_wheel"><collision><geometry><cylinder radius="0.057" length="0.07"/>'
    '</geometry><origin rpy="1.5707963 0 0"/></collision><collision><origin rpy="1.5707963 0 0"/>'
    '<geometry><cylinder radius="0.0625" length="0.03"/></geometry></collision></link>'
    '<joint name="{side}_wheel_joint" type="continuous"><parent link="base_link"/>'
    '<child link="{side}_wheel"/><origin xyz="0 {y} 0"/><axis xyz="0 1 0"/></joint>'
)


def test_a_wheel_of_several_cylinders_rolls_on_the_largest(tmp_path: Path) -> None:
    robot, _ = files(
        tmp_path,
        '<robot name="leo"><link name="base_link"/>'
        + LEO_WHEEL.format(side="left", y="0.1795")
        + LEO_WHEEL.format(side="right", y="-0.1795")
        + "</robot>",
    )
    params = diffbot.load_params(robot)
    assert params.wheel_radius == 0.0625
    notes = [w for w in params.warnings if "several collision cylinders" in w]
    assert len(notes) == 2
    assert "not 0.057 m" in notes[0]
    assert math.isclose(params.wheel_separation, 0.359, abs_tol=1e-12)


def test_an_argument_only_the_controllers_file_uses_is_not_called_ignored(tmp_path: Path) -> None:
    ros1 = """base_controller:
  type: diff_drive_controller/DiffDriveController
  left_wheel: '$(arg prefix)left_wheel_joint'
  right_wheel: '$(arg prefix)right_wheel_joint'
"""
    robot, yaml = files(tmp_path, TWO.replace("BODY", ""), ros1)
    params = diffbot.load_params(robot, {"prefix": "", "other": "1"}, controllers=yaml)
    assert params.left_joints == ("left_wheel_joint",)
    assert params.wheel_separation == pytest.approx(0.3, abs=1e-12)  # from the URDF
    ignored = [w for w in params.warnings if "ignored" in w]
    assert len(ignored) == 1
    assert "'other'" in ignored[0]


def test_a_ros1_file_of_other_drives_is_named_too(tmp_path: Path) -> None:
    robot, yaml = files(
        tmp_path,
        JACKAL,
        "base:\n  mobile_base_controller:\n    type: steer_drive_controller/SteerDriveController\n",
    )
    plugin = (
        '<gazebo><plugin filename="gazebo_ros2_control" name="c">'
        f"<parameters>{yaml}</parameters></plugin></gazebo>"
    )
    robot.write_text(JACKAL.replace("</robot>", plugin + "</robot>"), encoding="utf-8")
    with pytest.raises(
        diffbot.NotDifferentialError,
        match=r"'mobile_base_controller' \(steer_drive_controller/SteerDriveController",
    ):
        diffbot.load_params(robot)
