"""Robots as they ship: workspaces shaped like public robots' repositories (their packages,
macros, ``$(find)``, ``$(optenv)``, controllers files in their dialect), with their real
numbers, used the way a new user would, from another current folder."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner

import diffbot
from diffbot.cli import main

XACRO_NS = 'xmlns:xacro="http://ros.org/wiki/xacro"'


def package(folder: Path, name: str) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "package.xml").write_text(
        f'<?xml version="1.0"?>\n<package format="2"><name>{name}</name>'
        "<version>0.4.0</version></package>\n",
        encoding="utf-8",
    )
    return folder


def write(path: Path, text: str) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    return path


# --- Husky (ROS 1) ---------------------------------------------------------------------------
# Shaped like husky/husky (noetic-devel): husky_description/urdf/husky.urdf.xacro with its
# wheel macro (wheel.urdf.xacro, a block argument for the joint pose), `$(optenv)` defaults,
# an extras file included through an argument, a laser behind a false `xacro:if` that needs a
# package the workspace does not hold; husky_control/config/control.yaml, the ROS 1 controller
# with no separation nor radius and a wheel_separation_multiplier of 1.875. The numbers: track
# 0.5708 m, wheel radius 0.1651 m, so ros_controllers runs with 0.5708 * 1.875 = 1.07025 m.

HUSKY_WHEEL = f"""<?xml version="1.0"?>
<robot {XACRO_NS} name="husky_wheel">
  <xacro:macro name="husky_wheel" params="wheel_prefix *joint_pose">
    <link name="${{wheel_prefix}}_wheel_link">
      <collision>
        <origin xyz="0 0 0" rpy="${{M_PI/2}} 0 0" />
        <geometry><cylinder length="${{wheel_length}}" radius="${{wheel_radius}}" /></geometry>
      </collision>
    </link>
    <joint name="${{wheel_prefix}}_wheel" type="continuous">
      <parent link="base_link"/>
      <child link="${{wheel_prefix}}_wheel_link"/>
      <xacro:insert_block name="joint_pose"/>
      <axis xyz="0 1 0" rpy="0 0 0" />
    </joint>
  </xacro:macro>
</robot>
"""

HUSKY = f"""<?xml version="1.0"?>
<robot name="husky" {XACRO_NS}>
  <xacro:arg name="laser_enabled" default="$(optenv HUSKY_LMS1XX_ENABLED false)" />
  <xacro:arg name="urdf_extras" default="$(optenv HUSKY_URDF_EXTRAS empty.urdf)" />
  <xacro:property name="M_PI" value="3.14159"/>
  <xacro:property name="wheelbase" value="0.5120" />
  <xacro:property name="track" value="0.5708" />
  <xacro:property name="wheel_vertical_offset" value="0.03282" />
  <xacro:property name="wheel_length" value="0.1143" />
  <xacro:property name="wheel_radius" value="0.1651" />
  <xacro:include filename="$(find husky_description)/urdf/wheel.urdf.xacro" />
  <link name="base_link">
    <collision><origin xyz="0 0 0.061875" rpy="0 0 0" />
      <geometry><box size="0.9874 0.5709 0.12375"/></geometry></collision>
  </link>
  <link name="base_footprint"/>
  <joint name="base_footprint_joint" type="fixed">
    <origin xyz="0 0 ${{wheel_vertical_offset - wheel_radius}}" rpy="0 0 0" />
    <parent link="base_link" /><child link="base_footprint" />
  </joint>
  <link name="imu_link"/>
  <joint name="imu_joint" type="fixed">
    <origin xyz="$(optenv HUSKY_IMU_XYZ 0.19 0 0.149)"
            rpy="$(optenv HUSKY_IMU_RPY 0 -1.5708 3.1416)" />
    <parent link="base_link" /><child link="imu_link" />
  </joint>
  <xacro:husky_wheel wheel_prefix="front_left">
    <origin xyz="${{wheelbase/2}} ${{track/2}} ${{wheel_vertical_offset}}" rpy="0 0 0" />
  </xacro:husky_wheel>
  <xacro:husky_wheel wheel_prefix="front_right">
    <origin xyz="${{wheelbase/2}} ${{-track/2}} ${{wheel_vertical_offset}}" rpy="0 0 0" />
  </xacro:husky_wheel>
  <xacro:husky_wheel wheel_prefix="rear_left">
    <origin xyz="${{-wheelbase/2}} ${{track/2}} ${{wheel_vertical_offset}}" rpy="0 0 0" />
  </xacro:husky_wheel>
  <xacro:husky_wheel wheel_prefix="rear_right">
    <origin xyz="${{-wheelbase/2}} ${{-track/2}} ${{wheel_vertical_offset}}" rpy="0 0 0" />
  </xacro:husky_wheel>
  <xacro:if value="$(arg laser_enabled)">
    <xacro:include filename="$(find lms1xx)/urdf/sick_lms1xx.urdf.xacro" />
  </xacro:if>
  <gazebo>
    <plugin name="gazebo_ros_control" filename="libgazebo_ros_control.so">
      <robotNamespace>/</robotNamespace>
    </plugin>
  </gazebo>
  <xacro:include filename="$(arg urdf_extras)" />
</robot>
"""

HUSKY_CONTROL = """husky_joint_publisher:
  type: "joint_state_controller/JointStateController"
  publish_rate: 50

husky_velocity_controller:
  type: "diff_drive_controller/DiffDriveController"
  left_wheel: ['front_left_wheel', 'rear_left_wheel']
  right_wheel: ['front_right_wheel', 'rear_right_wheel']
  publish_rate: 50
  cmd_vel_timeout: 0.25
  base_frame_id: base_link
  enable_odom_tf: false
  # Wheel separation and radius multipliers
  wheel_separation_multiplier: 1.875 # default: 1.0
  wheel_radius_multiplier    : 1.0 # default: 1.0
  linear:
    x:
      has_velocity_limits    : true
      max_velocity           : 1.0   # m/s
"""


def husky(tmp_path: Path) -> tuple[Path, Path]:
    src = tmp_path / "catkin_ws" / "src" / "husky"
    (src / ".git").mkdir(parents=True)
    description = package(src / "husky_description", "husky_description")
    write(description / "urdf" / "wheel.urdf.xacro", HUSKY_WHEEL)
    write(description / "urdf" / "empty.urdf", '<?xml version="1.0"?>\n<robot name="empty"/>\n')
    robot = write(description / "urdf" / "husky.urdf.xacro", HUSKY)
    control = package(src / "husky_control", "husky_control")
    return robot, write(control / "config" / "control.yaml", HUSKY_CONTROL)


def test_husky_ros1_runs_with_its_track_times_the_multiplier(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    robot, control = husky(tmp_path)
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    monkeypatch.delenv("HUSKY_URDF_EXTRAS", raising=False)
    monkeypatch.delenv("HUSKY_LMS1XX_ENABLED", raising=False)
    runner = CliRunner()
    plain = runner.invoke(main, ["params", str(robot), "--json"])
    assert plain.exit_code == 0, plain.output
    geometry = json.loads(plain.stdout)
    assert geometry["wheel_separation"] == pytest.approx(0.5708, abs=1e-12)
    assert geometry["wheel_radius"] == pytest.approx(0.1651, abs=1e-12)
    assert geometry["left_joints"] == ["front_left_wheel", "rear_left_wheel"]
    controlled = runner.invoke(
        main, ["params", "--robot", str(robot), "--controllers", str(control), "--json"]
    )
    assert controlled.exit_code == 0, controlled.output
    values = json.loads(controlled.stdout)
    assert values["wheel_separation"] == pytest.approx(0.5708 * 1.875, abs=1e-12)
    assert values["wheel_radius"] == pytest.approx(0.1651, abs=1e-12)
    assert values["sources"]["wheel_separation"] == f"controllers:{control}"
    # the multiplier is the controller's deliberate skid-steer setting: check agrees
    check = runner.invoke(main, ["check", str(robot), "--controllers", str(control)])
    assert check.exit_code == 0, check.output
    assert "wheel_separation_multiplier 1.875" in check.stdout
    # turning in place at 1 rad/s: each side at 1.07025 / 2 m from the centre
    ik = runner.invoke(main, ["ik", "0", "1", "--robot", str(robot), "--controllers", str(control)])
    assert ik.exit_code == 0, ik.output
    assert f"{0.5708 * 1.875 / 2 / 0.1651:.5f}" in ik.stdout


def test_husky_with_its_laser_names_the_package_it_lacks(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    robot, _ = husky(tmp_path)
    monkeypatch.delenv("HUSKY_URDF_EXTRAS", raising=False)
    monkeypatch.setenv("HUSKY_LMS1XX_ENABLED", "true")
    result = CliRunner().invoke(main, ["params", str(robot)])
    assert result.exit_code == 2
    assert "package 'lms1xx' not found (needed by husky.urdf.xacro)" in result.stderr


# --- ros2_control_demos example_2 ------------------------------------------------------------
# Shaped like ros-controls/ros2_control_demos: example_2/description/urdf/diffbot.urdf.xacro
# including, from the sibling package ros2_control_demo_description, the diffbot macro
# (diffbot/urdf/diffbot_description.urdf.xacro: base 0.1 m wide, wheels of radius 0.015 m,
# joints at y = -/+ base_width/2) and its own ros2_control macro; the controllers file
# example_2/bringup/config/diffbot_controllers.yaml (wheel_separation 0.10, wheel_radius
# 0.015). The macro puts 'left_wheel_joint' at y = -0.05 m, on the right (REP-103), while the
# controller drives it as its left wheel: the sources disagree on the joints.

DEMO_ROBOT = f"""<?xml version="1.0"?>
<robot {XACRO_NS} name="diffdrive_robot">
  <xacro:arg name="prefix" default="" />
  <xacro:include
    filename="$(find ros2_control_demo_description)/diffbot/urdf/diffbot_description.urdf.xacro" />
  <xacro:include
    filename="$(find ros2_control_demo_example_2)/ros2_control/diffbot.ros2_control.xacro" />
  <xacro:diffbot prefix="$(arg prefix)" />
  <xacro:diffbot_ros2_control name="DiffBot" prefix="$(arg prefix)" />
</robot>
"""

DEMO_MACRO = f"""<?xml version="1.0"?>
<robot {XACRO_NS}>
  <xacro:macro name="diffbot" params="prefix">
  <xacro:property name="PI" value="3.1415926535897931"/>
  <xacro:property name="base_width" value="0.1" />
  <xacro:property name="base_height" value="0.05" />
  <xacro:property name="wheel_len" value="0.020" />
  <xacro:property name="wheel_radius" value="0.015" />
  <xacro:property name="z_offset" value="-${{base_height/2}}" />
  <link name="${{prefix}}base_link">
    <collision><geometry><box size="0.1 0.1 ${{base_height}}"/></geometry></collision>
  </link>
  <joint name="${{prefix}}left_wheel_joint" type="continuous">
    <parent link="${{prefix}}base_link"/><child link="${{prefix}}left_wheel"/>
    <origin xyz="0 -${{base_width/2}} ${{z_offset}}" rpy="0 0 0"/><axis xyz="0 1 0"/>
    <limit effort="100" velocity="60.0"/>
  </joint>
  <link name="${{prefix}}left_wheel">
    <collision><origin xyz="0 0 0" rpy="${{PI/2}} 0 0"/>
      <geometry><cylinder length="${{wheel_len}}" radius="${{wheel_radius}}"/></geometry>
    </collision>
  </link>
  <joint name="${{prefix}}right_wheel_joint" type="continuous">
    <parent link="${{prefix}}base_link"/><child link="${{prefix}}right_wheel"/>
    <origin xyz="0 ${{base_width/2}} ${{z_offset}}" rpy="0 0 0"/><axis xyz="0 1 0"/>
    <limit effort="100" velocity="60.0"/>
  </joint>
  <link name="${{prefix}}right_wheel">
    <collision><origin xyz="0 0 0" rpy="${{PI/2}} 0 0"/>
      <geometry><cylinder length="${{wheel_len}}" radius="${{wheel_radius}}"/></geometry>
    </collision>
  </link>
  </xacro:macro>
</robot>
"""

DEMO_ROS2_CONTROL = f"""<?xml version="1.0"?>
<robot {XACRO_NS}>
  <xacro:macro name="diffbot_ros2_control" params="name prefix">
    <ros2_control name="${{name}}" type="system">
      <hardware><plugin>ros2_control_demo_example_2/DiffBotSystemHardware</plugin></hardware>
      <joint name="${{prefix}}left_wheel_joint"><command_interface name="velocity"/></joint>
      <joint name="${{prefix}}right_wheel_joint"><command_interface name="velocity"/></joint>
    </ros2_control>
  </xacro:macro>
</robot>
"""

DEMO_CONTROLLERS = """controller_manager:
  ros__parameters:
    update_rate: 10  # Hz
    joint_state_broadcaster:
      type: joint_state_broadcaster/JointStateBroadcaster
    diffbot_base_controller:
      type: diff_drive_controller/DiffDriveController

diffbot_base_controller:
  ros__parameters:
    left_wheel_names: ["left_wheel_joint"]
    right_wheel_names: ["right_wheel_joint"]
    wheel_separation: 0.10
    #wheels_per_side: 1  # actually 2, but both are controlled by 1 signal
    wheel_radius: 0.015
    wheel_separation_multiplier: 1.0
    left_wheel_radius_multiplier: 1.0
    right_wheel_radius_multiplier: 1.0
    publish_rate: 50.0
    linear.x.max_velocity: 1.0
"""


def demos(tmp_path: Path) -> tuple[Path, Path]:
    src = tmp_path / "ros2_control_demos"
    (src / ".git").mkdir(parents=True)
    shared = package(src / "ros2_control_demo_description", "ros2_control_demo_description")
    write(shared / "diffbot" / "urdf" / "diffbot_description.urdf.xacro", DEMO_MACRO)
    example = package(src / "example_2", "ros2_control_demo_example_2")
    write(example / "ros2_control" / "diffbot.ros2_control.xacro", DEMO_ROS2_CONTROL)
    robot = write(example / "description" / "urdf" / "diffbot.urdf.xacro", DEMO_ROBOT)
    return robot, write(
        example / "bringup" / "config" / "diffbot_controllers.yaml", DEMO_CONTROLLERS
    )


def test_example_2_finds_both_packages_and_its_controller_numbers(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    robot, controllers = demos(tmp_path)
    monkeypatch.chdir(tmp_path)
    params = diffbot.load_params(robot, controllers=controllers)
    assert (params.wheel_separation, params.wheel_radius) == (0.10, 0.015)
    assert params.max_wheel_speed == 60.0
    # the geometry decides the sides: 'right_wheel_joint' is the one at +y
    assert (params.left_joint, params.right_joint) == ("right_wheel_joint", "left_wheel_joint")
    assert any("named left but sits on the right side" in w for w in params.warnings)


def test_example_2s_mirrored_joints_fail_check(tmp_path: Path) -> None:
    robot, controllers = demos(tmp_path)
    result = CliRunner().invoke(
        main, ["check", str(robot), "--controllers", str(controllers), "--json"]
    )
    assert result.exit_code == 1, result.output
    report = json.loads(result.stdout)
    assert {d["field"] for d in report["disagreements"]} == {"left_joints", "right_joints"}
    assert report["controller"] == "diffbot_base_controller"


# --- Husky in Gazebo classic with the skid-steer plugin ----------------------------------------
# A common way Husky users simulate it (the plugin of gazebo_ros_pkgs,
# gazebo_plugins/src/gazebo_ros_skid_steer_drive.cpp, in place of gazebo_ros_control): four
# joints, wheelSeparation 0.5708 and wheelDiameter 0.3302. The plugin drives each side's two
# wheels alike at (v -/+ w * wheelSeparation / 2) / (wheelDiameter / 2): a diff drive.

SKID_STEER = """  <gazebo>
    <plugin name="skid_steer_drive_controller" filename="libgazebo_ros_skid_steer_drive.so">
      <updateRate>100.0</updateRate>
      <leftFrontJoint>front_left_wheel</leftFrontJoint>
      <leftRearJoint>rear_left_wheel</leftRearJoint>
      <rightFrontJoint>front_right_wheel</rightFrontJoint>
      <rightRearJoint>rear_right_wheel</rightRearJoint>
      <wheelSeparation>{separation}</wheelSeparation>
      <wheelDiameter>0.3302</wheelDiameter>
      <robotBaseFrame>base_link</robotBaseFrame>
      <torque>35</torque>
      <broadcastTF>true</broadcastTF>
    </plugin>
  </gazebo>
"""


def skid_steered_husky(tmp_path: Path, separation: str) -> Path:
    robot, _ = husky(tmp_path)
    text = robot.read_text(encoding="utf-8").replace(
        '  <xacro:include filename="$(arg urdf_extras)" />',
        SKID_STEER.format(separation=separation),
    )
    robot.write_text(text, encoding="utf-8")
    return robot


def test_the_skid_steer_plugin_is_the_simulated_husky_s_controller(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.delenv("HUSKY_LMS1XX_ENABLED", raising=False)
    robot = skid_steered_husky(tmp_path, "0.5708")
    params = diffbot.load_params(robot, source="plugin")
    assert params.wheel_separation == pytest.approx(0.5708, abs=1e-12)
    assert params.wheel_radius == pytest.approx(0.1651, abs=1e-12)
    assert params.left_joints == ("front_left_wheel", "rear_left_wheel")
    assert params.right_joints == ("front_right_wheel", "rear_right_wheel")
    assert params.sources["wheel_separation"] == "plugin"
    assert diffbot.load_params(robot).sources["wheel_radius"] == "plugin"


def test_a_skid_steer_plugin_widened_for_the_slip_is_what_the_simulation_runs(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.delenv("HUSKY_LMS1XX_ENABLED", raising=False)
    robot = skid_steered_husky(tmp_path, "1.07025")
    ik = CliRunner().invoke(main, ["ik", "0", "1", "--robot", str(robot)])
    assert ik.exit_code == 0, ik.output
    assert f"{1.07025 / 2 / 0.1651:.5f}" in ik.stdout
    check = CliRunner().invoke(main, ["check", str(robot), "--json"])
    assert check.exit_code == 1, check.output
    (found,) = json.loads(check.stdout)["disagreements"]
    assert found["field"] == "wheel_separation"
    assert found["difference"] == pytest.approx(1.07025 - 0.5708, abs=1e-9)


def test_ik_and_fk_take_the_robot_first_like_every_command(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.delenv("HUSKY_LMS1XX_ENABLED", raising=False)
    robot = skid_steered_husky(tmp_path, "0.5708")
    runner = CliRunner()
    first = runner.invoke(main, ["ik", str(robot), "0", "-1"])
    assert first.exit_code == 0, first.output
    assert first.stdout == runner.invoke(main, ["ik", "0", "-1", "--robot", str(robot)]).stdout
    assert f"{-0.5708 / 2 / 0.1651:.5f}" in first.stdout.replace(" ", "")
    fk = runner.invoke(main, ["fk", str(robot), "1", "1", "--json"])
    assert fk.exit_code == 0, fk.output
    assert json.loads(fk.stdout)["linear"] == pytest.approx(0.1651, abs=1e-9)
    both = runner.invoke(main, ["ik", str(robot), "0", "1", "--robot", str(robot) + "x"])
    assert both.exit_code == 2
    assert "two robots given" in both.stderr


# --- linorobot2 2wd ------------------------------------------------------------------------------
# Shaped like linorobot/linorobot2: linorobot2_description/urdf/robots/2wd.urdf.xacro including
# its properties file (2wd_properties.urdf.xacro: wheel_radius 0.045, wheel_pos_y 0.1, a laser
# pose as a block property), the wheel macro (mech/wheel.urdf.xacro, `${pi/2}`) and the gz-sim
# DiffDrive macro (controllers/diff_drive.urdf.xacro) given wheel_separation="${wheel_pos_y * 2}":
# the simulation runs with 0.2 m and 0.045 m.

LINO_ROBOT = f"""<?xml version="1.0"?>
<robot name="linorobot2_2wd" {XACRO_NS}>
  <xacro:include filename="$(find linorobot2_description)/urdf/2wd_properties.urdf.xacro" />
  <xacro:include filename="$(find linorobot2_description)/urdf/mech/wheel.urdf.xacro" />
  <xacro:include filename="$(find linorobot2_description)/urdf/controllers/diff_drive.urdf.xacro" />
  <link name="base_footprint"/>
  <link name="base_link"><collision><geometry>
    <box size="${{base_length}} ${{base_width}} 0.003"/></geometry></collision></link>
  <joint name="base_joint" type="fixed"><parent link="base_footprint"/><child link="base_link"/>
    <origin xyz="0 0 ${{wheel_radius - wheel_pos_z}}" rpy="0 0 0"/></joint>
  <xacro:wheel side="left" radius="${{wheel_radius}}" width="${{wheel_width}}"
    pos_x="${{wheel_pos_x}}" pos_y="${{wheel_pos_y}}" pos_z="${{wheel_pos_z}}"/>
  <xacro:wheel side="right" radius="${{wheel_radius}}" width="${{wheel_width}}"
    pos_x="${{wheel_pos_x}}" pos_y="${{-wheel_pos_y}}" pos_z="${{wheel_pos_z}}"/>
  <link name="laser"/>
  <joint name="laser_to_base_link" type="fixed">
    <parent link="base_link"/><child link="laser"/><xacro:insert_block name="laser_pose" />
  </joint>
  <xacro:diff_drive_controller wheel_separation="${{wheel_pos_y * 2}}"
    wheel_radius="${{wheel_radius}}"/>
</robot>
"""

LINO_PROPERTIES = f"""<?xml version="1.0"?>
<robot {XACRO_NS}>
  <xacro:property name="base_length" value="0.17" />
  <xacro:property name="base_width" value="0.17" />
  <xacro:property name="wheel_radius" value="0.045" />
  <xacro:property name="wheel_width" value="0.01" />
  <xacro:property name="wheel_pos_x" value="-0.0415" />
  <xacro:property name="wheel_pos_y" value="0.1" />
  <xacro:property name="wheel_pos_z" value="0.023" />
  <xacro:property name="laser_pose">
    <origin xyz="0 0 0.1" rpy="0 0 0"/>
  </xacro:property>
</robot>
"""

LINO_WHEEL = f"""<?xml version="1.0"?>
<robot {XACRO_NS}>
  <xacro:macro name="wheel" params="side radius width pos_x pos_y pos_z">
    <link name="${{side}}_wheel_link">
      <collision><origin xyz="0 0 0" rpy="${{pi/2}} 0 0"/>
        <geometry><cylinder radius="${{radius}}" length="${{width}}"/></geometry></collision>
    </link>
    <joint name="${{side}}_wheel_joint" type="continuous">
      <axis xyz="0 1 0" />
      <parent link="base_link"/><child link="${{side}}_wheel_link"/>
      <origin xyz="${{pos_x}} ${{pos_y}} ${{pos_z}}" rpy="0 0 0"/>
    </joint>
  </xacro:macro>
</robot>
"""

LINO_DIFF_DRIVE = f"""<robot {XACRO_NS}>
  <xacro:macro name="diff_drive_controller" params="wheel_separation wheel_radius">
    <gazebo>
      <plugin filename="gz-sim-diff-drive-system" name="gz::sim::systems::DiffDrive">
        <topic>/cmd_vel</topic>
        <child_frame_id>base_footprint</child_frame_id>
        <max_linear_acceleration>1.0</max_linear_acceleration>
        <left_joint>left_wheel_joint</left_joint>
        <right_joint>right_wheel_joint</right_joint>
        <wheel_separation>${{wheel_separation}}</wheel_separation>
        <wheel_radius>${{wheel_radius}}</wheel_radius>
      </plugin>
    </gazebo>
  </xacro:macro>
</robot>
"""


def test_linorobot2_runs_with_its_plugin_numbers(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    src = tmp_path / "linorobot2"
    (src / ".git").mkdir(parents=True)
    package(src / "linorobot2_bringup", "linorobot2_bringup")
    urdf = package(src / "linorobot2_description", "linorobot2_description") / "urdf"
    write(urdf / "2wd_properties.urdf.xacro", LINO_PROPERTIES)
    write(urdf / "mech" / "wheel.urdf.xacro", LINO_WHEEL)
    write(urdf / "controllers" / "diff_drive.urdf.xacro", LINO_DIFF_DRIVE)
    robot = write(urdf / "robots" / "2wd.urdf.xacro", LINO_ROBOT)
    monkeypatch.chdir(src / "linorobot2_bringup")
    relative = "../linorobot2_description/urdf/robots/2wd.urdf.xacro"
    result = CliRunner().invoke(main, ["params", relative, "--json"])
    assert result.exit_code == 0, result.output
    values = json.loads(result.stdout)
    assert (values["wheel_separation"], values["wheel_radius"]) == (0.2, 0.045)
    assert values["sources"]["wheel_separation"] == "plugin"
    described = diffbot.load_params(robot, source="description")
    assert described.wheel_separation == pytest.approx(0.2, abs=1e-12)
    assert described.wheel_radius == pytest.approx(0.045, abs=1e-12)
    check = CliRunner().invoke(main, ["check", relative])
    assert check.exit_code == 0, check.output
