"""Robot parameters from a URDF or xacro description, without a ROS install.

The pipeline is: expand xacro (:func:`expand`), check and parse the URDF with yourdfpy, find the
drive wheels from the structure of the kinematic tree, and derive :class:`DiffDriveParams`
(:func:`load_params`).

Drive wheels are the continuous joints whose axis is lateral (along y) in the base frame and that
hang from the base through fixed joints only (so a caster wheel under a swivel is never taken for
one). Left is the +y side (REP-103).

Deriving needs yourdfpy, whose import costs about half a second (it pulls in trimesh), so the
result is cached on disk keyed by the expanded URDF text: a second run on the same description
only pays for the xacro expansion. ``DIFFBOT_CACHE_DIR`` moves the cache; ``DIFFBOT_NO_CACHE=1``
turns it off.
"""

from __future__ import annotations

import contextlib
import hashlib
import io
import json
import math
import os
import re
import tempfile
import threading
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from diffbot.errors import (
    DescriptionError,
    DriveWheelError,
    PackageNotFoundError,
    ParameterError,
    XacroError,
)
from diffbot.kinematics import DiffDriveParams
from diffbot.textfile import read_text

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray

__all__ = [
    "BUNDLED_DESCRIPTION",
    "BUNDLED_PACKAGES",
    "Expansion",
    "derive_params",
    "expand",
    "load_params",
]

_DESCRIPTION_DIR = Path(__file__).resolve().parent / "description"

#: The bundled robot description (the class's diffbot).
BUNDLED_DESCRIPTION = _DESCRIPTION_DIR / "diffbot.urdf.xacro"

#: ROS packages the bundled description refers to with ``$(find ...)``.
BUNDLED_PACKAGES: Mapping[str, Path] = {
    "diffbot_description": _DESCRIPTION_DIR,
    "diffbot_control": _DESCRIPTION_DIR,
}

#: A joint axis counts as lateral when its y component (unit axis, base frame) is at least this.
_LATERAL_MIN = math.cos(math.radians(25.0))
#: Wheel centres closer than this to the x-z plane (m) are on neither side.
_SIDE_EPS = 1e-9
_CACHE_VERSION = "1"

# xacro keeps its state in module globals, so expansions are serialised.
_XACRO_LOCK = threading.Lock()


@dataclass(frozen=True)
class Expansion:
    """An expanded description.

    Attributes:
        urdf: the URDF XML text.
        warnings: what xacro warned about, and xacro arguments the description never declares.
    """

    urdf: str
    warnings: tuple[str, ...] = ()


class _RecordingArgs(dict[str, str]):
    """xacro's argument table, remembering which names the description declares or reads."""

    def __init__(self, given: Mapping[str, str]) -> None:
        super().__init__(given)
        self.seen: set[str] = set()

    def __contains__(self, key: object) -> bool:
        if isinstance(key, str):
            self.seen.add(key)
        return super().__contains__(key)

    def __getitem__(self, key: str) -> str:
        self.seen.add(key)
        return super().__getitem__(key)


def _package_resolver(packages: Mapping[str, str | os.PathLike[str]]) -> Any:
    def find(pkg: str) -> str:
        if pkg in packages:
            return str(Path(packages[pkg]))
        for prefix in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep):
            candidate = Path(prefix) / "share" / pkg
            if prefix and candidate.is_dir():
                return str(candidate)
        raise PackageNotFoundError(
            f"package {pkg!r} not found: give its directory with --package {pkg}=DIR "
            f"(packages={{{pkg!r}: DIR}} in Python)"
        )

    return find


def _is_xacro(path: Path, text: str) -> bool:
    return path.suffix == ".xacro" or re.search(r"xmlns:xacro\s*=", text) is not None


def _check_file(path: Path) -> str:
    return read_text(path, DescriptionError, "a URDF or xacro file")


def _one_line(text: str) -> str:
    return " ".join(str(text).split())


def _xacro_message(err: BaseException, filestack: list[Any] | None) -> str:
    location = ""
    if filestack:
        files = [str(f) for f in filestack if f]
        if files:
            location = f" (in {files[-1]})"
    return _one_line(f"xacro: {err}{location}")


def expand(
    path: str | os.PathLike[str] | None = None,
    args: Mapping[str, object] | None = None,
    packages: Mapping[str, str | os.PathLike[str]] | None = None,
) -> Expansion:
    """Expand a xacro description (or read a plain URDF) into URDF text.

    Args:
        path: a .urdf or .urdf.xacro file; None for the bundled robot.
        args: xacro arguments (``NAME:=VALUE`` on a xacro command line).
        packages: directories of ROS packages, for ``$(find PKG)``; the bundled robot's packages
            are always known, and ``AMENT_PREFIX_PATH`` is searched last.

    Returns:
        The URDF text and any warnings.

    Raises:
        DescriptionError: the file cannot be read or is not well-formed XML.
        XacroError: xacro failed (bad macro, expression, include).
        PackageNotFoundError: a ``$(find PKG)`` names an unknown package.
    """
    source = Path(path) if path is not None else BUNDLED_DESCRIPTION
    text = _check_file(source)
    given = {str(k): str(v) for k, v in (args or {}).items()}
    if not _is_xacro(source, text):
        _check_xml(text, str(source))
        warnings = [f"{source} is plain URDF: xacro argument {name!r} ignored" for name in given]
        return Expansion(text, tuple(warnings))

    known: dict[str, str | os.PathLike[str]] = dict(BUNDLED_PACKAGES)
    known.update(packages or {})
    return _run_xacro(source, given, known)


def _run_xacro(
    source: Path, given: dict[str, str], packages: Mapping[str, str | os.PathLike[str]]
) -> Expansion:
    import xml.parsers.expat

    import xacro
    import xacro.substitution_args as subst

    mappings = _RecordingArgs(given)
    find = _package_resolver(packages)
    stderr = io.StringIO()
    with _XACRO_LOCK:
        saved_find, saved_eval_find = subst._eval_find, subst._eval_dict.get("find")
        subst._eval_find = find
        subst._eval_dict["find"] = find
        saved_all_includes = list(getattr(xacro, "all_includes", []))
        try:
            with contextlib.redirect_stderr(stderr):
                doc = xacro.process_file(str(source), mappings=mappings)
                urdf = doc.toprettyxml(indent="  ")
        except PackageNotFoundError:
            raise
        except xacro.XacroException as err:
            if isinstance(err.exc, PackageNotFoundError):
                raise err.exc from None
            raise XacroError(_xacro_message(err, xacro.filestack)) from None
        except xml.parsers.expat.ExpatError as err:
            where = xacro.filestack[-1] if xacro.filestack else source
            raise DescriptionError(f"{where}: malformed XML: {err}") from None
        except RecursionError:
            raise XacroError(
                f"xacro: {source}: infinite recursion (a macro calls itself)"
            ) from None
        except Exception as err:  # xacro lets Python errors of bad expressions escape
            raise XacroError(_xacro_message(err, xacro.filestack)) from None
        finally:
            subst._eval_find = saved_find
            if saved_eval_find is not None:
                subst._eval_dict["find"] = saved_eval_find
            xacro.all_includes = saved_all_includes
    warnings = [
        _one_line(line.removeprefix("warning: ")) for line in stderr.getvalue().splitlines()
    ]
    warnings = [w for w in warnings if w]
    for name in given:
        if name not in mappings.seen:
            warnings.append(f"xacro argument {name!r} is not declared by {source.name}: ignored")
    return Expansion(urdf, tuple(warnings))


def _check_xml(text: str, source: str) -> None:
    """Reject text that is not well-formed XML (yourdfpy would silently 'recover' it)."""
    import xml.etree.ElementTree as ET

    try:
        root = ET.fromstring(text)
    except ET.ParseError as err:
        raise DescriptionError(f"{source}: malformed XML: {err}") from None
    if root.tag != "robot":
        raise DescriptionError(
            f"{source}: not a URDF: the root element is <{root.tag}>, not <robot>"
        )


# --------------------------------------------------------------------------------------------
# URDF structure -> parameters


@dataclass(frozen=True)
class _Joint:
    name: str
    type: str
    parent: str
    child: str
    origin: NDArray[np.float64]  # 4x4, parent frame -> joint frame
    axis: NDArray[np.float64]  # unit, joint frame
    velocity_limit: float | None
    mimic: bool = False
    full_turn: bool = False  # revolute with a range of at least one turn: a wheel all the same


@dataclass(frozen=True)
class _Wheel:
    joint: _Joint
    centre: NDArray[np.float64]  # base frame (m)
    axis: NDArray[np.float64]  # unit, base frame
    radius: float | None
    radius_from: str


def _parse_urdf(text: str, source: str) -> Any:
    """Parse URDF text with yourdfpy (no meshes, no scene graph) into its Robot record."""
    _check_xml(text, source)
    import logging

    logging.getLogger("yourdfpy").setLevel(logging.CRITICAL)
    import yourdfpy

    try:
        model = yourdfpy.URDF.load(
            io.BytesIO(text.encode("utf-8")), build_scene_graph=False, load_meshes=False
        )
    except Exception as err:  # yourdfpy raises bare KeyError/AttributeError/ValueError on bad URDF
        raise DescriptionError(f"{source}: invalid URDF: {_one_line(repr(err))}") from None
    return model.robot


def _joints_of(robot: Any, source: str) -> dict[str, _Joint]:
    import numpy as np

    link_names = {link.name for link in robot.links}
    joints: dict[str, _Joint] = {}
    for j in robot.joints:
        for role, link in (("parent", j.parent), ("child", j.child)):
            if link not in link_names:
                raise DescriptionError(
                    f"{source}: joint {j.name!r} has unknown {role} link {link!r}"
                )
        origin = np.eye(4) if j.origin is None else np.asarray(j.origin, dtype=float)
        axis = np.asarray(j.axis if j.axis is not None else (1.0, 0.0, 0.0), dtype=float)
        norm = float(np.linalg.norm(axis))
        if not np.all(np.isfinite(origin)) or not math.isfinite(norm):
            raise DescriptionError(f"{source}: joint {j.name!r} has a non-finite origin or axis")
        if norm == 0.0 and j.type in ("continuous", "revolute", "prismatic"):
            raise DescriptionError(f"{source}: joint {j.name!r} has a zero axis")
        velocity = None
        full_turn = False
        if j.limit is not None:
            if j.limit.velocity is not None:
                velocity = float(j.limit.velocity)
            if j.limit.lower is not None and j.limit.upper is not None:
                full_turn = float(j.limit.upper) - float(j.limit.lower) >= 2.0 * math.pi
        joints[j.name] = _Joint(
            j.name,
            str(j.type),
            j.parent,
            j.child,
            origin,
            axis / (norm or 1.0),
            velocity,
            mimic=j.mimic is not None,
            full_turn=full_turn,
        )
    return joints


class _Tree:
    """Link frames at the zero configuration, relative to the base link."""

    def __init__(self, robot: Any, joints: dict[str, _Joint], source: str) -> None:
        import numpy as np

        self.joints = joints
        self.parent_joint: dict[str, _Joint] = {}
        for joint in joints.values():
            if joint.child in self.parent_joint:
                other = self.parent_joint[joint.child].name
                raise DescriptionError(
                    f"{source}: link {joint.child!r} has two parent joints "
                    f"({other!r} and {joint.name!r})"
                )
            self.parent_joint[joint.child] = joint
        links = [link.name for link in robot.links]
        duplicates = sorted({name for name in links if links.count(name) > 1})
        if duplicates:
            raise DescriptionError(f"{source}: links defined more than once: {duplicates}")
        roots = [name for name in links if name not in self.parent_joint]
        if len(roots) != 1:
            what = "no root link (a cycle)" if not roots else f"several root links {roots}"
            raise DescriptionError(f"{source}: the links do not form one tree: {what}")
        for name in links:
            seen = {name}
            node = name
            while node in self.parent_joint:
                node = self.parent_joint[node].parent
                if node in seen:
                    raise DescriptionError(
                        f"{source}: the links do not form one tree: a cycle through {node!r}"
                    )
                seen.add(node)
        self.links = {link.name: link for link in robot.links}
        self.base = "base_link" if "base_link" in self.links else roots[0]
        self._from_root: dict[str, NDArray[np.float64]] = {roots[0]: np.eye(4)}
        self._base_inv = np.linalg.inv(self._root_frame(self.base))

    def _root_frame(self, link: str) -> NDArray[np.float64]:
        chain: list[_Joint] = []
        node = link
        while node not in self._from_root:
            joint = self.parent_joint[node]
            chain.append(joint)
            node = joint.parent
        frame = self._from_root[node]
        for joint in reversed(chain):
            frame = frame @ joint.origin
            self._from_root[joint.child] = frame
        return frame

    def frame(self, link: str) -> NDArray[np.float64]:
        """The link's frame in the base frame (4x4)."""
        return self._base_inv @ self._root_frame(link)

    def ancestors(self, link: str) -> list[str]:
        out = [link]
        while out[-1] in self.parent_joint:
            out.append(self.parent_joint[out[-1]].parent)
        return out

    def joints_between(self, a: str, b: str) -> list[_Joint]:
        """The joints on the path between two links."""
        up_a, up_b = self.ancestors(a), self.ancestors(b)
        common = next(link for link in up_a if link in set(up_b))
        path = up_a[: up_a.index(common)] + up_b[: up_b.index(common)]
        return [self.parent_joint[link] for link in path]


def _wheel_radius(tree: _Tree, joint: _Joint, source: str) -> tuple[float | None, str, Any]:
    """Radius of the wheel link's cylinder (collision first, then visual), and its origin."""
    link = tree.links[joint.child]
    for kind, elements in (("collision", link.collisions), ("visual", link.visuals)):
        for element in elements:
            geometry = element.geometry
            if geometry is None:
                continue
            shape = geometry.cylinder or geometry.sphere
            if shape is not None and shape.radius is not None:
                shape_name = "cylinder" if geometry.cylinder is not None else "sphere"
                return float(shape.radius), f"{kind} {shape_name}", element
    return None, "", None


def _wheel(tree: _Tree, joint: _Joint, source: str) -> _Wheel:
    import numpy as np

    joint_frame = tree.frame(joint.parent) @ joint.origin
    rotation = joint_frame[:3, :3]
    axis = rotation @ joint.axis
    axis = axis / np.linalg.norm(axis)
    centre = joint_frame[:3, 3]
    radius, radius_from, element = _wheel_radius(tree, joint, source)
    if element is not None and element.origin is not None:
        # The wheel's mid-plane point on the axle: the shape's centre projected on the joint axis.
        shape_centre = (joint_frame @ np.asarray(element.origin, dtype=float))[:3, 3]
        centre = centre + float(np.dot(shape_centre - centre, axis)) * axis
    return _Wheel(joint, centre, axis, radius, radius_from)


def _shape_axis_warning(tree: _Tree, wheel: _Wheel) -> str | None:
    import numpy as np

    link = tree.links[wheel.joint.child]
    for element in [*link.collisions, *link.visuals]:
        if element.geometry is not None and element.geometry.cylinder is not None:
            origin = (
                np.eye(4) if element.origin is None else np.asarray(element.origin, dtype=float)
            )
            cylinder_axis = origin[:3, :3] @ np.array([0.0, 0.0, 1.0])  # link frame
            if abs(float(np.dot(cylinder_axis, wheel.joint.axis))) < _LATERAL_MIN:
                return (
                    f"the cylinder of wheel link {link.name!r} is not aligned with the axis of "
                    f"{wheel.joint.name!r}: the wheel may be modelled lying flat"
                )
            return None
    return None


def _side(wheel: _Wheel) -> str:
    y = float(wheel.centre[1])
    if y > _SIDE_EPS:
        return "left"
    if y < -_SIDE_EPS:
        return "right"
    return "centre"


def _named_side(name: str) -> str | None:
    words = set(re.split(r"[^a-z]+", name.lower()))
    left = bool(words & {"left", "l", "lft"}) or "left" in name.lower()
    right = bool(words & {"right", "r", "rgt"}) or "right" in name.lower()
    if left == right:
        return None
    return "left" if left else "right"


def _why_not_a_wheel(tree: _Tree, joint: _Joint) -> str | None:
    """Why a joint cannot be a drive wheel, or None when it can."""
    if joint.type != "continuous" and not (joint.type == "revolute" and joint.full_turn):
        return f"it is {joint.type}, not continuous"
    between = [j.name for j in tree.joints_between(joint.parent, tree.base) if j.type != "fixed"]
    if between:
        return f"it hangs from {tree.base!r} through the moving joint(s) {between}"
    return None


def _is_rotary(joint: _Joint) -> bool:
    return joint.type == "continuous" or (joint.type == "revolute" and joint.full_turn)


def _pick(
    tree: _Tree,
    source: str,
    left_joint: str | None,
    right_joint: str | None,
) -> tuple[_Wheel, _Wheel]:
    candidates: list[_Wheel] = []
    for joint in tree.joints.values():
        # a mimic joint follows another one: it is driven, not a drive
        if joint.mimic or _why_not_a_wheel(tree, joint) is not None:
            continue
        wheel = _wheel(tree, joint, source)
        if abs(float(wheel.axis[1])) >= _LATERAL_MIN:
            candidates.append(wheel)

    def chosen(name: str, side: str) -> _Wheel:
        if name not in tree.joints:
            raise DriveWheelError(f"{source}: no joint named {name!r} (the {side} wheel joint)")
        why = _why_not_a_wheel(tree, tree.joints[name])
        if why is not None:
            raise DriveWheelError(f"{source}: joint {name!r} cannot drive a wheel: {why}")
        wheel = _wheel(tree, tree.joints[name], source)
        if abs(float(wheel.axis[1])) < _LATERAL_MIN:
            raise DriveWheelError(
                f"{source}: joint {name!r} cannot drive a wheel: its axis is not lateral in "
                f"{tree.base!r}"
            )
        if _side(wheel) != side:
            raise DriveWheelError(
                f"{source}: the {side} wheel joint {name!r} sits at y = {wheel.centre[1]:+.4g} m "
                f"in {tree.base!r}, not on the {side} side"
            )
        return wheel

    by_side: dict[str, list[_Wheel]] = {"left": [], "right": [], "centre": []}
    for wheel in candidates:
        by_side[_side(wheel)].append(wheel)

    def auto(side: str) -> _Wheel:
        found = by_side[side]
        if len(found) == 1:
            return found[0]
        names = [w.joint.name for w in candidates]
        if not candidates:
            continuous = [j.name for j in tree.joints.values() if _is_rotary(j)]
            raise DriveWheelError(
                f"{source}: no drive wheels: no continuous joint with a lateral axis hangs from "
                f"{tree.base!r} through fixed joints (continuous joints: {continuous or 'none'})"
            )
        if not found:
            raise DriveWheelError(
                f"{source}: no drive wheel on the {side} side of {tree.base!r} "
                f"(candidates: {names}); choose with left_joint=/right_joint= "
                "(--left-joint/--right-joint)"
            )
        raise DriveWheelError(
            f"{source}: {len(candidates)} candidate drive wheels {names}, "
            f"{len(found)} on the {side} side; choose with left_joint=/right_joint= "
            "(--left-joint/--right-joint)"
        )

    if candidates:
        for side, given in (("left", left_joint), ("right", right_joint)):
            if not given and not by_side[side]:
                auto(side)  # raises: nothing on that side is worse than a choice on the other
    left = chosen(left_joint, "left") if left_joint else auto("left")
    right = chosen(right_joint, "right") if right_joint else auto("right")
    return left, right


def _signed(wheel: _Wheel) -> int:
    # A wheel spinning at w about unit axis a rolls its centre at r w (a x z); its forward (x)
    # part is r w a_y, so a positive joint velocity drives forward exactly when a_y > 0.
    return 1 if float(wheel.axis[1]) > 0 else -1


def _derive(
    robot: Any, source: str, left_joint: str | None, right_joint: str | None
) -> dict[str, Any]:
    """Everything derivable from the URDF alone, as JSON-ready fields (radius may be None)."""

    joints = _joints_of(robot, source)
    tree = _Tree(robot, joints, source)
    left, right = _pick(tree, source, left_joint, right_joint)
    warnings: list[str] = []

    for wheel, side in ((left, "left"), (right, "right")):
        named = _named_side(wheel.joint.name)
        if named is not None and named != side:
            warnings.append(
                f"joint {wheel.joint.name!r} is named {named} but sits on the {side} side "
                f"(y = {wheel.centre[1]:+.4g} m in {tree.base!r})"
            )
        if wheel.radius_from.startswith("visual"):
            warnings.append(
                f"wheel link {wheel.joint.child!r} has no collision cylinder: radius taken from "
                f"its {wheel.radius_from}"
            )
        axis_warning = _shape_axis_warning(tree, wheel)
        if axis_warning:
            warnings.append(axis_warning)

    radius: float | None = None
    radii = [w.radius for w in (left, right) if w.radius is not None]
    if len(radii) == 2 and not math.isclose(radii[0], radii[1], rel_tol=1e-9):
        warnings.append(
            f"the wheels have different radii ({radii[0]:.6g} m left, {radii[1]:.6g} m right): "
            "using their mean"
        )
    if radii:
        radius = sum(radii) / len(radii)
        if len(radii) == 1:
            missing = left if left.radius is None else right
            warnings.append(
                f"wheel link {missing.joint.child!r} has no cylinder: "
                "using the other wheel's radius"
            )

    offset = left.centre - right.centre
    # A rigid body's forward velocity at a point depends on the point's lateral offset only
    # (v_x = v - w y), so the kinematic track is the lateral distance, whatever x and z differ by.
    separation = abs(float(offset[1]))
    if abs(float(offset[0])) > 1e-6 or abs(float(offset[2])) > 1e-6:
        warnings.append(
            "the drive wheels are not on one lateral axle "
            f"(offset x {offset[0]:+.4g} m, z {offset[2]:+.4g} m): "
            "separation is their lateral distance"
        )

    limits = [w.joint.velocity_limit for w in (left, right)]
    for wheel, value in zip((left, right), limits, strict=True):
        if value is not None and not math.isfinite(value):
            raise DescriptionError(
                f"{source}: joint {wheel.joint.name!r} has a non-finite velocity limit {value!r}"
            )
    usable = [v for v in limits if v is not None and v > 0]
    for wheel, value in zip((left, right), limits, strict=True):
        if value is not None and value not in usable:
            warnings.append(f"joint {wheel.joint.name!r} has velocity limit {value!r}: ignored")
    max_speed = min(usable) if usable else None
    if len(usable) == 2 and usable[0] != usable[1]:
        warnings.append(
            f"the wheel joints have different velocity limits {usable}: using the lower one"
        )
    elif len(usable) == 1 and all(v is not None for v in limits) is False:
        warnings.append("only one wheel joint has a velocity limit: using it for both")

    return {
        "wheel_radius": radius,
        "wheel_separation": separation,
        "left_joint": left.joint.name,
        "right_joint": right.joint.name,
        "left_sign": _signed(left),
        "right_sign": _signed(right),
        "max_wheel_speed": max_speed,
        "warnings": warnings,
        "base_link": tree.base,
        "left_child": left.joint.child,
        "right_child": right.joint.child,
    }


def _finish(
    fields: Mapping[str, Any],
    source: str,
    extra_warnings: tuple[str, ...],
    wheel_radius: float | None,
    wheel_separation: float | None,
    max_wheel_speed: float | None,
) -> DiffDriveParams:
    radius = fields["wheel_radius"] if wheel_radius is None else wheel_radius
    if radius is None:
        raise DriveWheelError(
            f"{source}: wheel links {fields['left_child']!r} and {fields['right_child']!r} have no "
            "cylinder to take the radius from: give it with wheel_radius= (--wheel-radius)"
        )
    try:
        return DiffDriveParams(
            wheel_radius=radius,
            wheel_separation=(
                fields["wheel_separation"] if wheel_separation is None else wheel_separation
            ),
            left_joint=fields["left_joint"],
            right_joint=fields["right_joint"],
            left_sign=fields["left_sign"],
            right_sign=fields["right_sign"],
            max_wheel_speed=(
                fields["max_wheel_speed"] if max_wheel_speed is None else max_wheel_speed
            ),
            source=source,
            warnings=(*extra_warnings, *fields["warnings"]),
        )
    except ParameterError as err:
        given = wheel_radius is not None or wheel_separation is not None
        raise ParameterError(f"{err}" if given else f"{source}: {err}") from None


def derive_params(
    urdf: str,
    source: str = "(URDF text)",
    *,
    left_joint: str | None = None,
    right_joint: str | None = None,
    wheel_radius: float | None = None,
    wheel_separation: float | None = None,
    max_wheel_speed: float | None = None,
) -> DiffDriveParams:
    """Derive robot parameters from URDF text (no xacro, no cache).

    Args:
        urdf: URDF XML text.
        source: a name for the text in messages.
        left_joint: the left drive wheel joint, when the structure leaves a choice.
        right_joint: the right drive wheel joint, likewise.
        wheel_radius: override (m); required when the wheel links have no cylinder.
        wheel_separation: override (m).
        max_wheel_speed: override of the motor limit (rad/s).

    Returns:
        The parameters, with warnings about the description.
    """
    fields = _derive_text(urdf, source, left_joint, right_joint)
    return _finish(fields, source, (), wheel_radius, wheel_separation, max_wheel_speed)


def _cache_dir() -> Path | None:
    if os.environ.get("DIFFBOT_NO_CACHE", "") not in ("", "0"):
        return None
    if os.environ.get("DIFFBOT_CACHE_DIR"):
        return Path(os.environ["DIFFBOT_CACHE_DIR"])
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "diffbot"


def _quiet_oserror() -> contextlib.suppress:
    # A cache that cannot be read or written only makes the run slower.
    return contextlib.suppress(OSError, ValueError, TypeError, KeyError)


_FIELD_TYPES: dict[str, tuple[type, ...]] = {
    "wheel_radius": (float, int, type(None)),
    "wheel_separation": (float, int),
    "left_joint": (str,),
    "right_joint": (str,),
    "left_sign": (int,),
    "right_sign": (int,),
    "max_wheel_speed": (float, int, type(None)),
    "warnings": (list,),
    "base_link": (str,),
    "left_child": (str,),
    "right_child": (str,),
}


def _valid_fields(data: Any) -> bool:
    """True when a cache entry has exactly the fields :func:`_derive` writes, well typed."""
    if not isinstance(data, dict) or set(data) != set(_FIELD_TYPES):
        return False
    for name, types in _FIELD_TYPES.items():
        value = data[name]
        if not isinstance(value, types) or isinstance(value, bool):
            return False
        if isinstance(value, float) and not math.isfinite(value):
            return False
    return all(isinstance(w, str) for w in data["warnings"]) and all(
        data[s] in (1, -1) for s in ("left_sign", "right_sign")
    )


def _code_fingerprint() -> str:
    # Entries are keyed by this module's own text, so a change to the derivation is never
    # hidden behind results the old code cached.
    try:
        return hashlib.sha256(Path(__file__).read_bytes()).hexdigest()
    except OSError:
        return _CACHE_VERSION


def _derive_text(
    urdf: str, source: str, left_joint: str | None, right_joint: str | None
) -> dict[str, Any]:
    import warnings

    import numpy as np

    # Overflowing numbers in a description end in a clear error below; numpy's and trimesh's
    # RuntimeWarnings on the way there would only add noise to it.
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore")
        return _derive(_parse_urdf(urdf, source), source, left_joint, right_joint)


def _cached_fields(
    urdf: str, source: str, left_joint: str | None, right_joint: str | None
) -> dict[str, Any]:
    key = hashlib.sha256(
        json.dumps([_code_fingerprint(), urdf, left_joint, right_joint]).encode("utf-8")
    ).hexdigest()
    directory = _cache_dir()
    path = directory / f"params-{key}.json" if directory else None
    if path is not None:
        with _quiet_oserror():
            cached = json.loads(path.read_text(encoding="utf-8"))
            if _valid_fields(cached):
                return dict(cached)
    fields = _derive_text(urdf, source, left_joint, right_joint)
    if path is not None:
        with _quiet_oserror():
            path.parent.mkdir(parents=True, exist_ok=True)
            fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=".params-", suffix=".tmp")
            with os.fdopen(fd, "w", encoding="utf-8") as out:
                json.dump(fields, out)
            os.replace(tmp, path)
    return fields


def load_params(
    path: str | os.PathLike[str] | None = None,
    args: Mapping[str, object] | None = None,
    packages: Mapping[str, str | os.PathLike[str]] | None = None,
    *,
    left_joint: str | None = None,
    right_joint: str | None = None,
    wheel_radius: float | None = None,
    wheel_separation: float | None = None,
    max_wheel_speed: float | None = None,
) -> DiffDriveParams:
    """Robot parameters from a URDF/xacro description.

    Args:
        path: a .urdf or .urdf.xacro file; None for the bundled diffbot.
        args: xacro arguments, e.g. ``{"wheel_radius": "0.04"}``.
        packages: ROS package directories for ``$(find PKG)``, e.g. ``{"my_robot": "/path/share"}``.
        left_joint: the left drive wheel joint, needed only when more than two joints qualify.
        right_joint: the right drive wheel joint, likewise.
        wheel_radius: override of the wheel radius (m).
        wheel_separation: override of the wheel separation (m).
        max_wheel_speed: override of the motor limit (rad/s).

    Returns:
        The robot's :class:`DiffDriveParams`.

    Raises:
        DescriptionError: unreadable or malformed description, xacro failure, unknown package,
            no or ambiguous drive wheels, wheels without a radius.
        ParameterError: an override or derived value is not a positive finite number.
    """
    source = str(path) if path is not None else "bundled diffbot"
    expansion = expand(path, args, packages)
    fields = _cached_fields(expansion.urdf, source, left_joint, right_joint)
    return _finish(
        fields, source, expansion.warnings, wheel_radius, wheel_separation, max_wheel_speed
    )
