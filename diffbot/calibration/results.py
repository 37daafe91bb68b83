"""Calibration results in the forms a robot's configuration takes: ``params``-style numbers,
diff_drive_controller multiplier lines, xacro arguments, and calibrated copies of a controllers
YAML or a description (written beside the original, never over it)."""

from __future__ import annotations

import os
import re
from pathlib import Path
from typing import NamedTuple, Protocol

from diffbot.calibration.checks import positive
from diffbot.errors import CalibrationError
from diffbot.kinematics import DiffDriveParams

__all__ = [
    "ApplyResult",
    "WheelGeometry",
    "XacroArguments",
    "apply_to",
    "calibrated_path",
    "controller_yaml_lines",
    "multiplier_base",
    "params_json",
    "xacro_arguments",
]

#: Keys of the ``params`` JSON of a calibration (UMBmark adds ``ed`` and ``eb``).
_EXTRA_KEYS = ("ed", "eb")


class WheelGeometry(Protocol):
    """What the text builders need: calibrated wheel radii and separation (m)."""

    @property
    def left_wheel_radius(self) -> float: ...
    @property
    def right_wheel_radius(self) -> float: ...
    @property
    def wheel_separation(self) -> float: ...


def _number(value: float) -> str:
    return f"{value:.9g}"


def controller_yaml_lines(
    result: WheelGeometry, nominal_radius: float, nominal_separation: float
) -> list[str]:
    """diff_drive_controller parameters that apply a calibration to a nominal configuration.

    ros2_controllers' diff_drive_controller multiplies its ``wheel_radius`` by
    ``left_wheel_radius_multiplier`` and ``right_wheel_radius_multiplier``, and its
    ``wheel_separation`` by ``wheel_separation_multiplier``.

    Args:
        result: a calibration (:class:`UmbmarkResult`, :class:`FitResult`).
        nominal_radius: the controller's ``wheel_radius`` (m).
        nominal_separation: the controller's ``wheel_separation`` (m).

    Returns:
        Three ``name: value`` lines (9 significant digits), to go under ``ros__parameters``.

    Raises:
        ParameterError: a nominal value that is not a positive finite number.
    """
    radius = positive("nominal_radius", nominal_radius)
    separation = positive("nominal_separation", nominal_separation)
    return [
        f"wheel_separation_multiplier: {_number(result.wheel_separation / separation)}",
        f"left_wheel_radius_multiplier: {_number(result.left_wheel_radius / radius)}",
        f"right_wheel_radius_multiplier: {_number(result.right_wheel_radius / radius)}",
    ]


def multiplier_base(params: DiffDriveParams) -> tuple[float, float]:
    """The radius and separation (m) a robot's diff_drive_controller multipliers scale: its
    controller's ``wheel_radius`` and ``wheel_separation`` when it was loaded with one that sets
    both, else the robot's ``wheel_radius`` and ``wheel_separation``."""
    config = params.controller
    radius = None if config is None else config.wheel_radius
    separation = None if config is None else config.wheel_separation
    if radius is None or separation is None:
        return params.wheel_radius, params.wheel_separation
    return radius, separation


class XacroArguments(NamedTuple):
    """xacro arguments of a calibration.

    Attributes:
        arguments: ``wheel_radius:=... wheel_separation:=...`` (m).
        note: why one radius cannot say it all, when the two radii differ; else None.
    """

    arguments: str
    note: str | None


def xacro_arguments(result: WheelGeometry, *, tolerance: float = 1e-6) -> XacroArguments:
    """The description's arguments (one radius for both wheels) for a calibration.

    Args:
        result: a calibration (:class:`UmbmarkResult`, :class:`FitResult`).
        tolerance: relative difference of the radii below which they count as equal.

    Returns:
        The arguments with the mean radius, and a note when the radii differ by more than
        ``tolerance``.
    """
    left = result.left_wheel_radius
    right = result.right_wheel_radius
    mean = 0.5 * (left + right)
    arguments = (
        f"wheel_radius:={_number(mean)} wheel_separation:={_number(result.wheel_separation)}"
    )
    note = None
    if abs(right - left) > tolerance * mean:
        note = (
            f"the radii differ (left {_number(left)} m, right {_number(right)} m, "
            f"{100.0 * (right - left) / mean:+.3g} %): wheel_radius is their mean; apply the "
            "difference with the controller's left and right radius multipliers"
        )
    return XacroArguments(arguments, note)


def params_json(result: WheelGeometry) -> dict[str, float]:
    """A calibration as JSON-ready numbers.

    Returns:
        ``left_wheel_radius``, ``right_wheel_radius``, ``wheel_separation`` (m), and for UMBmark
        also ``ed`` and ``eb`` (ratios).
    """
    data = {
        "left_wheel_radius": result.left_wheel_radius,
        "right_wheel_radius": result.right_wheel_radius,
        "wheel_separation": result.wheel_separation,
    }
    for key in _EXTRA_KEYS:
        value = getattr(result, key, None)
        if isinstance(value, float):
            data[key] = value
    return data


def calibrated_path(path: Path) -> Path:
    """Where the calibrated copy of ``path`` goes: beside it, ``.calibrated`` before its first
    suffix (``robot.urdf.xacro`` -> ``robot.calibrated.urdf.xacro``)."""
    name = path.name
    stem, dot, suffixes = name.partition(".")
    if not stem:  # a hidden file such as .robot.yaml
        stem, dot, suffixes = name, "", ""
    return path.with_name(f"{stem}.calibrated{dot}{suffixes}")


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


def _set_key(text: str, key: str, value: str, after: str, source: str) -> str:
    """YAML text with ``key: value``: replacing the key's value where it is, else as a new line
    after the line of ``after`` (with its indentation)."""
    pattern = re.compile(rf"^(?P<indent>[ \t]*){re.escape(key)}[ \t]*:[^\n#]*", re.MULTILINE)
    found = pattern.findall(text)
    if len(found) > 1:
        raise CalibrationError(f"{source}: {key} is set {len(found)} times: cannot tell which")
    if found:
        return pattern.sub(lambda m: f"{m.group('indent')}{key}: {value}", text, count=1)
    anchor = re.compile(rf"^(?P<indent>[ \t]*){re.escape(after)}[ \t]*:.*$", re.MULTILINE)
    match = anchor.search(text)
    if match is None:
        raise CalibrationError(f"{source}: no {after} line to add {key} beside")
    end = match.end()
    return f"{text[:end]}\n{match.group('indent')}{key}: {value}{text[end:]}"


def _apply_controllers(text: str, source: str, result: WheelGeometry) -> ApplyResult:
    from diffbot.urdf.controllers import read_controllers

    configs = read_controllers(text, source)
    if len(configs) != 1:
        raise CalibrationError(
            f"{source}: {len(configs)} diff-drive controllers configured: a calibrated copy "
            "needs exactly one"
        )
    config = configs[0]
    if config.wheel_radius is None or config.wheel_separation is None:
        raise CalibrationError(
            f"{source}: the controller {config.name!r} sets no wheel_radius or no "
            "wheel_separation, which the multipliers scale"
        )
    lines = controller_yaml_lines(result, config.wheel_radius, config.wheel_separation)
    for line in reversed(lines):  # each new line goes right after wheel_separation
        key, _, value = line.partition(": ")
        text = _set_key(text, key, value, "wheel_separation", source)
    return ApplyResult(text, lines, None)


def _apply_description(text: str, source: str, result: WheelGeometry) -> ApplyResult:
    arguments = xacro_arguments(result)
    changed: list[str] = []
    for assignment in arguments.arguments.split():
        name, _, value = assignment.partition(":=")
        pattern = re.compile(
            rf"(<xacro:arg\s+name\s*=\s*[\"']{name}[\"']\s+default\s*=\s*)([\"'])[^\"']*\2"
        )
        text, count = pattern.subn(rf"\g<1>\g<2>{value}\g<2>", text)
        if count != 1:
            raise CalibrationError(
                f'{source}: {"no" if count == 0 else count} <xacro:arg name="{name}" '
                "default=...> found: a calibrated copy needs exactly one"
            )
        changed.append(f"{name}: {value}")
    return ApplyResult(text, changed, arguments.note)


def apply_to(path: str | os.PathLike[str], result: WheelGeometry) -> ApplyResult:
    """A calibrated copy of a configuration file's text (the file itself is only read).

    A controllers YAML (``.yaml``, ``.yml``) with one diff-drive controller gets the three
    multipliers (replaced where it sets them, else added after its ``wheel_separation``); a
    description (``.xacro``, ``.urdf``) gets the defaults of its ``wheel_radius`` and
    ``wheel_separation`` xacro arguments (the mean radius: a note says so when the radii differ).

    Raises:
        CalibrationError: a file that cannot take the calibration (no or several diff-drive
            controllers, no radius or separation to scale, no such xacro arguments).
        DiffbotError: the file cannot be read.
    """
    from diffbot.io.textfile import read_text

    p = Path(path)
    suffix = p.suffix.lower()
    if suffix in (".yaml", ".yml"):
        return _apply_controllers(read_text(p, CalibrationError, "a YAML file"), str(p), result)
    if suffix in (".xacro", ".urdf"):
        text = read_text(p, CalibrationError, "a robot description")
        return _apply_description(text, str(p), result)
    raise CalibrationError(
        f"{p}: a calibration applies to a controllers YAML (.yaml, .yml) or a description "
        "(.urdf, .xacro)"
    )
