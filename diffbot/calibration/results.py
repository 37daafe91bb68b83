"""Calibration results in the forms a robot's configuration takes: ``params``-style numbers,
diff_drive_controller multiplier lines and xacro arguments (the calibrated copies of files are
:mod:`diffbot.calibration.apply`'s)."""

from __future__ import annotations

from collections.abc import Collection
from typing import NamedTuple

from diffbot.calibration.checks import WheelGeometry, positive
from diffbot.kinematics import DiffDriveParams

__all__ = [
    "WheelGeometry",
    "XacroArguments",
    "controller_yaml_lines",
    "multiplier_base",
    "params_json",
    "xacro_arguments",
    "yaml_number",
]

#: Keys of the ``params`` JSON of a calibration (UMBmark adds ``ed`` and ``eb``).
_EXTRA_KEYS = ("ed", "eb")


def _number(value: float) -> str:
    return f"{value:.9g}"


def yaml_number(value: float) -> str:
    """A float as YAML for a ROS 2 double parameter: 9 significant digits, always with a
    decimal point or an exponent (ROS 2 refuses ``1`` for a double parameter)."""
    text = _number(value)
    return text if any(c in text for c in ".en") else f"{text}.0"


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
        Three ``name: value`` lines (:func:`yaml_number`), to go under ``ros__parameters``.

    Raises:
        ParameterError: a nominal value that is not a positive finite number.
    """
    radius = positive("nominal_radius", nominal_radius)
    separation = positive("nominal_separation", nominal_separation)
    return [
        f"wheel_separation_multiplier: {yaml_number(result.wheel_separation / separation)}",
        f"left_wheel_radius_multiplier: {yaml_number(result.left_wheel_radius / radius)}",
        f"right_wheel_radius_multiplier: {yaml_number(result.right_wheel_radius / radius)}",
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
        arguments: ``wheel_radius:=... wheel_separation:=...`` (m), those of the two the
            description declares; None when it declares neither.
        note: why one radius cannot say it all, when the two radii differ; else None.
    """

    arguments: str | None
    note: str | None


def xacro_arguments(
    result: WheelGeometry,
    *,
    tolerance: float = 1e-6,
    declared: Collection[str] | None = None,
) -> XacroArguments:
    """The description's arguments (one radius for both wheels) for a calibration.

    Args:
        result: a calibration (:class:`UmbmarkResult`, :class:`FitResult`).
        tolerance: relative difference of the radii below which they count as equal.
        declared: the xacro arguments the description declares
            (:attr:`~diffbot.kinematics.DiffDriveParams.xacro_arguments`): only those of
            ``wheel_radius`` and ``wheel_separation`` it declares are given (an argument it does
            not declare would be ignored); None: both.

    Returns:
        The arguments with the mean radius, and a note when the radii differ by more than
        ``tolerance``.
    """
    left = result.left_wheel_radius
    right = result.right_wheel_radius
    mean = 0.5 * (left + right)
    values = {"wheel_radius": mean, "wheel_separation": result.wheel_separation}
    given = [
        f"{name}:={_number(value)}"
        for name, value in values.items()
        if declared is None or name in declared
    ]
    note = None
    if abs(right - left) > tolerance * mean and (declared is None or "wheel_radius" in declared):
        note = (
            f"the radii differ (left {_number(left)} m, right {_number(right)} m, "
            f"{100.0 * (right - left) / mean:+.3g} %): wheel_radius is their mean; apply the "
            "difference with the controller's left and right radius multipliers"
        )
    return XacroArguments(" ".join(given) or None, note)


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
