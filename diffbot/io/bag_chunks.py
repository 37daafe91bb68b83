"""Stream one topic of a rosbag2 recording in chunks of raw messages, in constant memory.

Uncompressed sqlite3 storage (a bag directory whose ``metadata.yaml`` names it, or one ``.db3``
file) is read with :mod:`sqlite3` itself: the topic's type from the metadata or the file's
``topics`` table, then its messages many rows per call, in the order rosbags reads them (by
receive time; ties by insertion order, as the bag's timestamp index yields them). Anything else
(mcap, compressed bags, metadata this module does not follow) is opened and read by rosbags'
reader and cut into chunks.
"""

from __future__ import annotations

import os
import sqlite3
from collections.abc import Iterator
from operator import itemgetter
from pathlib import Path, PurePath
from typing import TYPE_CHECKING, Any, Final, NamedTuple

import numpy as np

from diffbot.errors import DiffbotError, RecordingError
from diffbot.formats.text import listing
from diffbot.io.bag import BAG_INSTALL_HINT

if TYPE_CHECKING:
    from numpy.typing import NDArray
    from rosbags.interfaces import Connection
    from rosbags.rosbag2 import Reader

__all__ = ["CHUNK_MESSAGES", "BagChunk", "BagError", "TopicChunks"]

#: Messages per chunk unless asked otherwise: about 3 MB of JointState messages of four joints.
#: Larger chunks are no faster and leave more memory behind (measured: 58 MB peak at 16384,
#: 100-110 MB at 65536 for 1e6-3e6 messages).
CHUNK_MESSAGES: Final = 16384


class BagError(RecordingError):
    """A rosbag2 recording cannot be read, or lacks the topic asked for."""


class BagChunk(NamedTuple):
    """Consecutive messages of one topic.

    Attributes:
        receive_ns: the times (ns) the bag received them, int64, shape (n,); None when not
            asked for.
        blobs: the serialized messages, n of them.
    """

    receive_ns: NDArray[np.int64] | None
    blobs: list[bytes]


def _unreadable(source: str, err: Exception) -> BagError:
    detail = " ".join(str(err).split()) or type(err).__name__
    return BagError(f"{source}: not a readable rosbag2 recording: {detail}")


def _open_uri(path: Path) -> sqlite3.Connection:
    return sqlite3.connect(path.resolve().as_uri() + "?mode=ro&immutable=1", uri=True)


class _SqlitePlan(NamedTuple):
    """What to read from uncompressed sqlite3 storage: the files and the topics found."""

    files: list[Path]
    topics: dict[str, set[str]]
    counts: dict[str, int]


def _sqlite_plan(path: Path) -> _SqlitePlan | None:
    """The storage files and topics of an uncompressed sqlite3 bag; None for any other bag.

    Raises:
        Exception: from sqlite3 or YAML on damaged files (the caller then lets rosbags judge).
    """
    if path.is_file():
        if path.suffix != ".db3":
            return None
        files = [path]
        topics: dict[str, set[str]] = {}
        counts: dict[str, int] = {}
    else:
        import yaml

        info: Any = yaml.safe_load((path / "metadata.yaml").read_text(encoding="utf-8"))
        info = info["rosbag2_bagfile_information"]
        mode = str(info.get("compression_mode") or "").lower()
        if (
            info["storage_identifier"] != "sqlite3"
            or info["version"] > 9
            or mode not in ("", "none")
        ):
            return None
        files = [path / PurePath(name).name for name in info["relative_file_paths"]]
        if not all(f.is_file() for f in files):
            return None
        topics = {}
        counts = {}
        for entry in info["topics_with_message_count"]:
            meta = entry["topic_metadata"]
            topics.setdefault(meta["name"], set()).add(meta["type"])
            counts[meta["name"]] = counts.get(meta["name"], 0) + int(entry["message_count"])
    for file in files:
        connection = _open_uri(file)
        try:
            for name, msgtype in connection.execute("SELECT name, type FROM topics"):
                topics.setdefault(name, set()).add(msgtype)
        finally:
            connection.close()
    return _SqlitePlan(files, topics, counts)


class TopicChunks:
    """The messages of one topic of a rosbag2 recording, chunk by chunk.

    Opened on construction (so a missing topic fails at once) and closed by :meth:`close` (use
    :func:`contextlib.closing`). Iterating reads the topic from its start, each time.

    Args:
        path: a rosbag2 directory (sqlite3 or mcap storage), or one ``.db3`` or ``.mcap`` file.
        topic: the topic to read.
        chunk_size: messages per chunk (the last may hold fewer).

    Attributes:
        msgtype: the topic's message type, from the bag's topic table or metadata.
        message_count: how many messages the bag's metadata says the topic holds; None for a
            lone ``.db3`` file (counting would read the whole file).

    Raises:
        BagError: rosbags is missing, the path is not a readable bag, or it lacks the topic,
            or the topic carries several message types.
    """

    def __init__(
        self, path: str | os.PathLike[str], topic: str, *, chunk_size: int = CHUNK_MESSAGES
    ) -> None:
        if chunk_size < 1:
            raise BagError(f"chunk_size must be at least 1, got {chunk_size}")
        p = Path(path)
        self.source = str(p)
        self.topic = topic
        self.chunk_size = chunk_size
        if not p.exists():
            raise BagError(f"{self.source}: no such file or directory")
        if p.is_file() and p.stat().st_size == 0:
            raise BagError(f"{self.source}: empty file")
        self._reader: Reader | None = None
        self._sqlite: _SqlitePlan | None = None
        try:
            self._sqlite = _sqlite_plan(p)
        except Exception:  # damaged or unusual: rosbags' reader decides what is wrong
            self._sqlite = None
        if self._sqlite is not None:
            self._check_topic(self._sqlite.topics)
            self.message_count: int | None = self._sqlite.counts.get(topic)
            return
        try:
            from rosbags.rosbag2 import Reader
        except ImportError:
            raise BagError(
                f"reading this ROS 2 bag needs the rosbags library: {BAG_INSTALL_HINT}"
            ) from None
        try:
            self._reader = Reader(p)
            self._reader.open()
        except Exception as err:
            raise _unreadable(self.source, err) from None
        try:
            self._connections = [c for c in self._reader.connections if c.topic == topic]
            topics: dict[str, set[str]] = {}
            for c in self._reader.connections:
                topics.setdefault(c.topic, set()).add(c.msgtype)
            self._check_topic(topics)
            self.message_count = sum(c.msgcount for c in self._connections)
        except BaseException:
            self._reader.close()
            raise

    def _check_topic(self, topics: dict[str, set[str]]) -> None:
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

    def close(self) -> None:
        """Close the recording (and remove any files it decompressed)."""
        if self._reader is not None and self._reader.is_open:
            self._reader.close()

    def __iter__(self) -> Iterator[BagChunk]:
        return self.chunks()

    def chunks(self, *, receive_times: bool = True) -> Iterator[BagChunk]:
        """The topic's messages from the start, chunk by chunk, in receive order.

        Args:
            receive_times: whether the chunks carry the receive times; without them reading
                sqlite3 storage makes one Python object less per message.

        Yields:
            Chunks of messages; ``receive_ns`` is None when ``receive_times`` is false and the
            bag is read with sqlite3.

        Raises:
            BagError: the storage is damaged.
        """
        try:
            if self._sqlite is not None:
                for path in self._sqlite.files:
                    yield from self._sqlite_chunks(path, receive_times)
            else:
                yield from self._generic_chunks()
        except DiffbotError:
            raise
        except Exception as err:
            # rosbags and sqlite3 raise assorted errors on damaged files; all mean the same.
            raise _unreadable(self.source, err) from None

    def _sqlite_chunks(self, path: Path, receive_times: bool) -> Iterator[BagChunk]:
        connection = _open_uri(path)
        try:
            ids = [
                row[0]
                for row in connection.execute(
                    "SELECT id FROM topics WHERE name = ? AND type = ?", (self.topic, self.msgtype)
                )
            ]
            marks = ",".join("?" * len(ids))
            # A damaged or hostile bag may hold TEXT, numbers or NULL where a message's bytes
            # go: those arrive as empty messages, which decode as unreadable and are skipped.
            blob = "CASE WHEN typeof(data) = 'blob' THEN data ELSE x'' END"
            columns = f"timestamp, {blob}" if receive_times else blob
            cursor = connection.execute(
                f"SELECT {columns} FROM messages WHERE topic_id IN ({marks}) "
                "ORDER BY timestamp, id",
                ids,
            )
            if not receive_times:
                data = itemgetter(0)
                while rows := cursor.fetchmany(self.chunk_size):
                    yield BagChunk(None, list(map(data, rows)))
                return
            stamp, data = itemgetter(0), itemgetter(1)
            while rows := cursor.fetchmany(self.chunk_size):
                stamps = np.fromiter(map(stamp, rows), dtype=np.int64, count=len(rows))
                yield BagChunk(stamps, list(map(data, rows)))
        finally:
            connection.close()

    def _generic_chunks(self) -> Iterator[BagChunk]:
        assert self._reader is not None
        connections: list[Connection] = self._connections
        stamps: list[int] = []
        blobs: list[bytes] = []
        for _, timestamp, data in self._reader.messages(connections=connections):
            stamps.append(timestamp)
            blobs.append(bytes(data))
            if len(blobs) == self.chunk_size:
                yield BagChunk(np.array(stamps, dtype=np.int64), blobs)
                stamps, blobs = [], []
        if blobs:
            yield BagChunk(np.array(stamps, dtype=np.int64), blobs)
