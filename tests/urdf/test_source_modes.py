"""``source=``/``--source``: the controller, else the simulator's plugin, else the geometry;
the other sources still cross-checked."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from cli_results import assert_one_error_line
from click.testing import CliRunner

import diffbot
from diffbot.cli import main


def wheel(side: str, y: float) -> str:
    return (
        f'<link name="{side}_wheel"><collision><origin rpy="1.5707963 0 0"/><geometry>'
        '<cylinder radius="0.1" length="0.04"/></geometry></collision></link>'
        f'<joint name="{side}_wheel_joint" type="continuous"><parent link="chassis"/>'
        f'<child link="{side}_wheel"/><origin xyz="0.1 {y} 0"/><axis xyz="0 1 0"/></joint>'
    )


#: Shaped like Dolly's URDF twin: the simulator's plugin runs it with other numbers than its
#: geometry (a wider separation, a smaller radius).
SIM_ROBOT = (
    '<?xml version="1.0"?>\n<robot name="dolly"><link name="chassis"/>'
    + wheel("left", 0.2)
    + wheel("right", -0.2)
    + "PLUGIN</robot>\n"
)
GZ = (
    '<gazebo><plugin filename="gz-sim-diff-drive-system" name="gz::sim::systems::DiffDrive">'
    "<left_joint>left_wheel_joint</left_joint><right_joint>right_wheel_joint</right_joint>"
    "<wheel_separation>0.42</wheel_separation><wheel_radius>0.095</wheel_radius>"
    "</plugin></gazebo>"
)
CLASSIC = (
    '<gazebo><plugin name="dd" filename="libgazebo_ros_diff_drive.so">'
    "<left_joint>left_wheel_joint</left_joint><right_joint>right_wheel_joint</right_joint>"
    "<wheel_separation>0.44</wheel_separation><wheel_diameter>0.18</wheel_diameter>"
    "</plugin></gazebo>"
)
CONTROLLERS = """diff_cont:
  ros__parameters:
    type: diff_drive_controller/DiffDriveController
    left_wheel_names: [left_wheel_joint]
    right_wheel_names: [right_wheel_joint]
    wheel_separation: 0.4
    wheel_radius: 0.1
"""


def robot(tmp_path: Path, plugin: str = GZ) -> Path:
    path = tmp_path / "dolly.urdf"
    path.write_text(SIM_ROBOT.replace("PLUGIN", plugin), encoding="utf-8")
    return path


def controllers(tmp_path: Path) -> Path:
    path = tmp_path / "controllers.yaml"
    path.write_text(CONTROLLERS, encoding="utf-8")
    return path


def test_auto_takes_the_plugin_of_a_robot_without_a_controller(tmp_path: Path) -> None:
    params = diffbot.load_params(robot(tmp_path))
    assert (params.wheel_separation, params.wheel_radius) == (0.42, 0.095)
    assert params.sources["wheel_separation"] == "plugin"
    assert params.sources["left_joints"] == "plugin"
    fields = {d.field for d in params.disagreements}
    assert fields == {"wheel_separation", "wheel_radius"}  # still listed


def test_a_classic_plugin_gives_half_its_diameter(tmp_path: Path) -> None:
    params = diffbot.load_params(robot(tmp_path, CLASSIC))
    assert (params.wheel_separation, params.wheel_radius) == (0.44, 0.09)


def test_auto_takes_the_controller_over_the_plugin(tmp_path: Path) -> None:
    params = diffbot.load_params(robot(tmp_path), controllers=controllers(tmp_path))
    assert params.wheel_separation == pytest.approx(0.4, abs=1e-15)
    assert params.sources["wheel_separation"].startswith("controllers:")


def test_each_source_can_be_asked_for(tmp_path: Path) -> None:
    path, yaml = robot(tmp_path), controllers(tmp_path)
    plugin = diffbot.load_params(path, controllers=yaml, source="plugin")
    assert plugin.wheel_separation == 0.42
    described = diffbot.load_params(path, controllers=yaml, source="description")
    assert described.wheel_separation == pytest.approx(0.4, abs=1e-12)
    assert described.wheel_radius == pytest.approx(0.1, abs=1e-12)
    assert set(described.sources.values()) == {"description"}
    assert described.disagreements  # the plugin still disagrees


def test_asking_for_a_source_that_is_not_there_is_bad_input(tmp_path: Path) -> None:
    path = robot(tmp_path)
    missing = CliRunner().invoke(main, ["params", str(path), "--source", "controllers"])
    assert_one_error_line(missing, "no diff-drive controller was found", "--controllers")
    bare = tmp_path / "bare.urdf"
    bare.write_text(SIM_ROBOT.replace("PLUGIN", ""), encoding="utf-8")
    no_plugin = CliRunner().invoke(main, ["params", str(bare), "--source", "plugin"])
    assert_one_error_line(no_plugin, "the description has no diff-drive plugin")
    unknown = CliRunner().invoke(main, ["params", str(path), "--source", "yaml"])
    assert unknown.exit_code == 2


def test_params_json_says_plugin(tmp_path: Path) -> None:
    result = CliRunner().invoke(main, ["params", str(robot(tmp_path)), "--json"])
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert data["sources"]["wheel_radius"] == "plugin"
    assert data["wheel_radius"] == 0.095
