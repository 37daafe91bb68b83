"""``diffbot plot``: a figure of a plan's path and wheel speeds, with recorded odometry over it."""

from __future__ import annotations

import tempfile
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, Final

import click

from diffbot import plotting
from diffbot.commands.messages import emit_json
from diffbot.commands.options import (
    NUMBERS,
    RobotOptions,
    fail,
    output_option,
    split_xacro_args,
    topic_option,
    warn,
)
from diffbot.commands.paths import InputPath
from diffbot.commands.plan_options import PlanOptions, plan_arguments
from diffbot.commands.recording_options import (
    RecordingOptions,
    exit_if_implausible,
    recording_options,
    robot_label,
)
from diffbot.formats.text import fmt
from diffbot.io.outputs import output_target
from diffbot.kinematics import DiffDriveParams
from diffbot.trajectory import Plan

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray

    from diffbot.chunk_odometry import ChunkPoses
    from diffbot.conditioning import ConditioningReport
    from diffbot.reference import ReferenceComparison

__all__ = ["plot"]


def _prepared(
    given: Sequence[str | Path | None], output: str | None, force: bool, show: bool
) -> list[Path]:
    """The inputs named, once the output and the display are known to be usable."""
    inputs = [Path(path) for path in given if path is not None]
    if output is not None:
        plotting.file_format(output)
        output_target(Path(output), force=force, inputs=inputs)
    if show:
        plotting.require_window()
    else:
        plotting.require_matplotlib()
    return inputs


class _Said:
    """What plot says on stdout: a line per result for people, or with ``--json`` one object
    once the figure is written: ``robot`` (a path, ``"bundled"`` or ``"options"``, as ``odom
    --json`` says it), ``plan`` (its source, null without one), ``output`` (the figure's file,
    null when only shown) and ``paths``, one per path drawn over the plan: ``input`` (the
    recording), ``path`` (``odometry``, ``true pose`` or ``reference``), ``end`` (its last
    ``x``, ``y``, m), ``plan_end_distance`` (m from the plan's end, null without a plan), and
    for a reference the fields of ``odom --json``'s ``reference``."""

    def __init__(self, as_json: bool) -> None:
        self.as_json = as_json
        self.paths: list[dict[str, Any]] = []

    def echo(self, text: str) -> None:
        """A line for people (none with ``--json``)."""
        if not self.as_json:
            click.echo(text)

    def path(self, source: str, kind: str, drawn: _Path, **fields: Any) -> _Path:
        """Note a path drawn from the recording ``source``, and give it back."""
        _, x, y = drawn
        end = {"x": float(x[-1]), "y": float(y[-1])} if len(x) else None
        entry = {"input": source, "path": kind, "end": end, "plan_end_distance": None}
        self.paths.append(entry | fields)
        return drawn

    def emit(self, robot: str, plan: str | None, output: str | None) -> None:
        """The ``--json`` object, when asked for."""
        if self.as_json:
            emit_json({"robot": robot, "plan": plan, "output": output, "paths": self.paths})


def _recordings_only(
    robot: RobotOptions,
    xacro_args: dict[str, str],
    odom_inputs: tuple[str, ...],
    topic: str | None,
    options: RecordingOptions,
    reference: str | None,
    output: str | None,
    force: bool,
    show: bool,
    said: _Said,
) -> None:
    """Recordings with no plan: their odometry paths alone (and their references'), and where
    each ends."""
    robot = robot.with_path(None, xacro_args)
    given = [robot.robot, robot.controllers, *odom_inputs]
    inputs = _prepared(given, output, force, show)
    differences: list[tuple[str, list[float], list[float]]] = []
    params = robot.load()
    options.check_robot(robot, params)
    reports: list[ConditioningReport] = []
    recordings = _odometry(
        odom_inputs, params, topic, options, reports, said, reference, differences
    )
    figure = plotting.recordings_figure(recordings, differences=differences, window=show)
    references = {label for label, _, _ in differences}
    said.echo(f"robot {robot_label(robot)}")
    for label, xs, ys in recordings:
        what = "ends" if label in references else "odometry ends"
        said.echo(f"{label}: {what} at x {fmt(xs[-1], 4)} m, y {fmt(ys[-1], 4)} m")
    if output is not None:
        plotting.save(figure, output, force=force, inputs=inputs)
    said.emit(robot_label(robot), None, output)
    if show:
        plotting.show()
    exit_if_implausible(reports)


#: The poses of a recording kept for its figure, at most twice this many: beyond, every other one
#: is dropped, and every other one of those to come, so that a recording of any length takes the
#: same memory (the figure draws at most 100 000 points of a path anyway).
KEPT_POSES: Final = 100_000

_Kept = tuple[
    "NDArray[np.int64]",
    "NDArray[np.float64]",
    "NDArray[np.float64]",
    "NDArray[np.float64]",
    "NDArray[np.float64]",
]


_Path = tuple[str, "NDArray[np.float64]", "NDArray[np.float64]"]


class _PathSink:
    """The poses of a recording as they come, compared with a reference (when given) and
    thinned to evenly spread ones, the first and the last among them: the stamp, x and y of
    each, and the reference's x and y there (NaN where it has none)."""

    columns: list[list[NDArray[Any]]]
    last: list[NDArray[Any]]
    seen: int
    kept: int
    stride: int

    def __init__(self, comparison: ReferenceComparison | None = None) -> None:
        self.comparison = comparison
        self.restart()

    def write(self, poses: ChunkPoses) -> None:
        import numpy as np

        count = poses.stamp_ns.size
        if not count:
            return
        if self.comparison is not None:
            rx, ry, _ = self.comparison.add(poses.stamp_ns, poses.x, poses.y, poses.heading)
        else:
            rx = ry = np.full(count, np.nan)
        values = (poses.stamp_ns, poses.x, poses.y, rx, ry)
        keep = np.arange(self.seen, self.seen + count) % self.stride == 0
        for column, value in zip(self.columns, values, strict=True):
            column.append(value[keep])
        self.last = [value[-1:].copy() for value in values]
        self.seen += count
        self.kept += int(np.count_nonzero(keep))
        while self.kept > 2 * KEPT_POSES:  # keep the poses at every other multiple
            self.columns = [[np.concatenate(column)[::2]] for column in self.columns]
            self.kept = self.columns[0][0].size
            self.stride *= 2

    def restart(self) -> None:
        self.columns = [[] for _ in range(5)]
        self.last = []
        self.seen = self.kept = 0
        self.stride = 1
        if self.comparison is not None:
            self.comparison.reset()

    def arrays(self) -> _Kept:
        """The stamps (ns), x (m), y (m), and the reference's x and y (m) of the poses kept."""
        import numpy as np

        # The last pose too, when it was not kept as it came.
        lasts = self.last if (self.seen - 1) % self.stride else [last[:0] for last in self.last]
        pairs = zip(self.columns, lasts, strict=True)
        stamps, x, y, rx, ry = (np.concatenate([*column, last]) for column, last in pairs)
        return stamps, x, y, rx, ry


def _odometry(
    inputs: tuple[str, ...],
    params: DiffDriveParams,
    topic: str | None,
    options: RecordingOptions,
    reports: list[ConditioningReport],
    said: _Said,
    reference: str | None = None,
    differences: list[tuple[str, list[float], list[float]]] | None = None,
) -> list[_Path]:
    """The odometry path of each recording, labelled by its file name, each followed by its
    reference's path when a reference topic is given (the distances between the two over time
    then go to ``differences``). Recordings are read in chunks, as ``diffbot odom`` reads them,
    so that millions of samples stay small; what was done to each one's positions goes to
    ``reports``, in their order, for the exit code ``diffbot odom`` would give."""
    if differences is None:
        differences = []
    recordings: list[_Path] = []
    with tempfile.TemporaryDirectory() as folder:
        for source in inputs:
            path = _stdin_file(Path(folder)) if source == "-" else Path(source)
            paths, report = _recording(
                source, path, params, topic, options, reference, differences, said
            )
            recordings.extend(paths)
            reports.append(report)
    return recordings


def _stdin_file(folder: Path) -> Path:
    """The CSV on standard input copied to a file in ``folder`` as it comes, so that it can be
    read twice: for its odometry, then for its true path."""
    import shutil
    import sys

    path = folder / "stdin.csv"
    with path.open("wb") as copy:
        shutil.copyfileobj(sys.stdin.buffer, copy)
    return path


def _recording(
    source: str,
    path: Path,
    params: DiffDriveParams,
    topic: str | None,
    options: RecordingOptions,
    reference: str | None,
    differences: list[tuple[str, list[float], list[float]]],
    said: _Said,
) -> tuple[list[_Path], ConditioningReport]:
    """The odometry path of the recording named ``source`` and read from ``path`` (standard
    input's copy for ``-``), then its true path and its reference's, when it has them; and what
    was done to its positions (warned about as ``diffbot odom`` warns)."""
    from diffbot.commands.recording_options import warn_conditioning, warn_notes
    from diffbot.reading import Reading
    from diffbot.replay import csv_odometry, recording_odometry

    comparison = None if reference is None else _comparison(source, reference)
    sink = _PathSink(comparison)
    settings: dict[str, Any] = {
        "sink": sink,
        "conditioning": options.conditioning(),
        "layout": options.layout(),
        "feedback": options.feedback_for(params),
    }
    if source == "-":
        run = csv_odometry(path, params, Reading(**settings), source=source)
    else:
        run = recording_odometry(source, params, topic, **settings)
    warn_notes(run.notes, source)
    warn_conditioning(run.conditioning, source)
    summary = run.summary
    skipped = sum(summary.skipped.values())
    if skipped:
        warn(
            f"{source}: skipped {skipped} of {summary.samples + skipped} samples "
            f"('diffbot odom {source}' says why)"
        )
    stamps, x, y, rx, ry = sink.arrays()
    implausible = run.conditioning.implausible_steps
    paths = [said.path(source, "odometry", (source, x, y), implausible_steps=implausible)]
    truth = _true_path(source, path)
    if truth is not None:
        paths.append(said.path(source, TRUE_PATH, truth))
    if comparison is not None:
        kept = (stamps, x, y, rx, ry)
        paths.append(_reference(source, comparison, kept, differences, said))
    return paths, run.conditioning


#: The label a recording's true path is drawn under: its source and this.
TRUE_PATH = "true pose"


def _true_path(source: str, path: Path) -> _Path | None:
    """The true path of a simulated run's CSV (its ``x`` and ``y`` columns, as ``diffbot
    simulate`` writes them with a true robot or a disturbed one), or None when it has none;
    read as every pose track is (:func:`~diffbot.io.poses.read_pose_track`: finite, in range,
    or one error naming the line); ``path`` is where ``source`` is read from."""
    import csv

    from diffbot.calibration.truth import TRUTH_COLUMNS
    from diffbot.errors import RecordingError
    from diffbot.io.bag import is_bag
    from diffbot.io.poses import read_pose_track
    from diffbot.io.textfile import open_text

    if is_bag(path):
        return None
    with open_text(path, RecordingError, "a recording", name=source, newline="") as handle:
        header = [name.strip() for name in next(csv.reader(handle), [])]
    if not set(TRUTH_COLUMNS) <= set(header):
        return None
    track = read_pose_track(path, name=source)
    return f"{source} {TRUE_PATH}", track.x, track.y


def _comparison(source: str, topic: str) -> ReferenceComparison:
    """The comparison of a recording's odometry with its bag's pose topic, its poses read."""
    from diffbot.io.bag import is_bag
    from diffbot.io.poses import read_pose_track
    from diffbot.reference import ReferenceComparison

    if not is_bag(source):
        fail(f"{source}: a reference topic is read from a bag, and this is a CSV")
    track = read_pose_track(source, topic)
    return ReferenceComparison(track.topic or topic, track.stamps_ns, track.x, track.y, track.theta)


def _reference(
    source: str,
    comparison: ReferenceComparison,
    kept: _Kept,
    differences: list[tuple[str, list[float], list[float]]],
    said: _Said,
) -> _Path:
    """The reference's path in the odometry's frame, its distance from the odometry over time
    appended to ``differences``, and the comparison said on stdout.

    Args:
        comparison: the comparison, every pose of the recording given to it.
        kept: the stamps (ns), x and y (m) of the poses kept for the figure, and the
            reference's x and y (m) there.
    """
    import numpy as np

    stamps, x, y, rx, ry = kept
    result = comparison.result()
    if not result.samples:
        fail(f"{source}: {comparison.topic}: {result.no_overlap_text()}")
    inside = ~np.isnan(rx)
    seconds = (stamps[inside] - stamps[0]) / 1e9
    distance = np.hypot(x[inside] - rx[inside], y[inside] - ry[inside])
    label = f"{source} {comparison.topic}"
    differences.append((label, seconds.tolist(), distance.tolist()))
    said.echo(
        f"{label}: final {fmt(result.final_position_error, 3)} m, max "
        f"{fmt(result.max_position_error, 3)} m, RMS {fmt(result.rms_position_error, 3)} m "
        "from the odometry"
    )
    return said.path(source, "reference", (label, rx[inside], ry[inside]), **result.as_dict())


@click.command(context_settings=NUMBERS)
@plan_arguments
@click.option(
    "--odom",
    "odom_inputs",
    type=InputPath(allow_dash=True),
    metavar="INPUT",
    multiple=True,
    help="A recording of the wheel joints (CSV or rosbag2, as for 'diffbot odom') whose "
    "odometry is drawn over the plan. Repeatable.",
)
@topic_option("The sensor_msgs/JointState topic of --odom bags.", reading=True)
@recording_options
@click.option(
    "--reference",
    metavar="TOPIC",
    help="Draw each --odom bag's pose topic (the robot's own odometry, nav_msgs/Odometry, or a "
    "PoseStamped track) beside diffbot's odometry, and, without a plan, their distance over "
    "time.",
)
@output_option(
    "Write the figure to FILE, its type by suffix: .png, .svg or .pdf (whole or not at all)."
)
@click.option("--force", is_flag=True, help="Overwrite --output if it exists.")
@click.option("--show", is_flag=True, help="Open the figure in a window (needs a display).")
@click.option(
    "--json",
    "as_json",
    is_flag=True,
    help="Machine-readable summary on stdout: the robot, the plan, the output and where each "
    "path drawn ends.",
)
def plot(
    robot: RobotOptions,
    plan_options: PlanOptions,
    tokens: tuple[str, ...],
    odom_inputs: tuple[str, ...],
    topic: str | None,
    recording: RecordingOptions,
    reference: str | None,
    output: str | None,
    force: bool,
    show: bool,
    as_json: bool,
) -> None:
    """A figure of a plan's path and wheel speeds, with recordings over it.

    SPEC, FILE and the plan options are those of 'diffbot plan'; without a plan,
    Trajectory A is drawn. Above: the path in the odom frame (equal axes), the start and end
    poses, the robot's footprint at each segment's end and the segment numbers; with --odom,
    each recording's odometry path, its legend giving how far it ends from the plan's end, and
    the true path of a simulated run's CSV (its x, y columns: `diffbot simulate --follow`, or
    a true robot), so that a followed run shows the plan, where the robot went and where its
    odometry says it went. A recording with implausible steps (wheel jumps) is still drawn,
    with the warning 'diffbot odom' gives for it, and the exit code is 1, as there.
    Below: both wheels' speeds over time (rpm, rad/s on the right), the motor limit, and the
    segments over it shaded (a warning names them; the exit code stays 0).

    Writing a file needs no display. Plotting needs the optional matplotlib dependency:

    \b
      pip install 'diffbot-kinematics[plot]'

    \b
    Examples:
      diffbot plot --example A -o a.png
      diffbot plot "straight 1 10s; spin 90" --odom docs/examples/joints.csv -o run.svg
      diffbot plot --example B --fastest -o b.pdf
    """
    rest, xacro_args = split_xacro_args(tokens)
    said = _Said(as_json)
    if output is None and not show:
        fail("nothing to do: give -o FILE (.png, .svg or .pdf) to write the figure, or --show")
    if output is not None and not output.strip():
        fail("-o needs a file name, got ''")
    if odom_inputs.count("-") > 1:
        fail("--odom - reads standard input, which can be read once: give it once")
    if recording.feedback is not None and not odom_inputs:
        fail("--feedback says how --odom recordings are read: give one with --odom")
    if odom_inputs and not rest and plan_options.example is None and plan_options.goal is None:
        _recordings_only(
            robot, xacro_args, odom_inputs, topic, recording, reference, output, force, show, said
        )
        return
    request = plan_options.request(robot, tokens)
    source, robot = request.source, request.robot
    given = [source.path, robot.robot, robot.controllers, *odom_inputs]
    inputs = _prepared(given, output, force, show)
    built = plan_options.build(request, writes=True)
    params, made = built.params, built.made
    if not isinstance(made, Plan):
        # The step plan holds the cruise speeds, the motor limit check and the poses.
        warn("a ramped plan is drawn at its cruise speeds: the ramps are not drawn")
        made = made.steps
    p = made
    if odom_inputs:
        recording.check_robot(robot, params)
        said.echo(f"robot {robot_label(robot)}")
    reports: list[ConditioningReport] = []
    recordings = _odometry(odom_inputs, params, topic, recording, reports, said, reference)
    figure = plotting.plan_figure(p, params, recordings=recordings, window=show)
    for entry, (label, xs, ys) in zip(said.paths, recordings, strict=True):
        miss = plotting.end_distance(p, xs[-1], ys[-1])
        entry["plan_end_distance"] = miss
        what = "ends" if label.endswith(TRUE_PATH) else "odometry ends"
        said.echo(f"{label}: {what} {fmt(miss, 3)} m from the plan's end")
    for found in sorted({v.index for v in p.violations()}):
        segment = p.segments[found]
        warn(f"segment {found + 1} ({segment.kind}) is over the motor limit: shaded in the figure")
    if output is not None:
        plotting.save(figure, output, force=force, inputs=inputs)
    said.emit(robot_label(robot), source.label, output)
    if show:
        plotting.show()
    exit_if_implausible(reports)
