"""Plans as text, YAML and JSON: parsing them into segments and writing segments back.

Text form: segments separated by ``;`` or newlines, ``#`` comments; lengths in m (or ``cm``,
``mm``), angles in degrees (or ``rad``), durations in s. Files: ``.yaml``/``.yml``/``.json``
lists of mappings such as ``{straight: 1.0, duration: 10}``, or ``.txt`` in text form.
"""

from __future__ import annotations

import difflib
import math
import operator
import os
import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import Any, Literal

from diffbot.errors import PlanError
from diffbot.formats.text import brief
from diffbot.io.textfile import read_text
from diffbot.numbers import MAX_SEGMENTS, finite_in_range
from diffbot.segments import too_many_segments
from diffbot.trajectory import Arc, Segment, Spin, Straight

__all__ = [
    "format_plan",
    "format_segment",
    "load_plan",
    "parse_plan",
    "segments_from_data",
]

# ASCII digits only (float() would also take other scripts' digits and underscores); the unit
# follows at once, in files as in text (where a space would split the token).
_NUMBER = re.compile(r"([+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?)(.*)", re.DOTALL)
_DIVISORS: dict[str, dict[str, float]] = {
    # Dividing by an exact power of ten rounds once, so 25cm is exactly 0.25.
    "length": {"": 1.0, "m": 1.0, "cm": 100.0, "mm": 1000.0},
    "duration": {"": 1.0, "s": 1.0},
}
_ANGLE_UNITS = {"": True, "deg": True, "rad": False}
_ALL_UNITS = {unit for units in _DIVISORS.values() for unit in units if unit} | {"deg", "rad"}
_UNIT_HELP = {"length": "m, cm or mm", "angle": "deg or rad", "duration": "s"}

Dimension = Literal["length", "angle", "duration"]


class _BadValueError(Exception):
    """A value that cannot be read; the caller adds where it was."""


def _quantity(text: str, dimension: Dimension) -> float:
    """An SI value (m, rad or s) from a number with an optional unit (default m, deg, s)."""
    match = _NUMBER.fullmatch(text.strip())
    if match is None:
        if text.strip().lower().lstrip("+-") in ("nan", "inf", "infinity"):
            raise _BadValueError("not a finite number")
        raise _BadValueError("not a number")
    number = float(match.group(1))
    if not math.isfinite(number):
        raise _BadValueError("not a finite number")
    if match.group(2)[:1].isspace():
        raise _BadValueError(
            f"write the unit attached to its number, as in {match.group(1)}{match.group(2).strip()}"
        )
    unit = match.group(2).lower()
    if dimension == "angle":
        if unit not in _ANGLE_UNITS:
            raise _BadValueError(
                f"unknown unit {brief(match.group(2))} for an angle (use deg or rad)"
            )
        value = math.radians(number) if _ANGLE_UNITS[unit] else number
    else:
        divisors = _DIVISORS[dimension]
        if unit not in divisors:
            raise _BadValueError(
                f"unknown unit {brief(match.group(2))} for a {dimension} "
                f"(use {_UNIT_HELP[dimension]})"
            )
        value = number / divisors[unit]
    if not math.isfinite(value):
        raise _BadValueError("not a finite number")
    return value


@dataclass(frozen=True)
class _Token:
    text: str
    line: int
    column: int


# One entry per argument: (role, dimension, rule) where rule is "positive" or "nonzero".
_SIGNATURES: dict[str, tuple[tuple[str, Dimension, str], ...]] = {
    "straight": (("length", "length", "nonzero"),),
    "ccw": (("radius", "length", "positive"), ("angle", "angle", "positive")),
    "cw": (("radius", "length", "positive"), ("angle", "angle", "positive")),
    "spin": (("angle", "angle", "nonzero"),),
}
_USAGE = {
    "reverse": "reverse ccw|cw RADIUS ANGLE [DURATION], or straight -LENGTH",
    "straight": "straight LENGTH [DURATION]",
    "ccw": "ccw RADIUS ANGLE [DURATION]",
    "cw": "cw RADIUS ANGLE [DURATION]",
    "spin": "spin ANGLE [DURATION]",
}


def _segments_of(text: str) -> list[list[_Token]]:
    """Split plan text into segments of tokens, dropping comments and empty segments; refused
    (:func:`~diffbot.segments.too_many_segments`) when more than
    :data:`~diffbot.numbers.MAX_SEGMENTS`, before any is read into tokens."""
    pieces: list[tuple[int, int, str]] = []
    for line_number, line in enumerate(text.splitlines() or [""], start=1):
        code = line.split("#", 1)[0]
        start = 0
        for piece in code.split(";"):
            if piece and not piece.isspace():
                if len(pieces) == MAX_SEGMENTS:
                    raise too_many_segments()
                pieces.append((line_number, start, piece))
            start += len(piece) + 1
    return [
        [_Token(m.group(), line_number, start + m.start() + 1) for m in re.finditer(r"\S+", piece)]
        for line_number, start, piece in pieces
    ]


def _written_nonzero(text: str) -> bool:
    """Whether a number's text has a digit other than 0 before its exponent (``1e-400`` does,
    though it reads as 0)."""
    mantissa = text.lower().partition("e")[0]
    return any(c in "123456789" for c in mantissa)


def _segment_from_tokens(tokens: list[_Token], number: int, multiline: bool) -> Segment:
    def where(token: _Token) -> str:
        if multiline:
            return f"line {token.line}, column {token.column}"
        return f"column {token.column}"

    def error(token: _Token, message: str) -> PlanError:
        return PlanError(f"segment {number}: {message} ({where(token)})")

    head = tokens[0]
    kind = head.text.lower()
    reverse = kind == "reverse"
    if reverse:
        if len(tokens) == 1 or tokens[1].text.lower() not in ("ccw", "cw", "straight"):
            after = tokens[1] if len(tokens) > 1 else head
            found = f"got {brief(after.text)}" if len(tokens) > 1 else "got nothing"
            spin = " (a spin turns in place: turn the other way with a negative angle)"
            hint = spin if after.text.lower() == "spin" else ""
            raise error(after, f"reverse needs an arc or a straight after it, {found}{hint}")
        tokens = tokens[1:]
        head = tokens[0]
        kind = head.text.lower()
    if kind not in _SIGNATURES:
        if kind == "arc":
            hint = " (arcs are written ccw/cw RADIUS ANGLE)"
        else:
            close = difflib.get_close_matches(kind, [*_SIGNATURES, "reverse"], n=1)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
        raise error(
            head,
            f"unknown segment kind {brief(head.text)}: expected straight, ccw, cw, spin or "
            f"reverse{hint}",
        )
    signature = _SIGNATURES[kind]
    args = tokens[1:]
    for token in args:
        if token.text.lower() in _ALL_UNITS:
            raise error(
                token,
                f"{brief(token.text)} is a unit: write it attached to its number, as in 25cm",
            )
    if len(args) < len(signature):
        missing = " and ".join(role.upper() for role, _, _ in signature[len(args) :])
        last = args[-1] if args else head
        raise error(
            last, f"{brief(head.text)} needs {missing} after {brief(last.text)}: {_USAGE[kind]}"
        )
    if len(args) > len(signature) + 1:
        extra = args[len(signature) + 1]
        raise error(extra, f"unexpected {brief(extra.text)}: {_USAGE[kind]}")
    values: list[float] = []
    for token, (role, dimension, rule) in zip(args, signature, strict=False):
        try:
            value = _quantity(token.text, dimension)
        except _BadValueError as err:
            raise error(token, f"{role} {brief(token.text)}: {err}") from None
        if value == 0.0 and _written_nonzero(token.text):
            raise error(token, f"{role} {brief(token.text)} is too small: it rounds to 0")
        if (rule == "positive" or reverse) and value <= 0.0:
            hint = ""
            if kind in ("ccw", "cw") and role == "angle":
                hint = f" (the direction is in the kind: {'cw' if kind == 'ccw' else 'ccw'})"
            elif kind in ("ccw", "cw") and role == "radius" and not reverse:
                hint = f" (to drive the arc backwards write reverse {kind} RADIUS ANGLE)"
            elif reverse:
                hint = " (reverse already drives it backwards)"
            raise error(token, f"{role} {brief(token.text)} must be > 0{hint}")
        if rule == "nonzero" and value == 0.0:
            raise error(token, f"{role} {brief(token.text)} must not be zero")
        values.append(value)
    duration: float | None = None
    if len(args) > len(signature):
        token = args[-1]
        try:
            duration = _quantity(token.text, "duration")
        except _BadValueError as err:
            raise error(token, f"duration {brief(token.text)}: {err}") from None
        if duration == 0.0 and _written_nonzero(token.text):
            raise error(token, f"duration {brief(token.text)} is too small: it rounds to 0")
        if duration <= 0.0:
            raise error(token, f"duration {brief(token.text)} must be > 0")
    if kind == "straight":
        return Straight(-values[0] if reverse else values[0], duration)
    if kind == "spin":
        return Spin(values[0], duration)
    return Arc(values[0], values[1], "ccw" if kind == "ccw" else "cw", duration, reverse)


def parse_plan(text: str) -> list[Segment]:
    """Read a plan written as text.

    Segments are separated by ``;`` or newlines; ``#`` starts a comment. Each is one of
    ``straight LENGTH [DURATION]`` (a negative length drives backwards), ``ccw RADIUS ANGLE
    [DURATION]``, ``cw RADIUS ANGLE [DURATION]`` (``reverse ccw ...`` and ``reverse cw ...``
    drive the arc backwards, the heading still turning the named way), ``spin ANGLE
    [DURATION]`` (positive = counter-clockwise). Lengths are in m
    unless suffixed ``cm``/``mm``/``m``, angles in degrees unless suffixed ``rad``/``deg``,
    durations in s (suffix ``s``).

    Args:
        text: the plan, e.g. ``"ccw 0.25 180 10s; straight 1 10s"``.

    Returns:
        The segments (SI units).

    Raises:
        PlanError: empty plan, more than :data:`~diffbot.numbers.MAX_SEGMENTS` segments,
            unknown kind or unit, missing or extra values, a value that is not
            a finite number, or not positive (not zero, for spins); the message quotes the token
            and gives the segment number and column (and line, when the text has several).
    """
    return _parse_text(text, lines=len(text.splitlines()) > 1)


def _parse_text(text: str, *, lines: bool) -> list[Segment]:
    """:func:`parse_plan`; ``lines``: give line numbers in errors (not only columns)."""
    pieces = _segments_of(text)
    if not pieces:
        raise PlanError("empty plan: no segments (write for example 'straight 1 10s')")
    return [
        _segment_from_tokens(tokens, number, lines) for number, tokens in enumerate(pieces, start=1)
    ]


def _number_text(value: float, digits: int | None = None) -> str:
    if digits is not None:
        text = f"{float(value):.{digits}g}"
        return "0" if text == "-0" else text
    text = repr(float(value))
    return text[:-2] if text.endswith(".0") else text


def _angle_text(angle: float, digits: int | None = None) -> str:
    degrees = math.degrees(angle)
    exact = digits is not None or math.radians(degrees) == angle
    if math.isfinite(degrees) and exact:
        return _number_text(degrees, digits)
    return f"{_number_text(angle, digits)}rad"


#: The most significant digits a float has to give (``repr`` gives at most 17).
MAX_DIGITS = 17


def _checked_digits(digits: object) -> int | None:
    """``digits`` as a whole number of significant digits from 1 to :data:`MAX_DIGITS`."""
    if digits is None:
        return None
    try:
        count = operator.index(digits)  # type: ignore[arg-type]
    except TypeError:
        count = 0
    if isinstance(digits, bool) or not 1 <= count <= MAX_DIGITS:
        raise PlanError(
            f"digits must be a whole number from 1 to {MAX_DIGITS}, got {brief(digits)}"
        )
    return int(count)


def format_segment(segment: Segment, digits: int | None = None) -> str:
    """The text form of one segment; :func:`parse_plan` reads it back exactly, or, with
    ``digits``, to that many significant digits (angles in degrees): for people."""
    digits = _checked_digits(digits)
    if isinstance(segment, Straight):
        words = ["straight", _number_text(segment.length, digits)]
    elif isinstance(segment, Arc):
        words = [
            segment.direction,
            _number_text(segment.radius, digits),
            _angle_text(segment.angle, digits),
        ]
        if segment.reverse:
            words.insert(0, "reverse")
    else:
        words = ["spin", _angle_text(segment.angle, digits)]
    if segment.duration is not None:
        words.append(f"{_number_text(segment.duration, digits)}s")
    return " ".join(words)


def format_plan(segments: Iterable[Segment], digits: int | None = None) -> str:
    """The text form of a plan (one line, ``;``-separated); :func:`parse_plan` reads it back
    exactly: numbers keep every digit, and angles are written in degrees only when that converts
    back to the same radians (otherwise in ``rad``). With ``digits``, numbers are rounded to that
    many significant digits and angles written in degrees: a plan for people to read."""
    digits = _checked_digits(digits)
    return "; ".join(format_segment(segment, digits) for segment in segments)


# --------------------------------------------------------------------------------------------
# Files

_ENTRY_KEYS = {
    "straight": {"straight", "duration"},
    "arc": {"arc", "radius", "angle", "duration", "reverse"},
    "spin": {"spin", "duration"},
}


def _entry_value(value: object, dimension: Dimension, what: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float | str):
        raise _BadValueError(f"{what} {brief(value)}: expected a number or a string such as '25cm'")
    if isinstance(value, str):
        try:
            return _quantity(value, dimension)
        except _BadValueError as err:
            raise _BadValueError(f"{what} {brief(value)}: {err}") from None
    number = finite_in_range(value, what, error=PlanError)
    return math.radians(number) if dimension == "angle" else number


def _segment_from_entry(entry: object) -> Segment:
    if isinstance(entry, str):
        segments = parse_plan(entry)
        if len(segments) != 1:
            raise _BadValueError(f"{brief(entry)} holds {len(segments)} segments, expected one")
        return segments[0]
    if not isinstance(entry, Mapping):
        raise _BadValueError(
            f"expected a mapping such as {{straight: 1.0, duration: 10}}, got {brief(entry)}"
        )
    kinds = [kind for kind in _ENTRY_KEYS if kind in entry]
    if len(kinds) != 1:
        found = "none" if not kinds else " and ".join(kinds)
        raise _BadValueError(
            f"expected exactly one of 'straight', 'arc', 'spin' as a key, got {found}"
        )
    kind = kinds[0]
    unknown = [key for key in entry if key not in _ENTRY_KEYS[kind]]
    if unknown:
        allowed = ", ".join(sorted(_ENTRY_KEYS[kind]))
        raise _BadValueError(f"unknown key {brief(unknown[0])} for a {kind} (allowed: {allowed})")

    def get(key: str, dimension: Dimension, rule: str = "positive") -> float:
        if key not in entry:
            raise _BadValueError(f"a {kind} needs {key!r}")
        value = _entry_value(entry[key], dimension, key)
        if rule == "positive" and value <= 0.0:
            raise _BadValueError(f"{key} {brief(entry[key])} must be > 0")
        if rule == "nonzero" and value == 0.0:
            raise _BadValueError(f"{key} {brief(entry[key])} must not be zero")
        return value

    duration = get("duration", "duration") if entry.get("duration") is not None else None
    if kind == "straight":
        return Straight(get("straight", "length", "nonzero"), duration)
    if kind == "spin":
        return Spin(get("spin", "angle", "nonzero"), duration)
    arc = entry["arc"]
    direction = arc.lower() if isinstance(arc, str) else None  # case as free as in text
    if direction not in ("ccw", "cw"):
        raise _BadValueError(f"arc {brief(arc)}: expected 'ccw' or 'cw'")
    reverse = entry.get("reverse", False)
    if not isinstance(reverse, bool):
        raise _BadValueError(f"reverse {brief(reverse)}: expected true or false")
    return Arc(
        get("radius", "length"),
        get("angle", "angle"),
        "ccw" if direction == "ccw" else "cw",
        duration,
        reverse,
    )


def _looks_structured(text: str) -> bool:
    for line in text.splitlines():
        stripped = line.strip()
        if stripped and not stripped.startswith("#"):
            return stripped[0] in "[{-"
    return False


def segments_from_data(data: object, source: str = "plan") -> list[Segment]:
    """Segments from parsed YAML/JSON: a list of entries, or a mapping with only a ``segments``
    list.

    Entries are mappings such as ``{straight: 1.0, duration: 10}`` (``{straight: -1.0}`` drives
    backwards), ``{arc: ccw, radius: 0.25, angle: 180, duration: 10}`` (``ccw``/``cw`` in any
    case; ``reverse: true`` drives the arc backwards) or ``{spin: 90}`` (numbers in m,
    degrees and s; strings may carry a unit attached to the number: ``"25cm"``, ``"1.5rad"``,
    ``"10s"``), or text segments such as ``"straight 1 10s"``.

    Raises:
        PlanError: naming the source and the entry (counted from 1), quoting at most 60
            characters of it.
    """
    if isinstance(data, Mapping) and "segments" in data:
        others = [key for key in data if key != "segments"]
        if others:
            raise PlanError(
                f"{source}: unknown top-level key {brief(others[0])} (a plan file holds a list "
                "of segments, or a mapping with only 'segments')"
            )
        data = data["segments"]
    if not isinstance(data, list):
        raise PlanError(f"{source}: expected a list of segments, got {type(data).__name__}")
    if not data:
        raise PlanError(f"{source}: empty plan: no segments")
    if len(data) > MAX_SEGMENTS:
        raise PlanError(f"{source}: {too_many_segments()}")
    segments: list[Segment] = []
    for number, entry in enumerate(data, start=1):
        try:
            segments.append(_segment_from_entry(entry))
        except (_BadValueError, PlanError) as err:
            raise PlanError(f"{source}: entry {number}: {err}") from None
    return segments


def load_plan(path: str | os.PathLike[str]) -> list[Segment]:
    """Read a plan file.

    ``.json`` files are JSON, ``.yaml``/``.yml`` files YAML (see :func:`segments_from_data` for
    the entries), ``.txt`` files the text form (see :func:`parse_plan`); other files are read as
    YAML when they start with ``[``, ``{`` or ``-``, else as text. Files are UTF-8 (a byte order
    mark is skipped). Duplicate keys in a mapping are errors, and so are YAML aliases (``*name``):
    a plan never needs them, and nested ones grow exponentially.

    Args:
        path: the file.

    Returns:
        The segments (SI units).

    Raises:
        PlanError: the file cannot be read or parsed, or an entry is bad (the message names it).
    """
    source = os.fspath(path)
    text = read_text(source, PlanError, "a plan file")
    suffix = os.path.splitext(source)[1].lower()
    if suffix == ".json":
        return segments_from_data(_load_json(text, source), source)
    if suffix in (".yaml", ".yml") or (suffix != ".txt" and _looks_structured(text)):
        return segments_from_data(_load_yaml(text, source), source)
    try:
        return _parse_text(text, lines=True)
    except PlanError as err:
        raise PlanError(f"{source}: {err}") from None


#: Deepest nesting of lists and mappings read from a plan file (a plan needs 2): deeper data is
#: refused before it is parsed, as the parsers would recurse once per level.
MAX_NESTING = 32
#: A JSON string; one never closed runs to the end of the text (json refuses it), so that no
#: opening quote is scanned to the end more than once.
_JSON_STRING = re.compile(r'"(?:[^"\\]|\\.)*"?', re.DOTALL)
_BRACKETS = re.compile(r"[\[\]{}]")


def _nesting_error(source: str) -> PlanError:
    return PlanError(f"{source}: lists and mappings nested more than {MAX_NESTING} deep")


def _check_json_nesting(text: str, source: str) -> None:
    depth = 0
    for bracket in _BRACKETS.findall(_JSON_STRING.sub("", text)):
        depth += 1 if bracket in "[{" else -1
        if depth > MAX_NESTING:
            raise _nesting_error(source)


def _load_json(text: str, source: str) -> Any:
    import json

    _check_json_nesting(text, source)

    def reject(constant: str) -> float:
        raise PlanError(f"{source}: {constant} is not a finite number")

    def unique(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
        mapping: dict[str, Any] = {}
        for key, value in pairs:
            if key in mapping:
                raise PlanError(f"{source}: duplicate key {brief(key)} in a JSON object")
            mapping[key] = value
        return mapping

    try:
        return json.loads(text, parse_constant=reject, object_pairs_hook=unique)
    except json.JSONDecodeError as err:
        raise PlanError(
            f"{source}: malformed JSON: {err.msg} (line {err.lineno}, column {err.colno})"
        ) from None
    except ValueError as err:  # a number with more digits than Python reads
        if "digits" in str(err):  # as YAML files say it (diffbot.io.yamlfile)
            raise PlanError(f"{source}: malformed JSON: a number too long to read") from None
        raise PlanError(f"{source}: a value cannot be read: {str(err).split(':')[0]}") from None


def _load_yaml(text: str, source: str) -> Any:
    from diffbot.io.yamlfile import load_yaml

    return load_yaml(text, source, PlanError, "a plan file", unique_keys=True)
