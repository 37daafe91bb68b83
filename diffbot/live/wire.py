"""What arrives on the wire, checked once, in one place, for every node.

A message is someone else's numbers: each one a node computes with passes these checks before
it touches the node's state. Every number the node uses must be finite and within a physical
range (a wheel turning 1e300 rad, a twist of 1e308 m/s, a stamp years ahead are garbage, not
motion); a failed check names its reason, and the node counts the message under it (its
status line says how many) and skips it. A bad message never ends a node and never changes
what the next good one does.

The ranges are far beyond any robot's (a unit mistake passes; it is the controller's limits
that bound the motion), and small enough that everything computed from a value stays finite.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from typing import Final

from diffbot.numbers import (
    MAX_ANGULAR_SPEED,
    MAX_COORDINATE,
    MAX_LINEAR_SPEED,
    MAX_RECORDED_ANGLE,
    MAX_WHEEL_SPEED,
)
from diffbot.samples import SKIP_NOT_FINITE

__all__ = [
    "BAD_STAMP",
    "MAX_STAMP_AHEAD_NS",
    "NOT_FINITE",
    "OUT_OF_RANGE",
    "STAMPED_AHEAD",
    "WRONG_LENGTH",
    "Refusals",
    "joint_state_problem",
    "planar_pose_problem",
    "pose_problem",
    "twist_problem",
    "wheel_problem",
]

#: Why a message was refused: a NaN or an infinity (the reason a recorded sample is skipped for).
NOT_FINITE: Final = SKIP_NOT_FINITE
#: A number beyond its physical range.
OUT_OF_RANGE: Final = "out of range"
#: A stamp before 1970 (negative seconds: ROS time is never negative) or with nanoseconds not
#: within 0..999999999.
BAD_STAMP: Final = "bad stamp"
#: A stamp further ahead of this machine's clock than :data:`MAX_STAMP_AHEAD_NS`.
STAMPED_AHEAD: Final = "stamped in the future"
#: Not one value per joint.
WRONG_LENGTH: Final = "wrong length"

#: Furthest a stamp may lie ahead of this machine's clock (ns): clocks on one network agree
#: far better; a stamp beyond it would hold up every later message as "going back in time".
MAX_STAMP_AHEAD_NS: Final = 60 * 1_000_000_000
#: How far a pose's quaternion may be from unit length (squared norm within 1 +- this): a
#: rounding error passes, a zero or a scaled quaternion is no rotation.
QUATERNION_SLACK: Final = 0.1


def _number_problem(value: float, bound: float) -> str | None:
    # x - x is 0.0 for every finite x and NaN for NaN and the infinities.
    if value - value != 0.0:
        return NOT_FINITE
    if abs(value) > bound:
        return OUT_OF_RANGE
    return None


def _values_problem(values: Sequence[float], bound: float) -> str | None:
    for value in values:
        problem = _number_problem(value, bound)
        if problem is not None:
            return problem
    return None


def twist_problem(linear: float, angular: float) -> str | None:
    """Why a velocity command of ``linear`` (m/s) and ``angular`` (rad/s) is refused, or
    None."""
    return _number_problem(linear, MAX_LINEAR_SPEED) or _number_problem(angular, MAX_ANGULAR_SPEED)


def wheel_problem(values: Sequence[float], joints: int) -> str | None:
    """Why one side's joint velocity commands (rad/s) for ``joints`` joints are refused, or
    None."""
    if len(values) != joints:
        return WRONG_LENGTH
    return _values_problem(values, MAX_WHEEL_SPEED)


def joint_state_problem(
    sec: int,
    nanosec: int,
    values: Sequence[float],
    now_ns: int | None = None,
    *,
    velocity: bool = False,
) -> str | None:
    """Why a joint state stamped ``sec``/``nanosec`` with joint angles ``values`` (rad), or with
    ``velocity`` joint velocities (rad/s), is refused, or None. ``now_ns``: this machine's clock
    (ns; read when None)."""
    bound = MAX_WHEEL_SPEED if velocity else MAX_RECORDED_ANGLE
    return _stamp_problem(sec, nanosec, now_ns) or _values_problem(values, bound)


def _stamp_problem(sec: int, nanosec: int, now_ns: int | None) -> str | None:
    """Why a stamp is refused (before 1970, nanoseconds out of their range, or further ahead
    of this machine's clock ``now_ns`` than :data:`MAX_STAMP_AHEAD_NS`; read when None), or
    None. A negative stamp would start a wheel's clock decades back, and the next good message
    would then hold its velocity over all those years."""
    if sec < 0 or not 0 <= nanosec < 1_000_000_000:
        return BAD_STAMP
    now = time.time_ns() if now_ns is None else now_ns
    if sec * 1_000_000_000 + nanosec - now > MAX_STAMP_AHEAD_NS:
        return STAMPED_AHEAD
    return None


def pose_problem(
    sec: int,
    nanosec: int,
    position: Sequence[float],
    orientation: Sequence[float],
    now_ns: int | None = None,
) -> str | None:
    """Why a pose stamped ``sec``/``nanosec`` at ``position`` (x, y, z in m) with the quaternion
    ``orientation`` (x, y, z, w) is refused, or None. ``now_ns``: this machine's clock (ns;
    read when None)."""
    stamp = _stamp_problem(sec, nanosec, now_ns)
    if stamp is not None:
        return stamp
    for value in position:
        problem = _number_problem(value, MAX_COORDINATE)
        if problem is not None:
            return problem
    for value in orientation:
        problem = _number_problem(value, 1.0 + QUATERNION_SLACK)
        if problem is not None:
            return problem
    if abs(sum(q * q for q in orientation) - 1.0) > QUATERNION_SLACK:
        return OUT_OF_RANGE
    return None


def planar_pose_problem(x: float, y: float, yaw: float) -> str | None:
    """Why a planar pose asked for (x, y in m, yaw in rad: a ``set_odometry`` request) is
    refused, or None: positions within the poses' bound, a heading within the angles'."""
    return (
        _number_problem(x, MAX_COORDINATE)
        or _number_problem(y, MAX_COORDINATE)
        or _number_problem(yaw, MAX_RECORDED_ANGLE)
    )


class Refusals:
    """Messages refused, by reason, in the order the reasons first came."""

    def __init__(self) -> None:
        self.counts: dict[str, int] = {}

    def check(self, problem: str | None) -> bool:
        """Count ``problem`` (a reason, or None); whether the message passed."""
        if problem is None:
            return True
        self.counts[problem] = self.counts.get(problem, 0) + 1
        return False

    @property
    def total(self) -> int:
        """Messages refused."""
        return sum(self.counts.values())
