"""``diffbot node odom|ik|robot``: the course's nodes on a live ROS 2 graph (extra ``live``)."""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, TypeVar

import click
from click.core import ParameterSource

from diffbot.commands.follow_options import disturbance_options
from diffbot.commands.limit_options import body_limit_option
from diffbot.commands.live import (
    PUBLISH_RATE,
    RATE,
    WAIT,
    announce_option,
    checked_frame,
    checked_topic,
    checked_topics,
    duration_option,
    run_node,
)
from diffbot.commands.options import (
    Count,
    RobotOptions,
    encoder_noise_options,
    fail,
    quiet_option,
    robot_options,
    true_geometry_options,
    warn,
)
from diffbot.commands.recording_options import feedback_option
from diffbot.commands.settings import from_options
from diffbot.commands.shown_defaults import name_option
from diffbot.commands.topic_options import (
    CMD_VEL_HELP,
    distro_option,
    resolve_cmd_vel,
    resolve_wheel_topics,
)
from diffbot.numbers import MAX_ROLLING_WINDOW

if TYPE_CHECKING:
    from diffbot.live.transport import Node

__all__ = ["node"]


F = TypeVar("F", bound=Callable[..., object])


def _stale_timeout_option(why: str) -> Callable[[F], F]:
    """``--timeout``: how long without a command before the wheels are stopped."""
    return click.option(
        "--timeout",
        type=WAIT,
        default=0.5,
        show_default=True,
        metavar="S",
        help=f"Stop the wheels when no command came for this long (0: never){why}.",
    )


@click.group("node")
def node() -> None:
    """The course's nodes on a live ROS 2 graph, with no ROS install (DDS through cyclonedds:
    pip install 'diffbot-kinematics[live]').

    The domain comes from ROS_DOMAIN_ID; ROS_LOCALHOST_ONLY=1 or
    ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST keep the traffic on this machine. Each node runs
    until Ctrl-C (or --duration) and then prints what it counted.

    \b
    Examples:
      diffbot node odom --duration 1     odometry from joint_states, for a second
      ROS_LOCALHOST_ONLY=1 diffbot node ik & diffbot drive --example A
    """


@node.command("odom")
@click.argument("tokens", nargs=-1, metavar="[ROBOT] [NAME:=VALUE]...")
@robot_options
@name_option("--joint-states", "joint_states", "The sensor_msgs/JointState topic to read.")
@name_option(
    "--odom-topic",
    None,
    "The nav_msgs/Odometry topic to publish [the controllers file's diff-drive controller's "
    "/<name>/odom, else odom].",
)
@click.option("--no-tf", is_flag=True, help="Do not broadcast odom -> base_link on /tf.")
@click.option("--frame-id", metavar="FRAME", help="Odometry frame [the controller's, else odom].")
@click.option(
    "--child-frame-id",
    metavar="FRAME",
    help="The robot's frame [the controller's, behind its prefix; else base_link].",
)
@click.option(
    "--publish-rate",
    type=PUBLISH_RATE,
    metavar="HZ",
    help="Publish at most this often, by the joint states' stamps [controllers file, else one "
    "odometry per joint state].",
)
@click.option(
    "--window",
    type=Count(1, MAX_ROLLING_WINDOW),
    metavar="N",
    help="Velocity rolling window in steps, up to 1,000,000 [the controller's, 10 when its "
    "file leaves it out; else 1].",
)
@feedback_option
@click.option(
    "--open-loop",
    is_flag=True,
    help="Integrate the velocity commands instead of the wheels, as diff_drive_controller does "
    "with open_loop: true: each held until the next or until cmd_vel_timeout (the controllers "
    "file's, else 0.5 s); published at --publish-rate [else 50 Hz], stamped by this machine's "
    "clock.",
)
@click.option("--cmd-vel", metavar="TOPIC", help="With --open-loop: " + CMD_VEL_HELP)
@distro_option
@click.option(
    "--stamped",
    is_flag=True,
    help="With --open-loop: read geometry_msgs/TwistStamped only. Default: Twist or "
    "TwistStamped, whichever the publisher sends.",
)
@duration_option
@announce_option
@quiet_option
def odom(
    robot: RobotOptions,
    tokens: tuple[str, ...],
    joint_states: str,
    odom_topic: str | None,
    no_tf: bool,
    frame_id: str | None,
    child_frame_id: str | None,
    publish_rate: float | None,
    window: int | None,
    feedback: str | None,
    open_loop: bool,
    cmd_vel: str | None,
    distro: str | None,
    stamped: bool,
    duration: float | None,
    announce: bool,
    quiet: bool,
) -> None:
    """Odometry from joint states: subscribes JOINT_STATES, publishes nav_msgs/Odometry and the
    odom -> base_link transform on /tf, integrated exactly along each step's arc.

    Stamps come from the joint states' headers. Frames, rate, covariances, the velocity window,
    enable_odom_tf and position_feedback come from the controllers file when there is one
    (--controllers; its frames behind the controller's tf prefix, the controller's defaults
    where it leaves them out); the options override. With --feedback velocity
    (position_feedback: false) each wheel's velocity is held over the time since the last joint
    state, as the controller does. A joint state without a wheel joint, with a NaN, going back
    in time or with mismatched arrays is skipped and counted in the status line. With
    --open-loop the odometry comes from the velocity commands instead (CMD_VEL, as node ik
    reads it).

    It serves diff_drive_controller's ~/set_odometry (control_msgs/srv/SetOdometry: x, y, yaw)
    and a ~/reset_odometry (std_srvs/srv/Empty) back to the origin, under the controller's name
    when the controllers file names one (else /diffbot_odometry/...), for 'ros2 service call'.

    \b
    Examples:
      diffbot node odom --duration 1     listen for a second, then say what was counted
      ROS_LOCALHOST_ONLY=1 diffbot node odom --controllers my_controllers.yaml
      diffbot node odom --open-loop --duration 1    from cmd_vel, as a controller's open loop
    """
    checked_topics(joint_states=joint_states, odom_topic=odom_topic)
    if open_loop and feedback is not None:
        fail("--open-loop integrates the commands, not the wheels' --feedback: choose one")
    if not open_loop and (cmd_vel is not None or stamped or distro is not None):
        fail("--cmd-vel, --stamped and --distro go with --open-loop")
    context = click.get_current_context()
    if open_loop and context.get_parameter_source("joint_states") == ParameterSource.COMMANDLINE:
        fail("--open-loop reads the commands, not --joint-states: choose one")
    if cmd_vel is not None:
        checked_topic("--cmd-vel", cmd_vel)
    from diffbot.live.odometry import OdometryNode, OdometrySettings

    checked_frame("--frame-id", frame_id)
    checked_frame("--child-frame-id", child_frame_id)
    params = robot.with_tokens(tokens, "ROBOT").load()
    from diffbot.commands.odom import tell_open_loop

    if not open_loop:
        tell_open_loop(
            params,
            "this node integrates the wheels' feedback from the joint states: --open-loop "
            "integrates the commands as the controller does",
        )
    settings = OdometrySettings(joint_states=joint_states).with_controller(
        params.controller,
        odom_topic=odom_topic,
        frame_id=frame_id,
        child_frame_id=child_frame_id,
        publish_rate=publish_rate,
        window=window,
        publish_tf=False if no_tf else None,
        feedback=feedback,
    )
    if not open_loop:
        _spin(lambda: OdometryNode(params, settings), "odom", duration, announce, quiet)
        return
    from diffbot.live.open_loop_node import CommandSettings, OpenLoopOdometryNode

    topic, stamped = resolve_cmd_vel(params, cmd_vel, stamped, distro)
    controller = params.controller
    timeout = controller.cmd_vel_timeout if controller is not None else None
    commands = CommandSettings(
        cmd_vel=topic,
        stamped=True if stamped else None,
        timeout=CommandSettings.timeout if timeout is None else timeout,
    )
    _spin(
        lambda: OpenLoopOdometryNode(params, settings, commands), "odom", duration, announce, quiet
    )


@node.command("ik")
@click.argument("tokens", nargs=-1, metavar="[ROBOT] [NAME:=VALUE]...")
@robot_options
@click.option("--cmd-vel", metavar="TOPIC", help=CMD_VEL_HELP)
@distro_option
@click.option(
    "--stamped",
    is_flag=True,
    help="Read geometry_msgs/TwistStamped (diff_drive_controller's since Jazzy) only. Default: "
    "Twist or TwistStamped, whichever the publisher sends.",
)
@click.option(
    "--left-topic",
    metavar="TOPIC",
    help="The left side's Float64MultiArray topic [the controllers file's velocity controller "
    "of the left wheels + /commands, else left_wheel_velocity_controller/commands].",
)
@click.option("--right-topic", metavar="TOPIC", help="The right side's, likewise.")
@_stale_timeout_option(", as diff_drive_controller's cmd_vel_timeout")
@click.option(
    "--rate",
    type=RATE,
    metavar="HZ",
    help="Limiter updates per second, when the controllers file has limits [its update_rate, "
    "else 100].",
)
@click.option(
    "--no-limits", is_flag=True, help="Ignore the controllers file's acceleration and jerk limits."
)
@body_limit_option(0)
@body_limit_option(1)
@duration_option
@announce_option
@quiet_option
def ik(
    robot: RobotOptions,
    tokens: tuple[str, ...],
    cmd_vel: str | None,
    distro: str | None,
    stamped: bool,
    left_topic: str | None,
    right_topic: str | None,
    timeout: float,
    rate: float | None,
    no_limits: bool,
    max_linear: float | None,
    max_angular: float | None,
    duration: float | None,
    announce: bool,
    quiet: bool,
) -> None:
    """Wheel commands from velocity commands: subscribes CMD_VEL, publishes one
    std_msgs/Float64MultiArray per side (one value per joint, direction signs applied) to the
    wheels' velocity controllers.

    Wheel speeds over the motor limit are scaled down together, keeping the turning radius; the
    controllers file's velocity, acceleration and jerk limits go through diff_drive_controller's
    limiter. Linear and angular commands beyond --max-linear and --max-angular (else the
    controllers file's linear.x and angular.z max_velocity) are clamped apart, as the controller
    does (the turning radius changes). A NaN or infinite command is refused and the wheels
    stop; so they do when CMD_VEL goes quiet for --timeout seconds.

    \b
    Examples:
      diffbot node ik --duration 1       listen for a second, then say what was counted
      ROS_LOCALHOST_ONLY=1 diffbot node ik --stamped
    """
    checked_topics(cmd_vel=cmd_vel, left_topic=left_topic, right_topic=right_topic)
    from diffbot.body_limits import body_limits
    from diffbot.live.inverse_kinematics import IkSettings, InverseKinematicsNode

    params = robot.with_tokens(tokens, "ROBOT").load()
    left, right = resolve_wheel_topics(params, robot.controllers, (left_topic, right_topic))
    topic, stamped = resolve_cmd_vel(params, cmd_vel, stamped, distro)
    controller = params.controller
    settings = IkSettings(
        cmd_vel=topic,
        stamped=True if stamped else None,
        left_topic=left,
        right_topic=right,
        timeout=timeout,
        rate=rate or (controller.update_rate if controller and controller.update_rate else 100.0),
        use_limits=not no_limits,
        body=body_limits(params, max_linear, max_angular),
    )
    _spin(lambda: InverseKinematicsNode(params, settings), "ik", duration, announce, quiet)


def _spin(
    make: Callable[[], Node], label: str, duration: float | None, announce: bool, quiet: bool
) -> None:
    """Spin the node ``make()`` makes as :func:`run_node` does, its warnings printed as every
    command prints them."""

    def made() -> Node:
        live = make()
        live.warn = warn
        return live

    run_node(made, label, quiet=quiet, duration=duration, announce=announce)


@node.command("robot")
@click.argument("tokens", nargs=-1, metavar="[ROBOT] [NAME:=VALUE]...")
@robot_options
@click.option(
    "--rate",
    type=RATE,
    default=50.0,
    show_default=True,
    metavar="HZ",
    help="Updates per second: wheels moved, joint states and poses published.",
)
@click.option(
    "--cmd-vel",
    metavar="TOPIC",
    help="Take velocity commands from this topic (through the same inverse kinematics as "
    "'node ik') instead of per-side wheel commands.",
)
@click.option("--stamped", is_flag=True, help="The --cmd-vel commands are TwistStamped.")
@click.option(
    "--left-topic",
    metavar="TOPIC",
    help="The left side's Float64MultiArray command topic [as 'node ik' publishes].",
)
@click.option("--right-topic", metavar="TOPIC", help="The right side's, likewise.")
@_stale_timeout_option("")
@click.option(
    "--ticks",
    type=Count(1, 2**32),
    metavar="N",
    help="Encoder resolution (counts per revolution): quantise the reported wheel angles.",
)
@encoder_noise_options
@true_geometry_options(
    "The real left and right wheel radii (m): ground_truth/odom moves by them, while "
    "joint_states report the angles the wheels turned.",
    "The real wheel separation (m); likewise for ground_truth/odom.",
)
@click.option(
    "--limit-wheels",
    is_flag=True,
    help="Run the wheel commands through the controllers file's acceleration and jerk limits, "
    "as velocity commands (--cmd-vel) always are.",
)
@disturbance_options
@duration_option
@announce_option
@quiet_option
def robot_command(
    robot: RobotOptions,
    tokens: tuple[str, ...],
    rate: float,
    cmd_vel: str | None,
    stamped: bool,
    left_topic: str | None,
    right_topic: str | None,
    timeout: float,
    ticks: int | None,
    noise: float,
    seed: int | None,
    true_radii: tuple[float, float] | None,
    true_separation: float | None,
    limit_wheels: bool,
    motor_lag: float,
    latency: float,
    drop: float,
    slip: float,
    duration: float | None,
    announce: bool,
    quiet: bool,
) -> None:
    """A robot without hardware: turns its wheels as commanded and publishes joint_states, its
    exact pose on ground_truth/odom, /robot_description and every link's transforms (/tf_static
    for fixed joints, /tf for moving ones), so that nodes and RViz can be tried without Gazebo.

    The wheel commands are the velocity controllers' (one Float64MultiArray per side, as 'node
    ik' and 'drive --wheels' publish) unless --cmd-vel is given. The wheels stop when commands go
    quiet for --timeout seconds. --motor-lag, --latency, --drop and --slip make it a robot that
    does not do what it is told, as 'simulate' does (seeded by --seed): each command message
    reaches the motors late or never, the wheels lag and saturate at the motor limit, the ground
    slips; ground_truth/odom says where it really went.

    \b
    Examples:
      diffbot node robot --duration 1    a robot for a second, standing still without commands
      ROS_LOCALHOST_ONLY=1 diffbot node robot --rate 100 --ticks 4096
      diffbot node robot --cmd-vel cmd_vel --motor-lag 0.15 --latency 0.04 --drop 0.05 \\
          --seed 1 --duration 1    a robot that lags, delays and drops its commands
    """
    from diffbot.urdf.xacro import expand

    checked_topics(cmd_vel=cmd_vel, left_topic=left_topic, right_topic=right_topic)
    options = robot.with_tokens(tokens, "ROBOT")
    params = options.load()
    if stamped and cmd_vel is None:
        warn("--stamped applies to --cmd-vel commands only")
    left, right = resolve_wheel_topics(params, options.controllers, (left_topic, right_topic))
    expansion = expand(options.robot, options.xacro_args, options.packages, trust=options.trust)
    from diffbot.live.robot import RobotNode, RobotSettings
    from diffbot.simulation import Disturbances

    settings = from_options(
        RobotSettings,
        "rate stamped timeout ticks noise seed true_radii true_separation limit_wheels",
        cmd_vel=cmd_vel,
        left_topic=left,
        right_topic=right,
        disturbances=Disturbances(motor_lag, latency, drop, slip, seed=seed),
    )
    _spin(lambda: RobotNode(params, expansion.urdf, settings), "robot", duration, announce, quiet)
