"""Ground-truth pose tracks: a CSV with x, y and theta columns, or a pose topic of a rosbag2
recording (geometry_msgs/PoseStamped from motion capture, nav_msgs/Odometry from a simulator)."""

from __future__ import annotations

import csv
import math
import os
from array import array
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Final

from diffbot.errors import RecordingError
from diffbot.formats.text import listing
from diffbot.io.csv_columns import preferred_time_column
from diffbot.io.csv_lines import RowLines
from diffbot.io.textfile import open_text
from diffbot.numbers import MAX_COORDINATE, MAX_RECORDED_ANGLE, finite_in_range, written_number
from diffbot.samples import INT64, NS_PER_S, ns_from_seconds

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray

__all__ = ["POSE_COLUMNS", "POSE_TYPES", "PoseTrack", "read_pose_track", "yaw_from_quaternion"]

#: The CSV columns of a pose (m, m, rad), case-insensitive; ``yaw`` is read as ``theta`` too.
POSE_COLUMNS: Final = ("x", "y", "theta")
#: The message types a pose topic may carry.
POSE_TYPES: Final = ("geometry_msgs/msg/PoseStamped", "nav_msgs/msg/Odometry")


@dataclass(frozen=True)
class PoseTrack:
    """Poses over time, in file order.

    Attributes:
        source: where they came from (a path, and a topic for a bag), for messages.
        stamps_ns: stamps (ns), int64, shape (n,).
        x: x (m), shape (n,).
        y: y (m), shape (n,).
        theta: heading (rad) as recorded (wrapped or not), shape (n,).
        topic: the bag topic read, as the bag names it; None for a CSV.
    """

    source: str
    stamps_ns: NDArray[np.int64]
    x: NDArray[np.float64]
    y: NDArray[np.float64]
    theta: NDArray[np.float64]
    topic: str | None = None


def yaw_from_quaternion(x: float, y: float, z: float, w: float) -> float:
    """The heading (rad, about z) of a rotation given as a quaternion (any norm but 0).

    NaN when the quaternion gives none: a component not finite, all of them 0 (a message whose
    orientation was never set), or too large to square; a pose read with it is then refused
    as not finite, where atan2 would have made up a heading (0 for the zero quaternion).
    """
    sine = 2.0 * (w * z + x * y)
    cosine = w * w + x * x - y * y - z * z
    if not (math.isfinite(sine) and math.isfinite(cosine)) or sine == cosine == 0.0:
        return math.nan
    return math.atan2(sine, cosine)


def read_pose_track(
    path: str | os.PathLike[str], topic: str | None = None, *, name: str | None = None
) -> PoseTrack:
    """Read a ground-truth pose track.

    Args:
        path: a CSV file (a time column, the first of ``time``, ``stamp``, ``t`` and
            ``__time`` it has, and ``x``, ``y``, ``theta`` or ``yaw``; rows with an empty pose
            cell are skipped), or a rosbag2 recording.
        topic: the pose topic of a bag; by default its one topic of PoseStamped or Odometry.
        name: the CSV's name in messages (default: its path), such as ``-`` for a copy of
            standard input.

    Returns:
        The poses, stamped by their header stamps in a bag (by the receive times when any
        header stamp is zero).

    Raises:
        RecordingError: a missing or malformed file, missing columns, no (or several) pose
            topics, or no pose at all.
    """
    from diffbot.io.bag import is_bag
    from diffbot.io.recordings import existing_recording

    p = existing_recording(path)
    if is_bag(p):
        return _read_bag(p, topic)
    return _read_csv(p, name)


class _Poses:
    """Poses as they are read, in typed arrays: 32 bytes a pose, where a tuple of Python numbers
    takes about 180 (a track of a million poses stays small)."""

    def __init__(self, source: str) -> None:
        self.source = source
        self.stamps = array("q")
        self.x = array("d")
        self.y = array("d")
        self.theta = array("d")

    def append(self, stamp_ns: int, x: float, y: float, theta: float) -> None:
        try:
            self.stamps.append(stamp_ns)
        except OverflowError:
            raise RecordingError(
                f"{self.source}: a stamp of {stamp_ns / NS_PER_S:.6g} s is out of range"
            ) from None
        self.x.append(x)
        self.y.append(y)
        self.theta.append(theta)

    def __len__(self) -> int:
        return len(self.stamps)


def _track(source: str, poses: _Poses, topic: str | None = None) -> PoseTrack:
    import numpy as np

    if not poses.stamps:
        raise RecordingError(f"{source}: no ground-truth pose")
    return PoseTrack(
        source,
        np.frombuffer(poses.stamps, dtype=np.int64),
        np.frombuffer(poses.x, dtype=np.float64),
        np.frombuffer(poses.y, dtype=np.float64),
        np.frombuffer(poses.theta, dtype=np.float64),
        topic,
    )


def _pose(values: Sequence[float], where: str) -> tuple[float, float, float]:
    """x, y (m) and theta (rad) of a ground-truth pose, each finite and within its range
    (:data:`~diffbot.numbers.MAX_COORDINATE`, :data:`~diffbot.numbers.MAX_RECORDED_ANGLE`)."""
    x, y, theta = values
    return (
        finite_in_range(
            x, f"{where}: x", -MAX_COORDINATE, MAX_COORDINATE, error=RecordingError, unit="m"
        ),
        finite_in_range(
            y, f"{where}: y", -MAX_COORDINATE, MAX_COORDINATE, error=RecordingError, unit="m"
        ),
        finite_in_range(
            theta,
            f"{where}: theta",
            -MAX_RECORDED_ANGLE,
            MAX_RECORDED_ANGLE,
            error=RecordingError,
            unit="rad",
        ),
    )


def _read_csv(path: Path, name: str | None = None) -> PoseTrack:
    source = str(path) if name is None else name
    rows = _Poses(source)
    with open_text(path, RecordingError, "a CSV file", name=source, newline="") as stream:
        lines = RowLines(stream, source=source)
        reader = csv.reader(lines)
        headers = [h.strip().lower() for h in next(reader, [])]
        lines.row_done()
        time_index = preferred_time_column(headers)
        names = {"yaw": "theta"}
        columns = {names.get(h, h): i for i, h in reversed(list(enumerate(headers)))}
        missing = [c for c in POSE_COLUMNS if c not in columns]
        if time_index is None or missing:
            wanted = "a time column" if time_index is None else ", ".join(missing)
            raise RecordingError(
                f"{source}: no ground truth: needs {wanted} (time in s, x and y in m, theta "
                f"in rad); columns found: {listing(headers)}"
            )
        indexes = [time_index, *(columns[c] for c in POSE_COLUMNS)]
        try:
            for line, row in enumerate(reader, start=2):
                lines.row_done()
                cells = [row[i].strip() if i < len(row) else "" for i in indexes]
                if not all(cells[1:]):
                    continue
                try:
                    stamp_ns = ns_from_seconds(cells[0]) if cells[0] else None
                    values = [written_number(cell) for cell in cells[1:]]
                except ValueError:
                    stamp_ns = None
                    values = []
                if stamp_ns is None or not all(math.isfinite(v) for v in values):
                    raise RecordingError(f"{source}: line {line}: not a finite time and pose")
                values = list(_pose(values, f"{source}: line {line}"))
                if not -INT64 <= stamp_ns < INT64:
                    raise RecordingError(
                        f"{source}: line {line}: time {cells[0]} s lies outside the int64 "
                        f"nanosecond stamps of ROS (about ±{INT64 / NS_PER_S:.3g} s)"
                    )
                rows.append(stamp_ns, values[0], values[1], values[2])
        except csv.Error as err:
            raise RecordingError(f"{source}: malformed CSV: {err}") from None
    return _track(source, rows)


def _pose_of(message: Any) -> tuple[Any, Any]:
    """The header and the geometry_msgs/Pose of a PoseStamped or an Odometry."""
    pose = message.pose
    return message.header, getattr(pose, "pose", pose)


def _read_bag(path: Path, topic: str | None) -> PoseTrack:
    """A pose topic of a bag, opened as the joint states are (rosbag2 folders with or without
    metadata, lone storage files, ROS 1 bags)."""
    from contextlib import closing

    from diffbot.io.bag import require_rosbags, typestore
    from diffbot.io.bag_chunks import TopicChunks

    require_rosbags()
    source = str(path)
    kinds = " or ".join(POSE_TYPES)

    def choose(topics: dict[str, set[str]]) -> str:
        poses = sorted(t for t, types in topics.items() if types & set(POSE_TYPES))
        if not poses:
            raise RecordingError(f"{source}: no topic of {kinds}: no ground truth")
        if len(poses) > 1:
            raise RecordingError(
                f"{source}: several topics of {kinds} ({listing(poses)}): name the ground "
                "truth's topic"
            )
        return poses[0]

    store = typestore()
    header_rows = _Poses(source)
    receive_rows = _Poses(source)
    with closing(TopicChunks(path, topic, choose=choose)) as chunks:
        if chunks.msgtype not in POSE_TYPES:
            found = sorted(f"{t} ({m})" for t, types in chunks.topics.items() for m in types)
            raise RecordingError(
                f"{source}: no topic {chunks.topic!r} of {kinds}; topics found: {listing(found)}"
            )
        for chunk in chunks:
            assert chunk.receive_ns is not None  # asked for by default
            for received_ns, raw in zip(chunk.receive_ns.tolist(), chunk.blobs, strict=True):
                try:
                    message = store.deserialize_cdr(raw, chunks.msgtype)
                except Exception as err:
                    detail = " ".join(str(err).split()) or type(err).__name__
                    raise RecordingError(
                        f"{source}: a {chunks.msgtype} message cannot be decoded: {detail}"
                    ) from None
                header, pose = _pose_of(message)
                q = pose.orientation
                values = _pose(
                    (
                        float(pose.position.x),
                        float(pose.position.y),
                        yaw_from_quaternion(q.x, q.y, q.z, q.w),
                    ),
                    f"{source}: {chunks.topic} message {len(header_rows) + 1}",
                )
                stamp_ns = int(header.stamp.sec) * NS_PER_S + int(header.stamp.nanosec)
                header_rows.append(stamp_ns, *values)
                receive_rows.append(int(received_ns), *values)
        topic = chunks.topic
    use_header = 0 not in header_rows.stamps
    return _track(f"{source} {topic}", header_rows if use_header else receive_rows, topic)
