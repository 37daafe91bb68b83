"""Where each number comes from: the description's geometry, the robot's diff_drive_controller
configuration and its Gazebo diff-drive plugin, reconciled and cross-checked.

The values the controller uses win over the geometry (they are what the robot runs with):
effective separation = ``wheel_separation * wheel_separation_multiplier``, per-wheel radius =
``wheel_radius * side multiplier``. What the caller overrides wins over both. Sources that
disagree by more than :data:`TOLERANCE`, or name other joints, are reported.
"""

from __future__ import annotations

import dataclasses
import functools
import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Final
from xml.etree import ElementTree

from diffbot.controller_config import ControllerConfig
from diffbot.errors import DescriptionError, DriveWheelError, OutsideRootsError
from diffbot.io.pathnames import resolved
from diffbot.kinematics import DiffDriveParams, Disagreement
from diffbot.numbers import motor_limit, motor_limits, store_checked, wheel_size
from diffbot.urdf.controllers import choose_controller, load_controller_files, load_controllers
from diffbot.urdf.gazebo import GazeboDrive, gazebo_drives, ros2_control_parameter_files
from diffbot.urdf.other_drives import note_other_drives, refusing_other_drives
from diffbot.urdf.ros1 import urdf_radius, urdf_separation
from diffbot.urdf.ros2_control import velocity_limits
from diffbot.urdf.sandbox import inside_folders
from diffbot.urdf.wheels import Derived, JointChoice, finish

__all__ = [
    "DESCRIPTION",
    "GAZEBO",
    "OVERRIDE",
    "PLUGIN",
    "SOURCE_MODES",
    "TOLERANCE",
    "Overriding",
    "find_controller",
    "from_controller",
    "from_options",
    "reconcile",
]

#: Disagreements smaller than this (m) are rounding, not a different robot.
TOLERANCE: Final = 5e-4
#: Source names, as ``params --json`` reports them (a controllers file is ``controllers:<path>``).
DESCRIPTION: Final = "description"
GAZEBO: Final = "gazebo plugin"
#: The source of a value taken from the simulator's diff-drive plugin.
PLUGIN: Final = "plugin"
OVERRIDE: Final = "override"
#: Where the values may be asked from (``--source``).
SOURCE_MODES: Final = ("auto", "description", "controllers", "plugin")


@dataclass(frozen=True)
class Overriding:
    """What the caller gives instead of what the sources say (None: not given), the numbers
    read at once as the robot's own (:func:`~diffbot.numbers.wheel_size`,
    :func:`~diffbot.numbers.motor_limit`): a numeric string is its number before any source
    compares it."""

    left_joint: JointChoice = None
    right_joint: JointChoice = None
    wheel_radius: float | None = None
    wheel_separation: float | None = None
    max_wheel_speed: float | None = None

    def __post_init__(self) -> None:
        for name in ("wheel_radius", "wheel_separation"):
            store_checked(self, name, functools.partial(wheel_size, what=name), optional=True)
        limit = functools.partial(motor_limit, what="max_wheel_speed")
        store_checked(self, "max_wheel_speed", limit, optional=True)


def _controller_source(config: ControllerConfig) -> str:
    return f"controllers:{config.source}"


def find_controller(
    root: ElementTree.Element,
    controllers: str | os.PathLike[str] | None,
    controller: str | None,
    warnings: list[str],
    *,
    description: str | os.PathLike[str] | None = None,
    folders: Sequence[Path] | None = None,
    args: Mapping[str, object] | None = None,
    named_from: Mapping[str, Path] | None = None,
    others: list[tuple[str, str]] | None = None,
) -> ControllerConfig | None:
    """The diff-drive controller the robot runs with: from ``controllers`` when given, else from
    the parameters file its ros2_control Gazebo plugin names (a missing file is a warning).

    A file the description names is the description's to choose, so it is held to the
    description's sandbox: a relative name is taken from the folder of the file that wrote it
    (an included xacro file's, else the description's; never the current directory), and
    unless ``folders`` is None (a trusted description) the file, symbolic links resolved, must
    lie in one of ``folders``; it must be a regular file. A file holding only controllers of
    other drives (mecanum, omni, Ackermann...) is named in a warning with their types.

    Args:
        root: the expanded URDF.
        controllers: the controllers file the user gives, read wherever it is.
        controller: which diff-drive controller of the file.
        warnings: receives a warning for a named file that does not exist.
        description: the description file, whose folder relative names start from.
        folders: the folders an untrusted description may read; None to read any file.
        args: the values of ``$(arg NAME)`` in ROS 1 files.
        named_from: the folder of the included file that wrote each ``<parameters>`` text
            (:attr:`diffbot.urdf.xacro.Expansion.named_from`).
        others: receives the other drives' controllers, ``(name, type)``, of files that hold
            no diff-drive controller.

    Returns None when no file is given or found, or the files found hold no diff-drive
    controller (and none was asked for by name).

    Raises:
        OutsideRootsError: a file the description names lies outside ``folders``.
        ControllerConfigError: a file is not a regular file, or is malformed.
    """
    values = {str(k): str(v) for k, v in (args or {}).items()}
    if controllers is not None:
        configs = load_controllers(controllers, values)
        if not configs:
            note_other_drives([Path(controllers)], warnings, others)
        return choose_controller(configs, controller)
    base = resolved(description, DescriptionError).parent if description is not None else Path.cwd()
    read: list[Path] = []
    for name in ros2_control_parameter_files(root):
        named = Path(name.strip())
        origin = (named_from or {}).get(name.strip(), base)
        path = named if named.is_absolute() else origin / named
        if folders is not None and not inside_folders(path, folders):
            raise OutsideRootsError(
                f"{name.strip()}: the controllers file the description's ros2_control plugin "
                "names is outside the description's folders, so it is not read; trust the "
                "description ({trust}) or give the file ({controllers})"
            )
        if not (path.exists() or path.is_symlink()):
            warnings.append(
                f"the ros2_control plugin names the parameters file {name.strip()!r}, which does "
                "not exist here: its controller settings are not read"
            )
            continue
        read.append(_shown(path))
    # One node takes every file, in order: a later file's value replaces an earlier one's.
    configs = load_controller_files(read, values)
    if not configs:
        note_other_drives(read, warnings, others)
    if not configs and controller is None:
        return None
    return choose_controller(configs, controller)


def _shown(path: Path) -> Path:
    """``path`` relative to the current directory when it lies below it (as a user would type
    it), else as it is."""
    try:
        return path.relative_to(Path.cwd())
    except ValueError:
        return path


def _numeric(field: str, values: Mapping[str, float | None]) -> Disagreement | None:
    given = {source: value for source, value in values.items() if value is not None}
    if len(given) < 2:
        return None
    difference = max(given.values()) - min(given.values())
    if difference <= TOLERANCE:
        return None
    return Disagreement(field, given, difference)


def _joints(field: str, values: Mapping[str, Sequence[str]]) -> Disagreement | None:
    given = {source: tuple(names) for source, names in values.items() if names}
    if len({frozenset(names) for names in given.values()}) < 2:
        return None
    return Disagreement(field, given, None)


def _describe(found: Disagreement) -> str:
    shown = ", ".join(
        f"{source} {value if found.difference is None else f'{value:.6g} m'}"
        for source, value in found.values.items()
    )
    if found.difference is None:
        return f"the sources name different {found.field.replace('_', ' ')}: {shown}"
    mm = found.difference * 1e3
    return f"the sources disagree on {found.field.replace('_', ' ')} by {mm:.3g} mm: {shown}"


def _choose_mode(mode: str, config: ControllerConfig | None, drives: Sequence[GazeboDrive]) -> str:
    """The source the values are taken from: ``controllers``, ``plugin`` or ``description``."""
    if mode not in SOURCE_MODES:
        raise DescriptionError(f"source {mode!r} is none of {', '.join(SOURCE_MODES)}", value=mode)
    if mode == "controllers" and config is None:
        raise DescriptionError(
            "the values were asked from the controllers, but no diff-drive controller was "
            "found: give its file with {controllers}"
        )
    if mode == "plugin" and not drives:
        raise DescriptionError(
            "the values were asked from the simulator's plugin, but the description has no "
            "diff-drive plugin (gazebo_ros_diff_drive, gazebo_ros_skid_steer_drive or gz-sim "
            "DiffDrive)"
        )
    if mode != "auto":
        return mode
    if config is not None:
        return "controllers"
    return "plugin" if drives else "description"


@dataclass(frozen=True)
class _Controlled:
    """What the controller runs with: its base values (m) and where they came from."""

    separation: float | None  # base, before the multiplier
    radius: float | None
    separation_from_file: bool
    radius_from_file: bool


def _controller_values(
    config: ControllerConfig, root: ElementTree.Element, warnings: list[str]
) -> _Controlled:
    """The controller's base separation and radius; ROS 1 looks absent ones up in the URDF."""
    separation, radius = config.wheel_separation, config.wheel_radius
    from_file = (separation is not None, radius is not None)
    if config.ros_version == 1 and config.left_wheel_names and None in (separation, radius):
        left, right = config.left_wheel_names[0], config.right_wheel_names[0]
        if separation is None:
            separation = urdf_separation(root, left, right)
            if separation is not None:
                warnings.append(
                    f"the controller {config.name!r} has no wheel_separation: taken from the "
                    f"URDF as ROS 1's diff_drive_controller does (the distance of {left!r} and "
                    f"{right!r}, {separation:.6g} m), times its multiplier "
                    f"{config.wheel_separation_multiplier:g}"
                )
        if radius is None:
            radius = urdf_radius(root, left)
            if radius is not None:
                warnings.append(
                    f"the controller {config.name!r} has no wheel_radius: taken from the URDF as "
                    f"ROS 1's diff_drive_controller does (the collision of {left!r}'s link, "
                    f"{radius:.6g} m)"
                )
    return _Controlled(separation, radius, *from_file)


def reconcile(
    derive: Callable[[JointChoice, JointChoice], Derived],
    root: ElementTree.Element,
    source: str,
    warnings: list[str],
    config: ControllerConfig | None,
    given: Overriding,
    mode: str = "auto",
    other_drives: Sequence[tuple[str, str]] = (),
    meshes: Callable[[Derived], tuple[float, str] | None] | None = None,
) -> DiffDriveParams:
    """The robot's parameters, each from the source that wins, with the cross-check.

    Args:
        derive: what the description gives for a choice of wheel joints (None: found from the
            structure).
        root: the expanded URDF, for its Gazebo plugins.
        source: the description's name, for messages.
        warnings: warnings so far (expansion, controller files); more are added.
        config: the diff-drive controller, or None.
        given: the caller's overrides.
        mode: which source the values come from (:data:`SOURCE_MODES`): ``auto`` takes the
            controller when there is one, else the simulator's plugin, else the geometry.
        other_drives: the controllers of other drives (mecanum, steering...) that the
            controllers files read hold, as ``(name, type)``.
        meshes: the radius of wheels whose collision is a mesh, and its source
            (``mesh:<file>``), asked only when no other source gives a radius.

    Raises:
        NotDifferentialError: the wheels steer, or the description is driven by a steering,
            mecanum or omnidirectional controller or plugin and by no diff-drive one.
    """
    drives = gazebo_drives(root)
    derive = refusing_other_drives(derive, root, source, config, drives, other_drives)
    chosen = _choose_mode(mode, config, drives)
    ctl = _controller_source(config) if config is not None else ""
    plugin = drives[0] if drives else None
    auto = None
    left_choice, right_choice = given.left_joint, given.right_joint
    joint_source = OVERRIDE if left_choice or right_choice else DESCRIPTION
    named: tuple[tuple[str, ...], tuple[str, ...], str] | None = None
    if not (left_choice or right_choice):
        if chosen == "controllers" and config is not None and config.left_wheel_names:
            named = (config.left_wheel_names, config.right_wheel_names, ctl)
        elif chosen == "plugin" and plugin is not None and plugin.left_joints:
            named = (plugin.left_joints, plugin.right_joints, PLUGIN)
    if named is not None:
        try:
            fields = derive(named[0], named[1])
            joint_source = named[2]
        except DriveWheelError as err:
            owner = "controller" if named[2] == ctl else "plugin"
            warnings.append(f"the {owner}'s wheels cannot be used: {err}")
            fields = auto = derive(None, None)
    else:
        fields = derive(left_choice, right_choice)
        auto = fields if joint_source == DESCRIPTION else None

    controlled = _controller_values(config, root, warnings) if config is not None else None
    found: list[Disagreement] = []
    lengths = (
        (
            "wheel_separation",
            fields.wheel_separation,
            controlled and controlled.separation_from_file and controlled.separation,
        ),
        (
            "wheel_radius",
            fields.wheel_radius,
            controlled and controlled.radius_from_file and controlled.radius,
        ),
    )
    for field, described, from_controller in lengths:
        values: dict[str, float | None] = {DESCRIPTION: described}
        if config is not None:
            values[ctl] = from_controller or None
        for k, drive in enumerate(drives):
            values[_gazebo_name(k)] = getattr(drive, field)
        disagreement = _numeric(field, values)
        if disagreement is not None:
            found.append(disagreement)
    if auto is None and joint_source != OVERRIDE:
        try:
            auto = derive(None, None)
        except DriveWheelError:
            auto = None
    for side in ("left", "right"):
        names: dict[str, Sequence[str]] = {}
        if auto is not None:
            names[DESCRIPTION] = getattr(auto, f"{side}_joints")
        if config is not None:
            names[ctl] = getattr(config, f"{side}_wheel_names")
        for k, drive in enumerate(drives):
            names[_gazebo_name(k)] = getattr(drive, f"{side}_joints")
        disagreement = _joints(f"{side}_joints", names)
        if disagreement is not None:
            found.append(disagreement)
    warnings += [_describe(d) for d in found]

    radius, radius_source = given.wheel_radius, OVERRIDE
    left_radius = right_radius = given.wheel_radius
    separation, separation_source = given.wheel_separation, OVERRIDE
    if chosen == "controllers" and config is not None and controlled is not None:
        if radius is None and controlled.radius is not None:
            radius, radius_source = controlled.radius, ctl
            left_radius = controlled.radius * config.left_wheel_radius_multiplier
            right_radius = controlled.radius * config.right_wheel_radius_multiplier
        if separation is None and controlled.separation is not None:
            separation = controlled.separation * config.wheel_separation_multiplier
            separation_source = ctl
    elif chosen == "plugin" and plugin is not None:
        if radius is None and plugin.wheel_radius is not None:
            radius, radius_source = plugin.wheel_radius, PLUGIN
            left_radius = right_radius = radius
        if separation is None and plugin.wheel_separation is not None:
            separation, separation_source = plugin.wheel_separation, PLUGIN
    if radius is None and fields.wheel_radius is None and meshes is not None:
        measured = meshes(fields)
        if measured is not None:
            radius, radius_source = measured
            left_radius = right_radius = radius
    if radius is None:
        radius_source = DESCRIPTION
    if separation is None:
        separation, separation_source = fields.wheel_separation, DESCRIPTION
    fields = _flipped(fields, left_radius, right_radius, warnings)
    left_radius = None if left_radius is None else abs(left_radius)
    right_radius = None if right_radius is None else abs(right_radius)
    max_speed, speed_source = _motor_limit(root, fields, given, warnings)
    sources = {
        "wheel_radius": radius_source,
        "left_wheel_radius": radius_source,
        "right_wheel_radius": radius_source,
        "wheel_separation": separation_source,
        "left_joints": joint_source,
        "right_joints": joint_source,
        "max_wheel_speed": speed_source,
    }
    return finish(
        fields,
        source,
        tuple(warnings),
        radius,
        separation,
        max_speed,
        left_wheel_radius=left_radius,
        right_wheel_radius=right_radius,
        sources=sources,
        disagreements=tuple(found),
        controller=config,
        plugin_topics=next((d.topics for d in drives if d.topics), {}),
    )


def _split(names: JointChoice) -> tuple[str, ...]:
    parts = names.split(",") if isinstance(names, str) else list(names or ())
    return tuple(name.strip() for name in parts if name.strip())


def from_options(
    given: Overriding,
    controllers: str | os.PathLike[str] | None,
    controller: str | None,
    args: Mapping[str, object] | None,
    no_controllers: bool,
) -> DiffDriveParams:
    """A robot from the caller's joints, radius and separation alone (no description); a
    controllers file given adds its limits and settings, not its geometry."""
    config = None
    if controllers is not None and not no_controllers:
        config = choose_controller(
            load_controllers(controllers, {str(k): str(v) for k, v in (args or {}).items()}),
            controller,
        )
    left, right = _split(given.left_joint), _split(given.right_joint)
    if not left or not right:
        raise DriveWheelError("give both wheel joints by name ({left_joint}, {right_joint})")
    return DiffDriveParams(
        wheel_radius=given.wheel_radius,  # type: ignore[arg-type]  # checked by the caller
        wheel_separation=given.wheel_separation,  # type: ignore[arg-type]
        left_joints=left,
        right_joints=right,
        max_wheel_speed=given.max_wheel_speed,
        source="(options)",
        sources=dict.fromkeys(_FIELDS, OVERRIDE),
        controller=config,
    )


#: The fields ``sources`` names.
_FIELDS = (
    "wheel_radius",
    "left_wheel_radius",
    "right_wheel_radius",
    "wheel_separation",
    "left_joints",
    "right_joints",
    "max_wheel_speed",
)


def from_controller(
    config: ControllerConfig,
    root: ElementTree.Element,
    source: str,
    warnings: list[str],
    given: Overriding,
) -> DiffDriveParams:
    """A robot whose description has no links (a Webots robot's): every value from its
    controller, the caller's overrides winning, the motor limit from ros2_control tags.

    Raises:
        DescriptionError: the controller leaves out its wheels, radius or separation.
    """
    ctl = _controller_source(config)
    left = _split(given.left_joint) or config.left_wheel_names
    right = _split(given.right_joint) or config.right_wheel_names
    radius = given.wheel_radius if given.wheel_radius is not None else config.wheel_radius
    separation = given.wheel_separation
    if separation is None and config.wheel_separation is not None:
        separation = config.wheel_separation * config.wheel_separation_multiplier
    missing = [
        name
        for name, value in (
            ("wheel names", left and right),
            ("wheel_radius", radius),
            ("wheel_separation", separation),
        )
        if not value
    ]
    if missing or radius is None or separation is None:
        raise DescriptionError(
            f"{source}: the description defines no links, and its controller {config.name!r} "
            f"in {config.source} leaves out {', '.join(missing)}: give them with "
            "{wheel_radius}, {wheel_separation}, {left_joint} and {right_joint}",
            path=source,
        )
    signs = {}
    radii = {}
    for side in ("left", "right"):
        multiplier = getattr(config, f"{side}_wheel_radius_multiplier")
        signs[side] = -1 if multiplier < 0 and given.wheel_radius is None else 1
        radii[side] = radius * (1.0 if given.wheel_radius is not None else abs(multiplier))
    tagged = _interface_limits(root, [*left, *right], warnings)
    speed = given.max_wheel_speed
    if speed is None and tagged:
        speed = min(tagged)
    warnings.append(
        f"{source} defines no links: the robot is its controller {config.name!r} "
        f"({config.source}), with no geometry to check it against"
    )
    sources = dict.fromkeys(_FIELDS, ctl)
    for name, value in (
        ("wheel_radius", given.wheel_radius),
        ("wheel_separation", given.wheel_separation),
        ("max_wheel_speed", given.max_wheel_speed),
    ):
        if value is not None:
            sources[name] = OVERRIDE
    sources["max_wheel_speed"] = OVERRIDE if given.max_wheel_speed is not None else DESCRIPTION
    if given.wheel_radius is not None:
        sources["left_wheel_radius"] = sources["right_wheel_radius"] = OVERRIDE
    return DiffDriveParams(
        wheel_radius=radius,
        wheel_separation=separation,
        left_joints=left,
        right_joints=right,
        left_sign=signs["left"],
        right_sign=signs["right"],
        left_wheel_radius=radii["left"],
        right_wheel_radius=radii["right"],
        max_wheel_speed=speed,
        source=source,
        warnings=tuple(warnings),
        sources=sources,
        controller=config,
    )


def _flipped(
    fields: Derived, left: float | None, right: float | None, warnings: list[str]
) -> Derived:
    """The fields with each side's direction turned where a negative radius multiplier turns
    the controller's commands to it."""
    flips = {}
    for side, radius in (("left", left), ("right", right)):
        if radius is not None and radius < 0.0:
            sign = -getattr(fields, f"{side}_sign")
            flips[f"{side}_sign"] = sign
            warnings.append(
                f"the controller's {side}_wheel_radius_multiplier is negative: it turns the "
                f"{side} wheels the other way, read as direction {sign:+d}"
            )
    return dataclasses.replace(fields, **flips) if flips else fields


def _interface_limits(
    root: ElementTree.Element, wheels: Sequence[str], warnings: list[str]
) -> list[float]:
    """The velocity limits (rad/s) the ros2_control velocity command interfaces of ``wheels``
    give, those in :data:`MOTOR_LIMIT_RANGE`; one above it is a placeholder, with a warning."""
    limits = velocity_limits(root)
    named = [(name, limits[name]) for name in wheels if name in limits]
    return motor_limits("the ros2_control velocity command interface max of", named, warnings)


def _motor_limit(
    root: ElementTree.Element, fields: Derived, given: Overriding, warnings: list[str]
) -> tuple[float | None, str]:
    """The motor limit (rad/s) and its source: the override, else the lower of the joints'
    ``<limit velocity>`` and their ros2_control velocity command interface's ``max``."""
    if given.max_wheel_speed is not None:
        return given.max_wheel_speed, OVERRIDE
    tagged = _interface_limits(root, [*fields.left_joints, *fields.right_joints], warnings)
    if not tagged:
        return None, DESCRIPTION
    tag = min(tagged)
    if fields.max_wheel_speed is not None and fields.max_wheel_speed <= tag:
        return None, DESCRIPTION
    if fields.max_wheel_speed is not None:
        warnings.append(
            f"the ros2_control velocity command interfaces allow {tag:g} rad/s, less than the "
            f"joints' velocity limit {fields.max_wheel_speed:g} rad/s: using the lower"
        )
    return tag, DESCRIPTION


def _gazebo_name(index: int) -> str:
    """The source name of the robot's index-th Gazebo diff-drive plugin."""
    return GAZEBO if index == 0 else f"{GAZEBO} {index + 1}"
