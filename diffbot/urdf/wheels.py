"""Drive wheels from the structure of a URDF tree, and the parameters they give.

Drive wheels are the continuous joints whose axis is lateral (along y) in the base frame and that
hang from the base through fixed joints only (so a caster wheel under a swivel is never taken for
one). Left is the +y side (REP-103).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, TypedDict

from diffbot.errors import DescriptionError, DriveWheelError, ParameterError
from diffbot.kinematics import DiffDriveParams
from diffbot.urdf.tree import Joint, Tree, joints_of, parse_urdf

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray
    from typing_extensions import Unpack

__all__ = ["Derived", "Overrides", "derive", "derive_params", "derive_text", "finish"]

#: A joint axis counts as lateral when its y component (unit axis, base frame) is at least this.
_LATERAL_MIN = math.cos(math.radians(25.0))
#: Wheel centres closer than this to the x-z plane (m) are on neither side.
_SIDE_EPS = 1e-9


@dataclass(frozen=True)
class _Wheel:
    joint: Joint
    centre: NDArray[np.float64]  # base frame (m)
    axis: NDArray[np.float64]  # unit, base frame
    radius: float | None
    radius_from: str


def _wheel_radius(tree: Tree, joint: Joint, source: str) -> tuple[float | None, str, Any]:
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


def _wheel(tree: Tree, joint: Joint, source: str) -> _Wheel:
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


def _shape_axis_warning(tree: Tree, wheel: _Wheel) -> str | None:
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


def _why_not_a_wheel(tree: Tree, joint: Joint) -> str | None:
    """Why a joint cannot be a drive wheel, or None when it can."""
    if joint.type != "continuous" and not (joint.type == "revolute" and joint.full_turn):
        return f"it is {joint.type}, not continuous"
    between = [j.name for j in tree.joints_between(joint.parent, tree.base) if j.type != "fixed"]
    if between:
        return f"it hangs from {tree.base!r} through the moving joint(s) {between}"
    return None


def _is_rotary(joint: Joint) -> bool:
    return joint.type == "continuous" or (joint.type == "revolute" and joint.full_turn)


def _pick(
    tree: Tree,
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
                f"(candidates: {names}); choose with {{left_joint}}/{{right_joint}}",
                path=source,
                candidates=names,
            )
        raise DriveWheelError(
            f"{source}: {len(candidates)} candidate drive wheels {names}, "
            f"{len(found)} on the {side} side; choose with {{left_joint}}/{{right_joint}}",
            path=source,
            candidates=names,
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


@dataclass(frozen=True)
class Derived:
    """Everything derivable from a URDF alone (JSON-ready: the disk cache stores it).

    Attributes:
        wheel_radius: mean radius of the wheel cylinders (m), None when they have none.
        wheel_separation: lateral distance of the wheels (m).
        left_joint: the left drive wheel joint.
        right_joint: the right drive wheel joint.
        left_sign: +1 when a positive left joint velocity drives forward, else -1.
        right_sign: likewise for the right joint.
        max_wheel_speed: the lower joint velocity limit (rad/s), None without one.
        warnings: what looks wrong in the description.
        base_link: the link the wheels are found from.
        left_child: the left wheel's link.
        right_child: the right wheel's link.
    """

    wheel_radius: float | None
    wheel_separation: float
    left_joint: str
    right_joint: str
    left_sign: int
    right_sign: int
    max_wheel_speed: float | None
    warnings: tuple[str, ...]
    base_link: str
    left_child: str
    right_child: str


def derive(robot: Any, source: str, left_joint: str | None, right_joint: str | None) -> Derived:
    """Everything derivable from a parsed URDF (yourdfpy's Robot record)."""

    joints = joints_of(robot, source)
    tree = Tree(robot, joints, source)
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

    return Derived(
        wheel_radius=radius,
        wheel_separation=separation,
        left_joint=left.joint.name,
        right_joint=right.joint.name,
        left_sign=_signed(left),
        right_sign=_signed(right),
        max_wheel_speed=max_speed,
        warnings=tuple(warnings),
        base_link=tree.base,
        left_child=left.joint.child,
        right_child=right.joint.child,
    )


def derive_text(
    urdf: str, source: str, left_joint: str | None = None, right_joint: str | None = None
) -> Derived:
    """Parse URDF text and derive from it."""
    import warnings

    import numpy as np

    # Overflowing numbers in a description end in a clear error below; numpy's and trimesh's
    # RuntimeWarnings on the way there would only add noise to it.
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore")
        return derive(parse_urdf(urdf, source), source, left_joint, right_joint)


def finish(
    fields: Derived,
    source: str,
    extra_warnings: tuple[str, ...],
    wheel_radius: float | None,
    wheel_separation: float | None,
    max_wheel_speed: float | None,
) -> DiffDriveParams:
    """The parameters from derived fields and the caller's overrides."""
    radius = fields.wheel_radius if wheel_radius is None else wheel_radius
    if radius is None:
        raise DriveWheelError(
            f"{source}: wheel links {fields.left_child!r} and {fields.right_child!r} have no "
            "cylinder to take the radius from: give it with {wheel_radius}",
            path=source,
        )
    try:
        return DiffDriveParams(
            wheel_radius=radius,
            wheel_separation=(
                fields.wheel_separation if wheel_separation is None else wheel_separation
            ),
            left_joint=fields.left_joint,
            right_joint=fields.right_joint,
            left_sign=fields.left_sign,
            right_sign=fields.right_sign,
            max_wheel_speed=(
                fields.max_wheel_speed if max_wheel_speed is None else max_wheel_speed
            ),
            source=source,
            warnings=(*extra_warnings, *fields.warnings),
        )
    except ParameterError as err:
        given = wheel_radius is not None or wheel_separation is not None
        raise ParameterError(f"{err}" if given else f"{source}: {err}") from None


class Overrides(TypedDict, total=False):
    """What a caller may give instead of (or to choose among) what a description says."""

    left_joint: str | None
    right_joint: str | None
    wheel_radius: float | None
    wheel_separation: float | None
    max_wheel_speed: float | None


def derive_params(
    urdf: str, source: str = "(URDF text)", **overrides: Unpack[Overrides]
) -> DiffDriveParams:
    """Derive robot parameters from URDF text (no xacro, no cache).

    Args:
        urdf: URDF XML text.
        source: a name for the text in messages.
        **overrides: ``left_joint``, ``right_joint`` (the drive wheels, when the structure leaves
            a choice), ``wheel_radius``, ``wheel_separation`` (m) and ``max_wheel_speed``
            (rad/s), as for :func:`diffbot.load_params`.

    Returns:
        The parameters, with warnings about the description.
    """
    left_joint, right_joint = overrides.get("left_joint"), overrides.get("right_joint")
    wheel_radius, wheel_separation = (
        overrides.get("wheel_radius"),
        overrides.get("wheel_separation"),
    )
    max_wheel_speed = overrides.get("max_wheel_speed")
    fields = derive_text(urdf, source, left_joint, right_joint)
    return finish(fields, source, (), wheel_radius, wheel_separation, max_wheel_speed)
