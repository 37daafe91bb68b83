"""Recordings of wheel joint states in, odometry out: CSV files and ROS 2 bags.

Input is a sequence of :class:`JointSample` (a sensor_msgs/JointState's stamp, names and
positions), read from

- a CSV file with a time column (``time``, ``stamp``, ``t`` or ``__time``, in seconds) and one
  position column per wheel, named by the joint or ending with ``/<joint>/position`` (as bag
  export tools name the fields of a JointState); other columns are ignored and an empty cell means
  the joint is missing from that row;
- a rosbag2 recording (a directory with sqlite3 or mcap storage, or one ``.db3`` or ``.mcap``
  storage file), through the ``rosbags`` library (``pip install 'diffbot-kinematics[bag]'``):
  the sensor_msgs/msg/JointState messages of one topic, all stamped by their header stamps, or
  all by the bag's receive times when any header stamp is zero.

Stamps are kept as integer nanoseconds, like ROS time, so outputs carry the inputs' stamps
unchanged. Outputs (a CSV of poses, a bag of nav_msgs/Odometry and tf2_msgs/TFMessage, a bag or CSV
of joint states) are written whole or not at all, and never over an existing file unless asked.
Inputs are only ever opened for reading.
"""

from __future__ import annotations

import array
import contextlib
import csv
import io
import os
import shutil
import tempfile
from collections.abc import Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from decimal import ROUND_HALF_EVEN, Decimal, InvalidOperation
from pathlib import Path
from typing import TYPE_CHECKING, Final, NamedTuple, TextIO, cast, overload

from diffbot.errors import DiffbotError, OutputExistsError, RecordingError
from diffbot.kinematics import DiffDriveParams, Pose, Twist, norm_angle
from diffbot.odometry import SKIP_MISSING_JOINT, SKIP_NOT_FINITE, Odometry, quaternion_from_yaw

if TYPE_CHECKING:
    from numpy.typing import ArrayLike
    from rosbags.rosbag2 import Writer
    from rosbags.typesys.store import Typestore
    from rosbags.typesys.stores.ros2_humble import sensor_msgs__msg__JointState as JointState

__all__ = [
    "BAG_INSTALL_HINT",
    "CLOCK_HEADER",
    "CLOCK_RECEIVE",
    "DEFAULT_TOPIC",
    "JOINT_STATE",
    "SKIP_MISSING_STAMP",
    "SKIP_STAMP_RANGE",
    "SKIP_UNREADABLE",
    "TIME_COLUMNS",
    "JointSample",
    "OdometryRow",
    "OdometryRun",
    "Recording",
    "format_joint_states_csv",
    "format_odometry_csv",
    "is_bag",
    "read_bag",
    "read_csv",
    "read_recording",
    "run_odometry",
    "seconds_text",
    "write_joint_states_bag",
    "write_odometry_bag",
]

#: Names a CSV time column may have (seconds), case-insensitive, in order of preference.
TIME_COLUMNS: Final = ("time", "stamp", "t", "__time")
#: The JointState topic read from bags unless another is asked for.
DEFAULT_TOPIC: Final = "/joint_states"
#: The message type read from bags.
JOINT_STATE: Final = "sensor_msgs/msg/JointState"
#: What to install for bag support.
BAG_INSTALL_HINT: Final = "pip install 'diffbot-kinematics[bag]'"
#: :attr:`Recording.clock` of a bag stamped by the messages' header stamps.
CLOCK_HEADER: Final = "header"
#: :attr:`Recording.clock` of a bag stamped by the times the bag received the messages.
CLOCK_RECEIVE: Final = "receive"
#: Why a CSV row was skipped: its time cell is empty.
SKIP_MISSING_STAMP: Final = "missing stamp"
#: Why a CSV row or bag message was skipped: a value (or the message) cannot be read.
SKIP_UNREADABLE: Final = "unreadable value"
#: Why a CSV row was skipped: its time is outside ROS time in int64 ns (about ±292 years).
SKIP_STAMP_RANGE: Final = "stamp out of range"

_NS_PER_S: Final = 1_000_000_000
_INT64: Final = 2**63
_BAG_SUFFIXES: Final = (".mcap", ".db3")
_MAX_LISTED: Final = 30
#: rosbag2 format version written: read by ROS 2 Iron and later.
_BAG_VERSION: Final = 8


class JointSample(NamedTuple):
    """One JointState: stamp (ns), joint names and positions (rad), parallel sequences."""

    stamp_ns: int
    names: Sequence[str]
    positions: Sequence[float]


@dataclass(frozen=True)
class Recording:
    """Joint samples read from a file, in file order.

    Attributes:
        source: the path read, for messages.
        kind: ``"csv"`` or ``"rosbag2"``.
        samples: the samples, stamps in ns.
        skipped: rows or messages that could not be turned into a sample, by reason.
        clock: for a bag, what stamps the samples: :data:`CLOCK_HEADER` (the header stamps) or
            :data:`CLOCK_RECEIVE` (the bag's receive times); None for a CSV file (its time
            column).
    """

    source: str
    kind: str
    samples: Sequence[JointSample]
    skipped: Mapping[str, int] = field(default_factory=dict)
    clock: str | None = None


def seconds_text(stamp_ns: int) -> str:
    """A stamp (ns) as exact decimal seconds without trailing zeros (1500000000 -> ``"1.5"``)."""
    sign = "-" if stamp_ns < 0 else ""
    whole, frac = divmod(abs(stamp_ns), _NS_PER_S)
    if frac == 0:
        return f"{sign}{whole}"
    return f"{sign}{whole}.{frac:09d}".rstrip("0")


def _ns_from_seconds(text: str) -> int | None:
    """Decimal seconds -> ns, exactly rounded (ties to even); None if NaN or infinite;
    ValueError if not a plain decimal number (Python's digit grouping, ``1_0``, included).

    Beyond 1e30 s (far outside ROS time) the result is ±10**39 rather than the exact value, so
    that ``1e100000000`` costs nothing.
    """
    if "_" in text:
        raise ValueError(text)
    try:
        seconds = Decimal(text.strip())
    except InvalidOperation:
        raise ValueError(text) from None
    if not seconds.is_finite():
        return None
    if seconds.adjusted() > 30:
        return -(10**39) if seconds.is_signed() else 10**39
    if seconds.adjusted() < -30:
        return 0
    sign, digits, exponent = seconds.as_tuple()
    assert isinstance(exponent, int)  # finite
    nanoseconds = Decimal((sign, digits, exponent + 9))  # exact: no context rounding
    return int(nanoseconds.to_integral_value(rounding=ROUND_HALF_EVEN))


def is_bag(path: str | os.PathLike[str]) -> bool:
    """Whether a path is read as a rosbag2 recording (a directory, ``.mcap`` or ``.db3``)."""
    p = Path(path)
    return p.is_dir() or p.suffix.lower() in _BAG_SUFFIXES


def read_recording(
    path: str | os.PathLike[str], params: DiffDriveParams, topic: str = DEFAULT_TOPIC
) -> Recording:
    """Read wheel joint samples from a CSV file or a rosbag2 recording.

    Args:
        path: a CSV file, a rosbag2 directory, or one of its ``.db3`` or ``.mcap`` files.
        params: the robot, whose wheel joint names select the CSV columns.
        topic: the JointState topic of a bag.

    Returns:
        The samples.

    Raises:
        RecordingError: missing, empty or unreadable input; missing columns or topic.
    """
    p = Path(path)
    if not p.exists():
        raise RecordingError(f"{p}: no such file or directory")
    if is_bag(p):
        return read_bag(p, topic)
    return read_csv(p, params.left_joint, params.right_joint)


def _listing(names: Iterable[str]) -> str:
    names = list(names)
    if not names:
        return "none"
    shown = ", ".join(repr(n) for n in names[:_MAX_LISTED])
    more = len(names) - _MAX_LISTED
    return f"{shown}, and {more} more" if more > 0 else shown


def _column(headers: Sequence[str], joint: str, side: str, source: str) -> int:
    suffix = f"/{joint}/position"
    found = [i for i, h in enumerate(headers) if h == joint or h.endswith(suffix)]
    if not found:
        raise RecordingError(
            f"{source}: no column for the {side} wheel joint {joint!r} (named {joint!r} or "
            f"ending with '{suffix}'); columns found: {_listing(headers)}"
        )
    if len(found) > 1:
        raise RecordingError(
            f"{source}: several columns for the {side} wheel joint {joint!r}: "
            f"{_listing(headers[i] for i in found)}"
        )
    return found[0]


class _CsvSamples(Sequence[JointSample]):
    """The samples of a CSV file as compact columns rather than one object per row.

    Stamps are int64 ns and wheel positions float64 (8 bytes each); a byte per row says which
    wheels the row has. :class:`JointSample` records are made only when asked for.
    """

    def __init__(self, left_joint: str, right_joint: str) -> None:
        self.stamps_ns = array.array("q")
        self.left = array.array("d")
        self.right = array.array("d")
        #: Per row: 1 if the left wheel's cell is set, 2 if the right's, 3 if both.
        self.present = bytearray()
        self._names: tuple[tuple[str, ...], ...] = (
            (),
            (left_joint,),
            (right_joint,),
            (left_joint, right_joint),
        )

    def __len__(self) -> int:
        return len(self.stamps_ns)

    @overload
    def __getitem__(self, index: int) -> JointSample: ...
    @overload
    def __getitem__(self, index: slice) -> list[JointSample]: ...
    def __getitem__(self, index: int | slice) -> JointSample | list[JointSample]:
        if isinstance(index, slice):
            return [self[i] for i in range(*index.indices(len(self)))]
        return self._sample(self.stamps_ns[index], self.left[index], self.right[index], index)

    def __iter__(self) -> Iterator[JointSample]:
        for k, (stamp_ns, left, right) in enumerate(
            zip(self.stamps_ns, self.left, self.right, strict=True)
        ):
            yield self._sample(stamp_ns, left, right, k)

    def _sample(self, stamp_ns: int, left: float, right: float, index: int) -> JointSample:
        present = self.present[index]
        values = (left, right) if present == 3 else (right,) if present == 2 else (left,)
        return JointSample(stamp_ns, self._names[present], values[: bin(present).count("1")])


def read_csv(
    path: str | os.PathLike[str] | TextIO,
    left_joint: str,
    right_joint: str,
    *,
    source: str | None = None,
) -> Recording:
    """Read wheel joint samples from a CSV file.

    Only the time column and the two wheel columns are kept, in compact arrays (about 25 bytes
    a row), so files of millions of rows fit in memory.

    Args:
        path: the file, or an open text stream (read from where it stands); the first row names
            the columns.
        left_joint: the left wheel joint's name.
        right_joint: the right wheel joint's name.
        source: the name of the input in messages (default: the path, or the stream's name).

    Returns:
        One sample per data row, holding the wheel joints whose cells are not empty. Rows whose
        time is empty, NaN or infinite, or outside the int64 nanosecond range of ROS time
        (about ±292 years from 1970), and rows with a cell that is not a number (including
        Python's digit grouping, ``1_0``) are counted in ``skipped``.

    Raises:
        RecordingError: missing, empty or non-text file, no time column, no (or several)
            columns for a wheel.
    """
    if isinstance(path, (str, os.PathLike)):
        p = Path(path)
        name = source if source is not None else str(p)
        try:
            with p.open(encoding="utf-8-sig", newline="") as stream:
                return _read_csv_stream(stream, left_joint, right_joint, name)
        except FileNotFoundError:
            raise RecordingError(f"{name}: no such file or directory") from None
        except IsADirectoryError:
            raise RecordingError(f"{name}: is a directory, not a CSV file") from None
        except OSError as err:
            raise RecordingError(f"{name}: cannot read: {err.strerror or err}") from None
    name = source if source is not None else str(getattr(path, "name", "<stream>"))
    return _read_csv_stream(path, left_joint, right_joint, name)


def _read_csv_stream(
    stream: Iterable[str], left_joint: str, right_joint: str, source: str
) -> Recording:
    samples = _CsvSamples(left_joint, right_joint)
    skipped: dict[str, int] = {}
    try:
        rows = csv.reader(stream)
        headers: list[str] | None = None
        for row in rows:
            if any(cell.strip() for cell in row):
                headers = [h.strip() for h in row]
                break
        if headers is None:
            raise RecordingError(f"{source}: empty file")
        lowered = [h.lower() for h in headers]
        time_index = next((lowered.index(n) for n in TIME_COLUMNS if n in lowered), None)
        if time_index is None:
            raise RecordingError(
                f"{source}: no time column ({', '.join(TIME_COLUMNS)}, in seconds); "
                f"columns found: {_listing(headers)}"
            )
        left_index = _column(headers, left_joint, "left", source)
        right_index = _column(headers, right_joint, "right", source)
        _read_rows(rows, (time_index, left_index, right_index), samples, skipped)
    except UnicodeDecodeError:
        raise RecordingError(f"{source}: not a text (UTF-8) CSV file") from None
    except csv.Error as err:
        raise RecordingError(f"{source}: malformed CSV: {err}") from None
    return Recording(source, "csv", samples, skipped)


def _read_rows(
    rows: Iterator[list[str]],
    indexes: tuple[int, int, int],
    samples: _CsvSamples,
    skipped: dict[str, int],
) -> None:
    """Parse the data rows into ``samples``, counting the rows that are skipped by reason."""
    time_index, left_index, right_index = indexes
    width = max(indexes) + 1
    add_stamp = samples.stamps_ns.append
    add_left = samples.left.append
    add_right = samples.right.append
    add_present = samples.present.append
    for row in rows:
        if len(row) >= width:
            stamp_text = row[time_index]
            left_text = row[left_index]
            right_text = row[right_index]
        else:  # a short row: the cells it lacks are empty
            if not any(cell.strip() for cell in row):
                continue  # a blank line is no sample
            stamp_text, left_text, right_text = (row[i] if i < len(row) else "" for i in indexes)
        stamp_ns = _stamp_ns(stamp_text)
        if stamp_ns is None or not -_INT64 <= stamp_ns < _INT64:
            if not any(cell.strip() for cell in row):
                continue  # a line of empty cells is no sample
            reason = _stamp_skip_reason(stamp_text)
            skipped[reason] = skipped.get(reason, 0) + 1
            continue
        present = 0
        left = right = 0.0
        try:
            if left_text and not left_text.isspace():
                left = _position(left_text)
                present = 1
            if right_text and not right_text.isspace():
                right = _position(right_text)
                present += 2
        except ValueError:
            skipped[SKIP_UNREADABLE] = skipped.get(SKIP_UNREADABLE, 0) + 1
            continue
        add_stamp(stamp_ns)
        add_left(left)
        add_right(right)
        add_present(present)


def _position(text: str) -> float:
    """A position cell as a float; ValueError if it is no plain number (``1_0`` is not)."""
    if "_" in text:
        raise ValueError(text)
    return float(text)


def _stamp_ns(text: str) -> int | None:
    """A time cell (decimal seconds) as ns; None if it is not usable."""
    whole, _, frac = text.strip().partition(".")
    # The usual forms ("12", "1700000000.123456789") without Decimal's cost per row.
    if (
        whole.isdigit()
        and whole.isascii()
        and len(whole) <= 12
        and len(frac) <= 9
        and (not frac or (frac.isdigit() and frac.isascii()))
    ):
        return int(whole) * _NS_PER_S + int(frac.ljust(9, "0"))
    try:
        return _ns_from_seconds(text)
    except ValueError:
        return None


def _stamp_skip_reason(text: str) -> str:
    """Why a time cell that :func:`_stamp_ns` could not use was skipped."""
    if not text.strip():
        return SKIP_MISSING_STAMP
    try:
        return SKIP_NOT_FINITE if _ns_from_seconds(text) is None else SKIP_STAMP_RANGE
    except ValueError:
        return SKIP_UNREADABLE


def _require_rosbags() -> None:
    """Raise a RecordingError saying what to install when rosbags is missing."""
    try:
        import rosbags.typesys  # noqa: F401
    except ImportError:
        raise RecordingError(
            f"reading and writing ROS 2 bags needs the rosbags library: {BAG_INSTALL_HINT}"
        ) from None


def _typestore() -> Typestore:
    from rosbags.typesys import Stores, get_typestore

    return get_typestore(Stores.ROS2_HUMBLE)


def read_bag(path: str | os.PathLike[str], topic: str = DEFAULT_TOPIC) -> Recording:
    """Read the sensor_msgs/msg/JointState messages of one topic from a rosbag2 recording.

    The recording is opened with rosbags' rosbag2 reader (never as ROS 1, whatever its name
    ends with) and the messages are decoded with the ROS 2 Humble type store.

    One clock stamps the whole topic: the header stamps when every message has a non-zero one,
    otherwise the bag's receive times for all of them (mixing the two would put samples decades
    apart). :attr:`Recording.clock` says which (:data:`CLOCK_HEADER` or :data:`CLOCK_RECEIVE`).

    Args:
        path: a rosbag2 directory (sqlite3 or mcap storage), or one of its ``.db3`` or ``.mcap``
            storage files.
        topic: the topic to read; other topics are ignored.

    Returns:
        One sample per message, stamps in ns. Messages that cannot be decoded are counted in
        ``skipped``.

    Raises:
        RecordingError: rosbags is missing, the path is not a readable bag, the topic is absent
            or does not carry JointState messages.
    """
    _require_rosbags()
    from rosbags.rosbag2 import Reader

    p = Path(path)
    source = str(p)
    if not p.exists():
        raise RecordingError(f"{source}: no such file or directory")
    if p.is_file() and p.stat().st_size == 0:
        raise RecordingError(f"{source}: empty file")
    typestore = _typestore()
    names_seen: list[Sequence[str]] = []
    positions_seen: list[list[float]] = []
    header_ns: list[int] = []
    receive_ns: list[int] = []
    skipped: dict[str, int] = {}
    try:
        with Reader(p) as reader:
            connections = [c for c in reader.connections if c.topic == topic]
            if not connections:
                topics = sorted({c.topic for c in reader.connections})
                raise RecordingError(
                    f"{source}: no topic {topic!r} in the bag; topics found: {_listing(topics)}"
                )
            types = sorted({c.msgtype for c in connections})
            if types != [JOINT_STATE]:
                raise RecordingError(
                    f"{source}: topic {topic!r} carries {', '.join(types)}, not {JOINT_STATE}"
                )
            last_names: list[str] = []
            for _, timestamp, raw in reader.messages(connections=connections):
                try:
                    msg = cast("JointState", typestore.deserialize_cdr(raw, JOINT_STATE))
                    stamp = msg.header.stamp
                    stamp_ns = int(stamp.sec) * _NS_PER_S + int(stamp.nanosec)
                    names = list(msg.name)
                    positions: list[float] = msg.position.tolist()
                except Exception:  # a corrupt message is one bad sample, not a bad bag
                    skipped[SKIP_UNREADABLE] = skipped.get(SKIP_UNREADABLE, 0) + 1
                    continue
                if names == last_names:
                    names = last_names  # one list for a run of equal names: less memory
                last_names = names
                names_seen.append(names)
                positions_seen.append(positions)
                header_ns.append(stamp_ns)
                receive_ns.append(int(timestamp))
    except DiffbotError:
        raise
    except Exception as err:
        # rosbags raises assorted errors (its own, sqlite3, struct, OSError) on files that are
        # not bags or are damaged; all of them mean the same thing to the user.
        detail = " ".join(str(err).split()) or type(err).__name__
        raise RecordingError(f"{source}: not a readable rosbag2 recording: {detail}") from None
    use_header = all(header_ns)
    stamps = header_ns if use_header else receive_ns
    samples = [
        JointSample(*sample) for sample in zip(stamps, names_seen, positions_seen, strict=True)
    ]
    clock = CLOCK_HEADER if use_header else CLOCK_RECEIVE
    return Recording(source, "rosbag2", samples, skipped, clock)


# --------------------------------------------------------------------------------------------
# Odometry over a recording


class OdometryRow(NamedTuple):
    """The odometry after one used sample: its stamp (ns), the pose and the twist."""

    stamp_ns: int
    pose: Pose
    twist: Twist


class _OdometryRows(Sequence[OdometryRow]):
    """Odometry rows as compact columns: stamps int64 ns, the rest float64 (48 bytes a row).

    ``theta`` holds the unwrapped heading; rows report it in (-pi, pi].
    """

    def __init__(self) -> None:
        self.stamps_ns = array.array("q")
        self.x = array.array("d")
        self.y = array.array("d")
        self.heading = array.array("d")
        self.linear = array.array("d")
        self.angular = array.array("d")

    def add(self, stamp_ns: int, odom: Odometry) -> None:
        """Append the integrator's state after a used sample."""
        # The state is read directly (one package): odom.pose and odom.twist would wrap the
        # heading and build two records per row only to be taken apart here.
        self.stamps_ns.append(stamp_ns)
        self.x.append(odom._x)
        self.y.append(odom._y)
        self.heading.append(odom._heading)
        self.linear.append(odom._linear)
        self.angular.append(odom._angular)

    def __len__(self) -> int:
        return len(self.stamps_ns)

    @overload
    def __getitem__(self, index: int) -> OdometryRow: ...
    @overload
    def __getitem__(self, index: slice) -> list[OdometryRow]: ...
    def __getitem__(self, index: int | slice) -> OdometryRow | list[OdometryRow]:
        if isinstance(index, slice):
            return [self[i] for i in range(*index.indices(len(self)))]
        return OdometryRow(
            self.stamps_ns[index],
            Pose(self.x[index], self.y[index], norm_angle(self.heading[index])),
            Twist(self.linear[index], self.angular[index]),
        )

    def __iter__(self) -> Iterator[OdometryRow]:
        columns = (self.stamps_ns, self.x, self.y, self.heading, self.linear, self.angular)
        for stamp_ns, x, y, heading, linear, angular in zip(*columns, strict=True):
            yield OdometryRow(stamp_ns, Pose(x, y, norm_angle(heading)), Twist(linear, angular))


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
    rows = _OdometryRows()
    samples = recording.samples
    origin = samples[0].stamp_ns if samples else 0
    missing = 0
    if isinstance(samples, _CsvSamples):
        # The columns straight to update(): no JointSample per row.
        update = odom.update
        columns = (samples.stamps_ns, samples.left, samples.right, samples.present)
        for stamp_ns, left, right, present in zip(*columns, strict=True):
            if present != 3:
                missing += 1  # counted as the integrator would count it
            elif update(left, right, (stamp_ns - origin) / _NS_PER_S):
                rows.add(stamp_ns, odom)
    else:
        update_joint_state = odom.update_joint_state
        for stamp_ns, names, positions in samples:
            if update_joint_state(names, positions, (stamp_ns - origin) / _NS_PER_S):
                rows.add(stamp_ns, odom)
    skipped = dict(recording.skipped)
    for reason, count in odom.skipped.items():
        skipped[reason] = skipped.get(reason, 0) + count
    if missing:
        skipped[SKIP_MISSING_JOINT] = skipped.get(SKIP_MISSING_JOINT, 0) + missing
    if not rows:
        reasons = ", ".join(f"{reason}: {n}" for reason, n in sorted(skipped.items()))
        raise RecordingError(
            f"{recording.source}: no usable sample"
            + (f" (skipped: {reasons})" if reasons else " (the recording holds no samples)")
        )
    duration = (rows.stamps_ns[-1] - rows.stamps_ns[0]) / _NS_PER_S
    return OdometryRun(rows, odom.samples, skipped, odom.distance, duration)


# --------------------------------------------------------------------------------------------
# Outputs


def format_odometry_csv(rows: Iterable[OdometryRow]) -> str:
    """Poses as CSV text: ``time,x,y,theta,linear,angular`` (s, m, m, rad in (-pi, pi], m/s,
    rad/s); floats printed so that they read back exactly."""
    out = io.StringIO()
    out.write("time,x,y,theta,linear,angular\n")
    write = out.write
    if isinstance(rows, _OdometryRows):  # from the columns: no records per row
        columns = (rows.stamps_ns, rows.x, rows.y, rows.heading, rows.linear, rows.angular)
        for stamp_ns, x, y, heading, linear, angular in zip(*columns, strict=True):
            theta = norm_angle(heading)
            write(f"{seconds_text(stamp_ns)},{x!r},{y!r},{theta!r},{linear!r},{angular!r}\n")
        return out.getvalue()
    for stamp_ns, (x, y, theta), (linear, angular) in rows:
        write(f"{seconds_text(stamp_ns)},{x!r},{y!r},{theta!r},{linear!r},{angular!r}\n")
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

    rows = np.asarray(positions, dtype=np.float64).reshape(len(names), len(stamps_ns)).T
    out = io.StringIO()
    out.write(",".join(["time", *names]) + "\n")
    for stamp_ns, values in zip(stamps_ns, rows.tolist(), strict=True):
        out.write(f"{seconds_text(stamp_ns)},{','.join(map(repr, values))}\n")
    return out.getvalue()


def _check_output(path: Path, force: bool) -> None:
    if (path.exists() or path.is_symlink()) and not force:
        raise OutputExistsError(f"{path} exists: use --force to overwrite it")
    if path.is_dir() and any(path.iterdir()) and not (path / "metadata.yaml").exists():
        # --force replaces files and earlier bags, never a directory of something else.
        raise OutputExistsError(f"{path} is a directory that is not a rosbag2 recording")
    parent = path.parent if str(path.parent) else Path(".")
    if not parent.is_dir():
        raise RecordingError(f"{path}: directory {parent} does not exist")


@contextlib.contextmanager
def _bag_writer(path: Path, force: bool) -> Iterator[Writer]:
    """A rosbags Writer on a temporary directory beside ``path``, renamed to it on success."""
    _check_output(path, force)
    _require_rosbags()
    from rosbags.rosbag2 import Writer

    parent = path.parent if str(path.parent) else Path(".")
    staging = Path(tempfile.mkdtemp(dir=parent, prefix=f".{path.name}.", suffix=".tmp"))
    try:
        # Written under the final name so the storage file inside is named after it.
        with Writer(staging / path.name, version=_BAG_VERSION) as writer:
            yield writer
        _replace(staging / path.name, path, force)
    finally:
        shutil.rmtree(staging, ignore_errors=True)


def _replace(new: Path, path: Path, force: bool) -> None:
    if not (path.exists() or path.is_symlink()):
        os.replace(new, path)
        return
    if not force:
        raise OutputExistsError(f"{path} exists: use --force to overwrite it")
    old = Path(tempfile.mkdtemp(dir=new.parent, prefix="old."))
    os.replace(path, old / path.name)
    try:
        os.replace(new, path)
    except BaseException:
        os.replace(old / path.name, path)
        raise


def _check_stamps(stamps_ns: Iterable[int], path: Path) -> None:
    for stamp_ns in stamps_ns:
        if not 0 <= stamp_ns < 2**31 * _NS_PER_S:
            raise RecordingError(
                f"{path}: cannot stamp a bag at {seconds_text(stamp_ns)} s: ROS time must be "
                f"between 0 and 2**31 s"
            )


def write_odometry_bag(
    path: str | os.PathLike[str],
    rows: Sequence[OdometryRow],
    odom: Odometry,
    *,
    force: bool = False,
    odom_topic: str = "/odom",
    tf_topic: str = "/tf",
) -> None:
    """Write poses as a rosbag2 of nav_msgs/msg/Odometry and tf2_msgs/msg/TFMessage.

    Args:
        path: the bag directory to create.
        rows: the poses and twists, stamped (ns) from the input.
        odom: the integrator that produced them: its frame ids and covariances are used.
        force: replace an existing file or bag at ``path``.
        odom_topic: the Odometry topic.
        tf_topic: the transform topic (odom -> base_link).

    Raises:
        OutputExistsError: ``path`` exists and ``force`` is false, or it is a directory that is
            not a bag.
        RecordingError: rosbags is missing, or a stamp is outside ROS time.
    """
    import numpy as np

    p = Path(path)
    _check_stamps((row.stamp_ns for row in rows), p)
    _require_rosbags()
    from rosbags.typesys.stores import ros2_humble as m

    typestore = _typestore()
    pose_cov = np.array(odom.pose_covariance, dtype=np.float64)
    twist_cov = np.array(odom.twist_covariance, dtype=np.float64)
    odom_type = m.nav_msgs__msg__Odometry.__msgtype__
    tf_type = m.tf2_msgs__msg__TFMessage.__msgtype__
    with _bag_writer(p, force) as writer:
        odom_conn = writer.add_connection(odom_topic, odom_type, typestore=typestore)
        tf_conn = writer.add_connection(tf_topic, tf_type, typestore=typestore)
        for stamp_ns, (x, y, theta), (linear, angular) in rows:
            sec, nanosec = divmod(stamp_ns, _NS_PER_S)
            header = m.std_msgs__msg__Header(
                stamp=m.builtin_interfaces__msg__Time(sec=sec, nanosec=nanosec),
                frame_id=odom.frame_id,
            )
            q = quaternion_from_yaw(theta)
            orientation = m.geometry_msgs__msg__Quaternion(x=q.x, y=q.y, z=q.z, w=q.w)
            message = m.nav_msgs__msg__Odometry(
                header=header,
                child_frame_id=odom.child_frame_id,
                pose=m.geometry_msgs__msg__PoseWithCovariance(
                    pose=m.geometry_msgs__msg__Pose(
                        position=m.geometry_msgs__msg__Point(x=x, y=y, z=0.0),
                        orientation=orientation,
                    ),
                    covariance=pose_cov,
                ),
                twist=m.geometry_msgs__msg__TwistWithCovariance(
                    twist=m.geometry_msgs__msg__Twist(
                        linear=m.geometry_msgs__msg__Vector3(x=float(linear), y=0.0, z=0.0),
                        angular=m.geometry_msgs__msg__Vector3(x=0.0, y=0.0, z=float(angular)),
                    ),
                    covariance=twist_cov,
                ),
            )
            transform = m.geometry_msgs__msg__TransformStamped(
                header=header,
                child_frame_id=odom.child_frame_id,
                transform=m.geometry_msgs__msg__Transform(
                    translation=m.geometry_msgs__msg__Vector3(x=x, y=y, z=0.0),
                    rotation=orientation,
                ),
            )
            tf_message = m.tf2_msgs__msg__TFMessage(transforms=[transform])
            writer.write(odom_conn, stamp_ns, typestore.serialize_cdr(message, odom_type))
            writer.write(tf_conn, stamp_ns, typestore.serialize_cdr(tf_message, tf_type))


def write_joint_states_bag(
    path: str | os.PathLike[str],
    stamps_ns: Sequence[int],
    names: Sequence[str],
    positions: ArrayLike,
    *,
    force: bool = False,
    topic: str = DEFAULT_TOPIC,
) -> None:
    """Write joint positions as a rosbag2 of sensor_msgs/msg/JointState.

    Args:
        path: the bag directory to create.
        stamps_ns: the stamps (ns), one per message.
        names: the joint names of every message.
        positions: joint angles (rad), shape (len(names), len(stamps_ns)): one row per joint.
        force: replace an existing file or bag at ``path``.
        topic: the topic.

    Raises:
        OutputExistsError: ``path`` exists and ``force`` is false, or it is a directory that is
            not a bag.
        RecordingError: rosbags is missing, or a stamp is outside ROS time.
    """
    import numpy as np

    p = Path(path)
    _check_stamps(stamps_ns, p)
    _require_rosbags()
    from rosbags.typesys.stores import ros2_humble as m

    typestore = _typestore()
    columns = np.array(positions, dtype=np.float64).reshape(len(names), len(stamps_ns))
    empty = np.empty(0, dtype=np.float64)
    with _bag_writer(p, force) as writer:
        conn = writer.add_connection(topic, JOINT_STATE, typestore=typestore)
        for k, stamp_ns in enumerate(stamps_ns):
            sec, nanosec = divmod(stamp_ns, _NS_PER_S)
            message = m.sensor_msgs__msg__JointState(
                header=m.std_msgs__msg__Header(
                    stamp=m.builtin_interfaces__msg__Time(sec=sec, nanosec=nanosec), frame_id=""
                ),
                name=list(names),
                position=np.ascontiguousarray(columns[:, k]),
                velocity=empty,
                effort=empty,
            )
            writer.write(conn, stamp_ns, typestore.serialize_cdr(message, JOINT_STATE))
