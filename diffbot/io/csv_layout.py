"""How to read a recording CSV written by another tool: which columns, delimiter and time unit."""

from __future__ import annotations

from dataclasses import dataclass

from diffbot.errors import RecordingError
from diffbot.io.csv_stamps import TIME_UNITS

__all__ = ["CsvLayout", "names_joint"]


@dataclass(frozen=True)
class CsvLayout:
    """How to read a CSV written by another tool: which columns, which delimiter, which unit.

    Attributes:
        time_column: the time column's name (default: the first of :data:`TIME_COLUMNS`).
        left_columns: the left wheels' position columns (default: named by the joints).
        right_columns: the right wheels' position columns.
        delimiter: the delimiter (default: a comma, or the one the header is split by: ``;``,
            a tab or ``|``).
        time_unit: ``s``, ``ms``, ``us`` or ``ns`` (default: seconds, unless the first stamp is
            too large for seconds since 1970: its magnitude says which).
        field: ``position`` or ``velocity``: the JointState field whose columns are found by
            the joints' names (``/<joint>/velocity``; a column named by the joint alone is a
            position).
        counts_per_rev: encoder counts per revolution when the wheel columns hold counts
            (counts/s): a row is skipped when a wheel's value, converted to radians (rad/s), is
            beyond :func:`~diffbot.samples.wheel_limit`; None when they hold radians.
    """

    time_column: str | None = None
    left_columns: tuple[str, ...] | None = None
    right_columns: tuple[str, ...] | None = None
    delimiter: str | None = None
    time_unit: str | None = None
    field: str = "position"
    counts_per_rev: float | None = None

    def __post_init__(self) -> None:
        if self.delimiter is not None and len(self.delimiter) != 1:
            raise RecordingError(
                f"the delimiter must be one character, got {self.delimiter!r} ({{delimiter}})"
            )
        if self.time_unit is not None and self.time_unit not in TIME_UNITS:
            raise RecordingError(
                f"unknown time unit {self.time_unit!r}: give one of {', '.join(TIME_UNITS)} "
                "({time_unit})"
            )


def names_joint(header: str, joint: str, field: str = "position") -> bool:
    """Whether a CSV column named ``header`` holds ``field`` (``position`` or ``velocity``) of
    ``joint``: ``.../<joint>/<field>``, as bag export tools name a JointState's fields, or the
    joint's name alone for its position."""
    return header.endswith(f"/{joint}/{field}") or (field == "position" and header == joint)
