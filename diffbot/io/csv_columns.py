"""Which columns of a recording CSV's header hold the time and each wheel: found by name, and
refused when two columns could be the one meant (a silent choice would read the wrong one)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Final

from diffbot.errors import RecordingError
from diffbot.formats.text import listing
from diffbot.io.csv_layout import names_joint

__all__ = ["TIME_COLUMNS", "joint_columns", "named_columns", "preferred_time_column", "time_column"]

#: Names a time column may have (seconds), case-insensitive, in order of preference.
TIME_COLUMNS: Final = ("time", "stamp", "t", "__time")


def time_column(headers: Sequence[str], source: str, given: str | None = None) -> int | None:
    """The index of the time column: the one named ``given`` (see :func:`named_columns`), else
    the one column named as :data:`TIME_COLUMNS` are; None when no column is.

    Raises:
        RecordingError: several columns that may be the time (``t`` and ``time``, or one name
            twice), or a ``given`` name no column or several columns have.
    """
    if given is not None:
        ((_, index),) = named_columns(headers, [given], "{time_column}", source)
        return index
    candidates = [i for i, name in enumerate(headers) if name.lower() in TIME_COLUMNS]
    twice = next((headers[i] for i in candidates if headers.count(headers[i]) > 1), None)
    if twice is not None:
        raise RecordingError(
            f"{source}: {headers.count(twice)} columns are named {twice!r}, each may be the "
            "time: rename all but the one to read"
        )
    if len(candidates) > 1:
        raise RecordingError(
            f"{source}: several columns may be the time "
            f"({listing(headers[i] for i in candidates)}): name the one to read ({{time_column}})"
        )
    return candidates[0] if candidates else None


def preferred_time_column(headers: Sequence[str]) -> int | None:
    """The index of the first column named as the first of :data:`TIME_COLUMNS` that any column
    is (any case), or None: the time of a ground-truth track, which has no option to name
    it."""
    lowered = [h.lower() for h in headers]
    return next((lowered.index(name) for name in TIME_COLUMNS if name in lowered), None)


def named_columns(
    headers: Sequence[str], names: Sequence[str], option: str, source: str
) -> list[tuple[str, int]]:
    """The columns named exactly (or else, ignoring case, uniquely) as (name, index).

    Raises:
        RecordingError: a name that no column has, or that several columns have (the message
            names ``option``, the place the name was given).
    """
    found = []
    lowered = [h.lower() for h in headers]
    for name in names:
        if headers.count(name) > 1:
            raise RecordingError(
                f"{source}: {headers.count(name)} columns are named {name!r} ({option}): "
                "rename all but the one to read"
            )
        if name in headers:
            found.append((name, headers.index(name)))
        elif lowered.count(name.lower()) == 1:
            found.append((name, lowered.index(name.lower())))
        elif lowered.count(name.lower()) > 1:
            raise RecordingError(
                f"{source}: several columns are named {name!r} but for case "
                f"({listing(h for h in headers if h.lower() == name.lower())}; {option}): "
                "give one's exact name"
            )
        else:
            raise RecordingError(
                f"{source}: no column {name!r} ({option}); columns found: {listing(headers)}"
            )
    return found


def joint_columns(
    headers: Sequence[str], joints: Sequence[str], side: str, source: str, field: str = "position"
) -> list[tuple[str, int]]:
    """The columns of a side's joints that the file has, as (joint, index); at least one."""
    found: list[tuple[str, int]] = []
    for joint in joints:
        matches = [i for i, h in enumerate(headers) if names_joint(h, joint, field)]
        if len(matches) > 1:
            raise RecordingError(
                f"{source}: several columns for the {side} wheel joint {joint!r}: "
                f"{listing(headers[i] for i in matches)}"
            )
        found.extend((joint, i) for i in matches)
    if not found:
        names = " or ".join(repr(j) for j in joints)
        positions = field == "velocity" and any(
            names_joint(h, joint) for h in headers for joint in joints
        )
        raise RecordingError(
            f"{source}: no column for the {side} wheel joint {names} ("
            + ("named by the joint or " if field == "position" else "")
            + f"ending with '/<joint>/{field}'); columns found: {listing(headers)}"
            + (
                "; the file holds the wheels' positions: read them with {feedback} position"
                if positions
                else "; another robot's recording? give its description ({robot}), or name "
                "the columns ({left_column}, {right_column})"
            )
        )
    return found
