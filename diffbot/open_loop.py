"""Open-loop odometry: the pose the robot would reach by doing exactly what it was commanded.

ros2_controllers' diff_drive_controller with ``open_loop: true`` integrates the body velocity it
commands instead of the wheels' feedback (``try_update_open_loop(linear_command,
angular_command, period)`` in its ``diff_drive_controller.cpp``). Here the commands are those of a
recording: the ``geometry_msgs/msg/Twist`` or ``TwistStamped`` messages of a bag topic
(``/cmd_vel`` unless told), or a CSV of ``t,v,w`` columns (s, m/s, rad/s). Each command holds
from its stamp until the next command's, so the robot moves along an arc of linear velocity v and
angular velocity w for that time; the last command ends the recording (a plan's commands end
with a zero one). The arcs are integrated in closed form by the same exact integrator as wheel
odometry (:class:`~diffbot.chunk_odometry.ChunkOdometry`), fed the wheel angles that the
commands turn the robot's wheels through: held against the wheel odometry of the same run, the
difference is what the wheels did that was not commanded.

A command with a NaN or infinite value, or stamped no later than the command before it, is
skipped and counted; the command before it then holds on.
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from contextlib import closing
from typing import TYPE_CHECKING, Any, Final, NamedTuple

import numpy as np

from diffbot.errors import ParameterError, RecordingError
from diffbot.numbers import MAX_ANGULAR_SPEED, MAX_LINEAR_SPEED
from diffbot.odometry import SKIP_NOT_FINITE, SKIP_STAMP_NOT_AFTER
from diffbot.reading import Reading
from diffbot.samples import (
    CLOCK_HEADER,
    CLOCK_RECEIVE,
    NS_PER_S,
    SKIP_POSITION_RANGE,
    SKIP_UNREADABLE,
)

if TYPE_CHECKING:
    from numpy.typing import NDArray

    from diffbot.chunk_odometry import ChunkOdometry
    from diffbot.io.csv_chunks import CsvLayout
    from diffbot.kinematics import DiffDriveParams
    from diffbot.replay import RecordingOdometry

__all__ = [
    "COMMAND_TOPIC",
    "SKIP_COMMAND_RANGE",
    "TWIST",
    "TWIST_STAMPED",
    "Commands",
    "command_angles",
    "open_loop_odometry",
    "read_commands",
]

#: The command topic read when none is given.
COMMAND_TOPIC: Final = "/cmd_vel"
TWIST: Final = "geometry_msgs/msg/Twist"
TWIST_STAMPED: Final = "geometry_msgs/msg/TwistStamped"
#: The columns of an open-loop CSV besides its time column: linear (m/s), angular (rad/s).
_CSV_COLUMNS: Final = ("v", "w")
#: Why a command was skipped: faster than any robot drives, as the live nodes refuse it
#: (:data:`~diffbot.numbers.MAX_LINEAR_SPEED`, :data:`~diffbot.numbers.MAX_ANGULAR_SPEED`).
SKIP_COMMAND_RANGE: Final = "command out of range"


class Commands(NamedTuple):
    """Body velocity commands in recording order.

    Attributes:
        source: the input's name.
        kind: ``"csv"``, ``"rosbag2"`` or ``"rosbag1"``.
        stamp_ns: stamps (ns), int64, shape (n,).
        linear: linear velocities (m/s), float64, shape (n,).
        angular: angular velocities (rad/s), float64, shape (n,).
        skipped: rows or messages that are no command, by reason.
        clock: for a bag, the header stamps or the receive times; None for a CSV.
        topic: for a bag, the topic read.
        notes: what a CSV reader judged by itself, for people.
        guessed: whether the topic was not asked for but taken as the bag's only command topic.
    """

    source: str
    kind: str
    stamp_ns: NDArray[np.int64]
    linear: NDArray[np.float64]
    angular: NDArray[np.float64]
    skipped: dict[str, int]
    clock: str | None = None
    topic: str | None = None
    notes: tuple[str, ...] = ()
    guessed: bool = False


def command_angles(
    stamps_ns: NDArray[np.int64],
    linear: NDArray[np.float64],
    angular: NDArray[np.float64],
    params: DiffDriveParams,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The wheel joint angles (rad) at each stamp when each command holds until the next.

    Args:
        stamps_ns: increasing stamps (ns), shape (n,).
        linear: the commands' linear velocities (m/s).
        angular: their angular velocities (rad/s).
        params: the robot (radii, separation, direction signs).

    Returns:
        The left and right joint angles, 0 at the first stamp: fed to the exact integrator,
        they move the robot by each command's arc.
    """
    dt = np.diff(stamps_ns).astype(np.float64) / NS_PER_S
    half = 0.5 * params.wheel_separation
    left_radius, right_radius = params.radii
    v, w = linear[:-1], angular[:-1]
    left = np.zeros(stamps_ns.shape[0])
    right = np.zeros(stamps_ns.shape[0])
    np.cumsum((v - w * half) * dt / (params.left_sign * left_radius), out=left[1:])
    np.cumsum((v + w * half) * dt / (params.right_sign * right_radius), out=right[1:])
    return left, right


def open_loop_odometry(
    path: str | os.PathLike[str],
    params: DiffDriveParams,
    topic: str | None = None,
    reading: Reading | None = None,
) -> RecordingOdometry:
    """The odometry of the commanded body velocities of a recording: the step of
    :func:`~diffbot.replay.recording_odometry` with ``open_loop``.

    Args:
        path: a bag (its ``topic``: default ``/cmd_vel``, or else the bag's only Twist or
            TwistStamped topic) or a CSV of ``t,v,w`` columns (the layout's time column,
            delimiter and unit apply; its left and right columns, if named, are the linear and
            angular ones).
        params: the robot, whose wheels carry out the commands.
        topic: the command topic of a bag (Twist or TwistStamped).
        reading: the CSV's layout, and where the poses and the progress (once, the number of
            commands read) go; the commands take no ``conditioning`` and no ``feedback``.

    Raises:
        RecordingError: missing or unreadable input, a topic of another type, a column that
            is missing or not a number, no command.
        ParameterError: a ``reading`` with a ``conditioning`` or a velocity ``feedback``.
    """
    from diffbot.chunk_odometry import ChunkOdometry
    from diffbot.conditioning import Conditioner, Conditioning
    from diffbot.replay import RecordingOdometry

    reading = reading or Reading()
    if reading.conditioning is not None or reading.feedback != "position":
        raise ParameterError(
            "commands are integrated as they are: conditioning= and {feedback} apply to the "
            "wheel joints' values"
        )
    commands = read_commands(path, topic, reading.layout)
    odom = ChunkOdometry(params)
    stamps, linear, angular = _usable(commands, odom)
    left, right = command_angles(stamps, linear, angular, params)
    joints = (params.left_joint, params.right_joint)
    conditioner = Conditioner.for_robot(params, joints, 1, Conditioning(wrap=0))
    conditioner.feed(stamps, np.column_stack((left, right)))
    reading.deliver(odom.feed(stamps, left, right), stamps.size)
    summary = odom.summary(commands.source, " (no command)")
    return RecordingOdometry(
        commands.source,
        commands.kind,
        summary,
        commands.clock,
        conditioner.report(),
        commands.topic,
        commands.guessed,
        notes=commands.notes,
    )


def _usable(
    commands: Commands, odom: ChunkOdometry
) -> tuple[NDArray[np.int64], NDArray[np.float64], NDArray[np.float64]]:
    """The commands that are finite, within the speeds any robot drives at and later than every
    one before them; the rest counted."""
    for reason, count in commands.skipped.items():
        odom.skip(reason, count)
    stamps, linear, angular = commands.stamp_ns, commands.linear, commands.angular
    finite = np.isfinite(linear) & np.isfinite(angular)
    odom.skip(SKIP_NOT_FINITE, int(finite.size - np.count_nonzero(finite)))
    within = finite & (np.abs(linear) <= MAX_LINEAR_SPEED) & (np.abs(angular) <= MAX_ANGULAR_SPEED)
    odom.skip(SKIP_COMMAND_RANGE, int(np.count_nonzero(finite) - np.count_nonzero(within)))
    index = np.flatnonzero(within)
    t = stamps[index]
    used = np.ones(t.size, dtype=np.bool_)
    if t.size > 1:
        used[1:] = t[1:] > np.maximum.accumulate(t[:-1])
    odom.skip(SKIP_STAMP_NOT_AFTER, int(used.size - np.count_nonzero(used)))
    index = index[used]
    return stamps[index], linear[index], angular[index]


def read_commands(
    path: str | os.PathLike[str], topic: str | None = None, layout: CsvLayout | None = None
) -> Commands:
    """Read the body velocity commands of a bag topic or a ``t,v,w`` CSV whole.

    A bag's TwistStamped messages are stamped by their header stamps unless one is zero (then
    all by the receive times), Twist messages by the receive times.

    Raises:
        RecordingError: as :func:`open_loop_odometry`.
    """
    from diffbot.io.bag import is_bag
    from diffbot.io.recordings import existing_recording

    p = existing_recording(path)
    if is_bag(p):
        return _bag_commands(p, topic)
    return _csv_commands(p, layout)


def _command_topic(topics: dict[str, set[str]]) -> str:
    """Without a topic given: ``/cmd_vel``, else the bag's only Twist or TwistStamped topic."""
    from diffbot.formats.text import listing
    from diffbot.io.bag_chunks import BagError

    for name in (COMMAND_TOPIC, COMMAND_TOPIC.lstrip("/")):
        if name in topics:
            return name
    found = sorted(t for t, types in topics.items() if types & {TWIST, TWIST_STAMPED})
    if len(found) == 1:
        return found[0]
    what = f"several command topics: {listing(found)}" if found else "no Twist topic"
    raise BagError(
        f"no topic {COMMAND_TOPIC!r} and {what}; give the command topic ({{topic}}); topics "
        f"found: {listing(sorted(topics))}"
    )


def _bag_commands(path: os.PathLike[str], topic: str | None) -> Commands:
    from diffbot.io.bag import typestore
    from diffbot.io.bag_chunks import BagError, TopicChunks

    store = typestore()
    stamps: list[int] = []
    header: list[int] = []
    values: list[tuple[float, float]] = []
    unreadable = 0
    with closing(TopicChunks(path, topic, choose=_command_topic)) as chunks:
        kind = chunks.msgtype
        if kind not in (TWIST, TWIST_STAMPED):
            raise BagError(
                f"{chunks.source}: topic {chunks.topic!r} carries {kind}, not {TWIST} or "
                f"{TWIST_STAMPED} ({{topic}} names the command topic)"
            )
        for chunk in chunks.chunks(receive_times=True):
            assert chunk.receive_ns is not None  # asked for
            for receive_ns, blob in zip(chunk.receive_ns.tolist(), chunk.blobs, strict=True):
                try:
                    message: Any = store.deserialize_cdr(blob, kind)
                    twist = message.twist if kind == TWIST_STAMPED else message
                    value = (float(twist.linear.x), float(twist.angular.z))
                    stamp = message.header.stamp if kind == TWIST_STAMPED else None
                    stamp_ns = 0 if stamp is None else stamp.sec * NS_PER_S + stamp.nanosec
                except Exception:  # a damaged message is one skipped command
                    unreadable += 1
                    continue
                values.append(value)
                stamps.append(int(receive_ns))
                header.append(int(stamp_ns))
        source, chosen, ros1 = chunks.source, chunks.topic, chunks.ros1
        # Named in the summary only when it was not /cmd_vel by default.
        guessed = chunks.topic_chosen and chosen.lstrip("/") != COMMAND_TOPIC.lstrip("/")
    use_header = kind == TWIST_STAMPED and all(header)
    pairs = np.array(values, dtype=np.float64).reshape(-1, 2)
    return Commands(
        source,
        "rosbag1" if ros1 else "rosbag2",
        np.array(header if use_header else stamps, dtype=np.int64),
        pairs[:, 0].copy(),
        pairs[:, 1].copy(),
        {SKIP_UNREADABLE: unreadable} if unreadable else {},
        CLOCK_HEADER if use_header else CLOCK_RECEIVE,
        chosen,
        guessed=guessed,
    )


def _csv_commands(path: os.PathLike[str], layout: CsvLayout | None) -> Commands:
    from diffbot.io.csv_chunks import CsvLayout, open_csv_chunks

    layout = layout or CsvLayout()
    columns = (
        layout.left_columns or (_CSV_COLUMNS[0],),
        layout.right_columns or (_CSV_COLUMNS[1],),
    )
    if len(columns[0]) != 1 or len(columns[1]) != 1:
        raise RecordingError(
            "an open-loop CSV has one linear and one angular column ({left_column}, {right_column})"
        )
    wanted = CsvLayout(layout.time_column, None, None, layout.delimiter, layout.time_unit)
    try:
        with open_csv_chunks(path, columns, layout=wanted) as chunks:
            parts = list(_chunks(chunks))
            source, notes = chunks.source, chunks.notes()
    except RecordingError as err:
        raise RecordingError(
            f"{err.template}; an open-loop CSV holds a time column and the commanded velocities "
            f"in columns {_CSV_COLUMNS[0]} (m/s) and {_CSV_COLUMNS[1]} (rad/s)",
            **err.fields,
        ) from None
    skipped: dict[str, int] = {}
    for chunk_skipped in (part[2] for part in parts):
        for reason, count in chunk_skipped.items():
            skipped[reason] = skipped.get(reason, 0) + count
    if skipped.get(SKIP_UNREADABLE):
        raise RecordingError(
            f"{source}: {skipped[SKIP_UNREADABLE]} rows hold a cell that is not a number in the "
            f"columns {columns[0][0]!r}, {columns[1][0]!r} or the time column: commands are "
            "numbers (m/s, rad/s)"
        )
    stamps = np.concatenate([part[0] for part in parts]) if parts else np.empty(0, np.int64)
    values = np.concatenate([part[1] for part in parts]) if parts else np.empty((0, 2))
    return Commands(source, "csv", stamps, values[:, 0], values[:, 1], skipped, notes=notes)


def _chunks(chunks: Any) -> Iterator[tuple[NDArray[np.int64], NDArray[np.float64], Any]]:
    """Each chunk's stamps and (v, w) rows; a row with an empty cell is no command."""
    for chunk in chunks:
        whole = chunk.present.all(axis=1)
        missing = int(whole.size - np.count_nonzero(whole))
        skipped = dict(chunk.skipped)
        # the CSV reader's bound for wheel positions (1e12), far past the commands' own
        if SKIP_POSITION_RANGE in skipped:
            skipped[SKIP_COMMAND_RANGE] = skipped.pop(SKIP_POSITION_RANGE)
        if missing:
            skipped["missing value"] = skipped.get("missing value", 0) + missing
        yield chunk.stamp_ns[whole], chunk.positions[whole], skipped
