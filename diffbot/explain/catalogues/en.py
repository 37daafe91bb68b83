"""English strings of the worked derivations."""

from __future__ import annotations

from typing import Final

STRINGS: Final[dict[str, str]] = {
    "title.ik": "Inverse kinematics: wheel speeds for v = {v} and ω = {w}",
    "title.fk": "Forward kinematics: robot velocity for ω_L = {left} and ω_R = {right}",
    "title.plan": "Motion plan of {duration}, segments: {count}",
    "title.odom": "Odometry: one step of {dt}",
    "section.given": "Given",
    "section.wheels": "Wheel speeds",
    "section.body": "Robot velocity",
    "section.limit": "Motor limit check",
    "section.segment": "Segment {number}: {kind}",
    "section.travel": "Arcs rolled by the wheels",
    "section.pose": "New pose",
    "kind.straight": "straight line of {length}",
    "kind.ccw": "counter-clockwise arc of radius {radius} through {angle}",
    "kind.cw": "clockwise arc of radius {radius} through {angle}",
    "kind.spin": "turn in place through {angle}",
    "label.wheel_radius": "Wheel radius",
    "label.left_wheel_radius": "Radius of the left wheels",
    "label.right_wheel_radius": "Radius of the right wheels",
    "label.wheel_separation": "Wheel separation",
    "label.motor_limit": "Motor limit",
    "label.linear": "Linear velocity",
    "label.angular": "Angular velocity",
    "label.left_speed": "Angular velocity of the left wheel",
    "label.right_speed": "Angular velocity of the right wheel",
    "label.limit_share": "Share of the motor limit used by the faster wheel",
    "label.duration": "Duration",
    "label.path_length": "Path length",
    "label.heading_change": "Heading change",
    "label.radius": (
        "Radius of the arc, signed as v/ω (negative clockwise forwards or counter-clockwise "
        "backwards)"
    ),
    "label.arc_speed": "Linear velocity from the arc, as a check",
    "label.start_x": "x at the start",
    "label.start_y": "y at the start",
    "label.start_heading": "Heading at the start",
    "label.end_x": "x at the end",
    "label.end_y": "y at the end",
    "label.end_heading": "Heading at the end",
    "label.left_before": "Left wheel angle before the step",
    "label.left_after": "Left wheel angle after the step",
    "label.right_before": "Right wheel angle before the step",
    "label.right_after": "Right wheel angle after the step",
    "label.joint": "{what}, as its joint sees it (the axis is mirrored)",
    "label.time_step": "Time step",
    "label.left_arc": "Arc rolled by the left wheel",
    "label.right_arc": "Arc rolled by the right wheel",
    "label.distance": "Distance travelled by the centre",
    "label.chord": "Chord of the arc (sinc form: exact while the wheel speeds are constant)",
    "check.within": "{peak} ≤ {limit}: within the motor limit",
    "check.over": "{peak} > {limit}: over the motor limit",
    "check.over_plan": (
        "{peak} > {limit}: over the motor limit; the segment needs at least {duration}"
    ),
}
