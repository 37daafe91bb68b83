"""Wheel radii from collision meshes: the farthest vertex from the wheel's axis, read only inside
the description's folders."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from cli_results import assert_one_error_line
from click.testing import CliRunner
from hypothesis import given
from hypothesis import strategies as st

import diffbot
from diffbot.cli import main
from diffbot.errors import DescriptionError, OutsideRootsError
from diffbot.urdf import meshes
from diffbot.urdf.meshes import mesh_radius, origin_matrix

IDENTITY = origin_matrix(None, "test")


def write_mesh(path: Path, radius: float = 0.075, height: float = 0.04) -> Path:
    """A cylinder mesh about its z axis, vertices ``radius`` from it (STL)."""
    import trimesh

    path.parent.mkdir(parents=True, exist_ok=True)
    trimesh.creation.cylinder(radius=radius, height=height, sections=24).export(path)
    return path


def package(folder: Path, name: str) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "package.xml").write_text(
        f'<?xml version="1.0"?><package format="3"><name>{name}</name></package>\n',
        encoding="utf-8",
    )
    return folder


def robot(filename: str, *, rpy: str = f"{math.pi / 2!r} 0 0", scale: str = "1 1 1") -> str:
    wheels = "".join(
        f'<joint name="{side}_wheel_joint" type="continuous"><parent link="base_link"/>'
        f'<child link="{side}_wheel"/><origin xyz="0 {y} 0"/><axis xyz="0 1 0"/></joint>'
        f'<link name="{side}_wheel"><collision><origin rpy="{rpy}"/><geometry>'
        f'<mesh filename="{filename}" scale="{scale}"/></geometry></collision></link>'
        for side, y in (("left", 0.2), ("right", -0.2))
    )
    return f'<?xml version="1.0"?>\n<robot name="m"><link name="base_link"/>{wheels}</robot>\n'


def test_the_radius_is_the_farthest_vertex_from_the_axis(tmp_path: Path) -> None:
    path = write_mesh(tmp_path / "tyre.stl")
    # The cylinder's own axis is z: about z its vertices lie 0.075 m out.
    assert mesh_radius(path, (1, 1, 1), IDENTITY, (0, 0, 1), "tyre.stl") == pytest.approx(
        0.075, abs=1e-6
    )
    # About x, the farthest vertex is a rim point at the top: sqrt(0.075^2 + 0.02^2).
    assert mesh_radius(path, (1, 1, 1), IDENTITY, (1, 0, 0), "tyre.stl") == pytest.approx(
        math.hypot(0.075, 0.02), abs=1e-6
    )
    # Scaled by 2 across and turned a quarter turn about x, the axis z lands on -y.
    turned = origin_matrix(None, "t")
    turned[1][1], turned[1][2], turned[2][1], turned[2][2] = 0.0, -1.0, 1.0, 0.0
    assert mesh_radius(path, (2, 2, 1), turned, (0, 1, 0), "tyre.stl") == pytest.approx(
        0.15, abs=1e-6
    )


def test_a_packaged_mesh_gives_the_wheels_radius_and_says_so(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    folder = package(tmp_path / "mesh_robot", "mesh_robot")
    write_mesh(folder / "meshes" / "tyre.stl", radius=0.06)
    description = folder / "urdf" / "robot.urdf"
    description.parent.mkdir()
    description.write_text(robot("package://mesh_robot/meshes/tyre.stl"), encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    params = diffbot.load_params("mesh_robot/urdf/robot.urdf")
    assert params.wheel_radius == pytest.approx(0.06, abs=1e-6)
    assert params.wheel_separation == pytest.approx(0.4, abs=1e-12)
    assert params.sources["wheel_radius"] == "mesh:mesh_robot/meshes/tyre.stl"
    # A given radius wins, and the mesh is then not needed.
    given = diffbot.load_params("mesh_robot/urdf/robot.urdf", wheel_radius=0.05)
    assert (given.wheel_radius, given.sources["wheel_radius"]) == (0.05, "override")


def test_a_relative_mesh_is_taken_from_the_descriptions_folder(tmp_path: Path) -> None:
    write_mesh(tmp_path / "meshes" / "tyre.stl", radius=0.05)
    description = tmp_path / "robot.urdf"
    description.write_text(robot("meshes/tyre.stl", scale="1.5 1.5 1"), encoding="utf-8")
    params = diffbot.load_params(description)
    assert params.wheel_radius == pytest.approx(0.075, abs=1e-6)


def test_a_mesh_outside_the_descriptions_folders_is_not_read(tmp_path: Path) -> None:
    outside = write_mesh(tmp_path / "elsewhere" / "tyre.stl")
    description = tmp_path / "robot" / "robot.urdf"
    description.parent.mkdir()
    description.write_text(robot(f"file://{outside}"), encoding="utf-8")
    read: list[Path] = []
    original = meshes.mesh_radius

    def spy(path: Path, *args: object, **kwargs: object) -> float:
        read.append(path)
        return original(path, *args, **kwargs)  # type: ignore[arg-type]

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(meshes, "mesh_radius", spy)
        with pytest.raises(OutsideRootsError, match="outside the description's folders") as err:
            diffbot.load_params(description)
        assert read == []
    assert "wheel_radius=" in str(err.value)
    assert "\n" not in str(err.value)
    # Trusted, it is read; with the radius given, it is not needed.
    assert diffbot.load_params(description, trust=True).wheel_radius == pytest.approx(
        0.075, abs=1e-6
    )
    assert diffbot.load_params(description, wheel_radius=0.07).wheel_radius == 0.07


def test_a_mesh_that_cannot_be_read_is_one_error(tmp_path: Path) -> None:
    (tmp_path / "tyre.step").write_text("ISO-10303-21;", encoding="utf-8")
    (tmp_path / "broken.stl").write_bytes(b"\x00" * 10)
    (tmp_path / "folder.stl").mkdir()
    for name, match in (
        ("tyre.step", "format 'step' is not read"),
        ("broken.stl", "cannot read the mesh|no vertices"),
        ("folder.stl", "is a directory"),
        ("missing.stl", "no such file"),
    ):
        description = tmp_path / f"{name}.urdf"
        description.write_text(robot(name), encoding="utf-8")
        with pytest.raises(DescriptionError, match=match):
            diffbot.load_params(description)


def test_a_mesh_larger_than_the_bound_is_not_read(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    path = write_mesh(tmp_path / "tyre.stl")
    monkeypatch.setattr(meshes, "MAX_MESH_BYTES", path.stat().st_size - 1)
    with pytest.raises(DescriptionError, match="larger than"):
        mesh_radius(path, (1, 1, 1), IDENTITY, (0, 0, 1), "tyre.stl")


def test_an_unknown_package_names_the_option(tmp_path: Path) -> None:
    description = tmp_path / "robot.urdf"
    description.write_text(robot("package://nowhere_pkg/tyre.stl"), encoding="utf-8")
    with pytest.raises(DescriptionError, match=r"'nowhere_pkg'.*packages: nowhere_pkg=DIR"):
        diffbot.load_params(description)


def write_collada(path: Path, asset: str = "", node_asset: str = "") -> Path:
    """A COLLADA triangle whose farthest vertex is 80 units from the y axis (x = 80 and z = 80).

    ``asset`` goes in the document's ``<asset>``, ``node_asset`` in its node's.
    """
    path.write_text(
        '<?xml version="1.0" encoding="utf-8"?>\n'
        '<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">'
        f"<asset>{asset}<up_axis>Z_UP</up_axis></asset>"
        '<library_geometries><geometry id="w"><mesh><source id="p">'
        '<float_array id="a" count="9">80 0 0  0 0 80  0 10 0</float_array>'
        '<technique_common><accessor source="#a" count="3" stride="3">'
        '<param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>'
        "</accessor></technique_common>"
        '</source><vertices id="v"><input semantic="POSITION" source="#p"/></vertices>'
        '<triangles count="1"><input semantic="VERTEX" source="#v" offset="0"/><p>0 1 2</p>'
        "</triangles></mesh></geometry></library_geometries>"
        '<library_visual_scenes><visual_scene id="s"><node id="n">'
        f"{f'<asset>{node_asset}</asset>' if node_asset else ''}"
        '<instance_geometry url="#w"/></node></visual_scene></library_visual_scenes>'
        '<scene><instance_visual_scene url="#s"/></scene></COLLADA>\n',
        encoding="utf-8",
    )
    return path


def unit(meter: str, name: str = "unit") -> str:
    return f'<unit name="{name}" meter="{meter}"/>'


@pytest.mark.parametrize(
    ("asset", "node_asset", "radius"),
    [
        (unit("0.001", "millimeter"), "", 0.08),
        (unit("0.0254", "inch"), "", 80 * 0.0254),
        ("", "", 80.0),
        ('<unit name="meter"/>', "", 80.0),
        # As in Gazebo and RViz, only the document's unit counts.
        ("", unit("0.001", "millimeter"), 80.0),
        (unit("0.01", "centimeter"), unit("0.001", "millimeter"), 0.8),
    ],
)
def test_a_collada_meshs_coordinates_are_in_its_unit(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, asset: str, node_asset: str, radius: float
) -> None:
    monkeypatch.chdir(tmp_path)
    write_collada(tmp_path / "wheel.dae", asset, node_asset)
    description = tmp_path / "robot.urdf"
    description.write_text(robot("wheel.dae", rpy="0 0 0"), encoding="utf-8")
    params = diffbot.load_params(description)
    assert params.wheel_radius == pytest.approx(radius, rel=1e-12)
    assert params.sources["wheel_radius"] == "mesh:wheel.dae"


@given(meter=st.floats(1e-6, 1e3))
def test_scaling_a_collada_unit_scales_the_radius(
    tmp_path_factory: pytest.TempPathFactory, meter: float
) -> None:
    folder = tmp_path_factory.mktemp("unit")
    path = write_collada(folder / "wheel.dae", unit(repr(meter)))
    y_axis = (0.0, 1.0, 0.0)
    assert mesh_radius(path, (1, 1, 1), IDENTITY, y_axis, "wheel.dae") == pytest.approx(
        80 * meter, rel=1e-12
    )
    # The unit and the description's scale multiply.
    assert mesh_radius(path, (2, 2, 2), IDENTITY, y_axis, "wheel.dae") == pytest.approx(
        160 * meter, rel=1e-12
    )


@pytest.mark.parametrize("meter", ["0", "-1", "nan", "abc", "1e400", "inf", "", "1_0"])
def test_a_collada_unit_that_is_not_a_length_is_one_error(tmp_path: Path, meter: str) -> None:
    write_collada(tmp_path / "wheel.dae", unit(meter))
    description = tmp_path / "robot.urdf"
    description.write_text(robot("wheel.dae", rpy="0 0 0"), encoding="utf-8")
    with pytest.raises(DescriptionError, match="not a finite positive number of metres"):
        diffbot.load_params(description)
    result = CliRunner().invoke(main, ["params", str(description)])
    assert_one_error_line(result, "wheel.dae", f"meter={meter!r}")


def test_a_collada_file_that_is_not_xml_is_one_error(tmp_path: Path) -> None:
    (tmp_path / "wheel.dae").write_text("<COLLADA><asset>", encoding="utf-8")
    with pytest.raises(DescriptionError, match="cannot read the mesh"):
        mesh_radius(tmp_path / "wheel.dae", (1, 1, 1), IDENTITY, (0, 1, 0), "wheel.dae")
