"""A model included many times: read once, in time linear in the bytes on disk, with the same
result as the same model read from as many copies."""

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
