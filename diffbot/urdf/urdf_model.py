"""The records of a URDF that finding the wheels reads: links with their collision and visual
shapes, joints with their origin, axis, limits and mimic, read from the element tree the XML
check already made (standard library and NumPy only).

The records hold what yourdfpy's ``Robot`` holds for the same fields, with its defaults: an
absent ``<origin>`` is None (the identity), an absent ``<axis>`` (or one without ``xyz``) is
(1, 0, 0), an absent limit attribute is None, a mimic's multiplier 1 and offset 0. An origin's
``rpy`` are fixed-axis roll, pitch and yaw (rad): R = Rz(yaw) Ry(pitch) Rx(roll). Numbers are
read as Python reads them (``nan`` and ``inf`` included: the callers decide what they mean); a
number that is not one, an origin of other than three numbers, a missing name, link or shape is
one :class:`DescriptionError` saying "invalid URDF". What finding the wheels never reads
(inertials, materials, dynamics, calibration, safety controllers, transmissions) is not read.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING
from xml.etree.ElementTree import Element

from diffbot.errors import DescriptionError
from diffbot.numbers import shown, written_number

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray

__all__ = [
    "Box",
    "Cylinder",
    "Geometry",
    "JointModel",
    "Limit",
    "LinkModel",
    "Mesh",
    "Mimic",
    "RobotModel",
    "Shape",
    "Sphere",
    "origin_of",
    "read_robot",
    "rpy_matrix",
]


@dataclass(frozen=True)
class Box:
    size: tuple[float, ...]  # m, as written (x y z)


@dataclass(frozen=True)
class Cylinder:
    radius: float  # m
    length: float  # m, along the shape's z


@dataclass(frozen=True)
class Sphere:
    radius: float  # m


@dataclass(frozen=True)
class Mesh:
    filename: str | None
    scale: float | tuple[float, ...] | None  # one factor, one per axis, or None (1)


@dataclass(frozen=True)
class Geometry:
    """One shape: exactly one of the four is set."""

    box: Box | None = None
    cylinder: Cylinder | None = None
    sphere: Sphere | None = None
    mesh: Mesh | None = None


@dataclass(frozen=True)
class Shape:
    """A ``<collision>`` or ``<visual>``: its geometry posed in the link frame."""

    name: str | None
    origin: NDArray[np.float64] | None  # 4x4, link frame -> shape frame; None: identity
    geometry: Geometry


@dataclass(frozen=True)
class LinkModel:
    name: str
    collisions: tuple[Shape, ...]
    visuals: tuple[Shape, ...]


@dataclass(frozen=True)
class Limit:
    effort: float | None  # N or N m
    velocity: float | None  # m/s or rad/s
    lower: float | None  # m or rad
    upper: float | None  # m or rad


@dataclass(frozen=True)
class Mimic:
    joint: str | None
    multiplier: float
    offset: float  # m or rad


@dataclass(frozen=True)
class JointModel:
    name: str
    type: str | None
    parent: str | None
    child: str | None
    origin: NDArray[np.float64] | None  # 4x4, parent frame -> joint frame; None: identity
    axis: NDArray[np.float64]  # as written: any count of numbers, (1, 0, 0) when absent
    limit: Limit | None
    mimic: Mimic | None


@dataclass(frozen=True)
class RobotModel:
    name: str
    links: tuple[LinkModel, ...]
    joints: tuple[JointModel, ...]


#: A ``<limit>``'s attributes, in the order of :class:`Limit`'s fields.
_LIMIT_KEYS = ("effort", "velocity", "lower", "upper")


class _Reader:
    """Reads the elements of one description, naming it in its errors."""

    def __init__(self, source: str) -> None:
        self.source = source

    def fail(self, message: str) -> DescriptionError:
        return DescriptionError(f"{self.source}: invalid URDF: {message}")

    def number(self, text: str, where: str) -> float:
        try:
            return written_number(text)
        except (ValueError, OverflowError):
            raise self.fail(f"{where} must be a number, got {shown(text)}") from None

    def numbers(self, text: str, where: str, *, commas: bool = False) -> list[float]:
        words = (text.replace(",", " ") if commas else text).split()
        return [self.number(word, where) for word in words]

    def three(self, element: Element, key: str, where: str) -> tuple[float, float, float]:
        text = element.get(key, "0 0 0")
        values = self.numbers(text, f"{where} {key}")
        if len(values) != 3:
            raise self.fail(f"{where} {key} must be 3 numbers, got {shown(text)}")
        return values[0], values[1], values[2]

    def optional(self, element: Element, key: str, where: str) -> float | None:
        text = element.get(key)
        return None if text is None else self.number(text, f"{where} {key}")

    def required(self, element: Element, key: str, where: str) -> str:
        text = element.get(key)
        if text is None:
            raise self.fail(f"{where} has no {key!r} attribute")
        return text

    def origin(self, element: Element | None, where: str) -> NDArray[np.float64] | None:
        if element is None:
            return None
        where = f"{where} <origin>"
        xyz = self.three(element, "xyz", where)
        rpy = self.three(element, "rpy", where)
        return origin_of(xyz, rpy)

    def geometry(self, element: Element | None, where: str) -> Geometry:
        if element is None:
            raise self.fail(f"{where} has no <geometry>")
        shapes = list(element)
        if not shapes:
            raise self.fail(f"{where} has an empty <geometry>")
        shape = shapes[0]  # as yourdfpy: the first element is the shape
        owner, where = where, f"{where} <{shape.tag}>"
        if shape.tag == "cylinder":
            radius = self.number(self.required(shape, "radius", where), f"{where} radius")
            length = self.number(self.required(shape, "length", where), f"{where} length")
            return Geometry(cylinder=Cylinder(radius, length))
        if shape.tag == "sphere":
            radius = self.number(self.required(shape, "radius", where), f"{where} radius")
            return Geometry(sphere=Sphere(radius))
        if shape.tag == "box":
            size = self.required(shape, "size", where)
            return Geometry(box=Box(tuple(self.numbers(size, f"{where} size", commas=True))))
        if shape.tag == "mesh":
            scale: float | tuple[float, ...] | None = None
            if "scale" in shape.attrib:
                factors = self.numbers(shape.attrib["scale"], f"{where} scale", commas=True)
                if len(factors) == 1:
                    scale = factors[0]
                elif factors:
                    scale = tuple(factors)
            return Geometry(mesh=Mesh(shape.get("filename"), scale))
        raise self.fail(f"{owner} has an unknown shape <{shape.tag}>")

    def shape(self, element: Element, where: str) -> Shape:
        name = element.get("name")
        where = f"{where} <{element.tag}>"
        geometry = self.geometry(element.find("geometry"), where)
        return Shape(name, self.origin(element.find("origin"), where), geometry)

    def link(self, element: Element) -> LinkModel:
        name = self.required(element, "name", "a <link>")
        where = f"link {name!r}"
        return LinkModel(
            name,
            tuple(self.shape(c, where) for c in element.findall("collision")),
            tuple(self.shape(v, where) for v in element.findall("visual")),
        )

    def joint(self, element: Element) -> JointModel:
        import numpy as np

        name = self.required(element, "name", "a <joint>")
        where = f"joint {name!r}"
        ends = []
        for role in ("parent", "child"):
            end = element.find(role)
            if end is None:
                raise self.fail(f"{where} has no <{role}>")
            ends.append(end.get("link"))
        axis_element = element.find("axis")
        axis_text = "1 0 0" if axis_element is None else axis_element.get("xyz", "1 0 0")
        axis = np.array(self.numbers(axis_text, f"{where} <axis> xyz"), dtype=np.float64)
        limit = element.find("limit")
        mimic = element.find("mimic")
        return JointModel(
            name,
            element.get("type"),
            ends[0],
            ends[1],
            self.origin(element.find("origin"), where),
            axis,
            None
            if limit is None
            else Limit(*(self.optional(limit, key, f"{where} <limit>") for key in _LIMIT_KEYS)),
            None
            if mimic is None
            else Mimic(
                mimic.get("joint"),
                self.number(mimic.get("multiplier", "1"), f"{where} <mimic> multiplier"),
                self.number(mimic.get("offset", "0"), f"{where} <mimic> offset"),
            ),
        )


def rpy_matrix(roll: float, pitch: float, yaw: float) -> list[list[float]]:
    """The rotation of fixed-axis roll, pitch and yaw (rad): R = Rz(yaw) Ry(pitch) Rx(roll).

    The same rotation as :func:`diffbot.urdf.poses.pose_matrix`, its products taken in the order
    trimesh's ``euler_matrix`` (yourdfpy's) takes them, so that derived parameters stay the same
    to the last bit as when the URDF was read through yourdfpy. A non-finite angle gives a
    matrix of NaN, as NumPy's sine and cosine would.
    """
    if not all(math.isfinite(a) for a in (roll, pitch, yaw)):
        return [[math.nan] * 3 for _ in range(3)]
    si, sj, sk = math.sin(roll), math.sin(pitch), math.sin(yaw)
    ci, cj, ck = math.cos(roll), math.cos(pitch), math.cos(yaw)
    cc, cs, sc, ss = ci * ck, ci * sk, si * ck, si * sk
    return [
        [cj * ck, sj * sc - cs, sj * cc + ss],
        [cj * sk, sj * ss + cc, sj * cs - sc],
        [-sj, cj * si, cj * ci],
    ]


def origin_of(
    xyz: tuple[float, float, float], rpy: tuple[float, float, float]
) -> NDArray[np.float64]:
    """The 4x4 transform of an ``<origin>``: translation ``xyz`` (m), rotation ``rpy`` (rad)."""
    import numpy as np

    matrix = np.eye(4)
    matrix[:3, :3] = rpy_matrix(*rpy)
    matrix[:3, 3] = xyz
    return matrix


def read_robot(root: Element, source: str) -> RobotModel:
    """The robot a checked ``<robot>`` element describes.

    Args:
        root: the root element, as :func:`diffbot.urdf.xacro.check_xml` returns it.
        source: a name for the description in messages.

    Raises:
        DescriptionError: "SOURCE: invalid URDF: ..." (one line) when a name, a joint's parent
            or child, a shape or a shape's size is missing, a number is not one, an origin is
            not three numbers or a shape is of an unknown kind.
    """
    reader = _Reader(source)
    name = reader.required(root, "name", "<robot>")
    links = tuple(reader.link(element) for element in root.findall("link"))
    joints = tuple(reader.joint(element) for element in root.findall("joint"))
    return RobotModel(name, links, joints)
