"""Recordings shaped like a real Pioneer 3-DX's: its driver publishes raw encoder counts, 128 per
mm of wheel travel, on a 16-bit counter that wraps around, 10 times a second, the counts
stamped 100 ms after the poses they belong to."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from bags import write_bag_with_odometry
from robots import two_wheel_urdf
from wheel_motion import Segment, wheel_samples

from diffbot.kinematics import DiffDriveParams, Pose

#: The topic of the Pioneer's joint states.
TOPIC = "/pioneer5/joint_states"
#: The Pioneer's wheel radius (m) and separation (m), as its URDF gives them.
RADIUS = 0.0975
SEPARATION = 0.33
#: Encoder counts per mm of wheel travel.
COUNTS_PER_MM = 128
#: Counts per wheel revolution: 128 per mm around a 97.5 mm wheel.
COUNTS_PER_REV = COUNTS_PER_MM * 1000.0 * 2.0 * math.pi * RADIUS
#: The counter's modulus (16 bits).
WRAP = 65536
#: How late the counts are stamped (ns).
LATE_NS = 100_000_000
#: A start in 2026, like a real bag's stamps (ns).
START_NS = 1_764_000_000_000_000_000
PIONEER = DiffDriveParams(
    wheel_radius=RADIUS,
    wheel_separation=SEPARATION,
    left_joint="left_wheel_joint",
    right_joint="right_wheel_joint",
)
#: A metre forward at 0.25 m/s, a quarter turn left on the spot, half a metre forward.
RUN: list[Segment] = [
    (0.25, 0.0, 4.0, 40),
    (0.0, math.pi / 8, 4.0, 40),
    (0.25, 0.0, 2.0, 20),
]
#: Where RUN ends.
RUN_END = Pose(1.0, 0.5, math.pi / 2)


def urdf(folder: Path) -> Path:
    """The Pioneer as a two-wheel URDF (the joints of :data:`PIONEER`)."""
    half = SEPARATION / 2
    path = folder / "pioneer.urdf"
    path.write_text(
        two_wheel_urdf(radius=str(RADIUS), left_xyz=f"0 {half} 0", right_xyz=f"0 -{half} 0"),
        encoding="utf-8",
    )
    return path


def counts(
    segments: list[Segment] = RUN, start_mm: float = 30_000.0
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The run as the driver records it: stamps (ns, int64), left and right counts (0..65535).

    The counters start ``start_mm`` of travel into their range, so they wrap early on.
    """
    stamps, lefts, rights = wheel_samples(PIONEER, segments)
    stamps_ns = START_NS + LATE_NS + np.rint(np.array(stamps) * 1e9).astype(np.int64)
    travel = [np.array(side) * RADIUS * 1000.0 + start_mm for side in (lefts, rights)]
    left, right = (np.rint(mm * COUNTS_PER_MM) % WRAP for mm in travel)
    return stamps_ns, left, right


def truth(segments: list[Segment] = RUN) -> tuple[np.ndarray, list[Pose]]:
    """The poses the counts belong to, stamped on time (ns): 100 ms before the counts."""
    import diffbot

    stamps, lefts, rights = wheel_samples(PIONEER, segments)
    poses = diffbot.integrate(PIONEER, lefts, rights)
    stamps_ns = START_NS + np.rint(np.array(stamps) * 1e9).astype(np.int64)
    return stamps_ns, [
        Pose(float(x), float(y), float(th))
        for x, y, th in zip(poses.x, poses.y, poses.theta, strict=True)
    ]


def counts_csv(folder: Path, name: str = "pioneer.csv", segments: list[Segment] = RUN) -> Path:
    """The counts as a CSV with the joints' names as columns, stamps in seconds."""
    stamps_ns, left, right = counts(segments)
    lines = [f"time,{PIONEER.left_joint},{PIONEER.right_joint}"]
    for stamp, lc, rc in zip(stamps_ns.tolist(), left.tolist(), right.tolist(), strict=True):
        whole, frac = divmod(stamp, 1_000_000_000)
        lines.append(f"{whole}.{frac:09d},{int(lc)},{int(rc)}")
    path = folder / name
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def truth_csv(folder: Path, name: str, segments: list[Segment] = RUN) -> Path:
    """The true poses as a CSV (time, x, y, theta), stamped on time (100 ms before the counts)."""
    stamps_ns, poses = truth(segments)
    lines = ["time,x,y,theta"]
    for stamp, pose in zip(stamps_ns.tolist(), poses, strict=True):
        whole, frac = divmod(stamp, 1_000_000_000)
        lines.append(f"{whole}.{frac:09d},{pose.x!r},{pose.y!r},{pose.theta!r}")
    path = folder / name
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def pioneer_messages() -> list[tuple[int, int, list[str], list[float]]]:
    stamps, left, right = counts()
    joints = [PIONEER.left_joint, PIONEER.right_joint]
    return [
        (stamp, stamp, joints, [lc, rc])
        for stamp, lc, rc in zip(stamps.tolist(), left.tolist(), right.tolist(), strict=True)
    ]


def reference_bag(tmp_path: Path, drift: float = 0.0) -> Path:
    """The Pioneer's counts and its own odometry on /odom (the true poses, stamped on time with
    the counts), drifting ``drift`` m along x per sample."""
    stamps, poses = truth()
    messages = pioneer_messages()
    reference = [
        (int(stamp) + LATE_NS, pose.x + drift * k, pose.y, pose.theta)
        for k, (stamp, pose) in enumerate(zip(stamps.tolist(), poses, strict=True))
    ]
    return write_bag_with_odometry(tmp_path / "bag", messages, reference, topic=TOPIC)
