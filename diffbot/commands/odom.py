"""``diffbot odom``: odometry from recorded wheel joint positions."""

from __future__ import annotations

import io
import math
import sys
from collections.abc import Mapping
from pathlib import Path

import click

from diffbot.commands import options as opt
from diffbot.commands.options import OutOptions, RobotOptions
from diffbot.formats.text import fmt
from diffbot.io.bag import write_odometry_bag
from diffbot.io.csvfile import format_odometry_csv, read_csv
from diffbot.io.outputs import write_text_atomic
from diffbot.io.recordings import read_recording
from diffbot.kinematics import DiffDriveParams
from diffbot.odometry import Odometry
from diffbot.replay import run_odometry
from diffbot.samples import Recording

__all__ = ["odom"]


def _read_stdin_csv(params: DiffDriveParams) -> Recording:
    """The CSV on stdin, read whole (``diffbot simulate | diffbot odom -``)."""

    data = sys.stdin.buffer.read()
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError:
        opt.fail("-: stdin is not a text (UTF-8) CSV")
    return read_csv(
        io.StringIO(text, newline=""), params.left_joint, params.right_joint, source="-"
    )


def _skipped_text(skipped: Mapping[str, int]) -> str:
    return ", ".join(f"{count} {reason}" for reason, count in sorted(skipped.items()))


@click.command()
@click.argument("tokens", nargs=-1, metavar="INPUT [NAME:=VALUE]...")
@opt.robot_options
@opt.topic_option("The sensor_msgs/JointState topic of a bag.")
@opt.out_options(
    "Write the poses: a CSV file (time,x,y,theta,linear,angular), or a bag with --bag.",
    "Write --out as a rosbag2 directory: nav_msgs/Odometry on /odom, TF on /tf.",
)
@click.option("--json", "as_json", is_flag=True, help="Machine-readable summary.")
def odom(
    robot: RobotOptions,
    tokens: tuple[str, ...],
    topic: str,
    out: OutOptions,
    as_json: bool,
) -> None:
    """Odometry from recorded wheel joint positions.

    INPUT is a CSV file (a time column `time`, `stamp`, `t` or `__time` in seconds, and one
    position column per wheel named by its joint or ending with `/<joint>/position`; `-` reads
    it from stdin), a rosbag2
    directory (sqlite3 or mcap) or one of its .db3/.mcap files holding sensor_msgs/JointState on
    --topic. A bag's samples are all stamped by their header stamps, or all by the bag's receive
    times when any header stamp is zero (the summary says which). Each step is integrated
    exactly along its arc; the first sample sets the encoder baseline. Samples
    without both wheel joints, with NaN/inf or with a stamp not after the previous one are
    skipped and reported.

    \b
    Reading bags needs the optional rosbags dependency:
      pip install 'rosbags>=0.11'     (or, in a clone: pip install -e '.[bag]')

    \b
    Examples:
      diffbot odom joints.csv
      diffbot simulate "straight 1; spin 90" | diffbot odom -
      diffbot odom my_bag/ --topic /joint_states --out odom.csv
      diffbot odom run.mcap --out odom_bag --bag --json
    """

    rest, xacro_args = opt.split_xacro_args(tokens)
    if len(rest) != 1:
        opt.fail(
            "expected one INPUT (a CSV file, - for a CSV on stdin, a rosbag2 directory or a "
            f".db3/.mcap file), got {rest}"
        )
    source = rest[0]
    from_stdin = source == "-"
    if not source.strip():
        opt.fail("INPUT is empty: give a CSV file, - for stdin, or a rosbag2 recording")
    if not from_stdin and not Path(source).exists():
        opt.fail(f"{source}: no such file or directory")
    out.require_out_for_bag()
    robot = robot.with_path(None, xacro_args)
    inputs = [Path(path) for path in (None if from_stdin else source, robot.robot) if path]
    out_path = out.path(inputs)
    p = robot.load()
    recording = _read_stdin_csv(p) if from_stdin else read_recording(source, p, topic)
    integrator = Odometry(p)
    run = run_odometry(recording, integrator)
    if out_path is not None:
        if out.as_bag:
            write_odometry_bag(out_path, run.rows, integrator, force=out.force)
        else:
            write_text_atomic(out_path, format_odometry_csv(run.rows), force=out.force)
    skipped_total = sum(run.skipped.values())
    if skipped_total:
        opt.warn(
            f"skipped {skipped_total} of {run.samples + skipped_total} samples: "
            f"{_skipped_text(run.skipped)}"
        )
    pose = run.final_pose
    if as_json:
        opt.emit_json(
            {
                "input": source,
                "final_pose": {"x": pose.x, "y": pose.y, "theta": pose.theta},
                "distance": run.distance,
                "samples": run.samples,
                "skipped": dict(sorted(run.skipped.items())),
                "duration": run.duration,
                "clock": recording.clock,
                "output": out.out,
            }
        )
        return
    kind = "CSV" if recording.kind == "csv" else f"rosbag2, topic {topic}, {recording.clock} stamps"
    rows = [
        ("input", f"{source} ({kind})"),
        ("samples", f"{run.samples} used, {skipped_total} skipped"),
        ("duration", f"{fmt(run.duration)} s"),
        ("distance", f"{fmt(run.distance)} m"),
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
        rows.append(("output", f"{out.out} ({what}, {len(run.rows)} poses)"))
    for label, value in rows:
        click.echo(f"{label:<11} {value}")


# --------------------------------------------------------------------------------------------
# simulate: the wheel joint states a plan would produce
