"""Odometry of a recording given by path: a CSV file or a rosbag2 JointState topic, read and
integrated chunk by chunk in memory that does not grow with the recording.

The result is that of reading the whole recording and feeding its samples one by one to
:class:`diffbot.odometry.Odometry` (stamps in seconds since the first sample), bit for bit. A
side with several drive wheels is the mean of its joints present in a sample; a sample is
skipped only when a whole side is missing.

A bag topic is stamped by one clock: the header stamps when every readable message has a
non-zero one, otherwise the bag's receive times. A zero header stamp is seen only while
reading, so a topic that turns out to need the receive times is read a second time: the sink
is then told to start again (:meth:`PoseSink.restart`).
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Callable, Sequence
from contextlib import closing
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol, TextIO

import numpy as np

from diffbot.chunk_odometry import ChunkOdometry, ChunkPoses, OdometrySummary, side_means
from diffbot.conditioning import Conditioner, Conditioning, ConditioningReport
from diffbot.errors import RecordingError
from diffbot.formats.text import listing
from diffbot.io.bag import JOINT_STATE, bag_suffix, is_bag, read_bag
from diffbot.io.bag_chunks import CHUNK_MESSAGES, BagError, TopicChunks
from diffbot.io.csv_chunks import CHUNK_BYTES, CsvLayout, open_csv_chunks, read_csv
from diffbot.io.jointstate_cdr import decode_positions
from diffbot.io.outputs import note_input
from diffbot.io.textfile import check_regular
from diffbot.kinematics import DiffDriveParams
from diffbot.odometry import SKIP_MISSING_JOINT
from diffbot.samples import (
    CLOCK_HEADER,
    CLOCK_RECEIVE,
    MAX_POSITION,
    SKIP_POSITION_RANGE,
    SKIP_UNREADABLE,
    JointSample,
    Recording,
    beyond_range,
)

if TYPE_CHECKING:
    from numpy.typing import NDArray

__all__ = [
    "PoseSink",
    "RecordingOdometry",
    "bag_odometry",
    "csv_layout",
    "csv_odometry",
    "existing_recording",
    "read_recording",
    "recording_odometry",
    "recording_size",
]

#: Called with how much of the input a chunk used (messages of a bag, characters of a CSV).
Progress = Callable[[int], None]


class PoseSink(Protocol):
    """Where the poses of a run go as they come."""

    def write(self, poses: ChunkPoses) -> None:
        """Take the poses after the used samples of one chunk, in order."""

    def restart(self) -> None:
        """Drop every pose written so far: the run starts again from the first sample."""


class RecordingOdometry:
    """The odometry of one recording.

    Attributes:
        source: the input's name.
        kind: ``"csv"``, ``"rosbag2"`` or ``"rosbag1"`` (a ROS 1 bag).
        summary: the end of the run.
        clock: for a bag, :data:`~diffbot.samples.CLOCK_HEADER` or
            :data:`~diffbot.samples.CLOCK_RECEIVE`; None for a CSV.
        conditioning: what was done to the recorded positions (units, wraps) and the steps
            found implausible.
        topic: for a bag, the topic read; None for a CSV.
        topic_chosen: whether the topic was not asked for but taken as the bag's only
            JointState topic.
        notes: what the reader judged by itself (a CSV's delimiter, its time unit), for people.
    """

    def __init__(
        self,
        source: str,
        kind: str,
        summary: OdometrySummary,
        clock: str | None,
        conditioning: ConditioningReport,
        topic: str | None = None,
        topic_chosen: bool = False,
        notes: tuple[str, ...] = (),
    ) -> None:
        self.source = source
        self.kind = kind
        self.summary = summary
        self.clock = clock
        self.conditioning = conditioning
        self.topic = topic
        self.topic_chosen = topic_chosen
        self.notes = notes


def csv_odometry(
    path: str | os.PathLike[str] | TextIO,
    params: DiffDriveParams,
    *,
    sink: PoseSink | None = None,
    progress: Progress | None = None,
    source: str | None = None,
    chunk_bytes: int = CHUNK_BYTES,
    conditioning: Conditioning | None = None,
    layout: CsvLayout | None = None,
) -> RecordingOdometry:
    """The odometry of the wheel columns of a recording CSV (a file or a text stream).

    The positions go through a :class:`~diffbot.conditioning.Conditioner` (units, wraps,
    implausible steps) as ``conditioning`` says before they are integrated.

    Raises:
        RecordingError: missing, empty or non-text input, no time column, no column for a side,
            malformed CSV, or no usable sample.
    """
    odom = ChunkOdometry(params)
    sides = (params.left_joints, params.right_joints)
    with open_csv_chunks(
        path, sides, chunk_bytes=chunk_bytes, source=source, layout=layout
    ) as chunks:
        conditioner = Conditioner.for_robot(params, chunks.joints, chunks.left_count, conditioning)
        for chunk in chunks:
            for reason, count in chunk.skipped.items():
                odom.skip(reason, count)
            positions = conditioner.feed(chunk.stamp_ns, chunk.positions, chunk.present)
            left, right, both = side_means(positions, chunk.present, chunks.left_count)
            poses = odom.feed(chunk.stamp_ns, left, right, both)
            if sink is not None:
                sink.write(poses)
            if progress is not None:
                progress(chunk.chars)
        summary = odom.summary(chunks.source)
        report = conditioner.report()
        return RecordingOdometry(chunks.source, "csv", summary, None, report, notes=chunks.notes())


def _bag_pass(
    topic: TopicChunks,
    params: DiffDriveParams,
    clock: str,
    sink: PoseSink | None,
    progress: Progress | None,
    conditioning: Conditioning | None,
) -> tuple[ChunkOdometry, Conditioner] | None:
    """One pass over the topic; None when a zero header stamp asks for the receive clock."""
    odom = ChunkOdometry(params)
    joints = (*params.left_joints, *params.right_joints)
    conditioner = Conditioner.for_robot(params, joints, len(params.left_joints), conditioning)
    for chunk in topic.chunks(receive_times=clock == CLOCK_RECEIVE):
        decoded = decode_positions(chunk.blobs, joints)
        readable = decoded.readable
        header = decoded.stamp_ns[readable]
        if clock == CLOCK_HEADER and not np.all(header):
            return None
        unreadable = int(readable.size - np.count_nonzero(readable))
        odom.skip(SKIP_UNREADABLE, unreadable)
        positions, present = decoded.positions, decoded.present
        if clock == CLOCK_HEADER:
            stamps = header
        else:
            assert chunk.receive_ns is not None  # asked for
            stamps = chunk.receive_ns[readable]
        # Readable messages with a finite wheel position too large to compute with are
        # skipped, as read_recording skips them.
        with np.errstate(invalid="ignore"):
            large = (np.abs(positions) > MAX_POSITION) & np.isfinite(positions) & present
        out_of_range: NDArray[np.bool_] = np.any(large, axis=1)[readable]
        if unreadable:
            positions, present = positions[readable], present[readable]
        if out_of_range.any():
            odom.skip(SKIP_POSITION_RANGE, int(np.count_nonzero(out_of_range)))
            keep = ~out_of_range
            positions, present, stamps = positions[keep], present[keep], stamps[keep]
        positions = conditioner.feed(stamps, positions, present)
        left, right, both = side_means(positions, present, len(params.left_joints))
        poses = odom.feed(stamps, left, right, both)
        if sink is not None:
            sink.write(poses)
        if progress is not None:
            progress(len(chunk.blobs))
    return odom, conditioner


def bag_odometry(
    path: str | os.PathLike[str],
    params: DiffDriveParams,
    topic: str | None = None,
    *,
    chunk_size: int = CHUNK_MESSAGES,
    sink: PoseSink | None = None,
    progress: Progress | None = None,
    conditioning: Conditioning | None = None,
) -> RecordingOdometry:
    """The odometry of the sensor_msgs/msg/JointState messages of one bag topic.

    Messages of a repeating layout are decoded in bulk (fixed byte offsets, NumPy over many
    messages at once), any other one by rosbags' deserializer.

    Raises:
        RecordingError: rosbags is missing (for storage it must read), the path is not a
            readable bag, the topic is absent or does not carry JointState messages, or no
            sample could be used.
    """
    with closing(TopicChunks(path, topic, chunk_size=chunk_size)) as chunks:
        if chunks.msgtype != JOINT_STATE:
            raise BagError(
                f"{chunks.source}: topic {chunks.topic!r} carries {chunks.msgtype}, "
                f"not {JOINT_STATE}"
            )
        clock = CLOCK_HEADER
        done = _bag_pass(chunks, params, clock, sink, progress, conditioning)
        if done is None:
            clock = CLOCK_RECEIVE
            if sink is not None:
                sink.restart()
            done = _bag_pass(chunks, params, clock, sink, progress, conditioning)
        assert done is not None  # the receive clock never asks for another pass
        odom, conditioner = done
        hint = ""
        if odom.skipped.get(SKIP_MISSING_JOINT) and not odom.used:
            hint = _joints_hint(chunks, params)
        summary = odom.summary(chunks.source, hint)
        return RecordingOdometry(
            chunks.source,
            "rosbag1" if chunks.ros1 else "rosbag2",
            summary,
            clock,
            conditioner.report(),
            chunks.topic,
            chunks.topic_chosen,
        )


def _joints_hint(chunks: TopicChunks, params: DiffDriveParams) -> str:
    """The wheel joints wanted and the joints the topic's first readable message holds."""
    from diffbot.io.bag import typestore

    wanted = listing([*params.left_joints, *params.right_joints])
    store = typestore()
    for chunk in chunks.chunks(receive_times=False):
        for blob in chunk.blobs:
            try:
                message: Any = store.deserialize_cdr(blob, JOINT_STATE)
                names = [str(name) for name in message.name]
            except Exception:  # a damaged message: the next one may say
                continue
            return f"; wheel joints wanted: {wanted}; joints found: {listing(names)}"
    return f"; wheel joints wanted: {wanted}"


def existing_recording(path: str | os.PathLike[str]) -> Path:
    """The path of a recording whose files are all regular files (a FIFO or a device would
    block or feed endless data), noted as an input of the run.

    A bag folder's storage files are the ones its ``metadata.yaml`` names, under any name and
    read from the folder itself, so every file in the folder is checked, not only ``.db3`` and
    ``.mcap`` ones.

    Raises:
        RecordingError: it is missing, or one of its files is not a regular file.
    """
    p = Path(path)
    if not p.exists():
        raise RecordingError(f"{p}: no such file or directory")
    note_input(p)
    parts = [p] if not p.is_dir() else sorted(p.iterdir())
    for part in parts:
        if part is p or not part.is_dir():
            check_regular(part, RecordingError, "a recording")
    return p


def recording_odometry(
    path: str | os.PathLike[str],
    params: DiffDriveParams,
    topic: str | None = None,
    *,
    sink: PoseSink | None = None,
    progress: Progress | None = None,
    conditioning: Conditioning | None = None,
    layout: CsvLayout | None = None,
) -> RecordingOdometry:
    """The odometry of a CSV file or a rosbag2 recording, by what the path is.

    Args:
        path: a CSV file, a rosbag2 directory, or one of its ``.db3`` or ``.mcap`` files.
        params: the robot, whose wheel joints are looked up by name.
        topic: the JointState topic of a bag.
        sink: where the poses go as they come, if anywhere.
        progress: called after each chunk with how much of the input it used (see
            :func:`recording_size`).
        conditioning: the positions' units and wrap (default: radians, wraps detected).
        layout: a CSV's columns, delimiter and time unit, where not the defaults.

    Raises:
        RecordingError: missing, empty or unreadable input; missing columns or topic; no
            usable sample.
    """
    p = existing_recording(path)
    if is_bag(p):
        return bag_odometry(
            p, params, topic, sink=sink, progress=progress, conditioning=conditioning
        )
    return csv_odometry(
        p, params, sink=sink, progress=progress, conditioning=conditioning, layout=layout
    )


def recording_size(path: str | os.PathLike[str], topic: str | None = None) -> int | None:
    """How much :func:`recording_odometry` will report to ``progress`` in all: a bag topic's
    message count from its metadata, a CSV file's size; None when not known cheaply."""
    try:
        p = existing_recording(path)
        if not is_bag(p):
            return p.stat().st_size
        if bag_suffix(p) == ".db3.zstd" or (p.is_dir() and not (p / "metadata.yaml").exists()):
            return None  # no metadata to count by: the progress shows no total
        with closing(TopicChunks(p, topic)) as chunks:
            return chunks.message_count
    except (OSError, RecordingError):
        return None


def read_recording(
    path: str | os.PathLike[str],
    params: DiffDriveParams,
    topic: str | None = None,
    *,
    conditioning: Conditioning | None = None,
    time_column: str | None = None,
    left_column: str | Sequence[str] | None = None,
    right_column: str | Sequence[str] | None = None,
    delimiter: str | None = None,
    time_unit: str | None = None,
) -> Recording:
    """Read wheel joint samples whole from a CSV file or a rosbag2 recording.

    Args:
        path: a CSV file, a rosbag2 directory, or one of its ``.db3`` or ``.mcap`` files.
        params: the robot, whose wheel joint names select the CSV columns.
        topic: the JointState topic of a bag.
        conditioning: the positions' units and wrap (default: radians, wraps detected); the
            samples hold the wheel angles, and ``conditioning`` of the result says what was
            done.
        time_column: a CSV's time column (default: ``time``, ``stamp``, ``t`` or ``__time``).
        left_column: a CSV's left wheel position column(s) (default: named by the joints).
        right_column: a CSV's right wheel position column(s).
        delimiter: a CSV's delimiter (default: a comma, or what splits the header).
        time_unit: a CSV's time unit, ``s``, ``ms``, ``us`` or ``ns`` (default: seconds, or as
            the first stamp's size says; the result's ``notes`` say so).

    Returns:
        The samples.

    Raises:
        RecordingError: missing, empty or unreadable input; missing columns or topic.
    """
    p = existing_recording(path)
    if is_bag(p):
        wheels = {params.left_joint, params.right_joint, *params.left_joints, *params.right_joints}
        recording = _within_range(read_bag(p, topic), wheels)
        return _conditioned(recording, params, conditioning)

    def conditioner(joints: Sequence[str], left_count: int) -> Conditioner:
        return Conditioner.for_robot(params, joints, left_count, conditioning)

    layout = csv_layout(time_column, left_column, right_column, delimiter, time_unit)
    return read_csv(
        p, params.left_joints, params.right_joints, conditioner=conditioner, layout=layout
    )


def csv_layout(
    time_column: str | None = None,
    left_column: str | Sequence[str] | None = None,
    right_column: str | Sequence[str] | None = None,
    delimiter: str | None = None,
    time_unit: str | None = None,
) -> CsvLayout:
    """A :class:`~diffbot.io.csv_chunks.CsvLayout` from the library's arguments (a column
    given as a string may list several, comma-separated)."""

    def names(value: str | Sequence[str] | None) -> tuple[str, ...] | None:
        if value is None:
            return None
        parts = value.split(",") if isinstance(value, str) else list(value)
        return tuple(part.strip() for part in parts if part.strip()) or None

    return CsvLayout(time_column, names(left_column), names(right_column), delimiter, time_unit)


def _conditioned(
    recording: Recording, params: DiffDriveParams, conditioning: Conditioning | None
) -> Recording:
    """A bag's samples with their wheel joints' positions conditioned (other joints as read)."""
    joints = [*params.left_joints, *params.right_joints]
    conditioner = Conditioner.for_robot(params, joints, len(params.left_joints), conditioning)
    samples = recording.samples
    n = len(samples)
    positions = np.zeros((n, len(joints)))
    present = np.zeros((n, len(joints)), dtype=np.bool_)
    stamps = np.empty(n, dtype=np.int64)
    column = {joint: j for j, joint in enumerate(joints)}
    for k, (stamp_ns, names, values) in enumerate(samples):
        stamps[k] = stamp_ns
        for name, value in zip(names, values, strict=False):
            j = column.get(name)
            if j is not None:
                positions[k, j] = value
                present[k, j] = True
    conditioned = conditioner.feed(stamps, positions, present)
    report = conditioner.report()
    if conditioned is positions:
        return dataclasses.replace(recording, conditioning=report)
    kept = []
    for k, sample in enumerate(samples):
        values = list(sample.positions)
        for i, name in enumerate(sample.names[: len(values)]):
            j = column.get(name)
            if j is not None:
                values[i] = float(conditioned[k, j])
        kept.append(JointSample(sample.stamp_ns, sample.names, values))
    return dataclasses.replace(recording, samples=kept, conditioning=report)


def _within_range(recording: Recording, wheels: set[str]) -> Recording:
    """The recording without the samples whose wheel positions are too large to compute with
    (counted as skipped, as a CSV reader counts them)."""
    kept = [
        sample
        for sample in recording.samples
        if not any(
            name in wheels and beyond_range(value)
            for name, value in zip(sample.names, sample.positions, strict=False)
        )
    ]
    dropped = len(recording.samples) - len(kept)
    if not dropped:
        return recording
    skipped = dict(recording.skipped)
    skipped[SKIP_POSITION_RANGE] = skipped.get(SKIP_POSITION_RANGE, 0) + dropped
    return dataclasses.replace(recording, samples=kept, skipped=skipped)
