"""Diff-drive plugins in a robot description: Gazebo classic's ``gazebo_ros_diff_drive``,
``gazebo_ros_skid_steer_drive`` and its own ``DiffDrivePlugin``, the gz-sim / Ignition
``DiffDrive`` system, and the ``<parameters>`` file of a ros2_control plugin.

They are read as a cross-check of the geometry and the controller configuration.
"""

from __future__ import annotations

import copy
import math
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from xml.etree.ElementTree import Element

from diffbot.errors import DescriptionError
from diffbot.numbers import positive_written

__all__ = [
    "GazeboDrive",
    "GazeboPluginError",
    "gazebo_drives",
    "other_drive_plugins",
    "ros2_control_parameter_files",
    "ros_topic",
    "scoped_plugin",
]


class GazeboPluginError(DescriptionError):
    """A Gazebo diff-drive plugin in a description holds a malformed value."""


@dataclass(frozen=True)
class GazeboDrive:
    """A Gazebo diff-drive plugin found in a description.

    Attributes:
        kind: ``gazebo_ros_diff_drive`` (Gazebo classic, ROS 1 or 2),
            ``gazebo_ros_skid_steer_drive`` (Gazebo classic, ROS 1), ``gazebo_diff_drive``
            (Gazebo classic's own ``DiffDrivePlugin``, without ROS) or ``gz_sim_diff_drive``
            (gz-sim and Ignition Gazebo).
        plugin: the plugin's ``filename`` attribute, as written.
        left_joints: the left wheel joints, in the order written.
        right_joints: the right wheel joints.
        wheel_separations: every separation written (m), one per wheel pair for Gazebo classic.
        wheel_radii: every radius written (m); half the diameter for Gazebo classic.
        topics: the ROS topics of a Gazebo classic ROS plugin by their default names:
            ``cmd_vel``, the geometry_msgs/Twist commands it takes, and ``odom``, the
            nav_msgs/Odometry it publishes (``/demo/cmd_demo``: see :func:`ros_topic`); empty
            for plugins outside ROS (gz-sim's, whose topics reach ROS only through a bridge,
            and Gazebo classic's own).

    A plugin without a separation or radius runs with its own default (gz-sim: 1.0 m and 0.2 m),
    which is rarely the robot's; the fields stay empty so that a check can say so.
    """

    kind: str
    plugin: str
    left_joints: tuple[str, ...]
    right_joints: tuple[str, ...]
    wheel_separations: tuple[float, ...] = ()
    wheel_radii: tuple[float, ...] = ()
    topics: Mapping[str, str] = field(default_factory=dict, compare=False)

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
_CLASSIC_OWN = re.compile(r"^(lib)?DiffDrivePlugin(\.so)?$")
_SKID_STEER = re.compile(r"^(lib)?gazebo_ros_skid_steer_drive(\.so)?$")
_GZ_SIM = re.compile(r"^(lib)?(gz-sim|ignition-gazebo)\d*-diff-drive-system(\.so)?$")
_GZ_SIM_NAMES = frozenset({"gz::sim::systems::DiffDrive", "ignition::gazebo::systems::DiffDrive"})
#: Plugins that drive a base but not as a differential drive: gz-sim's AckermannSteering and
#: MecanumDrive systems, Gazebo classic's ackermann and tricycle drives.
_OTHER_DRIVE = re.compile(r"(ackermann|steering|tricycle|bicycle|mecanum|omni|swerve)", re.I)
#: The elements of the diff-drive plugins that name a joint.
_JOINT_TAGS = frozenset(
    {
        "left_joint",
        "right_joint",
        "leftJoint",
        "rightJoint",
        "leftFrontJoint",
        "leftRearJoint",
        "rightFrontJoint",
        "rightRearJoint",
    }
)
_ROS2_CONTROL = re.compile(r"^(lib)?(gazebo_ros2_control|gz_ros2_control|ign_ros2_control)")


def _plugin_texts(plugin: Element, *tags: str) -> list[str]:
    return [(child.text or "").strip() for child in plugin if child.tag in tags]


def _plugin_lengths(plugin: Element, filename: str, tag: str, scale: float) -> tuple[float, ...]:
    values = []
    for text in _plugin_texts(plugin, tag):
        value = positive_written(text)
        if value is None:
            raise GazeboPluginError(
                f"Gazebo plugin {filename!r}: <{tag}> must be a positive length in m, got {text!r}"
            )
        values.append(value * scale)
    return tuple(values)


#: The ROS 1 plugins' elements that name each topic of a drive plugin.
_ROS1_TOPIC_TAGS = {"cmd_vel": "commandTopic", "odom": "odometryTopic"}


def ros_topic(plugin: Element, name: str) -> str:
    """The absolute ROS topic a Gazebo classic ROS drive plugin uses for its topic ``name``
    (``cmd_vel``: the Twist commands it subscribes; ``odom``: the odometry it publishes).

    ROS 2's ``gazebo_ros_diff_drive`` uses ``name`` in its ``<ros><namespace>``, as a
    ``<remapping>FROM:=TO</remapping>`` (or an older ``<argument>``, which may also set
    ``__ns:=``) renames it when FROM names the same topic (``cmd_vel``, ``/ns/cmd_vel``; not
    ``/cmd_vel`` in another namespace); ROS 1's plugins use ``<commandTopic>`` and
    ``<odometryTopic>`` (default ``cmd_vel`` and ``odom``) in their ``<robotNamespace>``.
    Without a namespace the plugin is in the one it is spawned in, the root unless the spawner
    is told another. Names are expanded as rcl expands them: ``/`` absolute, ``~`` the
    plugin's node (its ``name``), else in the namespace.
    """
    namespace = next(iter(_plugin_texts(plugin, "robotNamespace")), "")
    topic = next((t for t in _plugin_texts(plugin, _ROS1_TOPIC_TAGS[name]) if t), name)
    rules: list[tuple[str, str]] = []
    for ros in (child for child in plugin if child.tag == "ros"):
        for child in ros:
            text = (child.text or "").strip()
            if child.tag == "namespace" and text:
                namespace = text
            elif child.tag in ("remapping", "argument"):
                for word in text.split():
                    source, said, target = word.partition(":=")
                    if said and target and source == "__ns":
                        namespace = target
                    elif said and target:
                        rules.append((source, target))
    node = plugin.get("name", "")

    def expanded(written: str) -> str:
        if written.startswith("~"):
            written = node + written[1:]
        parts = [] if written.startswith("/") else namespace.split("/")
        return "/" + "/".join(part for part in (*parts, *written.split("/")) if part)

    full = expanded(topic)
    # rcl applies the first rule that matches.
    return next((expanded(to) for source, to in rules if expanded(source) == full), full)


def scoped_plugin(plugin: Element, prefix: str) -> Element:
    """A plugin of a nested or included SDF model as the whole model holds it: the joints it
    names are the model's own, each named with ``prefix`` (``wheels::``) before it, as the
    simulator finds them in the model the plugin is attached to. ``plugin`` is not changed."""
    if not prefix:
        return plugin
    scoped = copy.deepcopy(plugin)
    for child in scoped:
        if child.tag in _JOINT_TAGS and (child.text or "").strip():
            child.text = prefix + (child.text or "").strip()
    return scoped


def gazebo_drives(root: Element) -> list[GazeboDrive]:
    """The Gazebo diff-drive plugins of an expanded description.

    Gazebo classic's ``libgazebo_ros_diff_drive.so`` (ROS 2 tags ``left_joint``, ``right_joint``,
    ``wheel_separation``, ``wheel_diameter``, repeated per wheel pair; ROS 1 tags ``leftJoint``,
    ``rightJoint``, ``wheelSeparation``, ``wheelDiameter``), Gazebo classic's
    ``libgazebo_ros_skid_steer_drive.so`` (``leftFrontJoint``, ``leftRearJoint``,
    ``rightFrontJoint``, ``rightRearJoint``, ``wheelSeparation``, ``wheelDiameter``: it drives
    both wheels of a side alike, as a diff drive of that separation) and the gz-sim / Ignition
    DiffDrive system (``left_joint`` and ``right_joint`` repeated per wheel, ``wheel_separation``,
    ``wheel_radius``). Gazebo classic's own ``libDiffDrivePlugin.so`` (``left_joint``,
    ``right_joint``, ``torque``) takes no lengths: it runs with the distance between the two
    joints' anchors (their frames, whatever their lateral offset) and the radius of the left
    wheel link's first collision, a cylinder or a sphere, as its ``Init`` measures them.

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
        topics: dict[str, str] = {}
        if _CLASSIC.match(filename):
            kind = "gazebo_ros_diff_drive"
            separations = _plugin_lengths(plugin, filename, "wheel_separation", 1.0)
            separations += _plugin_lengths(plugin, filename, "wheelSeparation", 1.0)
            radii = _plugin_lengths(plugin, filename, "wheel_diameter", 0.5)
            radii += _plugin_lengths(plugin, filename, "wheelDiameter", 0.5)
            left = _plugin_texts(plugin, "left_joint", "leftJoint")
            right = _plugin_texts(plugin, "right_joint", "rightJoint")
            topics = {name: ros_topic(plugin, name) for name in _ROS1_TOPIC_TAGS}
        elif _CLASSIC_OWN.match(filename):
            # Gazebo classic's own plugin takes no lengths: it measures them when it starts.
            kind = "gazebo_diff_drive"
            left = _plugin_texts(plugin, "left_joint")
            right = _plugin_texts(plugin, "right_joint")
            separations, radii = _measured(root, left[:1], right[:1])
        elif _SKID_STEER.match(filename):
            kind = "gazebo_ros_skid_steer_drive"
            separations = _plugin_lengths(plugin, filename, "wheelSeparation", 1.0)
            radii = _plugin_lengths(plugin, filename, "wheelDiameter", 0.5)
            left = _plugin_texts(plugin, "leftFrontJoint", "leftRearJoint")
            right = _plugin_texts(plugin, "rightFrontJoint", "rightRearJoint")
            topics = {name: ros_topic(plugin, name) for name in _ROS1_TOPIC_TAGS}
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
                topics=topics,
            )
        )
    return drives


def _anchor(root: Element, name: str) -> tuple[float, float, float] | None:
    """Where a joint's frame lies in the root link's frame (m), every joint at rest (0); None
    when the joint is unknown, malformed or the links do not form a chain to a root."""
    joints = {j.get("name"): j for j in root.iter("joint")}
    by_child: dict[str | None, Element] = {}
    for joint in joints.values():
        child = joint.find("child")
        if child is not None:
            by_child.setdefault(child.get("link"), joint)
    chain: list[Element] = []
    step = joints.get(name)
    while step is not None and len(chain) <= len(joints):
        chain.append(step)
        parent = step.find("parent")
        step = by_child.get(None if parent is None else parent.get("link"))
    if not chain or len(chain) > len(joints):
        return None
    from diffbot.urdf.meshes import origin_matrix
    from diffbot.urdf.poses import identity, multiply

    frame = identity()
    for joint in reversed(chain):
        try:
            pose = origin_matrix(joint.find("origin"), f"joint {name!r}")
        except DescriptionError:
            return None
        frame = multiply(frame, pose)
    return frame[0][3], frame[1][3], frame[2][3]


def _measured(
    root: Element, left: list[str], right: list[str]
) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """The separation and radius Gazebo classic's DiffDrivePlugin measures (m), each empty
    when it cannot be measured."""
    from diffbot.urdf.ros1 import urdf_radius

    separations: tuple[float, ...] = ()
    radii: tuple[float, ...] = ()
    if left and right:
        a, b = _anchor(root, left[0]), _anchor(root, right[0])
        distance = math.dist(a, b) if a is not None and b is not None else math.nan
        if math.isfinite(distance) and distance > 0.0:
            separations = (distance,)
    if left:
        radius = urdf_radius(root, left[0])
        if radius is not None:
            radii = (radius,)
    return separations, radii


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


def other_drive_plugins(root: Element) -> list[str]:
    """The plugins of an expanded description that drive a base but not as a differential
    drive (gz-sim ``AckermannSteering`` or ``MecanumDrive``, Gazebo classic
    ``gazebo_ros_ackermann_drive``...), each named by its ``name`` when that is a system's
    scoped name, else by its ``filename``; in document order."""
    found: list[str] = []
    for plugin in root.iter("plugin"):
        filename, name = plugin.get("filename", ""), plugin.get("name", "")
        if _OTHER_DRIVE.search(filename) or ("::" in name and _OTHER_DRIVE.search(name)):
            label = name if "::" in name else filename
            if label not in found:
                found.append(label)
    return found
