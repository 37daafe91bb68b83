"""The course's per-wheel velocity controllers' command topics (std_msgs/Float64MultiArray).

Their own module, free of imports, so that the command line can show them as defaults without
loading the code that computes the commands.
"""

from __future__ import annotations

__all__ = ["LEFT_TOPIC", "RIGHT_TOPIC"]

LEFT_TOPIC = "left_wheel_velocity_controller/commands"
RIGHT_TOPIC = "right_wheel_velocity_controller/commands"
