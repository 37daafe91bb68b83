"""Drive wheels from the structure of a URDF tree, and the parameters they give.

Drive wheels are the continuous joints whose axis is lateral (along y) in the base frame and that
hang from the base through fixed joints only (so a caster wheel under a swivel is never taken for
one). Left is the +y side (REP-103).
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, TypedDict

from diffbot.errors import DescriptionError, DriveWheelError, ParameterError
from diffbot.kinematics import DiffDriveParams
from diffbot.numbers import MOTOR_LIMIT_RANGE, WHEEL_SIZE_RANGE, motor_limits
from diffbot.urdf.tree import Joint, Tree, check_not_steered, joints_of, parse_urdf
from diffbot.urdf.urdf_model import RobotModel, Shape

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray
    from typing_extensions import Unpack

__all__ = [
    "SIZE_RANGE",
    "Derived",
    "Overrides",
    "derive",
    "derive_params",
    "derive_text",
    "finish",
]

#: Wheel radius and separation a description may give (m). Outside, the value is taken for a unit
#: mistake or a hostile file (a subnormal 1e-320, a 1e308) and refused; an override is held to
#: the same range (:class:`~diffbot.kinematics.DiffDriveParams`).
SIZE_RANGE = WHEEL_SIZE_RANGE

#: Drive wheel joints as given: one name, a comma-separated list, a sequence, or None.
JointChoice = str | Sequence[str] | None

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


def _wheel_radius(tree: Tree, joint: Joint, source: str) -> tuple[float | None, str, Shape | None]:
    """Radius of the wheel link's cylinder (collision first, then visual), and its element.

    A link with several cylinders (a hub and a tyre) rolls on the largest: that one is taken.
    """
    link = tree.links[joint.child]
    for kind, elements in (("collision", link.collisions), ("visual", link.visuals)):
        shapes = []
        for element in elements:
            geometry = element.geometry
            shape = geometry.cylinder or geometry.sphere
            if shape is not None:
                shape_name = "cylinder" if geometry.cylinder is not None else "sphere"
                shapes.append((float(shape.radius), f"{kind} {shape_name}", element))
        if shapes:
            return max(shapes, key=lambda found: found[0])
    return None, "", None


def _other_radii(tree: Tree, wheel: _Wheel) -> list[float]:
    """The radii of the wheel link's other cylinders and spheres of the kind taken (m)."""
    link = tree.links[wheel.joint.child]
    elements = link.collisions if wheel.radius_from.startswith("collision") else link.visuals
    radii = []
    for element in elements:
        shape = element.geometry.cylinder or element.geometry.sphere
        if shape is not None:
            radii.append(float(shape.radius))
    radii.remove(max(radii))
    return radii


def _wheel(tree: Tree, joint: Joint, source: str, *, fixed: bool = False) -> _Wheel:
    import numpy as np

    joint_frame = tree.frame(joint.parent) @ joint.origin
    rotation = joint_frame[:3, :3]
    # A fixed joint has no axis: its wheel turns about the base's lateral axis.
    axis = np.array([0.0, 1.0, 0.0]) if fixed else rotation @ joint.axis
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
        if element.geometry.cylinder is not None:
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
    if not _is_rotary(joint):
        return f"it is {joint.type}, not continuous"
    between = [j.name for j in tree.joints_between(joint.parent, tree.base) if _is_rotary(j)]
    between += [
        j.name
        for j in tree.joints_between(joint.parent, tree.base)
        if j.type in ("floating", "planar")
    ]
    if between:
        return f"it hangs from {tree.base!r} through the moving joint(s) {between}"
    return None


def suspension_of(tree: Tree, joint: Joint) -> list[str]:
    """The suspension (prismatic or limited revolute) joints between a wheel and the base."""
    return [
        j.name
        for j in tree.joints_between(joint.parent, tree.base)
        if j.type in ("prismatic", "revolute") and not j.full_turn
    ]


def _is_rotary(joint: Joint) -> bool:
    return joint.type == "continuous" or (joint.type == "revolute" and joint.full_turn)


def _names(given: JointChoice) -> list[str]:
    """Joint names given as one name, a comma-separated list or a sequence."""
    if given is None:
        return []
    parts = given.split(",") if isinstance(given, str) else list(given)
    return [name.strip() for name in parts if name.strip()]


def _pick(
    tree: Tree,
    source: str,
    left_joint: JointChoice,
    right_joint: JointChoice,
    warnings: list[str],
) -> tuple[list[_Wheel], list[_Wheel]]:
    """The drive wheels of each side: the given joints, or those the structure shows."""
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
        joint = tree.joints[name]
        if joint.type == "fixed":
            # Some robots (Neobotix) declare wheel joints fixed; the controller still drives them.
            warnings.append(
                f"joint {name!r} is fixed in the description: taken as a wheel because it was "
                "named as one"
            )
            return _wheel(tree, joint, source, fixed=True)
        why = _why_not_a_wheel(tree, joint)
        if why is not None:
            raise DriveWheelError(f"{source}: joint {name!r} cannot drive a wheel: {why}")
        wheel = _wheel(tree, joint, source)
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
    names = [w.joint.name for w in candidates]

    def refuse(message: str) -> DriveWheelError:
        return DriveWheelError(
            f"{source}: {message}; choose with {{left_joint}}/{{right_joint}}",
            path=source,
            candidates=names,
        )

    left_names, right_names = _names(left_joint), _names(right_joint)
    if not candidates and not (left_names and right_names):
        continuous = [j.name for j in tree.joints.values() if _is_rotary(j)]
        raise DriveWheelError(
            f"{source}: no drive wheels: no continuous joint with a lateral axis hangs from "
            f"{tree.base!r} through fixed joints (continuous joints: {continuous or 'none'})"
        )
    for side, given in (("left", left_names), ("right", right_names)):
        if not given and not by_side[side]:
            raise refuse(
                f"no drive wheel on the {side} side of {tree.base!r} (candidates: {names})"
            )
    counts = {side: len(by_side[side]) for side in ("left", "right")}
    automatic = [
        side for side, given in (("left", left_names), ("right", right_names)) if not given
    ]
    if automatic and any(counts[side] > 1 for side in automatic):
        if left_names or right_names or counts["left"] != counts["right"]:
            side = next(side for side in automatic if counts[side] > 1)
            raise refuse(
                f"{len(candidates)} candidate drive wheels {names}, {counts[side]} on the {side} "
                "side"
            )
        warnings.append(
            f"{counts['left']} drive wheels on each side (a skid steer): all are used; a skid "
            "steer's effective separation is usually larger than its track (give the one it runs "
            "with, or a controller's wheel_separation_multiplier)"
        )
    left = [chosen(n, "left") for n in left_names] if left_names else by_side["left"]
    right = [chosen(n, "right") for n in right_names] if right_names else by_side["right"]
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
        left_joints: every left drive wheel joint (several on a skid steer).
        right_joints: every right drive wheel joint.
        passive_joints: the other moving joints (a caster's).
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
    left_joints: tuple[str, ...]
    right_joints: tuple[str, ...]
    passive_joints: tuple[str, ...]


def derive(
    robot: RobotModel,
    source: str,
    left_joint: JointChoice,
    right_joint: JointChoice,
) -> Derived:
    """Everything derivable from a parsed URDF (:func:`diffbot.urdf.tree.parse_urdf`)."""

    joints = joints_of(robot, source)
    tree = Tree(robot, joints, source)
    check_not_steered(tree, source)
    warnings: list[str] = []
    lefts, rights = _pick(tree, source, left_joint, right_joint, warnings)
    left, right = lefts[0], rights[0]
    wheels = [*lefts, *rights]

    for side, side_wheels in (("left", lefts), ("right", rights)):
        for wheel in side_wheels:
            named = _named_side(wheel.joint.name)
            if named is not None and named != side:
                warnings.append(
                    f"joint {wheel.joint.name!r} is named {named} but sits on the {side} side "
                    f"(y = {wheel.centre[1]:+.4g} m in {tree.base!r})"
                )
            if wheel.radius_from.startswith("visual"):
                warnings.append(
                    f"wheel link {wheel.joint.child!r} has no collision cylinder: radius taken "
                    f"from its {wheel.radius_from}"
                )
            others = _other_radii(tree, wheel) if wheel.radius is not None else []
            if others:
                shown = ", ".join(f"{r:.6g}" for r in others)
                warnings.append(
                    f"wheel link {wheel.joint.child!r} has several {wheel.radius_from}s: the "
                    f"largest ({wheel.radius:.6g} m) is taken as the one it rolls on, not "
                    f"{shown} m"
                )
            axis_warning = _shape_axis_warning(tree, wheel)
            if axis_warning:
                warnings.append(axis_warning)
    suspended = sorted({name for wheel in wheels for name in suspension_of(tree, wheel.joint)})
    if suspended:
        warnings.append(
            f"the drive wheels hang from {tree.base!r} through the suspension joint(s) "
            f"{suspended}: geometry taken at their rest position (0, within their limits)"
        )

    radius: float | None = None
    radii = [w.radius for w in wheels if w.radius is not None]
    if len(radii) == 2 and not math.isclose(radii[0], radii[1], rel_tol=1e-9):
        warnings.append(
            f"the wheels have different radii ({radii[0]:.6g} m left, {radii[1]:.6g} m right): "
            "using their mean"
        )
    elif len(radii) > 2 and not all(math.isclose(r, radii[0], rel_tol=1e-9) for r in radii):
        warnings.append(f"the wheels have different radii {radii} (m): using their mean")
    if radii:
        radius = sum(radii) / len(radii)
        for missing in (w for w in wheels if w.radius is None):
            warnings.append(
                f"wheel link {missing.joint.child!r} has no cylinder: "
                "using the other wheels' radius"
            )

    # A rigid body's forward velocity at a point depends on the point's lateral offset only
    # (v_x = v - w y), so the kinematic track is the lateral distance, whatever x and z differ by.
    left_y = sum(float(w.centre[1]) for w in lefts) / len(lefts)
    right_y = sum(float(w.centre[1]) for w in rights) / len(rights)
    separation = abs(left_y - right_y)
    if len(wheels) == 2:
        offset = left.centre - right.centre
        if abs(float(offset[0])) > 1e-6 or abs(float(offset[2])) > 1e-6:
            warnings.append(
                "the drive wheels are not on one lateral axle "
                f"(offset x {offset[0]:+.4g} m, z {offset[2]:+.4g} m): "
                "separation is their lateral distance"
            )

    limits = [w.joint.velocity_limit for w in wheels]
    for wheel, value in zip(wheels, limits, strict=True):
        if value is not None and not math.isfinite(value):
            raise DescriptionError(
                f"{source}: joint {wheel.joint.name!r} has a non-finite velocity limit {value!r}"
            )
    given = [(w.joint.name, v) for w, v in zip(wheels, limits, strict=True) if v is not None]
    usable = motor_limits("the velocity limit of", given, warnings)
    for wheel, value in zip(wheels, limits, strict=True):
        if value is not None and value <= MOTOR_LIMIT_RANGE[1] and value not in usable:
            warnings.append(f"joint {wheel.joint.name!r} has velocity limit {value!r}: ignored")
    max_speed = min(usable) if usable else None
    if len(set(usable)) > 1:
        warnings.append(
            f"the wheel joints have different velocity limits {usable}: using the lower one"
        )
    elif usable and len(usable) < len(limits) and None in limits:
        warnings.append("only some wheel joints have a velocity limit: using it for all")
    for side, side_wheels in (("left", lefts), ("right", rights)):
        if len({_signed(w) for w in side_wheels}) > 1:
            raise DescriptionError(
                f"{source}: the {side} wheels {[w.joint.name for w in side_wheels]} turn in "
                "opposite directions for forward motion: give each side's wheels one direction"
            )
    drive = {w.joint.name for w in wheels}
    passive = tuple(
        j.name
        for j in tree.joints.values()
        if j.name not in drive and j.type not in ("fixed", "floating", "planar") and not j.mimic
    )

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
        left_joints=tuple(w.joint.name for w in lefts),
        right_joints=tuple(w.joint.name for w in rights),
        passive_joints=passive,
    )


def derive_text(
    urdf: str,
    source: str,
    left_joint: JointChoice = None,
    right_joint: JointChoice = None,
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
    **extra: Any,
) -> DiffDriveParams:
    """The parameters from derived fields and the caller's overrides (``extra``: more
    :class:`DiffDriveParams` fields, such as the per-wheel radii and the sources).

    Raises:
        DriveWheelError: the description gives no radius and no override does.
        DescriptionError: a radius or separation from the description lies outside
            :data:`SIZE_RANGE`.
        ParameterError: a value is not positive and finite.
    """
    radius = fields.wheel_radius if wheel_radius is None else wheel_radius
    if radius is None:
        raise DriveWheelError(
            f"{source}: wheel links {fields.left_child!r} and {fields.right_child!r} have no "
            "cylinder to take the radius from: give it with {wheel_radius}",
            path=source,
        )
    # A value counts as the description's when no override replaced it, or when the caller
    # passed the description's own value on (its ``sources`` say so).
    # A controllers file is a description too: its values get the same check.
    sources = extra.get("sources") or {}
    wheels = f"the cylinders of wheel links {fields.left_child!r} and {fields.right_child!r}"
    joints = f"joints {fields.left_joint!r} and {fields.right_joint!r}"
    separation = fields.wheel_separation if wheel_separation is None else wheel_separation
    for value, what, name, where in (
        (radius, "wheel radius", "wheel_radius", wheels),
        (separation, "wheel separation", "wheel_separation", joints),
    ):
        given = sources.get(name, "override")
        if given.startswith("controllers:"):
            _check_size(value, what, name, f"the controller's {name} in {given[12:]}", source)
            if name == "wheel_radius":  # each side's multiplier makes a radius of its own
                for side in ("left", "right"):
                    origin = f"the controller's wheel_radius and {side}_wheel_radius_multiplier"
                    wheel = extra.get(f"{side}_wheel_radius")
                    if wheel is not None:
                        _check_size(
                            wheel, f"{side} wheel radius", name, f"{origin} in {given[12:]}", source
                        )
        elif given == "plugin":
            _check_size(value, what, name, "the simulator's diff-drive plugin", source)
        elif given.startswith("mesh:"):
            _check_size(value, what, name, f"the collision meshes {given[5:]}", source)
        elif (wheel_radius if name == "wheel_radius" else wheel_separation) is None or (
            given == "description"
        ):
            _check_size(value, what, name, where, source)
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
            left_joints=fields.left_joints,
            right_joints=fields.right_joints,
            passive_joints=fields.passive_joints,
            **extra,
        )
    except ParameterError as err:
        given = wheel_radius is not None or wheel_separation is not None
        raise ParameterError(f"{err}" if given else f"{source}: {err}") from None


def _check_size(value: float, what: str, option: str, where: str, source: str) -> None:
    low, high = SIZE_RANGE
    # zero, negative and NaN are left to DiffDriveParams' own check
    if value > 0.0 and not low <= value <= high:
        raise DescriptionError(
            f"{source}: {what} {value:g} m (from {where}) is outside {low:g}..{high:g} m: "
            f"refused as a unit mistake; give the right one with {{{option}}}",
            path=source,
            value=value,
        )


class Overrides(TypedDict, total=False):
    """What a caller may give instead of (or to choose among) what a description says."""

    left_joint: JointChoice
    right_joint: JointChoice
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
