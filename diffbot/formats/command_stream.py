"""Command streams as data for programs: CSV rows and JSON columns, one command per period."""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Callable, Iterable
from typing import TYPE_CHECKING, Any, TextIO

from diffbot.errors import PlanError

if TYPE_CHECKING:
    from diffbot.ramps import CommandStream

__all__ = [
    "STREAM_COLUMNS",
    "stream_csv",
    "stream_json",
    "write_stream_csv",
    "write_stream_json",
]

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


def write_stream_csv(chunks: Iterable[CommandStream], out: TextIO) -> None:
    """:func:`stream_csv` written piece by piece as the commands come, in constant memory."""
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(STREAM_COLUMNS)
    for chunk in chunks:
        writer.writerows(
            [repr(value) for value in row] for row in zip(*_columns(chunk), strict=True)
        )


_FIELDS = ("times", "linear", "angular", "left", "right")
#: Stands for the commands in a JSON document until they are written column by column.
_PLACEHOLDER = "\x00commands\x00"


def write_stream_json(
    document: dict[str, Any],
    chunks: Callable[[], Iterable[CommandStream]],
    rate: float,
    count: int,
    out: TextIO,
) -> None:
    """A JSON document (indented by 2, as ``json.dumps(..., indent=2)`` writes it) whose
    ``"commands"`` value is :func:`stream_json` of the commands, written as they come.

    The columns are written one after another, so the commands are made once per column
    (``chunks`` is called five times); memory stays constant however many there are.

    Args:
        document: the JSON data; its ``"commands"`` key is replaced (and added last if absent).
        chunks: makes the commands, in pieces (:meth:`diffbot.ramps.RampedPlan.command_chunks`).
        rate: the command rate (Hz).
        count: how many commands ``chunks`` makes.
        out: where to write; a newline ends the document.

    Raises:
        PlanError: a command is not a finite number.
    """
    import json

    head, tail = json.dumps(
        {**document, "commands": _PLACEHOLDER}, indent=2, allow_nan=False
    ).split(json.dumps(_PLACEHOLDER))
    out.write(head)
    out.write(f'{{\n    "rate": {json.dumps(rate, allow_nan=False)},\n    "count": {count}')
    for index, name in enumerate(STREAM_COLUMNS):
        out.write(f',\n    "{name}": [')
        separator = "\n      "
        for chunk in chunks():
            values: list[float] = getattr(chunk, _FIELDS[index]).tolist()
            if not all(map(math.isfinite, values)):
                raise PlanError(f"a command's {name} is not a finite number")
            out.write(separator + ",\n      ".join(map(repr, values)))
            separator = ",\n      "
        out.write("\n    ]")
    out.write("\n  }")
    out.write(tail + "\n")
