"""``diffbot plan``: velocity commands, wheel speeds and exact poses of a path."""

from __future__ import annotations

import json
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, TextIO

import click

from diffbot.commands.options import (
    MAX_PUBLISH_RATE,
    MIN_COMMAND_RATE,
    NUMBERS,
    FiniteFloat,
    RobotOptions,
    fail,
    named_output,
    output_option,
    robot_options,
    warn,
)
from diffbot.commands.plan_options import (
    PLAN_FORMATS,
    PlanOptions,
    check_topic,
    frame_id_option,
    plan_input_options,
)
from diffbot.commands.shown_defaults import choice_option
from diffbot.commands.topic_options import (
    distro_option,
    resolve_cmd_vel,
    resolve_wheel_topics,
    wheel_topic_options,
)
from diffbot.errors import EXIT_CHECK_FAILED, OutputError
from diffbot.formats.command_stream import write_stream_csv, write_stream_json
from diffbot.formats.plan_data import plan_csv, plan_json
from diffbot.formats.plan_messages import plan_twist, plan_wheels
from diffbot.formats.plan_table import body_limit_line, plan_table
from diffbot.formats.text import fmt
from diffbot.io.command_bag import write_command_bag
from diffbot.io.outputs import atomic_text, check_not_input, input_clash, write_text_atomic
from diffbot.ros.script import ros2_script
from diffbot.trajectory import Plan

if TYPE_CHECKING:
    from diffbot.ramps import RampedPlan

#: Commands per second of a command bag unless --rate says otherwise.
BAG_RATE = 20.0
#: What the table of a ramped plan adds.
RAMP_NOTE = (
    "ramps: each run of equal curvature speeds up and slows down within the acceleration and\n"
    "jerk limits; v, w and the wheel speeds are each segment's peak, times are ramped\n"
)

__all__ = ["plan_command"]


@click.command("plan", context_settings=NUMBERS)
@click.argument("tokens", nargs=-1, metavar="[SPEC | FILE] [NAME:=VALUE]...")
@robot_options
@plan_input_options
@choice_option(
    "--format",
    "output_format",
    choices=PLAN_FORMATS,
    default="table",
    help="table: for people; json, csv: for programs; twist, wheels: ROS message lines; "
    "ros2: a shell script that publishes the plan.",
)
@click.option("--json", "as_json", is_flag=True, help="Same as --format json.")
@click.option(
    "--wide",
    is_flag=True,
    help="table: each wheel's speed in rad/s too, and the motor limit on the robot line (about "
    "130 columns; the default table fits 100).",
)
@click.option(
    "--wheels",
    "per_wheel",
    is_flag=True,
    help="ros2 script: publish per-wheel controller commands instead of cmd_vel Twists.",
)
@click.option(
    "--rate",
    type=FiniteFloat(MIN_COMMAND_RATE, maximum=MAX_PUBLISH_RATE),
    metavar="HZ",
    help="Sample the commands in time, each the mean over its period (csv, json, --bag; "
    f"bags default to {BAG_RATE:g} Hz); ros2 script: publishing rate (default 10). "
    f"From {MIN_COMMAND_RATE:g} to {MAX_PUBLISH_RATE:g}.",
)
@click.option(
    "--stamped",
    is_flag=True,
    help="geometry_msgs/TwistStamped commands instead of Twist (twist, json, ros2, --bag), as "
    "diff_drive_controller takes since ROS 2 Jazzy.",
)
@frame_id_option
@click.option(
    "--cmd-vel-topic",
    metavar="TOPIC",
    help="Twist topic (twist and ros2 formats, --bag) [the controllers file's diff-drive "
    "controller's /<name>/cmd_vel, TwistStamped from Jazzy on (cmd_vel_unstamped with "
    "use_stamped_vel: false on Humble), else the description's Gazebo classic diff-drive "
    "plugin's, else cmd_vel].",
)
@distro_option
@wheel_topic_options(
    "Left wheel Float64MultiArray topic (wheels format, ros2 --wheels).",
    "Right wheel topic, likewise.",
)
@output_option(
    "Write to this file (with --bag: this rosbag2 directory) instead of stdout, whole or "
    "not at all.",
    metavar="PATH",
)
@click.option(
    "--bag",
    "as_bag",
    is_flag=True,
    help="Write the commands sampled at --rate as a rosbag2 for 'ros2 bag play': Twist (or "
    "TwistStamped) on --cmd-vel-topic, Float64MultiArray on each wheel topic, from time zero, "
    "ending with zero.",
)
@click.option("--force", is_flag=True, help="Overwrite --output if it exists.")
def plan_command(
    robot: RobotOptions,
    tokens: tuple[str, ...],
    plan_options: PlanOptions,
    output_format: str,
    as_json: bool,
    wide: bool,
    per_wheel: bool,
    rate: float | None,
    stamped: bool,
    frame_id: str,
    cmd_vel_topic: str | None,
    distro: str | None,
    left_topic: str | None,
    right_topic: str | None,
    output: str | None,
    as_bag: bool,
    force: bool,
) -> None:
    """Velocity commands, wheel speeds and exact poses of a path.

    SPEC is a plan in text form, segments separated by ';' or newlines ('#' comments):

    \b
      straight LENGTH [DURATION]
      ccw RADIUS ANGLE [DURATION]     counter-clockwise (left) arc
      cw RADIUS ANGLE [DURATION]      clockwise (right) arc
      spin ANGLE [DURATION]           turn in place, positive = counter-clockwise
      straight -LENGTH, reverse ccw|cw RADIUS ANGLE   drive backwards

    Lengths are in m (or 25cm, 250mm), angles in degrees (or 1.57rad), durations in s (10s).
    Several arguments are joined: each starts a segment ('straight 1' 'spin 90' is 'straight 1;
    spin 90'), except one that starts with a number, which continues the segment before it (so
    straight 1 10s and spin -90deg need no quotes).
    FILE is a .yaml/.yml list such as [{straight: 1, duration: 10}, {arc: ccw, radius: 0.25,
    angle: 180}, {spin: 90}], the same in .json ([{"straight": 1, "duration": 10}, {"spin":
    90}]), or a .txt file in text form. Without either, Trajectory A is planned
    (--example A).

    With --max-accel, --max-angular-accel, --max-wheel-accel or --max-jerk (or the limits of the
    robot's diff_drive_controller configuration, unless --steps), each run of segments of equal
    curvature is driven with a speed ramp (S-curve under a jerk limit) on the same path: poses
    stay exact, and the robot stops only where the curvature changes. Such a plan is many
    commands: --rate HZ samples them (csv, json), --out DIR --bag writes them for 'ros2 bag play'.

    Segments without a duration run at --speed (spins at --spin-rate). The robot starts at
    (0, 0) heading along x. Exit code 1 when a wheel exceeds the motor limit, or a segment's
    velocity the body limits (--max-linear, --max-angular, or the controller's linear.x and
    angular.z max_velocity); the output is still printed, and the message names the segment and
    the shortest duration that fits. Segments the plan times itself (--speed, --fastest, goal
    plans) take as long as the body limits ask.

    \b
    Examples:
      diffbot plan                                    Trajectory A (the default)
      diffbot plan "straight 1 10s; ccw 25cm 90; spin -90 2s"
      diffbot plan --example B --fastest
      diffbot plan docs/examples/path.yaml --format ros2 -o run.sh
                                                      a script of 'ros2 topic pub' commands
      diffbot plan --to 0,1,0                         the fastest way to (0 m, 1 m, 0 deg)
    """

    if as_json and output_format not in ("table", "json"):
        fail(f"--json and --format {output_format} ask for two formats: give one")
    if as_json:
        output_format = "json"
    if per_wheel and output_format != "ros2":
        warn("--wheels only changes --format ros2 (the wheels format is always per wheel)")
    if stamped and (output_format in ("table", "csv", "wheels") or per_wheel) and not as_bag:
        warn("--stamped changes Twist commands only (twist, json, ros2 and --bag)")
    if frame_id != "base_link" and not stamped:
        warn("--frame-id only applies to --stamped commands")
    if cmd_vel_topic is not None:
        check_topic("--cmd-vel-topic", cmd_vel_topic)
    for option, given in (("--left-topic", left_topic), ("--right-topic", right_topic)):
        if given is not None:
            check_topic(option, given)
    request = plan_options.request(robot, tokens)
    source = request.source
    # Early, before any work, and in the plan's own words; write_text_atomic checks again.
    plan_file = [Path(source.path)] if source.path is not None else []
    named_output(output, bag=as_bag)
    if output is not None:
        clash = input_clash(Path(output), plan_file)
        if clash is not None and clash[0] == "is" and clash[1] in plan_file:
            fail(f"{output} is the plan file itself: write the output elsewhere")
        check_not_input(Path(output), inputs=plan_file)
    writes = output is not None or as_bag or output_format != "table"
    built = plan_options.build(request, writes=writes)
    source, params, made = built.source, built.params, built.made
    # Checked only where the topic is written: a table or a wheel format names none.
    sends_twist = as_bag or output_format == "twist" or (output_format == "ros2" and not per_wheel)
    cmd_vel_topic, stamped = resolve_cmd_vel(
        params, cmd_vel_topic, stamped, distro, "--cmd-vel-topic" if sends_twist else None
    )
    sends_wheels = as_bag or output_format == "wheels" or (output_format == "ros2" and per_wheel)
    left_topic, right_topic = resolve_wheel_topics(
        params, robot.controllers, (left_topic, right_topic), check=sends_wheels
    )
    ramped: RampedPlan | None = None
    p = made if isinstance(made, Plan) else made.summary
    if not isinstance(made, Plan):
        ramped = made
    frame = frame_id if stamped else None
    if as_bag:
        if output is None:
            fail("--bag writes the --out directory: give --out DIR")
        if as_json or output_format != "table":
            fail("--bag writes a bag: give it without --format and --json")
        bag_rate = BAG_RATE if rate is None else rate
        commands = _commands(made)
        count = commands.command_count(bag_rate)
        write_command_bag(
            Path(output),
            commands.command_chunks(bag_rate),
            cmd_vel=cmd_vel_topic,
            left_topic=left_topic,
            right_topic=right_topic,
            stamped=stamped,
            frame_id=frame_id,
            joints=(len(params.left_joints), len(params.right_joints)),
            force=force,
        )
        kind = "TwistStamped" if stamped else "Twist"
        click.echo(
            f"wrote {count} commands at {fmt(bag_rate)} Hz "
            f"({fmt((count - 1) / bag_rate)} s) to {output}: {kind} on {cmd_vel_topic}, "
            f"Float64MultiArray on {left_topic} and {right_topic}"
        )
        _check_limit(built.limit_lines())
        return
    if rate is not None and output_format in ("csv", "json"):
        commands = _commands(made)
        count = commands.command_count(rate)

        def write(out: TextIO) -> None:
            assert rate is not None
            if output_format == "csv":
                write_stream_csv(commands.command_chunks(rate), out)
            else:
                document = _with_frame(
                    plan_json(
                        p, source.label, steps=built.steps, body=built.body, start=source.start
                    )
                    | {"commands": None},
                    frame,
                )
                write_stream_json(document, lambda: commands.command_chunks(rate), rate, count, out)

        read = [source.path, *params.description_files]
        _write_streamed(write, output, force, [Path(x) for x in read if x is not None])
        _check_limit(built.limit_lines())
        return
    if ramped is not None and output_format in ("csv", "twist", "wheels", "ros2"):
        fail(
            "a ramped plan is many commands: sample them with --rate HZ (--format csv or json), "
            "write a command bag with --out DIR --bag for 'ros2 bag play', or plan velocity "
            "steps with --steps"
        )
    if rate is not None and output_format in ("table", "twist", "wheels"):
        warn(
            f"--rate changes nothing with --format {output_format} (it samples csv and json, "
            "times --bag and the ros2 script)"
        )
    if output_format == "json":
        data = plan_json(p, source.label, steps=built.steps, body=built.body, start=source.start)
        if ramped is not None:
            data["runs"] = [
                {
                    "segments": [i + 1 for i in run.segments],
                    "start": run.start,
                    "duration": run.duration,
                }
                for run in ramped.runs
            ]
        text = _json_text(data, frame)
    elif output_format == "csv":
        text = plan_csv(p)
    elif output_format == "twist":
        text = plan_twist(p, source.label, cmd_vel_topic, stamped=stamped, frame_id=frame_id)
    elif output_format == "wheels":
        text = plan_wheels(p, source.label, left_topic, right_topic)
    elif output_format == "ros2":
        text = ros2_script(
            p,
            source.label,
            wheels=per_wheel,
            rate=10.0 if rate is None else rate,
            cmd_vel=cmd_vel_topic,
            left_topic=left_topic,
            right_topic=right_topic,
            stamped=stamped,
            frame_id=frame_id,
        )
    else:
        text = plan_table(p, source.label, wide=wide, steps=built.steps)
        text += body_limit_line(built.steps, built.body)
        text += source.note
        if ramped is not None:
            text += RAMP_NOTE
    if output is None:
        click.echo(text, nl=False)
    else:
        inputs = [path for path in (source.path, *params.description_files) if path is not None]
        write_text_atomic(
            Path(output),
            text,
            force=force,
            inputs=[Path(path) for path in inputs],
            executable=output_format == "ros2",
        )
    _check_limit(built.limit_lines())


def _check_limit(lines: list[str]) -> None:
    """Exit 1, naming every segment over the motor or a body velocity limit, when there is one."""
    if lines:
        for line in lines:
            click.echo(line, err=True)
        sys.exit(EXIT_CHECK_FAILED)


def _with_frame(data: dict[str, Any], frame_id: str | None) -> dict[str, Any]:
    if frame_id is not None:
        data["message_type"] = "geometry_msgs/msg/TwistStamped"
        data["frame_id"] = frame_id
    return data


def _json_text(data: dict[str, Any], frame_id: str | None) -> str:
    return json.dumps(_with_frame(data, frame_id), indent=2, allow_nan=False) + "\n"


def _write_streamed(
    writer: Callable[[TextIO], None], output: str | None, force: bool, inputs: Sequence[Path]
) -> None:
    """Write text as it comes: to stdout, or to ``output`` whole or not at all."""
    if output is None:
        writer(sys.stdout)
        return
    with atomic_text(Path(output), force=force, inputs=inputs) as out:
        try:
            writer(out)
        except OSError as err:  # a full disk, a quota
            raise OutputError(f"{output}: cannot write ({err.strerror})", path=output) from None


def _commands(made: Plan | RampedPlan) -> RampedPlan:
    """The plan whose commands are sampled: a step plan as a ramped plan without ramps."""
    from diffbot.ramps import sampled

    return sampled(made)


# --------------------------------------------------------------------------------------------
