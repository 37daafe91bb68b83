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

from diffbot.errors import DescriptionError
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


# --- rotations --------------------------------------------------------------------------------


def test_a_quaternion_that_is_not_normalised_poses_a_link_in_a_turned_frame(
    tmp_path: Path,
) -> None:
    # The wheel is placed relative to a base that is moved and turned, once by roll, pitch and
    # yaw and once by the same rotation as a quaternion three times too long.
    q = 3.0 * Rotation.from_euler("xyz", LINK[3:]).as_quat()  # x, y, z, w
    base = "<pose>0.1 -0.2 0.05 0.1 -0.2 0.3</pose>"
    text = two_links(f'<pose relative_to="base">{words(LINK)}</pose>').replace(
        '<link name="base"/>', f'<link name="base">{base}</link>'
    )
    as_rpy = expand(tmp_path / "rpy.sdf", text)
    as_quaternion = expand(
        tmp_path / "quaternion.sdf", text.replace(words(LINK), words((*LINK[:3], *q)))
    )
    np.testing.assert_allclose(
        origin(as_quaternion.find("joint")), origin(as_rpy.find("joint")), rtol=0, atol=1e-12
    )
    # Known value: the base's URDF frame keeps its place, not its rotation.
    frame = np.eye(4)
    frame[:3, 3] = (0.1, -0.2, 0.05)
    want = np.linalg.inv(frame) @ matrix(0.1, -0.2, 0.05, 0.1, -0.2, 0.3) @ matrix(*LINK)
    np.testing.assert_allclose(origin(as_quaternion.find("joint")), want, rtol=0, atol=1e-12)


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


# --- joints and plugins -----------------------------------------------------------------------


def test_a_joint_to_the_world_is_left_out_and_the_joints_after_it_kept(tmp_path: Path) -> None:
    world = (
        '<joint name="fix" type="fixed"><parent>world</parent><child>base</child></joint>\n'
        '  <plugin filename="gz-sim-diff-drive-system" name="gz::sim::systems::DiffDrive">'
        "<left_joint>spin</left_joint></plugin>\n"
    )
    text = two_links().replace('<link name="base"/>', f'<link name="base"/>\n  {world}')
    robot = expand(tmp_path / "world.sdf", text)
    assert [j.get("name") for j in robot.iter("joint")] == ["spin"]
    plugin = robot.find("gazebo/plugin")
    assert plugin is not None
    assert (plugin.get("name"), plugin.findtext("left_joint")) == (
        "gz::sim::systems::DiffDrive",
        "spin",
    )


def test_a_joint_to_an_unknown_link_is_named_with_it(tmp_path: Path) -> None:
    path = tmp_path / "unknown.sdf"
    with pytest.raises(DescriptionError) as caught:
        expand(path, two_links().replace("<child>wheel</child>", "<child>tyre</child>"))
    assert str(caught.value) == f"{path}: joint 'spin' names the unknown link 'tyre'"


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


def test_a_relative_include_is_read_beside_the_file_that_includes_it(tmp_path: Path) -> None:
    wheel_model(tmp_path / "robot" / "parts" / "wheel")
    robot = expand(tmp_path / "robot" / "model.sdf", including("parts/wheel"))
    assert links(robot) == ["base", "left::tyre"]


def test_an_include_of_another_scheme_is_refused_by_name(tmp_path: Path) -> None:
    path = tmp_path / "robot.sdf"
    with pytest.raises(DescriptionError) as caught:
        expand(path, including("https://example.com/wheel"))
    assert str(caught.value) == (
        f"{path}: include 'https://example.com/wheel': only model://, package:// and file URIs "
        "are read"
    )
