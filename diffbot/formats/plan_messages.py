"""Plans as ROS message lines: Twist commands for cmd_vel, Float64MultiArray per wheel."""

from __future__ import annotations

from diffbot.formats.text import fmt, one_line
from diffbot.ros.messages import array_yaml, command_type, command_yaml
from diffbot.segments import describe_segment
from diffbot.trajectory import Plan, PlannedSegment

__all__ = ["plan_twist", "plan_wheels", "segment_note"]


def segment_note(s: PlannedSegment, count: int) -> str:
    """``i/n description, duration s``: a comment naming a segment."""

    return f"{s.index + 1}/{count} {describe_segment(s.segment)}, {fmt(s.duration, 6)} s"


def plan_twist(
    p: Plan, label: str, topic: str, *, stamped: bool = False, frame_id: str = "base_link"
) -> str:
    """One geometry_msgs/Twist YAML line per segment, then a stop; with ``stamped``,
    TwistStamped lines in ``frame_id``."""
    count = len(p.segments)
    frame = frame_id if stamped else None
    kind = command_type(frame)
    example = command_yaml(0.0, 0.0, frame).replace("0.0", "...")
    lines = [
        f"# {one_line(label)} on {one_line(p.params.source)}: {kind} commands "
        f"for {topic}, each held for its duration (m/s, rad/s)",
        f"# publish one with: ros2 topic pub -r 10 {topic} {kind} '{example}'",
    ]
    for s in p.segments:
        twist = command_yaml(float(s.twist.linear), float(s.twist.angular), frame)
        lines.append(f"{twist}  # {segment_note(s, count)}")
    lines.append(f"{command_yaml(0.0, 0.0, frame)}  # stop")
    return "\n".join(lines) + "\n"


def plan_wheels(p: Plan, label: str, left_topic: str, right_topic: str) -> str:
    """Per segment, a Float64MultiArray YAML line for each wheel topic, then a stop."""
    params = p.params
    count = len(p.segments)
    width = max(len(left_topic), len(right_topic))
    lines = [
        f"# {one_line(label)} on {one_line(params.source)}: std_msgs/msg/Float64MultiArray "
        "joint velocity commands (rad/s), each held for its duration",
        f"# left: {left_topic} ({', '.join(params.left_joints)}, direction {params.left_sign:+d})",
        f"# right: {right_topic} ({', '.join(params.right_joints)}, direction "
        f"{params.right_sign:+d})",
    ]
    lefts, rights = len(params.left_joints), len(params.right_joints)
    for s in p.segments:
        lines.append(f"# {segment_note(s, count)}")
        lines.append(f"{left_topic.ljust(width)}  {array_yaml(float(s.joints.left), lefts)}")
        lines.append(f"{right_topic.ljust(width)}  {array_yaml(float(s.joints.right), rights)}")
    lines.append("# stop")
    lines.append(f"{left_topic.ljust(width)}  {array_yaml(0.0, lefts)}")
    lines.append(f"{right_topic.ljust(width)}  {array_yaml(0.0, rights)}")
    return "\n".join(lines) + "\n"
