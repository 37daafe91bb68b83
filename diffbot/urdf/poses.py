"""Poses as plain 4x4 matrices (lists of rows), for the readers that work without NumPy."""

from __future__ import annotations

import math

__all__ = ["Matrix", "identity", "multiply", "pose_matrix"]

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


def identity() -> Matrix:
    """The transform that leaves every point where it is."""
    return [[1.0 if i == j else 0.0 for j in range(4)] for i in range(4)]


def multiply(a: Matrix, b: Matrix) -> Matrix:
    """The product of two transforms: ``b`` expressed in the frame ``a`` is relative to."""
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]
