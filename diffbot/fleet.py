"""Odometry of many recordings: one task per recording, run in turn, in a process pool of the
standard library, or on a Dask cluster (``pip install 'diffbot-kinematics[fleet]'``).

A task reads its recording in chunks and writes its poses as they come (a CSV file or a bag,
whole or not at all); a recording that cannot be read is reported in its result and does not
stop the others. Results come back in the order of the tasks.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import Final, TextIO

from diffbot.chunk_odometry import ChunkPoses
from diffbot.conditioning import Conditioning
from diffbot.errors import DiffbotError, OutputError, RecordingError
from diffbot.io.bag import OdometryBagWriter
from diffbot.io.csv_chunks import CsvLayout
from diffbot.io.csvfile import ODOMETRY_HEADER, odometry_lines
from diffbot.io.outputs import atomic_text, input_clash
from diffbot.kinematics import DiffDriveParams, norm_angle
from diffbot.odometry import Odometry
from diffbot.reference import ReferenceComparison, ReferenceResult
from diffbot.replay import Progress, RecordingOdometry, csv_odometry, recording_odometry

__all__ = [
    "DASK_INSTALL_HINT",
    "OdometryResult",
    "OdometryTask",
    "output_name",
    "run_task",
    "run_tasks",
]

#: What to install for --dask.
DASK_INSTALL_HINT: Final = "pip install 'dask[distributed]' (the fleet extra of diffbot-kinematics)"


@dataclass(frozen=True)
class OdometryTask:
    """The odometry of one recording, and where its poses go.

    Attributes:
        input: a CSV file, a rosbag2 directory or one of its storage files; ``-`` for the CSV
            on ``stream``.
        params: the robot.
        topic: the JointState topic of a bag (None: ``/joint_states``, or else its only
            JointState topic).
        output: where to write the poses (a CSV file, or a bag directory with ``as_bag``).
        as_bag: write ``output`` as a rosbag2 of nav_msgs/Odometry and TF.
        force: replace an existing output.
        conditioning: the recorded positions' units and wrap (default: radians, wraps
            detected).
        layout: a CSV's columns, delimiter and time unit, where not the defaults.
        reference: a pose topic of the same bag (nav_msgs/Odometry or PoseStamped) to hold
            the odometry against; its poses are added to the CSV output.
    """

    input: str
    params: DiffDriveParams
    topic: str | None = None
    output: str | None = None
    as_bag: bool = False
    force: bool = False
    conditioning: Conditioning | None = None
    layout: CsvLayout | None = None
    reference: str | None = None


@dataclass(frozen=True)
class OdometryResult:
    """What a task gave: the run, or the error that stopped it; and how many poses it wrote."""

    task: OdometryTask
    run: RecordingOdometry | None
    error: DiffbotError | None = None
    poses: int = 0
    reference: ReferenceResult | None = None


def output_name(path: str | os.PathLike[str], as_bag: bool) -> str:
    """The name of a recording's output in an output directory: its stem, ``.csv`` unless a
    bag (``run.mcap`` -> ``run.csv``; the bag folder ``day1/`` -> ``day1``)."""
    p = Path(path)
    stem = p.name if p.is_dir() else p.stem
    return stem if as_bag else f"{stem}.csv"


#: The columns a reference adds to an odometry CSV: its pose at each row's stamp.
REFERENCE_COLUMNS: Final = ("reference_x", "reference_y", "reference_theta")


class _CsvSink:
    def __init__(self, out: TextIO, comparison: ReferenceComparison | None = None) -> None:
        self.out = out
        self.count = 0
        self.comparison = comparison
        self.header = ODOMETRY_HEADER
        if comparison is not None:
            self.header = ODOMETRY_HEADER.rstrip("\n") + "," + ",".join(REFERENCE_COLUMNS) + "\n"
        out.write(self.header)

    def write(self, poses: ChunkPoses) -> None:
        text = odometry_lines(*(column.tolist() for column in poses))
        if self.comparison is not None:
            ref = self.comparison.add(poses.stamp_ns, poses.x, poses.y, poses.heading)
            cells = [
                ",".join("" if v != v else repr(v) for v in row)
                for row in zip(*(column.tolist() for column in ref), strict=True)
            ]
            text = "".join(
                f"{line},{extra}\n" for line, extra in zip(text.splitlines(), cells, strict=True)
            )
        self.out.write(text)
        self.count += poses.stamp_ns.size

    def restart(self) -> None:
        self.out.seek(0)
        self.out.truncate()
        self.out.write(self.header)
        self.count = 0
        if self.comparison is not None:
            self.comparison.reset()


class _ComparingSink:
    """Poses to a reference comparison, then on to another sink (if any)."""

    def __init__(self, comparison: ReferenceComparison, inner: _CsvSink | _BagSink | None) -> None:
        self.comparison = comparison
        self.inner = inner

    def write(self, poses: ChunkPoses) -> None:
        self.comparison.add(poses.stamp_ns, poses.x, poses.y, poses.heading)
        if self.inner is not None:
            self.inner.write(poses)

    def restart(self) -> None:
        self.comparison.reset()
        if self.inner is not None:
            self.inner.restart()


class _BagSink:
    def __init__(self, bag: OdometryBagWriter) -> None:
        self.bag = bag

    @property
    def count(self) -> int:
        return self.bag.count

    def write(self, poses: ChunkPoses) -> None:
        theta = [norm_angle(h) for h in poses.heading.tolist()]
        self.bag.write(
            poses.stamp_ns.tolist(),
            poses.x.tolist(),
            poses.y.tolist(),
            theta,
            poses.linear.tolist(),
            poses.angular.tolist(),
        )

    def restart(self) -> None:
        self.bag.restart()


_Sink = _CsvSink | _BagSink | _ComparingSink


def _comparison(task: OdometryTask) -> ReferenceComparison | None:
    """The comparison with the task's reference topic, its poses read whole; None without."""
    if task.reference is None:
        return None
    from diffbot.io.bag import is_bag
    from diffbot.io.poses import read_pose_track

    if task.input == "-" or not is_bag(task.input):
        raise RecordingError(
            f"{task.input}: a reference topic is read from a bag, and this is a CSV"
        )
    track = read_pose_track(task.input, task.reference)
    return ReferenceComparison(task.reference, track.stamps_ns, track.x, track.y, track.theta)


def run_task(
    task: OdometryTask, progress: Progress | None = None, stream: TextIO | None = None
) -> OdometryResult:
    """Run one task; a :class:`DiffbotError` is returned in the result, not raised.

    Args:
        task: the task.
        progress: called after each chunk with how much of the input it used.
        stream: the CSV text when ``task.input`` is ``-``.
    """
    try:
        comparison = _comparison(task)

        def compared(sink: _CsvSink | _BagSink | None) -> _Sink | None:
            if comparison is None or isinstance(sink, _CsvSink):
                return sink  # a CSV sink compares as it writes its reference columns
            return _ComparingSink(comparison, sink)

        def result(run: RecordingOdometry, poses: int = 0) -> OdometryResult:
            reference = None if comparison is None else comparison.result()
            return OdometryResult(task, run, poses=poses, reference=reference)

        def odometry(output: _CsvSink | _BagSink | None) -> RecordingOdometry:
            sink = compared(output)
            if task.input == "-":
                assert stream is not None
                return csv_odometry(
                    stream,
                    task.params,
                    source="-",
                    sink=sink,
                    progress=progress,
                    conditioning=task.conditioning,
                    layout=task.layout,
                )
            return recording_odometry(
                task.input,
                task.params,
                task.topic,
                sink=sink,
                progress=progress,
                conditioning=task.conditioning,
                layout=task.layout,
            )

        inputs = [] if task.input == "-" else [Path(task.input)]
        if task.output is None:
            return result(odometry(None))
        if input_clash(Path(task.output), inputs) is not None:
            raise OutputError(f"{task.output} is or holds the input {task.input}: refusing it")
        if task.as_bag:
            with OdometryBagWriter(task.output, Odometry(task.params), force=task.force) as bag:
                bag_sink = _BagSink(bag)
                run = odometry(bag_sink)
            return result(run, bag_sink.count)
        with atomic_text(Path(task.output), force=task.force, inputs=inputs) as out:
            csv_sink = _CsvSink(out, comparison)
            run = odometry(csv_sink)
        return result(run, csv_sink.count)
    except DiffbotError as err:
        return OdometryResult(task, None, err)
    except OSError as err:
        where = f"{err.filename}: " if err.filename else f"{task.input}: "
        return OdometryResult(task, None, RecordingError(f"{where}{err.strerror or err}"))


def run_tasks(
    tasks: Sequence[OdometryTask],
    *,
    jobs: int = 1,
    dask_address: str | None = None,
    done: Callable[[OdometryResult], None] | None = None,
) -> Iterator[OdometryResult]:
    """Run the tasks and yield their results in order.

    Args:
        tasks: the tasks.
        jobs: processes to run them in (1: in this process, one after another).
        dask_address: the scheduler of a Dask cluster to run them on instead (``tcp://...``).
        done: called as each task finishes, in the order they finish.

    Raises:
        RecordingError: dask is missing, or its scheduler cannot be reached.
    """
    if dask_address is not None:
        yield from _run_dask(tasks, dask_address, done)
        return
    if jobs <= 1 or len(tasks) <= 1:
        for task in tasks:
            result = run_task(task)
            if done is not None:
                done(result)
            yield result
        return
    with ProcessPoolExecutor(max_workers=min(jobs, len(tasks))) as pool:
        futures = [pool.submit(run_task, task) for task in tasks]
        if done is not None:
            for future in futures:
                future.add_done_callback(lambda f: done(f.result()))
        for future in futures:
            yield future.result()


def _run_dask(
    tasks: Sequence[OdometryTask],
    address: str,
    done: Callable[[OdometryResult], None] | None,
) -> Iterator[OdometryResult]:
    try:
        from distributed import Client
    except ImportError:
        raise RecordingError(
            f"running on a Dask cluster needs dask.distributed: {DASK_INSTALL_HINT}"
        ) from None
    try:
        client = Client(address, timeout=10)  # type: ignore[no-untyped-call]
    except (OSError, TimeoutError) as err:
        raise RecordingError(f"cannot reach the Dask scheduler at {address}: {err}") from None
    with client:
        futures = client.map(run_task, list(tasks), pure=False)
        results = client.gather(futures)  # type: ignore[no-untyped-call]
        for result in results:
            if done is not None:
                done(result)
            yield result
