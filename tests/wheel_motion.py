"""Wheel motion in closed form, for tests: constant-velocity segments and where they end."""

from __future__ import annotations

import math
from collections.abc import Sequence

import pytest

import diffbot
from diffbot.kinematics import DiffDriveParams, Pose, norm_angle

#: Trajectory A of the seed (bundled robot): ccw 0.25 m 180 deg, 1 m, cw 0.25 m 180 deg, 1 m,
#: 10 s each, as (linear m/s, angular rad/s, duration s, steps at 10 Hz); it ends at (0, 1, 0).
TRAJECTORY_A: list[tuple[float, float, float, int]] = [
    (0.025 * math.pi, math.pi / 10, 10.0, 100),
    (0.1, 0.0, 10.0, 100),
    (0.025 * math.pi, -math.pi / 10, 10.0, 100),
    (0.1, 0.0, 10.0, 100),
]


def angle_error(a: float, b: float) -> float:
    """The smallest rotation (rad) between two headings, whole turns ignored."""
    return abs(norm_angle(a - b))


def assert_pose_close(pose: Pose, expected: Pose, tol: float = 1e-9) -> None:
    assert pose.x == pytest.approx(expected.x, abs=tol)
    assert pose.y == pytest.approx(expected.y, abs=tol)
    assert angle_error(pose.theta, expected.theta) <= tol


def closed_form(pose: Pose, linear: float, angular: float, duration: float) -> Pose:
    """Where a constant body velocity for ``duration`` s takes the robot (an arc or a line)."""
    x, y, theta = pose
    if angular == 0.0:
        return Pose(
            x + linear * duration * math.cos(theta),
            y + linear * duration * math.sin(theta),
            theta,
        )
    radius = linear / angular
    end = theta + angular * duration
    return Pose(
        x + radius * (math.sin(end) - math.sin(theta)),
        y - radius * (math.cos(end) - math.cos(theta)),
        end,
    )


Segment = tuple[float, float, float, int]  # linear (m/s), angular (rad/s), duration (s), steps


def wheel_samples(
    params: DiffDriveParams, segments: Sequence[Segment], start: tuple[float, float] = (0.0, 0.0)
) -> tuple[list[float], list[float], list[float]]:
    """Stamps and joint angles of constant-velocity segments, a sample on every boundary."""
    left, right = start
    stamp = 0.0
    stamps, lefts, rights = [stamp], [left], [right]
    for linear, angular, duration, steps in segments:
        speeds = diffbot.inverse(params, linear, angular)
        joint_left = params.left_sign * float(speeds.left)
        joint_right = params.right_sign * float(speeds.right)
        for k in range(1, steps + 1):
            t = duration * k / steps
            stamps.append(stamp + t)
            lefts.append(left + joint_left * t)
            rights.append(right + joint_right * t)
        stamp += duration
        left += joint_left * duration
        right += joint_right * duration
    return stamps, lefts, rights


def trajectory_a_velocities(start_ns: int = 0) -> list[tuple[int, float, float]]:
    """Trajectory A of the course's robot at 10 Hz as (stamp ns, left, right joint velocity
    rad/s): each sample holds the velocity of the step that ends at it (the first: 0)."""
    params = DiffDriveParams(wheel_radius=0.035, wheel_separation=0.135)
    rows = [(start_ns, 0.0, 0.0)]
    stamp = 0.0
    for linear, angular, duration, steps in TRAJECTORY_A:
        speeds = diffbot.inverse(params, linear, angular)
        for k in range(1, steps + 1):
            t = stamp + duration * k / steps
            rows.append((start_ns + round(t * 1e9), float(speeds.left), float(speeds.right)))
        stamp += duration
    return rows
