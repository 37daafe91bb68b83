"""Poses as plain 4x4 matrices (lists of rows), for the readers that work without NumPy."""

from __future__ import annotations

import math

__all__ = ["Matrix", "pose_matrix"]

#: A 4x4 homogeneous transform as four rows.
Matrix = list[list[float]]


def pose_matrix(x: float, y: float, z: float, roll: float, pitch: float, yaw: float) -> Matrix:
    """The transform of a translation (m) and fixed-axis roll, pitch, yaw (rad): R = Rz Ry Rx,
    the convention of URDF's ``rpy`` and SDF's ``<pose>``."""
    cr, sr, cp, sp = math.cos(roll), math.sin(roll), math.cos(pitch), math.sin(pitch)
    cy, sy = math.cos(yaw), math.sin(yaw)
    return [
        [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr, x],
        [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr, y],
        [-sp, cp * sr, cp * cr, z],
        [0.0, 0.0, 0.0, 1.0],
    ]
