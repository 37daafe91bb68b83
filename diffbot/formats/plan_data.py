"""Plans as data for programs: JSON and CSV."""

from __future__ import annotations

import csv
import io
from typing import TYPE_CHECKING, Any

from diffbot.formats.robot import robot_json
from diffbot.kinematics import Pose, rpm_from_rad_s
from diffbot.planfile import format_plan, format_segment
from diffbot.segments import describe_segment
from diffbot.trajectory import Plan

if TYPE_CHECKING:
    from diffbot.body_limits import BodyLimits

__all__ = ["plan_csv", "plan_json", "pose_json", "start_json"]


def pose_json(pose: Pose) -> dict[str, float]:
    """A pose as ``{x, y, theta}`` (m, m, rad)."""
    return {"x": pose.x, "y": pose.y, "theta": pose.theta}


def start_json(start: Pose | None) -> dict[str, dict[str, float]]:
    """``{"start_pose": {x, y, theta}}`` for a goal plan's start pose (m, m, rad), which its
    poses are relative to; nothing for a plan of segments (None), which starts at its own
    origin."""
    return {} if start is None else {"start_pose": pose_json(start)}


def plan_json(
    p: Plan,
    label: str,
    *,
    steps: Plan | None = None,
    body: BodyLimits | None = None,
    start: Pose | None = None,
) -> dict[str, Any]:
    """The whole plan as JSON-ready data (SI units, rpm labelled).

    ``start`` is a goal plan's start pose, in the frame its goals are given in: the plan's
    poses (each segment's, the final one) are relative to it, and ``start_pose`` says so.

    ``steps`` is the step plan of a ramped plan ``p`` (its summary): the limits are checked
    on it, as the durations a plan gives are cruise durations that the ramps lengthen, so the
    shortest duration that fits is one of those, not a ramped one. With body velocity limits
    ``body``, ``body_limits`` gives them and ``body_violations`` every segment over them.
    """
    checked = p if steps is None else steps
    segments = []
    for s in p.segments:
        segments.append(
            {
                "segment": s.index + 1,
                "kind": s.kind,
                "spec": format_segment(s.segment),
                "description": describe_segment(s.segment),
                "duration": s.duration,
                "linear": float(s.twist.linear),
                "angular": float(s.twist.angular),
                "left": float(s.joints.left),
                "right": float(s.joints.right),
                "left_rpm": float(rpm_from_rad_s(s.joints.left)),
                "right_rpm": float(rpm_from_rad_s(s.joints.right)),
                "fraction": s.fraction,
                "start_pose": pose_json(s.start_pose),
                "end_pose": pose_json(s.end_pose),
                "end_heading": s.end_heading,
            }
        )
    return {
        "source": label,
        "plan": format_plan(s.segment for s in p.segments),
        "segments": segments,
        "duration": p.duration,
        **start_json(start),
        "final_pose": pose_json(p.final_pose),
        "within_limit": p.within_limit,
        "limit": p.limit,
        "limit_rpm": None if p.limit is None else float(f"{rpm_from_rad_s(p.limit):.12g}"),
        "violations": [
            {
                "segment": v.index + 1,
                "wheel": v.wheel,
                "rpm": v.rpm,
                "shortest_duration": v.shortest_duration,
            }
            for v in checked.violations()
        ],
        "robot": robot_json(p.params),
    } | _body_json(checked, body)


def _body_json(checked: Plan, body: BodyLimits | None) -> dict[str, Any]:
    """The body velocity limits and the segments over them; nothing without limits."""
    if body is None or body.unlimited:
        return {}
    from diffbot.body_limits import violations

    return {
        "body_limits": {
            "linear": None if body.linear is None else list(body.linear),
            "angular": None if body.angular is None else list(body.angular),
        },
        "body_violations": [
            {
                "segment": v.index + 1,
                "axis": v.axis,
                "value": v.value,
                "bounds": list(v.bounds),
                "shortest_duration": v.shortest_duration,
            }
            for v in violations(checked, body)
        ],
    }


def plan_csv(p: Plan) -> str:
    """One CSV row per segment; floats printed so that they read back exactly."""

    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(
        [
            "segment",
            "kind",
            "spec",
            "duration",
            "linear",
            "angular",
            "left",
            "right",
            "left_rpm",
            "right_rpm",
            "fraction",
            "x",
            "y",
            "theta",
        ]
    )
    for s in p.segments:
        values = [
            s.duration,
            s.twist.linear,
            s.twist.angular,
            s.joints.left,
            s.joints.right,
            rpm_from_rad_s(s.joints.left),
            rpm_from_rad_s(s.joints.right),
        ]
        writer.writerow(
            [
                s.index + 1,
                s.kind,
                format_segment(s.segment),
                *(repr(float(v)) for v in values),
                "" if s.fraction is None else repr(s.fraction),
                repr(s.end_pose.x),
                repr(s.end_pose.y),
                repr(s.end_pose.theta),
            ]
        )
    return out.getvalue()
