"""diffbot on a live ROS 2 graph: the course's nodes speaking DDS (extra ``live``: cyclonedds).

The nodes are classes shaped like rclpy's: make one, use it as a context manager (it cleans up on
the way out), :meth:`~diffbot.live.transport.Node.spin` it until a signal or call
:meth:`~diffbot.live.transport.Node.spin_once` from a loop of your own. Nothing here is imported
by ``import diffbot``; :mod:`diffbot.live.cyclone` is the only module that imports cyclonedds.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from diffbot.lazy import lazy_names

if TYPE_CHECKING:
    from diffbot.live.drive import Driver, DriveReport, DriveSettings
    from diffbot.live.errors import LiveError
    from diffbot.live.follow_drive import FollowDriver, FollowReport, FollowSettings
    from diffbot.live.inverse_kinematics import IkSettings, InverseKinematicsNode
    from diffbot.live.odometry import OdometryNode, OdometrySettings
    from diffbot.live.robot import RobotNode, RobotSettings
    from diffbot.live.transport import Node

__all__ = [
    "DriveReport",
    "DriveSettings",
    "Driver",
    "FollowDriver",
    "FollowReport",
    "FollowSettings",
    "IkSettings",
    "InverseKinematicsNode",
    "LiveError",
    "Node",
    "OdometryNode",
    "OdometrySettings",
    "RobotNode",
    "RobotSettings",
]

#: Where each public name lives: loaded on first use, so that importing the package is free.
_HOMES = {
    "DriveReport": "drive",
    "DriveSettings": "drive",
    "Driver": "drive",
    "FollowDriver": "follow_drive",
    "FollowReport": "follow_drive",
    "FollowSettings": "follow_drive",
    "IkSettings": "inverse_kinematics",
    "InverseKinematicsNode": "inverse_kinematics",
    "LiveError": "errors",
    "Node": "transport",
    "OdometryNode": "odometry",
    "OdometrySettings": "odometry",
    "RobotNode": "robot",
    "RobotSettings": "robot",
}


__getattr__, __dir__ = lazy_names(
    "diffbot.live", {name: f"diffbot.live.{home}" for name, home in _HOMES.items()}, globals()
)
