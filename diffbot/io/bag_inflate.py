"""Decompression of bag data, each bounded by the size it may grow to.

A few kilobytes of zstd, lz4 or bz2 can hold gigabytes of zeros, so nothing a bag holds is
decompressed whole. Every stream is inflated piece by piece with a ``max_length`` and refused
(a :class:`~diffbot.errors.RecordingError`, one line) as soon as it passes its bound:

- a ROS 1 chunk: the uncompressed size its record header declares, itself at most
  :data:`MAX_CHUNK_BYTES`;
- an MCAP chunk: likewise its declared uncompressed size;
- a message of a rosbag2 bag compressed message by message: :data:`MAX_MESSAGE_BYTES`;
- a storage file of a bag compressed file by file (``.db3.zstd``, ``.mcap.zstd``):
  :data:`FILE_RATIO` times its compressed size, at least :data:`MIN_FILE_BYTES`;
- all a read of one bag inflates (:class:`InflationBudget`): likewise, of the bag's size on
  disk. Chunks that are each within their bound add up: an MCAP index that lists every chunk
  as the first makes rosbags inflate them all before the first message, and a ROS 1 bag whose
  messages alternate between chunks inflates a chunk again for each message.

rosbags decompresses in its own readers: :func:`bound_rosbags` puts these bounded inflaters in
place of its whole-buffer ones (once, before a reader is opened), and :class:`BoundedRos1Reader`
reads each ROS 1 chunk's declared size, which rosbags does not.
"""

from __future__ import annotations

import contextlib
import functools
import os
import shutil
import threading
from collections.abc import Callable, Iterator
from typing import IO, TYPE_CHECKING, Any, Final, Protocol

from diffbot.errors import RecordingError
from diffbot.io.bag import BAG_INSTALL_HINT

if TYPE_CHECKING:
    from pathlib import Path

__all__ = [
    "FILE_RATIO",
    "MAX_CHUNK_BYTES",
    "MAX_MESSAGE_BYTES",
    "MIN_FILE_BYTES",
    "InflationBudget",
    "bound_rosbags",
    "copy_inflated",
    "file_limit",
    "inflate",
    "ros1_reader",
]

#: Largest chunk of a ROS 1 or MCAP bag inflated (bytes): rosbag writes chunks of 768 KiB.
MAX_CHUNK_BYTES: Final = 256 << 20
#: Largest message of a bag compressed message by message inflated (bytes).
MAX_MESSAGE_BYTES: Final = 64 << 20
#: Most a compressed storage file may grow, as a multiple of its compressed size (real
#: recordings compress 3 to 30 times).
FILE_RATIO: Final = 100
#: A compressed storage file may always grow to this many bytes.
MIN_FILE_BYTES: Final = 64 << 20
#: Bytes inflated per step (of a file copy, or of a stream held in memory).
_STEP: Final = 1 << 20


class _Decompressor(Protocol):
    eof: bool
    needs_input: bool
    unused_data: bytes

    def decompress(self, data: bytes, max_length: int = -1) -> bytes: ...


def _zstd() -> Any:
    try:
        from compression import zstd  # type: ignore[import-not-found,unused-ignore]
    except ImportError:
        try:
            from backports import zstd  # type: ignore[no-redef,import-not-found,unused-ignore]
        except ImportError:
            raise RecordingError(
                f"decompressing zstd needs the rosbags library: {BAG_INSTALL_HINT}"
            ) from None
    return zstd


def _decompressor(kind: str) -> Callable[[], _Decompressor]:
    if kind == "zstd":
        return _zstd().ZstdDecompressor  # type: ignore[no-any-return]
    if kind == "lz4":
        import lz4.frame  # type: ignore[import-untyped,unused-ignore]

        return lz4.frame.LZ4FrameDecompressor  # type: ignore[no-any-return]
    if kind == "bz2":
        import bz2

        return bz2.BZ2Decompressor  # type: ignore[return-value]
    raise RecordingError(f"unknown compression {kind!r}")


_ACTIVE = threading.local()


class InflationBudget:
    """The bytes one read of a bag may inflate in all: :func:`file_limit` of its size on disk.

    Args:
        compressed_size: the bag's storage files' size on disk (bytes).
        what: the bag, for the message.
    """

    def __init__(self, compressed_size: int, what: str) -> None:
        self.limit = file_limit(compressed_size)
        self.used = 0
        self.what = what

    @contextlib.contextmanager
    def active(self) -> Iterator[None]:
        """Count what this thread inflates inside the block against this budget."""
        previous = getattr(_ACTIVE, "budget", None)
        _ACTIVE.budget = self
        try:
            yield
        finally:
            _ACTIVE.budget = previous

    def spend(self, count: int) -> None:
        """Count ``count`` bytes inflated; refuse the read once they pass the limit."""
        self.used += count
        if self.used > self.limit:
            raise RecordingError(
                f"{self.what}: reading it decompresses more than {self.limit} bytes (the most "
                f"a bag may: {FILE_RATIO} times its size on disk, at least "
                f"{MIN_FILE_BYTES >> 20} MiB): refused (a bomb, or chunks read over and over?)"
            )


def _spend(count: int) -> None:
    budget: InflationBudget | None = getattr(_ACTIVE, "budget", None)
    if budget is not None:
        budget.spend(count)


def _too_large(what: str, limit: int) -> RecordingError:
    return RecordingError(f"{what} decompresses to more than {limit} bytes, refused (a bomb?)")


def inflate(data: bytes, kind: str, limit: int, what: str) -> bytes:
    """``data`` (one or more ``kind`` frames or streams: zstd, lz4 or bz2) decompressed.

    Args:
        data: the compressed bytes.
        kind: ``zstd``, ``lz4`` or ``bz2``.
        limit: most bytes the result may hold.
        what: the data, for the message.

    Raises:
        RecordingError: the result would exceed ``limit``, or the data is truncated or not of
            its kind.
    """
    new = _decompressor(kind)
    out = bytearray()
    rest = data
    try:
        while rest:
            stream = new()
            # A step at a time: a piece as large as the whole would be held beside it.
            piece = stream.decompress(rest, min(_STEP, limit + 1 - len(out)))
            while True:
                out += piece
                _spend(len(piece))
                if len(out) > limit:
                    raise _too_large(what, limit)
                if stream.eof:
                    break
                if stream.needs_input:
                    raise RecordingError(f"{what}: its {kind} data is truncated")
                piece = stream.decompress(b"", min(_STEP, limit + 1 - len(out)))
                if not (piece or stream.eof or stream.needs_input):
                    raise RecordingError(f"{what}: its {kind} data is truncated")  # no progress
            rest = stream.unused_data
    except (OSError, EOFError, ValueError, RuntimeError) as err:
        # lz4 raises RuntimeError, bz2 OSError, zstd its ZstdError (a ValueError in 3.14)
        raise RecordingError(f"{what}: malformed {kind} data: {err}") from None
    except Exception as err:
        if type(err).__name__ != "ZstdError":
            raise
        raise RecordingError(f"{what}: malformed {kind} data: {err}") from None
    return bytes(out)


def file_limit(compressed_size: int) -> int:
    """Most bytes a compressed storage file of ``compressed_size`` bytes may inflate to."""
    return max(MIN_FILE_BYTES, FILE_RATIO * compressed_size)


class _BoundedReader:
    """A decompressing file object that refuses to read past ``limit`` bytes."""

    def __init__(self, stream: IO[bytes], limit: int, what: str) -> None:
        self.stream = stream
        self.limit = limit
        self.what = what
        self.count = 0

    def read(self, size: int = -1) -> bytes:
        want = self.limit + 1 - self.count
        data = self.stream.read(want if size < 0 else min(size, want))
        self.count += len(data)
        if self.count > self.limit:
            raise _too_large(self.what, self.limit)
        return data

    def __enter__(self) -> _BoundedReader:
        return self

    def __exit__(self, *_: object) -> None:
        self.stream.close()

    def close(self) -> None:
        self.stream.close()


def copy_inflated(source: Path, target: Path) -> None:
    """A zstd-compressed storage file written decompressed to ``target``, bounded by
    :func:`file_limit` of its size."""
    limit = file_limit(os.path.getsize(source))
    with _zstd().open(source, "rb") as stream, target.open("wb") as sink:
        shutil.copyfileobj(_BoundedReader(stream, limit, str(source)), sink, _STEP)


class _ZstdForRosbag2:
    """What rosbags' rosbag2 reader uses of the zstd module, bounded."""

    @staticmethod
    def decompress(data: bytes) -> bytes:
        return inflate(data, "zstd", MAX_MESSAGE_BYTES, "a compressed bag message")

    @staticmethod
    def open(file: IO[bytes], mode: str = "rb") -> _BoundedReader:
        if mode != "rb":
            raise ValueError(mode)
        try:
            size = os.fstat(file.fileno()).st_size
        except (OSError, AttributeError, ValueError):
            size = 0
        return _BoundedReader(_zstd().open(file, "rb"), file_limit(size), "a compressed bag file")


_BOUND = False


def bound_rosbags() -> None:
    """Put bounded inflaters in the place of rosbags' own (once; rosbags must be installed)."""
    global _BOUND
    if _BOUND:
        return
    import rosbags.rosbag1.reader as ros1
    import rosbags.rosbag2.reader as ros2
    import rosbags.rosbag2.storage_mcap as mcap

    def chunk(kind: str) -> Callable[[bytes, int], bytes]:
        def decompress(data: bytes, size: int) -> bytes:
            return inflate(data, kind, min(size, MAX_CHUNK_BYTES), "a bag chunk")

        return decompress

    mcap.DECOMPRESSORS["lz4"] = chunk("lz4")
    mcap.DECOMPRESSORS["zstd"] = chunk("zstd")
    # Chunks read by a plain rosbag1 reader (without their declared size) keep the cap.
    for kind in ("lz4", "bz2"):
        ros1.decompressors[kind] = functools.partial(
            inflate, kind=kind, limit=MAX_CHUNK_BYTES, what="a bag chunk"
        )
    setattr(ros2, "zstd", _ZstdForRosbag2)  # noqa: B010 (a module global rosbags reads)
    _BOUND = True


def ros1_reader(path: Path) -> Any:
    """A rosbags ROS 1 reader whose chunks inflate no further than their declared size."""
    bound_rosbags()
    from rosbags.rosbag1.reader import Header, Reader, RecordType

    class BoundedRos1Reader(Reader):
        def read_chunk(self) -> Any:
            assert self.bio is not None
            start = self.bio.tell()
            header = Header.read(self.bio, RecordType.CHUNK)
            kind = header.get_string("compression")
            declared = header.get_uint32("size")
            self.bio.seek(start)
            found = super().read_chunk()
            if kind == "none":
                return found
            if declared > MAX_CHUNK_BYTES:
                raise _too_large(f"{path}: a chunk declaring {declared} bytes", MAX_CHUNK_BYTES)
            what = f"{path}: a chunk declaring {declared} bytes"
            return found._replace(decompressor=lambda data: inflate(data, kind, declared, what))

    return BoundedRos1Reader(path)
