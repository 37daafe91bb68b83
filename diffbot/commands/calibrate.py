"""``diffbot calibrate umbmark|fit``: wheel radii and separation from test runs or recordings."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import click

from diffbot.commands.groups import SuggestingGroup
from diffbot.commands.options import (
    NUMBERS,
    POSITIVE,
    Count,
    NumberPair,
    RobotOptions,
    emit_json,
    fail,
    option_group,
    output_option,
    parse_number,
    robot_options,
    split_xacro_args,
    topic_option,
)
from diffbot.commands.paths import EditedPath, InputPath, input_path
from diffbot.commands.plan_options import check_topic
from diffbot.commands.recording_options import (
    RecordingOptions,
    exit_if_implausible,
    recording_options,
    robot_label,
)
from diffbot.errors import CalibrationError
from diffbot.formats.calibration import calibration_data, calibration_lines
from diffbot.formats.text import fmt
from diffbot.io.pathnames import resolved
from diffbot.io.textfile import read_text
from diffbot.kinematics import DiffDriveParams
from diffbot.numbers import finite_in_range, shown
from diffbot.urdf import load_params

if TYPE_CHECKING:
    from diffbot.calibration.fit import FitResult
    from diffbot.calibration.umbmark import UmbmarkResult
    from diffbot.conditioning import ConditioningReport
    from diffbot.samples import Recording

__all__ = ["calibrate"]


_POINT = NumberPair("X,Y", "m")


@dataclass(frozen=True)
class _Output:
    """What a calibration prints (--json) and writes (--apply-to, --force)."""

    as_json: bool
    apply_to: str | None
    force: bool
    output: str | None = None

    def target(self) -> Path | None:
        """Where the calibrated copy goes: the output option, else beside --apply-to."""
        if self.apply_to is None:
            return None
        from diffbot.calibration.apply import calibrated_path

        return (
            Path(self.output) if self.output is not None else calibrated_path(Path(self.apply_to))
        )

    def check(self) -> None:
        """Refuse, before any work, a --apply-to that is missing or whose copy may not be
        written (it exists and --force is not given)."""
        from diffbot.io.outputs import output_target

        if self.output is not None and self.apply_to is None:
            fail("-o/--output names where the calibrated copy goes: give --apply-to FILE too")
        target = self.target()
        if self.apply_to is not None and target is not None:
            source = Path(self.apply_to)
            if not source.exists():
                fail(f"--apply-to {self.apply_to}: no such file")
            output_target(target, force=self.force, inputs=[source])


_output_options = option_group(
    [
        click.option("--json", "as_json", is_flag=True, help="Machine-readable output."),
        click.option(
            "--apply-to",
            type=EditedPath(),
            metavar="FILE",
            help="Write a calibrated copy of FILE beside it (FILE.calibrated...): a controllers "
            "YAML gets the multipliers of the robot's diff-drive controller, a .urdf/.xacro the "
            "xacro:arg or xacro:property that defines wheel_radius and wheel_separation. The "
            "copy is read back before it is written; FILE itself is never changed.",
        ),
        output_option(
            "Write the calibrated copy of --apply-to here instead of beside it "
            "(FILE.calibrated...)."
        ),
        click.option("--force", is_flag=True, help="Overwrite the calibrated copy if it exists."),
    ],
    "output",
    lambda kw: _Output(kw.pop("as_json"), kw.pop("apply_to"), kw.pop("force"), kw.pop("output")),
)


def _read_back(robot: RobotOptions, path: Path) -> Callable[[Path], DiffDriveParams]:
    """How to load a calibrated copy of the description ``path``: as the robot was loaded
    (its packages, joints, trust; its xacro arguments when it is the robot's own description)
    but without the overrides and arguments of the calibrated values themselves."""
    same = robot.robot is not None and resolved(robot.robot) == resolved(path)
    args = {
        name: value
        for name, value in (robot.xacro_args.items() if same else ())
        if name not in ("wheel_radius", "wheel_separation")
    }

    def load(copy: Path) -> DiffDriveParams:
        return load_params(
            copy,
            args,
            robot.packages,
            left_joint=robot.left_joint,
            right_joint=robot.right_joint,
            trust=robot.trust,
        )

    return load


def _report(
    result: UmbmarkResult | FitResult,
    params: DiffDriveParams,
    output: _Output,
    robot: RobotOptions,
    extra: dict[str, object] | None = None,
) -> None:
    """Print a calibration and write the calibrated copy of --apply-to."""
    from diffbot.calibration.apply import apply_to
    from diffbot.calibration.checks import check_geometry
    from diffbot.io.outputs import write_text_atomic

    check_geometry(result, "the calibration gives")
    written: str | None = None
    if output.apply_to is not None:
        source = Path(output.apply_to)
        target = output.target()
        assert target is not None
        controller = params.controller.name if params.controller is not None else None
        applied = apply_to(source, result, controller=controller, load=_read_back(robot, source))
        write_text_atomic(target, applied.text, force=output.force, inputs=[source])
        written = str(target)
    if output.as_json:
        emit_json(
            {
                **calibration_data(result, params),
                **(extra or {}),
                "applied_to": written,
            }
        )
        return
    for line in calibration_lines(result, params):
        click.echo(line)
    if written is not None:
        click.echo(f"wrote {written} (a calibrated copy of {output.apply_to})")


def _robot(
    robot: RobotOptions, tokens: tuple[str, ...]
) -> tuple[list[str], RobotOptions, DiffDriveParams]:
    """The tokens that are no xacro arguments, the robot options with those arguments, and the
    robot."""
    rest, xacro_args = split_xacro_args(tokens)
    robot = robot.with_path(None, xacro_args)
    return rest, robot, robot.load()


@click.group(cls=SuggestingGroup, context_settings={"help_option_names": ["-h", "--help"]})
def calibrate() -> None:
    """Calibrate the wheel radii and separation of a real robot.

    \b
    umbmark  from where square test runs ended (Borenstein and Feng's UMBmark)
    fit      by least squares, from a recording with a ground-truth pose track

    Both print the corrected left and right wheel radii and separation, the
    diff_drive_controller multipliers and the xacro arguments; --apply-to writes a calibrated
    copy of a controllers YAML or a description beside it. The derivations are in
    docs/calibration.md.

    \b
    Examples:
      diffbot calibrate umbmark --side 4 --runs docs/examples/runs.yaml
      diffbot calibrate fit --help
    """


#: Most runs a runs file may hold: UMBmark drives five each way; a million rows took 20 s and
#: 700 MB.
MAX_RUNS = 10_000

#: Longest runs file read (characters): room for :data:`MAX_RUNS` runs written out at length.
MAX_RUNS_CHARS = 100 * MAX_RUNS


def _runs_file(path: str) -> tuple[list[tuple[float, float]], list[tuple[float, float]]]:
    """The cw and ccw end points of a runs file: YAML ``{cw: [[x, y], ...], ccw: [...]}`` or
    CSV with columns ``direction,x,y``."""
    from diffbot.io.yamlfile import load_yaml

    text = read_text(path, CalibrationError, "a runs file (CSV or YAML)", max_chars=MAX_RUNS_CHARS)
    runs: dict[str, list[tuple[float, float]]] = {"cw": [], "ccw": []}
    if path.lower().endswith(".csv"):
        lines = [line.split(",") for line in text.splitlines() if line.strip()]
        header = [cell.strip().lower() for cell in lines[0]] if lines else []
        if header != ["direction", "x", "y"]:
            fail(f"{path}: a runs CSV has the columns direction,x,y (got {','.join(header)})")
        rows = [(cells[0].strip().lower(), cells[1:]) for cells in lines[1:]]
    else:
        data = load_yaml(text, path, CalibrationError, "a runs file")
        if not isinstance(data, dict) or not set(data) <= {"cw", "ccw"}:
            fail(f"{path}: a runs YAML maps cw and ccw to lists of [x, y] (m)")
        rows = []
        for key, points in data.items():
            if points is not None and not isinstance(points, list):
                fail(f"{path}: {key} must be a list of [x, y] (m), got {shown(points)}")
            rows += [(str(key), point) for point in points or []]
    if len(rows) > MAX_RUNS:
        fail(f"{path}: {len(rows)} runs, more than {MAX_RUNS}: not a UMBmark test's record")
    for direction, point in rows:
        if direction not in runs or not isinstance(point, list) or len(point) != 2:
            fail(f"{path}: {direction} {shown(point)}: expected cw or ccw and two numbers x, y (m)")
        x, y = (
            finite_in_range(
                v.strip() if isinstance(v, str) else v, f"{path}: {direction} {name}", unit="m"
            )
            for v, name in zip(point, "xy", strict=True)
        )
        runs[direction].append((x, y))
    return runs["cw"], runs["ccw"]


@calibrate.command()
@click.argument("tokens", nargs=-1, metavar="[NAME:=VALUE]...")
@robot_options
@click.option("--side", type=POSITIVE, required=True, metavar="M", help="Side of the square (m).")
@click.option(
    "--cw", "cw", type=_POINT, multiple=True, metavar="X,Y", help="End of a clockwise run (m)."
)
@click.option(
    "--ccw",
    "ccw",
    type=_POINT,
    multiple=True,
    metavar="X,Y",
    help="End of a counter-clockwise run.",
)
@click.option(
    "--runs",
    type=InputPath(),
    metavar="FILE",
    help="The ends in a file: CSV direction,x,y or YAML {cw, ccw}.",
)
@click.option(
    "--exact",
    is_flag=True,
    help="Fit the exact model of the squares instead of the first-order formulas.",
)
@_output_options
def umbmark(
    robot: RobotOptions,
    tokens: tuple[str, ...],
    side: float,
    cw: tuple[tuple[float, float], ...],
    ccw: tuple[tuple[float, float], ...],
    runs: str | None,
    exact: bool,
    output: _Output,
) -> None:
    """Wheel diameter ratio Ed and separation error Eb from UMBmark runs.

    Drive the square `diffbot plan --example umbmark --side L` gives, clockwise (--cw) and
    counter-clockwise (--ccw), several times each (5 is usual), and measure where the robot
    stopped relative to its start pose: X forward, Y left (m). Give each run as --cw X,Y or
    --ccw X,Y, or all of them in a --runs file. The robot options name the nominal robot the
    runs were commanded with.

    \b
    Examples:
      diffbot calibrate umbmark --side 4 --cw -0.31,-0.40 --cw -0.36,-0.39 \\
          --ccw 0.12,-0.09 --ccw 0.10,-0.12
      diffbot calibrate umbmark --side 4 --runs docs/examples/runs.yaml --json
    """
    from diffbot.calibration.umbmark import umbmark as run_umbmark

    output.check()
    rest, robot, params = _robot(robot, tokens)
    if rest:
        fail(f"unexpected argument {rest[0]!r}: give the runs as --cw X,Y and --ccw X,Y")
    cw_ends, ccw_ends = list(cw), list(ccw)
    if runs is not None:
        more_cw, more_ccw = _runs_file(runs)
        cw_ends += more_cw
        ccw_ends += more_ccw
    if not cw_ends or not ccw_ends:
        fail(
            "UMBmark needs at least one clockwise and one counter-clockwise run: --cw X,Y "
            "and --ccw X,Y (or --runs FILE)"
        )
    result = run_umbmark(side, cw_ends, ccw_ends, params, exact=exact)
    _report(result, params, output, robot)


@calibrate.command(context_settings=NUMBERS)
@click.argument("tokens", nargs=-1, metavar="INPUT [NAME:=VALUE]...")
@robot_options
@_output_options
@topic_option("The sensor_msgs/JointState topic of a bag.", reading=True)
@recording_options
@click.option(
    "--truth",
    type=InputPath(),
    metavar="FILE",
    multiple=True,
    help="The ground truth: a CSV with time, x, y, theta, or a bag. Default: INPUT itself. "
    "With several INPUTs, once per INPUT, in their order.",
)
@click.option(
    "--truth-topic",
    metavar="TOPIC",
    help="The ground truth's PoseStamped or Odometry topic of a bag (default: its only one).",
)
@click.option(
    "--window",
    type=Count(1),
    metavar="N",
    help="Sample intervals per window (default 50).",
)
@click.option("--window-duration", type=POSITIVE, metavar="S", help="Windows of S seconds instead.")
@click.option(
    "--time-offset",
    metavar="SECONDS|auto",
    default="0",
    show_default=True,
    help="How late the wheel stamps are against the ground truth (s), or auto: found for "
    "each recording by aligning the heading rates of the wheels and the truth.",
)
@click.option(
    "--max-stderr",
    type=POSITIVE,
    default=0.01,
    show_default=True,
    metavar="FRACTION",
    help="Refuse results whose standard error exceeds this fraction of a parameter.",
)
def fit(
    robot: RobotOptions,
    tokens: tuple[str, ...],
    topic: str | None,
    recording: RecordingOptions,
    truth: tuple[str, ...],
    truth_topic: str | None,
    window: int | None,
    window_duration: float | None,
    time_offset: str,
    max_stderr: float,
    output: _Output,
) -> None:
    """Left and right wheel radii and separation by least squares against a ground truth.

    INPUT holds the wheel joint positions, as for `diffbot odom` (CSV, or a rosbag2 recording
    with sensor_msgs/JointState on --topic), or their velocities with --feedback velocity
    (integrated as `diffbot odom` integrates them); several INPUTs are fitted at once, each against
    its own ground truth (in it, or a --truth each). Wheel stamps late against the truth are
    moved back by --time-offset. The ground truth is a pose track: CSV columns x, y, theta
    (m, m, rad) beside a time column, or a bag's geometry_msgs/PoseStamped or
    nav_msgs/Odometry topic; it is interpolated at the wheel stamps. The motion over windows
    of --window samples is compared, starting from the description's values. Drive straights
    and turns both ways (Trajectory A is enough). A recording with implausible steps (wheel
    jumps) is fitted and reported, but the exit code is 1, as for `diffbot odom`: the windows
    across a jump spoil the fit.

    Uses SciPy, which the base install brings.

    \b
    Examples:
      diffbot simulate --example A --true-wheel-radius 0.0352,0.0348 --true-separation 0.138 \\
          --out run.csv && diffbot calibrate fit run.csv
      diffbot simulate --example A --true-separation 0.138 -o run_bag --bag && \\
          diffbot calibrate fit run_bag --truth-topic /ground_truth --json
    """
    from diffbot.calibration.fit import require_scipy
    from diffbot.calibration.fit_recordings import fit_recordings
    from diffbot.io.poses import read_pose_track

    require_scipy()
    # the recordings are inputs before the output is checked
    rest = [input_path(token) for token in split_xacro_args(tokens)[0]]
    output.check()
    _, robot, params = _robot(robot, tokens)
    if not rest:
        fail("give an INPUT: the recording of wheel joint positions")
    recording.check_robot(robot, params)
    if truth and len(truth) != len(rest):
        fail(
            f"give --truth once per INPUT ({len(rest)} INPUT{'s' if len(rest) != 1 else ''}, "
            f"{len(truth)} --truth), or none"
        )
    offset: float | str = "auto"
    if time_offset.strip().lower() != "auto":
        offset = parse_number(time_offset, "--time-offset")
    if topic is not None:
        check_topic("--topic", topic)
    if truth_topic is not None:
        check_topic("--truth-topic", truth_topic)
    if window is not None and window_duration is not None:
        fail("give --window or --window-duration, not both")
    # Read one recording at a time, as the fit takes them: each is let go once reduced.
    reports: list[ConditioningReport] = []

    def read(source: str) -> Recording:
        read = recording.read(source, params, topic)
        if read.conditioning is not None:
            reports.append(read.conditioning)
        return read

    pairs = (
        (read(source), read_pose_track(truth[k] if truth else source, truth_topic))
        for k, source in enumerate(rest)
    )
    result, offsets = fit_recordings(
        pairs,
        params,
        time_offset=offset,
        window=window,
        window_duration=window_duration,
        max_relative_stderr=max_stderr,
    )
    if offset == "auto" and not output.as_json:
        for source, found in zip(rest, offsets, strict=True):
            click.echo(f"time offset {fmt(found, 4)} s ({source}: heading rates aligned)")
    feedback = recording.feedback_for(params)
    if not output.as_json:
        click.echo(f"{'robot':<13} {robot_label(robot)}")
        if feedback == "velocity":
            click.echo(f"{'feedback':<13} wheel velocities, integrated")
    extra: dict[str, object] = {
        "time_offsets": offsets,
        "robot": robot_label(robot),
        "feedback": feedback,
    }
    _report(result, params, output, robot, extra)
    # As odom: a wheel jump spoils the windows across it, and the warning said where.
    exit_if_implausible(reports)
