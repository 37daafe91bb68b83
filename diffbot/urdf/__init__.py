"""Robot parameters from a URDF, xacro or SDF description, without a ROS install.

The pipeline is: expand xacro (:func:`expand`), check and read the URDF
(:mod:`diffbot.urdf.urdf_model`), find the drive wheels from the structure of the kinematic tree,
and derive :class:`DiffDriveParams` (:func:`load_params`).

Drive wheels are the continuous joints whose axis is lateral (along y) in the base frame and that
hang from the base through fixed joints only (so a caster wheel under a swivel is never taken for
one). Left is the +y side (REP-103).

Deriving needs NumPy, and trimesh only for a wheel whose radius must come from its mesh. The
result is cached on disk keyed by the expanded URDF text: a second run on the same description
only pays for the xacro expansion. ``DIFFBOT_CACHE_DIR`` moves the cache; ``DIFFBOT_NO_CACHE=1``
turns it off.
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Mapping
from pathlib import Path
from xml.etree import ElementTree

from diffbot.errors import DescriptionError
from diffbot.kinematics import DiffDriveParams
from diffbot.numbers import flag
from diffbot.urdf.cache import cached_fields
from diffbot.urdf.meshes import finder_for, wheel_mesh_radius
from diffbot.urdf.shipped import BUNDLED_LABEL, shipped_fields
from diffbot.urdf.sources import (
    Overriding,
    find_controller,
    from_controller,
    from_options,
    reconcile,
)
from diffbot.urdf.wheels import Derived, JointChoice, derive_params
from diffbot.urdf.xacro import BUNDLED_DESCRIPTION, BUNDLED_PACKAGES, Expansion, expand

__all__ = [
    "BUNDLED_DESCRIPTION",
    "BUNDLED_PACKAGES",
    "Expansion",
    "derive_params",
    "expand",
    "load_params",
]


def load_params(
    path: str | os.PathLike[str] | None = None,
    args: Mapping[str, object] | None = None,
    packages: Mapping[str, str | os.PathLike[str]] | None = None,
    *,
    left_joint: JointChoice = None,
    right_joint: JointChoice = None,
    wheel_radius: float | None = None,
    wheel_separation: float | None = None,
    max_wheel_speed: float | None = None,
    controllers: str | os.PathLike[str] | None = None,
    controller: str | None = None,
    trust: bool = False,
    source: str = "auto",
    no_controllers: bool = False,
) -> DiffDriveParams:
    """Robot parameters from a URDF/xacro description and its controller configuration.

    The values the robot runs with win over the geometry (``source="auto"``): its
    diff_drive_controller's ``wheel_separation * wheel_separation_multiplier``, its
    ``wheel_radius`` times each side's multiplier and its wheel names; without a controller, the
    simulator's diff-drive plugin (Gazebo classic or gz-sim). The controllers file is
    ``controllers``, or else the one the description's ros2_control Gazebo plugin names.
    ``params.sources`` says where each value came from and ``params.disagreements`` where the
    sources differ (each is also a warning); a controller's multipliers are settings, so its
    base values are what is compared with the geometry.

    Args:
        path: a .urdf or .urdf.xacro file, an SDF model (``.sdf`` or a model folder) or a
            rosbag2 recording holding ``/robot_description``; None for the bundled diffbot.
        args: xacro arguments, e.g. ``{"wheel_radius": "0.04"}``.
        packages: ROS package directories for ``$(find PKG)``, e.g. ``{"my_robot": "/path/share"}``.
        left_joint: the left drive wheel joint(s) (a name, comma-separated names or a sequence),
            needed only when the structure leaves a choice.
        right_joint: the right drive wheel joint(s), likewise.
        wheel_radius: override of the wheel radius (m), both sides.
        wheel_separation: override of the wheel separation (m).
        max_wheel_speed: override of the motor limit (rad/s).
        controllers: a ros2_control controllers YAML file.
        controller: which diff-drive controller in it, when it holds several.
        trust: let the description run xacro's full Python and read any file (see
            :func:`expand`); off by default, for descriptions from anywhere.
        source: where the values come from: ``auto``, ``description`` (the geometry),
            ``controllers`` or ``plugin``; the other sources are still cross-checked.
        no_controllers: read no controllers file, not even the one the description names.

    With no ``path`` and all of ``left_joint``, ``right_joint``, ``wheel_radius`` and
    ``wheel_separation`` given, no description is loaded: the robot is what they say. A
    description without links (a Webots robot's) takes every value from its controller.

    Returns:
        The robot's :class:`DiffDriveParams`.

    Raises:
        DescriptionError: unreadable or malformed description, xacro failure, unknown package,
            no or ambiguous drive wheels, wheels without a radius, a bad controllers file.
        ParameterError: an override or derived value is not a positive finite number.
    """
    trust, no_controllers = flag(trust, "trust"), flag(no_controllers, "no_controllers")
    given = Overriding(left_joint, right_joint, wheel_radius, wheel_separation, max_wheel_speed)
    if path is None and None not in (left_joint, right_joint, wheel_radius, wheel_separation):
        return from_options(given, controllers, controller, args, no_controllers)
    label = str(path) if path is not None else BUNDLED_LABEL
    expansion = expand(path, args, packages, trust=trust)
    root = ElementTree.fromstring(expansion.urdf)
    warnings = list(expansion.warnings)
    other_drives: list[tuple[str, str]] = []
    if no_controllers and controllers is not None:
        raise DescriptionError(
            "a controllers file is given ({controllers}) and refused (no_controllers=True): "
            "choose one"
        )
    config = (
        None
        if no_controllers
        else find_controller(
            root,
            controllers,
            controller,
            warnings,
            description=expansion.files[0] if expansion.files else None,
            folders=None if trust else expansion.folders,
            args=args,
            named_from=dict(expansion.named_from),
            others=other_drives,
        )
    )
    if config is not None:
        # an argument the controllers file substitutes is used, though the description has none
        used = [f"xacro argument {name!r} " for name in config.arguments]
        warnings = [w for w in warnings if not any(u in w for u in used)]
        warnings += [f"controller {config.name!r}: {note}" for note in config.warnings]

    def derive(left: JointChoice, right: JointChoice) -> Derived:
        shipped = shipped_fields(expansion.urdf, label, left, right)
        return shipped or cached_fields(expansion.urdf, label, left, right)

    if root.find("link") is None and config is not None:
        params = from_controller(config, root, label, warnings, given)
    else:
        params = reconcile(
            derive,
            root,
            label,
            warnings,
            config,
            given,
            source,
            other_drives,
            meshes=lambda fields: wheel_mesh_radius(
                root,
                [*fields.left_joints, *fields.right_joints],
                Path(expansion.files[0]) if expansion.files else None,
                finder_for(Path(path) if path is not None else None, packages),
                None if trust else expansion.folders,
            ),
        )
    files = tuple(str(path) for path in expansion.files)
    return dataclasses.replace(params, description_files=files, xacro_arguments=expansion.arguments)
