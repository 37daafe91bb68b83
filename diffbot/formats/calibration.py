"""Calibration results as text for people and as JSON-ready data."""

from __future__ import annotations

import math
from typing import Any

from diffbot.calibration.fit import FitResult
from diffbot.calibration.results import (
    WheelGeometry,
    controller_yaml_lines,
    multiplier_base,
    params_json,
    xacro_arguments,
)
from diffbot.calibration.umbmark import UmbmarkResult
from diffbot.formats.text import fmt
from diffbot.kinematics import DiffDriveParams

__all__ = ["calibration_data", "calibration_lines"]


def _nominal(robot: DiffDriveParams) -> tuple[float, float, float]:
    """The robot's left radius, right radius and separation (m), before the calibration."""
    left, right = robot.radii
    return left, right, robot.wheel_separation


def _geometry_rows(
    result: WheelGeometry, nominal: tuple[float, float, float], stderr: tuple[float, ...] | None
) -> list[tuple[str, str]]:
    names = ("left radius", "right radius", "separation")
    values = (result.left_wheel_radius, result.right_wheel_radius, result.wheel_separation)
    rows = []
    for k, (name, value, start) in enumerate(zip(names, values, nominal, strict=True)):
        error = "" if stderr is None else f" ± {fmt(stderr[k], 2)}"
        change = 100.0 * (value / start - 1.0)
        rows.append((name, f"{fmt(value, 9)} m{error} (nominal {fmt(start)} m, {change:+.4g} %)"))
    return rows


def calibration_lines(result: UmbmarkResult | FitResult, robot: DiffDriveParams) -> list[str]:
    """The report of a calibration: the errors, the geometry and how to apply it.

    Args:
        result: the calibration.
        robot: the robot before it: its radii and separation are the nominal ones, its
            controller's radius and separation what the multipliers scale
            (:func:`~diffbot.calibration.results.multiplier_base`), its description's xacro
            arguments those suggested (:func:`~diffbot.calibration.results.xacro_arguments`).
    """
    nominal, base = _nominal(robot), multiplier_base(robot)
    rows: list[tuple[str, str]] = []
    stderr: tuple[float, ...] | None = None
    if isinstance(result, UmbmarkResult):
        (xc, yc), (xa, ya) = result.cw_centre, result.ccw_centre
        rows += [
            ("cw centre", f"x {fmt(xc)} m, y {fmt(yc)} m"),
            ("ccw centre", f"x {fmt(xa)} m, y {fmt(ya)} m"),
            ("alpha", f"{fmt(result.alpha)} rad ({fmt(math.degrees(result.alpha))} deg) a corner"),
            ("beta", f"{fmt(result.beta)} rad ({fmt(math.degrees(result.beta))} deg) a side"),
            ("Ed", f"{fmt(result.ed, 9)} (right / left wheel diameter)"),
            ("Eb", f"{fmt(result.eb, 9)} (actual / nominal separation)"),
        ]
    else:
        stderr = (
            result.left_wheel_radius_stderr,
            result.right_wheel_radius_stderr,
            result.wheel_separation_stderr,
        )
        rows += [
            ("windows", str(result.windows)),
            (
                "residuals",
                f"position RMS {fmt(result.position_rms_before, 3)} m -> "
                f"{fmt(result.position_rms_after, 3)} m, heading RMS "
                f"{fmt(result.heading_rms_before, 3)} rad -> "
                f"{fmt(result.heading_rms_after, 3)} rad",
            ),
        ]
    rows += _geometry_rows(result, nominal, stderr)
    lines = [f"{label:<13} {value}" for label, value in rows]
    lines.append("diff_drive_controller (ros__parameters):")
    lines += [f"  {line}" for line in controller_yaml_lines(result, *base)]
    arguments = xacro_arguments(result, declared=robot.xacro_arguments)
    if arguments.arguments is not None:
        lines.append(f"xacro arguments: {arguments.arguments}")
    if arguments.note is not None:
        lines.append(f"note: {arguments.note}")
    return lines


def calibration_data(result: UmbmarkResult | FitResult, robot: DiffDriveParams) -> dict[str, Any]:
    """The calibration as JSON-ready data: the ``params`` keys first, then the details (the
    arguments as for :func:`calibration_lines`; ``xacro_arguments`` null when the description
    declares neither)."""
    nominal, base = _nominal(robot), multiplier_base(robot)
    data: dict[str, Any] = dict(params_json(result))
    if isinstance(result, UmbmarkResult):
        data.update(
            method="umbmark",
            alpha=result.alpha,
            beta=result.beta,
            cw_centre=list(result.cw_centre),
            ccw_centre=list(result.ccw_centre),
        )
    else:
        data.update(
            method="fit",
            left_wheel_radius_stderr=result.left_wheel_radius_stderr,
            right_wheel_radius_stderr=result.right_wheel_radius_stderr,
            wheel_separation_stderr=result.wheel_separation_stderr,
            windows=result.windows,
            residuals={
                "position_rms_before": result.position_rms_before,
                "position_rms_after": result.position_rms_after,
                "heading_rms_before": result.heading_rms_before,
                "heading_rms_after": result.heading_rms_after,
            },
        )
    arguments = xacro_arguments(result, declared=robot.xacro_arguments)
    data.update(
        nominal={
            "left_wheel_radius": nominal[0],
            "right_wheel_radius": nominal[1],
            "wheel_separation": nominal[2],
        },
        controller_yaml=controller_yaml_lines(result, *base),
        xacro_arguments=arguments.arguments,
        note=arguments.note,
    )
    return data
