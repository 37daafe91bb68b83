"""SDF models: links, joints, collisions, nested and included models, the diff-drive plugin as
a source, and the untrusted-input rules of xacro descriptions."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from cli_results import assert_one_error_line
from click.testing import CliRunner

import diffbot
from diffbot.cli import main
from diffbot.errors import ExpansionLimitError, OutsideRootsError
from diffbot.urdf import sdf
from diffbot.urdf.packages import PackageFinder

#: Shaped like Dolly: a chassis, two sphere wheels turned so that their z axis is lateral, a ball
#: caster, and gz-sim's DiffDrive system (the Ignition spelling).
DOLLY = """<?xml version="1.0"?>
<sdf version="1.6">
  <model name="dolly">
    <pose>0 0 0.225 0 0 0</pose>
    <link name="chassis">
      <collision name="collision"><geometry><box><size>2.01 1 0.57</size></box></geometry>
      </collision>
    </link>
    <link name="left_wheel">
      <pose>0.554283 0.625029 -0.025 -1.5707 0 0</pose>
      <collision name="c"><geometry><sphere><radius>0.3</radius></sphere></geometry></collision>
    </link>
    <link name="right_wheel">
      <pose>0.554283 -0.625029 -0.025 -1.5707 0 0</pose>
      <collision name="c"><geometry><sphere><radius>0.3</radius></sphere></geometry></collision>
    </link>
    <link name="caster">
      <pose>-0.957138 0 -0.125 0 0 0</pose>
      <collision name="c"><geometry><sphere><radius>0.2</radius></sphere></geometry></collision>
    </link>
    <joint name="left_wheel_joint" type="revolute">
      <parent>chassis</parent><child>left_wheel</child>
      <axis><xyz>0 0 1</xyz>
        <limit><lower>-1.79769e+308</lower><upper>1.79769e+308</upper></limit></axis>
    </joint>
    <joint name="right_wheel_joint" type="revolute">
      <parent>chassis</parent><child>right_wheel</child><axis><xyz>0 0 1</xyz></axis>
    </joint>
    <joint name="caster_wheel" type="ball"><parent>chassis</parent><child>caster</child></joint>
    <plugin filename="libignition-gazebo-diff-drive-system.so"
            name="ignition::gazebo::systems::DiffDrive">
      <left_joint>left_wheel_joint</left_joint><right_joint>right_wheel_joint</right_joint>
      <wheel_separation>1.25</wheel_separation><wheel_radius>0.3</wheel_radius>
    </plugin>
  </model>
</sdf>
"""

CONFIG = """<?xml version="1.0"?>
<model><name>{name}</name><version>1.0</version><sdf version="1.6">{file}</sdf></model>
"""


def model_folder(parent: Path, name: str, text: str, file: str = "model.sdf") -> Path:
    folder = parent / name
    folder.mkdir(parents=True)
    (folder / "model.config").write_text(CONFIG.format(name=name, file=file), encoding="utf-8")
    (folder / file).write_text(text, encoding="utf-8")
    return folder


def test_an_sdf_model_gives_its_wheels_and_its_plugin(tmp_path: Path) -> None:
    folder = model_folder(tmp_path / "models", "dolly", DOLLY)
    params = diffbot.load_params(folder / "model.sdf")
    # the plugin is the controller of a simulated robot: its values win
    assert (params.wheel_separation, params.wheel_radius) == (1.25, 0.3)
    assert params.sources["wheel_separation"] == "plugin"
    assert (params.left_joint, params.right_joint) == ("left_wheel_joint", "right_wheel_joint")
    assert (params.left_sign, params.right_sign) == (1, 1)
    described = diffbot.load_params(folder / "model.sdf", source="description")
    assert described.wheel_separation == pytest.approx(1.250058, abs=1e-9)
    assert described.wheel_radius == 0.3
    assert described.disagreements == ()  # 0.058 mm apart: within the tolerance


def test_a_model_folder_is_read_through_its_model_config(tmp_path: Path) -> None:
    folder = model_folder(tmp_path / "models", "dolly", DOLLY, file="dolly.sdf")
    params = diffbot.load_params(folder)
    assert params.wheel_radius == 0.3
    assert str(folder / "dolly.sdf") in params.description_files


def test_every_command_takes_a_model_folder(tmp_path: Path) -> None:
    folder = model_folder(tmp_path / "models", "dolly", DOLLY)
    result = CliRunner().invoke(main, ["params", str(folder), "--json"])
    assert result.exit_code == 0, result.output
    assert json.loads(result.stdout)["sources"]["wheel_radius"] == "plugin"
    check = CliRunner().invoke(main, ["check", str(folder)])
    assert check.exit_code == 0, check.output
    ik = CliRunner().invoke(main, ["ik", "0.3", "0", "--robot", str(folder / "model.sdf")])
    assert ik.exit_code == 0, ik.output
    assert "1 rad/s" in ik.stdout  # 0.3 m/s on 0.3 m wheels
    urdf = CliRunner().invoke(main, ["urdf", str(folder / "model.sdf")])
    assert '<joint name="left_wheel_joint" type="continuous">' in urdf.stdout


WHEEL = """<sdf version="1.7"><model name="wheel">
  <link name="tyre"><pose>0 0 0 1.5707963 0 0</pose>
    <collision name="hub"><geometry>
      <cylinder><radius>0.05</radius><length>0.04</length></cylinder></geometry></collision>
    <collision name="tyre"><geometry>
      <cylinder><radius>0.08</radius><length>0.04</length></cylinder></geometry></collision>
  </link></model></sdf>
"""

ROBOT = """<sdf version="1.7"><model name="rover">
  <link name="base"/>
  <include><uri>model://wheel</uri><name>left</name><pose>0 0.2 0 0 0 0</pose></include>
  <include><uri>model://wheel</uri><name>right</name><pose>0 -0.2 0 0 0 0</pose></include>
  <joint name="left_joint" type="revolute"><parent>base</parent><child>left::tyre</child>
    <axis><xyz expressed_in="__model__">0 1 0</xyz></axis></joint>
  <joint name="right_joint" type="revolute"><parent>base</parent><child>right::tyre</child>
    <axis><xyz expressed_in="__model__">0 1 0</xyz></axis></joint>
  <model name="mast"><pose>0 0 0.3 0 0 0</pose><link name="top"/>
    <joint name="fix" type="fixed"><parent>top</parent><child>top</child></joint></model>
  <joint name="mast_joint" type="fixed"><parent>base</parent><child>mast::top</child></joint>
</model></sdf>
"""


def test_included_and_nested_models_join_the_tree(tmp_path: Path) -> None:
    models = tmp_path / "models"
    model_folder(models, "wheel", WHEEL)
    robot = model_folder(
        models,
        "rover",
        ROBOT.replace(
            '<joint name="fix" type="fixed"><parent>top</parent><child>top</child></joint>', ""
        ),
    )
    params = diffbot.load_params(robot)
    assert params.wheel_separation == pytest.approx(0.4, abs=1e-12)
    assert params.wheel_radius == 0.08  # the tyre, not the hub
    assert (params.left_joint, params.right_joint) == ("left_joint", "right_joint")
    assert (params.left_sign, params.right_sign) == (1, 1)
    assert any("several collision cylinders" in w for w in params.warnings)


def test_an_unknown_model_is_bad_input(tmp_path: Path) -> None:
    robot = model_folder(tmp_path / "models", "rover", ROBOT)
    result = CliRunner().invoke(main, ["params", str(robot)])
    assert_one_error_line(
        result, "model 'wheel' of 'model://wheel' not found", "--package wheel=DIR"
    )


def test_a_file_outside_the_tree_is_refused(tmp_path: Path) -> None:
    secret = tmp_path / "secret.sdf"
    secret.write_text(WHEEL, encoding="utf-8")
    text = ROBOT.replace("model://wheel", f"file://{secret}")
    robot = model_folder(tmp_path / "ws" / "models", "rover", text)
    with pytest.raises(OutsideRootsError, match="outside the description's folders"):
        diffbot.load_params(robot)


def test_includes_are_bounded(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    selfish = '<sdf version="1.7"><model name="m"><link name="a"/><include><uri>model://loop</uri></include></model></sdf>'
    robot = model_folder(tmp_path / "models", "loop", selfish)
    with pytest.raises(ExpansionLimitError, match="nested more than 16 deep"):
        diffbot.load_params(robot)
    monkeypatch.setattr(sdf, "MAX_FILE_BYTES", 100)
    with pytest.raises(ExpansionLimitError, match="larger than 100 bytes"):
        diffbot.load_params(model_folder(tmp_path / "m2", "dolly", DOLLY))


def test_malformed_sdf_is_one_error_line(tmp_path: Path) -> None:
    path = tmp_path / "bad.sdf"
    path.write_text(
        '<sdf version="1.6"><model name="x"><link name="a"><pose>1 2</pose></link></model></sdf>',
        encoding="utf-8",
    )
    result = CliRunner().invoke(main, ["params", str(path)])
    assert_one_error_line(result, "expected 6 finite numbers")


#: Shaped like TurtleBot3 Burger's model.sdf (ROBOTIS-GIT/turtlebot3_simulations,
#: turtlebot3_gazebo/models/turtlebot3_burger/model.sdf): the wheel links sit at the model's
#: origin, each wheel joint's own <pose> (relative to its child link, SDF's default) places it
#: 0.08 m to the side and turns it so that its z axis is lateral; gz-sim's DiffDrive system runs
#: the robot with a separation of 0.160 m and a radius of 0.033 m.
BURGER = """<?xml version="1.0" ?>
<sdf version="1.5">
  <model name="turtlebot3_burger">
    <link name="base_footprint"/>
    <link name="base_link">
      <collision name="base_collision"><pose>-0.032 0 0.070 0 0 0</pose>
        <geometry><box><size>0.140 0.140 0.140</size></box></geometry></collision>
    </link>
    <link name="wheel_left_link">
      <collision name="wheel_left_collision"><pose>0 0.08 0.023 -1.57 0 0</pose>
        <geometry><cylinder><radius>0.033</radius><length>0.018</length></cylinder></geometry>
      </collision>
    </link>
    <link name="wheel_right_link">
      <collision name="wheel_right_collision"><pose>0.0 -0.08 0.023 -1.57 0 0</pose>
        <geometry><cylinder><radius>0.033</radius><length>0.018</length></cylinder></geometry>
      </collision>
    </link>
    <link name="caster_back_link">
      <pose>-0.081 0 -0.004 -1.57 0 0</pose>
      <collision name="collision"><geometry><sphere><radius>0.005</radius></sphere></geometry>
      </collision>
    </link>
    <joint name="base_joint" type="fixed"><parent>base_footprint</parent>
      <child>base_link</child><pose>0.0 0.0 0.010 0 0 0</pose></joint>
    <joint name="wheel_left_joint" type="revolute">
      <parent>base_link</parent><child>wheel_left_link</child>
      <pose>0.0 0.08 0.023 -1.57 0 0</pose><axis><xyz>0 0 1</xyz></axis>
    </joint>
    <joint name="wheel_right_joint" type="revolute">
      <parent>base_link</parent><child>wheel_right_link</child>
      <pose>0.0 -0.08 0.023 -1.57 0 0</pose><axis><xyz>0 0 1</xyz></axis>
    </joint>
    <joint name="caster_back_joint" type="ball">
      <parent>base_link</parent><child>caster_back_link</child></joint>
    <plugin filename="gz-sim-diff-drive-system" name="gz::sim::systems::DiffDrive">
      <left_joint>wheel_left_joint</left_joint><right_joint>wheel_right_joint</right_joint>
      <wheel_separation>0.160</wheel_separation><wheel_radius>0.033</wheel_radius>
      <child_frame_id>base_footprint</child_frame_id>
    </plugin>
  </model>
</sdf>
"""


def test_a_joint_pose_places_the_wheel_where_the_joint_is(tmp_path: Path) -> None:
    folder = model_folder(tmp_path / "turtlebot3_gazebo" / "models", "turtlebot3_burger", BURGER)
    described = diffbot.load_params(folder, source="description")
    assert described.wheel_separation == pytest.approx(0.160, abs=1e-9)
    assert described.wheel_radius == pytest.approx(0.033, abs=1e-12)
    assert (described.left_joint, described.right_joint) == (
        "wheel_left_joint",
        "wheel_right_joint",
    )
    # the joint's turned z axis is +y on both sides: forward is a positive speed on each
    assert (described.left_sign, described.right_sign) == (1, 1)
    assert described.disagreements == ()
    check = CliRunner().invoke(main, ["check", str(folder)])
    assert check.exit_code == 0, check.output


def test_a_joint_pose_relative_to_the_model_is_taken_as_written(tmp_path: Path) -> None:
    text = BURGER.replace(
        "<pose>0.0 0.08 0.023 -1.57", '<pose relative_to="__model__">0 0.09 0.033 -1.57'
    )
    text = text.replace('<sdf version="1.5">', '<sdf version="1.8">')
    folder = model_folder(tmp_path / "models", "burger", text)
    urdf, _ = sdf.expand_sdf(folder, PackageFinder(None, {}), [folder])
    joint = urdf[urdf.index('<joint name="wheel_left_joint"') :]
    # base_link is 0.010 m up (base_joint); the joint frame is where its pose puts it
    assert '<origin xyz="0 0.089999999999999997 0.023' in joint[: joint.index("</joint>")]
    described = diffbot.load_params(folder, source="description")
    # the wheels roll on their cylinders, which have not moved: the same separation
    assert described.wheel_separation == pytest.approx(0.160, abs=1e-4)
    assert (described.left_sign, described.right_sign) == (1, 1)


#: Shaped like the Pioneer 2DX of Gazebo's old model database: wheel links turned by
#: (0, pi/2, pi/2), whose axis 0 1 0 is written in the model's frame as SDF 1.4 has it.
PIONEER_14 = """<?xml version="1.0"?>
<sdf version="1.4">
  <model name="pioneer">
    <link name="chassis"><pose>0 0 0.16 0 0 0</pose>
      <collision name="c"><geometry><box><size>0.445 0.277 0.17</size></box></geometry></collision>
    </link>
    <link name="left_wheel"><pose>0.1 0.17 0.11 0 1.5707963267948966 1.5707963267948966</pose>
      <collision name="c"><geometry><cylinder><radius>0.11</radius><length>0.05</length>
      </cylinder></geometry></collision>
    </link>
    <link name="right_wheel"><pose>0.1 -0.17 0.11 0 1.5707963267948966 1.5707963267948966</pose>
      <collision name="c"><geometry><cylinder><radius>0.11</radius><length>0.05</length>
      </cylinder></geometry></collision>
    </link>
    <joint type="revolute" name="left_wheel_hinge">
      <child>left_wheel</child><parent>chassis</parent><axis><xyz>0 1 0</xyz></axis>
    </joint>
    <joint type="revolute" name="right_wheel_hinge">
      <child>right_wheel</child><parent>chassis</parent><axis><xyz>0 1 0</xyz></axis>
    </joint>
  </model>
</sdf>
"""


@pytest.mark.parametrize(
    ("version", "in_model"),
    [
        ("1.4", True),
        ("1.3", True),
        ("1.0", True),
        (" 1.4 ", True),
        ("1.5", False),
        ("1.10", False),
        ("2.0", False),
        ("", False),
        ("one", False),
        ("1.x", False),
    ],
)
def test_axes_are_in_the_model_frame_up_to_sdf_1_4(version: str, in_model: bool) -> None:
    root = sdf.ET.fromstring(f'<sdf version="{version}"/>')
    assert sdf._axes_in_model(root) is in_model


def test_an_sdf_1_4_axis_is_read_in_the_model_frame(tmp_path: Path) -> None:
    folder = model_folder(tmp_path / "models", "pioneer", PIONEER_14)
    params = diffbot.load_params(folder, source="description")
    assert (params.left_joint, params.right_joint) == ("left_wheel_hinge", "right_wheel_hinge")
    assert params.wheel_separation == pytest.approx(0.34, abs=1e-9)
    assert params.wheel_radius == pytest.approx(0.11, abs=1e-12)
    assert (params.left_sign, params.right_sign) == (1, 1)
    # from 1.5 on the same axis is in the joint's frame: the turned wheels' y is the model's -x,
    # an axle along the robot, no drive wheel
    newer = model_folder(tmp_path / "models", "newer", PIONEER_14.replace('"1.4"', '"1.5"'))
    with pytest.raises(diffbot.DescriptionError, match="no drive wheels"):
        diffbot.load_params(newer, source="description")


#: A CAD export: the chassis yawed a quarter turn in the model, the wheels placed in the model.
ROTATED_CHASSIS = """<?xml version="1.0"?>
<sdf version="1.6">
  <model name="cad_bot">
    <link name="chassis"><pose>0 0 0.1 0 0 1.5707963267948966</pose>
      <collision name="c"><geometry><box><size>0.3 0.4 0.1</size></box></geometry></collision>
    </link>
    <link name="wheel_l"><pose>0.02 0.15 0.05 -1.5707963267948966 0 0</pose>
      <collision name="c"><geometry><cylinder><radius>0.05</radius><length>0.02</length>
      </cylinder></geometry></collision>
    </link>
    <link name="wheel_r"><pose>0.02 -0.15 0.05 1.5707963267948966 0 0</pose>
      <collision name="c"><geometry><cylinder><radius>0.05</radius><length>0.02</length>
      </cylinder></geometry></collision>
    </link>
    <joint name="wheel_l_joint" type="revolute">
      <parent>chassis</parent><child>wheel_l</child><axis><xyz>0 0 1</xyz></axis>
    </joint>
    <joint name="wheel_r_joint" type="revolute">
      <parent>chassis</parent><child>wheel_r</child><axis><xyz>0 0 1</xyz></axis>
    </joint>
  </model>
</sdf>
"""


def test_the_drive_plane_is_the_models_frame_when_the_main_link_is_rotated(
    tmp_path: Path,
) -> None:
    folder = model_folder(tmp_path / "models", "cad_bot", ROTATED_CHASSIS)
    params = diffbot.load_params(folder, source="description")
    assert params.wheel_separation == pytest.approx(0.3, abs=1e-9)
    assert params.wheel_radius == pytest.approx(0.05, abs=1e-12)
    # left z -> +y, right z -> -y: forward is +1 on the left, -1 on the right
    assert (params.left_sign, params.right_sign) == (1, -1)
    urdf, _ = sdf.expand_sdf(folder, PackageFinder(None, {}), [folder])
    chassis = urdf[urdf.index('<link name="chassis">') :]
    chassis = chassis[: chassis.index("</link>")]
    # the chassis frame is the model's turned, its box keeps its quarter turn
    assert 'rpy="0 -0 1.5707963267948966"' in chassis or 'rpy="0 0 1.5707963267948966"' in chassis
    joint = urdf[urdf.index('<joint name="wheel_l_joint"') :]
    assert '<origin xyz="0.02 0.14999999999999999 -0.050000000000000003"' in joint
