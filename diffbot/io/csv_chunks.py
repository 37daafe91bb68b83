"""Read the wheel columns of a recording CSV in chunks, without Python objects per cell.

A recording CSV has a time column (``time``, ``stamp``, ``t`` or ``__time``, any case, in
seconds) and one position column per wheel joint, named by the joint or ending with
``/<joint>/position`` (as bag export tools name the fields of a JointState); two columns that
may be the same one are refused (:mod:`diffbot.io.csv_columns`), other columns are ignored and
an empty cell means the joint is missing from that row. A side with several drive wheels needs
a column for at least one of them. The rules are those of :mod:`csv` (excel dialect, UTF-8 with
an optional byte order mark): the first row that is not blank names the columns. Stamps are
decimal seconds turned into integer nanoseconds exactly (ties to even).

A chunk of lines is parsed by :func:`numpy.loadtxt` (the wheel cells as float64, the time cells
as bytes) and the stamps by integer arithmetic on those bytes (:mod:`diffbot.io.csv_stamps`).
Python's rules take over where NumPy's could differ: a chunk that loadtxt refuses (an empty or
odd cell, a short row) is read row by row with :mod:`csv`, and so is the rest of a file from the
first quote character or NUL on (or from a chunk without a line end), in chunks of rows of about
``chunk_bytes`` characters, each row turned into numbers as it is read and none longer than
:data:`~diffbot.io.csv_lines.ROW_CHARS`; a time cell that is not plain digits with at most 9
decimals is converted on its own.
"""

from __future__ import annotations

import contextlib
import csv
import io
import itertools
import math
import os
import re
from collections.abc import Iterable, Iterator, Mapping, Sequence
from typing import TYPE_CHECKING, Final, NamedTuple, TextIO

import numpy as np

from diffbot.errors import RecordingError
from diffbot.formats.text import listing
from diffbot.io.csv_columns import TIME_COLUMNS, joint_columns, named_columns, time_column
from diffbot.io.csv_layout import CsvLayout
from diffbot.io.csv_lines import RowLines
from diffbot.io.csv_stamps import (
    TIME_UNITS,
    UNIT_NAMES,
    stamp_ns_from_text,
    stamps_from_digits,
    unit_by_magnitude,
)
from diffbot.io.textfile import open_text
from diffbot.numbers import reads_as_number, written_number
from diffbot.samples import (
    INT64,
    SKIP_MISSING_STAMP,
    SKIP_NOT_FINITE,
    SKIP_STAMP_RANGE,
    SKIP_UNREADABLE,
    ColumnSamples,
    Recording,
    beyond_range,
    beyond_ranges,
    range_reason,
    wheel_limit,
)

if TYPE_CHECKING:
    from numpy.typing import NDArray


__all__ = [
    "CHUNK_BYTES",
    "TIME_COLUMNS",
    "TIME_UNITS",
    "UNIT_NAMES",
    "CsvChunk",
    "CsvChunks",
    "CsvLayout",
    "open_csv_chunks",
    "read_csv",
    "stamp_ns_from_text",
    "stamps_from_digits",
    "unit_by_magnitude",
]

#: A number written with a decimal comma (``-0,25``, ``1764000000,1``).
_DECIMAL_COMMA: Final = re.compile(r"[-+]?[0-9]+,[0-9]+")
#: A whole number (``0``, ``-12``), written alike with a decimal point or comma.
_WHOLE: Final = re.compile(r"[-+]?[0-9]+")
#: Rows looked at, at most, for the first one with a fraction (a file of whole numbers, counts
#: at integer stamps, would otherwise have its whole first chunk parsed row by row).
_COMMA_ROWS: Final = 1000
#: Whole-number stamps this far apart (or more) are doubted as seconds.
_DOUBTFUL_STEP: Final = 10
#: Delimiters recognised in a header when none is given, besides the comma.
_OTHER_DELIMITERS: Final = (";", "\t", "|")
#: Characters of text read per chunk: about 17,000 rows of a simulator's CSV. Larger chunks are
#: no faster and leave more memory behind (measured: 48 MB peak at 1 MiB, 84 MB at 4 MiB).
CHUNK_BYTES: Final = 1 << 20

#: Width of the time cells as loadtxt returns them; a cell that fills it may have been cut.
_TIME_WIDTH: Final = 32
#: Rows parsed per chunk on the row-by-row path.
_EXACT_ROWS: Final = 65536


class CsvChunk(NamedTuple):
    """The samples of consecutive rows (n of them; the rows skipped are not among them).

    Attributes:
        stamp_ns: stamps (ns), int64, shape (n,).
        positions: the wheel joints' angles (rad), float64, shape (n, joints), in the order of
            :attr:`CsvChunks.joints`; 0.0 where the cell is empty.
        present: whether each cell is set, bool, same shape.
        skipped: rows of the chunk that are no sample, by reason.
        chars: characters of text the chunk was read from (for progress; 0 when not known).
    """

    stamp_ns: NDArray[np.int64]
    positions: NDArray[np.float64]
    present: NDArray[np.bool_]
    skipped: Mapping[str, int]
    chars: int = 0


def _stamp(text: str, decimals: int = 9) -> int | str:
    """A time cell as ns in int64, or the reason the row is skipped."""
    try:
        stamp_ns = stamp_ns_from_text(text, decimals)
    except ValueError:
        return SKIP_MISSING_STAMP if not text.strip() else SKIP_UNREADABLE
    if stamp_ns is None:
        return SKIP_NOT_FINITE
    if not -INT64 <= stamp_ns < INT64:
        return SKIP_STAMP_RANGE
    return stamp_ns


def _rows_exactly(
    rows: Iterable[list[str]],
    indexes: Sequence[int],
    decimals: int = 9,
    field: str = "position",
    limit: float | None = None,
) -> CsvChunk:
    """Rows parsed by :mod:`csv` into one chunk, cell by cell: wheel ``field`` values beyond
    ``limit`` (default: its :func:`~diffbot.samples.wheel_limit`) skip their row."""
    out_of_range = range_reason(field)
    limit = wheel_limit(field) if limit is None else limit
    time_index, *joint_indexes = indexes
    width = max(indexes) + 1
    stamps: list[int] = []
    positions: list[float] = []
    present: list[bool] = []
    skipped: dict[str, int] = {}
    for row in rows:
        if len(row) < width:
            if not any(cell.strip() for cell in row):
                continue  # a blank line is no sample
            row = row + [""] * (width - len(row))  # the cells a short row lacks are empty
        stamp = _stamp(row[time_index], decimals)
        if isinstance(stamp, str):
            if any(cell.strip() for cell in row):  # a line of empty cells is no sample
                skipped[stamp] = skipped.get(stamp, 0) + 1
            continue
        values: list[float] = []
        bits: list[bool] = []
        try:
            for i in joint_indexes:
                text = row[i]
                if text and not text.isspace():
                    values.append(written_number(text))
                    bits.append(True)
                else:
                    values.append(0.0)
                    bits.append(False)
        except ValueError:
            skipped[SKIP_UNREADABLE] = skipped.get(SKIP_UNREADABLE, 0) + 1
            continue
        if any(beyond_range(value, limit) for value in values):
            skipped[out_of_range] = skipped.get(out_of_range, 0) + 1
            continue
        stamps.append(stamp)
        positions.extend(values)
        present.extend(bits)
    joints = len(joint_indexes)
    return CsvChunk(
        np.array(stamps, dtype=np.int64),
        np.array(positions, dtype=np.float64).reshape(-1, joints),
        np.array(present, dtype=np.bool_).reshape(-1, joints),
        skipped,
    )


class CsvChunks:
    """The samples of a recording CSV stream, chunk by chunk, in constant memory.

    The header is read on construction (so a missing column fails at once). Iterate once.

    Args:
        stream: the text, read from where it stands (opened with ``newline=""``).
        sides: the left wheel joints and the right wheel joints.
        chunk_bytes: text read per chunk (characters, about).
        source: the input's name in messages.
        layout: columns, delimiter and time unit, where not the defaults.

    Attributes:
        joints: the wheel joints that have a column (or the columns named by ``layout``), the
            left ones first.
        left_count: how many of them are on the left.
        delimiter: the delimiter used.
        delimiter_detected: whether it was found in the header rather than given or a comma.
        time_unit: the time unit (``s``, ``ms``, ``us``, ``ns``); known once the first chunk
            is read when not given.
        unit_detected: whether ``time_unit`` was judged by the first stamp's magnitude.

    Raises:
        RecordingError: empty or non-text input, no time column, no column for a side, several
            columns for a joint.
    """

    def __init__(
        self,
        stream: TextIO,
        sides: tuple[Sequence[str], Sequence[str]],
        *,
        chunk_bytes: int = CHUNK_BYTES,
        source: str = "<stream>",
        layout: CsvLayout | None = None,
    ) -> None:
        layout = layout or CsvLayout()
        self.chunk_bytes = chunk_bytes
        self.source = source
        self._field = layout.field
        self._limit = wheel_limit(layout.field, layout.counts_per_rev)
        self._stream = stream
        self.delimiter = layout.delimiter or ","
        self.delimiter_detected = False
        self.time_unit = layout.time_unit or "s"
        self.unit_detected = False
        self._unit_known = layout.time_unit is not None
        self.decimal_comma = False
        self.unit_doubt: str | None = None
        self._comma_known = False
        headers: list[str] | None = None
        lines = RowLines(self._stream, source=source)
        with self._errors():
            for row in csv.reader(lines, delimiter=self.delimiter):
                lines.row_done()
                if any(cell.strip() for cell in row):
                    headers = [h.strip() for h in row]
                    break
        #: Lines read so far: those of the header, then of the chunks given.
        self._line = lines.line
        if headers is None:
            raise RecordingError(f"{source}: empty file")
        if layout.delimiter is None and len(headers) == 1:
            counts = {d: headers[0].count(d) for d in _OTHER_DELIMITERS}
            other = max(counts, key=lambda d: counts[d])
            if counts[other]:
                self.delimiter = other
                self.delimiter_detected = True
                headers = [h.strip() for h in next(csv.reader([headers[0]], delimiter=other))]
        if all(reads_as_number(h) for h in headers):
            example = self.delimiter.join(["time", *sides[0][:1], *sides[1][:1]])
            raise RecordingError(
                f"{source}: the first line holds numbers, not column names: a header line "
                f"naming the columns is needed (such as {example}; other names with "
                "{time_column}, {left_column}, {right_column})"
            )
        time_index = time_column(headers, source, layout.time_column)
        if time_index is None:
            raise RecordingError(
                f"{source}: no time column ({', '.join(TIME_COLUMNS)}; or name it: "
                f"{{time_column}}); columns found: {listing(headers)}"
            )
        if layout.left_columns is not None:
            left = named_columns(headers, layout.left_columns, "{left_column}", source)
        else:
            left = joint_columns(headers, sides[0], "left", source, layout.field)
        if layout.right_columns is not None:
            right = named_columns(headers, layout.right_columns, "{right_column}", source)
        else:
            right = joint_columns(headers, sides[1], "right", source, layout.field)
        seen = {time_index}
        for _, index in left + right:
            if index in seen:
                raise RecordingError(
                    f"{source}: column {headers[index]!r} is named for two roles ({{time_column}}, "
                    "{left_column}, {right_column}): each column is one wheel or the time"
                )
            seen.add(index)
        self.joints = tuple(joint for joint, _ in left + right)
        self.left_count = len(left)
        self.indexes = (time_index, *(index for _, index in left + right))

    def notes(self) -> tuple[str, ...]:
        """What was judged rather than given, for people: the delimiter, the time unit."""
        notes = []
        if self.delimiter_detected:
            notes.append(f"columns separated by {self.delimiter!r}, as the header is")
        if self.decimal_comma:
            notes.append("numbers with decimal commas, as the first row with fractions writes them")
        if self.unit_doubt is not None:
            notes.append(f"stamps read as seconds, though {self.unit_doubt} (milliseconds?)")
        if self.unit_detected:
            notes.append(
                f"stamps read as {UNIT_NAMES[self.time_unit]}, judged by the size of the first "
                "(too large for seconds since 1970)"
            )
        return tuple(notes)

    def _judge_comma(self, text: str) -> None:
        """Whether the numbers have decimal commas (``0,25``, as spreadsheets in many locales
        write them): only where the delimiter is not a comma, by the first row whose cells are
        not all whole numbers (those read alike either way: a run that starts ``0;0;0`` has
        its fractions in the rows after), among the first :data:`_COMMA_ROWS`."""
        self._comma_known = True
        if self.delimiter == ",":
            return
        rows = (line for line in io.StringIO(text, newline="") if line.strip())
        for line in itertools.islice(rows, _COMMA_ROWS):
            row = next(csv.reader([line], delimiter=self.delimiter), [])
            cells = [row[i].strip() for i in self.indexes if i < len(row)]
            if all(not c or _WHOLE.fullmatch(c) for c in cells):
                continue
            self.decimal_comma = any(_DECIMAL_COMMA.fullmatch(c) for c in cells) and all(
                _DECIMAL_COMMA.fullmatch(c) or reads_as_number(c) or not c for c in cells
            )
            return

    def _text(self, text: str) -> str:
        """A chunk's text as read: decimal commas made points."""
        return text.replace(",", ".") if self.decimal_comma else text

    @property
    def _decimals(self) -> int:
        return TIME_UNITS[self.time_unit]

    def _judge_unit(self, text: str) -> None:
        """Take the time unit from the first stamp's magnitude, when not given; doubt seconds
        out loud when the first two stamps are whole numbers at least 10 apart (a wheel log
        sampled every 10 s or more is rarer than milliseconds since power-on)."""
        cells = []
        for line in io.StringIO(text, newline=""):
            if not line.strip():
                continue
            row = next(csv.reader([line], delimiter=self.delimiter), [])
            if len(row) <= self.indexes[0]:
                break
            cells.append(row[self.indexes[0]].strip())
            if len(cells) == 2:
                break
        if not cells:
            return
        try:
            value = written_number(cells[0])
        except ValueError:
            return
        if not math.isfinite(value):
            return
        unit = unit_by_magnitude(value)
        self._unit_known = True
        if unit != "s":
            self.time_unit = unit
            self.unit_detected = True
        elif len(cells) == 2 and all(cell.isdigit() for cell in cells):
            step = int(cells[1]) - int(cells[0])
            if step >= _DOUBTFUL_STEP:
                self.unit_doubt = f"whole numbers {step} apart"

    def _errors(self) -> contextlib.AbstractContextManager[None]:
        return _translated(self.source)

    def __iter__(self) -> Iterator[CsvChunk]:
        fields = [("t", f"S{_TIME_WIDTH}")] + [(f"p{j}", "f8") for j in range(len(self.joints))]
        dtype = np.dtype(fields)
        carry = ""
        while True:
            with self._errors():
                block = self._stream.read(self.chunk_bytes)
            text = carry + block
            if not text:
                return
            carry = ""
            if block:  # cut after the last complete line; the rest starts the next chunk
                cut = text.rfind("\n") + 1
                text, carry = text[:cut], text[cut:]
            if not self._comma_known:
                with self._errors():
                    self._judge_comma(text)
            text = self._text(text)
            if not self._unit_known:
                with self._errors():
                    self._judge_unit(text)
            if not text or '"' in text or "\0" in text:
                # Quotes may hold delimiters and line breaks across chunks: csv from here on.
                yield from self._exact_rest(text, carry)
                return
            yield self._fast(text, dtype)._replace(chars=len(text))
            self._line += text.count("\n")

    def _exact_rest(self, text: str, carry: str) -> Iterator[CsvChunk]:
        """The rest of the input, row by row with csv, in chunks of at most
        :data:`_EXACT_ROWS` rows and about ``chunk_bytes`` characters: a chunk holds its
        samples and one row of cells at a time.

        Raises:
            RecordingError: a row longer than :data:`~diffbot.io.csv_lines.ROW_CHARS`.
        """
        lines = RowLines(
            self._stream, text + self._text(carry), self._text, source=self.source, line=self._line
        )
        rows = csv.reader(lines, delimiter=self.delimiter)
        while True:
            start = lines.chars
            with self._errors():
                chunk = _rows_exactly(
                    self._batch(rows, lines), self.indexes, self._decimals, self._field, self._limit
                )
            if lines.chars == start:
                return
            yield chunk._replace(chars=lines.chars - start)

    def _batch(self, rows: Iterator[list[str]], lines: RowLines) -> Iterator[list[str]]:
        """The next rows of ``rows`` (read from ``lines``), up to :data:`_EXACT_ROWS` of them
        or as soon as they reach ``chunk_bytes`` characters."""
        start = lines.chars
        for count, row in enumerate(rows, 1):
            lines.row_done()
            yield row
            if count == _EXACT_ROWS or lines.chars - start >= self.chunk_bytes:
                return

    def _fast(self, text: str, dtype: np.dtype[np.void]) -> CsvChunk:
        """Complete lines without quotes: loadtxt when it can, else csv row by row."""
        if len(set(self.indexes)) != len(self.indexes):
            return self._exact(text)
        if text.isspace():
            return _rows_exactly([], self.indexes)  # blank lines: no samples
        try:
            table = np.loadtxt(
                io.StringIO(text),
                delimiter=self.delimiter,
                usecols=self.indexes,
                dtype=dtype,
                comments=None,
                quotechar=None,
                ndmin=1,
            )
        except ValueError:
            return self._exact(text)
        cells = np.ascontiguousarray(table["t"])
        if cells.size and np.any(cells.view(np.uint8).reshape(cells.size, -1)[:, -1]):
            return self._exact(text)  # a time cell may have been cut to _TIME_WIDTH bytes
        stamps, ok = stamps_from_digits(cells, self._decimals)
        keep = np.ones(cells.size, dtype=np.bool_)
        skipped: dict[str, int] = {}
        for k in np.flatnonzero(~ok).tolist():
            stamp = _stamp(bytes(cells[k]).decode("latin-1"), self._decimals)
            if isinstance(stamp, str):
                skipped[stamp] = skipped.get(stamp, 0) + 1
                keep[k] = False
            else:
                stamps[k] = stamp
        rows = table[keep]
        positions = np.empty((rows.size, len(self.joints)), dtype=np.float64)
        for j in range(len(self.joints)):
            positions[:, j] = rows[f"p{j}"]
        stamps = stamps[keep]
        large = beyond_ranges(positions, self._limit).any(axis=1)
        if large.any():
            skipped[range_reason(self._field)] = int(np.count_nonzero(large))
            positions, stamps = positions[~large], stamps[~large]
        present = np.ones(positions.shape, dtype=np.bool_)
        return CsvChunk(stamps, positions, present, skipped)

    def _exact(self, text: str) -> CsvChunk:
        with self._errors():
            rows = csv.reader(io.StringIO(text, newline=""), delimiter=self.delimiter)
            return _rows_exactly(rows, self.indexes, self._decimals, self._field, self._limit)


@contextlib.contextmanager
def _translated(source: str) -> Iterator[None]:
    """Turn decoding and csv errors into a :class:`RecordingError` naming the input."""
    try:
        yield
    except UnicodeDecodeError:
        raise RecordingError(f"{source}: not a text (UTF-8) CSV file") from None
    except csv.Error as err:
        raise RecordingError(f"{source}: malformed CSV: {err}") from None


@contextlib.contextmanager
def open_csv_chunks(
    path: str | os.PathLike[str] | TextIO,
    sides: tuple[Sequence[str], Sequence[str]],
    *,
    chunk_bytes: int = CHUNK_BYTES,
    source: str | None = None,
    layout: CsvLayout | None = None,
) -> Iterator[CsvChunks]:
    """The chunks of a recording CSV file or stream; the file is closed at the end.

    Args:
        path: the file, or an open text stream (read from where it stands).
        sides: the left wheel joints and the right wheel joints.
        chunk_bytes: text read per chunk (characters, about).
        source: the input's name in messages (default: the path, or the stream's name).

    Raises:
        RecordingError: missing, empty or non-text input, no time column, no column for a
            side, several columns for a joint, malformed CSV.
    """
    if isinstance(path, (str, os.PathLike)):
        name = source if source is not None else os.fspath(path)
        with open_text(path, RecordingError, "a CSV file", name=name, newline="") as stream:
            yield CsvChunks(stream, sides, chunk_bytes=chunk_bytes, source=name, layout=layout)
        return
    name = source if source is not None else str(getattr(path, "name", "<stream>"))
    yield CsvChunks(path, sides, chunk_bytes=chunk_bytes, source=name, layout=layout)


def read_csv(
    path: str | os.PathLike[str] | TextIO,
    left_joint: str | Sequence[str],
    right_joint: str | Sequence[str],
    *,
    source: str | None = None,
    layout: CsvLayout | None = None,
) -> Recording:
    """Read the wheel joint samples of a recording CSV whole, as compact columns.

    A side with several joints moves by the motion of its joints present in each row (see
    :func:`diffbot.samples.side_means`).

    Args:
        path: the file, or an open text stream (read from where it stands).
        left_joint: the left wheel joint's name, or all of the left side's.
        right_joint: likewise on the right.
        source: the input's name in messages (default: the path, or the stream's name).
        layout: columns, delimiter and time unit, where not the defaults.

    Returns:
        One sample per data row, holding the sides whose cells are not all empty. Rows whose
        time is empty, NaN or infinite, or outside the int64 nanosecond range of ROS time, and
        rows with a cell that is not a number are counted in ``skipped``.

    Raises:
        RecordingError: missing, empty or non-text file, no time column, no (or several)
            columns for a wheel.
    """
    sides = tuple((s,) if isinstance(s, str) else tuple(s) for s in (left_joint, right_joint))
    first = (sides[0][0], sides[1][0])
    skipped: dict[str, int] = {}
    with open_csv_chunks(path, (sides[0], sides[1]), source=source, layout=layout) as chunks:
        samples = ColumnSamples(*first)
        for chunk in chunks:
            for reason, count in chunk.skipped.items():
                skipped[reason] = skipped.get(reason, 0) + count
            samples.add_chunk(chunk.stamp_ns, chunk.positions, chunk.present, chunks.left_count)
        return Recording(chunks.source, "csv", samples, skipped, notes=chunks.notes())
