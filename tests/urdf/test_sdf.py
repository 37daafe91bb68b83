"""SDF models: links, joints, collisions, nested and included models, the diff-drive plugin as
a source, and the untrusted-input rules of xacro descriptions."""

from __future__ import annotations

import json
import math
from pathlib import Path
from xml.etree import ElementTree

import numpy as np
import pytest
from cli_results import assert_one_error_line
from click.testing import CliRunner
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

import diffbot
from diffbot.cli import main
from diffbot.errors import DescriptionError, ExpansionLimitError, OutsideRootsError
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


#: :data:`ROBOT` as a whole robot (its mast's joint to itself taken out).
ROVER = ROBOT.replace(
    '<joint name="fix" type="fixed"><parent>top</parent><child>top</child></joint>', ""
)


def test_a_sibling_model_linked_from_elsewhere_is_not_read(tmp_path: Path) -> None:
    # models/<name> beside the robot is read as model://<name>; a link there pointing out of
    # the models folder would open whatever folder it names.
    elsewhere = model_folder(tmp_path / "elsewhere", "wheel", WHEEL)
    models = tmp_path / "ws" / "models"
    robot = model_folder(models, "rover", ROVER)
    (models / "wheel").symlink_to(elsewhere, target_is_directory=True)
    result = CliRunner().invoke(main, ["params", str(robot)])
    assert_one_error_line(result, "model 'wheel' of 'model://wheel' not found")
    # the same folder copied in place is a sibling like any other
    (models / "wheel").unlink()
    model_folder(models, "wheel", WHEEL)
    assert diffbot.load_params(robot).wheel_radius == 0.08


@pytest.mark.parametrize("variable", ["GZ_SIM_RESOURCE_PATH", "GAZEBO_MODEL_PATH"])
@pytest.mark.parametrize("uri", ["model://../secret", "model://./../secret", "package://../secret"])
def test_a_model_name_that_is_a_path_reaches_nothing_outside(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, variable: str, uri: str
) -> None:
    model_folder(tmp_path, "secret", WHEEL)
    (tmp_path / "resources").mkdir()
    monkeypatch.setenv(variable, str(tmp_path / "resources"))
    monkeypatch.setenv("AMENT_PREFIX_PATH", str(tmp_path / "resources"))
    robot = model_folder(tmp_path / "ws" / "models", "rover", ROVER.replace("model://wheel", uri))
    result = CliRunner().invoke(main, ["params", str(robot)])
    assert_one_error_line(result, "not found")


def test_a_model_folder_outside_is_refused_before_its_model_config_is_read(
    tmp_path: Path,
) -> None:
    outside = tmp_path / "outside"
    outside.mkdir()
    (outside / "model.config").write_text("<model><sdf>not closed", encoding="utf-8")
    robot = model_folder(
        tmp_path / "ws" / "models", "rover", ROVER.replace("model://wheel", "../../../outside")
    )
    with pytest.raises(OutsideRootsError, match="outside the description's folders"):
        diffbot.load_params(robot)


@pytest.mark.parametrize("included", [True, False])
def test_a_model_config_linked_from_outside_is_refused_unread(
    tmp_path: Path, included: bool
) -> None:
    # The model folder lies inside the tree, its model.config is a link out of it: the file
    # is refused before it is parsed, so nothing of it shows in the message.
    secret = tmp_path / "outside" / "notes.xml"
    secret.parent.mkdir()
    secret.write_text("<config><sdf>SECRET-CONTENT</sdf></config>", encoding="utf-8")
    models = tmp_path / "ws" / "models"
    robot = model_folder(models, "rover", ROVER.replace("model://wheel", "wheel"))
    linked = robot / "wheel" if included else robot
    linked.mkdir(exist_ok=True)
    (linked / "model.config").unlink(missing_ok=True)
    (linked / "model.config").symlink_to(secret)
    with pytest.raises(OutsideRootsError, match=r"model\.config: reading refused") as caught:
        diffbot.load_params(robot)
    assert "SECRET" not in str(caught.value)
    result = CliRunner().invoke(main, ["params", str(robot)])
    assert_one_error_line(
        result,
        f"outside the description's folders ({robot.resolve()}); trust the description "
        "(--trust) to let it read any file",
    )
    assert "SECRET" not in result.output


@pytest.mark.parametrize(
    ("limits", "expected"),
    [
        ("<lower>abc</lower><upper>1</upper>", "a limit must be a number, got 'abc'"),
        ("<lower>nan</lower><upper>1</upper>", "a limit must be a number, got 'nan'"),
        ("<lower>0</lower><upper>1</upper><velocity>fast</velocity>", "got 'fast'"),
        (f"<lower>0</lower><upper>{'9' * 400}</upper>", None),  # beyond a float: no bound
    ],
)
def test_joint_limits_are_numbers_or_one_error_line(
    tmp_path: Path, limits: str, expected: str | None
) -> None:
    text = DOLLY.replace(
        "<limit><lower>-1.79769e+308</lower><upper>1.79769e+308</upper></limit>",
        f"<limit>{limits}</limit>",
    )
    folder = model_folder(tmp_path, "dolly", text)
    result = CliRunner().invoke(main, ["params", str(folder)])
    if expected is None:
        assert result.exit_code == 0, result.output
        assert "wheel radius      0.3 m" in result.stdout
    else:
        assert_one_error_line(result, "joint 'left_wheel_joint'", expected)


def pose_matrix(x: float, y: float, z: float, roll: float, pitch: float, yaw: float) -> np.ndarray:
    """A pose as a 4x4 matrix, by SciPy's fixed-axis x-y-z rotations (R = Rz Ry Rx)."""
    m = np.eye(4)
    m[:3, :3] = Rotation.from_euler("xyz", [roll, pitch, yaw]).as_matrix()
    m[:3, 3] = (x, y, z)
    return m


def origin_matrix(element: ElementTree.Element) -> np.ndarray:
    """A URDF element's <origin> as a 4x4 matrix."""
    origin = element.find("origin")
    assert origin is not None
    xyz = [float(v) for v in origin.get("xyz", "").split()]
    rpy = [float(v) for v in origin.get("rpy", "").split()]
    return pose_matrix(*xyz, *rpy)


BASE = (0.1, -0.2, 0.05, 0.1, -0.2, 0.3)
WHEEL_LINK = (0.3, 0.4, 0.1, -1.2, 0.25, 0.7)
WHEEL_JOINT = (0.02, -0.03, 0.04, 0.3, 0.4, -0.5)
TYRE = (0.01, 0.0, -0.02, 0.0, 1.0, 0.2)


def base_frame() -> NDArray[np.float64]:
    """The URDF frame of the base: a link no joint moves keeps its place but takes the model's
    orientation, so that the model frame is the drive plane."""
    frame = np.eye(4)
    frame[:3, 3] = BASE[:3]
    return frame


def posed_model(joint_pose: str, axis: str = "<xyz>0 0 1</xyz>") -> str:
    def words(pose: tuple[float, ...]) -> str:
        return " ".join(repr(v) for v in pose)

    return f"""<sdf version="1.9"><model name="posed">
  <pose>5 6 7 0.5 0.5 0.5</pose>
  <link name="base"><pose>{words(BASE)}</pose></link>
  <link name="wheel"><pose>{words(WHEEL_LINK)}</pose>
    <collision name="c"><pose>{words(TYRE)}</pose><geometry>
      <cylinder><radius>0.05</radius><length>0.02</length></cylinder></geometry></collision>
  </link>
  <joint name="spin" type="continuous"><parent>base</parent><child>wheel</child>
    {joint_pose}<axis>{axis}</axis></joint>
</model></sdf>
"""


def expanded(tmp_path: Path, text: str) -> ElementTree.Element:
    path = tmp_path / "posed.sdf"
    path.write_text(text, encoding="utf-8")
    urdf, _ = sdf.expand_sdf(path, PackageFinder(None, {}), [tmp_path])
    return ElementTree.fromstring(urdf)


def test_rotated_link_and_joint_poses_compose(tmp_path: Path) -> None:
    words = " ".join(repr(v) for v in WHEEL_JOINT)
    robot = expanded(tmp_path, posed_model(f"<pose>{words}</pose>"))
    joint = robot.find("joint")
    assert joint is not None
    # The joint's frame is its pose in its child link's frame; URDF wants it in the parent's.
    wheel, at_joint = pose_matrix(*WHEEL_LINK), pose_matrix(*WHEEL_JOINT)
    want = np.linalg.inv(base_frame()) @ wheel @ at_joint
    np.testing.assert_allclose(origin_matrix(joint), want, rtol=0, atol=1e-12)
    # The tyre stays where the SDF put it: in the URDF link frame (the joint's) it is moved
    # back by the joint's pose.
    collision = robot.find("link[@name='wheel']/collision")
    assert collision is not None
    tyre = np.linalg.inv(at_joint) @ pose_matrix(*TYRE)
    np.testing.assert_allclose(origin_matrix(collision), tyre, rtol=0, atol=1e-12)


def test_a_joint_pose_relative_to_the_parent_link_and_an_axis_in_the_model_frame(
    tmp_path: Path,
) -> None:
    words = " ".join(repr(v) for v in WHEEL_JOINT)
    text = posed_model(
        f'<pose relative_to="base">{words}</pose>', '<xyz expressed_in="__model__">0 1 0</xyz>'
    )
    robot = expanded(tmp_path, text)
    joint = robot.find("joint")
    assert joint is not None
    at_joint = pose_matrix(*WHEEL_JOINT)  # in the SDF base link's frame
    want = np.linalg.inv(base_frame()) @ pose_matrix(*BASE) @ at_joint
    np.testing.assert_allclose(origin_matrix(joint), want, rtol=0, atol=1e-12)
    # The model's +y, seen from the joint's frame.
    frame = pose_matrix(*BASE) @ at_joint
    axis = joint.find("axis")
    assert axis is not None
    got = [float(v) for v in axis.get("xyz", "").split()]
    np.testing.assert_allclose(got, frame[:3, :3].T @ [0.0, 1.0, 0.0], rtol=0, atol=1e-12)


def test_poses_in_degrees_and_quaternions_and_links_relative_to_links(tmp_path: Path) -> None:
    # The wheel link placed relative to base by a quaternion (x y z qx qy qz qw), the joint's
    # pose in degrees.
    q = Rotation.from_euler("xyz", WHEEL_LINK[3:]).as_quat()  # x, y, z, w
    link = " ".join(repr(float(v)) for v in (*WHEEL_LINK[:3], *q))
    degrees = " ".join(
        repr(v) for v in (*WHEEL_JOINT[:3], *(math.degrees(a) for a in WHEEL_JOINT[3:]))
    )
    text = posed_model(f'<pose degrees="true">{degrees}</pose>')
    text = text.replace(
        f"<pose>{' '.join(repr(v) for v in WHEEL_LINK)}</pose>",
        f'<pose relative_to="base">{link}</pose>',
    )
    robot = expanded(tmp_path, text)
    joint = robot.find("joint")
    assert joint is not None
    # The wheel is at base * link in the model, seen from the base's URDF frame.
    link_pose = pose_matrix(*BASE) @ pose_matrix(*WHEEL_LINK)
    want = np.linalg.inv(base_frame()) @ link_pose @ pose_matrix(*WHEEL_JOINT)
    np.testing.assert_allclose(origin_matrix(joint), want, rtol=0, atol=1e-12)


def joints_model(joints: str) -> str:
    links = "".join(f'<link name="{n}"/>' for n in ("base", "a", "b", "c", "d", "e"))
    return f'<sdf version="1.9"><model name="m">{links}{joints}</model></sdf>'


def test_joint_kinds_and_limits_as_urdf_has_them(tmp_path: Path) -> None:
    robot = expanded(
        tmp_path,
        joints_model(
            '<joint name="j1" type="revolute"><parent>base</parent><child>a</child>'
            "<axis><xyz>0 1 0</xyz><limit><lower>-0.5</lower><upper>1.5</upper>"
            "<velocity>3.5</velocity></limit></axis></joint>"
            '<joint name="j2" type="revolute"><parent>base</parent><child>b</child>'
            "<axis><xyz>0 1 0</xyz><limit><lower>-4</lower><upper>4</upper>"
            "<velocity>-1</velocity></limit></axis></joint>"
            '<joint name="j3" type="prismatic"><parent>base</parent><child>c</child>'
            "<axis><xyz>1 0 0</xyz><limit><lower>0</lower><upper>0.2</upper></limit></axis>"
            "</joint>"
            '<joint name="j4" type="universal"><parent>base</parent><child>d</child></joint>'
            '<joint name="j5" type="revolute"><parent>base</parent><child>e</child>'
            "<axis><xyz>0 0 1</xyz><limit><velocity>inf</velocity></limit></axis></joint>"
        ),
    )
    kinds = {j.get("name"): j.get("type") for j in robot.iter("joint")}
    assert kinds == {
        "j1": "revolute",  # 2 rad of travel: a bounded joint
        "j2": "continuous",  # 8 rad, a full turn or more: continuous
        "j3": "prismatic",
        "j4": "fixed",
        "j5": "continuous",  # no bounds
    }
    limits = {j.get("name"): j.find("limit") for j in robot.iter("joint")}
    one = limits["j1"]
    assert one is not None
    assert one.attrib == {"effort": "0", "lower": "-0.5", "upper": "1.5", "velocity": "3.5"}
    assert limits["j2"] is None  # continuous, and a negative velocity is no limit
    three = limits["j3"]
    assert three is not None
    assert three.attrib == {"effort": "0", "lower": "0.0", "upper": "0.2"}
    assert limits["j4"] is None
    assert limits["j5"] is None  # an infinite velocity is no limit
    axes = {j.get("name"): j.find("axis") for j in robot.iter("joint")}
    three_axis = axes["j3"]
    assert three_axis is not None
    assert three_axis.get("xyz") == "1.0 0.0 0.0"
    assert axes["j4"] is None


def test_a_pitch_of_a_quarter_turn_keeps_the_rotation(tmp_path: Path) -> None:
    # Gimbal lock: roll and yaw are one rotation there; the origin still turns the same way.
    pose = (0.0, 0.0, 0.0, 0.4, math.pi / 2, 0.3)
    words = " ".join(repr(v) for v in pose)
    robot = expanded(
        tmp_path,
        joints_model(
            f'<joint name="j" type="fixed"><parent>base</parent><child>a</child>'
            f'<pose relative_to="base">{words}</pose></joint>'
        ),
    )
    joint = robot.find("joint")
    assert joint is not None
    np.testing.assert_allclose(origin_matrix(joint), pose_matrix(*pose), rtol=0, atol=1e-12)
    # A quaternion of zero length is read as no rotation rather than a division by zero.
    robot = expanded(
        tmp_path,
        joints_model(
            '<joint name="j" type="fixed"><parent>base</parent><child>a</child>'
            '<pose relative_to="base">1 2 3 0 0 0 0</pose></joint>'
        ),
    )
    joint = robot.find("joint")
    assert joint is not None
    np.testing.assert_allclose(
        origin_matrix(joint), pose_matrix(1, 2, 3, 0, 0, 0), rtol=0, atol=1e-15
    )


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


def test_a_folder_to_read_that_is_a_loop_of_links_is_one_description_error(tmp_path: Path) -> None:
    folder = model_folder(tmp_path / "models", "bot", '<sdf version="1.7"><model name="m"/></sdf>')
    (tmp_path / "a").symlink_to(tmp_path / "b")
    (tmp_path / "b").symlink_to(tmp_path / "a")
    with pytest.raises(DescriptionError, match=r"a loop of symbolic links"):
        sdf.expand_sdf(folder, PackageFinder(None, {}), [tmp_path / "a"])
