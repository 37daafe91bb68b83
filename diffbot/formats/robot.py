"""A robot's parameters as text for people and JSON for programs, with where each came from."""

from __future__ import annotations

from typing import Any

from diffbot.formats.plan_table import limit_text
from diffbot.formats.text import fmt
from diffbot.kinematics import DiffDriveParams, Disagreement

__all__ = [
    "check_lines",
    "disagreement_json",
    "multipliers_json",
    "params_json",
    "params_lines",
    "robot_json",
]


def disagreement_json(found: Disagreement) -> dict[str, Any]:
    """A disagreement as ``{field, values: {source: value}, difference}`` (m, or None)."""
    values = {source: list(v) if isinstance(v, tuple) else v for source, v in found.values.items()}
    return {"field": found.field, "values": values, "difference": found.difference}


def robot_json(params: DiffDriveParams) -> dict[str, Any]:
    """The robot a plan was made for (m, rad/s, rpm)."""
    return {
        "wheel_radius": params.wheel_radius,
        "wheel_separation": params.wheel_separation,
        "left_joint": params.left_joint,
        "right_joint": params.right_joint,
        "left_sign": params.left_sign,
        "right_sign": params.right_sign,
        "max_wheel_speed": params.max_wheel_speed,
        "max_wheel_rpm": params.max_wheel_rpm,
        "source": params.source,
    }


def params_json(p: DiffDriveParams) -> dict[str, Any]:
    """Everything ``params --json`` prints (SI units; rpm labelled)."""
    return {
        **robot_json(p),
        "warnings": list(p.warnings),
        "left_joints": list(p.left_joints),
        "right_joints": list(p.right_joints),
        "left_wheel_radius": p.left_wheel_radius,
        "right_wheel_radius": p.right_wheel_radius,
        "sources": dict(p.sources),
        "disagreements": [disagreement_json(d) for d in p.disagreements],
    }


def _from(p: DiffDriveParams, *fields: str) -> str:
    """`` (from SOURCE)`` when a value comes from elsewhere than the description."""
    found = {p.sources.get(field, "description") for field in fields} - {"description"}
    return f" (from {', '.join(sorted(found))})" if found else ""


def params_lines(p: DiffDriveParams) -> list[str]:
    """The parameters for people, one ``label value`` line each."""
    left_radius, right_radius = p.radii
    radius = f"{fmt(p.wheel_radius)} m"
    if (left_radius, right_radius) != (p.wheel_radius, p.wheel_radius):
        radius += f"; left {fmt(left_radius)} m, right {fmt(right_radius)} m"
    rows = [
        ("robot", p.source),
        ("wheel radius", radius + _from(p, "wheel_radius", "left_wheel_radius")),
        ("wheel separation", f"{fmt(p.wheel_separation)} m" + _from(p, "wheel_separation")),
        (
            "left wheel",
            f"{', '.join(p.left_joints)} (direction {p.left_sign:+d})" + _from(p, "left_joints"),
        ),
        (
            "right wheel",
            f"{', '.join(p.right_joints)} (direction {p.right_sign:+d})" + _from(p, "right_joints"),
        ),
        ("motor limit", limit_text(p) + _from(p, "max_wheel_speed")),
    ]
    return [f"{label:<17} {value}" for label, value in rows]


def _shown(value: object) -> str:
    """A source's value: a length (m) or joint names."""
    if isinstance(value, (int, float)):
        return f"{fmt(float(value))} m"
    return ", ".join(str(name) for name in value) if isinstance(value, tuple) else str(value)


def multipliers_json(p: DiffDriveParams) -> dict[str, float] | None:
    """The controller's multipliers by name, or None without a controller."""
    if p.controller is None:
        return None
    return {
        "wheel_separation_multiplier": p.controller.wheel_separation_multiplier,
        "left_wheel_radius_multiplier": p.controller.left_wheel_radius_multiplier,
        "right_wheel_radius_multiplier": p.controller.right_wheel_radius_multiplier,
    }


def check_lines(p: DiffDriveParams) -> list[str]:
    """The cross-check of the description, controller and Gazebo plugins, for people."""
    lines = [f"robot             {p.source}"]
    if p.controller is not None:
        lines.append(f"controller        {p.controller.name} in {p.controller.source}")
    for field in ("wheel_separation", "wheel_radius", "left_joints", "right_joints"):
        lines.append(f"{field.replace('_', ' '):<17} from {p.sources.get(field, 'description')}")
    multipliers = multipliers_json(p)
    if multipliers is not None and set(multipliers.values()) != {1.0}:
        shown = ", ".join(f"{key} {fmt(value)}" for key, value in multipliers.items())
        lines.append(f"{'multipliers':<17} {shown} (the controller's settings, not compared)")
    if not p.disagreements:
        lines.append("all sources agree (within 0.5 mm, same joints)")
    for found in p.disagreements:
        lines.append(f"DISAGREE          {found.field}:")
        for source, value in found.values.items():
            shown = _shown(value)
            lines.append(f"  {source:<28} {shown}")
        if found.difference is not None:
            lines.append(f"  {'difference':<28} {fmt(found.difference * 1e3, 4)} mm")
    return lines
