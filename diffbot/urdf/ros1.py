"""What ROS 1's diff_drive_controller (ros_controllers) reads from the URDF itself.

When its YAML leaves out ``wheel_separation`` or ``wheel_radius``, the controller takes them from
``robot_description`` before applying its multipliers: the separation is the distance between
the origins of the first left and first right wheel joints (each in its parent link's frame), the
radius that of the first left wheel link's first collision, a cylinder or a sphere.
"""

from __future__ import annotations

import math
from xml.etree.ElementTree import Element

from diffbot.numbers import positive_written, written_number

__all__ = ["urdf_radius", "urdf_separation"]


def _joint(root: Element, name: str) -> Element | None:
    return next((j for j in root.iter("joint") if j.get("name") == name), None)


def _xyz(joint: Element) -> tuple[float, float, float] | None:
    origin = joint.find("origin")
    text = "0 0 0" if origin is None else origin.get("xyz", "0 0 0")
    try:
        x, y, z = (written_number(v) for v in text.split())
    except ValueError:
        return None
    return x, y, z


def urdf_separation(root: Element, left: str, right: str) -> float | None:
    """The separation (m) the controller looks up: the distance between the joints' origins, or
    None when a joint is missing or malformed."""
    joints = [_joint(root, left), _joint(root, right)]
    if joints[0] is None or joints[1] is None:
        return None
    a, b = _xyz(joints[0]), _xyz(joints[1])
    if a is None or b is None:
        return None
    distance = math.dist(a, b)
    return distance if math.isfinite(distance) and distance > 0.0 else None


def urdf_radius(root: Element, left: str) -> float | None:
    """The radius (m) the controller looks up: the left wheel link's first collision, when it is
    a cylinder or a sphere; None otherwise."""
    joint = _joint(root, left)
    child = None if joint is None else joint.find("child")
    link_name = None if child is None else child.get("link")
    link = next((k for k in root.iter("link") if k.get("name") == link_name), None)
    collision = None if link is None else link.find("collision")
    geometry = None if collision is None else collision.find("geometry")
    if geometry is None:
        return None
    shape = geometry.find("cylinder")
    if shape is None:
        shape = geometry.find("sphere")
    return None if shape is None else positive_written(shape.get("radius", ""))
