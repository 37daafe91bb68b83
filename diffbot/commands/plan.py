"""``diffbot plan``: velocity commands, wheel speeds and exact poses of a path."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import click

from diffbot.commands.options import (
    MAX_PUBLISH_RATE,
    NUMBERS,
    FiniteFloat,
    RobotOptions,
    fail,
    robot_options,
    split_xacro_args,
    warn,
)
from diffbot.commands.plan_options import (
    PLAN_FORMATS,
    PlanOptions,
    check_topic,
    plan_input,
    plan_input_options,
)
from diffbot.errors import EXIT_CHECK_FAILED
from diffbot.formats.plan_data import plan_csv, plan_json
from diffbot.formats.plan_messages import plan_twist, plan_wheels
from diffbot.formats.plan_table import plan_table, violation_lines
from diffbot.io.outputs import input_clash, write_text_atomic
from diffbot.ros.script import ros2_script

__all__ = ["plan_command"]


@click.command("plan", context_settings=NUMBERS)
@click.argument("tokens", nargs=-1, metavar="[SPEC | FILE] [NAME:=VALUE]...")
@robot_options
@plan_input_options
@click.option(
    "--format",
    "output_format",
    type=click.Choice(PLAN_FORMATS),
    default="table",
    show_default=True,
    help="table: for people; json, csv: for programs; twist, wheels: ROS message lines; "
    "ros2: a shell script that publishes the plan.",
)
@click.option("--json", "as_json", is_flag=True, help="Same as --format json.")
@click.option(
    "--wheels",
    "per_wheel",
    is_flag=True,
    help="ros2 script: publish per-wheel controller commands instead of cmd_vel Twists.",
)
@click.option(
    "--rate",
    type=FiniteFloat(0.0, open_min=True, maximum=MAX_PUBLISH_RATE),
    default=10.0,
    show_default=True,
    metavar="HZ",
    help=f"ros2 script: publishing rate (Hz, at most {MAX_PUBLISH_RATE:g}).",
)
@click.option(
    "--cmd-vel-topic",
    default="cmd_vel",
    show_default=True,
    metavar="TOPIC",
    help="Twist topic (twist and ros2 formats).",
)
@click.option(
    "--left-topic",
    default="left_wheel_velocity_controller/commands",
    show_default=True,
    metavar="TOPIC",
    help="Left wheel Float64MultiArray topic (wheels format, ros2 --wheels).",
)
@click.option(
    "--right-topic",
    default="right_wheel_velocity_controller/commands",
    show_default=True,
    metavar="TOPIC",
    help="Right wheel topic, likewise.",
)
@click.option(
    "-o",
    "--output",
    type=click.Path(dir_okay=False),
    help="Write to this file instead of stdout (whole or not at all).",
)
@click.option("--force", is_flag=True, help="Overwrite --output if it exists.")
def plan_command(
    robot: RobotOptions,
    tokens: tuple[str, ...],
    plan_options: PlanOptions,
    output_format: str,
    as_json: bool,
    per_wheel: bool,
    rate: float,
    cmd_vel_topic: str,
    left_topic: str,
    right_topic: str,
    output: str | None,
    force: bool,
) -> None:
    """Velocity commands, wheel speeds and exact poses of a path.

    SPEC is a plan in text form, segments separated by ';' or newlines ('#' comments):

    \b
      straight LENGTH [DURATION]
      ccw RADIUS ANGLE [DURATION]     counter-clockwise (left) arc
      cw RADIUS ANGLE [DURATION]      clockwise (right) arc
      spin ANGLE [DURATION]           turn in place, positive = counter-clockwise

    Lengths are in m (or 25cm, 250mm), angles in degrees (or 1.57rad), durations in s (10s).
    Several arguments are joined: each starts a segment ('straight 1' 'spin 90' is 'straight 1;
    spin 90'), except one that starts with a number, which continues the segment before it (so
    straight 1 10s and spin -90deg need no quotes).
    FILE is a .yaml/.yml list such as [{straight: 1, duration: 10}, {arc: ccw, radius: 0.25,
    angle: 180}, {spin: 90}], the same in .json ([{"straight": 1, "duration": 10}, {"spin":
    90}]), or a .txt file in text form. Without either, the seed's Trajectory A is planned
    (--example A).

    Segments without a duration run at --speed (spins at --spin-rate). The robot starts at
    (0, 0) heading along x. Exit code 1 when a wheel exceeds the motor limit (the output is still
    printed); the message names the segment, the wheel and the shortest duration that fits.

    \b
    Examples:
      diffbot plan                                    the seed's Trajectory A
      diffbot plan "straight 1 10s; ccw 25cm 90; spin -90 2s"
      diffbot plan --example B --fastest
      diffbot plan path.yaml --format ros2 -o run.sh  a script of 'ros2 topic pub' commands
    """

    rest, xacro_args = split_xacro_args(tokens)
    if as_json and output_format not in ("table", "json"):
        fail(f"--json and --format {output_format} ask for two formats: give one")
    if as_json:
        output_format = "json"
    if per_wheel and output_format != "ros2":
        warn("--wheels only changes --format ros2 (the wheels format is always per wheel)")
    check_topic("--cmd-vel-topic", cmd_vel_topic)
    check_topic("--left-topic", left_topic)
    check_topic("--right-topic", right_topic)
    source = plan_input(rest, plan_options.example)
    # Early, before any work, and in the plan's own words; write_text_atomic checks again.
    plan_file = [Path(source.path)] if source.path is not None else []
    if output is not None and input_clash(Path(output), plan_file) is not None:
        fail(f"{output} is the plan file itself: write the output elsewhere")
    params = robot.with_path(None, xacro_args).load()
    if plan_options.fastest and plan_options.limit is None and params.max_wheel_speed is None:
        fail(
            "--fastest needs a motor limit, and the robot description has none: "
            "give one with --max-rpm RPM or --rpm-limit RPM"
        )
    p = plan_options.make(source.segments, params)
    if output_format == "json":
        text = json.dumps(plan_json(p, source.label), indent=2, allow_nan=False) + "\n"
    elif output_format == "csv":
        text = plan_csv(p)
    elif output_format == "twist":
        text = plan_twist(p, source.label, cmd_vel_topic)
    elif output_format == "wheels":
        text = plan_wheels(p, source.label, left_topic, right_topic)
    elif output_format == "ros2":
        text = ros2_script(
            p,
            source.label,
            wheels=per_wheel,
            rate=rate,
            cmd_vel=cmd_vel_topic,
            left_topic=left_topic,
            right_topic=right_topic,
        )
    else:
        text = plan_table(p, source.label)
    if output is None:
        click.echo(text, nl=False)
    else:
        inputs = [path for path in (source.path, robot.robot) if path is not None]
        write_text_atomic(
            Path(output),
            text,
            force=force,
            inputs=[Path(path) for path in inputs],
            executable=output_format == "ros2",
        )
    if not p.within_limit:
        for line in violation_lines(p):
            click.echo(line, err=True)
        sys.exit(EXIT_CHECK_FAILED)


# --------------------------------------------------------------------------------------------
