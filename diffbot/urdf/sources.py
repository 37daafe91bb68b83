"""Where each number comes from: the description's geometry, the robot's diff_drive_controller
configuration and its Gazebo diff-drive plugin, reconciled and cross-checked.

The values the controller uses win over the geometry (they are what the robot runs with):
effective separation = ``wheel_separation * wheel_separation_multiplier``, per-wheel radius =
``wheel_radius * side multiplier``. What the caller overrides wins over both. Sources that
disagree by more than :data:`TOLERANCE`, or name other joints, are reported.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Final
from xml.etree import ElementTree

from diffbot.controller_config import ControllerConfig
from diffbot.errors import DriveWheelError, OutsideRootsError
from diffbot.kinematics import DiffDriveParams, Disagreement
from diffbot.urdf.controllers import choose_controller, load_controllers
from diffbot.urdf.gazebo import gazebo_drives, ros2_control_parameter_files
from diffbot.urdf.sandbox import inside_folders
from diffbot.urdf.wheels import Derived, JointChoice, finish

__all__ = [
    "DESCRIPTION",
    "GAZEBO",
    "OVERRIDE",
    "TOLERANCE",
    "Overriding",
    "find_controller",
    "reconcile",
]

#: Disagreements smaller than this (m) are rounding, not a different robot.
TOLERANCE: Final = 5e-4
#: Source names, as ``params --json`` reports them (a controllers file is ``controllers:<path>``).
DESCRIPTION: Final = "description"
GAZEBO: Final = "gazebo plugin"
OVERRIDE: Final = "override"


@dataclass(frozen=True)
class Overriding:
    """What the caller gives instead of what the sources say (None: not given)."""

    left_joint: JointChoice = None
    right_joint: JointChoice = None
    wheel_radius: float | None = None
    wheel_separation: float | None = None
    max_wheel_speed: float | None = None


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
) -> ControllerConfig | None:
    """The diff-drive controller the robot runs with: from ``controllers`` when given, else from
    the parameters file its ros2_control Gazebo plugin names (a missing file is a warning).

    A file the description names is the description's to choose, so it is held to the
    description's sandbox: a relative name is taken from the description's folder (not the
    current directory), and unless ``folders`` is None (a trusted description) the file,
    symbolic links resolved, must lie in one of ``folders``; it must be a regular file.

    Args:
        root: the expanded URDF.
        controllers: the controllers file the user gives, read wherever it is.
        controller: which diff-drive controller of the file.
        warnings: receives a warning for a named file that does not exist.
        description: the description file, whose folder relative names start from.
        folders: the folders an untrusted description may read; None to read any file.

    Returns None when no file is given or found, or the files found hold no diff-drive
    controller (and none was asked for by name).

    Raises:
        OutsideRootsError: a file the description names lies outside ``folders``.
        ControllerConfigError: a file is not a regular file, or is malformed.
    """
    if controllers is not None:
        return choose_controller(load_controllers(controllers), controller)
    configs = []
    base = Path(description).resolve().parent if description is not None else Path.cwd()
    for name in ros2_control_parameter_files(root):
        named = Path(name.strip())
        path = named if named.is_absolute() else base / named
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
        configs += load_controllers(_shown(path))
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


def reconcile(
    derive: Callable[[JointChoice, JointChoice], Derived],
    root: ElementTree.Element,
    source: str,
    warnings: list[str],
    config: ControllerConfig | None,
    given: Overriding,
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
    """
    ctl = _controller_source(config) if config is not None else ""
    auto = None
    left_choice, right_choice = given.left_joint, given.right_joint
    joint_source = OVERRIDE if left_choice or right_choice else DESCRIPTION
    if config is not None and not (left_choice or right_choice) and config.left_wheel_names:
        try:
            fields = derive(config.left_wheel_names, config.right_wheel_names)
            joint_source = ctl
        except DriveWheelError as err:
            warnings.append(f"the controller's wheels cannot be used: {err}")
            fields = auto = derive(None, None)
    else:
        fields = derive(left_choice, right_choice)
        auto = fields if joint_source == DESCRIPTION else None

    drives = gazebo_drives(root)
    found: list[Disagreement] = []
    lengths = (
        ("wheel_separation", fields.wheel_separation, config and config.effective_separation),
        ("wheel_radius", fields.wheel_radius, config and config.wheel_radius),
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

    radius_source = OVERRIDE if given.wheel_radius is not None else DESCRIPTION
    radius = given.wheel_radius
    left_radius = right_radius = given.wheel_radius
    if radius is None and config is not None and config.wheel_radius is not None:
        radius, radius_source = config.wheel_radius, ctl
        left_radius, right_radius = config.left_radius, config.right_radius
    separation, separation_source = given.wheel_separation, OVERRIDE
    if separation is None:
        separation, separation_source = fields.wheel_separation, DESCRIPTION
        if config is not None and config.effective_separation is not None:
            separation, separation_source = config.effective_separation, ctl
    sources = {
        "wheel_radius": radius_source,
        "left_wheel_radius": radius_source,
        "right_wheel_radius": radius_source,
        "wheel_separation": separation_source,
        "left_joints": joint_source,
        "right_joints": joint_source,
        "max_wheel_speed": OVERRIDE if given.max_wheel_speed is not None else DESCRIPTION,
    }
    return finish(
        fields,
        source,
        tuple(warnings),
        radius,
        separation,
        given.max_wheel_speed,
        left_wheel_radius=left_radius,
        right_wheel_radius=right_radius,
        sources=sources,
        disagreements=tuple(found),
        controller=config,
    )


def _gazebo_name(index: int) -> str:
    """The source name of the robot's index-th Gazebo diff-drive plugin."""
    return GAZEBO if index == 0 else f"{GAZEBO} {index + 1}"
