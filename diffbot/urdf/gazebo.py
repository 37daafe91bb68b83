"""Diff-drive plugins in a robot description: Gazebo classic's ``gazebo_ros_diff_drive`` and
``gazebo_ros_skid_steer_drive``, the gz-sim / Ignition ``DiffDrive`` system, and the
``<parameters>`` file of a ros2_control plugin.

They are read as a cross-check of the geometry and the controller configuration.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from xml.etree.ElementTree import Element

from diffbot.errors import DescriptionError

__all__ = ["GazeboDrive", "GazeboPluginError", "gazebo_drives", "ros2_control_parameter_files"]


class GazeboPluginError(DescriptionError):
    """A Gazebo diff-drive plugin in a description holds a malformed value."""


@dataclass(frozen=True)
class GazeboDrive:
    """A Gazebo diff-drive plugin found in a description.

    Attributes:
        kind: ``gazebo_ros_diff_drive`` (Gazebo classic, ROS 1 or 2),
            ``gazebo_ros_skid_steer_drive`` (Gazebo classic, ROS 1) or ``gz_sim_diff_drive``
            (gz-sim and Ignition Gazebo).
        plugin: the plugin's ``filename`` attribute, as written.
        left_joints: the left wheel joints, in the order written.
        right_joints: the right wheel joints.
        wheel_separations: every separation written (m), one per wheel pair for Gazebo classic.
        wheel_radii: every radius written (m); half the diameter for Gazebo classic.

    A plugin without a separation or radius runs with its own default (gz-sim: 1.0 m and 0.2 m),
    which is rarely the robot's; the fields stay empty so that a check can say so.
    """

    kind: str
    plugin: str
    left_joints: tuple[str, ...]
    right_joints: tuple[str, ...]
    wheel_separations: tuple[float, ...] = ()
    wheel_radii: tuple[float, ...] = ()

    @property
    def wheel_separation(self) -> float | None:
        """The first separation written (m), or None (the plugin then uses its default)."""
        return self.wheel_separations[0] if self.wheel_separations else None

    @property
    def wheel_radius(self) -> float | None:
        """The first radius written (m), or None (the plugin then uses its default)."""
        return self.wheel_radii[0] if self.wheel_radii else None


# --- Gazebo plugins ---------------------------------------------------------------------------

_CLASSIC = re.compile(r"^(lib)?gazebo_ros_diff_drive(\.so)?$")
_SKID_STEER = re.compile(r"^(lib)?gazebo_ros_skid_steer_drive(\.so)?$")
_GZ_SIM = re.compile(r"^(lib)?(gz-sim|ignition-gazebo)\d*-diff-drive-system(\.so)?$")
_GZ_SIM_NAMES = frozenset({"gz::sim::systems::DiffDrive", "ignition::gazebo::systems::DiffDrive"})
_ROS2_CONTROL = re.compile(r"^(lib)?(gazebo_ros2_control|gz_ros2_control|ign_ros2_control)")


def _plugin_texts(plugin: Element, *tags: str) -> list[str]:
    return [(child.text or "").strip() for child in plugin if child.tag in tags]


def _plugin_lengths(plugin: Element, filename: str, tag: str, scale: float) -> tuple[float, ...]:
    values = []
    for text in _plugin_texts(plugin, tag):
        try:
            value = float(text)
        except ValueError:
            value = math.nan
        if not (math.isfinite(value) and value > 0.0):
            raise GazeboPluginError(
                f"Gazebo plugin {filename!r}: <{tag}> must be a positive length in m, got {text!r}"
            )
        values.append(value * scale)
    return tuple(values)


def gazebo_drives(root: Element) -> list[GazeboDrive]:
    """The Gazebo diff-drive plugins of an expanded description.

    Gazebo classic's ``libgazebo_ros_diff_drive.so`` (ROS 2 tags ``left_joint``, ``right_joint``,
    ``wheel_separation``, ``wheel_diameter``, repeated per wheel pair; ROS 1 tags ``leftJoint``,
    ``rightJoint``, ``wheelSeparation``, ``wheelDiameter``), Gazebo classic's
    ``libgazebo_ros_skid_steer_drive.so`` (``leftFrontJoint``, ``leftRearJoint``,
    ``rightFrontJoint``, ``rightRearJoint``, ``wheelSeparation``, ``wheelDiameter``: it drives
    both wheels of a side alike, as a diff drive of that separation) and the gz-sim / Ignition
    DiffDrive system (``left_joint`` and ``right_joint`` repeated per wheel, ``wheel_separation``,
    ``wheel_radius``).

    Args:
        root: the ``<robot>`` element of the expanded URDF.

    Returns:
        The plugins in document order.

    Raises:
        GazeboPluginError: a separation, diameter or radius that is not a positive number.
    """
    drives: list[GazeboDrive] = []
    for plugin in root.iter("plugin"):
        filename = plugin.get("filename", "")
        if _CLASSIC.match(filename):
            kind = "gazebo_ros_diff_drive"
            separations = _plugin_lengths(plugin, filename, "wheel_separation", 1.0)
            separations += _plugin_lengths(plugin, filename, "wheelSeparation", 1.0)
            radii = _plugin_lengths(plugin, filename, "wheel_diameter", 0.5)
            radii += _plugin_lengths(plugin, filename, "wheelDiameter", 0.5)
            left = _plugin_texts(plugin, "left_joint", "leftJoint")
            right = _plugin_texts(plugin, "right_joint", "rightJoint")
        elif _SKID_STEER.match(filename):
            kind = "gazebo_ros_skid_steer_drive"
            separations = _plugin_lengths(plugin, filename, "wheelSeparation", 1.0)
            radii = _plugin_lengths(plugin, filename, "wheelDiameter", 0.5)
            left = _plugin_texts(plugin, "leftFrontJoint", "leftRearJoint")
            right = _plugin_texts(plugin, "rightFrontJoint", "rightRearJoint")
        elif _GZ_SIM.match(filename) or plugin.get("name") in _GZ_SIM_NAMES:
            kind = "gz_sim_diff_drive"
            separations = _plugin_lengths(plugin, filename, "wheel_separation", 1.0)
            radii = _plugin_lengths(plugin, filename, "wheel_radius", 1.0)
            left = _plugin_texts(plugin, "left_joint")
            right = _plugin_texts(plugin, "right_joint")
        else:
            continue
        drives.append(
            GazeboDrive(
                kind=kind,
                plugin=filename,
                left_joints=tuple(t for t in left if t),
                right_joints=tuple(t for t in right if t),
                wheel_separations=separations,
                wheel_radii=radii,
            )
        )
    return drives


def ros2_control_parameter_files(root: Element) -> list[str]:
    """The controller files named by the ros2_control plugins of Gazebo in a description.

    Args:
        root: the ``<robot>`` element of the expanded URDF (``$(find ...)`` already resolved).

    Returns:
        The text of every ``<parameters>`` of a ``gazebo_ros2_control``, ``gz_ros2_control`` or
        ``ign_ros2_control`` plugin, stripped, in document order.
    """
    files: list[str] = []
    for plugin in root.iter("plugin"):
        if not _ROS2_CONTROL.match(plugin.get("filename", "")):
            continue
        files.extend(text for text in _plugin_texts(plugin, "parameters") if text)
    return files
