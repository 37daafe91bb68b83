"""Recordings as CSV text: poses and joint states out, a chunk at a time or whole.

Reading recording CSVs is :mod:`diffbot.io.csv_chunks`. Floats are printed so that they read
back exactly; stamps as exact decimal seconds.
"""

from __future__ import annotations

import io
from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING, Final

from diffbot.kinematics import norm_angle
from diffbot.samples import OdometryRow, OdometryRows, seconds_text

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = [
    "ODOMETRY_HEADER",
    "format_joint_states_csv",
    "format_odometry_csv",
    "joint_states_header",
    "joint_states_lines",
    "odometry_lines",
]

#: The header line of an odometry CSV.
ODOMETRY_HEADER: Final = "time,x,y,theta,linear,angular\n"


def odometry_lines(
    stamps_ns: Iterable[int],
    x: Iterable[float],
    y: Iterable[float],
    heading: Iterable[float],
    linear: Iterable[float],
    angular: Iterable[float],
) -> str:
    """Odometry rows as CSV lines (no header): the heading is reported in (-pi, pi]."""
    out = io.StringIO()
    write = out.write
    for stamp_ns, x_, y_, heading_, linear_, angular_ in zip(
        stamps_ns, x, y, heading, linear, angular, strict=True
    ):
        theta = norm_angle(heading_)
        write(f"{seconds_text(stamp_ns)},{x_!r},{y_!r},{theta!r},{linear_!r},{angular_!r}\n")
    return out.getvalue()


def format_odometry_csv(rows: Iterable[OdometryRow]) -> str:
    """Poses as CSV text: ``time,x,y,theta,linear,angular`` (s, m, m, rad in (-pi, pi], m/s,
    rad/s); floats printed so that they read back exactly."""
    if isinstance(rows, OdometryRows):  # from the columns: no records per row
        columns = (rows.stamps_ns, rows.x, rows.y, rows.heading, rows.linear, rows.angular)
        return ODOMETRY_HEADER + odometry_lines(*columns)
    records = list(rows)
    return ODOMETRY_HEADER + odometry_lines(
        (row.stamp_ns for row in records),
        (float(row.pose.x) for row in records),
        (float(row.pose.y) for row in records),
        (float(row.pose.theta) for row in records),
        (float(row.twist.linear) for row in records),
        (float(row.twist.angular) for row in records),
    )


def joint_states_header(names: Sequence[str]) -> str:
    """The header line of a joint states CSV: ``time`` then one column per joint."""
    return ",".join(["time", *names]) + "\n"


def joint_states_lines(stamps_ns: Sequence[int], positions: ArrayLike) -> str:
    """Joint states as CSV lines (no header).

    Args:
        stamps_ns: the stamps (ns), one per row.
        positions: joint angles (rad), shape (joints, len(stamps_ns)): one row per joint.
    """
    import numpy as np

    columns = np.asarray(positions, dtype=np.float64)
    rows = columns.reshape(-1, len(stamps_ns)).T
    out = io.StringIO()
    for stamp_ns, values in zip(stamps_ns, rows.tolist(), strict=True):
        out.write(f"{seconds_text(stamp_ns)},{','.join(map(repr, values))}\n")
    return out.getvalue()


def format_joint_states_csv(
    stamps_ns: Sequence[int], names: Sequence[str], positions: ArrayLike
) -> str:
    """Joint positions as CSV text: ``time`` (s) then one column (rad) per joint, by name.

    Args:
        stamps_ns: the stamps (ns), one per row.
        names: the joint names, the column headers.
        positions: joint angles (rad), shape (len(names), len(stamps_ns)): one row per joint.
    """
    import numpy as np

    columns = np.asarray(positions, dtype=np.float64).reshape(len(names), len(stamps_ns))
    return joint_states_header(names) + joint_states_lines(stamps_ns, columns)
