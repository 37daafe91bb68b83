"""Odometry of many recordings: one task per recording, run in turn, in a process pool of the
standard library, or on a Dask cluster (``pip install 'diffbot-kinematics[fleet]'``).

A task reads its recording in chunks and writes its poses as they come (a CSV file or a bag,
whole or not at all); a recording that cannot be read is reported in its result and does not
stop the others. Results come back in the order of the tasks.
"""

from __future__ import annotations

import contextlib
import functools
import os
import re
import warnings
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, Final, TextIO

from diffbot.chunk_odometry import ChunkPoses
from diffbot.conditioning import Conditioning
from diffbot.errors import DiffbotError, OutputError, RecordingError
from diffbot.formats.text import brief, fmt
from diffbot.io.bag import OdometryBagWriter
from diffbot.io.csv_chunks import CsvLayout
from diffbot.io.csvfile import ODOMETRY_HEADER, odometry_lines
from diffbot.io.outputs import atomic_text, input_clash
from diffbot.kinematics import DiffDriveParams, norm_angle
from diffbot.odometry import Odometry
from diffbot.processes import safe_starts
from diffbot.reading import Progress, Reading
from diffbot.reference import ReferenceComparison, ReferenceResult
from diffbot.replay import RecordingOdometry, csv_odometry, recording_odometry

if TYPE_CHECKING:
    from concurrent.futures import Future
    from multiprocessing.synchronize import Event

__all__ = [
    "DASK_DEFAULT_PORT",
    "DASK_INSTALL_HINT",
    "DASK_SCHEMES",
    "DASK_TIMEOUT",
    "OdometryResult",
    "OdometryTask",
    "dask_address",
    "output_name",
    "run_task",
    "run_tasks",
]

#: What to install for --dask.
DASK_INSTALL_HINT: Final = "pip install 'dask[distributed]' (the fleet extra of diffbot-kinematics)"
#: Address schemes of a Dask scheduler (``inproc`` only names one in this same process).
DASK_SCHEMES: Final = ("tcp", "tls", "ws", "wss", "ucx", "inproc")
#: The scheduler's port when an address gives none (Dask's default).
DASK_DEFAULT_PORT: Final = 8786
#: Seconds to wait for a Dask scheduler to answer, unless told otherwise.
DASK_TIMEOUT: Final = 10.0


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
        feedback: ``"position"`` or ``"velocity"``: the wheel joints' field to integrate.
        open_loop: integrate the commanded body velocities instead (``topic`` is then the
            command topic, a CSV holds ``t,v,w``).
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
    feedback: str = "position"
    open_loop: bool = False


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
    """Poses to an odometry bag; with a ``window`` of more than one step, their twists over
    that many steps, as the robot's controller (and ``node odom``) publishes them."""

    def __init__(self, bag: OdometryBagWriter, window: int = 1) -> None:
        from diffbot.window_sums import RollingVelocity

        self.bag = bag
        self.rolling = RollingVelocity(window) if window > 1 else None

    @property
    def count(self) -> int:
        return self.bag.count

    def write(self, poses: ChunkPoses) -> None:
        theta = [norm_angle(h) for h in poses.heading.tolist()]
        stamps, linear, angular = (
            poses.stamp_ns.tolist(),
            poses.linear.tolist(),
            poses.angular.tolist(),
        )
        if self.rolling is not None:
            linear, angular = self.rolling(stamps, linear, angular)
        self.bag.write(stamps, poses.x.tolist(), poses.y.tolist(), theta, linear, angular)

    def restart(self) -> None:
        self.bag.restart()
        if self.rolling is not None:
            self.rolling.restart()


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
    topic = track.topic or task.reference
    return ReferenceComparison(topic, track.stamps_ns, track.x, track.y, track.theta)


def _published_as(params: DiffDriveParams) -> Odometry:
    """An integrator carrying the frames and covariances the robot's controller publishes (its
    prefixed frames, its covariances or their zero defaults), else the odometry's own."""
    controller = params.controller
    if controller is None:
        return Odometry(params)
    return Odometry(
        params,
        frame_id=controller.odom_frame,
        child_frame_id=controller.base_frame,
        pose_covariance=controller.pose_covariance,
        twist_covariance=controller.twist_covariance,
    )


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
            if task.open_loop:
                if task.input == "-":
                    raise RecordingError("{open_loop} reads a bag or a CSV file, not stdin")
                # Only the wheels have a conditioning and a feedback.
                return recording_odometry(
                    task.input,
                    task.params,
                    task.topic,
                    sink=sink,
                    layout=task.layout,
                    open_loop=True,
                )
            options: dict[str, Any] = {
                "sink": sink,
                "progress": progress,
                "conditioning": task.conditioning,
                "layout": task.layout,
                "feedback": task.feedback,
            }
            if task.input == "-":
                assert stream is not None
                return csv_odometry(stream, task.params, Reading(**options), source="-")
            return recording_odometry(task.input, task.params, task.topic, **options)

        inputs = [] if task.input == "-" else [Path(task.input)]
        if task.output is None:
            return result(odometry(None))
        if input_clash(Path(task.output), inputs) is not None:
            raise OutputError(f"{task.output} is or holds the input {task.input}: refusing it")
        if task.as_bag:
            with OdometryBagWriter(
                task.output, _published_as(task.params), force=task.force
            ) as bag:
                # The controller's open loop publishes the held command: no window.
                controller = task.params.controller
                window = 1 if controller is None or task.open_loop else controller.rolling_window
                bag_sink = _BagSink(bag, window)
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
    dask_timeout: float = DASK_TIMEOUT,
    done: Callable[[OdometryResult], None] | None = None,
) -> Iterator[OdometryResult]:
    """Run the tasks and yield their results in order.

    Args:
        tasks: the tasks.
        jobs: processes to run them in (1: in this process, one after another).
        dask_address: the scheduler of a Dask cluster to run them on instead
            (``tcp://HOST:PORT``); inputs and outputs travel to its workers as absolute paths,
            so the workers must share this machine's storage.
        dask_timeout: seconds to wait for the scheduler to answer when connecting.
        done: called as each task finishes, in the order they finish (after the whole run on
            Dask).

    Raises:
        RecordingError: dask is missing, the address is malformed, or the scheduler cannot be
            reached or talked to within ``dask_timeout``.
    """
    if dask_address is not None:
        yield from _run_dask(tasks, dask_address, dask_timeout, done)
        return
    if jobs <= 1 or len(tasks) <= 1:
        for task in tasks:
            result = run_task(task)
            if done is not None:
                done(result)
            yield result
        return
    # Loaded here: the process pool and asyncio below weigh on every single-input run's start.
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    # The pool's helper process starts with it (or with the event, the first thing it
    # shares) and every worker during the submissions, so all of them start clear of the
    # current folder's code.
    with safe_starts():
        stop = multiprocessing.get_context().Event()
        pool = ProcessPoolExecutor(
            max_workers=min(jobs, len(tasks)), initializer=_worker_start, initargs=(stop,)
        )
    with pool:
        try:
            with safe_starts():
                futures = [pool.submit(_pool_task, task) for task in tasks]
            if done is not None:
                for future in futures:
                    future.add_done_callback(functools.partial(_finished, done))
            for future in futures:
                yield future.result()
        except BaseException:
            # The run ends early (Ctrl-C, SIGTERM, results no longer wanted): the tasks not
            # started never start, and those under way stop at their next chunk, their
            # outputs unwritten.
            stop.set()
            pool.shutdown(wait=True, cancel_futures=True)
            raise


class _Stopped(BaseException):
    """The run the task belongs to has ended: it stops where it is."""


class _Worker:
    """What a pool worker knows of its run: the event set when the run ends early."""

    stop: Event | None = None


def _worker_start(stop: Event) -> None:
    """A pool worker's start. Ctrl-C reaches the whole process group, and is for the process
    that runs the pool to act on: one taken in a worker mid-task can leave the pool waiting for
    it forever. SIGTERM ends the task under way by an exception, so that its output's
    temporary file is removed."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if signal.getsignal(signal.SIGTERM) is not signal.SIG_IGN:
        signal.signal(signal.SIGTERM, _terminated)
    _Worker.stop = stop


def _terminated(signum: int, frame: object) -> None:
    raise SystemExit(128 + signum)  # the exit status of a process the signal ended


def _go_on(used: int = 0) -> None:
    """Raise :class:`_Stopped` once the worker's run has ended (called between chunks)."""
    if _Worker.stop is not None and _Worker.stop.is_set():
        raise _Stopped


def _pool_task(task: OdometryTask) -> OdometryResult:
    """A task in a pool worker: not started, or stopped between two chunks, once the run has
    ended."""
    _go_on()
    return run_task(task, progress=_go_on)


def _finished(done: Callable[[OdometryResult], None], future: Future[OdometryResult]) -> None:
    """Hand a finished task's result on; a task cancelled or stopped has none."""
    if not future.cancelled() and future.exception() is None:
        done(future.result())


_HOST = re.compile(r"[A-Za-z0-9](?:[A-Za-z0-9.\-]*[A-Za-z0-9])?|\[[0-9A-Fa-f:.]+\]")


def dask_address(address: str) -> str:
    """A Dask scheduler address checked and made whole: ``SCHEME://HOST:PORT``.

    The scheme defaults to ``tcp`` and the port to 8786, as in Dask.

    Raises:
        RecordingError: an unknown scheme, no host or a malformed one, or a port outside
            1-65535 (the message names the address).
    """
    shown = brief(address)
    scheme, sep, rest = address.partition("://")
    if not sep:
        scheme, rest = "tcp", address
    if scheme not in DASK_SCHEMES:
        raise RecordingError(
            f"{{dask_address}} {shown}: unknown scheme {brief(scheme)} "
            f"(expected {', '.join(DASK_SCHEMES)})"
        )
    if scheme == "inproc":
        if not rest or any(c.isspace() for c in rest):
            raise RecordingError(f"{{dask_address}} {shown}: an inproc address names HOST/PID/N")
        return address
    host, colon, port_text = rest.rpartition(":")
    if not colon or "]" in port_text:  # no port; an IPv6 address in brackets has colons
        host, port_text = rest, str(DASK_DEFAULT_PORT)
    if not _HOST.fullmatch(host):
        raise RecordingError(
            f"{{dask_address}} {shown}: expected {scheme}://HOST:PORT, "
            "the host is missing or malformed"
        )
    if not port_text.isdigit() or not 1 <= int(port_text[:6]) <= 65535:
        raise RecordingError(f"{{dask_address}} {shown}: the port must be a number from 1 to 65535")
    return f"{scheme}://{host}:{int(port_text)}"


def _absolute(task: OdometryTask) -> OdometryTask:
    """The task with absolute paths: workers share the storage, not this process's folder."""
    output = None if task.output is None else os.path.abspath(task.output)
    source = task.input if task.input == "-" else os.path.abspath(task.input)
    return replace(task, input=source, output=output)


def _run_dask(
    tasks: Sequence[OdometryTask],
    address: str,
    timeout: float,
    done: Callable[[OdometryResult], None] | None,
) -> Iterator[OdometryResult]:
    address = dask_address(address)
    try:
        import distributed  # noqa: F401
    except ImportError:
        raise RecordingError(
            f"running on a Dask cluster needs dask.distributed: {DASK_INSTALL_HINT}"
        ) from None
    import asyncio
    import logging

    remote = [_absolute(task) for task in tasks]
    logger = logging.getLogger("distributed")
    level = logger.level
    # Dask logs what went wrong with a traceback; the error raised here says it in one line.
    logger.setLevel(logging.CRITICAL + 1)
    try:
        with warnings.catch_warnings():
            # A scheduler that never answered leaves a client whose clean-up Python reports.
            warnings.simplefilter("ignore", RuntimeWarning)
            results = asyncio.run(_dask_results(remote, address, timeout))
    finally:
        logger.setLevel(level)
    for task, result in zip(tasks, results, strict=True):
        result = replace(result, task=task)
        if done is not None:
            done(result)
        yield result


async def _dask_results(
    tasks: list[OdometryTask], address: str, timeout: float
) -> list[OdometryResult]:
    """Run the tasks on the cluster; any failure to reach or talk to it is one error."""
    import asyncio

    from distributed import Client

    client = Client(address, asynchronous=True, timeout=timeout, set_as_default=False)  # type: ignore[no-untyped-call]
    try:
        await asyncio.wait_for(client, timeout)
    except BaseException as err:
        with contextlib.suppress(BaseException):
            await asyncio.wait_for(client.close(), 1)  # type: ignore[no-untyped-call]
        if isinstance(err, TimeoutError):
            raise RecordingError(
                f"the Dask scheduler at {address} did not answer within {fmt(timeout)} s "
                "({dask_timeout})"
            ) from None
        if isinstance(err, Exception):
            raise RecordingError(
                f"cannot talk to the Dask scheduler at {address}: {_reason(err)}"
            ) from None
        raise
    try:
        futures = client.map(run_task, tasks, pure=False)
        results: list[OdometryResult] = await client.gather(futures)  # type: ignore[no-untyped-call]
    except Exception as err:
        raise RecordingError(f"the Dask cluster at {address} failed: {_reason(err)}") from None
    finally:
        with contextlib.suppress(Exception):
            await asyncio.wait_for(client.close(), timeout)  # type: ignore[no-untyped-call]
    return results


def _reason(err: BaseException) -> str:
    """An exception in one short line: a garbage answer can make a long message."""
    if isinstance(err, MemoryError):
        return "it sent a message of absurd size"
    text = " ".join(str(err).split()) or f"a malformed answer ({type(err).__name__})"
    return text if len(text) <= 160 else text[:157] + "..."
