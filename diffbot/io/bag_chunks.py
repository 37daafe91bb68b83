"""Stream one topic of a bag in chunks of raw CDR messages, in constant memory.

Uncompressed sqlite3 storage (a bag directory whose ``metadata.yaml`` names it, a directory of
``.db3`` files without one, taken in the order of the numbers in their names, or one ``.db3``
file) is read with :mod:`sqlite3` itself: the topic's type from the metadata or the files'
``topics`` tables, then its messages a few dozen rows per call, in the order rosbags reads
them (by receive time; ties by insertion order, as the bag's timestamp index yields them). A lone
``.db3.zstd`` file (or such files in a directory without metadata) is first decompressed to a
temporary file, removed on :meth:`TopicChunks.close`. Anything else (mcap, compressed bags,
metadata this module does not follow) is opened and read by rosbags' rosbag2 reader, and a
ROS 1 ``.bag`` by its rosbag1 reader, its messages converted to CDR.

Whatever the storage, a chunk holds at most ``chunk_size`` messages and :data:`CHUNK_BYTES`
bytes of them, and a message larger than :data:`MAX_MESSAGE_BYTES` is refused: a few
kilobytes of compressed bag can hold thousands of messages of many megabytes each.

Without a topic, ``/joint_states`` is read, or else the bag's only JointState topic.
"""

from __future__ import annotations

import contextlib
import os
import re
import sqlite3
import tempfile
from collections.abc import Callable, Iterator
from operator import itemgetter
from pathlib import Path, PurePath
from typing import TYPE_CHECKING, Any, Final, NamedTuple

import numpy as np

from diffbot.errors import DiffbotError, RecordingError
from diffbot.formats.text import listing
from diffbot.io.bag import BAG_INSTALL_HINT, DEFAULT_TOPIC, JOINT_STATE, bag_suffix
from diffbot.io.bag_inflate import InflationBudget, bound_rosbags, copy_inflated, ros1_reader
from diffbot.io.pathnames import resolved
from diffbot.io.textfile import check_regular, read_text

if TYPE_CHECKING:
    from numpy.typing import NDArray
    from rosbags.interfaces import Connection
    from rosbags.rosbag1 import Reader as Reader1
    from rosbags.rosbag2 import Reader

__all__ = [
    "CHUNK_BYTES",
    "CHUNK_MESSAGES",
    "MAX_MESSAGE_BYTES",
    "BagChunk",
    "BagError",
    "TopicChunks",
]

#: Messages per chunk unless asked otherwise: about 3 MB of JointState messages of four joints.
#: Larger chunks are no faster and leave more memory behind (measured: 58 MB peak at 16384,
#: 100-110 MB at 65536 for 1e6-3e6 messages).
CHUNK_MESSAGES: Final = 16384
#: Most bytes of messages a chunk holds, whatever their count: a chunk ends before the message
#: that would take it past this. A few kilobytes of compressed bag inflate to messages of many
#: megabytes each, and 16384 of them were held at once.
CHUNK_BYTES: Final = 64 << 20
#: Largest message read (bytes), as stored and as CDR: the topics read (joint states, poses,
#: velocity commands) hold a few hundred bytes, a JointState of a hundred joints a few
#: kilobytes.
MAX_MESSAGE_BYTES: Final = 1 << 20


class BagError(RecordingError):
    """A rosbag2 recording cannot be read, or lacks the topic asked for."""


def _size_on_disk(path: Path) -> int:
    """The bytes a bag takes on disk: its file, or the files of its folder."""
    if path.is_file():
        return path.stat().st_size
    return sum(f.stat().st_size for f in path.iterdir() if f.is_file())


def _check_connection(source: str, topic: object, msgtype: object, count: object) -> None:
    """Refuse a connection whose metadata (``metadata.yaml``, a bag's own records) has a field
    of the wrong kind: a topic or type that is not a name, a count that is not a whole number."""
    for what, value in (("topic name", topic), ("message type", msgtype)):
        if not isinstance(value, str):
            raise BagError(f"{source}: malformed bag metadata: a {what} of {value!r}")
    if isinstance(count, bool) or not isinstance(count, int) or count < 0:
        raise BagError(f"{source}: malformed bag metadata: a message count of {count!r}")


class BagChunk(NamedTuple):
    """Consecutive messages of one topic.

    Attributes:
        receive_ns: the times (ns) the bag received them, int64, shape (n,); None when not
            asked for.
        blobs: the serialized messages, n of them.
    """

    receive_ns: NDArray[np.int64] | None
    blobs: list[bytes]


def _unreadable(source: str, err: Exception, ros1: bool) -> BagError:
    detail = " ".join(str(err).split()) or type(err).__name__
    kind = "ROS 1 bag" if ros1 else "rosbag2 recording"
    return BagError(f"{source}: not a readable {kind}: {detail}")


def _open_uri(path: Path) -> sqlite3.Connection:
    return sqlite3.connect(resolved(path, BagError).as_uri() + "?mode=ro&immutable=1", uri=True)


class _SqlitePlan(NamedTuple):
    """What to read from uncompressed sqlite3 storage: the files and the topics found."""

    files: list[Path]
    topics: dict[str, set[str]]
    counts: dict[str, int]


def _split_order(path: Path) -> tuple[list[str | int], str]:
    """A sort key putting numbered names in the order of their numbers: ``ros2 bag record
    --max-bag-size`` names its files ``NAME_0.db3``, ``NAME_1.db3``, ... ``NAME_10.db3``, which
    plain name order would read as 0, 1, 10, 2."""
    # re.split with a group alternates text and digits, so like compares with like; a file
    # name is at most 255 bytes, so int() never meets a number too long to convert.
    parts = re.split(r"(\d+)", path.name)
    key: list[str | int] = [int(part) if k % 2 else part for k, part in enumerate(parts)]
    return key, path.name


def _storage_files(folder: Path, suffix: str) -> list[Path]:
    """The files of a folder whose names end with ``suffix``, in the order of the numbers in
    their names (split recordings), each checked to be a regular file."""
    found = sorted(
        (p for p in folder.iterdir() if p.name.lower().endswith(suffix)), key=_split_order
    )
    for p in found:
        check_regular(p, BagError, "a bag's storage file")
    return found


def _decompressed(files: list[Path], into: Path) -> list[Path]:
    """``.db3.zstd`` files decompressed into a folder (others as they are)."""
    out = []
    for k, path in enumerate(files):
        if not path.name.lower().endswith(".zstd"):
            out.append(path)
            continue
        target = into / f"{k}_{path.name[: -len('.zstd')]}"
        copy_inflated(path, target)
        out.append(target)
    return out


def _sqlite_plan(path: Path, scratch: Path | None = None) -> _SqlitePlan | None:
    """The storage files and topics of an uncompressed sqlite3 bag; None for any other bag.

    Args:
        path: the bag (a directory or a storage file).
        scratch: where compressed ``.db3.zstd`` files are decompressed (None: not read here).

    Raises:
        BagError: ``metadata.yaml`` is malformed YAML, or refused (aliases, deep nesting).
        Exception: from sqlite3 or the metadata's fields on damaged files (the caller then lets
            rosbags judge).
    """
    topics: dict[str, set[str]] = {}
    counts: dict[str, int] = {}
    if path.is_file():
        suffix = bag_suffix(path)
        if suffix == ".db3.zstd" and scratch is not None:
            files = _decompressed([path], scratch)
        elif suffix != ".db3":
            return None
        else:
            files = [path]
    elif not (path / "metadata.yaml").exists():
        # A bag folder that lost its metadata: its storage files' own topic tables suffice.
        files = _storage_files(path, ".db3")
        packed = _storage_files(path, ".db3.zstd")
        if packed and scratch is not None:
            files = _decompressed(sorted(files + packed, key=_split_order), scratch)
        if not files:
            return None
    else:
        from diffbot.io.yamlfile import load_yaml

        metadata = path / "metadata.yaml"
        text = read_text(metadata, BagError, "bag metadata")
        info: Any = load_yaml(text, str(metadata), BagError, "bag metadata")
        info = info["rosbag2_bagfile_information"]
        mode = str(info.get("compression_mode") or "").lower()
        if (
            info["storage_identifier"] != "sqlite3"
            or info["version"] > 9
            or mode not in ("", "none")
        ):
            return None
        # Each file once, in the order given: a list naming one file 100,000 times was read
        # 100,000 times over.
        names = dict.fromkeys(PurePath(name).name for name in info["relative_file_paths"])
        files = [path / name for name in names]
        if not all(f.is_file() for f in files):
            return None
        for entry in info["topics_with_message_count"]:
            meta = entry["topic_metadata"]
            count = entry["message_count"]
            _check_connection(str(path), meta["name"], meta["type"], count)
            topics.setdefault(meta["name"], set()).add(meta["type"])
            counts[meta["name"]] = counts.get(meta["name"], 0) + count
    for file in files:
        connection = _open_uri(file)
        try:
            for name, msgtype in connection.execute("SELECT name, type FROM topics"):
                _check_connection(str(path), name, msgtype, 0)
                topics.setdefault(name, set()).add(msgtype)
            if not counts:  # no metadata: nothing said the messages are plain CDR
                _check_not_compressed(connection, path)
        finally:
            connection.close()
    return _SqlitePlan(files, topics, counts)


#: The first bytes of a zstd frame (a CDR message starts with its encapsulation, 0 0 or 0 1).
_ZSTD_MAGIC: Final = b"\x28\xb5\x2f\xfd"


def _check_not_compressed(connection: sqlite3.Connection, path: Path) -> None:
    """Refuse storage whose messages are zstd frames (compression mode ``message``, which only
    ``metadata.yaml`` records): read as CDR, every message would be skipped as unreadable."""
    row = connection.execute("SELECT substr(data, 1, 4) FROM messages LIMIT 1").fetchone()
    if row is not None and isinstance(row[0], bytes) and row[0] == _ZSTD_MAGIC:
        raise BagError(
            f"{path}: its messages are compressed one by one (zstd), which only the bag's "
            "metadata.yaml says: read the bag's folder with its metadata.yaml"
        )


_STAMP = itemgetter(0)
_DATA = itemgetter(1)


def _as_message(data: object) -> bytes:
    """A stored message as bytes. A damaged or hostile sqlite3 bag may hold TEXT, numbers or
    NULL where a message's bytes go: those become empty messages, which decode as unreadable
    and are skipped."""
    if isinstance(data, bytes):
        return data
    if isinstance(data, (memoryview, bytearray)):
        return bytes(data)
    return b""


class TopicChunks:
    """The messages of one topic of a rosbag2 recording, chunk by chunk.

    Opened on construction (so a missing topic fails at once) and closed by :meth:`close` (use
    :func:`contextlib.closing`). Iterating reads the topic from its start, each time.

    Args:
        path: a rosbag2 directory (sqlite3 or mcap storage), or one ``.db3`` or ``.mcap`` file.
        topic: the topic to read.
        chunk_size: messages per chunk (fewer in the last, and in a chunk that reaches
            :data:`CHUNK_BYTES`).
        choose: without a topic, picks the topic from the bag's topics and their types (and
            raises a :class:`~diffbot.errors.DiffbotError` when none fits); by default
            ``/joint_states`` or else the only JointState topic.

    Attributes:
        msgtype: the topic's message type, from the bag's topic table or metadata.
        message_count: how many messages the bag's metadata says the topic holds; None for a
            lone ``.db3`` file (counting would read the whole file).

    Raises:
        BagError: rosbags is missing, the path is not a readable bag, or it lacks the topic,
            or the topic carries several message types.
    """

    def __init__(
        self,
        path: str | os.PathLike[str],
        topic: str | None = None,
        *,
        chunk_size: int = CHUNK_MESSAGES,
        choose: Callable[[dict[str, set[str]]], str] | None = None,
    ) -> None:
        if chunk_size < 1:
            raise BagError(f"chunk_size must be at least 1, got {chunk_size}")
        p = Path(path)
        self.source = str(p)
        self._path = p
        self.topic = DEFAULT_TOPIC if topic is None else topic
        #: Whether the topic was chosen here, as the bag's only JointState topic.
        self.topic_chosen = False
        self._wanted = topic
        self._choose = choose
        #: The bag's topics and the message types each carries.
        self.topics: dict[str, set[str]] = {}
        self.chunk_size = chunk_size
        if not p.exists():
            raise BagError(f"{self.source}: no such file or directory")
        if p.is_file() and p.stat().st_size == 0:
            raise BagError(f"{self.source}: empty file")
        self._reader: Reader | Reader1 | None = None
        self._ros1 = False
        self._scratch: tempfile.TemporaryDirectory[str] | None = None
        self._sqlite: _SqlitePlan | None = None
        if bag_suffix(p) == ".db3.zstd" or (p.is_dir() and any(p.glob("*.db3.zstd"))):
            self._scratch = tempfile.TemporaryDirectory(prefix="diffbot-bag-")
        try:
            self._sqlite = _sqlite_plan(
                p, None if self._scratch is None else Path(self._scratch.name)
            )
        except DiffbotError:
            self.close()
            raise
        except Exception:  # damaged or unusual: rosbags' reader decides what is wrong
            self._sqlite = None
        if self._sqlite is not None:
            try:
                self._check_topic(self._sqlite.topics)
            except BaseException:
                self.close()
                raise
            self.message_count: int | None = self._sqlite.counts.get(self.topic)
            return
        self._open_reader(self._reader_path(p))

    def _reader_path(self, p: Path) -> Path:
        """What rosbags opens: the path, or the one mcap file of a folder without metadata."""
        if p.is_dir() and not (p / "metadata.yaml").exists():
            mcaps = _storage_files(p, ".mcap")
            if len(mcaps) == 1:
                return mcaps[0]
            raise BagError(
                f"{self.source}: not a bag folder: no metadata.yaml, and no .db3 file or single "
                f".mcap file to read without it"
            )
        return p

    def _open_reader(self, p: Path) -> None:
        self._ros1 = bag_suffix(p) == ".bag" and p.is_file()
        try:
            if self._ros1:
                import rosbags.rosbag1  # noqa: F401
            else:
                from rosbags.rosbag2 import Reader
        except ImportError:
            kind = "ROS 1" if self._ros1 else "ROS 2"
            raise BagError(
                f"reading this {kind} bag needs the rosbags library: {BAG_INSTALL_HINT}"
            ) from None
        try:
            bound_rosbags()
            self._reader = ros1_reader(p) if self._ros1 else Reader(p)
            self._reader.open()
        except Exception as err:
            kind = "ROS 1 bag" if self._ros1 else "rosbag2 recording"
            raise BagError(
                f"{self.source}: not a readable {kind}: {' '.join(str(err).split())}"
            ) from None
        try:
            topics: dict[str, set[str]] = {}
            for c in self._reader.connections:
                _check_connection(self.source, c.topic, c.msgtype, c.msgcount)
                topics.setdefault(c.topic, set()).add(c.msgtype)
            self._check_topic(topics)
            self._connections = [c for c in self._reader.connections if c.topic == self.topic]
            self.message_count = sum(c.msgcount for c in self._connections)
        except BaseException:
            self.close()
            raise

    def _check_topic(self, topics: dict[str, set[str]]) -> None:
        self.topics = topics
        if self._wanted is None and self._choose is not None:
            self.topic = self._choose(topics)
            self.topic_chosen = True
        elif self._wanted is None and DEFAULT_TOPIC not in topics:
            joint_topics = sorted(t for t, types in topics.items() if JOINT_STATE in types)
            if len(joint_topics) == 1:
                self.topic = joint_topics[0]
                self.topic_chosen = True
            elif joint_topics:
                raise BagError(
                    f"{self.source}: no topic {DEFAULT_TOPIC!r} and several {JOINT_STATE} "
                    f"topics: {listing(joint_topics)}; give the one to read ({{topic}})"
                )
        if self.topic not in topics and f"/{self.topic}" in topics:
            self.topic = f"/{self.topic}"  # a relative name, resolved in the root namespace
        if self.topic not in topics:
            found = listing(sorted(topics))
            raise BagError(
                f"{self.source}: no topic {self.topic!r} in the bag; topics found: {found}"
            )
        types = sorted(topics[self.topic])
        if len(types) > 1:
            raise BagError(
                f"{self.source}: topic {self.topic!r} carries several types: {', '.join(types)}"
            )
        self.msgtype: str = types[0]

    def notes(self) -> tuple[str, ...]:
        """What a reader should know of the bag, for people: a storage file with a write-ahead
        log (``.db3-wal``, left by a recording that did not close) whose messages are not
        read, as rosbags does not read them (nor may a reader add to a bag the files that
        reading them would)."""
        files = [self._path] if self._path.is_file() else sorted(self._path.glob("*.db3"))
        logs = []
        for file in files:
            log = file.with_name(file.name + "-wal")
            with contextlib.suppress(OSError):
                if log.is_file() and log.stat().st_size > 0:
                    logs.append(log.name)
        if not logs:
            return ()
        return (
            f"{listing(logs)}: a write-ahead log of a recording that did not close; the "
            "messages it holds are not read (open the bag once with sqlite3 to merge them)",
        )

    @property
    def ros1(self) -> bool:
        """Whether the bag is a ROS 1 bag (its messages converted to CDR as they are read)."""
        return self._ros1

    def close(self) -> None:
        """Close the recording (and remove any files it decompressed)."""
        if self._reader is not None and getattr(self._reader, "is_open", True):
            reader, self._reader = self._reader, None
            # rosbags' close trips over metadata it opened without checking (a file list
            # that is not a list); a reader that only read has nothing to lose on close
            with contextlib.suppress(Exception):
                reader.close()
        if self._scratch is not None:
            self._scratch.cleanup()
            self._scratch = None

    def __iter__(self) -> Iterator[BagChunk]:
        return self.chunks()

    def chunks(self, *, receive_times: bool = True) -> Iterator[BagChunk]:
        """The topic's messages from the start, chunk by chunk, in receive order.

        A chunk holds at most ``chunk_size`` messages and :data:`CHUNK_BYTES` bytes of them (a
        single message may fill one), whatever the storage.

        Args:
            receive_times: whether the chunks carry the receive times.

        Yields:
            Chunks of messages; ``receive_ns`` is None when ``receive_times`` is false.

        Raises:
            BagError: the storage is damaged, or a message is larger than
                :data:`MAX_MESSAGE_BYTES`.
        """
        try:
            if self._sqlite is not None:
                for path in self._sqlite.files:
                    yield from self._chunked(self._sqlite_batches(path), receive_times)
            else:
                yield from self._chunked(self._reader_batches(), receive_times)
        except DiffbotError as err:
            # Without the frames below: they hold the storage's buffers (a chunk of up to
            # 256 MiB), which the error would keep alive while it is handled.
            raise err.with_traceback(None) from None
        except Exception as err:
            # rosbags and sqlite3 raise assorted errors on damaged files; all mean the same.
            raise _unreadable(self.source, err, self._ros1) from None

    def _too_large(self, size: int) -> BagError:
        return BagError(
            f"{self.source}: a {self.msgtype} message of {size} bytes on topic {self.topic!r}, "
            f"more than the {MAX_MESSAGE_BYTES} bytes (1 MiB) a message may take: refused"
        )

    def _batch_size(self) -> int:
        """Rows read at once: a divisor of ``chunk_size`` (chunks keep their size) whose rows
        of :data:`MAX_MESSAGE_BYTES` each stay within :data:`CHUNK_BYTES`."""
        most = min(self.chunk_size, CHUNK_BYTES // MAX_MESSAGE_BYTES)
        return next(k for k in range(most, 0, -1) if self.chunk_size % k == 0)

    def _chunked(self, batches: Iterator[list[Any]], receive_times: bool) -> Iterator[BagChunk]:
        """Batches of rows (receive time in ns, stored data) in chunks of at most
        ``chunk_size`` messages and :data:`CHUNK_BYTES` bytes, each message checked against
        :data:`MAX_MESSAGE_BYTES`. A batch at a time, not a row: most of the reading is then
        done by C code (sqlite3's fetchmany, map)."""
        size = self.chunk_size
        stamps: list[int] = []
        blobs: list[bytes] = []
        held = 0
        for rows in batches:
            data = list(map(_DATA, rows))
            if not set(map(type, data)) <= {bytes}:
                data = list(map(_as_message, data))
            lengths = list(map(len, data))
            if max(lengths) > MAX_MESSAGE_BYTES:
                raise self._too_large(max(lengths))
            total = sum(lengths)
            if blobs and (held + total > CHUNK_BYTES or len(blobs) + len(data) > size):
                yield BagChunk(np.array(stamps, dtype=np.int64) if receive_times else None, blobs)
                stamps, blobs, held = [], [], 0
            if receive_times:
                stamps.extend(map(_STAMP, rows))
            blobs.extend(data)
            held += total
        if blobs:
            yield BagChunk(np.array(stamps, dtype=np.int64) if receive_times else None, blobs)

    def _sqlite_batches(self, path: Path) -> Iterator[list[Any]]:
        """(receive time in ns, data) of the topic's messages in one sqlite3 storage file,
        :meth:`_batch_size` rows at a time: a chunk's worth fetched at once would hold every
        large message of it. (Rows are stored whole in the file: a fetch holds no more than
        the file.)"""
        connection = _open_uri(path)
        try:
            ids = [
                row[0]
                for row in connection.execute(
                    "SELECT id FROM topics WHERE name = ? AND type = ?", (self.topic, self.msgtype)
                )
            ]
            marks = ",".join("?" * len(ids))
            cursor = connection.execute(
                f"SELECT timestamp, data FROM messages WHERE topic_id IN ({marks}) "
                "ORDER BY timestamp, id",
                ids,
            )
            step = self._batch_size()
            while rows := cursor.fetchmany(step):
                yield rows
        finally:
            connection.close()

    def _reader_batches(self) -> Iterator[list[Any]]:
        """(receive time in ns, CDR data) of the topic's messages, read by rosbags,
        :meth:`_batch_size` at a time."""
        assert self._reader is not None
        connections: list[Connection] = self._connections
        messages = self._reader.messages(connections=connections)
        convert = None
        if self._ros1:
            from diffbot.io.bag import typestore

            convert = typestore().ros1_to_cdr
        step = self._batch_size()
        batch: list[tuple[int, object]] = []
        budget = InflationBudget(_size_on_disk(self._path), self.source)
        pending = iter(messages)
        read = 0
        while True:
            with budget.active():  # rosbags inflates the chunks as the messages are taken
                taken = next(pending, None)
            if taken is None:
                break
            read += 1
            _, timestamp, data = taken
            if len(data) > MAX_MESSAGE_BYTES:  # before it is held in a batch or converted
                raise self._too_large(len(data))
            batch.append((timestamp, data if convert is None else convert(data, self.msgtype)))
            if len(batch) == step:
                yield batch
                batch = []
        if batch:
            yield batch
        listed = self.message_count
        if listed is not None and read < listed:
            # A damaged record (a message whose length runs past its end) ends rosbags' walk
            # through an MCAP chunk early, and the messages after it are lost without a word.
            raise BagError(
                f"{self.source}: {read} of the {listed} messages the bag lists on "
                f"{self.topic!r} could be read: the bag is damaged"
            )
