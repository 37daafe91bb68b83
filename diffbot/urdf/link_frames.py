"""Every link's transform from its parent, at given joint positions: what robot_state_publisher
broadcasts on /tf_static (fixed joints) and /tf (moving ones).

A joint's transform is its origin (parent frame -> joint frame) times its motion at the position:
a rotation by the angle about the axis (revolute, continuous), a translation along the axis
(prismatic), none (fixed). Rotations come out as unit quaternions (x, y, z, w) with w >= 0.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

from diffbot.urdf.tree import Joint, joints_of, parse_urdf

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray

__all__ = ["LinkTransform", "description_joints", "link_transform", "quaternion_of"]

#: Joints whose child moves with a position.
MOVING = ("revolute", "continuous", "prismatic")


@dataclass(frozen=True)
class LinkTransform:
    """The child link's frame in the parent's: translation (m) and rotation (x, y, z, w)."""

    parent: str
    child: str
    translation: tuple[float, float, float]
    rotation: tuple[float, float, float, float]


def description_joints(urdf: str, source: str = "description") -> list[Joint]:
    """The joints of a URDF text, fixed and moving, mimic and planar/floating ones aside (they
    need positions this robot does not have)."""
    robot = parse_urdf(urdf, source)
    return [
        joint
        for joint in joints_of(robot, source).values()
        if not joint.mimic and (joint.type == "fixed" or joint.type in MOVING)
    ]


def link_transform(joint: Joint, position: float = 0.0) -> LinkTransform:
    """The child's frame in the parent's with the joint at ``position`` (rad or m)."""
    moved = (
        joint.origin
        @ replace(joint, rest=position if joint.type in MOVING else 0.0).rest_transform()
    )
    x, y, z = (float(v) for v in moved[:3, 3])
    return LinkTransform(joint.parent, joint.child, (x, y, z), quaternion_of(moved[:3, :3]))


def quaternion_of(matrix: NDArray[np.float64]) -> tuple[float, float, float, float]:
    """The unit quaternion (x, y, z, w), w >= 0, of a 3x3 rotation matrix (Shepperd's method:
    the largest of the four squared components is computed first, for accuracy)."""
    m = [[float(matrix[i][j]) for j in range(3)] for i in range(3)]
    trace = m[0][0] + m[1][1] + m[2][2]
    if trace > 0.0:
        s = 2.0 * math.sqrt(1.0 + trace)
        q = ((m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s, 0.25 * s)
    elif m[0][0] > m[1][1] and m[0][0] > m[2][2]:
        s = 2.0 * math.sqrt(1.0 + m[0][0] - m[1][1] - m[2][2])
        q = (0.25 * s, (m[0][1] + m[1][0]) / s, (m[0][2] + m[2][0]) / s, (m[2][1] - m[1][2]) / s)
    elif m[1][1] > m[2][2]:
        s = 2.0 * math.sqrt(1.0 + m[1][1] - m[0][0] - m[2][2])
        q = ((m[0][1] + m[1][0]) / s, 0.25 * s, (m[1][2] + m[2][1]) / s, (m[0][2] - m[2][0]) / s)
    else:
        s = 2.0 * math.sqrt(1.0 + m[2][2] - m[0][0] - m[1][1])
        q = ((m[0][2] + m[2][0]) / s, (m[1][2] + m[2][1]) / s, 0.25 * s, (m[1][0] - m[0][1]) / s)
    norm = math.sqrt(sum(c * c for c in q))
    sign = -1.0 if q[3] < 0.0 else 1.0
    return (sign * q[0] / norm, sign * q[1] / norm, sign * q[2] / norm, sign * q[3] / norm)
