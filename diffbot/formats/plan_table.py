"""Plans as text for people: the table ``diffbot plan`` prints, and the limit messages."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from diffbot.formats.text import ceil_text, fixed, fmt
from diffbot.kinematics import DiffDriveParams, rpm_from_rad_s
from diffbot.planfile import format_plan
from diffbot.segments import describe_segment
from diffbot.trajectory import Plan, Violation

if TYPE_CHECKING:
    from diffbot.body_limits import BodyLimits, BodyViolation

#: Significant digits of the plan text above the table (machine outputs keep every digit).
HEADER_DIGITS = 6

__all__ = [
    "HEADER_DIGITS",
    "geometry_text",
    "limit_text",
    "plan_limit_text",
    "plan_table",
    "violation_lines",
]


def geometry_text(params: DiffDriveParams) -> str:
    """The robot's size for people: ``wheel radius R m, separation B m``, or each side's
    radius when they differ, as the commands use them (a controller's radius multipliers
    applied, equal or not)."""
    left, right = params.radii
    radius = (
        f"wheel radius {fmt(left)} m"
        if left == right
        else f"wheel radii {fmt(left)} m left and {fmt(right)} m right"
    )
    return f"{radius}, separation {fmt(params.wheel_separation)} m"


def limit_text(params: DiffDriveParams) -> str:
    """The motor limit for people."""
    if params.max_wheel_speed is None:
        return "none"
    return f"{fmt(params.max_wheel_rpm or 0.0, 5)} rpm ({fmt(params.max_wheel_speed)} rad/s)"


def plan_limit_text(p: Plan) -> str:
    """The limit a plan was checked against, for people."""
    if p.limit is None:
        return "none"
    origin = "" if p.limit == p.params.max_wheel_speed else ", the plan's own limit"
    return f"{fmt(rpm_from_rad_s(p.limit), 5)} rpm ({fmt(p.limit)} rad/s{origin})"


#: The width the default table fits in (characters): an ordinary terminal's.
WIDTH = 100


def plan_table(p: Plan, label: str, *, wide: bool = False, steps: Plan | None = None) -> str:
    """The plan as a table: each segment's twist, wheel speeds, share of the limit, end pose.

    The default table fits :data:`WIDTH` columns: wheel speeds in rpm only, short headers, the
    plan text shortened when it is longer; ``wide`` adds each wheel's speed in rad/s and the
    motor limit on the robot line (about 130 columns). ``steps`` is the step plan of a ramped
    plan ``p`` (its summary), whose check of the motor limit the table names the segments of:
    a ramp that never reaches a segment's step speed does not make that speed fit.
    """
    if not wide:
        return _narrow_table(p, label, steps)
    params = p.params
    header = [
        "#",
        "segment",
        "v m/s",
        "w rad/s",
        "left rad/s",
        "rpm",
        "right rad/s",
        "rpm",
        "limit %",
        "time s",
        "x m",
        "y m",
        "theta deg",
    ]
    rows = [header]
    for s in p.segments:
        left, right = float(s.joints.left), float(s.joints.right)
        rows.append(
            [
                str(s.index + 1),
                describe_segment(s.segment),
                fixed(float(s.twist.linear), 4),
                fixed(float(s.twist.angular), 4),
                fixed(left, 3),
                fixed(rpm_from_rad_s(left), 2),
                fixed(right, 3),
                fixed(rpm_from_rad_s(right), 2),
                "-" if s.fraction is None else fixed(100 * s.fraction, 1),
                fmt(s.duration, 6),
                fixed(s.end_pose.x, 4),
                fixed(s.end_pose.y, 4),
                fixed(math.degrees(s.end_pose.theta), 2),
            ]
        )
    lines = [
        f"{label}: {format_plan((s.segment for s in p.segments), HEADER_DIGITS)}",
        f"robot: {params.source} ({geometry_text(params)}); motor limit {plan_limit_text(p)}",
        "",
    ]
    return "\n".join([*lines, *_aligned(rows)]) + "\n" + _summary(p, steps)


def _aligned(rows: list[list[str]]) -> list[str]:
    """Table rows as text lines: the segment column (the second) aligned left, the others
    right, two spaces apart."""
    widths = [max(len(row[i]) for row in rows) for i in range(len(rows[0]))]
    return [
        "  ".join(
            cell.ljust(widths[i]) if i == 1 else cell.rjust(widths[i]) for i, cell in enumerate(row)
        ).rstrip()
        for row in rows
    ]


def _narrow_table(p: Plan, label: str, steps: Plan | None) -> str:
    params = p.params
    header = ["#", "segment", "v m/s", "w rad/s", "L rpm", "R rpm", "limit%", "t s", "x m", "y m"]
    header.append("theta deg")
    rows = [header]
    for s in p.segments:
        rows.append(
            [
                str(s.index + 1),
                describe_segment(s.segment).replace(" arc r ", " "),
                fixed(float(s.twist.linear), 4),
                fixed(float(s.twist.angular), 4),
                fixed(rpm_from_rad_s(float(s.joints.left)), 2),
                fixed(rpm_from_rad_s(float(s.joints.right)), 2),
                "-" if s.fraction is None else fixed(100 * s.fraction, 1),
                fmt(s.duration, 4),
                fixed(s.end_pose.x, 4),
                fixed(s.end_pose.y, 4),
                fixed(math.degrees(s.end_pose.theta), 2),
            ]
        )
    title = f"{label}: {format_plan((s.segment for s in p.segments), HEADER_DIGITS)}"
    lines = [
        title if len(title) <= WIDTH else title[: WIDTH - 4] + " ...",
        f"robot: {params.source} ({geometry_text(params)})",
        "",
    ]
    return "\n".join([*lines, *_aligned(rows)]) + "\n" + _summary(p, steps)


def _summary(p: Plan, steps: Plan | None) -> str:
    """The lines under a table: the total time, the final pose, the motor limit check (of
    ``steps`` when given)."""
    final = p.final_pose
    lines = [
        "",
        f"total {fmt(p.duration, 6)} s; final pose x {fixed(final.x, 4)} m, "
        f"y {fixed(final.y, 4)} m, theta {fixed(math.degrees(final.theta), 2)} deg",
    ]
    if p.limit is None:
        lines.append("motor limit: none in the description, not checked")
    else:
        peak = max(p.segments, key=lambda s: s.fraction or 0.0)
        if p.within_limit:
            lines.append(
                f"motor limit {plan_limit_text(p)}: within, peak "
                f"{fixed(100 * (peak.fraction or 0.0), 1)}% in segment {peak.index + 1}"
            )
        else:
            over = sorted({v.index + 1 for v in (p if steps is None else steps).violations()})
            lines.append(
                f"motor limit {plan_limit_text(p)}: OVER in segment"
                f"{'s' if len(over) > 1 else ''} {', '.join(map(str, over))}"
            )
    return "\n".join(lines) + "\n"


def violation_lines(p: Plan) -> list[str]:
    """One ``error:`` line per segment over the limit, with the shortest duration that fits."""

    limit_rpm = fmt(rpm_from_rad_s(p.limit), 5) if p.limit is not None else "?"
    by_segment: dict[int, list[Violation]] = {}
    for v in p.violations():
        by_segment.setdefault(v.index, []).append(v)
    lines = []
    for index, found in by_segment.items():
        s = p.segments[index]
        parts = [(v.wheel, fmt(v.rpm, 4)) for v in found]
        if len(parts) == 2 and parts[0][1] == parts[1][1]:
            what = f"left and right wheels at {parts[0][1]} rpm exceed"
        elif len(parts) == 2:
            what = f"left wheel at {parts[0][1]} rpm and right wheel at {parts[1][1]} rpm exceed"
        else:
            what = f"{parts[0][0]} wheel at {parts[0][1]} rpm exceeds"
        lines.append(
            f"error: segment {index + 1} ({describe_segment(s.segment)}, {fmt(s.duration, 6)} s): "
            f"{what} the {limit_rpm} rpm limit; shortest duration that fits: "
            f"{ceil_text(found[0].shortest_duration)} s"
        )
    return lines


def body_violation_lines(p: Plan, limits: BodyLimits) -> list[str]:
    """One ``error:`` line per segment over a body velocity limit, with the shortest duration
    that fits (both the linear and the angular limit)."""
    from diffbot.body_limits import violations

    units = {"linear": "m/s", "angular": "rad/s"}
    by_segment: dict[int, list[BodyViolation]] = {}
    for v in violations(p, limits):
        by_segment.setdefault(v.index, []).append(v)
    lines = []
    for index, found in by_segment.items():
        s = p.segments[index]
        what = " and ".join(
            f"{v.axis} velocity {fmt(v.value, 4)} {units[v.axis]} is outside "
            f"[{fmt(v.bounds[0], 4)}, {fmt(v.bounds[1], 4)}]"
            for v in found
        )
        lines.append(
            f"error: segment {index + 1} ({describe_segment(s.segment)}, {fmt(s.duration, 6)} s): "
            f"{what}, the body velocity limits; shortest duration that fits: "
            f"{ceil_text(found[0].shortest_duration)} s"
        )
    return lines


def body_limit_line(p: Plan, limits: BodyLimits) -> str:
    """The line under a table that checks the body velocity limits; empty without any."""
    if limits.unlimited:
        return ""
    from diffbot.body_limits import violations

    parts = []
    if limits.linear is not None:
        parts.append(f"linear [{fmt(limits.linear[0])}, {fmt(limits.linear[1])}] m/s")
    if limits.angular is not None:
        parts.append(f"angular [{fmt(limits.angular[0])}, {fmt(limits.angular[1])}] rad/s")
    over = sorted({v.index + 1 for v in violations(p, limits)})
    state = "within" if not over else "OVER in segment" + ("s " if len(over) > 1 else " ")
    return f"body limits {', '.join(parts)}: {state}{', '.join(map(str, over))}\n"
