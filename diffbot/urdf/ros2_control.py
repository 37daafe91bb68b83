"""Motor limits written in a description's ``<ros2_control>`` tags.

A velocity command interface may carry its limits as parameters
(``<command_interface name="velocity"><param name="max">25</param>``); ros2_control's hardware
and joint limiters hold the commands within them, so they are a motor limit as much as a
joint's ``<limit velocity>``.
"""

from __future__ import annotations

import math
from xml.etree.ElementTree import Element

from diffbot.numbers import written_number

__all__ = ["velocity_limits"]


def velocity_limits(root: Element) -> dict[str, float]:
    """The velocity limit (rad/s) of each joint whose velocity command interface has one.

    The limit is the smaller magnitude of ``max`` and ``min`` when both are given; values that
    are not positive finite numbers are left out.
    """
    limits: dict[str, float] = {}
    for block in root.iter("ros2_control"):
        for joint in block.iter("joint"):
            name = joint.get("name")
            for interface in joint.iter("command_interface"):
                if name is None or interface.get("name") != "velocity":
                    continue
                bounds = []
                for param in interface.iter("param"):
                    if param.get("name") not in ("max", "min"):
                        continue
                    try:
                        value = abs(written_number((param.text or "").strip()))
                    except ValueError:
                        continue
                    if math.isfinite(value) and value > 0.0:
                        bounds.append(value)
                if bounds:
                    limits[name] = min(bounds)
    return limits
