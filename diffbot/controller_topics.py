"""The velocity command topic of a diff_drive_controller, and its message type, by ROS release.

diff_drive_controller subscribes ``~/cmd_vel`` (``diff_drive_controller.cpp``'s
``DEFAULT_COMMAND_TOPIC``), a topic under its own node name: ``/<controller>/cmd_vel``, or
``/<namespace>/<controller>/cmd_vel`` when the controllers file puts the node in a namespace.
On Humble it takes geometry_msgs/TwistStamped there unless ``use_stamped_vel: false`` (its
default is true), and then geometry_msgs/Twist on ``~/cmd_vel_unstamped``
(``DEFAULT_COMMAND_UNSTAMPED_TOPIC``); from Jazzy on it takes TwistStamped on ``~/cmd_vel`` only.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

from diffbot.errors import ParameterError

if TYPE_CHECKING:
    from diffbot.controller_config import ControllerConfig

__all__ = ["DISTROS", "CommandTopic", "command_topic", "distro_of"]

#: The ROS 2 releases whose diff_drive_controller topics are known, oldest first.
DISTROS = ("humble", "jazzy", "kilted", "rolling")


@dataclass(frozen=True)
class CommandTopic:
    """Where a controller takes its velocity commands.

    Attributes:
        topic: the absolute topic name.
        stamped: geometry_msgs/TwistStamped (True) or geometry_msgs/Twist (False).
        why: how the topic was chosen, for people.
    """

    topic: str
    stamped: bool
    why: str


def distro_of(given: str | None, environ: Mapping[str, str] | None = None) -> str | None:
    """The ROS release: ``given``, else ``ROS_DISTRO``; None when neither says.

    Raises:
        ParameterError: a release that is not one of :data:`DISTROS` (``given`` only; an
            unknown ``ROS_DISTRO`` is None, as when it is unset).
    """
    if given is not None:
        name = given.strip().lower()
        if name not in DISTROS:
            raise ParameterError(f"distro must be one of {', '.join(DISTROS)}, got {given!r}")
        return name
    env = os.environ if environ is None else environ
    name = env.get("ROS_DISTRO", "").strip().lower()
    return name if name in DISTROS else None


def command_topic(controller: ControllerConfig, distro: str | None) -> CommandTopic:
    """The topic and type the diff-drive ``controller`` takes its commands on, on ``distro``.

    Without a release, a file that sets ``use_stamped_vel: false`` is read as Humble's (the
    parameter means nothing later) and any other as Jazzy's.
    """
    base = controller.node_name
    unstamped = controller.use_stamped_vel is False
    if distro == "humble" or (distro is None and unstamped):
        release = "Humble" if distro == "humble" else "Humble (use_stamped_vel: false)"
        if unstamped:
            return CommandTopic(f"{base}/cmd_vel_unstamped", False, f"{release}, Twist")
        return CommandTopic(f"{base}/cmd_vel", True, f"{release}, use_stamped_vel true")
    release = (distro or "jazzy").capitalize()
    note = "" if distro is not None else " (no ROS_DISTRO: Jazzy's topics)"
    return CommandTopic(f"{base}/cmd_vel", True, f"{release}, TwistStamped{note}")
