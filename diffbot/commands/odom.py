"""``diffbot odom``: odometry from recorded wheel joint positions."""

from __future__ import annotations

import glob
import io
import json
import math
import re
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from diffbot.commands import options as opt
from diffbot.commands.options import OutOptions, RobotOptions
from diffbot.commands.paths import input_path
from diffbot.commands.progress import progress
from diffbot.commands.recording_options import (
    RecordingOptions,
    conditioning_lines,
    exit_if_implausible,
    has_implausible_steps,
    recording_options,
    robot_label,
    skipped_text,
    warn_conditioning,
    warn_notes,
)
from diffbot.errors import EXIT_CHECK_FAILED
from diffbot.formats.text import fmt
from diffbot.io.outputs import check_not_input
from diffbot.odometry import SKIP_MISSING_JOINT

if TYPE_CHECKING:
    from diffbot.chunk_odometry import OdometrySummary
    from diffbot.fleet import OdometryResult, OdometryTask
    from diffbot.kinematics import DiffDriveParams
    from diffbot.reference import ReferenceResult

__all__ = ["odom"]

_GLOB = re.compile(r"[*?[]")


def _expand(sources: list[str]) -> list[str]:
    """The inputs, globs expanded (for shells that pass them on, or quoted ones)."""
    found: list[str] = []
    for source in sources:
        if not source.strip():
            opt.fail("INPUT is empty: give a CSV file, - for stdin, or a rosbag2 recording")
        if _GLOB.search(source) and not Path(source).exists():
            matches = sorted(glob.glob(source))
            if not matches:
                opt.fail(f"{source}: no file or directory matches")
            found.extend(matches)
        else:
            found.append(source)
    return [input_path(source) for source in found]  # all of them before any output


def _stdin_stream() -> io.TextIOWrapper:
    """The CSV on stdin as text, read as it comes (``diffbot simulate | diffbot odom -``)."""
    return io.TextIOWrapper(sys.stdin.buffer, encoding="utf-8-sig", newline="")


def _repeat_text(summary: OdometrySummary, kind: str) -> str:
    """Why samples were skipped for their stamps, and the rule applied (a CSV's rows, a bag's
    messages)."""
    if summary.first_repeat_ns is None:
        return ""
    from diffbot.samples import seconds_text

    start = f" (from stamp {seconds_text(summary.first_repeat_ns)} s on, "
    if kind == "csv":
        return start + (
            "rows whose stamp is not after the one before: rows out of order or repeated; the "
            "first row of each stamp is used, and only rows later than every one used)"
        )
    return start + (
        "samples whose stamp is not after the one before: two publishers on the topic, or a "
        "clock that went back; the first sample of each stamp is used, and only samples later "
        "than every one used)"
    )


def _missing_text(summary: OdometrySummary, kind: str) -> str:
    """What a bag's messages without a whole side may be (a CSV's are rows with empty cells)."""
    if kind == "csv" or not summary.skipped.get(SKIP_MISSING_JOINT):
        return ""
    return (
        " (messages without a wheel joint of each side: another publisher's on the topic, such "
        "as an arm's, or a side's wheels published apart)"
    )


def _feedback(task: OdometryTask) -> str:
    """What the odometry was computed from: ``position``, ``velocity`` or ``open-loop``."""
    return "open-loop" if task.open_loop else task.feedback


def _summary(result: OdometryResult) -> dict[str, Any]:
    run = result.run
    assert run is not None
    summary = run.summary
    pose = summary.final_pose
    return {
        "input": result.task.input,
        "feedback": _feedback(result.task),
        "final_pose": {"x": pose.x, "y": pose.y, "theta": pose.theta},
        "distance": summary.distance,
        "samples": summary.samples,
        "skipped": dict(sorted(summary.skipped.items())),
        "duration": summary.duration,
        "clock": run.clock,
        "output": result.task.output,
        "implausible_steps": run.conditioning.implausible_steps,
        "wrap": run.conditioning.wrap,
    } | ({} if result.reference is None else {"reference": result.reference.as_dict()})


def _error_text(result: OdometryResult) -> str:
    from diffbot.cli import FLAGS

    assert result.error is not None
    return " ".join(result.error.render(FLAGS.__getitem__).split())


@click.command()
@click.argument("tokens", nargs=-1, metavar="INPUT... [NAME:=VALUE]...")
@opt.robot_options
@opt.topic_option(
    "The sensor_msgs/JointState topic of a bag (with --open-loop, its Twist or TwistStamped "
    "command topic: default /cmd_vel, or else the bag's only one).",
    reading=True,
)
@recording_options
@click.option(
    "--open-loop",
    is_flag=True,
    help="Integrate the commanded body velocities instead (open_loop: true): a bag's "
    "--topic (default /cmd_vel) or a CSV of t,v,w (s, m/s, rad/s), each command held until "
    "the next.",
)
@click.option(
    "--reference",
    metavar="TOPIC",
    help="Hold the odometry against a pose topic of the same bag (the robot's own odometry, "
    "nav_msgs/Odometry, or a PoseStamped track): final, max and RMS differences; --out adds "
    "its poses as columns.",
)
@opt.out_options(
    "Write the poses: a CSV file (time,x,y,theta,linear,angular), or a bag with --bag; "
    "with several inputs, a directory that gets one output per input.",
    "Write --out as a rosbag2 directory: nav_msgs/Odometry on /odom, TF on /tf.",
)
@click.option(
    "--jobs",
    "-j",
    type=opt.Count(1),
    default=1,
    show_default=True,
    metavar="N",
    help="Read several inputs in N processes at once.",
)
@click.option(
    "--dask",
    "dask_address",
    metavar="ADDRESS",
    help="Run the inputs on a Dask cluster (its scheduler, tcp://HOST:PORT; extra 'fleet'). "
    "Its workers must see the inputs and outputs at the same absolute paths.",
)
@click.option(
    "--dask-timeout",
    type=opt.FiniteFloat(0.0, open_min=True, maximum=3600.0),
    default=10.0,
    show_default=True,
    metavar="SECONDS",
    help="How long to wait for the Dask scheduler to answer.",
)
@opt.quiet_option
@click.option("--json", "as_json", is_flag=True, help="Machine-readable summary.")
def odom(
    robot: RobotOptions,
    tokens: tuple[str, ...],
    topic: str | None,
    recording: RecordingOptions,
    open_loop: bool,
    reference: str | None,
    out: OutOptions,
    jobs: int,
    dask_address: str | None,
    dask_timeout: float,
    quiet: bool,
    as_json: bool,
) -> None:
    """Odometry from recorded wheel joint positions (or velocities, or commands).

    INPUT is a CSV file (a time column `time`, `stamp`, `t` or `__time` in seconds, and one
    position column per wheel named by its joint or ending with `/<joint>/position`; `-` reads
    it from stdin), a rosbag2
    directory (sqlite3 or mcap) or one of its .db3/.mcap files holding sensor_msgs/JointState on
    --topic. A bag's samples are all stamped by their header stamps, or all by the bag's receive
    times when any header stamp is zero (the summary says which). Each step is integrated
    exactly along its arc; the first sample sets the encoder baseline. A side with several
    wheels is the mean of their angles, and moves by the motion of those a sample has when it
    lacks some (never by their encoders' offsets). Samples without a whole side,
    with NaN/inf or with a stamp not after the previous one are skipped and reported.

    With --feedback velocity the wheels' velocities are read instead (a bag's JointState
    `velocity` fields, a CSV's columns ending with `/<joint>/velocity` or named by
    --left-column/--right-column), each sample's velocity held over the interval that ends at
    it, as diff_drive_controller integrates them. A recording whose positions never change
    while its velocities do is refused, naming --feedback velocity. With --open-loop the
    commands are integrated: compare them with the wheels' odometry of the same run through
    --reference or --out.

    Positions may be encoder counts (--counts-per-rev) from a counter that wraps around
    (--wrap; detected by itself when not given, and said so). A step no wheel can make (far
    beyond the motor limit, or beyond a rim speed of 30 m/s without one) is counted and
    reported with its first sample and time, and the exit code is then 1.

    Inputs are read in chunks and the poses written as they come, in constant memory; a
    progress bar shows on stderr when it is a terminal (not with --quiet). Several inputs
    (files, bag folders, globs) give one row each (JSON lines with --json) and, with --out DIR,
    one output each; a recording that cannot be read is reported in its row, and the exit code
    is then 1.

    \b
    Reading bags needs the optional rosbags dependency:
      pip install 'rosbags>=0.11'     (or, in a clone: pip install -e '.[bag]')

    \b
    Examples:
      diffbot odom docs/examples/joints.csv
      diffbot simulate "straight 1; spin 90" | diffbot odom -
      diffbot simulate --example B -o b_bag --bag && diffbot odom b_bag --topic /joint_states
      diffbot odom b_bag -o odom_bag --bag --json
      diffbot odom docs/examples/joints.csv b_bag --jobs 2 -o poses/ --json
      diffbot odom docs/examples/wheel_velocities.csv --feedback velocity
      diffbot odom docs/examples/commands.csv --open-loop
    """
    from diffbot.fleet import OdometryTask
    from diffbot.fleet import dask_address as checked_address

    if dask_address is not None:
        dask_address = checked_address(dask_address)
    rest, xacro_args = opt.split_xacro_args(tokens)
    if not rest:
        opt.fail(
            "expected an INPUT (a CSV file, - for a CSV on stdin, a rosbag2 directory or a "
            ".db3/.mcap file)"
        )
    sources = _expand(rest)
    conditioning = recording.conditioning()
    layout = recording.layout()
    out.require_out_for_bag()
    robot = robot.with_path(None, xacro_args)

    def task(source: str, output: str | None) -> OdometryTask:
        return OdometryTask(
            source,
            p,
            topic,
            output,
            out.as_bag,
            out.force,
            conditioning,
            layout,
            reference,
            recording.feedback_for(p),
            open_loop,
        )

    if open_loop and recording.feedback is not None:
        opt.fail("--open-loop integrates the commands, not the wheels' --feedback: choose one")
    if open_loop and (recording.counts_per_rev is not None or recording.wrap is not None):
        opt.fail("--open-loop reads commands: --counts-per-rev and --wrap apply to the wheels")
    if len(sources) > 1:
        if "-" in sources:
            opt.fail("- (a CSV on stdin) cannot be read with other inputs")
        p = robot.load()
        if not open_loop:  # commanded twists do not depend on the wheels' geometry
            recording.check_robot(robot, p)
            tell_open_loop(p)
        if out.as_bag:
            check_bag_frames(p)
        outputs = _outputs(sources, out)
        tasks = [task(source, output) for source, output in zip(sources, outputs, strict=True)]
        _many(
            tasks,
            jobs,
            (dask_address, dask_timeout),
            quiet=quiet,
            as_json=as_json,
            robot=robot_label(robot),
        )
        return
    source = sources[0]
    from_stdin = source == "-"
    if not from_stdin and not Path(source).exists():
        opt.fail(f"{source}: no such file or directory")
    inputs = [Path(path) for path in (None if from_stdin else source, robot.robot) if path]
    out.path(inputs)
    p = robot.load()
    if not open_loop:
        recording.check_robot(robot, p)
        tell_open_loop(p)
    if out.as_bag:
        check_bag_frames(p)
    out_path = out.path([*inputs, *(Path(path) for path in p.description_files)])
    output = None if out_path is None else str(out_path)
    _one(task(source, output), quiet, as_json, out, robot_label(robot))


def check_bag_frames(params: DiffDriveParams) -> None:
    """Bad input when the frames the robot's controller publishes in (those --bag writes) are
    no usable frame ids, as node odom refuses them."""
    from diffbot.live.names import frame_problem
    from diffbot.numbers import shown

    controller = params.controller
    if controller is None:
        return
    for frame in (controller.odom_frame, controller.base_frame):
        problem = frame_problem(frame)
        if problem is not None:
            opt.fail(
                f"{controller.source}: the frame {shown(frame)} its controller {controller.name} "
                f"publishes in {problem}"
            )


def tell_open_loop(
    params: DiffDriveParams,
    instead: str = "this is the wheels' odometry: --open-loop integrates the commands as the "
    "controller does",
) -> None:
    """Say that the controller's own odometry comes from its commands (``open_loop: true``) when
    the wheels' odometry is computed instead; ``instead`` says what is done."""
    from diffbot.commands.said_once import quieted, shown_before

    controller = params.controller
    if controller is None or not controller.open_loop or quieted():
        return
    message = (
        f"{controller.source}: {controller.name} computes its odometry from its commands "
        f"(open_loop: true); {instead}"
    )
    if not shown_before(controller.source, [message]):  # said once for a controllers file
        opt.warn(message)


def _one(task: OdometryTask, quiet: bool, as_json: bool, out: OutOptions, robot: str) -> None:
    """One input: the detailed summary."""
    from diffbot.fleet import run_task
    from diffbot.io.bag import is_bag
    from diffbot.io.recordings import recording_size

    source, topic = task.input, task.topic
    from_stdin = source == "-"
    total = None if from_stdin or task.open_loop else recording_size(source, topic)
    unit = "B" if from_stdin or not is_bag(source) else "msg"
    stream = _stdin_stream() if from_stdin else None
    with progress(total, Path(source).name, unit, quiet=quiet) as advance:
        result = run_task(task, advance, stream)
    if result.error is not None:
        raise result.error
    run = result.run
    assert run is not None
    summary = run.summary
    skipped_total = sum(summary.skipped.values())
    if skipped_total:
        opt.warn(
            f"skipped {skipped_total} of {summary.samples + skipped_total} samples: "
            f"{skipped_text(summary.skipped)}{_missing_text(summary, run.kind)}"
            f"{_repeat_text(summary, run.kind)}"
        )
    warn_notes(run.notes, source)
    warn_conditioning(run.conditioning, source, commands=result.task.open_loop)
    pose = summary.final_pose
    if as_json:
        opt.emit_json(_summary(result) | {"output": out.out, "robot": robot})
        _exit_if_implausible(result)
        return
    only = "command" if task.open_loop else "JointState"
    chosen = f" (its only {only} topic)" if run.topic_chosen else ""
    bag = "ROS 1 bag" if run.kind == "rosbag1" else "rosbag2"
    kind = "CSV" if run.kind == "csv" else f"{bag}, topic {run.topic}{chosen}, {run.clock} stamps"
    rows = [
        ("input", f"{source} ({kind})"),
        ("robot", robot),
        ("samples", f"{summary.samples} used, {skipped_total} skipped"),
        ("duration", f"{fmt(summary.duration)} s"),
        ("distance", f"{fmt(summary.distance)} m"),
        (
            # Rounded to the nanometre (nanoradian) so rounding noise reads as 0; --json has all.
            "final pose",
            f"x {fmt(round(pose.x, 9))} m, y {fmt(round(pose.y, 9))} m, "
            f"theta {fmt(round(pose.theta, 9))} rad "
            f"({fmt(round(math.degrees(pose.theta), 7), 5)} deg)",
        ),
    ]
    if out.out is not None:
        what = "rosbag2: /odom, /tf" if out.as_bag else "CSV"
        rows.append(("output", f"{out.out} ({what}, {result.poses} poses)"))
    rows[2:2] = conditioning_lines(run.conditioning)
    if _feedback(task) != "position":
        rows.insert(2, ("feedback", _feedback_text(task)))
    if result.reference is not None:
        rows.append(("reference", _reference_text(result.reference)))
    for label, value in rows:
        click.echo(f"{label:<11} {value}")
    _exit_if_implausible(result)


def _feedback_text(task: OdometryTask) -> str:
    """What the odometry integrated, for people."""
    if task.open_loop:
        return "open loop: the commanded velocities, each held until the next"
    if task.feedback == "velocity":
        return "wheel velocities, each held over the interval before its sample"
    return "wheel positions"


def _reference_text(reference: ReferenceResult) -> str:
    """The comparison with the reference on one line."""
    if not reference.samples:
        return f"{reference.topic}: {reference.no_overlap_text()}"
    return (
        f"{reference.topic}, {reference.samples} poses: final "
        f"{fmt(reference.final_position_error, 3)} m, "
        f"{fmt(math.degrees(reference.final_heading_error), 3)} deg; max "
        f"{fmt(reference.max_position_error, 3)} m, RMS {fmt(reference.rms_position_error, 3)} m"
    )


def _exit_if_implausible(result: OdometryResult) -> None:
    """Exit 1 after the summary when a step was implausible: the pose is not to be trusted."""
    if result.run is not None:
        exit_if_implausible([result.run.conditioning])


def _outputs(sources: list[str], out: OutOptions) -> list[str | None]:
    """The output of each input in the --out directory (made if missing), or None each."""
    from diffbot.fleet import output_name

    if out.out is None:
        return [None] * len(sources)
    folder = Path(out.out)
    if folder.exists() and not folder.is_dir():
        opt.fail(f"--out {out.out} is not a directory: several inputs write one output each")
    names = [output_name(source, out.as_bag) for source in sources]
    twice = sorted({name for name in names if names.count(name) > 1})
    if twice:
        opt.fail(f"several inputs would write --out {out.out}/{twice[0]}: rename one")
    for name in names:  # each output against every input, not only its own
        check_not_input(folder / name)
    folder.mkdir(parents=True, exist_ok=True)
    return [str(folder / name) for name in names]


def _many(
    tasks: list[OdometryTask],
    jobs: int,
    dask: tuple[str | None, float],
    *,
    quiet: bool,
    as_json: bool,
    robot: str,
) -> None:
    """Several inputs: one row (or JSON line) each; exit 1 when any failed."""
    from diffbot.fleet import run_tasks

    failed = 0
    with progress(len(tasks), "recordings", "rec", quiet=quiet) as advance:
        results = list(
            run_tasks(
                tasks,
                jobs=jobs,
                dask_address=dask[0],
                dask_timeout=dask[1],
                done=lambda _: advance(1),
            )
        )
    # The inputs' column as wide as the longest name, so the other columns stay aligned.
    width = max([24, *(len(result.task.input) for result in results)])
    if not as_json:
        click.echo(f"robot {robot}")
        click.echo(
            f"{'input':<{width}} {'samples':>9} {'skipped':>8} {'distance m':>11} final pose"
        )
    implausible = 0
    for result in results:
        if result.error is not None:
            failed += 1
            if as_json:
                line = {"input": result.task.input, "error": _error_text(result)}
                click.echo(json.dumps(line, allow_nan=False))
            else:
                click.echo(f"{result.task.input:<{width}} error: {_error_text(result)}")
            continue
        assert result.run is not None
        warn_notes(result.run.notes, result.task.input)
        warn_conditioning(
            result.run.conditioning, result.task.input, commands=result.task.open_loop
        )
        implausible += has_implausible_steps(result.run.conditioning)
        data = _summary(result) | {"robot": robot}
        if as_json:
            click.echo(json.dumps(data, allow_nan=False))
            continue
        pose = data["final_pose"]
        click.echo(
            f"{result.task.input:<{width}} {data['samples']:>9} {sum(data['skipped'].values()):>8} "
            f"{fmt(data['distance']):>11} x {fmt(round(pose['x'], 9))} m, "
            f"y {fmt(round(pose['y'], 9))} m, theta {fmt(round(pose['theta'], 9))} rad"
        )
        if result.reference is not None:
            click.echo(f"{'':<{width}} reference {_reference_text(result.reference)}")
    if failed:
        opt.warn(f"{failed} of {len(results)} recordings could not be read")
    if implausible:
        opt.warn(f"{implausible} of {len(results)} recordings have implausible steps")
    if failed or implausible:
        sys.exit(EXIT_CHECK_FAILED)
