"""``diffbot drive [PLAN]``: a plan driven live on a ROS 2 graph (extra ``live``)."""

from __future__ import annotations

import sys
from collections.abc import Iterator
from typing import TYPE_CHECKING

import click

from diffbot.commands.follow_options import live_follow_options
from diffbot.commands.live import RATE, WAIT, announce_option, checked_frame, checked_topics
from diffbot.commands.options import (
    RobotOptions,
    fail,
    quiet_option,
    warn,
)
from diffbot.commands.plan_options import PlanOptions, frame_id_option, plan_arguments
from diffbot.commands.settings import from_options
from diffbot.commands.topic_options import (
    CMD_VEL_HELP,
    distro_option,
    resolve_cmd_vel,
    resolve_odom_topic,
    resolve_wheel_topics,
    wheel_topic_options,
)
from diffbot.errors import EXIT_CHECK_FAILED
from diffbot.formats.text import fmt

if TYPE_CHECKING:
    from diffbot.live.drive import DriveReport, DriveSettings
    from diffbot.ramps import CommandStream

__all__ = ["drive"]

#: Commands per second unless --rate says otherwise.
DRIVE_RATE = 20.0


@click.command("drive", context_settings={"ignore_unknown_options": True})
@plan_arguments
@click.option(
    "--rate",
    type=RATE,
    default=DRIVE_RATE,
    show_default=True,
    metavar="HZ",
    help="Commands per second, each the mean velocity over its period.",
)
@click.option(
    "--stamped",
    is_flag=True,
    help="geometry_msgs/TwistStamped commands (diff_drive_controller's since Jazzy).",
)
@frame_id_option
@click.option(
    "--wheels",
    is_flag=True,
    help="Per-side Float64MultiArray commands to the velocity controllers instead of cmd_vel.",
)
@click.option("--cmd-vel", metavar="TOPIC", help=CMD_VEL_HELP)
@distro_option
@wheel_topic_options("The left side's topic (--wheels).", "The right side's topic (--wheels).")
@click.option(
    "--wait",
    type=WAIT,
    default=5.0,
    show_default=True,
    metavar="S",
    help="How long to wait for a subscriber before giving up.",
)
@live_follow_options
@announce_option
@quiet_option
def drive(
    robot: RobotOptions,
    tokens: tuple[str, ...],
    plan_options: PlanOptions,
    rate: float,
    stamped: bool,
    frame_id: str,
    wheels: bool,
    cmd_vel: str | None,
    distro: str | None,
    left_topic: str | None,
    right_topic: str | None,
    wait: float,
    follow: str | None,
    odom_topic: str | None,
    pose_topic: str | None,
    pose_timeout: float,
    lead: float,
    announce: bool,
    quiet: bool,
) -> None:
    """Drive a plan live: its commands on CMD_VEL (or per wheel) at --rate, on schedule.

    The plan is given as for 'diffbot plan' (text, a file, --example, and every speed, limit and
    ramp option). The drive waits until a subscriber has matched (--wait), publishes each
    command at its time on the monotonic clock (no drift), shows progress on a terminal and ends
    by commanding zero: after the last command, and on Ctrl-C, SIGTERM or SIGHUP too. Exit code
    1, before anything moves, when the plan exceeds the motor limit.

    With --follow the loop is closed: the commands come from a follower of the plan fed by the
    robot's pose (--odom-topic, or --pose-topic), at --rate, the tracking law acting on the pose
    predicted --lead s ahead from the commands the robot has not yet carried out (give about
    its latency plus motor lag plus half a command period); zero while the pose is stale
    (--pose-timeout), at the end and on a signal. Exit code 2, nothing commanded, when no pose
    came within --wait; 1 when the robot did not arrive in time.

    \b
    Examples:
      ROS_LOCALHOST_ONLY=1 diffbot drive --example A --stamped
      diffbot drive "straight 1; spin 90" --max-accel 0.2 --wheels --wait 1
          with no robot listening: exit code 2 after the 1 s wait
      diffbot drive "straight 0.5; spin 90" --follow --pose-timeout 0.3 --wait 1
          with no odometry on odom: exit code 2 after the 1 s wait, nothing commanded
      diffbot drive --example A --follow pure-pursuit --pose-topic amcl_pose --wait 1
          from localization's pose; exit code 2 likewise when none comes
    """
    checked_topics(
        cmd_vel=cmd_vel,
        left_topic=left_topic,
        right_topic=right_topic,
        odom_topic=odom_topic,
        pose_topic=pose_topic,
    )
    checked_frame("--frame-id", frame_id)
    if stamped and wheels:
        warn("--stamped changes Twist commands only, and --wheels sends none")
    if follow is not None and wheels:
        fail("--follow commands velocities on --cmd-vel; leave out --wheels")
    if lead and follow != "tracking":
        fail("--lead is the tracking follower's: add --follow (tracking)")
    built = plan_options.build(plan_options.request(robot, tokens))
    source, params = built.source, built.params
    cmd_vel, stamped = resolve_cmd_vel(
        params, cmd_vel, stamped, distro, None if wheels else "--cmd-vel"
    )
    left_topic, right_topic = resolve_wheel_topics(
        params, robot.controllers, (left_topic, right_topic), check=wheels
    )
    from diffbot.ramps import sampled

    limit_lines = built.limit_lines()
    if limit_lines:
        for line in limit_lines:
            click.echo(line, err=True)
        sys.exit(EXIT_CHECK_FAILED)
    if follow is not None:
        from diffbot.commands.drive_follow import LiveFollow, drive_follow

        pose = resolve_odom_topic(params, odom_topic) if pose_topic is None else pose_topic
        request = from_options(
            LiveFollow,
            "rate pose_timeout frame_id wait lead",
            law="pure-pursuit" if follow == "pure-pursuit" else "tracking",
            pose_topic=pose,
            from_odometry=pose_topic is None,
            cmd_vel=cmd_vel,
            stamped=stamped,
        )
        drive_follow(
            request,
            built.made,
            params,
            source.label,
            announce=announce,
            quiet=quiet,
            body=built.body,
        )
        return
    ramped = sampled(built.made)
    total = ramped.command_count(rate)
    planned = (total - 1) / rate  # the final zero's time
    from diffbot.live.drive import DriveSettings
    from diffbot.live.signals import deferred

    settings = from_options(
        DriveSettings,
        "frame_id wheels",
        left_topic=left_topic,
        right_topic=right_topic,
        cmd_vel=cmd_vel,
        stamped=stamped,
        joints=(max(len(params.left_joints), 1), max(len(params.right_joints), 1)),
    )
    # From the node's making on, a signal only stops the drive between two commands; it is
    # handed on (exit status 130, 143 or 129) once the robot was commanded zero.
    with deferred():
        report = _drive_live(
            ramped.command_chunks(rate), settings, total, source.label, wait, announce, quiet
        )
    if report is not None:
        click.echo(
            f"drove {source.label}: {report.sent} commands at {fmt(rate)} Hz over "
            f"{fmt(planned)} s, ending with zero; timing p99 "
            f"{report.percentile(0.99) * 1e3:.2f} ms late, "
            f"end {report.duration_error * 1e3:.2f} ms late",
            err=True,
        )


def _drive_live(
    pieces: Iterator[CommandStream],
    settings: DriveSettings,
    total: int,
    label: str,
    wait: float,
    announce: bool,
    quiet: bool,
) -> DriveReport | None:
    """Drive the commands once a subscriber matched; None when a signal came first. Says so
    when a signal cut the drive short."""
    from diffbot.commands.progress import progress
    from diffbot.live.drive import Driver
    from diffbot.live.signals import caught

    with Driver(pieces, settings) as driver:
        if announce:
            driver.announce()
        if not driver.wait_for_subscriber(wait):
            if caught() is not None:
                return None
            fail(f"no subscriber on {', '.join(driver.topics)} after {fmt(wait)} s")
        if driver.other_publishers():
            warn(
                f"another publisher sends on {', '.join(driver.topics)}: "
                "its commands mix with these"
            )
        with progress(total, label, "commands", quiet=quiet) as advance:
            report = driver.drive(advance)
        if not report.completed:
            click.echo(f"stopped after {report.sent} of {total} commands: commanded zero", err=True)
        return report
