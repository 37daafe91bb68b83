"""Command streams as data for programs: CSV rows and JSON columns, one command per period."""

from __future__ import annotations

import csv
import io
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from diffbot.ramps import CommandStream

__all__ = ["STREAM_COLUMNS", "stream_csv", "stream_json"]

#: The columns of a command stream: time (s), linear.x (m/s), angular.z (rad/s), and the left and
#: right joint velocity commands (rad/s).
STREAM_COLUMNS = ("time", "linear", "angular", "left", "right")


def _columns(stream: CommandStream) -> list[list[float]]:
    return [
        stream.times.tolist(),
        stream.linear.tolist(),
        stream.angular.tolist(),
        stream.left.tolist(),
        stream.right.tolist(),
    ]


def stream_csv(stream: CommandStream) -> str:
    """One CSV row per command; floats printed so that they read back exactly."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(STREAM_COLUMNS)
    for row in zip(*_columns(stream), strict=True):
        writer.writerow(repr(value) for value in row)
    return out.getvalue()


def stream_json(stream: CommandStream, rate: float) -> dict[str, Any]:
    """The commands as JSON-ready columns, with the rate (Hz) they are held at."""
    data: dict[str, Any] = {"rate": rate, "count": int(stream.times.size)}
    data.update(zip(STREAM_COLUMNS, _columns(stream), strict=True))
    return data
