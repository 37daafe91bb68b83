"""Wheel radii from collision meshes, for wheels described by a mesh only.

A wheel whose collision is a mesh rolls on the points of it farthest from its axis: the radius is
the largest distance of the mesh's vertices (scaled and posed as the collision says) from the
wheel joint's axis through the joint's origin. The mesh file is untrusted like the description:
it is read only inside the folders the description may read (its own, its package's, the
packages it names), only when it is a regular file of a bounded size, in a format read without
following references to other files. A COLLADA mesh's coordinates are in the unit its root
``<asset><unit meter>`` names (metres without one).
"""

from __future__ import annotations

import io
import math
import os
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Final
from xml.etree.ElementTree import Element, ParseError, iterparse

from diffbot.errors import DescriptionError, DiffbotError, OutsideRootsError
from diffbot.io.pathnames import resolved
from diffbot.numbers import positive_written, written_number
from diffbot.urdf.poses import Matrix, pose_matrix

__all__ = [
    "MAX_MESH_BYTES",
    "MESH_FORMATS",
    "collada_metres",
    "finder_for",
    "mesh_radius",
    "origin_matrix",
    "wheel_mesh_radius",
]

#: Largest mesh file read (bytes): a wheel's mesh is a few MB at most.
MAX_MESH_BYTES: Final = 64 * 1024 * 1024
#: Mesh formats read (by file extension), each read from the file alone.
MESH_FORMATS: Final = ("stl", "obj", "ply", "off", "glb", "dae")


def _numbers(text: str | None, default: str, count: int, where: str) -> list[float]:
    try:
        values = [written_number(v) for v in (text if text is not None else default).split()]
    except ValueError:
        values = []
    if len(values) != count or not all(math.isfinite(v) for v in values):
        raise DescriptionError(f"{where}: expected {count} finite numbers, got {text!r}")
    return values


def origin_matrix(element: Element | None, where: str) -> Matrix:
    """A URDF ``<origin>``'s 4x4 matrix (fixed-axis rpy, R = Rz Ry Rx; identity when absent).

    Raises:
        DescriptionError: ``xyz`` or ``rpy`` is not three finite numbers.
    """
    x, y, z = _numbers(None if element is None else element.get("xyz"), "0 0 0", 3, where)
    roll, pitch, yaw = _numbers(None if element is None else element.get("rpy"), "0 0 0", 3, where)
    return pose_matrix(x, y, z, roll, pitch, yaw)


def mesh_radius(
    path: Path,
    scale: Sequence[float],
    pose: Matrix,
    axis: Sequence[float],
    name: str,
) -> float:
    """The largest distance (m) of a mesh's vertices from an axis through the origin.

    Args:
        path: the mesh file (a regular file of at most :data:`MAX_MESH_BYTES`); a COLLADA
            file's coordinates are in its unit (see :func:`collada_metres`), others' in metres.
        scale: the mesh's scale along its x, y and z.
        pose: the mesh frame in the frame of the axis (4x4).
        axis: the axis direction in that frame (any length but zero).
        name: the file as the user knows it, for messages.

    Raises:
        DescriptionError: not a regular file, too large, of a format not read, unreadable,
            without vertices or (COLLADA) of a unit that is not a positive length.
    """
    from diffbot.io.textfile import check_regular, open_regular

    check_regular(path, DescriptionError, "a mesh", name=name)
    if path.stat().st_size > MAX_MESH_BYTES:
        raise DescriptionError(f"{name}: a mesh larger than {MAX_MESH_BYTES} bytes, not read")
    kind = path.suffix.lower().lstrip(".")
    if kind not in MESH_FORMATS:
        raise DescriptionError(
            f"{name}: a mesh of format {kind or '(none)'!r} is not read "
            f"(formats read: {', '.join(MESH_FORMATS)})"
        )
    import numpy as np
    import trimesh

    try:
        with open(open_regular(path, DescriptionError, "a mesh", name=name), "rb") as stream:
            data = io.BytesIO(stream.read(MAX_MESH_BYTES + 1))
    except OSError as err:
        raise DescriptionError(f"{name}: cannot read the mesh ({type(err).__name__})") from None
    metres = collada_metres(data.getvalue(), name) if kind == "dae" else 1.0
    try:
        loaded = trimesh.load(data, file_type=kind, force="mesh", process=False)
        vertices = np.asarray(getattr(loaded, "vertices", ()), dtype=np.float64)
    except Exception as err:  # trimesh and its format readers raise anything on a bad file
        raise DescriptionError(f"{name}: cannot read the mesh ({type(err).__name__})") from None
    if vertices.ndim != 2 or vertices.shape[0] == 0 or vertices.shape[1] != 3:
        raise DescriptionError(f"{name}: the mesh has no vertices")
    unit = np.asarray(axis, dtype=float)
    unit = unit / np.linalg.norm(unit)
    with np.errstate(all="ignore"):
        points = (vertices * (metres * np.asarray(scale, dtype=float))) @ np.asarray(pose)[:3, :3].T
        points = points + np.asarray(pose)[:3, 3]
        along = points @ unit
        squared = np.einsum("ij,ij->i", points, points) - along * along
        radius = float(np.sqrt(max(float(np.max(squared)), 0.0)))
    if not math.isfinite(radius):
        raise DescriptionError(f"{name}: the mesh has non-finite vertices")
    return radius


def collada_metres(data: bytes, name: str) -> float:
    """The length (m) of one unit of a COLLADA document: its root's ``<asset><unit meter>``.

    The root's unit scales the whole document, as Gazebo and RViz (Assimp) read it; the
    ``<asset>`` of nodes and geometries is ignored, as they ignore it. Without a ``<unit>`` or its
    ``meter``, a unit is a metre.

    Raises:
        DescriptionError: the document is not XML, or ``meter`` is not a finite positive number.
    """
    depth = 0
    in_asset = False
    try:
        for event, element in iterparse(io.BytesIO(data), events=("start", "end")):
            if event == "start":
                depth += 1
                in_asset = in_asset or (depth == 2 and _local(element.tag) == "asset")
                continue
            depth -= 1
            if in_asset and depth == 1:
                unit = next((c for c in element if _local(c.tag) == "unit"), None)
                return _unit_metres(None if unit is None else unit.get("meter"), name)
            if not in_asset:
                element.clear()  # the rest of the document is not needed: keep memory flat
    except ParseError as err:
        raise DescriptionError(f"{name}: cannot read the mesh ({type(err).__name__})") from None
    return 1.0


def _local(tag: str) -> str:
    return tag.rpartition("}")[2]


def _unit_metres(text: str | None, name: str) -> float:
    if text is None:
        return 1.0
    metres = positive_written(text)
    if metres is None:
        raise DescriptionError(
            f"{name}: the COLLADA unit's meter={text!r} is not a finite positive number of metres"
        )
    return metres


def _resolve(
    filename: str, description: Path | None, locate: Callable[[str], Path | None]
) -> tuple[Path, Path | None]:
    """The file a mesh URI names, and the package folder it was found in (None: none)."""
    for scheme in ("package://", "model://"):
        if filename.startswith(scheme):
            package, _, rest = filename[len(scheme) :].partition("/")
            folder = locate(package)
            if folder is None:
                raise DescriptionError(
                    f"{filename}: package {package!r} of the wheel's mesh not found: give its "
                    f"directory with {{packages}} {package}=DIR, or the radius with "
                    "{wheel_radius}"
                )
            return folder / rest, folder
    path = Path(filename.removeprefix("file://"))
    if not path.is_absolute():
        path = (description.parent if description is not None else Path.cwd()) / path
    return path, None


def _shown(path: Path) -> str:
    try:
        return str(resolved(path).relative_to(resolved(Path.cwd())))
    except (ValueError, DiffbotError):
        return str(path)


def wheel_mesh_radius(
    root: Element,
    joints: Sequence[str],
    description: Path | None,
    locate: Callable[[str], Path | None],
    folders: Sequence[Path] | None,
) -> tuple[float, str] | None:
    """The radius (m) of wheels whose collision is a mesh, and where it came from.

    Each wheel's radius is that of its link's first collision mesh about its joint's axis; the
    wheels' radius is their mean. The source is ``mesh:<file>`` (the files, comma-separated,
    when the wheels have different ones).

    Args:
        root: the expanded URDF.
        joints: the drive wheel joints.
        description: the description file (relative mesh names start in its folder).
        locate: finds a package's folder by name (``package://`` and ``model://``).
        folders: the folders an untrusted description may read (a package a mesh is found in
            counts too); None to read any file.

    Returns:
        None when no wheel link has a collision mesh.

    Raises:
        OutsideRootsError: a mesh lies outside the folders the description may read.
        DescriptionError: a mesh cannot be read or its package is not found.
    """
    joint_elements = {j.get("name"): j for j in root.iter("joint")}
    links = {link.get("name"): link for link in root.iter("link")}
    radii: list[float] = []
    files: list[str] = []
    for name in joints:
        joint = joint_elements.get(name)
        child = None if joint is None else joint.find("child")
        link = links.get(None if child is None else child.get("link"))
        mesh = None if link is None else link.find("collision/geometry/mesh")
        if joint is None or link is None or mesh is None:
            continue
        where = f"wheel link {link.get('name')!r}"
        filename = (mesh.get("filename") or "").strip()
        path, package = _resolve(filename, description, locate)
        allowed = [*(folders or ()), *([package] if package is not None else [])]
        if folders is not None and not _inside(path, allowed):
            raise OutsideRootsError(
                f"{filename}: the collision mesh of {where} lies outside the description's "
                "folders, so it is not read: give the wheel radius ({wheel_radius}) or trust "
                "the description ({trust})",
                path=filename,
            )
        collision = link.find("collision")
        pose = origin_matrix(None if collision is None else collision.find("origin"), where)
        scale = _numbers(mesh.get("scale"), "1 1 1", 3, f"{where} mesh scale")
        axis_element = joint.find("axis")
        axis = _numbers(
            None if axis_element is None else axis_element.get("xyz"), "1 0 0", 3, f"{name} axis"
        )
        if not any(axis):
            raise DescriptionError(f"joint {name!r} has a zero axis")
        radii.append(mesh_radius(path, scale, pose, axis, filename))
        if _shown(path) not in files:
            files.append(_shown(path))
    if not radii:
        return None
    return sum(radii) / len(radii), "mesh:" + ",".join(files)


def _inside(path: Path, folders: Sequence[Path]) -> bool:
    from diffbot.urdf.sandbox import inside_folders

    try:
        return inside_folders(path, folders)
    except (OSError, RuntimeError):  # a loop of symbolic links lies nowhere
        return False


def finder_for(
    description: Path | None, packages: Mapping[str, str | os.PathLike[str]] | None
) -> Callable[[str], Path | None]:
    """A package locator for a description, as its ``$(find)`` is resolved."""
    from diffbot.urdf.packages import PackageFinder
    from diffbot.urdf.xacro import BUNDLED_PACKAGES

    return PackageFinder(description, packages or {}, BUNDLED_PACKAGES).locate
