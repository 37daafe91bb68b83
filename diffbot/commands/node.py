"""``diffbot node odom|ik|robot``: the course's nodes on a live ROS 2 graph (extra ``live``)."""

from __future__ import annotations

import click

from diffbot.commands.live import duration_option, run_node
from diffbot.commands.options import POSITIVE, RobotOptions, quiet_option, robot_options
from diffbot.commands.plan_options import check_topic

__all__ = ["node"]


@click.group("node")
def node() -> None:
    """The course's nodes on a live ROS 2 graph, with no ROS install (DDS through cyclonedds:
    pip install 'diffbot-kinematics[live]').

    The domain comes from ROS_DOMAIN_ID; ROS_LOCALHOST_ONLY=1 or
    ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST keep the traffic on this machine. Each node runs
    until Ctrl-C (or --duration) and then prints what it counted.
    """


@node.command("odom")
@click.argument("description", required=False, metavar="[ROBOT]")
@robot_options
@click.option(
    "--joint-states",
    default="joint_states",
    show_default=True,
    metavar="TOPIC",
    help="The sensor_msgs/JointState topic to read.",
)
@click.option(
    "--odom-topic",
    default="odom",
    show_default=True,
    metavar="TOPIC",
    help="The nav_msgs/Odometry topic to publish.",
)
@click.option("--no-tf", is_flag=True, help="Do not broadcast odom -> base_link on /tf.")
@click.option("--frame-id", metavar="FRAME", help="Odometry frame [controllers file, else odom].")
@click.option(
    "--child-frame-id",
    metavar="FRAME",
    help="The robot's frame [controllers file, else base_link].",
)
@click.option(
    "--publish-rate",
    type=POSITIVE,
    metavar="HZ",
    help="Publish at most this often, by the joint states' stamps [controllers file, else one "
    "odometry per joint state].",
)
@click.option(
    "--window",
    type=click.IntRange(min=1),
    metavar="N",
    help="Velocity rolling window in steps [controllers file, else 1].",
)
@duration_option
@quiet_option
def odom(
    robot: RobotOptions,
    description: str | None,
    joint_states: str,
    odom_topic: str,
    no_tf: bool,
    frame_id: str | None,
    child_frame_id: str | None,
    publish_rate: float | None,
    window: int | None,
    duration: float | None,
    quiet: bool,
) -> None:
    """Odometry from joint states: subscribes JOINT_STATES, publishes nav_msgs/Odometry and the
    odom -> base_link transform on /tf, integrated exactly along each step's arc.

    Stamps come from the joint states' headers. Frames, rate, covariances, the velocity window
    and enable_odom_tf come from the controllers file when there is one (--controllers), else
    from the options. A joint state without a wheel joint, with a NaN, going back in time or
    with mismatched arrays is skipped and counted in the status line.

    \b
    Example:
      ROS_LOCALHOST_ONLY=1 diffbot node odom --controllers my_controllers.yaml
    """
    check_topic("--joint-states", joint_states)
    check_topic("--odom-topic", odom_topic)
    from diffbot.live.odometry import OdometryNode, OdometrySettings

    params = robot.with_path(description, {}).load()
    settings = OdometrySettings(joint_states=joint_states, odom_topic=odom_topic).with_controller(
        params.controller,
        frame_id=frame_id,
        child_frame_id=child_frame_id,
        publish_rate=publish_rate,
        window=window,
        publish_tf=False if no_tf else None,
    )
    live = OdometryNode(params, settings)
    run_node(live, "odom", live.status, quiet=quiet, duration=duration)
