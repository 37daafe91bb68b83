"""Goal poses and waypoints as people write them: ``X,Y[,HEADING]`` text and waypoint files.

Positions are in metres, headings in degrees unless written with ``rad`` (``1.57rad``) or
``deg``. A waypoint file is CSV (rows ``x,y[,heading]``, an optional header row naming the
columns, ``#`` comments) or a YAML or JSON list whose items are ``[x, y]``, ``[x, y, heading]``
or mappings ``{x: .., y: .., heading: ..}``.
"""

from __future__ import annotations

import math
import os
import re
from typing import Any

from diffbot.errors import PlanError
from diffbot.formats.text import brief
from diffbot.io.textfile import read_text
from diffbot.numbers import MAX_COORDINATE, MAX_TURN, as_number, finite_in_range

__all__ = ["parse_pose", "read_waypoints"]

Waypoint = tuple[float, float, float | None]

#: A number and its unit, the text stripped first. Unambiguous (one way to match any text), so
#: its time is linear in the text's length; ASCII digits only, as every number is written.
_NUMBER = re.compile(r"([+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?)\s*(m|rad|deg)?", re.ASCII)
_HEADER = ("x", "y", "heading")


#: The largest magnitude of each kind of number, and its unit: (angle, unit) -> (limit, shown).
_LIMITS = {
    (False, None): (MAX_COORDINATE, "m"),
    (False, "m"): (MAX_COORDINATE, "m"),
    (True, "rad"): (MAX_TURN, "rad"),
    (True, None): (math.degrees(MAX_TURN), "deg"),
    (True, "deg"): (math.degrees(MAX_TURN), "deg"),
}


def _value(text: object, angle: bool, what: str, name: str) -> float:
    """One number: metres, or for an angle degrees (``rad`` for radians), SI out.

    Coordinates lie within :data:`~diffbot.numbers.MAX_COORDINATE` (m) of the origin and headings
    within :data:`~diffbot.numbers.MAX_TURN` (rad) of zero; an integer of any size is refused as
    too large, never overflows.
    """
    if isinstance(text, bool) or not isinstance(text, int | float | str):
        raise PlanError(f"{what}: {brief(text)} is not a number")
    unit = None
    if isinstance(text, str):
        match = _NUMBER.fullmatch(text.strip())
        if match is None:
            if text.strip().lower().lstrip("+-") in ("nan", "inf", "infinity"):
                raise PlanError(f"{what}: {brief(text)} is not a finite number")
            raise PlanError(f"{what}: {brief(text)} is not a number")
        value, unit = float(match.group(1)), match.group(2)  # digits: never an error
        if unit is not None and (unit == "m") == angle:
            raise PlanError(f"{what}: {brief(text)} has the wrong unit")
    else:
        value = as_number(text, f"{what}: {name}", PlanError, "a finite number")
    if not math.isfinite(value):
        raise PlanError(f"{what}: {brief(text)} is not a finite number")
    limit, shown_unit = _LIMITS[angle, unit]
    if not -limit <= value <= limit:
        # raises, naming the range
        finite_in_range(value, f"{what}: {name}", -limit, limit, error=PlanError, unit=shown_unit)
    return math.radians(value) if angle and unit != "rad" else value


def _waypoint(items: list[Any], what: str) -> Waypoint:
    if len(items) not in (2, 3):
        raise PlanError(f"{what}: give x,y or x,y,heading, got {len(items)} values")
    x = _value(items[0], False, what, "x")
    y = _value(items[1], False, what, "y")
    empty = (
        len(items) == 2 or items[2] is None or (isinstance(items[2], str) and not items[2].strip())
    )
    return x, y, None if empty else _value(items[2], True, what, "heading")


def parse_pose(text: str, what: str) -> Waypoint:
    """``X,Y[,HEADING]`` (m, m, degrees or ``...rad``) as x, y (m) and heading (rad) or None.

    Raises:
        PlanError: not two or three numbers, or one that is not finite; the message starts with
            ``what``.
    """
    return _waypoint(text.split(","), what)


def read_waypoints(path: str | os.PathLike[str]) -> list[Waypoint]:
    """The waypoints of a CSV, YAML or JSON file (see the module's description).

    Raises:
        PlanError: the file cannot be read or parsed, has no waypoint, or a row or item is
            malformed (the message names it: ``row 3``, ``item 2``).
    """
    source = os.fspath(path)
    text = read_text(source, PlanError, "a waypoints file")
    suffix = os.path.splitext(source)[1].lower()
    if suffix in (".yaml", ".yml", ".json"):
        from diffbot.planfile import _load_json, _load_yaml

        data = _load_json(text, source) if suffix == ".json" else _load_yaml(text, source)
        if data is None:
            data = []
        if not isinstance(data, list):
            raise PlanError(f"{source}: a waypoints file is a list, got {brief(data)}")
        points = [_item(item, f"{source}: item {i + 1}") for i, item in enumerate(data)]
    else:
        points = []
        for number, line in enumerate(text.splitlines(), start=1):
            row = line.split("#", 1)[0].strip()
            if not row:
                continue
            cells = [cell.strip() for cell in row.split(",")]
            if not points and tuple(c.lower() for c in cells) in (_HEADER[:2], _HEADER):
                continue
            points.append(_waypoint(cells, f"{source}: row {number}"))
    if not points:
        raise PlanError(f"{source}: no waypoints (give rows x,y[,heading])")
    return points


def _item(item: object, what: str) -> Waypoint:
    if isinstance(item, dict):
        unknown = set(item) - set(_HEADER)
        if unknown or not {"x", "y"} <= set(item):
            raise PlanError(f"{what}: give x, y and an optional heading, got {brief(item)}")
        return _waypoint([item["x"], item["y"], item.get("heading")], what)
    if isinstance(item, list):
        return _waypoint(item, what)
    raise PlanError(f"{what}: give [x, y], [x, y, heading] or a mapping, got {brief(item)}")
