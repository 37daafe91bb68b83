"""What the readers need to know of a recording's path before they read it: that its files are
regular ones, how much there is to read, and a CSV's layout from the library's arguments.
Reading whole and conditioning are :func:`diffbot.recordings.read_recording`'s.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from contextlib import closing
from pathlib import Path

from diffbot.errors import ParameterError, RecordingError
from diffbot.formats.text import brief
from diffbot.io.bag import bag_suffix, is_bag
from diffbot.io.bag_chunks import TopicChunks
from diffbot.io.csv_chunks import CsvLayout
from diffbot.io.outputs import note_input
from diffbot.io.textfile import check_regular

__all__ = [
    "csv_layout",
    "existing_recording",
    "recording_size",
]


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


def csv_layout(
    time_column: str | None = None,
    left_column: str | Sequence[str] | None = None,
    right_column: str | Sequence[str] | None = None,
    delimiter: str | None = None,
    time_unit: str | None = None,
) -> CsvLayout:
    """A :class:`~diffbot.io.csv_chunks.CsvLayout` from the library's arguments (a column
    given as a string may list several, comma-separated)."""

    def names(value: str | Sequence[str] | None, name: str) -> tuple[str, ...] | None:
        if value is None:
            return None
        parts = value.split(",") if isinstance(value, str) else list(value)
        if not parts or not all(str(part).strip() for part in parts):
            # An empty name fell back to the joints' columns, silently reading other data.
            raise ParameterError(f"{{{name}}} {brief(value)}: a column name is empty")
        return tuple(str(part).strip() for part in parts)

    if time_column is not None and not time_column.strip():
        raise ParameterError(f"{{time_column}} {brief(time_column)}: a column name is empty")
    return CsvLayout(
        time_column,
        names(left_column, "left_column"),
        names(right_column, "right_column"),
        delimiter,
        time_unit,
    )
