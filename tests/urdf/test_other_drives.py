"""Robots that are not differential drives: steered wheels named with the controller the
description drives them with, and descriptions driven only by another drive's controller or
plugin."""

from __future__ import annotations

from pathlib import Path

import pytest

import diffbot

TWO_WHEELS = """<?xml version="1.0"?>
<robot name="rover">
  <link name="base_link"/>
  <joint name="left_wheel_joint" type="continuous"><parent link="base_link"/>
    <child link="left_wheel"/><origin xyz="0 0.18 0"/><axis xyz="0 1 0"/></joint>
  <link name="left_wheel"><collision><origin rpy="1.5707963267948966 0 0"/>
    <geometry><cylinder radius="0.05" length="0.03"/></geometry></collision></link>
  <joint name="right_wheel_joint" type="continuous"><parent link="base_link"/>
    <child link="right_wheel"/><origin xyz="0 -0.18 0"/><axis xyz="0 1 0"/></joint>
  <link name="right_wheel"><collision><origin rpy="1.5707963267948966 0 0"/>
    <geometry><cylinder radius="0.05" length="0.03"/></geometry></collision></link>
  BODY
</robot>
"""

CONTROL_PLUGIN = """<gazebo>
    <plugin filename="gz_ros2_control-system" name="gz_ros2_control::GazeboSimROS2ControlPlugin">
      <parameters>controllers.yaml</parameters>
    </plugin>
  </gazebo>"""

GZ_PLUGIN = """<gazebo>
    <plugin filename="gz-sim-diff-drive-system" name="gz::sim::systems::DiffDrive">
      <left_joint>left_wheel_joint</left_joint><right_joint>right_wheel_joint</right_joint>
      <wheel_separation>0.36</wheel_separation><wheel_radius>0.05</wheel_radius>
    </plugin>
  </gazebo>"""


def workspace(tmp_path: Path, body: str, controllers: str | None) -> Path:
    """A robot, with ``controllers`` as the file its ros2_control plugin names when given."""
    tmp_path.mkdir(parents=True, exist_ok=True)
    if controllers is not None:
        (tmp_path / "controllers.yaml").write_text(controllers, encoding="utf-8")
        body += CONTROL_PLUGIN
    robot = tmp_path / "robot.urdf"
    robot.write_text(TWO_WHEELS.replace("BODY", body), encoding="utf-8")
    return robot


def load(robot: Path, **options: object) -> diffbot.DiffDriveParams:
    return diffbot.load_params(robot, **options)  # type: ignore[arg-type]


KNUCKLES = """
  <joint name="steer_joint" type="revolute"><parent link="base_link"/><child link="knuckle"/>
    <origin xyz="0.3 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-0.5" upper="0.5" effort="1" velocity="1"/></joint>
  <link name="knuckle"/>
  <joint name="front_wheel_joint" type="continuous"><parent link="knuckle"/>
    <child link="front_wheel"/><axis xyz="0 1 0"/></joint>
  <link name="front_wheel"/>
"""

ACKERMANN_PLUGIN = """<gazebo>
    <plugin filename="gz-sim-ackermann-steering-system" name="gz::sim::systems::AckermannSteering">
      <left_joint>left_wheel_joint</left_joint><right_joint>right_wheel_joint</right_joint>
    </plugin>
  </gazebo>"""

TRICYCLE = """controller_manager:
  ros__parameters:
    tricycle:
      type: tricycle_controller/TricycleController
"""


def test_a_steered_robot_names_its_steering_joints_and_the_controller_it_needs(
    tmp_path: Path,
) -> None:
    robot = workspace(tmp_path, KNUCKLES, controllers=None)
    with pytest.raises(diffbot.NotDifferentialError) as raised:
        load(robot)
    message = str(raised.value)
    assert "a steered robot, not a differential drive" in message
    assert "['steer_joint']" in message
    assert "ackermann_steering_controller" in message  # what it needs: none is named
    assert "\n" not in message


def test_the_steering_controller_or_plugin_of_the_description_is_named(tmp_path: Path) -> None:
    robot = workspace(tmp_path, KNUCKLES, controllers=TRICYCLE)
    with pytest.raises(
        diffbot.NotDifferentialError,
        match=r"\['steer_joint'\].*'tricycle' \(tricycle_controller/TricycleController in ",
    ):
        load(robot)
    planted = workspace(tmp_path / "plugin", KNUCKLES + ACKERMANN_PLUGIN, controllers=None)
    with pytest.raises(
        diffbot.NotDifferentialError,
        match=r"\['steer_joint'\].*the plugin gz::sim::systems::AckermannSteering$",
    ):
        load(planted)


def test_a_steering_plugin_alone_says_the_robot_is_not_differential(tmp_path: Path) -> None:
    # The joints look like a differential drive's, but the simulator steers the robot.
    robot = workspace(tmp_path, ACKERMANN_PLUGIN, controllers=None)
    with pytest.raises(
        diffbot.NotDifferentialError,
        match=r"not a differential drive: the description drives it with the plugin "
        r"gz::sim::systems::AckermannSteering, and with no diff-drive controller or plugin$",
    ):
        load(robot)
    # A diff-drive plugin beside it is what the robot runs with in simulation.
    both = workspace(tmp_path / "both", ACKERMANN_PLUGIN + GZ_PLUGIN, controllers=None)
    assert load(both).sources["wheel_separation"] == "plugin"


MECANUM = """controller_manager:
  ros__parameters:
    joint_state_broadcaster: {type: joint_state_broadcaster/JointStateBroadcaster}
    mecanum: {type: mecanum_drive_controller/MecanumDriveController}
"""


def test_a_robot_driven_by_a_mecanum_controller_is_refused_unless_controllers_are_not_read(
    tmp_path: Path,
) -> None:
    robot = workspace(tmp_path, "", controllers=MECANUM)
    with pytest.raises(diffbot.NotDifferentialError) as raised:
        load(robot)
    message = str(raised.value)
    assert (
        "the controller 'mecanum' (mecanum_drive_controller/MecanumDriveController in " in message
    )
    assert "joint_state_broadcaster" not in message
    assert message.endswith("read no controllers file (no_controllers=True)")
    params = load(robot, no_controllers=True)
    assert params.wheel_separation == pytest.approx(0.36, abs=1e-12)


def test_a_diff_drive_controller_beside_other_drives_is_the_robots(tmp_path: Path) -> None:
    both = (
        MECANUM
        + """    diff: {type: diff_drive_controller/DiffDriveController}
diff:
  ros__parameters:
    left_wheel_names: [left_wheel_joint]
    right_wheel_names: [right_wheel_joint]
    wheel_separation: 0.4
    wheel_radius: 0.05
"""
    )
    params = load(workspace(tmp_path, "", controllers=both))
    assert params.wheel_separation == pytest.approx(0.4, abs=1e-12)
    assert params.sources["wheel_separation"].startswith("controllers:")
