"""``diffbot simulate``: the wheel joint states that executing a plan would produce."""

from __future__ import annotations

import contextlib
import functools
import math
import sys
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from diffbot.calibration.truth import TRUTH_COLUMNS, TruthStream, true_robot
from diffbot.commands.follow_options import disturbance_options, follow_options
from diffbot.commands.options import (
    NUMBERS,
    CheckedNumber,
    Count,
    FiniteFloat,
    OutOptions,
    RobotOptions,
    emit_json,
    encoder_noise_options,
    fail,
    out_options,
    quiet_option,
    robot_options,
    topic_option,
    true_geometry_options,
)
from diffbot.commands.plan_options import (
    PlanOptions,
    check_topic,
    plan_input_options,
)
from diffbot.commands.progress import progress
from diffbot.commands.simulate_loop import LoopRequest, end_errors, run_loop
from diffbot.errors import EXIT_CHECK_FAILED
from diffbot.formats.plan_data import start_json
from diffbot.formats.text import fmt
from diffbot.io.bag import JointStatesBagWriter
from diffbot.io.csvfile import joint_states_header, joint_states_lines
from diffbot.io.outputs import atomic_text
from diffbot.samples import ns_from_seconds
from diffbot.simulation import (
    MAX_RATE,
    MAX_SAMPLES,
    JointStateChunks,
    Motion,
    Sampling,
    boundaries,
    sample_count,
    simulate_chunks,
)
from diffbot.trajectory import Plan

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray

    from diffbot.execution import Execution
    from diffbot.kinematics import DiffDriveParams
    from diffbot.ramps import RampedPlan

__all__ = ["simulate"]


class _StartType(CheckedNumber):
    """Seconds since 1970 as a decimal number, read exactly into integer nanoseconds."""

    name = "seconds"

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> int:
        if isinstance(value, int):
            return value
        try:
            stamp_ns = ns_from_seconds(str(value))
        except ValueError:
            self.fail(f"{value!r} is not a number", param, ctx)
        if stamp_ns is None:
            self.fail(f"{value!r} is not a finite number", param, ctx)
        if stamp_ns < 0:
            self.fail(f"{value!r} must be >= 0", param, ctx)
        if stamp_ns >= 2**63:
            self.fail(f"{value!r} is past 2262, the end of int64 nanosecond stamps", param, ctx)
        return stamp_ns


def _write(
    states: JointStateChunks,
    start_ns: int,
    out_path: Path | None,
    out: OutOptions,
    topic: str,
    advance: Callable[[int], None],
    truth: TruthStream | None = None,
) -> None:
    """Write the samples chunk by chunk: CSV on stdout or --out, or a bag with --bag; with
    ``truth``, its poses too (CSV columns x, y, theta, or a pose topic)."""

    def stamped() -> Iterator[tuple[list[int], NDArray[np.float64], NDArray[np.float64] | None]]:
        for times, positions in states.chunks:
            poses = None if truth is None else truth.rows(times)
            yield [start_ns + round(t * 1e9) for t in times.tolist()], positions, poses
            advance(times.size)

    if out_path is not None and out.as_bag:
        with JointStatesBagWriter(
            out_path, states.names, force=out.force, topic=topic, poses=truth is not None
        ) as bag:
            for stamps, positions, poses in stamped():
                bag.write(stamps, positions)
                if poses is not None:
                    bag.write_poses(stamps, poses)
        return
    with contextlib.ExitStack() as stack:
        if out_path is None:
            write: Callable[[str], object] = functools.partial(click.echo, nl=False)
        else:
            write = stack.enter_context(atomic_text(out_path, force=out.force)).write
        names = states.names if truth is None else (*states.names, *TRUTH_COLUMNS)
        write(joint_states_header(names))
        for stamps, positions, poses in stamped():
            rows = positions if poses is None else [*positions, *poses]
            write(joint_states_lines(stamps, rows))


@click.command(context_settings=NUMBERS)
@click.argument("tokens", nargs=-1, metavar="[SPEC | FILE] [NAME:=VALUE]...")
@robot_options
@plan_input_options
@click.option(
    "--rate",
    type=FiniteFloat(0.0, open_min=True, maximum=MAX_RATE, unit="Hz"),
    default=50.0,
    show_default=True,
    metavar="HZ",
    help="Sampling rate of the joint states (Hz), at most 1e6.",
)
@click.option(
    "--ticks",
    type=Count(1, 2**32),  # diffbot.simulation.MAX_TICKS
    metavar="N",
    help="Encoder resolution (counts per revolution, up to 2**32): quantise the wheel angles.",
)
@encoder_noise_options
@click.option(
    "--start",
    "start_ns",
    type=_StartType(),
    default="0",
    show_default=True,
    metavar="S",
    help="Stamp of the first sample (s since 1970, read exactly to the nanosecond).",
)
@true_geometry_options(
    "The real left and right wheel radii (m): the robot moves by them, and the output "
    "gains its ground-truth pose (x, y, theta).",
    "The real wheel separation (m); likewise adds the ground-truth pose.",
)
@disturbance_options
@follow_options
@click.option("--json", "as_json", is_flag=True, help="Machine-readable summary (needs --out).")
@topic_option("The JointState topic of --bag.")
@out_options(
    "Write to this file (CSV) or, with --bag, this rosbag2 directory; default: CSV on stdout.",
    "Write --out as a rosbag2 directory of sensor_msgs/JointState.",
)
@quiet_option
def simulate(
    robot: RobotOptions,
    tokens: tuple[str, ...],
    plan_options: PlanOptions,
    rate: float,
    ticks: int | None,
    noise: float,
    seed: int | None,
    start_ns: int,
    out: OutOptions,
    topic: str,
    true_radii: tuple[float, float] | None,
    true_separation: float | None,
    as_json: bool,
    quiet: bool,
    motor_lag: float,
    latency: float,
    drop: float,
    slip: float,
    follow: str | None,
    control_rate: float,
    pose_source: str,
    pose_noise: tuple[float, float] | None,
    lead: float | None,
) -> None:
    """Wheel joint states that executing a plan would produce.

    The plan is given as for `diffbot plan` (SPEC text, a FILE, or --example; Trajectory A when
    nothing is given). The drive wheel joints follow its commands exactly, sampled at --rate Hz
    plus one sample at every segment boundary and at the end, so that `diffbot odom` of the
    result ends exactly at the plan's final pose. --noise adds Gaussian noise to the wheel angles,
    then --ticks quantises them as an encoder would. Every drive wheel joint of the robot is
    written (all wheels of a side turn alike); its other moving joints (a caster's) are reported
    at 0, as they are not modelled.

    When the robot's diff_drive_controller configuration has velocity, acceleration or jerk
    limits, the plan's commands (sampled at its update rate) first go through a model of the
    controller's speed limiter, and the joints follow what it executes; the summary then gives
    the executed final pose and its distance from the planned one. With --max-accel and the
    like the plan is ramped (see `diffbot plan --help`).

    Output: CSV (time in s, then one column per joint in rad) on stdout or --out, or with --bag a
    rosbag2 directory of sensor_msgs/JointState on --topic, written as the samples are made
    (constant memory; a file appears only when whole), with a progress bar on stderr when it is
    a terminal (not with --quiet). Exit code 1 when the plan exceeds the
    motor limit (the output is still written).

    --true-wheel-radius and --true-separation give the robot's real geometry, which differs
    from the description's: the commands come from the description, the wheels turn as
    commanded, and the real robot's exact pose is added as columns x, y, theta (m, m, rad) of
    the CSV, or as geometry_msgs/PoseStamped on /ground_truth in a bag: data for `diffbot
    calibrate fit`. The summary then gives where the real robot ended beside the plan's end
    (--json: true_final_pose, final_position_error, final_heading_error; final_pose is the
    plan's end).

    --motor-lag, --latency, --drop and --slip make the robot disobey as a real base does (its
    wheels also never exceed the motor limit); the plan's commands are then sent open loop at
    --control-rate, or, with --follow, a follower (`diffbot.follow`) closes the loop from the
    robot's wheel odometry (--pose-source odom) or its true pose with noise (--pose-source
    truth --pose-noise M,DEG); the tracking law acts on the pose predicted --lead s ahead
    (by default the robot's --latency plus --motor-lag plus half a control period). Such runs
    add the true pose columns x, y, theta and their --json summary gives true_final_pose,
    final_position_error, final_heading_error (m, rad), max_cross_track_error,
    rms_cross_track_error (m), peak_limit_fraction, duration (s), arrived and, followed, the
    lead (s).

    \b
    Examples:
      diffbot simulate --out a.csv && diffbot odom a.csv
      diffbot simulate "straight 1; spin 90" --rate 20 --ticks 1024 --noise 0.001 --seed 1
      diffbot simulate --example B --out b_bag --bag --start 1700000000
      diffbot simulate --example A --motor-lag 0.15 --latency 0.04 --drop 0.05 --seed 1 \\
          --ticks 4096 --follow -o followed.csv
    """

    check_topic("--topic", topic)
    request = plan_options.request(robot, tokens)
    source, robot = request.source, request.robot
    out.require_out_for_bag()
    if as_json and out.out is None:
        fail("--json prints a summary, so the samples need --out")
    loop = LoopRequest(
        follow, control_rate, pose_source, pose_noise, motor_lag, latency, drop, slip, lead
    )
    loop.check(rate)
    inputs = [path for path in (source.path, robot.robot) if path is not None]
    out.path([Path(path) for path in inputs])
    built = plan_options.build(request, writes=True)
    source, params, made = built.source, built.params, built.made
    out_path = out.path([Path(path) for path in (*inputs, *params.description_files)])
    p = made if isinstance(made, Plan) else made.steps
    if loop.wanted:
        real = None
        if true_radii is not None or true_separation is not None:
            real = true_robot(params, true_radii, true_separation)

        def write(states: JointStateChunks, truth: Any, advance: Callable[[int], None]) -> None:
            _write(states, start_ns, out_path, out, topic, advance, truth)

        sampling = (rate, ticks, noise, seed)
        run_loop(
            loop,
            made,
            params,
            sampling,
            real,
            write,
            out,
            source.label,
            as_json,
            quiet,
            built.body,
            source.start,
        )
        limit_lines = built.limit_lines()
        if limit_lines:
            for line in limit_lines:
                click.echo(line, err=True)
            sys.exit(EXIT_CHECK_FAILED)
        return
    from diffbot.body_limits import with_velocity_limits

    motion, executed = _executed(made, with_velocity_limits(params, built.body))
    duration, extra = motion.duration, len(boundaries(motion))
    count = sample_count(duration, rate, extra)
    if count > MAX_SAMPLES:
        highest = (MAX_SAMPLES - 2 - extra) / duration
        how = (
            f"lower --rate to at most {highest:.4g} Hz for this plan"
            if highest >= 1.0
            else "the plan is too long even at 1 Hz: shorten it (or raise --speed)"
        )
        fail(
            f"the plan's {fmt(duration)} s at {fmt(rate)} Hz would take {count:.4g} samples, "
            f"more than the {MAX_SAMPLES} simulate makes: {how}"
        )
    if start_ns + round(duration * 1e9) >= 2**63:
        fail(
            f"--start plus the plan's {fmt(duration)} s ends past 2262, the end of int64 "
            "nanosecond stamps"
        )
    states = simulate_chunks(motion, params, Sampling(rate, ticks, noise, seed))
    with progress(states.samples, "simulate", "samples", quiet=quiet) as advance:
        truth = None
        if true_radii is not None or true_separation is not None:
            truth = TruthStream(motion, true_robot(params, true_radii, true_separation))
        _write(states, start_ns, out_path, out, topic, advance, truth)
    if out_path is not None:
        pose = p.final_pose
        if as_json:
            summary = {
                "plan": source.label,
                "duration": duration,
                "samples": states.samples,
                "rate": rate,
                "joints": list(states.names),
                **start_json(source.start),
                "final_pose": {"x": pose.x, "y": pose.y, "theta": pose.theta},
                "within_limit": p.within_limit,
                "output": out.out,
            }
            if executed is not None:
                done = executed.final_pose
                summary["executed_final_pose"] = {"x": done.x, "y": done.y, "theta": done.theta}
                summary["offset"] = executed.offset
            if truth is not None and truth.final is not None:
                # The real robot's end, as a disturbed run gives it: final_pose is the plan's.
                end = truth.final
                position, heading = end_errors(pose, end)
                summary["true_final_pose"] = {"x": end.x, "y": end.y, "theta": end.theta}
                summary["final_position_error"] = position
                summary["final_heading_error"] = heading
            emit_json(summary)
        else:
            what = f"rosbag2, {topic}" if out.as_bag else "CSV"
            rows = [
                (
                    "plan",
                    f"{source.label} ({len(p.segments)} segment"
                    f"{'' if len(p.segments) == 1 else 's'}, {fmt(duration)} s)",
                ),
                (
                    "samples",
                    f"{states.samples} at {fmt(rate)} Hz and segment ends, "
                    f"{len(states.names)} joints",
                ),
                (
                    "final pose",
                    f"x {fmt(round(pose.x, 9))} m, y {fmt(round(pose.y, 9))} m, "
                    f"theta {fmt(round(pose.theta, 9))} rad",
                ),
                ("output", f"{out.out} ({what})"),
            ]
            if executed is not None:
                done = executed.final_pose
                rows[-1:-1] = [
                    (
                        "executed",
                        f"through the controller's limiter at {fmt(executed.rate)} Hz: "
                        f"x {fmt(round(done.x, 9))} m, y {fmt(round(done.y, 9))} m, "
                        f"theta {fmt(round(done.theta, 9))} rad, {fmt(executed.offset, 4)} m "
                        "from the planned end",
                    )
                ]
            if truth is not None and truth.final is not None:
                end = truth.final
                position, heading = end_errors(pose, end)
                millimetres = round(position, 9) * 1000.0  # rounding noise reads as 0
                rows[-1:-1] = [
                    (
                        "true end",
                        f"x {fmt(round(end.x, 9))} m, y {fmt(round(end.y, 9))} m, "
                        f"theta {fmt(round(end.theta, 9))} rad: {fmt(millimetres, 4)} mm, "
                        f"{fmt(math.degrees(heading), 3)} deg from the plan's end",
                    )
                ]
            for label, value in rows:
                click.echo(f"{label:<11} {value}")
    limit_lines = built.limit_lines()
    if limit_lines:
        for line in limit_lines:
            click.echo(line, err=True)
        sys.exit(EXIT_CHECK_FAILED)


def _executed(
    made: Plan | RampedPlan, params: DiffDriveParams
) -> tuple[Plan | Motion, Execution | None]:
    """What the wheels follow: the plan, or, when the controller configuration has limits, the
    commands its limiter executes."""
    if params.controller is None:
        return made, None
    from diffbot.execution import execute_plan, limits_apply

    if not limits_apply(params.controller):
        return made, None
    executed = execute_plan(made, params.controller)
    return executed, executed
