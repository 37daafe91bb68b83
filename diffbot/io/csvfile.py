"""Recordings as CSV files: joint samples in, poses and joint states out.

A recording CSV has a time column (``time``, ``stamp``, ``t`` or ``__time``, in seconds) and one
position column per wheel, named by the joint or ending with ``/<joint>/position`` (as bag
export tools name the fields of a JointState); other columns are ignored and an empty cell means
the joint is missing from that row.
"""

from __future__ import annotations

import csv
import io
import os
from collections.abc import Iterable, Iterator, Sequence
from typing import TYPE_CHECKING, Final, TextIO

from diffbot.errors import RecordingError
from diffbot.formats.text import listing
from diffbot.io.textfile import open_text
from diffbot.kinematics import norm_angle
from diffbot.odometry import SKIP_NOT_FINITE
from diffbot.replay import OdometryRow, OdometryRows
from diffbot.samples import (
    INT64,
    NS_PER_S,
    SKIP_MISSING_STAMP,
    SKIP_POSITION_RANGE,
    SKIP_STAMP_RANGE,
    SKIP_UNREADABLE,
    ColumnSamples,
    Recording,
    beyond_range,
    ns_from_seconds,
    seconds_text,
)

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = ["TIME_COLUMNS", "format_joint_states_csv", "format_odometry_csv", "read_csv"]

#: Names a CSV time column may have (seconds), case-insensitive, in order of preference.
TIME_COLUMNS: Final = ("time", "stamp", "t", "__time")


def _column(headers: Sequence[str], joint: str, side: str, source: str) -> int:
    suffix = f"/{joint}/position"
    found = [i for i, h in enumerate(headers) if h == joint or h.endswith(suffix)]
    if not found:
        raise RecordingError(
            f"{source}: no column for the {side} wheel joint {joint!r} (named {joint!r} or "
            f"ending with '{suffix}'); columns found: {listing(headers)}"
        )
    if len(found) > 1:
        raise RecordingError(
            f"{source}: several columns for the {side} wheel joint {joint!r}: "
            f"{listing(headers[i] for i in found)}"
        )
    return found[0]


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
        name = source if source is not None else os.fspath(path)
        with open_text(path, RecordingError, "a CSV file", name=name, newline="") as stream:
            return _read_csv_stream(stream, left_joint, right_joint, name)
    name = source if source is not None else str(getattr(path, "name", "<stream>"))
    return _read_csv_stream(path, left_joint, right_joint, name)


def _read_csv_stream(
    stream: Iterable[str], left_joint: str, right_joint: str, source: str
) -> Recording:
    samples = ColumnSamples(left_joint, right_joint)
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
                f"columns found: {listing(headers)}"
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
    samples: ColumnSamples,
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
        if stamp_ns is None or not -INT64 <= stamp_ns < INT64:
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
        if beyond_range(left) or beyond_range(right):
            skipped[SKIP_POSITION_RANGE] = skipped.get(SKIP_POSITION_RANGE, 0) + 1
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
        return int(whole) * NS_PER_S + int(frac.ljust(9, "0"))
    try:
        return ns_from_seconds(text)
    except ValueError:
        return None


def _stamp_skip_reason(text: str) -> str:
    """Why a time cell that :func:`_stamp_ns` could not use was skipped."""
    if not text.strip():
        return SKIP_MISSING_STAMP
    try:
        return SKIP_NOT_FINITE if ns_from_seconds(text) is None else SKIP_STAMP_RANGE
    except ValueError:
        return SKIP_UNREADABLE


def format_odometry_csv(rows: Iterable[OdometryRow]) -> str:
    """Poses as CSV text: ``time,x,y,theta,linear,angular`` (s, m, m, rad in (-pi, pi], m/s,
    rad/s); floats printed so that they read back exactly."""
    out = io.StringIO()
    out.write("time,x,y,theta,linear,angular\n")
    write = out.write
    if isinstance(rows, OdometryRows):  # from the columns: no records per row
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
