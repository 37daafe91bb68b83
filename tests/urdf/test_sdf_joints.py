"""SDF joints, shapes and model folders as URDF has them, case by case: every joint type, limits
at the edges of a full turn, axes in the parent model's frame, joints of included models, names
that need escaping, and one message for each malformed number (diffbot.urdf.sdf)."""

from __future__ import annotations

from pathlib import Path
from xml.etree import ElementTree

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import diffbot
from diffbot.errors import DescriptionError
from diffbot.urdf import sdf
from diffbot.urdf.packages import PackageFinder

SPHERE = (
    '<collision name="c"><geometry><sphere><radius>0.05</radius></sphere></geometry></collision>'
)


def expand(path: Path, text: str | None = None) -> ElementTree.Element:
    if text is not None:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
    urdf, _ = sdf.expand_sdf(path, PackageFinder(None, {}), [path.parent])
    return ElementTree.fromstring(urdf)


def model(body: str, version: str = "1.9") -> str:
    return f'<sdf version="{version}"><model name="m"><link name="base"/>{body}</model></sdf>'


def joint(name: str, kind: str, limit: str = "", child: str = "") -> str:
    """A link ``name`` and a joint ``name`` of ``kind`` moving it, with ``<limit>`` contents."""
    axis = f"<axis><xyz>0 1 0</xyz><limit>{limit}</limit></axis>" if limit else ""
    return (
        f'<link name="{child or name}">{SPHERE}</link>'
        f'<joint name="{name}" type="{kind}"><parent>base</parent><child>{child or name}</child>'
        f"{axis}</joint>"
    )


def test_every_sdf_joint_type_has_its_urdf_type(tmp_path: Path) -> None:
    body = "".join(
        joint(kind, kind)
        for kind in ("ball", "universal", "gearbox", "screw", "prismatic", "fixed", "revolute2")
    )
    body += f'<link name="untyped">{SPHERE}</link><joint name="untyped"><parent>base</parent>'
    body += "<child>untyped</child></joint>"
    robot = expand(tmp_path / "kinds.sdf", model(body))
    kinds = {j.get("name"): j.get("type") for j in robot.iter("joint")}
    assert kinds == {
        "ball": "fixed",
        "universal": "fixed",
        "gearbox": "fixed",
        "screw": "fixed",
        "prismatic": "prismatic",
        "fixed": "fixed",
        "revolute2": "revolute2",  # no URDF type: left for the URDF reader to name
        "untyped": "fixed",  # SDF's default
    }


@pytest.mark.parametrize(
    ("limit", "kind", "attributes"),
    [
        # From -pi to pi, as many wheels are written: a whole turn, so continuous.
        ("<lower>-3.141592653589793</lower><upper>3.141592653589793</upper>", "continuous", None),
        ("<lower>0</lower><upper>6.5</upper>", "continuous", None),
        (
            "<lower>-6</lower><upper>0</upper>",
            "revolute",
            {"effort": "0", "lower": "-6.0", "upper": "0.0"},
        ),
        # An empty bound reads as 0.
        (
            "<lower></lower><upper>1</upper>",
            "revolute",
            {"effort": "0", "lower": "0.0", "upper": "1.0"},
        ),
        ("<lower>-1</lower>", "continuous", None),  # one bound only: no bounds
        (
            "<upper>1</upper><velocity>0.5</velocity>",
            "continuous",
            {"effort": "0", "velocity": "0.5"},
        ),
        (
            "<lower>-1</lower><upper>1</upper><velocity>0</velocity>",
            "revolute",
            {"effort": "0", "lower": "-1.0", "upper": "1.0"},
        ),  # a velocity of 0 is no limit
    ],
)
def test_revolute_limits_at_the_edges_of_a_full_turn(
    tmp_path: Path, limit: str, kind: str, attributes: dict[str, str] | None
) -> None:
    robot = expand(tmp_path / "limits.sdf", model(joint("j", "revolute", limit)))
    found = robot.find("joint")
    assert found is not None
    assert found.get("type") == kind
    element = found.find("limit")
    assert (None if element is None else element.attrib) == attributes


@pytest.mark.parametrize("flag", ["true", "1"])
def test_an_axis_in_the_parent_model_frame_is_turned_into_the_joints(
    tmp_path: Path, flag: str
) -> None:
    rpy = (0.3, 0.2, 0.5)
    body = (
        f'<link name="w"><pose>0 0 0 {" ".join(map(repr, rpy))}</pose>{SPHERE}</link>'
        '<joint name="j" type="continuous"><parent>base</parent><child>w</child>'
        f"<axis><xyz>0 1 0</xyz><use_parent_model_frame>{flag}</use_parent_model_frame></axis>"
        "</joint>"
    )
    axis = expand(tmp_path / "axis.sdf", model(body, "1.6")).find("joint/axis")
    assert axis is not None
    got = [float(v) for v in axis.get("xyz", "").split()]
    want = Rotation.from_euler("xyz", rpy).as_matrix().T @ [0.0, 1.0, 0.0]
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-12)
    false = body.replace(f">{flag}<", ">false<")
    axis = expand(tmp_path / "false.sdf", model(false, "1.6")).find("joint/axis")
    assert axis is not None
    assert axis.get("xyz") == "0.0 1.0 0.0"


def test_joints_of_an_included_model_keep_their_links_frames_and_the_world(
    tmp_path: Path,
) -> None:
    wheel = model(
        '<link name="w"><pose>0 0.2 0 0 0 0</pose></link>'
        '<joint name="fix" type="fixed"><parent>world</parent><child>base</child></joint>'
        '<joint name="j" type="continuous"><parent>base</parent><child>w</child>'
        '<pose relative_to="base">0 0.1 0 0 0 0</pose><axis><xyz>0 0 1</xyz></axis></joint>'
        '<joint name="k" type="fixed"><parent>base</parent><child>w2</child>'
        '<pose relative_to="__model__">0.5 0 0 0 0 0</pose></joint>'
        '<link name="w2"><pose>0 0 1 0 0 0</pose></link>'
    )
    (tmp_path / "parts").mkdir()
    (tmp_path / "parts" / "wheel.sdf").write_text(wheel, encoding="utf-8")
    top = (
        '<sdf version="1.9"><model name="robot"><link name="body"/>'
        "<include><uri>parts/wheel.sdf</uri><name>left</name><pose>1 2 0 0 0 0</pose></include>"
        "</model></sdf>"
    )
    robot = expand(tmp_path / "robot.sdf", top)
    joints = {j.get("name"): j for j in robot.iter("joint")}
    assert set(joints) == {"left::j", "left::k"}  # the joint to the world left out
    parent = joints["left::j"].find("parent")
    assert parent is not None
    assert parent.get("link") == "left::base"
    origin = joints["left::j"].find("origin")
    assert origin is not None
    # In the included model's base frame, as written.
    assert [float(v) for v in origin.get("xyz", "").split()] == pytest.approx(
        [0.0, 0.1, 0.0], abs=1e-12
    )
    origin = joints["left::k"].find("origin")
    assert origin is not None
    assert [float(v) for v in origin.get("xyz", "").split()] == pytest.approx(
        [0.5, 0.0, 0.0], abs=1e-12
    )


def test_names_that_need_escaping_come_back_as_written(tmp_path: Path) -> None:
    name = 'a&b"c<d'
    escaped = "a&amp;b&quot;c&lt;d"
    body = (
        f'<link name="{escaped}">{SPHERE}</link>'
        f'<joint name="{escaped}" type="continuous"><parent>base</parent>'
        f"<child>{escaped}</child><axis><xyz>0 1 0</xyz></axis></joint>"
    )
    robot = expand(tmp_path / "names.sdf", model(body).replace('name="m"', f'name="{escaped}"'))
    assert robot.get("name") == name
    assert [link.get("name") for link in robot.iter("link")] == ["base", name]
    found = robot.find("joint")
    assert found is not None
    child = found.find("child")
    assert child is not None
    assert (found.get("name"), child.get("link")) == (name, name)


# --- poses, shapes and model folders ----------------------------------------------------------


def test_an_empty_pose_is_the_frame_it_is_relative_to(tmp_path: Path) -> None:
    body = (
        '<link name="w"><pose relative_to="base"/></link><link name="v"><pose></pose></link>'
        '<joint name="j" type="fixed"><parent>base</parent><child>w</child></joint>'
        '<joint name="k" type="fixed"><parent>w</parent><child>v</child></joint>'
    )
    text = model(body).replace(
        '<link name="base"/>', '<link name="base"><pose>1 2 3 0 0 0.5</pose></link>'
    )
    robot = expand(tmp_path / "empty.sdf", text)
    origins = {j.get("name"): j.find("origin") for j in robot.iter("joint")}
    first, second = origins["j"], origins["k"]
    assert first is not None
    assert second is not None
    # w sits on the base (turned by its 0.5 rad of yaw); v at the model's origin, seen from w.
    assert [float(v) for v in first.get("xyz", "").split()] == [0.0, 0.0, 0.0]
    assert [float(v) for v in first.get("rpy", "").split()] == pytest.approx(
        [0.0, 0.0, 0.5], abs=1e-12
    )
    turn = Rotation.from_euler("z", 0.5).as_matrix()
    assert [float(v) for v in second.get("xyz", "").split()] == pytest.approx(
        list(-turn.T @ [1.0, 2.0, 3.0]), abs=1e-12
    )


def test_a_mesh_is_no_shape_of_the_urdf(tmp_path: Path) -> None:
    mesh = '<collision name="m"><geometry><mesh><uri>w.dae</uri></mesh></geometry></collision>'
    robot = expand(tmp_path / "mesh.sdf", model(f'<link name="w">{mesh}</link>'))
    assert robot.find("link[@name='w']/collision") is None


@pytest.mark.parametrize(
    ("element", "message"),
    [
        (
            "<cylinder><radius>r</radius><length>1</length></cylinder>",
            "radius: expected 1 finite numbers, got 'r'",
        ),
        (
            "<cylinder><radius>1</radius><length>l</length></cylinder>",
            "length: expected 1 finite numbers, got 'l'",
        ),
        ("<sphere><radius>nan</radius></sphere>", "radius: expected 1 finite numbers, got 'nan'"),
        ("<box><size>a b c</size></box>", "size: expected 3 finite numbers, got 'a b c'"),
    ],
)
def test_a_malformed_shape_is_named_with_its_link(
    tmp_path: Path, element: str, message: str
) -> None:
    path = tmp_path / "shape.sdf"
    collision = f'<collision name="c"><geometry>{element}</geometry></collision>'
    with pytest.raises(DescriptionError) as caught:
        expand(path, model(f'<link name="w">{collision}</link>'))
    assert str(caught.value) == f"{path}: model 'm' link 'w' {message}"


def test_malformed_poses_and_axes_are_named_with_their_element(tmp_path: Path) -> None:
    path = tmp_path / "pose.sdf"
    collision = SPHERE.replace("<geometry>", "<pose>1 2</pose><geometry>")
    with pytest.raises(DescriptionError) as caught:
        expand(path, model(f'<link name="w">{collision}</link>'))
    assert (
        str(caught.value)
        == f"{path}: model 'm' link 'w' <pose>: expected 6 finite numbers, got '1 2'"
    )
    body = (
        '<link name="w"/><joint name="j" type="continuous"><parent>base</parent>'
        "<child>w</child><axis/></joint>"
    )
    with pytest.raises(DescriptionError) as caught:
        expand(path, model(body))
    assert str(caught.value) == f"{path}: model 'm' joint 'j': expected 3 finite numbers, got None"


def test_a_model_folder_without_a_config_is_read_from_its_model_sdf(tmp_path: Path) -> None:
    folder = tmp_path / "plain"
    robot = expand(folder / "model.sdf", model(f'<link name="w">{SPHERE}</link>'))
    assert [link.get("name") for link in robot.iter("link")] == ["base", "w"]
    assert sdf.model_file(folder) == folder / "model.sdf"
    # A config naming no file falls back to model.sdf too.
    (folder / "model.config").write_text(
        "<model><sdf version='1.9'></sdf></model>", encoding="utf-8"
    )
    assert sdf.model_file(folder) == folder / "model.sdf"


def test_a_folder_that_is_no_model_is_named_as_such(tmp_path: Path) -> None:
    with pytest.raises(DescriptionError) as caught:
        sdf.model_file(tmp_path)
    assert str(caught.value) == (
        f"{tmp_path}: is a directory, but no model folder (no model.config naming an SDF file, "
        "no model.sdf)"
    )


def test_a_limit_that_is_no_number_is_a_description_error(tmp_path: Path) -> None:
    path = tmp_path / "limit.sdf"
    with pytest.raises(DescriptionError) as caught:
        expand(path, model(joint("j", "revolute", "<lower>low</lower><upper>1</upper>")))
    assert str(caught.value) == f"{path}: model 'm' joint 'j': a limit must be a number, got 'low'"


def test_malformed_joint_and_nested_model_poses_are_named(tmp_path: Path) -> None:
    path = tmp_path / "poses.sdf"
    body = joint("j", "fixed").replace("<parent>", "<pose>1</pose><parent>")
    with pytest.raises(DescriptionError) as caught:
        expand(path, model(body))
    assert str(caught.value) == (
        f"{path}: model 'm' joint 'j' <pose>: expected 6 finite numbers, got '1'"
    )
    with pytest.raises(DescriptionError) as caught:
        expand(path, model('<model name="n"><pose>2</pose></model>'))
    assert str(caught.value) == f"{path}: model 'n' <pose>: expected 6 finite numbers, got '2'"


def _wheeled(version: str) -> str:
    """A TurtleBot3-like model: wheel joints posed turned about x in their wheels' frames, an
    axis of 0 0 1 in the joint's frame (lateral in SDF 1.5, vertical if read as 1.4's)."""
    wheels = "".join(
        f'<link name="{side}"><collision name="c"><pose>0 {y} 0.023 -1.57 0 0</pose><geometry>'
        "<cylinder><radius>0.033</radius><length>0.018</length></cylinder></geometry>"
        f'</collision></link><joint name="{side}_joint" type="revolute"><parent>base_link'
        f"</parent><child>{side}</child><pose>0 {y} 0.023 -1.57 0 0</pose>"
        "<axis><xyz>0 0 1</xyz></axis></joint>"
        for side, y in (("wheel_left", 0.08), ("wheel_right", -0.08))
    )
    model = f'<model name="burger"><link name="base_link"/>{wheels}</model>'
    return f'<sdf version="{version}">{model}</sdf>'


@pytest.mark.parametrize(
    "listed",
    [("1.4", "1.5"), ("1.5", "1.4")],
)
def test_a_model_folder_is_read_in_the_highest_sdf_version_its_model_config_lists(
    tmp_path: Path, listed: tuple[str, str]
) -> None:
    # TurtleBot3's model folders list model-1_4.sdf before model.sdf; Gazebo loads the highest
    # version its parser reads, whatever the order.
    files = {"1.4": "model-1_4.sdf", "1.5": "model.sdf"}
    for version, name in files.items():
        (tmp_path / name).write_text(_wheeled(version), encoding="utf-8")
    entries = "".join(f'<sdf version="{v}">{files[v]}</sdf>' for v in listed)
    (tmp_path / "model.config").write_text(f"<model>{entries}</model>", encoding="utf-8")
    assert sdf.model_file(tmp_path) == tmp_path / "model.sdf"
    params = diffbot.load_params(tmp_path)
    assert (params.left_joint, params.right_joint) == ("wheel_left_joint", "wheel_right_joint")
    assert params.wheel_separation == pytest.approx(0.16)


def test_a_model_config_without_versions_names_its_first_sdf(tmp_path: Path) -> None:
    (tmp_path / "model.config").write_text(
        "<model><sdf> </sdf><sdf>a.sdf</sdf><sdf>b.sdf</sdf></model>", encoding="utf-8"
    )
    assert sdf.model_file(tmp_path) == tmp_path / "a.sdf"
