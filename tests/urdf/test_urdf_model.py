"""diffbot's URDF reader: the same records as yourdfpy on every description the tests hold, the
fixed-axis rpy convention, one error line for what cannot be read, linear time, and deriving
without yourdfpy or trimesh."""

from __future__ import annotations

import io
import json
import math
import os
import subprocess
import sys
from functools import cache
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from linear_time import assert_linear
from robots import two_wheel_urdf

from diffbot.errors import DescriptionError, DiffbotError
from diffbot.urdf.tree import parse_urdf
from diffbot.urdf.urdf_model import RobotModel, Shape, read_robot, rpy_matrix
from diffbot.urdf.wheels import derive_text
from diffbot.urdf.xacro import check_xml, expand

ROOT = Path(__file__).resolve().parents[2]
CORPUS = ROOT / "tests" / "corpus"
EXAMPLES = ROOT / "docs" / "examples"
TOL = 1e-12


def _corpus() -> dict[str, tuple[Path, Any, Any]]:
    manifest = yaml.safe_load((CORPUS / "manifest.yaml").read_text(encoding="utf-8"))
    found = {}
    for name, case in manifest.items():
        packages = {pkg: CORPUS / folder for pkg, folder in case.get("packages", {}).items()}
        found[f"corpus:{name}"] = (CORPUS / case["path"], case.get("args"), packages or None)
    for suffix in ("*.urdf", "*.urdf.xacro", "*.sdf"):
        for path in sorted(EXAMPLES.rglob(suffix)):
            found[f"docs:{path.relative_to(EXAMPLES)}"] = (path, None, None)
    return found


DESCRIPTIONS = _corpus()


@cache
def _urdf(name: str) -> str | None:
    """The expanded URDF of a description of the tests, or None when it does not expand."""
    if name == "bundled":
        return expand(None).urdf
    path, args, packages = DESCRIPTIONS[name]
    try:
        return expand(path, args, packages).urdf
    except DiffbotError:
        return None


def _same_matrix(ours: Any, theirs: Any, what: str) -> None:
    if theirs is None:
        assert ours is None, what
        return
    assert ours is not None, what
    assert np.asarray(ours).shape == (4, 4), what
    assert np.allclose(ours, theirs, rtol=0.0, atol=TOL, equal_nan=True), what


def _same_shapes(ours: tuple[Shape, ...], theirs: list[Any], what: str) -> None:
    assert len(ours) == len(theirs), what
    for mine, other in zip(ours, theirs, strict=True):
        where = f"{what} {mine.name!r}"
        assert mine.name == other.name, where
        _same_matrix(mine.origin, other.origin, where)
        ours_g, theirs_g = mine.geometry, other.geometry
        for kind in ("box", "cylinder", "sphere", "mesh"):
            assert (getattr(ours_g, kind) is None) == (getattr(theirs_g, kind) is None), where
        if theirs_g.cylinder is not None:
            assert ours_g.cylinder is not None
            assert ours_g.cylinder.radius == theirs_g.cylinder.radius, where
            assert ours_g.cylinder.length == theirs_g.cylinder.length, where
        if theirs_g.sphere is not None:
            assert ours_g.sphere is not None
            assert ours_g.sphere.radius == theirs_g.sphere.radius, where
        if theirs_g.box is not None:
            assert ours_g.box is not None
            assert list(ours_g.box.size) == list(theirs_g.box.size), where
        if theirs_g.mesh is not None:
            assert ours_g.mesh is not None
            assert ours_g.mesh.filename == theirs_g.mesh.filename, where
            scale = theirs_g.mesh.scale
            expected = None if scale is None else np.asarray(scale, dtype=float).tolist()
            got = ours_g.mesh.scale
            assert (None if got is None else np.asarray(got, dtype=float).tolist()) == expected


def assert_same_as_yourdfpy(ours: RobotModel, theirs: Any) -> None:
    """Every field diffbot reads is what yourdfpy reads (origins within :data:`TOL`)."""
    assert ours.name == theirs.name
    assert [link.name for link in ours.links] == [link.name for link in theirs.links]
    for mine, other in zip(ours.links, theirs.links, strict=True):
        _same_shapes(mine.collisions, other.collisions, f"link {mine.name!r} collision")
        _same_shapes(mine.visuals, other.visuals, f"link {mine.name!r} visual")
    assert [j.name for j in ours.joints] == [j.name for j in theirs.joints]
    for joint, other in zip(ours.joints, theirs.joints, strict=True):
        what = f"joint {joint.name!r}"
        assert (joint.type, joint.parent, joint.child) == (other.type, other.parent, other.child)
        _same_matrix(joint.origin, other.origin, what)
        assert joint.axis.tolist() == np.asarray(other.axis, dtype=float).tolist(), what
        if other.limit is None:
            assert joint.limit is None, what
        else:
            assert joint.limit is not None, what
            for key in ("effort", "velocity", "lower", "upper"):
                assert getattr(joint.limit, key) == getattr(other.limit, key), (what, key)
        if other.mimic is None:
            assert joint.mimic is None, what
        else:
            assert joint.mimic is not None, what
            assert joint.mimic.joint == other.mimic.joint, what
            assert joint.mimic.multiplier == other.mimic.multiplier, what
            assert joint.mimic.offset == other.mimic.offset, what


def _yourdfpy(text: str) -> Any:
    import logging

    import yourdfpy

    logging.getLogger("yourdfpy").setLevel(logging.CRITICAL)
    model = yourdfpy.URDF.load(
        io.BytesIO(text.encode("utf-8")), build_scene_graph=False, load_meshes=False
    )
    return model.robot


#: Descriptions of the tests that are no robot to read: refused when expanded (files outside
#: the description's tree), or expanded to no links (a simulator's world).
NOT_ROBOTS = {
    "corpus:webots_like_no_links": "links",
    "docs:untrusted/etc.urdf.xacro": "expansion",
    "docs:untrusted/yaml.urdf.xacro": "expansion",
}


@pytest.mark.parametrize("name", ["bundled", *DESCRIPTIONS])
def test_every_description_reads_as_yourdfpy_reads_it(name: str) -> None:
    text = _urdf(name)
    if name in NOT_ROBOTS:
        if NOT_ROBOTS[name] == "expansion":
            assert text is None
        else:
            assert text is not None
            assert check_xml(text, name).find("link") is None
            with pytest.raises(DescriptionError, match="defines no links"):
                parse_urdf(text, name)
        return
    assert text is not None
    assert_same_as_yourdfpy(parse_urdf(text, name), _yourdfpy(text))


def test_the_compared_descriptions_are_most_of_the_corpus() -> None:
    read = [name for name in DESCRIPTIONS if name.startswith("corpus:") and _urdf(name)]
    assert len(read) >= 30
    assert any(name.startswith("docs:") and _urdf(name) for name in DESCRIPTIONS)


# --- known values ---------------------------------------------------------------------------


def _robot(joint: str = "", link: str = "") -> str:
    return (
        '<robot name="r"><link name="a"/>'
        f'<link name="b">{link}</link>'
        f'<joint name="j" type="continuous"><parent link="a"/><child link="b"/>{joint}</joint>'
        "</robot>"
    )


def _joint(joint: str) -> Any:
    return parse_urdf(_robot(joint), "r.urdf").joints[0]


def test_a_quarter_turn_of_yaw_turns_x_onto_y() -> None:
    origin = _joint('<origin xyz="1 2 3" rpy="0 0 1.5707963267948966"/>').origin
    expected = [[0, -1, 0, 1], [1, 0, 0, 2], [0, 0, 1, 3], [0, 0, 0, 1]]
    assert np.allclose(origin, expected, rtol=0.0, atol=1e-15)


def _about(axis: int, angle: float) -> Any:
    c, s = math.cos(angle), math.sin(angle)
    i, j = [k for k in range(3) if k != axis]
    rotation = np.eye(3)
    rotation[i, i], rotation[i, j], rotation[j, i], rotation[j, j] = c, -s, s, c
    return rotation if axis != 1 else rotation.T  # about y, z x is the positive turn


def test_roll_pitch_yaw_compose_about_fixed_axes_yaw_last() -> None:
    roll, pitch, yaw = 0.3, -0.7, 2.1
    origin = _joint(f'<origin rpy="{roll} {pitch} {yaw}"/>').origin
    expected = _about(2, yaw) @ _about(1, pitch) @ _about(0, roll)
    assert np.allclose(origin[:3, :3], expected, rtol=0.0, atol=1e-15)
    assert np.allclose(origin[:3, 3], 0.0, rtol=0.0, atol=0.0)
    # a pitch of a quarter turn alone takes z onto x
    turned = np.asarray(rpy_matrix(0.0, math.pi / 2, 0.0)) @ [0.0, 0.0, 1.0]
    assert np.allclose(turned, [1.0, 0.0, 0.0], rtol=0.0, atol=1e-15)


angles = st.floats(-10.0, 10.0, allow_nan=False)


@settings(max_examples=200, deadline=None)
@given(roll=angles, pitch=angles, yaw=angles)
def test_rpy_is_a_rotation_composed_from_its_three_turns(
    roll: float, pitch: float, yaw: float
) -> None:
    rotation = np.asarray(rpy_matrix(roll, pitch, yaw))
    expected = _about(2, yaw) @ _about(1, pitch) @ _about(0, roll)
    assert np.allclose(rotation, expected, rtol=0.0, atol=1e-14)
    assert np.allclose(rotation @ rotation.T, np.eye(3), rtol=0.0, atol=1e-14)
    assert math.isclose(float(np.linalg.det(rotation)), 1.0, abs_tol=1e-14)


def test_absent_elements_take_the_urdf_defaults() -> None:
    bare = _joint("")
    assert bare.origin is None
    assert bare.axis.tolist() == [1.0, 0.0, 0.0]
    assert (bare.limit, bare.mimic) == (None, None)
    joint = _joint('<axis/><limit velocity="4.5"/><mimic joint="k"/><origin xyz="0.5 0 0"/>')
    assert joint.axis.tolist() == [1.0, 0.0, 0.0]
    assert joint.limit is not None
    assert (joint.limit.velocity, joint.limit.effort, joint.limit.lower) == (4.5, None, None)
    assert joint.mimic is not None
    assert (joint.mimic.joint, joint.mimic.multiplier, joint.mimic.offset) == ("k", 1.0, 0.0)
    assert joint.origin is not None
    assert np.array_equal(joint.origin[:3, :3], np.eye(3))
    assert joint.origin[:3, 3].tolist() == [0.5, 0.0, 0.0]


def test_shapes_keep_their_kind_size_and_pose() -> None:
    link = (
        '<collision name="tyre"><origin xyz="0 0 0.1"/><geometry>'
        '<cylinder radius="0.05" length="0.02"/></geometry></collision>'
        '<collision><geometry><box size="1,2 3"/></geometry></collision>'
        '<visual><geometry><mesh filename="package://p/w.stl" scale="0.001"/></geometry>'
        '</visual><visual><geometry><sphere radius="0.2"/></geometry></visual>'
        '<visual><geometry><mesh filename="w.dae" scale="1 2 3"/></geometry></visual>'
    )
    (a, b) = parse_urdf(_robot(link=link), "r.urdf").links
    assert (a.collisions, a.visuals) == ((), ())
    tyre, box = b.collisions
    assert tyre.name == "tyre"
    assert tyre.geometry.cylinder is not None
    assert (tyre.geometry.cylinder.radius, tyre.geometry.cylinder.length) == (0.05, 0.02)
    assert tyre.origin is not None
    assert tyre.origin[2, 3] == 0.1
    assert box.origin is None
    assert box.geometry.box is not None
    assert box.geometry.box.size == (1.0, 2.0, 3.0)
    mesh, sphere, scaled = (v.geometry for v in b.visuals)
    assert mesh.mesh is not None
    assert (mesh.mesh.filename, mesh.mesh.scale) == (
        "package://p/w.stl",
        0.001,
    )
    assert sphere.sphere is not None
    assert sphere.sphere.radius == 0.2
    assert scaled.mesh is not None
    assert scaled.mesh.scale == (1.0, 2.0, 3.0)


# --- what cannot be read --------------------------------------------------------------------

BROKEN = {
    "a word for a number": ('<origin xyz="0 abc 0"/>', "", "xyz must be a number, got 'abc'"),
    "two numbers for three": ('<origin rpy="0 0"/>', "", "rpy must be 3 numbers"),
    "four numbers for three": ('<origin xyz="1 2 3 4"/>', "", "xyz must be 3 numbers"),
    "an empty origin": ('<origin xyz=""/>', "", "xyz must be 3 numbers"),
    "a word in the axis": ('<axis xyz="0 y 0"/>', "", "<axis> xyz must be a number"),
    "digits grouped as Python groups them": (
        '<origin xyz="0 1_0e-2 0"/>',
        "",
        "xyz must be a number, got '1_0e-2'",
    ),
    "digits of another script": ('<limit velocity="\u0665"/>', "", "velocity must be a number"),
    "a word as a limit": ('<limit velocity="fast"/>', "", "velocity must be a number"),
    "a word as a multiplier": ('<mimic joint="k" multiplier="x"/>', "", "multiplier must be"),
    "a word as a radius": (
        "",
        '<collision><geometry><cylinder radius="r" length="1"/></geometry></collision>',
        "<cylinder> radius must be a number",
    ),
    "a cylinder without length": (
        "",
        '<collision><geometry><cylinder radius="1"/></geometry></collision>',
        "has no 'length' attribute",
    ),
    "a sphere without radius": (
        "",
        "<visual><geometry><sphere/></geometry></visual>",
        "has no 'radius' attribute",
    ),
    "a box without size": ("", "<visual><geometry><box/></geometry></visual>", "'size'"),
    "a word in a box": (
        "",
        '<visual><geometry><box size="1 x 1"/></geometry></visual>',
        "size must be a number",
    ),
    "a word in a scale": (
        "",
        '<visual><geometry><mesh filename="m.stl" scale="1 q 1"/></geometry></visual>',
        "scale must be a number",
    ),
    "a visual without geometry": ("", "<visual/>", "has no <geometry>"),
    "an empty geometry": ("", "<collision><geometry/></collision>", "an empty <geometry>"),
    "an unknown shape": (
        "",
        "<collision><geometry><cone/></geometry></collision>",
        "an unknown shape <cone>",
    ),
}


@pytest.mark.parametrize(("joint", "link", "message"), BROKEN.values(), ids=list(BROKEN))
def test_what_cannot_be_read_is_one_error_line(joint: str, link: str, message: str) -> None:
    with pytest.raises(DescriptionError) as raised:
        parse_urdf(_robot(joint, link), "r.urdf")
    text = str(raised.value)
    assert text.startswith("r.urdf: invalid URDF: ")
    assert message in text
    assert "\n" not in text


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ('<robot><link name="a"/></robot>', "<robot> has no 'name' attribute"),
        ('<robot name="r"><link/></robot>', "a <link> has no 'name' attribute"),
        (
            '<robot name="r"><link name="a"/><joint type="fixed"><parent link="a"/></joint>'
            "</robot>",
            "a <joint> has no 'name' attribute",
        ),
        (
            '<robot name="r"><link name="a"/><joint name="j"><parent link="a"/></joint></robot>',
            "joint 'j' has no <child>",
        ),
    ],
)
def test_a_missing_name_or_end_is_one_error_line(text: str, message: str) -> None:
    with pytest.raises(DescriptionError, match=r"^r\.urdf: invalid URDF: ") as raised:
        read_robot(check_xml(text, "r.urdf"), "r.urdf")
    assert message in str(raised.value)


def test_a_long_bad_number_is_shown_cut_short() -> None:
    with pytest.raises(DescriptionError) as raised:
        _joint(f'<origin xyz="0 {"9" * 5000}x 0"/>')
    assert len(str(raised.value)) < 200


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (('xyz="0 0.1 0"', 'xyz="nan 0.1 0"'), "non-finite origin"),
        (('xyz="0 0.1 0"', 'xyz="0 inf 0"'), "non-finite origin"),
        (('rpy="1.5707963 0 0"', 'rpy="1.5707963 0 0"'), None),  # the healthy robot
        (('<axis xyz="0 1 0"/>', '<axis xyz=""/>'), "an axis of 0 numbers"),
        (('<axis xyz="0 1 0"/>', '<axis xyz="0 0 0"/>'), "zero axis"),
        (('<axis xyz="0 1 0"/>', '<axis xyz="0 nan 0"/>'), "non-finite origin or axis"),
        (('<parent link="base_link"/>', "<parent/>"), "unknown parent link None"),
    ],
)
def test_singular_values_are_one_error_line_when_deriving(
    change: tuple[str, str], message: str | None
) -> None:
    text = two_wheel_urdf().replace(*change, 1)
    if message is None:
        assert derive_text(text, "r.urdf").wheel_radius == 0.05
        return
    with pytest.raises(DescriptionError) as raised:
        derive_text(text, "r.urdf")
    assert message in str(raised.value)
    assert str(raised.value).startswith("r.urdf: ")
    assert "\n" not in str(raised.value)


def test_an_infinite_angle_is_a_non_finite_origin() -> None:
    text = two_wheel_urdf().replace('rpy="1.5707963 0 0"', 'rpy="inf 0 0"', 1)
    text = text.replace('<origin xyz="0 0.1 0"/>', '<origin xyz="0 0.1 0" rpy="0 -inf 0"/>', 1)
    with pytest.raises(DescriptionError, match="non-finite origin"):
        derive_text(text, "r.urdf")
    robot = parse_urdf(text, "r.urdf")
    assert robot.joints[0].origin is not None
    assert np.isnan(robot.joints[0].origin[:3, :3]).all()
    assert robot.joints[0].origin[:3, 3].tolist() == [0.0, 0.1, 0.0]


# --- time -----------------------------------------------------------------------------------


def _large(shape: str, word: str) -> Any:
    def make(n: int) -> bytes:
        if shape == "links":
            body = "".join(
                f'<link name="l{i}"><visual><origin xyz="0 0 {i}" rpy="0 0 1"/><geometry>'
                f'<box size="1 1 1"/></geometry></visual></link><joint name="j{i}" '
                f'type="fixed"><parent link="base_link"/><child link="l{i}"/></joint>'
                for i in range(n)
            )
        elif shape == "comments":
            body = f"<!-- {word} -->\n" * n
        elif shape == "a long number":
            body = (
                '<link name="n"/><joint name="n" type="fixed"><parent link="base_link"/>'
                f'<child link="n"/><origin xyz="0 0 0.{"1" * (40 * n)}"/></joint>'
            )
        else:  # a long name
            name = word.replace('"', "").replace("&", "").replace("<", "") or "x"
            body = f'<link name="{(name * (40 * n))[: 40 * n]}"/>'
        return two_wheel_urdf(body=body).encode()

    return make


WORDS = st.text(
    st.characters(codec="utf-8", exclude_characters="-<>&\r", exclude_categories=["Cs", "Cc"]),
    min_size=1,
    max_size=40,
)


@settings(
    max_examples=2,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
)
@given(shape=st.sampled_from(["links", "comments", "a long number", "a long name"]), word=WORDS)
def test_reading_takes_time_linear_in_the_size(shape: str, word: str) -> None:
    def read(data: bytes) -> object:
        text = data.decode("utf-8")
        return read_robot(check_xml(text, "r.urdf"), "r.urdf")

    print(shape, assert_linear(read, _large(shape, word), 200, accepts=True))


# --- what deriving loads --------------------------------------------------------------------


def test_deriving_a_new_description_loads_neither_yourdfpy_nor_trimesh(tmp_path: Path) -> None:
    # what the child process of the cache runs, in a fresh interpreter
    code = (
        "import sys\n"
        "from diffbot.urdf.cache import _child\n"
        "_child()\n"
        "print()\n"
        "print(*(name in sys.modules for name in ('numpy', 'yourdfpy', 'trimesh', 'scipy')))\n"
    )
    request = json.dumps([two_wheel_urdf(), "robot.urdf", None, None])
    env = {**os.environ, "DIFFBOT_CACHE_DIR": str(tmp_path / "cache")}
    done = subprocess.run(
        [sys.executable, "-c", code],
        input=request,
        capture_output=True,
        text=True,
        env=env,
        timeout=120,
        check=True,
    )
    fields, loaded = done.stdout.rsplit("\n", 2)[:2]
    assert json.loads(fields)["wheel_radius"] == pytest.approx(0.05, abs=1e-15)
    assert json.loads(fields)["wheel_separation"] == pytest.approx(0.2, abs=1e-15)
    assert loaded.split() == ["True", "False", "False", "False"]
