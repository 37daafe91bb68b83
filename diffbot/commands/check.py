"""``diffbot check``: the description, controller and Gazebo plugins cross-checked, for CI."""

from __future__ import annotations

import sys

import click

from diffbot.commands.options import (
    RobotOptions,
    emit_json,
    robot_options,
    warn,
)
from diffbot.commands.said_once import quieted, shown_before
from diffbot.errors import EXIT_CHECK_FAILED
from diffbot.formats.robot import check_lines, disagreement_json, multipliers_json

__all__ = ["check"]


@click.command()
@click.argument("tokens", nargs=-1, metavar="[PATH] [NAME:=VALUE]...")
@robot_options
@click.option("--json", "as_json", is_flag=True, help="Machine-readable output.")
def check(robot: RobotOptions, tokens: tuple[str, ...], as_json: bool) -> None:
    """Cross-check a robot's description, controller configuration and Gazebo plugins.

    Compares the wheel separation and radius (within 0.5 mm) and the wheel joints of each side
    that the URDF/xacro geometry, the diff_drive_controller configuration (--controllers, or the
    file the description's ros2_control Gazebo plugin names) and any Gazebo diff-drive plugin
    (classic gazebo_ros_diff_drive or gazebo_ros_skid_steer_drive, gz-sim DiffDrive) give. The
    controller's base values are compared; its multipliers are deliberate settings (a skid
    steer's separation correction), shown but not compared. Exit code 0 when they agree, 1 when
    they disagree: a lint a robot repository can run in its CI.

    \b
    Examples:
      diffbot check docs/examples/rover/urdf/rover.urdf.xacro \\
          --package rover_description=docs/examples/rover
      diffbot check docs/examples/tutorial_bot/tutorial_bot.urdf --json
                               exit code 1: its Gazebo plugin says b = 0.4 m
    """
    p = robot.with_tokens(tokens).load(quiet=True)
    if as_json:
        emit_json(
            {
                "robot": p.source,
                "controller": None if p.controller is None else p.controller.name,
                "sources": dict(p.sources),
                "multipliers": multipliers_json(p),
                "disagreements": [disagreement_json(d) for d in p.disagreements],
                "agree": not p.disagreements,
            }
        )
    else:
        for line in check_lines(p):
            click.echo(line)
        for message in p.warnings:
            if not message.startswith("the sources "):  # each disagreement is shown above
                warn(message)
        if p.warnings and not quieted():
            shown_before(p.source, p.warnings)  # shown in full: later commands count them
    if p.disagreements:
        sys.exit(EXIT_CHECK_FAILED)
