"""Decode many sensor_msgs/msg/JointState CDR messages at once, for the positions (or the
velocities) of a few joints.

A recorder publishes the same joint names in the same order, with the same frame id and the same
lengths of ``position``, ``velocity`` and ``effort``, message after message. Such messages share
one *layout*: the header stamp and each wanted joint's position sit at the same byte offsets in
all of them. The offsets are found once, by parsing the first message of a layout by hand; every
message of the same byte length whose layout bytes (encapsulation, frame id, names and sequence
lengths) equal that message's is then read with NumPy, as rows of one 2-D byte array.

Any other message (a layout seen too rarely, big-endian CDR, malformed bytes) is decoded on its
own by rosbags' deserializer (ROS 2 Humble type store), so the result is always what rosbags
would give. CDR offsets count from the payload, after the 4-byte encapsulation header; a float64
is aligned to 8 within the payload.
"""

from __future__ import annotations

import struct
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Final, NamedTuple

import numpy as np

from diffbot.errors import RecordingError
from diffbot.io.bag import BAG_INSTALL_HINT, JOINT_STATE
from diffbot.io.bag import typestore as bag_typestore
from diffbot.samples import NS_PER_S

if TYPE_CHECKING:
    from numpy.typing import NDArray
    from rosbags.typesys.store import Typestore

__all__ = [
    "CdrError",
    "DecodedPositions",
    "Layout",
    "decode_positions",
    "parse_layout",
]

#: Little-endian plain CDR: the encapsulation identifier (``CDR_LE``).
_CDR_LE: Final = b"\x00\x01"
#: Layouts tried per group of equal-length messages before the rest go to rosbags one by one: a
#: bag whose every message differs gains nothing from the fast path.
_MAX_LAYOUTS: Final = 8
_U32 = struct.Struct("<I")


class CdrError(RecordingError):
    """A JointState message that the fast path cannot parse (malformed or not little-endian)."""


@dataclass(frozen=True)
class Layout:
    """Where the fields of one JointState layout sit, as byte offsets from the message start.

    Attributes:
        size: the message length (bytes), encapsulation header included.
        key_end: end of the bytes that define the layout (frame id and names); bytes 0-1 and
            12 to ``key_end`` must match for a message to share the layout.
        count_offsets: offsets of the position, velocity and effort sequence lengths (uint32).
        counts: the position, velocity and effort sequence lengths.
        position_offset: offset of ``position[0]`` (float64).
        names: the joint names.
        frame_id: the header's frame id.
        velocity_offset: offset of ``velocity[0]`` (float64).
    """

    size: int
    key_end: int
    count_offsets: tuple[int, int, int]
    counts: tuple[int, int, int]
    position_offset: int
    names: tuple[str, ...]
    frame_id: str
    velocity_offset: int = 0

    def position_index(self, joint: str, field: int = 0) -> int | None:
        """The index of a joint's position (its first name), or None when it has none; with
        ``field`` 1, of its velocity."""
        try:
            index = self.names.index(joint)
        except ValueError:
            return None
        return index if index < self.counts[field] else None


class DecodedPositions(NamedTuple):
    """The wanted joints' positions of n messages, in the order given.

    Attributes:
        stamp_ns: header stamps (ns, ``sec * 10**9 + nanosec``), int64, shape (n,); 0 where the
            message is unreadable.
        positions: positions (rad), float64, shape (n, number of joints), bit for bit as in the
            message (NaN payloads and -0.0 kept); 0.0 where absent.
        present: whether the message names the joint and has a position for it, bool, shape
            (n, number of joints).
        readable: whether the message could be decoded at all, bool, shape (n,).
    """

    stamp_ns: NDArray[np.int64]
    positions: NDArray[np.float64]
    present: NDArray[np.bool_]
    readable: NDArray[np.bool_]


def _align(pos: int, to: int) -> int:
    return (pos + to - 1) & -to


def _string(blob: bytes, pos: int) -> tuple[str, int]:
    """A CDR string at payload offset ``pos`` (aligned) -> (text, payload offset after it)."""
    pos = _align(pos, 4)
    start = 4 + pos
    if start + 4 > len(blob):
        raise CdrError(f"string length at offset {pos} beyond the message end")
    (length,) = _U32.unpack_from(blob, start)
    end = start + 4 + length
    if length < 1 or end > len(blob) or blob[end - 1] != 0:
        raise CdrError(f"bad string of length {length} at offset {pos}")
    try:
        text = blob[start + 4 : end - 1].decode()
    except UnicodeDecodeError:
        raise CdrError(f"string at offset {pos} is not UTF-8") from None
    return text, pos + 4 + length


def _count(blob: bytes, pos: int, minimum: int) -> tuple[int, int]:
    """A sequence length at payload offset ``pos`` -> (length, payload offset after it)."""
    pos = _align(pos, 4)
    if 4 + pos + 4 > len(blob):
        raise CdrError(f"sequence length at offset {pos} beyond the message end")
    (count,) = _U32.unpack_from(blob, 4 + pos)
    if 4 + pos + 4 + count * minimum > len(blob):
        raise CdrError(f"sequence of {count} at offset {pos} beyond the message end")
    return count, pos + 4


def parse_layout(blob: bytes) -> Layout:
    """Parse one little-endian CDR JointState by hand into its :class:`Layout`.

    Accepts exactly what rosbags' deserializer accepts for little-endian messages: strings
    NUL-terminated UTF-8, sequences within the message, at most 3 bytes after the last field.

    Args:
        blob: the serialized message, encapsulation header included.

    Returns:
        The layout.

    Raises:
        CdrError: not little-endian CDR, or malformed.
    """
    if len(blob) < 12 or blob[:2] != _CDR_LE:
        raise CdrError("not a little-endian CDR message")
    frame_id, pos = _string(blob, 8)
    n_names, pos = _count(blob, pos, 5)
    names = []
    for _ in range(n_names):
        name, pos = _string(blob, pos)
        names.append(name)
    key_end = 4 + pos
    count_offsets = []
    counts = []
    offsets = [0, 0]
    for field in range(3):
        count, pos = _count(blob, pos, 8)
        count_offsets.append(pos)  # the count's absolute offset: payload offset + 4 - 4
        counts.append(count)
        if count:
            pos = _align(pos, 8)
        if field < 2:
            offsets[field] = 4 + pos
        pos += 8 * count
        if 4 + pos > len(blob):
            raise CdrError(f"float64 sequence of {count} beyond the message end")
    if 4 + pos + 3 < len(blob):
        raise CdrError(f"{len(blob) - 4 - pos} bytes after the message's last field")
    return Layout(
        size=len(blob),
        key_end=key_end,
        count_offsets=(count_offsets[0], count_offsets[1], count_offsets[2]),
        counts=(counts[0], counts[1], counts[2]),
        position_offset=offsets[0],
        names=tuple(names),
        frame_id=frame_id,
        velocity_offset=offsets[1],
    )


def _field(rows: NDArray[np.uint8], offset: int, dtype: str) -> NDArray[Any]:
    """One fixed-offset field of every row (a message), as a 1-D view of ``dtype``: a
    structured look at the rows' bytes, no copy."""
    width = np.dtype(dtype).itemsize
    field: NDArray[Any] = rows[:, offset : offset + width].view(dtype)[:, 0]
    return field


def _matches(rows: NDArray[np.uint8], layout: Layout) -> NDArray[np.bool_]:
    """Which rows (messages of the layout's size) share the layout bytes of row 0.

    Compared over all rows at once, in a fixed number of NumPy calls whatever the layout's
    length: the encapsulation word (its options too), the frame id and names as one block of
    8-byte words (and a last 4-byte word), and the three sequence lengths. Comparing the
    options and the padding after the last name as well only sends more messages to the exact
    path.
    """
    key_end = (layout.key_end + 3) & -4
    words_end = 12 + (key_end - 12) // 8 * 8
    fields = [(0, "<u4")]
    if words_end < key_end:
        fields.append((key_end - 4, "<u4"))
    fields += [(offset, "<u4") for offset in layout.count_offsets]
    same = np.ones(rows.shape[0], dtype=np.bool_)
    for offset, dtype in fields:
        column = _field(rows, offset, dtype)
        same &= column == column[0]
    # The names as one block: a call per word took about a second per megabyte of frame id.
    words = rows[:, 12:words_end].view("<u8")
    same &= (words == words[0]).all(axis=1)
    return same


class _Decoder:
    """Fills a :class:`DecodedPositions` message by message or row block by row block."""

    def __init__(self, n: int, joints: Sequence[str], field: int) -> None:
        self.joints = tuple(joints)
        self.field = field
        self.stamp_ns = np.zeros(n, dtype=np.int64)
        self.positions = np.zeros((n, len(self.joints)), dtype=np.float64)
        self.present = np.zeros((n, len(self.joints)), dtype=np.bool_)
        self.readable = np.zeros(n, dtype=np.bool_)

    def rows(
        self, index: NDArray[np.intp] | slice, rows: NDArray[np.uint8], layout: Layout
    ) -> None:
        sec = _field(rows, 4, "<i4").astype(np.int64)
        nanosec = _field(rows, 8, "<u4").astype(np.int64)
        sec *= NS_PER_S
        sec += nanosec
        self.stamp_ns[index] = sec
        self.readable[index] = True
        start = layout.velocity_offset if self.field else layout.position_offset
        for j, joint in enumerate(self.joints):
            k = layout.position_index(joint, self.field)
            if k is not None:
                self.positions[index, j] = _field(rows, start + 8 * k, "<f8")
                self.present[index, j] = True

    def one(self, i: int, blob: bytes, typestore: Typestore) -> None:
        try:
            msg = typestore.deserialize_cdr(blob, JOINT_STATE)
            stamp = msg.header.stamp  # type: ignore[attr-defined]
            stamp_ns = int(stamp.sec) * NS_PER_S + int(stamp.nanosec)
            names = list(msg.name)  # type: ignore[attr-defined]
            field = msg.velocity if self.field else msg.position  # type: ignore[attr-defined]
            values = np.asarray(field, dtype=np.float64)
        except Exception:  # a corrupt message is one unreadable sample, as read_bag counts it
            return
        self.stamp_ns[i] = stamp_ns
        self.readable[i] = True
        for j, joint in enumerate(self.joints):
            try:
                k = names.index(joint)
                value = values[k]
            except (ValueError, IndexError):
                continue
            self.positions[i, j] = value
            self.present[i, j] = True

    def result(self) -> DecodedPositions:
        return DecodedPositions(self.stamp_ns, self.positions, self.present, self.readable)


def decode_positions(
    blobs: Sequence[bytes], joints: Sequence[str], field: str = "position"
) -> DecodedPositions:
    """Decode the header stamps and some joints' positions from JointState CDR messages.

    Equal, value for value and bit for bit, to deserializing each message with rosbags (ROS 2
    Humble type store) and looking each joint up by name (its first occurrence) in ``name`` and
    then in ``position`` (or ``velocity``).

    Args:
        blobs: serialized sensor_msgs/msg/JointState messages (CDR, encapsulation included).
        joints: the joint names wanted.
        field: ``"position"`` or ``"velocity"``: the field whose values are returned (as
            ``positions``, in rad or rad/s).

    Returns:
        Stamps (ns), positions (rad), which joints each message has and which messages could be
        decoded; see :class:`DecodedPositions`.

    Raises:
        RecordingError: a message is not little-endian and rosbags is not installed.
    """
    if field not in ("position", "velocity"):
        raise RecordingError(f"field must be 'position' or 'velocity', got {field!r}")
    n = len(blobs)
    out = _Decoder(n, joints, field == "velocity")
    if n == 0:
        return out.result()
    lengths = np.fromiter(map(len, blobs), dtype=np.int64, count=n)
    leftover: list[int] = []
    # One size (the common case) needs no grouping: np.unique would also import numpy.ma.
    sizes = [int(lengths[0])] if lengths.min() == lengths.max() else sorted(set(lengths.tolist()))
    for size in sizes:
        whole = len(sizes) == 1
        index = np.arange(n) if whole else np.flatnonzero(lengths == size)
        group = blobs if whole else [blobs[i] for i in index.tolist()]
        rows = np.frombuffer(b"".join(group), dtype=np.uint8).reshape(len(index), size)
        for _ in range(_MAX_LAYOUTS):
            try:
                layout = parse_layout(bytes(blobs[int(index[0])]))
            except CdrError:
                leftover.append(int(index[0]))
                index, rows = index[1:], rows[1:]
            else:
                same = _matches(rows, layout)
                if same.all():  # the common case: no copy of the rows
                    out.rows(slice(None) if len(index) == n else index, rows, layout)
                    break
                out.rows(index[same], rows[same], layout)
                index, rows = index[~same], rows[~same]
            if len(index) == 0:
                break
        else:
            leftover.extend(index.tolist())
    if leftover:
        try:
            typestore = bag_typestore()
        except ImportError:
            raise RecordingError(
                f"decoding these JointState messages needs the rosbags library: {BAG_INSTALL_HINT}"
            ) from None
        for i in sorted(leftover):
            out.one(i, bytes(blobs[i]), typestore)
    return out.result()
