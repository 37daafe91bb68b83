"""Included models: placed by the include's pose, which replaces the model's own, and read once
however often they are included, in time linear in the bytes on disk, with the same result as
the same model read from as many copies."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from xml.etree import ElementTree

import pytest
from linear_time import assert_linear

import diffbot
from diffbot.urdf.xacro import Expansion, expand

WHEEL = '<link name="{0}"><pose>0 {1} 0.1 -1.5707963 0 0</pose><collision name="c"><geometry>'
WHEEL += "<cylinder><radius>0.1</radius><length>0.04</length></cylinder></geometry></collision>"
WHEEL += '</link><joint name="{0}_joint" type="revolute"><parent>base_link</parent>'
WHEEL += "<child>{0}</child><axis><xyz>0 0 1</xyz></axis></joint>"
ROBOT = '<sdf version="1.7"><model name="robot"><link name="base_link"/>{0}{1}{2}</model></sdf>'
CONFIG = '<?xml version="1.0"?><model><name>{0}</name><sdf version="1.7">model.sdf</sdf></model>'


def model_folder(models: Path, name: str, text: str) -> Path:
    """A model folder ``models/name`` of a ``model.config`` and ``text`` as its ``model.sdf``."""
    folder = models / name
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "model.config").write_text(CONFIG.format(name), encoding="utf-8")
    (folder / "model.sdf").write_text(text, encoding="utf-8")
    return folder


def robot(includes: str) -> str:
    """A two-wheel model with ``includes`` (and their joints) added."""
    return ROBOT.format(WHEEL.format("left", 0.2), WHEEL.format("right", -0.2), includes)


def includes(uris: list[str]) -> str:
    """An ``<include>`` of each URI, named ``bJ``, posed 1 m apart, fixed to the base."""
    return "".join(
        f"<include><uri>{uri}</uri><name>b{j}</name><pose>{j} 0 0 0 0 0.5</pose></include>"
        f'<joint name="f{j}" type="fixed"><parent>base_link</parent><child>b{j}::l</child></joint>'
        for j, uri in enumerate(uris)
    )


@pytest.fixture(autouse=True)
def _no_cache(monkeypatch: pytest.MonkeyPatch) -> None:
    # each read derives the parameters again, as a first run does
    monkeypatch.setenv("DIFFBOT_NO_CACHE", "1")


def _large_model_included(
    tmp_path: Path,
) -> tuple[Callable[[bytes], Expansion], Callable[[int], bytes]]:
    """A reader of a model folder and inputs of ``n`` includes of a model of ``8 n`` KiB (the
    two files of an input are joined by a NUL byte, which XML text never holds)."""

    def make(n: int) -> bytes:
        big = f'<sdf version="1.7"><model name="big"><link name="l"/><!-- {"w" * 8192 * n} -->'
        big += '<plugin name="p" filename="p.so"/></model></sdf>'
        return f"{big}\0{robot(includes(['model://big'] * n))}".encode()

    def read(data: bytes) -> Expansion:
        big, top = data.decode().split("\0")
        model_folder(tmp_path / "models", "big", big)
        return expand(model_folder(tmp_path / "models", "robot", top))

    return read, make


def test_a_large_model_included_many_times_is_read_in_linear_time(tmp_path: Path) -> None:
    read, make = _large_model_included(tmp_path)
    print("sdf includes", assert_linear(read, make, 16, accepts=True))


def test_a_model_included_many_times_reads_as_as_many_copies(tmp_path: Path) -> None:
    read, make = _large_model_included(tmp_path / "shared")
    shared = read(make(5))
    models = tmp_path / "copies" / "models"
    big = make(5).decode().split("\0")[0]
    for j in range(5):
        model_folder(models, f"big{j}", big)
    uris = [f"model://big{j}" for j in range(5)]
    copies = expand(model_folder(models, "robot", robot(includes(uris))))
    assert shared.urdf == copies.urdf
    urdf = ElementTree.fromstring(shared.urdf)
    for j in range(5):
        joint = urdf.find(f"joint[@name='f{j}']")
        assert joint is not None
        origin = joint.find("origin")
        assert origin is not None
        x, y, z = map(float, origin.get("xyz", "").split())
        assert (x, y, z) == pytest.approx((j, 0, 0), abs=1e-12)
        assert float(origin.get("rpy", "").split()[2]) == pytest.approx(0.5, abs=1e-12)
    assert len(urdf.findall("gazebo/plugin")) == 5  # each include keeps its plugin
    # the files read, each once: the robot's and the one it includes five times
    assert sorted(f.parent.name for f in shared.files) == ["big", "robot"]
    params = diffbot.load_params(tmp_path / "shared" / "models" / "robot")
    assert (params.wheel_radius, params.wheel_separation) == (0.1, pytest.approx(0.4, abs=1e-12))


#: A wheel model whose own pose stands it on the ground, turned so that its cylinder's axis is +y.
STANDING_WHEEL = (
    '<sdf version="1.9"><model name="wheel"><pose>0 0 0.1 -1.5707963267948966 0 0</pose>'
    '<link name="tyre"><collision name="c"><geometry><cylinder><radius>0.1</radius>'
    "<length>0.05</length></cylinder></geometry></collision></link></model></sdf>"
)


def wheels_included(left: str, right: str) -> str:
    """A chassis and the wheel model included twice, as ``left`` and ``right`` with the given
    ``<pose>`` elements (or none), each on a joint of axis z."""
    parts = ['<sdf version="1.9"><model name="bot"><link name="chassis"/>']
    for side, pose in (("left", left), ("right", right)):
        parts.append(f"<include><uri>model://wheel</uri><name>{side}</name>{pose}</include>")
        parts.append(
            f'<joint name="{side}_joint" type="revolute"><parent>chassis</parent>'
            f"<child>{side}::tyre</child><axis><xyz>0 0 1</xyz></axis></joint>"
        )
    return "".join(parts) + "</model></sdf>"


def test_an_includes_pose_replaces_the_included_models_own(tmp_path: Path) -> None:
    # As SDFormat has it, the include's pose is the model's pose: the roll the include repeats
    # from the model's own is applied once, and each wheel's axis is +y.
    models = tmp_path / "models"
    model_folder(models, "wheel", STANDING_WHEEL)
    turned = "<pose>0 {0} 0.1 -1.5707963267948966 0 0</pose>"
    text = wheels_included(turned.format(0.3), turned.format(-0.3))
    params = diffbot.load_params(model_folder(models, "bot", text))
    assert params.wheel_separation == pytest.approx(0.6, abs=1e-12)
    assert (params.left_joint, params.right_joint) == ("left_joint", "right_joint")
    assert (params.left_sign, params.right_sign) == (1, 1)
    assert params.wheel_radius == pytest.approx(0.1, abs=1e-12)


def test_an_include_without_a_pose_keeps_the_included_models_own(tmp_path: Path) -> None:
    # The right wheel is included without a pose: the model's own (rolled, at y = 0) places it.
    models = tmp_path / "models"
    model_folder(models, "wheel", STANDING_WHEEL)
    text = wheels_included("<pose>0 0.3 0.1 -1.5707963267948966 0 0</pose>", "")
    urdf = ElementTree.fromstring(expand(model_folder(models, "bot", text)).urdf)
    joint = urdf.find("joint[@name='right_joint']")
    assert joint is not None
    origin = joint.find("origin")
    assert origin is not None
    assert [float(v) for v in origin.get("xyz", "").split()] == pytest.approx([0, 0, 0.1])
    assert [float(v) for v in origin.get("rpy", "").split()] == pytest.approx(
        [-1.5707963267948966, 0, 0]
    )


def test_an_included_models_plugin_drives_the_included_models_joints(tmp_path: Path) -> None:
    # The robot, with its DiffDrive plugin, is included in a model that adds a sensor: the
    # plugin names the robot's joints as the robot's file writes them.
    models = tmp_path / "models"
    model_folder(models, "wheel", STANDING_WHEEL)
    pose = "<pose>0 {0} 0.1 -1.5707963267948966 0 0</pose>"
    plugin = (
        '<plugin filename="gz-sim-diff-drive-system" name="gz::sim::systems::DiffDrive">'
        "<left_joint>left_joint</left_joint><right_joint>right_joint</right_joint>"
        "<wheel_separation>0.6</wheel_separation><wheel_radius>0.1</wheel_radius></plugin>"
    )
    robot_text = wheels_included(pose.format(0.3), pose.format(-0.3))
    model_folder(models, "bot", robot_text.replace("</model></sdf>", plugin + "</model></sdf>"))
    wrapper = (
        '<sdf version="1.9"><model name="bot_with_lidar"><include><uri>model://bot</uri>'
        '<name>bot</name></include><link name="lidar"><pose>0 0 0.3 0 0 0</pose></link>'
        '<joint name="lidar_joint" type="fixed"><parent>bot::chassis</parent>'
        "<child>lidar</child></joint></model></sdf>"
    )
    params = diffbot.load_params(model_folder(models, "bot_with_lidar", wrapper))
    assert params.sources["left_joints"] == "plugin"
    assert (params.left_joints, params.right_joints) == (
        ("bot::left_joint",),
        ("bot::right_joint",),
    )
    assert params.disagreements == ()
    assert params.warnings == ()


def test_a_plugin_written_in_an_include_drives_the_included_model(tmp_path: Path) -> None:
    # SDF 1.9: the include adds the DiffDrive plugin to the model it includes; its values are
    # the ones the simulator drives with, and its joints are the included model's.
    models = tmp_path / "models"
    model_folder(models, "wheel", STANDING_WHEEL)
    pose = "<pose>0 {0} 0.1 -1.5707963267948966 0 0</pose>"
    model_folder(models, "bot", wheels_included(pose.format(0.3), pose.format(-0.3)))
    plugin = (
        '<plugin filename="gz-sim-diff-drive-system" name="gz::sim::systems::DiffDrive">'
        "<left_joint>left_joint</left_joint><right_joint>right_joint</right_joint>"
        "<wheel_separation>0.62</wheel_separation><wheel_radius>0.11</wheel_radius></plugin>"
    )
    wrapper = (
        '<sdf version="1.9"><model name="world_robot"><include><uri>model://bot</uri>'
        f"<name>bot</name>{plugin}</include></model></sdf>"
    )
    params = diffbot.load_params(model_folder(models, "world_robot", wrapper))
    assert (params.wheel_radius, params.wheel_separation) == (0.11, 0.62)
    assert params.sources["wheel_separation"] == "plugin"
    assert params.left_joints == ("bot::left_joint",)
    assert sorted(d.field for d in params.disagreements) == ["wheel_radius", "wheel_separation"]
