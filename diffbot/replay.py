"""Odometry of recordings: the pipeline read (:mod:`diffbot.io`) -> condition
(:mod:`diffbot.conditioning`) -> integrate (:mod:`diffbot.chunk_odometry`) -> write (a sink),
driven from here.

:func:`recording_odometry` reads a CSV file or a bag topic chunk by chunk, in memory that does
not grow with the recording; the result is that of feeding its samples one by one to
:class:`diffbot.odometry.Odometry` (stamps in seconds since the first sample), bit for bit. A
side with several drive wheels moves by the motion of its joints present in a sample
(:mod:`diffbot.side_angles`); a sample is skipped only when a whole side is missing. A bag
topic is stamped by one clock: the header stamps when every readable message with a wheel of
each side has a non-zero one, otherwise the bag's receive times. A
zero header stamp is seen only while reading, so a topic that turns out to need the receive
times is read a second time: the sink is then told to start again (:meth:`PoseSink.restart`).
The options it is given go, held in one :class:`~diffbot.reading.Reading`, to the step for its
kind of input: :func:`bag_odometry`, :func:`csv_odometry` (a file or a text stream), or with
``open_loop`` :func:`~diffbot.open_loop.open_loop_odometry`.

:func:`run_odometry` feeds a recording read whole to an :class:`Odometry`, the poses kept as
compact columns.
"""

from __future__ import annotations

import dataclasses
import itertools
import os
from collections.abc import Mapping, Sequence
from contextlib import closing
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, TextIO

from diffbot.errors import RecordingError
from diffbot.formats.text import listing
from diffbot.kinematics import Pose
from diffbot.odometry import SKIP_MISSING_JOINT, Odometry
from diffbot.reading import PoseSink, Progress, ReadAgain, Reading
from diffbot.samples import (
    CLOCK_HEADER,
    CLOCK_RECEIVE,
    NS_PER_S,
    SKIP_UNREADABLE,
    ColumnSamples,
    OdometryRow,
    OdometryRows,
    Recording,
    beyond_ranges,
    each_side,
    range_reason,
)

if TYPE_CHECKING:
    from numpy.typing import NDArray

    from diffbot.chunk_odometry import ChunkOdometry, OdometrySummary
    from diffbot.conditioning import Conditioning, ConditioningReport
    from diffbot.io.bag_chunks import TopicChunks
    from diffbot.io.csv_chunks import CsvLayout
    from diffbot.kinematics import DiffDriveParams
    from diffbot.reading import WheelAngles

__all__ = [
    "OdometryRow",
    "OdometryRows",
    "OdometryRun",
    "PoseSink",
    "Progress",
    "RecordingOdometry",
    "bag_odometry",
    "csv_odometry",
    "recording_odometry",
    "run_odometry",
]


@dataclass(frozen=True)
class OdometryRun:
    """The odometry of a whole recording.

    Attributes:
        rows: one row per used sample (the baseline first), kept as compact columns and made
            into :class:`OdometryRow` records when read.
        samples: how many samples were used.
        skipped: how many were skipped, by reason (reading and odometry together).
        distance: path length travelled (m), the sum of |ds|.
        duration: time (s) from the first to the last used sample.
    """

    rows: Sequence[OdometryRow]
    samples: int
    skipped: Mapping[str, int]
    distance: float
    duration: float

    @property
    def final_pose(self) -> Pose:
        """The pose after the last used sample."""
        return self.rows[-1].pose


def run_odometry(recording: Recording, odom: Odometry) -> OdometryRun:
    """Feed every sample of a recording to an odometry integrator.

    The integrator sees stamps in seconds relative to the first sample, so the differences it
    divides by keep full precision even for stamps since 1970.

    Args:
        recording: the samples.
        odom: the integrator, at its start pose.

    Returns:
        The run.

    Raises:
        RecordingError: no sample could be used.
    """
    rows = OdometryRows()
    samples = recording.samples
    origin = samples[0].stamp_ns if samples else 0
    missing = 0
    if isinstance(samples, ColumnSamples):
        # The columns straight to update(): no JointSample per row.
        update = odom.update
        columns = (samples.stamps_ns, samples.left, samples.right, samples.present)
        for stamp_ns, left, right, present in zip(*columns, strict=True):
            if present != 3:
                missing += 1  # counted as the integrator would count it
            elif update(left, right, (stamp_ns - origin) / NS_PER_S):
                rows.add(stamp_ns, odom)
    else:
        update_joint_state = odom.update_joint_state
        for stamp_ns, names, positions in samples:
            if update_joint_state(names, positions, (stamp_ns - origin) / NS_PER_S):
                rows.add(stamp_ns, odom)
    skipped = dict(recording.skipped)
    for reason, count in odom.skipped.items():
        skipped[reason] = skipped.get(reason, 0) + count
    if missing:
        skipped[SKIP_MISSING_JOINT] = skipped.get(SKIP_MISSING_JOINT, 0) + missing
    if not rows:
        reasons = ", ".join(f"{reason}: {n}" for reason, n in sorted(skipped.items()))
        hint = ""
        if skipped.get(SKIP_MISSING_JOINT) and samples:
            lists: list[tuple[str, ...]] = []
            for sample in itertools.islice(samples, _HINT_MESSAGES):
                names = tuple(sample.names)
                if names not in lists:
                    lists.append(names)
                    if len(lists) > _HINT_LISTS:
                        break
            hint = _joints_text(odom.params, lists)
        raise RecordingError(
            f"{recording.source}: no usable sample"
            + (f" (skipped: {reasons})" if reasons else " (the recording holds no samples)")
            + hint
        )
    duration = (rows.stamps_ns[-1] - rows.stamps_ns[0]) / NS_PER_S
    return OdometryRun(rows, odom.samples, skipped, odom.distance, duration)


# --------------------------------------------------------------------------------------------
# Chunked odometry of a recording by path


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
    reading: Reading | None = None,
    *,
    source: str | None = None,
    chunk_bytes: int | None = None,
) -> RecordingOdometry:
    """The odometry of the wheel columns of a recording CSV, a file or a text stream: the step
    of :func:`recording_odometry` for a CSV, ``chunk_bytes`` characters at a time.

    The wheel columns are read as ``reading`` says (``/<joint>/velocity`` columns for
    velocities unless its ``layout`` names them) and made wheel angles
    (:class:`~diffbot.reading.WheelAngles`) before they are integrated.

    Args:
        path: a CSV file, or a text stream of one.
        params: the robot, whose wheel joints name the columns.
        reading: how to read, and where the poses and the progress go (default: as
            :class:`~diffbot.reading.Reading` says by itself).
        source: the input's name in messages (default: the path, or the stream's name).
        chunk_bytes: how many characters a chunk holds (default:
            :data:`~diffbot.io.csv_chunks.CHUNK_BYTES`).

    Raises:
        RecordingError: missing, empty or non-text input, no time column, no column for a side,
            malformed CSV, or no usable sample.
    """
    from diffbot.chunk_odometry import ChunkOdometry
    from diffbot.io.csv_chunks import CHUNK_BYTES, open_csv_chunks
    from diffbot.side_angles import SideAngles

    reading = reading or Reading()
    odom = ChunkOdometry(params)
    sides = (params.left_joints, params.right_joints)
    with open_csv_chunks(
        path,
        sides,
        chunk_bytes=CHUNK_BYTES if chunk_bytes is None else chunk_bytes,
        source=source,
        layout=reading.csv_layout(),
    ) as chunks:
        wheels = reading.wheel_angles(params, chunks.joints, chunks.left_count)
        wheel_sides = SideAngles(chunks.left_count, len(chunks.joints) - chunks.left_count)
        for chunk in chunks:
            for reason, count in chunk.skipped.items():
                odom.skip(reason, count)
            positions = wheels.feed(chunk.stamp_ns, chunk.positions, chunk.present)
            left, right, both = wheel_sides.chunk(positions, chunk.present)
            reading.deliver(odom.feed(chunk.stamp_ns, left, right, both), chunk.chars)
        summary = odom.summary(chunks.source)
        report = wheels.report()
        return RecordingOdometry(chunks.source, "csv", summary, None, report, notes=chunks.notes())


def _bag_pass(
    topic: TopicChunks, params: DiffDriveParams, clock: str, reading: Reading
) -> tuple[ChunkOdometry, WheelAngles] | None:
    """One pass over the topic; None when a zero header stamp asks for the receive clock."""
    import numpy as np

    from diffbot.chunk_odometry import ChunkOdometry
    from diffbot.io.jointstate_cdr import decode_positions
    from diffbot.side_angles import SideAngles

    odom = ChunkOdometry(params)
    joints = (*params.left_joints, *params.right_joints)
    wheels = reading.wheel_angles(params, joints, len(params.left_joints))
    sides = SideAngles(len(params.left_joints), len(params.right_joints))
    limit = reading.wheel_limit()
    for chunk in topic.chunks(receive_times=clock == CLOCK_RECEIVE):
        decoded = decode_positions(chunk.blobs, joints, reading.feedback)
        readable = decoded.readable
        header = decoded.stamp_ns[readable]
        # the clock is chosen by the messages the odometry can use: a wheel of each side
        sided = each_side(decoded.present, len(params.left_joints))[readable]
        if clock == CLOCK_HEADER and not np.all(header[sided]):
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
        large = beyond_ranges(positions, limit) & present
        out_of_range: NDArray[np.bool_] = np.any(large, axis=1)[readable]
        if unreadable:
            positions, present = positions[readable], present[readable]
        if out_of_range.any():
            odom.skip(range_reason(reading.feedback), int(np.count_nonzero(out_of_range)))
            keep = ~out_of_range
            positions, present, stamps = positions[keep], present[keep], stamps[keep]
        positions = wheels.feed(stamps, positions, present)
        left, right, both = sides.chunk(positions, present)
        reading.deliver(odom.feed(stamps, left, right, both), len(chunk.blobs))
    return odom, wheels


def bag_odometry(
    path: str | os.PathLike[str],
    params: DiffDriveParams,
    topic: str | None = None,
    reading: Reading | None = None,
    *,
    chunk_size: int | None = None,
) -> RecordingOdometry:
    """The odometry of the sensor_msgs/msg/JointState messages of one bag topic: the step of
    :func:`recording_odometry` for a bag, ``chunk_size`` messages at a time.

    Messages of a repeating layout are decoded in bulk (fixed byte offsets, NumPy over many
    messages at once), any other one by rosbags' deserializer; their ``reading.feedback``
    fields are made wheel angles (:class:`~diffbot.reading.WheelAngles`) before they are
    integrated.

    Args:
        path: a bag: a rosbag2 directory, one of its storage files, or a ROS 1 ``.bag``.
        params: the robot, whose wheel joints are looked up by name.
        topic: the JointState topic (default: ``/joint_states``, or else the bag's only
            JointState topic).
        reading: how to read, and where the poses and the progress go (default: as
            :class:`~diffbot.reading.Reading` says by itself; its ``layout`` is a CSV's).
        chunk_size: how many messages a chunk holds (default:
            :data:`~diffbot.io.bag_chunks.CHUNK_MESSAGES`).

    Raises:
        RecordingError: rosbags is missing (for storage it must read), the path is not a
            readable bag, the topic is absent or does not carry JointState messages, or no
            sample could be used.
    """
    from diffbot.io.bag import JOINT_STATE
    from diffbot.io.bag_chunks import CHUNK_MESSAGES, BagError, TopicChunks

    reading = reading or Reading()
    again = None if reading.progress is None else ReadAgain(reading.progress)
    reading = dataclasses.replace(reading, progress=again)
    size = CHUNK_MESSAGES if chunk_size is None else chunk_size
    with closing(TopicChunks(path, topic, chunk_size=size)) as chunks:
        if chunks.msgtype != JOINT_STATE:
            raise BagError(
                f"{chunks.source}: topic {chunks.topic!r} carries {chunks.msgtype}, "
                f"not {JOINT_STATE}"
            )
        clock = CLOCK_HEADER
        done = _bag_pass(chunks, params, clock, reading)
        if done is None:
            clock = CLOCK_RECEIVE
            reading.restart()
            if again is not None:
                again.again()
            done = _bag_pass(chunks, params, clock, reading)
        assert done is not None  # the receive clock never asks for another pass
        odom, wheels = done
        hint = ""
        if odom.skipped.get(SKIP_MISSING_JOINT) and not odom.used:
            hint = _joints_hint(chunks, params)
            if reading.feedback == "velocity":
                hint += (
                    "; the messages hold no velocity for a side's wheels (empty velocity "
                    "fields?): read the positions with {feedback} position"
                )
        summary = odom.summary(chunks.source, hint)
        return RecordingOdometry(
            chunks.source,
            "rosbag1" if chunks.ros1 else "rosbag2",
            summary,
            clock,
            wheels.report(),
            chunks.topic,
            chunks.topic_chosen,
            chunks.notes(),
        )


#: How many messages :func:`_joints_hint` looks through, and how many joint lists it names.
_HINT_MESSAGES = 1000
_HINT_LISTS = 4


def _joints_hint(chunks: TopicChunks, params: DiffDriveParams) -> str:
    """The wheel joints wanted and the joints the topic's first readable messages hold: one
    list, or a list per kind of message when they differ (a publisher per wheel)."""
    from diffbot.io.bag import JOINT_STATE, typestore

    store = typestore()
    lists: list[tuple[str, ...]] = []
    looked = 0
    for chunk in chunks.chunks(receive_times=False):
        for blob in chunk.blobs:
            try:
                message: Any = store.deserialize_cdr(blob, JOINT_STATE)
                names = tuple(str(name) for name in message.name)
            except Exception:  # a damaged message: the next one may say
                continue
            if names not in lists:
                lists.append(names)
            looked += 1
            if looked >= _HINT_MESSAGES or len(lists) > _HINT_LISTS:
                break
        else:
            continue
        break
    return _joints_text(params, lists)


def _joints_text(params: DiffDriveParams, lists: list[tuple[str, ...]]) -> str:
    """The wheel joints wanted and the joint lists found: one, or one per kind of message."""
    joints = [*params.left_joints, *params.right_joints]
    wanted = listing(joints)
    if not lists:
        return f"; wheel joints wanted: {wanted}"
    if not set(joints) & {name for names in lists for name in names}:
        other = (
            "; none is a wheel joint of this robot: another robot's recording? give its "
            "description ({robot})"
        )
    else:
        other = ""
    if len(lists) == 1:
        return f"; wheel joints wanted: {wanted}; joints found: {listing(lists[0])}{other}"
    found = " / ".join(listing(names) for names in lists[:_HINT_LISTS])
    more = " / ..." if len(lists) > _HINT_LISTS else ""
    return (
        f"; wheel joints wanted: {wanted}; joints found, by message: {found}{more} (each "
        f"message must hold a joint of each side){other}"
    )


def recording_odometry(
    path: str | os.PathLike[str],
    params: DiffDriveParams,
    topic: str | None = None,
    *,
    sink: PoseSink | None = None,
    progress: Progress | None = None,
    conditioning: Conditioning | None = None,
    layout: CsvLayout | None = None,
    feedback: str = "position",
    open_loop: bool = False,
) -> RecordingOdometry:
    """The odometry of a CSV file or a bag, by what the path is: of its wheel joints, or with
    ``open_loop`` of its commanded body velocities.

    A recording read for its positions whose wheel positions never move while its wheel
    velocities do (a robot that reports velocities only, as diff_drive_controller's
    ``position_feedback: false`` expects) is refused, the message naming ``feedback``: its
    odometry would say the robot stood still.

    Args:
        path: a CSV file, a rosbag2 directory, or one of its ``.db3`` or ``.mcap`` files.
        params: the robot, whose wheel joints are looked up by name.
        topic: the JointState topic of a bag; with ``open_loop``, its Twist or TwistStamped
            command topic.
        sink, progress, conditioning, layout, feedback: how the recording is read and where
            the poses and the progress go, as the attributes of the same names of
            :class:`~diffbot.reading.Reading` say; held in one, they go to the step that reads
            the path (:func:`bag_odometry`, :func:`csv_odometry`,
            :func:`~diffbot.open_loop.open_loop_odometry`).
        open_loop: integrate the commanded body velocities instead, as diff_drive_controller
            does with ``open_loop: true`` (see :mod:`diffbot.open_loop`); they take no
            ``conditioning`` and no ``feedback``.

    Raises:
        RecordingError: missing, empty or unreadable input; missing columns or topic; no
            usable sample; positions that never move beside velocities that do.
        ParameterError: an unknown ``feedback``; ``conditioning`` or ``feedback`` with
            ``open_loop``.
    """
    from diffbot.io.bag import is_bag
    from diffbot.io.recordings import existing_recording

    reading = Reading(
        sink=sink, progress=progress, conditioning=conditioning, layout=layout, feedback=feedback
    )
    if open_loop:
        from diffbot.open_loop import open_loop_odometry

        return open_loop_odometry(path, params, topic, reading)
    p = existing_recording(path)
    try:
        run = (
            bag_odometry(p, params, topic, reading)
            if is_bag(p)
            else csv_odometry(p, params, reading)
        )
    except RecordingError as err:
        if feedback == "position" and velocities_move(p, params, topic, layout):
            raise RecordingError(f"{err.template}; {_VELOCITY_HINT}", **err.fields) from None
        raise
    summary = run.summary
    still = summary.distance == 0.0 and summary.heading == 0.0 and summary.samples > 1
    if feedback == "position" and still and velocities_move(p, params, topic, layout):
        raise RecordingError(
            f"{run.source}: the wheel positions never change while the wheel velocities do "
            f"(the odometry would stand still); {_VELOCITY_HINT}"
        )
    return run


#: What to do about a recording whose wheels report velocities only.
_VELOCITY_HINT = (
    "the wheels report velocities only (a controller with position_feedback: false): read "
    "the velocities with {feedback} velocity"
)


def velocities_move(
    path: str | os.PathLike[str],
    params: DiffDriveParams,
    topic: str | None = None,
    layout: CsvLayout | None = None,
) -> bool:
    """Whether a recording holds a wheel velocity that is finite and not zero (a JointState
    topic's ``velocity`` fields, a CSV's ``/<joint>/velocity`` columns); False when it holds
    none or cannot be read for them."""
    import numpy as np

    from diffbot.errors import DiffbotError
    from diffbot.io.bag import JOINT_STATE, is_bag

    joints = (*params.left_joints, *params.right_joints)

    def moving(values: NDArray[np.float64], present: NDArray[np.bool_]) -> bool:
        with np.errstate(invalid="ignore"):
            return bool(np.any(present & np.isfinite(values) & (values != 0.0)))

    try:
        if is_bag(path):
            from diffbot.io.bag_chunks import TopicChunks
            from diffbot.io.jointstate_cdr import decode_positions

            with closing(TopicChunks(path, topic)) as chunks:
                if chunks.msgtype != JOINT_STATE:
                    return False
                for chunk in chunks.chunks(receive_times=False):
                    decoded = decode_positions(chunk.blobs, joints, "velocity")
                    if moving(decoded.positions, decoded.present):
                        return True
            return False
        from diffbot.io.csv_chunks import CsvLayout, open_csv_chunks

        # The velocity columns by the joints' names (named columns are the positions').
        wanted = dataclasses.replace(
            layout or CsvLayout(), field="velocity", left_columns=None, right_columns=None
        )
        sides = (params.left_joints, params.right_joints)
        with open_csv_chunks(path, sides, layout=wanted) as csv_chunks:
            return any(moving(chunk.positions, chunk.present) for chunk in csv_chunks)
    except DiffbotError:
        return False
