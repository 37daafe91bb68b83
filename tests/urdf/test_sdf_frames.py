"""SDF models read into URDF, the frames and includes the first SDF tests leave aside: poses as
quaternions that are not normalised, rotations at and near a quarter pitch, axes in the model's
frame of any direction, joints posed in the model's frame, joints to the world, and models found
through a path, the packages given or the simulator's resource paths (diffbot.urdf.sdf)."""

from __future__ import annotations

import math
import os
from pathlib import Path
from xml.etree import ElementTree

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import diffbot
from diffbot.errors import DescriptionError, OutsideRootsError
from diffbot.urdf import sdf
from diffbot.urdf.packages import PackageFinder

#: A child link's pose and a joint's pose (x y z roll pitch yaw), both turned about every axis.
LINK = (0.3, 0.4, 0.1, -1.2, 0.25, 0.7)
JOINT = (0.02, -0.03, 0.04, 0.3, 0.4, -0.5)


def matrix(x: float, y: float, z: float, roll: float, pitch: float, yaw: float) -> np.ndarray:
    """A pose as a 4x4 matrix, by SciPy's fixed-axis x-y-z rotations (R = Rz Ry Rx)."""
    m = np.eye(4)
    m[:3, :3] = Rotation.from_euler("xyz", [roll, pitch, yaw]).as_matrix()
    m[:3, 3] = (x, y, z)
    return m


def origin(element: ElementTree.Element | None) -> np.ndarray:
    """A URDF element's ``<origin>`` as a 4x4 matrix."""
    assert element is not None
    found = element.find("origin")
    assert found is not None
    xyz = [float(v) for v in found.get("xyz", "").split()]
    rpy = [float(v) for v in found.get("rpy", "").split()]
    return matrix(*xyz, *rpy)


def words(values: tuple[float, ...]) -> str:
    return " ".join(repr(float(v)) for v in values)


def two_links(link_pose: str = "", joint: str = "", version: str = "1.9", axis: str = "") -> str:
    """A model of a base link at the origin and a wheel link, joined by a joint ``spin``."""
    return f"""<sdf version="{version}"><model name="two">
  <link name="base"/>
  <link name="wheel">{link_pose}
    <collision name="c"><geometry><sphere><radius>0.05</radius></sphere></geometry></collision>
  </link>
  <joint name="spin" type="continuous"><parent>base</parent><child>wheel</child>
    {joint}<axis><xyz>{axis or "0 0 1"}</xyz></axis></joint>
</model></sdf>
"""


def expand(
    path: Path, text: str | None = None, finder: PackageFinder | None = None
) -> ElementTree.Element:
    if text is not None:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
    urdf, _ = sdf.expand_sdf(path, finder or PackageFinder(None, {}), [path.parent])
    return ElementTree.fromstring(urdf)


def refusal(path: Path, text: str | None = None) -> str:
    """The message of the :class:`DescriptionError` that expanding ``path`` (``text`` written
    to it first) raises."""
    with pytest.raises(DescriptionError) as caught:
        expand(path, text)
    return str(caught.value)


# --- rotations --------------------------------------------------------------------------------


def test_a_quaternion_that_is_not_normalised_poses_a_link_in_a_turned_frame(
    tmp_path: Path,
) -> None:
    # The wheel is placed relative to a moved and turned link, "frame", once by roll, pitch and
    # yaw and once by the same rotation as a quaternion three times too long; its joint's
    # parent is the base at the origin.
    q = 3.0 * Rotation.from_euler("xyz", LINK[3:]).as_quat()  # x, y, z, w
    frame = "<pose>0.1 -0.2 0.05 0.1 -0.2 0.3</pose>"
    text = two_links(f'<pose relative_to="frame">{words(LINK)}</pose>').replace(
        '<link name="base"/>', f'<link name="base"/><link name="frame">{frame}</link>'
    )
    as_rpy = expand(tmp_path / "rpy.sdf", text)
    as_quaternion = expand(
        tmp_path / "quaternion.sdf", text.replace(words(LINK), words((*LINK[:3], *q)))
    )
    np.testing.assert_allclose(
        origin(as_quaternion.find("joint")), origin(as_rpy.find("joint")), rtol=0, atol=1e-12
    )
    want = matrix(0.1, -0.2, 0.05, 0.1, -0.2, 0.3) @ matrix(*LINK)
    np.testing.assert_allclose(origin(as_quaternion.find("joint")), want, rtol=0, atol=1e-12)


def test_a_quaternion_of_halves_is_a_quarter_pitch_and_a_quarter_roll(tmp_path: Path) -> None:
    # (0.5, 0.5, -0.5, 0.5), common in CAD exports: the matrix holds exact zeros where roll and
    # yaw are read, and the rotation must be kept whole all the same.
    collision = "<pose>0 0 0 0.5 0.5 -0.5 0.5</pose>"
    text = two_links().replace('<collision name="c">', f'<collision name="c">{collision}')
    got = origin(expand(tmp_path / "halves.sdf", text).find("link[@name='wheel']/collision"))
    want = Rotation.from_quat([0.5, 0.5, -0.5, 0.5]).as_matrix()
    np.testing.assert_allclose(got[:3, :3], want, rtol=0, atol=1e-12)


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_a_quarter_pitch_rounded_past_one_is_still_a_quarter_pitch(
    tmp_path: Path, sign: float
) -> None:
    # This quaternion's matrix holds sin(pitch) = 1.0000000000000002 after rounding.
    collision = f"<pose>0 0 0 0 {sign * 0.001!r} 0 0.001</pose>"
    text = two_links().replace('<collision name="c">', f'<collision name="c">{collision}')
    robot = expand(tmp_path / "pitch.sdf", text)
    got = origin(robot.find("link[@name='wheel']/collision"))
    np.testing.assert_allclose(got, matrix(0, 0, 0, 0, sign * math.pi / 2, 0), atol=1e-12)


@pytest.mark.parametrize(
    "pose",
    [
        (0.1, 0.2, 0.3, 0.3, math.pi / 2, 0.4),  # gimbal lock, pitch up
        (0.1, 0.2, 0.3, 0.2, -math.pi / 2, -0.7),  # gimbal lock, pitch down
        (0.1, 0.2, 0.3, math.pi / 2, 0.0, 0.5),  # a quarter roll: no lock at all
        (0.0, 0.0, 0.0, 0.4, 1.2, -2.5),
    ],
)
def test_a_joint_pose_keeps_its_rotation_at_and_near_a_quarter_pitch(
    tmp_path: Path, pose: tuple[float, ...]
) -> None:
    robot = expand(tmp_path / "lock.sdf", two_links(joint=f"<pose>{words(pose)}</pose>"))
    np.testing.assert_allclose(origin(robot.find("joint")), matrix(*pose), rtol=0, atol=1e-12)


def test_an_axis_of_any_direction_in_the_model_frame_is_turned_into_the_joints(
    tmp_path: Path,
) -> None:
    # SDF 1.4: the axis is in the model's frame; URDF wants it in the joint's (the wheel's).
    axis = (0.48, 0.6, 0.64)
    text = two_links(f"<pose>{words(LINK)}</pose>", version="1.4", axis=words(axis))
    joint = expand(tmp_path / "axis.sdf", text).find("joint/axis")
    assert joint is not None
    got = [float(v) for v in joint.get("xyz", "").split()]
    want = matrix(*LINK)[:3, :3].T @ axis
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-12)


def test_a_joint_posed_in_the_model_frame_is_not_moved_by_its_child_link(tmp_path: Path) -> None:
    text = two_links(
        f"<pose>{words(LINK)}</pose>", f'<pose relative_to="__model__">{words(JOINT)}</pose>'
    )
    robot = expand(tmp_path / "model_frame.sdf", text)
    np.testing.assert_allclose(origin(robot.find("joint")), matrix(*JOINT), rtol=0, atol=1e-12)
    # The wheel's sphere stays where its link put it: seen from the joint's frame.
    sphere = origin(robot.find("link[@name='wheel']/collision"))
    want = np.linalg.inv(matrix(*JOINT)) @ matrix(*LINK)
    np.testing.assert_allclose(sphere, want, rtol=0, atol=1e-12)


def drive(wheels: str, frames: str = "") -> str:
    """A cart of a chassis at the origin and two wheels (links ``left``, ``right``) on joints
    ``left_joint`` and ``right_joint``; ``wheels`` gives each wheel's pose and axis."""
    cylinder = (
        '<collision name="c"><pose>0 0 0 1.5707963267948966 0 0</pose><geometry><cylinder>'
        "<radius>0.05</radius><length>0.02</length></cylinder></geometry></collision>"
    )
    return (
        f'<sdf version="1.9"><model name="cart"><link name="chassis"/>{frames}'
        f"{wheels.replace('<collision/>', cylinder)}</model></sdf>"
    )


def wheel(name: str, pose: str, axis: str) -> str:
    return (
        f'<link name="{name}">{pose}<collision/></link>'
        f'<joint name="{name}_joint" type="revolute"><parent>chassis</parent>'
        f"<child>{name}</child><axis>{axis}</axis></joint>"
    )


def test_an_axis_expressed_in_another_link_is_turned_into_the_joints(tmp_path: Path) -> None:
    # The right wheel's link is turned half a turn about z; its axis is written as +y of the
    # chassis, so a positive speed rolls it forward, as the left one.
    path = tmp_path / "cart.sdf"
    path.write_text(
        drive(
            wheel("left", "<pose>0 0.2 0 0 0 0</pose>", '<xyz expressed_in="chassis">0 1 0</xyz>')
            + wheel(
                "right",
                "<pose>0 -0.2 0 0 0 3.141592653589793</pose>",
                '<xyz expressed_in="chassis">0 1 0</xyz>',
            )
        ),
        encoding="utf-8",
    )
    params = diffbot.load_params(path, source="description")
    assert (params.left_joint, params.right_joint) == ("left_joint", "right_joint")
    assert (params.left_sign, params.right_sign) == (1, 1)


def test_a_link_posed_relative_to_a_link_written_after_it_is_placed_there(
    tmp_path: Path,
) -> None:
    path = tmp_path / "cart.sdf"
    path.write_text(
        drive(
            wheel("right", '<pose relative_to="left">0 -0.4 0 0 0 0</pose>', "<xyz>0 1 0</xyz>")
            + wheel("left", "<pose>0 0.2 0 0 0 0</pose>", "<xyz>0 1 0</xyz>")
        ),
        encoding="utf-8",
    )
    params = diffbot.load_params(path, source="description")
    assert params.wheel_separation == pytest.approx(0.4, abs=1e-12)


def test_links_posed_relative_to_a_turned_frame_take_its_sides_and_its_axes(
    tmp_path: Path,
) -> None:
    # The axle frame is turned half a turn: the wheel at its -y is on the cart's left, and the
    # wheels' +y axes point to the cart's right, so a positive speed rolls them backwards.
    axle = '<frame name="axle"><pose>0 0 0 0 0 3.141592653589793</pose></frame>'
    path = tmp_path / "cart.sdf"
    path.write_text(
        drive(
            wheel("left", '<pose relative_to="axle">0 -0.2 0 0 0 0</pose>', "<xyz>0 1 0</xyz>")
            + wheel("right", '<pose relative_to="axle">0 0.2 0 0 0 0</pose>', "<xyz>0 1 0</xyz>"),
            axle,
        ),
        encoding="utf-8",
    )
    params = diffbot.load_params(path, source="description")
    assert (params.left_joint, params.right_joint) == ("left_joint", "right_joint")
    assert (params.left_sign, params.right_sign) == (-1, -1)
    assert params.wheel_separation == pytest.approx(0.4, abs=1e-12)


@pytest.mark.parametrize(
    ("left_pose", "message"),
    [
        (
            '<pose relative_to="nowhere">0 0.2 0 0 0 0</pose>',
            "link 'left' names the frame 'nowhere', which the model does not have",
        ),
        (
            '<pose relative_to="right">0 0.2 0 0 0 0</pose>',
            "frames posed relative to each other in a cycle: left -> right -> left",
        ),
    ],
)
def test_a_pose_relative_to_no_frame_or_to_itself_is_named(
    tmp_path: Path, left_pose: str, message: str
) -> None:
    path = tmp_path / "cart.sdf"
    right = '<pose relative_to="left">0 -0.4 0 0 0 0</pose>'
    path.write_text(
        drive(
            wheel("left", left_pose, "<xyz>0 1 0</xyz>") + wheel("right", right, "<xyz>0 1 0</xyz>")
        ),
        encoding="utf-8",
    )
    assert refusal(path) == f"{path}: {message}"


# --- joints and plugins -----------------------------------------------------------------------


def test_a_joint_to_the_world_is_left_out_and_the_joints_after_it_kept(tmp_path: Path) -> None:
    # The world joint's child is no link of this model: it is left out all the same, and the
    # joints after it keep their frames.
    world = (
        '<joint name="fix" type="fixed"><parent>world</parent><child>ground</child></joint>\n'
        '  <plugin filename="gz-sim-diff-drive-system" name="gz::sim::systems::DiffDrive">'
        "<left_joint>\n    spin\n  </left_joint></plugin>\n"
    )
    text = two_links(f"<pose>{words(LINK)}</pose>").replace(
        '<link name="base"/>', f'<link name="base"/>\n  {world}'
    )
    robot = expand(tmp_path / "world.sdf", text)
    assert [j.get("name") for j in robot.iter("joint")] == ["spin"]
    np.testing.assert_allclose(origin(robot.find("joint")), matrix(*LINK), rtol=0, atol=1e-12)
    gazebo = robot.find("gazebo")
    assert gazebo is not None
    assert (gazebo.text or "").strip() == ""
    plugin = gazebo.find("plugin")
    assert plugin is not None
    assert (plugin.get("name"), plugin.findtext("left_joint")) == (
        "gz::sim::systems::DiffDrive",
        "\n    spin\n  ",
    )


def test_a_joint_to_an_unknown_link_is_named_with_it(tmp_path: Path) -> None:
    path = tmp_path / "unknown.sdf"
    assert (
        refusal(path, two_links().replace("<child>wheel</child>", "<child>tyre</child>"))
        == f"{path}: joint 'spin' names the unknown link 'tyre'"
    )


# --- includes ---------------------------------------------------------------------------------

WHEEL = """<sdf version="1.9"><model name="{name}"><link name="{link}">
  <collision name="c"><geometry><sphere><radius>0.05</radius></sphere></geometry></collision>
</link></model></sdf>
"""
CONFIG = '<?xml version="1.0"?><model><name>w</name><sdf version="1.9">model.sdf</sdf></model>'


def wheel_model(folder: Path, link: str = "tyre") -> Path:
    folder.mkdir(parents=True)
    (folder / "model.config").write_text(CONFIG, encoding="utf-8")
    (folder / "model.sdf").write_text(WHEEL.format(name="wheel", link=link), encoding="utf-8")
    return folder


def including(uri: str) -> str:
    return (
        '<sdf version="1.9"><model name="robot"><link name="base"/>'
        f"<include><uri>{uri}</uri><name>left</name></include></model></sdf>"
    )


def links(robot: ElementTree.Element) -> list[str | None]:
    return [link.get("name") for link in robot.iter("link")]


def test_a_model_uri_may_name_a_file_in_the_model(tmp_path: Path) -> None:
    folder = wheel_model(tmp_path / "models" / "wheel")
    (folder / "other.sdf").write_text(WHEEL.format(name="w", link="rim"), encoding="utf-8")
    robot = expand(
        tmp_path / "models" / "robot" / "model.sdf", including("model://wheel/other.sdf")
    )
    assert links(robot) == ["base", "left::rim"]


def test_a_model_is_found_among_the_packages_given(tmp_path: Path) -> None:
    folder = wheel_model(tmp_path / "elsewhere" / "wheel")
    finder = PackageFinder(None, {"wheel": folder})
    robot = expand(tmp_path / "robot" / "model.sdf", including("model://wheel"), finder)
    assert links(robot) == ["base", "left::tyre"]


def test_a_model_is_found_in_any_folder_of_the_resource_path_even_through_a_link(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    wheel_model(tmp_path / "installed" / "wheel")
    (tmp_path / "linked").mkdir()
    os.symlink(tmp_path / "installed" / "wheel", tmp_path / "linked" / "wheel")
    monkeypatch.delenv("AMENT_PREFIX_PATH", raising=False)
    for variable in ("GZ_SIM_RESOURCE_PATH", "IGN_GAZEBO_RESOURCE_PATH", "GAZEBO_MODEL_PATH"):
        monkeypatch.delenv(variable, raising=False)
    paths = os.pathsep.join(["", str(tmp_path / "empty"), str(tmp_path / "linked")])
    monkeypatch.setenv("GZ_SIM_RESOURCE_PATH", paths)
    robot = expand(tmp_path / "robot" / "model.sdf", including("model://wheel"))
    assert links(robot) == ["base", "left::tyre"]
    # An empty entry is no folder, not even the current one.
    wheel_model(tmp_path / "here" / "wheel")
    monkeypatch.chdir(tmp_path / "here")
    monkeypatch.setenv("GZ_SIM_RESOURCE_PATH", os.pathsep.join(["", str(tmp_path / "empty")]))
    with pytest.raises(DescriptionError, match="model 'wheel' of 'model://wheel' not found"):
        expand(tmp_path / "robot" / "model.sdf")


def test_a_relative_include_is_read_beside_the_file_that_includes_it(tmp_path: Path) -> None:
    wheel_model(tmp_path / "robot" / "parts" / "wheel")
    robot = expand(tmp_path / "robot" / "model.sdf", including("parts/wheel"))
    assert links(robot) == ["base", "left::tyre"]


def test_an_include_of_another_scheme_is_refused_by_name(tmp_path: Path) -> None:
    path = tmp_path / "robot.sdf"
    assert refusal(path, including("https://example.com/wheel")) == (
        f"{path}: include 'https://example.com/wheel': only model://, package:// and file URIs "
        "are read"
    )


# --- model files, names and bounds ------------------------------------------------------------


def test_a_model_in_a_world_is_read_and_names_the_robot(tmp_path: Path) -> None:
    text = (
        two_links()
        .replace("<model", '<world name="w"><model')
        .replace("</model>", "</model></world>")
    )
    robot = expand(tmp_path / "world.sdf", text)
    assert robot.get("name") == "two"
    assert links(robot) == ["base", "wheel"]


def test_a_model_without_a_name_is_named_for_its_file(tmp_path: Path) -> None:
    robot = expand(tmp_path / "nameless.sdf", two_links().replace(' name="two"', ""))
    assert robot.get("name") == "nameless"
    assert expand(tmp_path / "named.sdf", two_links()).get("name") == "two"


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("<robot name='r'/>", "not SDF: the root element is <robot>"),
        ("<sdf version='1.9'/>", "expected one <model>, found 0: give the robot's model file"),
        (
            "<sdf version='1.9'><model name='a'/><model name='b'/></sdf>",
            "expected one <model>, found 2: give the robot's model file",
        ),
        ("<sdf version='1.9'><model", "malformed XML: unclosed token: line 1, column 19"),
    ],
)
def test_a_file_that_is_no_single_sdf_model_is_named_with_the_reason(
    tmp_path: Path, text: str, message: str
) -> None:
    path = tmp_path / "bad.sdf"
    assert refusal(path, text) == f"{path}: {message}"


def test_a_fifo_is_refused_as_no_sdf_file(tmp_path: Path) -> None:
    fifo = tmp_path / "pipe.sdf"
    os.mkfifo(fifo)
    assert refusal(fifo) == (
        f"{fifo}: not a regular file (a FIFO, socket or device), not an SDF file"
    )


def test_a_file_of_the_largest_size_is_read_and_one_byte_more_refused(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    text = two_links()
    monkeypatch.setattr(sdf, "MAX_FILE_BYTES", len(text.encode()))
    assert links(expand(tmp_path / "exact.sdf", text)) == ["base", "wheel"]
    path = tmp_path / "over.sdf"
    with pytest.raises(sdf.ExpansionLimitError) as caught:
        expand(path, text + " ")
    assert str(caught.value) == f"{path}: larger than {len(text.encode())} bytes, refused"


def nested(depth: int) -> str:
    """A model holding models ``depth`` deep, the innermost with a link."""
    inner = '<link name="l"/>'
    for level in range(depth):
        inner = f'<model name="n{level}">{inner}</model>'
    return f'<sdf version="1.9"><model name="top"><link name="base"/>{inner}</model></sdf>'


def test_models_nested_as_deep_as_allowed_are_read_and_one_deeper_refused(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(sdf, "MAX_DEPTH", 2)
    assert links(expand(tmp_path / "two.sdf", nested(2))) == ["base", "n1::n0::l"]
    path = tmp_path / "three.sdf"
    with pytest.raises(sdf.ExpansionLimitError) as caught:
        expand(path, nested(3))
    assert str(caught.value) == f"{path}: models nested more than 2 deep (max_depth)"
    # An included model is one level deeper too.
    (tmp_path / "inner.sdf").write_text(nested(1), encoding="utf-8")
    include = '<include><uri>inner.sdf</uri><name>i</name></include><link name="base"/>'
    top = f'<sdf version="1.9"><model name="t">{include}</model></sdf>'
    assert links(expand(tmp_path / "top.sdf", top)) == ["base", "i::base", "i::n0::l"]
    deeper = f'<sdf version="1.9"><model name="t"><model name="m">{include}</model></model></sdf>'
    with pytest.raises(sdf.ExpansionLimitError):
        expand(tmp_path / "deeper.sdf", deeper)


def test_as_many_includes_as_allowed_are_read_and_one_more_refused(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(sdf, "MAX_INCLUDES", 2)
    wheel_model(tmp_path / "parts" / "wheel")

    def includes(count: int) -> str:
        body = "".join(
            f"<include><uri>parts/wheel</uri><name>w{k}</name></include>" for k in range(count)
        )
        return f'<sdf version="1.9"><model name="r"><link name="base"/>{body}</model></sdf>'

    assert links(expand(tmp_path / "two.sdf", includes(2))) == ["base", "w0::tyre", "w1::tyre"]
    path = tmp_path / "three.sdf"
    with pytest.raises(sdf.ExpansionLimitError) as caught:
        expand(path, includes(3))
    assert str(caught.value) == f"{path}: more than 2 included models, refused"


def test_an_include_without_a_name_takes_its_models_folder_name(tmp_path: Path) -> None:
    wheel_model(tmp_path / "parts" / "wheel")
    text = including("parts/wheel").replace("<name>left</name>", "")
    assert links(expand(tmp_path / "robot.sdf", text)) == ["base", "wheel::tyre"]


def test_a_nested_model_is_placed_by_its_pose_and_reads_includes_beside_its_file(
    tmp_path: Path,
) -> None:
    wheel_model(tmp_path / "parts" / "wheel")
    text = (
        '<sdf version="1.9"><model name="r"><link name="base"/>'
        '<model name="arm"><pose>1 2 3 0 0 0</pose><link name="hand"/>'
        "<include><uri>parts/wheel</uri><name>w</name></include>"
        '<joint name="j" type="fixed"><parent>hand</parent><child>w::tyre</child></joint>'
        "</model>"
        '<joint name="k" type="fixed"><parent>base</parent><child>arm::hand</child></joint>'
        "</model></sdf>"
    )
    robot = expand(tmp_path / "robot.sdf", text)
    assert links(robot) == ["base", "arm::hand", "arm::w::tyre"]
    hand = robot.find("joint[@name='k']")
    np.testing.assert_allclose(origin(hand), matrix(1, 2, 3, 0, 0, 0), rtol=0, atol=1e-12)


def test_an_sdf_1_4_nested_model_has_its_axes_in_the_model_frame(tmp_path: Path) -> None:
    inner = two_links(f"<pose>{words(LINK)}</pose>", version="1.4", axis="0 1 0")
    inner = inner.replace('<sdf version="1.4"><model name="two">', "").replace("</model></sdf>", "")
    text = f'<sdf version="1.4"><model name="top"><model name="two">{inner}</model></model></sdf>'
    axis = expand(tmp_path / "legacy.sdf", text).find("joint/axis")
    assert axis is not None
    got = [float(v) for v in axis.get("xyz", "").split()]
    want = matrix(*LINK)[:3, :3].T @ [0.0, 1.0, 0.0]
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-12)


@pytest.mark.parametrize(("version", "legacy"), [("1.4.1", True), ("1.10.0", False)])
def test_a_version_with_a_patch_number_is_read_by_its_major_and_minor(
    tmp_path: Path, version: str, legacy: bool
) -> None:
    text = two_links(f"<pose>{words(LINK)}</pose>", version=version, axis="0 1 0")
    axis = expand(tmp_path / "version.sdf", text).find("joint/axis")
    assert axis is not None
    got = [float(v) for v in axis.get("xyz", "").split()]
    want = matrix(*LINK)[:3, :3].T @ [0.0, 1.0, 0.0] if legacy else [0.0, 1.0, 0.0]
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-12)


def test_a_visual_is_a_shape_of_the_urdf_too(tmp_path: Path) -> None:
    text = two_links().replace("<collision", "<visual").replace("</collision>", "</visual>")
    robot = expand(tmp_path / "visual.sdf", text)
    assert robot.find("link[@name='wheel']/visual/geometry/sphere") is not None
    assert robot.find("link[@name='wheel']/collision") is None


def test_a_quaternion_pose_must_have_seven_numbers(tmp_path: Path) -> None:
    path = tmp_path / "quat.sdf"
    for pose, count in (("1 2 3 0 0 0", 7), ("1 2 3 0 0 0 x", 7)):
        text = two_links(f'<pose rotation_format="quat_xyzw">{pose}</pose>')
        assert refusal(path, text) == (
            f"{path}: model 'two' link 'wheel' <pose>: expected {count} finite numbers, "
            f"got '{pose}'"
        )


def test_a_malformed_include_pose_is_named_with_its_uri(tmp_path: Path) -> None:
    wheel_model(tmp_path / "parts" / "wheel")
    path = tmp_path / "robot.sdf"
    text = including("parts/wheel").replace("<name>", "<pose>1</pose><name>")
    assert refusal(path, text) == (
        f"{path}: model 'robot' include 'parts/wheel' <pose>: expected 6 finite numbers, got '1'"
    )


def test_trust_reads_beyond_the_folders_and_without_it_the_refusal_names_them(
    tmp_path: Path,
) -> None:
    wheel_model(tmp_path / "outside" / "wheel")
    path = tmp_path / "robot" / "robot.sdf"
    path.parent.mkdir()
    path.write_text(including("../outside/wheel"), encoding="utf-8")
    finder = PackageFinder(None, {})
    (tmp_path / "shared").mkdir()
    with pytest.raises(OutsideRootsError) as caught:
        sdf.expand_sdf(path, finder, [tmp_path / "shared"])
    assert str(caught.value) == (
        f"{path.parent / '..' / 'outside' / 'wheel'}: reading refused in an untrusted "
        f"description: it is outside the description's folders ({tmp_path / 'shared'}, "
        f"{path.parent}); trust the description (trust=True) to let it read any file"
    )
    urdf, files = sdf.expand_sdf(path, finder, [], trust=True)
    assert 'name="left::tyre"' in urdf
    assert files == (path, path.parent / ".." / "outside" / "wheel" / "model.sdf")


def test_a_file_without_folders_given_may_read_beside_itself(tmp_path: Path) -> None:
    wheel_model(tmp_path / "parts" / "wheel")
    path = tmp_path / "robot.sdf"
    path.write_text(including("parts/wheel"), encoding="utf-8")
    urdf, _ = sdf.expand_sdf(path, PackageFinder(None, {}), [])
    assert 'name="left::tyre"' in urdf


# --- models posed relative to a frame ---------------------------------------------------------

#: A wheel of radius 0.07 in a model of its own, standing on its axle (its cylinder's axis is the
#: link's z).
WHEEL_MODEL = (
    '<model name="{0}">{1}<link name="wheel"><collision name="c"><geometry><cylinder>'
    "<radius>0.07</radius><length>0.04</length></cylinder></geometry></collision></link></model>"
)


def axle_cart(left: str, right: str) -> str:
    """A cart whose wheels (``left``, ``right``: their models, or includes) hang from an axle
    link turned half a turn about z and written after them, on joints of axis z."""
    joints = "".join(
        f'<joint name="{side}_joint" type="revolute"><parent>axle</parent>'
        f"<child>{side}::wheel</child><axis><xyz>0 0 1</xyz></axis></joint>"
        for side in ("left", "right")
    )
    return (
        f'<sdf version="1.9"><model name="cart"><link name="chassis"/>{left}{right}'
        '<link name="axle"><pose>0.1 0 0.05 0 0 3.141592653589793</pose></link>'
        '<joint name="axle_fixed" type="fixed"><parent>chassis</parent><child>axle</child>'
        f"</joint>{joints}</model></sdf>"
    )


#: Each wheel's pose relative to the turned axle: the left one at the axle's -y (the cart's +y),
#: rolled +pi/2 so that its axis, -y of the axle, is +y of the cart.
AXLE_POSE = '<pose relative_to="axle">0 {0} 0 1.5707963267948966 0 0</pose>'


@pytest.mark.parametrize("included", [False, True])
def test_wheel_models_posed_relative_to_a_turned_link_take_its_sides_and_its_axes(
    tmp_path: Path, included: bool
) -> None:
    wheel = WHEEL_MODEL.format
    if included:  # the same models, each an <include> of one wheel file
        (tmp_path / "wheel.sdf").write_text(
            f'<sdf version="1.9">{WHEEL_MODEL.format("wheel", "")}</sdf>', encoding="utf-8"
        )
        wheel = "<include><uri>wheel.sdf</uri><name>{0}</name>{1}</include>".format
    text = axle_cart(wheel("left", AXLE_POSE.format(-0.25)), wheel("right", AXLE_POSE.format(0.25)))
    path = tmp_path / "cart.sdf"
    path.write_text(text, encoding="utf-8")
    params = diffbot.load_params(path, source="description")
    assert (params.left_joint, params.right_joint) == ("left_joint", "right_joint")
    assert (params.left_sign, params.right_sign) == (1, 1)
    assert params.wheel_separation == pytest.approx(0.5, abs=1e-12)
    assert params.wheel_radius == pytest.approx(0.07, abs=1e-12)


def test_a_nested_model_posed_relative_to_no_frame_is_named(tmp_path: Path) -> None:
    pose = '<pose relative_to="nowhere">0 0.2 0 0 0 0</pose>'
    path = tmp_path / "cart.sdf"
    text = axle_cart(WHEEL_MODEL.format("left", pose), WHEEL_MODEL.format("right", ""))
    assert refusal(path, text) == (
        f"{path}: model 'left' names the frame 'nowhere', which the model does not have"
    )


def test_a_collision_posed_relative_to_the_model_is_placed_and_turned_there(
    tmp_path: Path,
) -> None:
    # Each wheel link is rolled to stand on its axle; its cylinder is posed in the model's frame,
    # 3 cm further out and with the same roll: it lies along the axle, its mid-plane at +-0.23.
    def side(name: str, y: float) -> str:
        roll = "-1.5707963267948966 0 0"
        return (
            f'<link name="{name}"><pose>0 {y} 0.1 {roll}</pose><collision name="c">'
            f'<pose relative_to="__model__">0 {y * 1.15:.2f} 0.1 {roll}</pose><geometry>'
            "<cylinder><radius>0.1</radius><length>0.04</length></cylinder></geometry>"
            f'</collision></link><joint name="{name}_joint" type="revolute"><parent>chassis'
            f"</parent><child>{name}</child><axis><xyz>0 0 1</xyz></axis></joint>"
        )

    path = tmp_path / "cart.sdf"
    path.write_text(drive(side("left", 0.2) + side("right", -0.2)), encoding="utf-8")
    params = diffbot.load_params(path, source="description")
    assert params.wheel_separation == pytest.approx(0.46, abs=1e-12)
    assert (params.left_sign, params.right_sign) == (1, 1)
    assert params.warnings == ()


def test_a_joint_between_frames_and_models_joins_the_links_they_are_attached_to(
    tmp_path: Path,
) -> None:
    # SDF 1.8: a joint's parent and child may be any frame. The wheels hang from a frame attached
    # to the chassis; the left joint's child is a hub frame of its wheel, rolled so that its z is
    # +y (the joint's frame is the hub's); the right one's child is a nested model, whose frame
    # is the joint's and whose link moves with it, with the axis -y.
    cylinder = (
        '<collision name="c"><pose>0 0 0 1.5707963267948966 0 0</pose><geometry><cylinder>'
        "<radius>0.08</radius><length>0.04</length></cylinder></geometry></collision>"
    )
    text = (
        '<sdf version="1.8"><model name="bot"><link name="chassis"><pose>0 0 0.1 0 0 0</pose>'
        '</link><frame name="footprint" attached_to="chassis"><pose>0 0 -0.1 0 0 0</pose></frame>'
        f'<link name="left_wheel"><pose>0.05 0.22 0.08 0 0 0</pose>{cylinder}</link>'
        '<frame name="left_hub" attached_to="left_wheel">'
        "<pose>0 0 0 -1.5707963267948966 0 0</pose></frame>"
        '<model name="right_wheel"><pose>0.05 -0.22 0.08 0 0 0</pose>'
        f'<link name="rim">{cylinder}</link></model>'
        '<joint name="left_joint" type="continuous"><parent>footprint</parent>'
        "<child>left_hub</child><axis><xyz>0 0 1</xyz></axis></joint>"
        '<joint name="right_joint" type="continuous"><parent>footprint</parent>'
        "<child>right_wheel</child><axis><xyz>0 -1 0</xyz></axis></joint>"
        "</model></sdf>"
    )
    path = tmp_path / "bot.sdf"
    robot = expand(path, text)
    ends = [(j.get("name"), j.find("parent"), j.find("child")) for j in robot.iter("joint")]
    assert [
        (n, p.get("link"), c.get("link")) for n, p, c in ends if p is not None and c is not None
    ] == [
        ("left_joint", "chassis", "left_wheel"),
        ("right_joint", "chassis", "right_wheel::rim"),
    ]
    params = diffbot.load_params(path, source="description")
    assert (params.left_joint, params.right_joint) == ("left_joint", "right_joint")
    assert (params.left_sign, params.right_sign) == (1, -1)
    assert params.wheel_separation == pytest.approx(0.44, abs=1e-12)
    assert params.warnings == ()
