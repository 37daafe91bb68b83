"""Calibrated copies of a robot's configuration: a controllers YAML with new multipliers, a
description with new wheel_radius and wheel_separation defaults.

The files are parsed to find the place to edit, and only the numbers there change: every other
byte (comments, quoting, indentation, other controllers) stays as it was. A controllers YAML is
located through a round-trip YAML parser (``ruamel.yaml``, which keeps each key's line and
column), in the diff-drive controller the calibration used; a description through an XML parser,
which sees ``<xacro:arg>`` and ``<xacro:property>`` elements whatever their attribute order and
never those inside comments. The copy is then read back through diffbot's own loaders and must
give the calibrated values, or nothing is returned.
"""

from __future__ import annotations

import math
import os
import re
import tempfile
from collections.abc import Callable, Iterator, Mapping
from pathlib import Path
from typing import Any, NamedTuple

from diffbot.calibration.checks import WheelGeometry, check_geometry, positive
from diffbot.calibration.results import controller_yaml_lines, xacro_arguments, yaml_number
from diffbot.errors import CalibrationError, DiffbotError
from diffbot.kinematics import DiffDriveParams
from diffbot.numbers import reads_as_number, written_number

__all__ = ["ApplyResult", "apply_to", "calibrated_path"]

#: What a copy's read-back values may differ from the calibration by (relative): the numbers
#: are written with 9 significant digits.
_READ_BACK = 1e-8
#: The multipliers a controllers copy sets, in the order they are written.
_MULTIPLIERS = (
    "wheel_separation_multiplier",
    "left_wheel_radius_multiplier",
    "right_wheel_radius_multiplier",
)
#: The description's names of the calibrated values.
_DESCRIPTION_NAMES = ("wheel_radius", "wheel_separation")

Loader = Callable[[Path], DiffDriveParams]


class ApplyResult(NamedTuple):
    """A calibrated copy of a configuration file.

    Attributes:
        text: the new file's text.
        changed: what changed, one ``name: value`` line each.
        note: something the copy cannot say (unequal radii in a description), or None.
    """

    text: str
    changed: list[str]
    note: str | None


def calibrated_path(path: Path) -> Path:
    """Where the calibrated copy of ``path`` goes: beside it, ``.calibrated`` before its first
    suffix (``robot.urdf.xacro`` -> ``robot.calibrated.urdf.xacro``).

    Raises:
        OutputError: ``path`` has no name to make the copy's from (``.``, ``/``, empty).
    """
    from diffbot.io.outputs import check_output_name

    check_output_name(os.fspath(path), source=True)
    name = path.name
    stem, dot, suffixes = name.partition(".")
    if not stem:  # a hidden file such as .robot.yaml
        stem, dot, suffixes = name, "", ""
    return path.with_name(f"{stem}.calibrated{dot}{suffixes}")


def _close(value: float, wanted: float) -> bool:
    return math.isfinite(value) and abs(value - wanted) <= _READ_BACK * abs(wanted)


# --- controllers YAML -------------------------------------------------------------------------


class _Edit(NamedTuple):
    """Text to put at (line, column) of a file, replacing ``length`` characters there."""

    line: int
    column: int
    length: int
    text: str


def _line_break(text: str) -> str:
    """The file's line break: CRLF when it has any, else LF."""
    return "\r\n" if "\r\n" in text else "\n"


def _edited(text: str, edits: list[_Edit]) -> str:
    lines = text.splitlines(keepends=True)
    for edit in sorted(edits, key=lambda e: (e.line, e.column), reverse=True):
        if edit.line >= len(lines):  # after the last line, which may lack its line break
            if lines and not lines[-1].endswith(("\n", "\r")):
                lines[-1] += _line_break(text)
            lines.append("")
        line = lines[edit.line]
        lines[edit.line] = f"{line[: edit.column]}{edit.text}{line[edit.column + edit.length :]}"
    return "".join(lines)


def _sections(tree: Mapping[Any, Any], path: tuple[str, ...] = ()) -> Iterator[tuple[str, Any]]:
    """Every ROS 2 ``<node>: ros__parameters:`` mapping (the node's base name, the mapping) and
    every ROS 1 diff-drive controller mapping, as :mod:`diffbot.urdf.controllers` finds them."""
    from diffbot.urdf.controllers import DIFF_DRIVE_TYPES, node_base_name

    for key, value in tree.items():
        if not isinstance(value, Mapping):
            continue
        here = (*path, str(key))
        if "ros__parameters" in value:
            yield node_base_name(here), value["ros__parameters"]
        elif isinstance(value.get("type"), str) and value["type"] in DIFF_DRIVE_TYPES:
            yield node_base_name(here), value
        else:
            yield from _sections(value, here)


def _plain_scalar(line: str, column: int) -> int:
    """Length of the plain scalar (a number) starting at ``column`` of ``line``."""
    match = re.compile(r"[^\s,\]}#]+").match(line, column)
    return 0 if match is None else match.end() - column


def _controller_edits(text: str, source: str, name: str, values: dict[str, str]) -> list[_Edit]:
    """Where the multipliers of controller ``name`` go: replaced where its own section sets
    them, else added after its ``wheel_separation`` (or before its first parameter)."""
    from ruamel.yaml import YAML
    from ruamel.yaml.error import YAMLError

    try:
        tree = YAML(typ="rt", pure=True).load(text)
    except (YAMLError, RecursionError, ValueError) as err:
        detail = " ".join(str(err).split())
        raise CalibrationError(f"{source}: cannot edit this YAML: {detail}") from None
    sections = [section for base, section in _sections(tree) if base == name]
    if not sections or not isinstance(sections[-1], Mapping) or not sections[-1]:
        raise CalibrationError(
            f"{source}: the controller {name!r} has no parameters of its own to add the "
            "multipliers to"
        )
    section: Any = sections[-1]  # the last section of a node wins, as the controller reads
    lines = text.splitlines(keepends=True)
    edits: list[_Edit] = []
    new: list[str] = []
    for key, value in values.items():
        if key in section:
            line, column = section.lc.value(key)
            length = _plain_scalar(lines[line], column)
            edits.append(_Edit(line, column, length, value))
        else:
            new.append(f"{key}: {value}")
    if not new:
        return edits
    flow = bool(section.fa.flow_style())
    anchor = "wheel_separation" if "wheel_separation" in section else next(iter(section))
    line, column = section.lc.key(anchor)
    same_line = section.lc.value(anchor)[0] == line
    if flow:
        edits.append(_Edit(line, column, 0, "".join(f"{item}, " for item in new)))
    else:
        indent = " " * column
        end = _line_break(text)
        if anchor == "wheel_separation" and same_line:
            added = "".join(f"{indent}{item}{end}" for item in new)
            edits.append(_Edit(line + 1, 0, 0, added))
        else:
            edits.append(_Edit(line, column, 0, "".join(f"{item}{end}{indent}" for item in new)))
    return edits


def _apply_controllers(
    text: str, source: str, result: WheelGeometry, controller: str | None
) -> ApplyResult:
    from diffbot.urdf.controllers import choose_controller, read_controllers

    configs = read_controllers(text, source)
    if not configs:
        raise CalibrationError(
            f"{source}: 0 diff-drive controllers configured: a calibrated copy needs one"
        )
    names = {config.name for config in configs}
    config = choose_controller(configs, controller if controller in names else None)
    if config.wheel_radius is None or config.wheel_separation is None:
        raise CalibrationError(
            f"{source}: the controller {config.name!r} sets no wheel_radius or no "
            "wheel_separation, which the multipliers scale"
        )
    radius = positive("wheel_radius", config.wheel_radius)
    separation = positive("wheel_separation", config.wheel_separation)
    multipliers = {
        "wheel_separation_multiplier": result.wheel_separation / separation,
        "left_wheel_radius_multiplier": result.left_wheel_radius / radius,
        "right_wheel_radius_multiplier": result.right_wheel_radius / radius,
    }
    values = {key: yaml_number(value) for key, value in multipliers.items()}
    copy = _edited(text, _controller_edits(text, source, config.name, values))
    back = choose_controller(read_controllers(copy, source), config.name)
    wanted = (result.wheel_separation, result.left_wheel_radius, result.right_wheel_radius)
    got = (back.effective_separation, back.left_radius, back.right_radius)
    if not all(g is not None and _close(g, w) for g, w in zip(got, wanted, strict=True)):
        raise CalibrationError(
            f"{source}: the calibrated copy reads back as separation {got[0]} m and radii "
            f"{got[1]}, {got[2]} m, not the calibrated {wanted[0]:.9g}, {wanted[1]:.9g}, "
            f"{wanted[2]:.9g} m: nothing written"
        )
    return ApplyResult(copy, controller_yaml_lines(result, radius, separation), None)


# --- descriptions -----------------------------------------------------------------------------


class _Definition(NamedTuple):
    """An element that defines a value: its kind, the attribute holding it, where it starts."""

    kind: str
    attribute: str
    start: int


def _definitions(data: bytes, source: str) -> dict[str, list[_Definition]]:
    """The ``<xacro:arg name=N default=...>`` and ``<xacro:property name=N value=NUMBER>`` of
    each calibrated name N (a property with an expression derives its value, it does not
    define it)."""
    from xml.parsers import expat

    found: dict[str, list[_Definition]] = {name: [] for name in _DESCRIPTION_NAMES}
    parser = expat.ParserCreate()

    def start(tag: str, attributes: dict[str, str]) -> None:
        name = attributes.get("name")
        if name not in found:
            return
        if tag == "xacro:arg" and "default" in attributes:
            found[name].append(_Definition("xacro:arg", "default", parser.CurrentByteIndex))
        elif tag == "xacro:property" and _finite(attributes.get("value", "")):
            found[name].append(_Definition("xacro:property", "value", parser.CurrentByteIndex))

    def refuse_entities(*_: object) -> None:
        raise CalibrationError(f"{source}: entity declarations are not accepted")

    parser.StartElementHandler = start
    parser.EntityDeclHandler = refuse_entities
    try:
        parser.Parse(data, True)
    except expat.ExpatError as err:
        raise CalibrationError(f"{source}: malformed XML: {err}") from None
    return found


def _finite(text: str) -> bool:
    """Whether ``text`` reads as a finite number."""
    return reads_as_number(text) and math.isfinite(written_number(text))


def _set_attribute(data: bytes, definition: _Definition, value: str, source: str) -> bytes:
    """``data`` with the attribute of the element starting at ``definition.start`` set."""
    tag = re.compile(rb"<[^\"'>]*(?:(?:\"[^\"]*\"|'[^']*')[^\"'>]*)*>").match(
        data, definition.start
    )
    attribute = re.compile(rb"(\s" + definition.attribute.encode() + rb"\s*=\s*)([\"'])[^\"']*\2")
    match = None if tag is None else attribute.search(data, tag.start(), tag.end())
    if match is None:  # expat saw the attribute: this cannot happen in well-formed XML
        raise CalibrationError(f"{source}: cannot find the {definition.attribute} to edit")
    quote = match.group(2)
    return (
        data[: match.start()]
        + match.group(1)
        + quote
        + value.encode()
        + quote
        + data[match.end() :]
    )


def _read_back_description(path: Path, data: bytes, wanted: dict[str, float], load: Loader) -> None:
    """Load the copy (a temporary file beside ``path``, so that its includes resolve) and
    check that it gives the calibrated radius and separation."""
    suffixes = "".join(path.suffixes[-2:]) or ".urdf"
    fd, name = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=suffixes)
    try:
        with os.fdopen(fd, "wb") as out:
            out.write(data)
        try:
            params = load(Path(name))
        except DiffbotError as err:
            detail = str(err).replace(name, str(calibrated_path(path)))
            raise CalibrationError(
                f"{path}: the calibrated copy does not load: {detail}: nothing written"
            ) from None
    finally:
        Path(name).unlink(missing_ok=True)
    for key, value in wanted.items():
        got = float(getattr(params, key))
        if not _close(got, value):
            origin = params.sources.get(key, "description") if params.sources else "description"
            raise CalibrationError(
                f"{path}: the calibrated copy gives {key} {got:.9g} m (from {origin}), not the "
                f"calibrated {value:.9g} m: nothing written"
            )


def _apply_description(path: Path, data: bytes, result: WheelGeometry, load: Loader) -> ApplyResult:
    source = str(path)
    arguments = xacro_arguments(result)  # both: the definitions are checked below
    values = dict(item.split(":=") for item in (arguments.arguments or "").split())
    found = _definitions(data, source)
    changed: list[str] = []
    for name in _DESCRIPTION_NAMES:
        definitions = found[name]
        if len(definitions) != 1:
            count = "no" if not definitions else str(len(definitions))
            raise CalibrationError(
                f'{source}: {count} <xacro:arg name="{name}" default=...> or <xacro:property '
                f'name="{name}" value=NUMBER> found: a calibrated copy needs exactly one'
            )
        changed.append(f"{name}: {values[name]}")
    # From the end of the file backwards, so each edit leaves the earlier offsets valid.
    for name in sorted(_DESCRIPTION_NAMES, key=lambda n: found[n][0].start, reverse=True):
        data = _set_attribute(data, found[name][0], values[name], source)
    wanted = {name: float(values[name]) for name in _DESCRIPTION_NAMES}
    _read_back_description(path, data, wanted, load)
    return ApplyResult(data.decode("utf-8"), changed, arguments.note)


def _load(path: Path) -> DiffDriveParams:
    from diffbot.urdf import load_params

    return load_params(path)


def apply_to(
    path: str | os.PathLike[str],
    result: WheelGeometry,
    *,
    controller: str | None = None,
    load: Loader | None = None,
) -> ApplyResult:
    """A calibrated copy of a configuration file's text, read back before it is returned.

    A controllers YAML (``.yaml``, ``.yml``) gets the three multipliers in the diff-drive
    controller ``controller`` (the only one when the file has one; a name the file does not
    have counts as none), replaced where its section sets them, else added after its
    ``wheel_separation``. A description (``.xacro``, ``.urdf``) gets new values in the
    ``<xacro:arg>`` (its ``default``) or ``<xacro:property>`` (its ``value``) that defines
    ``wheel_radius`` and ``wheel_separation`` (the mean radius: a note says so when the radii
    differ). Nothing else in the file changes. The file itself is only read; a description is
    read back from a temporary file beside it.

    Args:
        path: the file.
        result: the calibration (:class:`UmbmarkResult`, :class:`FitResult`).
        controller: the diff-drive controller the calibration used.
        load: how to load a description for the read-back (default :func:`load_params` with
            no options).

    Raises:
        CalibrationError: a result no robot can have (radii or separation not finite or
            outside the sizes a robot may have), a file that cannot take the calibration (no
            or several diff-drive controllers and no name, no radius or separation to scale,
            no or several definitions of the xacro values), or a copy that does not read back
            as the calibration.
        DiffbotError: the file cannot be read.
    """
    from diffbot.io.textfile import open_text

    check_geometry(result, "the calibration gives")
    p = Path(path)
    suffix = p.suffix.lower()
    kinds = {".yaml": "a YAML file", ".yml": "a YAML file"}
    kinds.update({".xacro": "a robot description", ".urdf": "a robot description"})
    if suffix in kinds:
        # Line breaks as they are (CRLF stays CRLF), and a leading BOM kept: the copy differs
        # only where it is edited.
        with open_text(p, CalibrationError, kinds[suffix], newline="", keep_bom=True) as stream:
            text = stream.read()
        bom = "\ufeff" if text.startswith("\ufeff") else ""
        text = text[len(bom) :]
        if suffix in (".yaml", ".yml"):
            applied = _apply_controllers(text, str(p), result, controller)
        else:
            applied = _apply_description(p, text.encode("utf-8"), result, load or _load)
        return applied._replace(text=bom + applied.text)
    raise CalibrationError(
        f"{p}: a calibration applies to a controllers YAML (.yaml, .yml) or a description "
        "(.urdf, .xacro)"
    )
