"""Which velocity command topic a command publishes or reads: ``--cmd-vel`` when given, else the
controllers file's diff-drive controller's own topic for the ROS release (``--distro``, else
``ROS_DISTRO``), else the topic of the description's Gazebo classic diff-drive plugin, else
plain ``cmd_vel``."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import TypeVar

import click

from diffbot.commands.shown_defaults import name_option
from diffbot.kinematics import DiffDriveParams
from diffbot.numbers import shown
from diffbot.wheel_topics import LEFT_TOPIC, RIGHT_TOPIC

__all__ = [
    "DEFAULT_CMD_VEL",
    "DEFAULT_ODOM",
    "distro_option",
    "resolve_cmd_vel",
    "resolve_odom_topic",
    "resolve_wheel_topics",
    "wheel_topic_options",
]

_F = TypeVar("_F", bound=Callable[..., object])

#: The velocity command topic without a controllers file.
DEFAULT_CMD_VEL = "cmd_vel"
#: The odometry topic without a controllers file (or a simulator plugin, to read it).
DEFAULT_ODOM = "odom"
#: Help of the --cmd-vel options: where the default comes from.
CMD_VEL_HELP = (
    "The velocity command topic [the controllers file's diff-drive controller's "
    "/<name>/cmd_vel (cmd_vel_unstamped with use_stamped_vel: false on Humble), else the "
    "description's Gazebo classic diff-drive plugin's (its namespace and remapping), else "
    "cmd_vel]."
)

#: --distro: the ROS release whose controller topics and types apply.
distro_option = click.option(
    "--distro",
    type=click.Choice(["humble", "jazzy", "kilted", "rolling"], case_sensitive=False),
    metavar="humble|jazzy|kilted|rolling",
    help="The ROS 2 release of the controller: its command topic and type (TwistStamped from "
    "Jazzy on, and on Humble unless use_stamped_vel: false), the type kept when a topic is "
    "given [ROS_DISTRO; with neither, Jazzy's, or Humble's when the controllers file sets "
    "use_stamped_vel: false].",
)


#: Where the per-side command topics come from when not given.
WHEEL_TOPICS_HELP = (
    " [the controllers file's velocity controller of that side's wheels + /commands, else "
    f"{LEFT_TOPIC} and {RIGHT_TOPIC}]"
)


def wheel_topic_options(left_help: str, right_help: str) -> Callable[[_F], _F]:
    """``--left-topic`` and ``--right-topic``: the per-side Float64MultiArray command topics,
    by default those :func:`resolve_wheel_topics` finds."""

    def add(command: _F) -> _F:
        sides = (("right", right_help), ("left", left_help + WHEEL_TOPICS_HELP))
        for side, text in sides:
            command = name_option(f"--{side}-topic", None, text)(command)
        return command

    return add


def resolve_wheel_topics(
    params: DiffDriveParams,
    controllers: str | None,
    given: tuple[str | None, str | None] = (None, None),
    *,
    check: bool = True,
) -> tuple[str, str]:
    """The left and right Float64MultiArray command topics: each given one, else that of the
    velocity controller of the side's wheels in the controllers file (``controllers``, else
    the one the robot's diff-drive controller came from), behind its namespace, else the
    course's (:mod:`diffbot.wheel_topics`). With ``check`` (the caller uses them), a topic
    found that no ROS node could take is a bad-input error naming the file."""
    from diffbot.urdf.controllers import load_command_controllers

    topics = [LEFT_TOPIC, RIGHT_TOPIC]
    if controllers is None and params.controller is not None:
        controllers = params.controller.source
    if controllers is not None and Path(controllers).is_file():
        found = load_command_controllers(controllers)
        sides = (
            params.left_joints or (params.left_joint,),
            params.right_joints or (params.right_joint,),
        )
        options = ("--left-topic", "--right-topic")
        for i, (joints, option) in enumerate(zip(sides, options, strict=True)):
            for name, commanded in found.items():
                if set(commanded) == set(joints):
                    topics[i] = _valid(f"{name}/commands", controllers, option if check else None)
    left, right = given
    return left or topics[0], right or topics[1]


def resolve_cmd_vel(
    params: DiffDriveParams,
    cmd_vel: str | None,
    stamped: bool,
    distro: str | None,
    option: str | None = "--cmd-vel",
) -> tuple[str, bool]:
    """The command topic and whether its messages are TwistStamped (``stamped`` can only add a
    stamp): the controller's topic and type when the robot has a diff-drive controller
    configuration, else the topic its description's Gazebo classic diff-drive plugin subscribes
    (Twist), else ``cmd_vel`` (the course's nodes, Twist). A ``cmd_vel`` given replaces the
    topic; with a controller configuration and ``distro`` given, the type stays the
    controller's on that release, else it is Twist unless ``stamped``. A topic found that no
    ROS node could take is a bad-input error naming the file and ``option`` (None: the caller
    uses no topic, and takes any)."""
    from diffbot.controller_topics import command_topic, distro_of

    if cmd_vel is None and params.controller is not None:
        release = distro_of(distro)
        found = command_topic(params.controller, release)
        # Without a release such a file is read as Humble's: only a later one named ignores it.
        if params.controller.use_stamped_vel is False and release not in (None, "humble"):
            from diffbot.commands.options import warn

            warn(
                f"{params.controller.source}: use_stamped_vel: false means nothing on "
                f"{str(release).capitalize()} (a Humble parameter): the controller takes "
                f"TwistStamped on {found.topic}"
            )
        return _valid(found.topic, params.controller.source, option), stamped or found.stamped
    topic = params.plugin_topics.get("cmd_vel", DEFAULT_CMD_VEL) if cmd_vel is None else cmd_vel
    if cmd_vel is None:
        topic = _valid(topic, "the description's diff-drive plugin", option)
    if distro is not None and params.controller is not None:  # its release named: its type
        stamped = stamped or command_topic(params.controller, distro_of(distro)).stamped
    return topic, stamped


def resolve_odom_topic(params: DiffDriveParams, given: str | None) -> str:
    """The nav_msgs/Odometry topic a reader of the robot's odometry takes: ``given``, else the
    diff-drive controller's own (``~/odom`` under its node's name) when the robot has a
    controller configuration, else the one its description's Gazebo classic diff-drive plugin
    publishes, else ``odom``; one found that no ROS node could take is a bad-input error."""
    if given is not None:
        return given
    if params.controller is not None:
        return _valid(params.controller.odom_topic, params.controller.source, "--odom-topic")
    topic = params.plugin_topics.get("odom", DEFAULT_ODOM)
    return _valid(topic, "the description's diff-drive plugin", "--odom-topic")


def _valid(topic: str, source: str, option: str | None) -> str:
    """``topic``, found in ``source``, when it is a valid ROS topic name (or ``option`` is
    None): else a bad-input error, as no publisher or subscriber could take it."""
    if option is None:
        return topic
    from diffbot.live.names import topic_problem

    problem = topic_problem(topic)
    if problem is not None:
        from diffbot.commands.messages import fail

        fail(f"{source}: the topic {shown(topic)} it gives {problem}: give {option}")
    return topic
