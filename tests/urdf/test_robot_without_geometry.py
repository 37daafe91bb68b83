"""Robots without a description's geometry: from options alone, from a controllers file when
the description has no links (a Webots robot), and from a bag's ``/robot_description``."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from bags import TYPESTORE
from cli_results import assert_one_error_line
from click.testing import CliRunner
from rosbags.rosbag2 import StoragePlugin, Writer
from rosbags.typesys.stores import ros2_humble as m

import diffbot
from diffbot.cli import main

OPTIONS = [
    "--left-joint",
    "wheel_l",
    "--right-joint",
    "wheel_r",
    "--wheel-radius",
    "0.04",
    "--wheel-separation",
    "0.25",
]


def test_a_robot_from_options_alone_loads_no_description() -> None:
    result = CliRunner().invoke(main, ["params", *OPTIONS, "--json"])
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert (data["left_joint"], data["right_joint"]) == ("wheel_l", "wheel_r")
    assert (data["wheel_radius"], data["wheel_separation"]) == (0.04, 0.25)
    assert set(data["sources"].values()) == {"override"}
    assert data["max_wheel_speed"] is None
    ik = CliRunner().invoke(main, ["ik", "0.1", "0", *OPTIONS, "--max-rpm", "30", "--json"])
    assert json.loads(ik.stdout)["left"] == pytest.approx(2.5, abs=1e-12)  # 0.1 / 0.04


def test_three_options_of_four_still_load_the_bundled_robot() -> None:
    result = CliRunner().invoke(main, ["params", *OPTIONS[:6]])
    assert_one_error_line(result, "no joint named 'wheel_l'")


def test_several_joints_per_side_from_options() -> None:
    params = diffbot.load_params(
        left_joint="fl,rl", right_joint="fr,rr", wheel_radius=0.1, wheel_separation=0.5
    )
    assert params.left_joints == ("fl", "rl")
    assert params.right_joints == ("fr", "rr")


#: Shaped like the Webots e-puck's description: a ros2_control block and a Webots plugin, no
#: links; its controllers file holds every value.
EPUCK = """<?xml version="1.0"?>
<robot name="e-puck">
  <webots><plugin type="webots_ros2_driver::Ros2Control"/></webots>
  <ros2_control name="WebotsControl" type="system">
    <hardware><plugin>webots_ros2_control::Ros2ControlSystem</plugin></hardware>
    <joint name="left wheel motor"><command_interface name="velocity">
      <param name="max">6.28</param></command_interface></joint>
    <joint name="right wheel motor"><command_interface name="velocity">
      <param name="max">6.28</param></command_interface></joint>
  </ros2_control>
</robot>
"""
EPUCK_CONTROLLERS = """controller_manager:
  ros__parameters:
    update_rate: 50
    diffdrive_controller:
      type: diff_drive_controller/DiffDriveController
diffdrive_controller:
  ros__parameters:
    left_wheel_names: ["left wheel motor"]
    right_wheel_names: ["right wheel motor"]
    wheel_separation: 0.052
    wheel_radius: 0.0205
"""


def epuck(tmp_path: Path, controllers: str = EPUCK_CONTROLLERS) -> tuple[Path, Path]:
    robot = tmp_path / "epuck.urdf"
    robot.write_text(EPUCK, encoding="utf-8")
    yaml = tmp_path / "ros2control.yml"
    yaml.write_text(controllers, encoding="utf-8")
    return robot, yaml


def test_a_description_without_links_takes_its_controller(tmp_path: Path) -> None:
    robot, yaml = epuck(tmp_path)
    params = diffbot.load_params(robot, controllers=yaml)
    assert (params.wheel_radius, params.wheel_separation) == (0.0205, 0.052)
    assert (params.left_joint, params.right_joint) == ("left wheel motor", "right wheel motor")
    assert params.max_wheel_speed == 6.28
    assert params.sources["wheel_separation"] == f"controllers:{yaml}"
    assert any("defines no links: the robot is its controller" in w for w in params.warnings)


def test_a_controller_missing_a_value_says_which(tmp_path: Path) -> None:
    robot, yaml = epuck(tmp_path, EPUCK_CONTROLLERS.replace("    wheel_radius: 0.0205\n", ""))
    result = CliRunner().invoke(main, ["params", str(robot), "--controllers", str(yaml)])
    assert_one_error_line(result, "leaves out wheel_radius", "--wheel-radius")


def test_without_a_controller_a_file_of_macros_is_still_said_so(tmp_path: Path) -> None:
    robot, _ = epuck(tmp_path)
    with pytest.raises(diffbot.DescriptionError, match="defines no links: is it a file of macros"):
        diffbot.load_params(robot)


ROBOT = """<?xml version="1.0"?>
<robot name="recorded"><link name="base_link"/>
<link name="l"><collision><origin rpy="1.5707963 0 0"/><geometry><cylinder radius="0.06"
  length="0.02"/></geometry></collision></link>
<link name="r"><collision><origin rpy="1.5707963 0 0"/><geometry><cylinder radius="0.06"
  length="0.02"/></geometry></collision></link>
<joint name="lw" type="continuous"><parent link="base_link"/><child link="l"/>
  <origin xyz="0 0.16 0"/><axis xyz="0 1 0"/></joint>
<joint name="rw" type="continuous"><parent link="base_link"/><child link="r"/>
  <origin xyz="0 -0.16 0"/><axis xyz="0 1 0"/></joint>
</robot>
"""


def description_bag(path: Path, text: str | None = ROBOT, storage: str = "sqlite3") -> Path:
    plugin = StoragePlugin.MCAP if storage == "mcap" else StoragePlugin.SQLITE3
    with Writer(path, version=9, storage_plugin=plugin) as writer:
        if text is not None:
            conn = writer.add_connection(
                "/robot_description", "std_msgs/msg/String", typestore=TYPESTORE
            )
            raw = TYPESTORE.serialize_cdr(m.std_msgs__msg__String(data=text), "std_msgs/msg/String")
            writer.write(conn, 1, bytes(raw))
        else:
            conn = writer.add_connection("/chatter", "std_msgs/msg/String", typestore=TYPESTORE)
    return path


@pytest.mark.parametrize("storage", ["sqlite3", "mcap"])
def test_a_bag_is_a_description_through_its_robot_description(tmp_path: Path, storage: str) -> None:
    bag = description_bag(tmp_path / "run", storage=storage)
    params = diffbot.load_params(bag)
    assert (params.left_joint, params.wheel_radius) == ("lw", 0.06)
    assert params.wheel_separation == pytest.approx(0.32, abs=1e-12)
    assert str(bag) in params.description_files
    result = CliRunner().invoke(main, ["params", "--robot", str(bag), "--json"])
    assert result.exit_code == 0, result.output
    assert json.loads(result.stdout)["right_joint"] == "rw"


def test_a_bag_without_the_topic_is_one_error_line(tmp_path: Path) -> None:
    bag = description_bag(tmp_path / "run", text=None)
    result = CliRunner().invoke(main, ["params", str(bag)])
    assert_one_error_line(result, "the bag has no /robot_description topic")
