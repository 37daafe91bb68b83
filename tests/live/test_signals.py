"""Live nodes stop cleanly on any signal, at any moment: hundreds of SIGINTs and SIGTERMs at
seeded random moments to nodes fed at 1 kHz, each ending its run between two steps (never inside
cyclonedds' take, where a raised KeyboardInterrupt killed the process with SIGSEGV), the last
commands of ``node ik`` and ``drive`` zero.

The signals go to harness processes (this file run as a script): each spins one kind of node in
its main thread, as the command line does, while a thread feeds it at 1 kHz and another sends
the process a signal a random few milliseconds into each run. A harness lives in a domain of
its own with discovery inside the process (``ROS_AUTOMATIC_DISCOVERY_RANGE=OFF``), so the
harnesses run side by side; its report is one JSON line.
"""

from __future__ import annotations

import json
import os
import random
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
from live_graph import PATIENCE, spare_domain

from diffbot import signal_handlers
from diffbot.live import signals

#: Signals per harness; four harnesses (odom, ik, robot, drive).
SIGNALS = 100
#: The feed's rate (Hz).
FEED_RATE = 1000.0
#: The drive's command rate (Hz).
DRIVE_RATE = 1000.0
#: How long into a run its signal comes (s): from at once to a few dozen feed periods.
MOMENTS = (0.0, 0.03)

Kind = str


def _harness_env(kind_index: int) -> dict[str, str]:
    env = os.environ.copy()
    env["ROS_DOMAIN_ID"] = str(spare_domain(1 + kind_index))
    env["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "OFF"
    env["PYTHONPATH"] = os.pathsep.join([str(Path(__file__).parents[1]), env.get("PYTHONPATH", "")])
    return env


@pytest.mark.parametrize("seed", [26])
def test_hundreds_of_signals_at_random_moments_end_every_run_cleanly(seed: int) -> None:
    kinds = ("odom", "ik", "robot", "drive")
    started = time.monotonic()
    processes = [
        subprocess.Popen(
            [sys.executable, __file__, kind, str(SIGNALS), str(seed + i)],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            env=_harness_env(i),
        )
        for i, kind in enumerate(kinds)
    ]
    reports: dict[str, dict[str, Any]] = {}
    try:
        for kind, process in zip(kinds, processes, strict=True):
            out, err = process.communicate(timeout=120)
            # A segmentation fault is -11; any traceback shows here too.
            assert process.returncode == 0, f"{kind}: exit {process.returncode}\n{err[-3000:]}"
            reports[kind] = json.loads(out.strip().splitlines()[-1])
    finally:
        for process in processes:
            process.kill()
    took = time.monotonic() - started
    total = 0
    for kind, report in reports.items():
        assert report["runs"] == SIGNALS, (kind, report)
        # Each run ended by its own signal, as the handler before would have had it: a
        # KeyboardInterrupt for SIGINT, the command line's SystemExit(143) for SIGTERM.
        assert report["ended_by_its_signal"] == SIGNALS, (kind, report)
        assert report["sigint"] > 0, (kind, report)
        assert report["sigterm"] > 0, (kind, report)
        assert report["sigint"] + report["sigterm"] == SIGNALS
        # The loop noticed at once: a woken wait returns at once, an unwoken one within its
        # 50 ms slice; the bound leaves room for a busy machine (a drive's stop includes its
        # final zero's acknowledgement).
        assert 0.0 < report["slowest_stop"] < 2.0, (kind, report)
        # Fed throughout, and still working after every signal.
        assert report["handled"] > SIGNALS, (kind, report)
        if kind != "drive":
            assert report["inside_take"] > SIGNALS // 4, (kind, report)
        total += report["runs"]
    for kind in ("ik", "drive"):
        assert reports[kind]["last_zero"] == SIGNALS, reports[kind]
    assert total == 4 * SIGNALS
    print(f"{total} signals in {took:.1f} s: {json.dumps(reports)}")


def test_a_deferred_signal_goes_to_the_handler_before_or_ends_the_run() -> None:
    got: list[int] = []
    woken: list[bool] = []
    before = signal.signal(signal.SIGTERM, lambda signum, frame: got.append(signum))
    try:
        with signals.deferred(lambda: woken.append(True)):
            signal.raise_signal(signal.SIGTERM)
            assert signals.caught() == signal.SIGTERM
            assert woken == [True]
            assert got == []  # not yet: the block is still running
        assert got == [signal.SIGTERM]
        assert signals.caught() is None
        with signals.deferred(deliver=False):
            with signals.deferred():  # nested: the outermost decides
                signal.raise_signal(signal.SIGTERM)
            assert signals.caught() == signal.SIGTERM
        assert got == [signal.SIGTERM]  # taken as the run's end, not handed on
        with pytest.raises(KeyboardInterrupt), signals.deferred():
            signal.raise_signal(signal.SIGINT)
    finally:
        signal.signal(signal.SIGTERM, before)


def test_a_block_that_decides_the_outcome_leaves_the_signals_it_took_ignored(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    got: list[int] = []
    before = {
        signal.SIGINT: signal.getsignal(signal.SIGINT),
        signal.SIGTERM: signal.signal(signal.SIGTERM, lambda signum, frame: got.append(signum)),
        signal.SIGHUP: signal.signal(signal.SIGHUP, signal.SIG_IGN),
    }
    handlers = {signum: signal.getsignal(signum) for signum in before}
    try:
        # Inside another program (this test run) the block gives its signals back ...
        with signals.deferred(deliver=False, ends_run=True):
            signal.raise_signal(signal.SIGTERM)
        assert {signum: signal.getsignal(signum) for signum in before} == handlers
        got.clear()
        # ... in a process that ends with its run (the command line's) they stay ignored.
        monkeypatch.setattr(signal_handlers._Process, "ends_with_run", True)
        with signals.deferred(deliver=False, ends_run=True):
            signal.raise_signal(signal.SIGTERM)
            assert signals.caught() == signal.SIGTERM
        assert signals.caught() is None
        for signum in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
            assert signal.getsignal(signum) is signal.SIG_IGN
        signal.raise_signal(signal.SIGTERM)  # a second signal: nothing runs, nothing ends
        assert got == []
    finally:
        for signum, handler in before.items():
            signal.signal(signum, handler)


def test_a_deferred_signal_under_the_default_action_is_raised_again_after_the_block(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # Under SIG_DFL the signal must end the process as it would have: raised again once the
    # block has restored the default action (recorded here instead of ending the test run).
    raised: list[tuple[int, object]] = []
    monkeypatch.setattr(
        signal, "raise_signal", lambda signum: raised.append((signum, signal.getsignal(signum)))
    )
    before = signal.signal(signal.SIGTERM, signal.SIG_DFL)
    try:
        with signals.deferred():
            os.kill(os.getpid(), signal.SIGTERM)
            assert signals.caught() == signal.SIGTERM
            assert raised == []
        assert raised == [(signal.SIGTERM, signal.SIG_DFL)]
    finally:
        signal.signal(signal.SIGTERM, before)


def test_only_the_main_thread_defers_and_sees_a_signal() -> None:
    seen: list[int | None] = []

    def elsewhere() -> None:
        with signals.deferred():  # does nothing outside the main thread
            seen.append(signals.caught())

    before = signal.getsignal(signal.SIGTERM)
    with signals.deferred(deliver=False):
        signal.raise_signal(signal.SIGTERM)
        assert signals.caught() == signal.SIGTERM
        thread = threading.Thread(target=elsewhere)
        thread.start()
        thread.join()
    assert seen == [None]
    assert signals.caught() is None
    assert signal.getsignal(signal.SIGTERM) is before


def test_an_ignored_signal_stays_ignored() -> None:
    before = signal.signal(signal.SIGHUP, signal.SIG_IGN)
    try:
        with signals.deferred():
            assert signal.getsignal(signal.SIGHUP) is signal.SIG_IGN
            signal.raise_signal(signal.SIGHUP)
            assert signals.caught() is None
    finally:
        signal.signal(signal.SIGHUP, before)


# ---- the harness: runs in its own process --------------------------------------------------


class _Feeder:
    """Calls ``send()`` at :data:`FEED_RATE` in a thread of its own until stopped."""

    def __init__(self, send: Callable[[], None]) -> None:
        self.send = send
        self.stopped = threading.Event()
        self.thread = threading.Thread(target=self.run, daemon=True)
        self.thread.start()

    def run(self) -> None:
        period = 1.0 / FEED_RATE
        due = time.monotonic()
        while not self.stopped.is_set():
            self.send()
            due += period
            time.sleep(max(0.0, due - time.monotonic()))

    def stop(self) -> None:
        self.stopped.set()
        self.thread.join(5.0)


class _Killer:
    """Sends this process one signal ``delay`` seconds after :attr:`go` is set, from a thread
    of its own (a random moment of the run)."""

    def __init__(self, signum: int, delay: float) -> None:
        self.signum = signum
        self.sent_at = 0.0
        self.go = threading.Event()
        self.thread = threading.Thread(target=self.run, args=(delay,), daemon=True)
        self.thread.start()

    def run(self, delay: float) -> None:
        self.go.wait()
        time.sleep(delay)
        self.sent_at = time.monotonic()
        os.kill(os.getpid(), self.signum)


class _InsideTake:
    """Raises a signal from inside cyclonedds' take, in the Python code its C part calls for a
    sample's info (``SampleInfo.__init__``): the moment where a handler that raises kills the
    process. Armed with a signal and a count of samples to let pass first."""

    def __init__(self) -> None:
        from cyclonedds import internal

        self.signum: int | None = None
        self.countdown = 0
        self.sent_at = 0.0
        original = internal.SampleInfo.__init__
        main = threading.main_thread()

        def init(info: object, *args: object, **kwargs: object) -> None:
            if self.signum is not None and threading.current_thread() is main:
                self.countdown -= 1
                if self.countdown <= 0:
                    signum, self.signum = self.signum, None
                    self.sent_at = time.monotonic()
                    signal.raise_signal(signum)
            original(info, *args, **kwargs)

        internal.SampleInfo.__init__ = init  # type: ignore[method-assign]

    def arm(self, signum: int, countdown: int) -> None:
        self.countdown = countdown
        self.signum = signum


def _ended_by(run: Callable[[], object]) -> int | None:
    """Which signal ended ``run()``: the exception the handler before raised."""
    try:
        run()
    except KeyboardInterrupt:
        return int(signal.SIGINT)
    except SystemExit as err:
        return int(err.code) - 128 if isinstance(err.code, int) else None
    return None


def _wait(condition: Callable[[], bool]) -> bool:
    end = time.monotonic() + PATIENCE
    while not condition():
        if time.monotonic() > end:
            return False
        time.sleep(0.001)
    return True


def harness(kind: Kind, runs: int, seed: int) -> dict[str, Any]:
    """Run ``runs`` runs of a ``kind`` node fed at 1 kHz, each ended by SIGINT or SIGTERM at a
    seeded random moment; what happened, counted."""
    from robots import BOT

    from diffbot.cli import _end_run
    from diffbot.live import types
    from diffbot.live.cdr import encode_joint_state
    from diffbot.live.messages import twist_command
    from diffbot.live.odometry import OdometryNode
    from diffbot.live.robot import RobotNode
    from diffbot.live.transport import Node, QosProfile
    from diffbot.planfile import parse_plan
    from diffbot.ramps import sampled
    from diffbot.trajectory import plan
    from diffbot.wheel_commands import LEFT_TOPIC, RIGHT_TOPIC

    signal.signal(signal.SIGTERM, _end_run)  # as the command line has it
    rng = random.Random(seed)
    report: dict[str, Any] = {
        "kind": kind,
        "runs": 0,
        "sigint": 0,
        "sigterm": 0,
        "ended_by_its_signal": 0,
        "slowest_stop": 0.0,
        "last_zero": 0,
        "handled": 0,
        "inside_take": 0,
    }
    inside_take = _InsideTake()
    reliable = QosProfile(reliable=True, depth=100_000)
    last: dict[str, Any] = {}
    feeder_node = Node("feeder")
    monitor = Node("monitor")
    counter = [0]
    names = ["front_left_wheel_joint", "front_right_wheel_joint"]

    def joint_state() -> bytes:
        counter[0] += 1
        angle = counter[0] * 1e-3
        return encode_joint_state(time.time_ns(), "", names, [angle, 2 * angle])

    if kind == "odom":
        joint_states = feeder_node.create_publisher(types.JointState, "joint_states")
        feed: Callable[[], None] = lambda: joint_states.publish_serialized(joint_state())  # noqa: E731
    elif kind in ("ik", "robot"):
        twists = feeder_node.create_publisher(types.Twist, "cmd_vel")
        feed = lambda: twists.publish(twist_command(0.05, 0.3))  # noqa: E731
    else:
        feed = lambda: None  # noqa: E731  (the drive feeds itself at 1 kHz)
    for topic in (LEFT_TOPIC, RIGHT_TOPIC):
        monitor.create_subscription(
            types.Float64MultiArray,
            topic,
            lambda m, topic=topic: last.__setitem__(topic, list(m.data)),
            reliable,
        )
    monitor.create_subscription(
        types.Twist,
        "cmd_vel",
        lambda m: last.__setitem__("cmd_vel", (m.linear.x, m.angular.z)),
        reliable,
    )
    monitor.start()  # its takes run in its own thread: signals reach the main thread only
    feeder = _Feeder(feed)

    odom = OdometryNode(BOT) if kind == "odom" else None
    robot = RobotNode(BOT, None, _robot_settings()) if kind == "robot" else None
    stream = sampled(plan(parse_plan("straight 1 10s"), BOT)).commands(DRIVE_RATE)

    def handled() -> int:
        if odom is not None:
            return int(odom.counts["used"])
        if robot is not None:
            return int(robot.updates + sum(s.received for s in robot.subscriptions))
        return int(report["handled"])

    for _ in range(runs):
        signum = rng.choice((signal.SIGINT, signal.SIGTERM))
        delay = rng.uniform(*MOMENTS)
        # Half the signals come from another thread at a random moment of the run, half from
        # inside a random sample's take (not in drive, which takes nothing).
        inside = kind != "drive" and rng.random() < 0.5
        killer = _Killer(signum, delay) if not inside else None
        if inside:
            inside_take.arm(signum, rng.randint(1, 30))
        last.clear()
        # As the commands do, from the node's making on, signals are deferred: the signal comes
        # at any moment of the run, and its exception once the run has ended.
        go = (lambda: None) if killer is None else killer.go.set
        if kind in ("odom", "robot"):
            node = odom or robot
            assert node is not None
            ended = _ended_by(lambda node=node, go=go: _spin_run(node, go))  # type: ignore[misc]
        elif kind == "ik":
            ended = _ended_by(lambda go=go: _ik_run(report, go))  # type: ignore[misc]
            report["last_zero"] += int(
                _wait(lambda: last.get(LEFT_TOPIC) == [0.0] and last.get(RIGHT_TOPIC) == [0.0])
            )
        else:
            ended = _ended_by(lambda go=go: _drive_run(stream, report, go))  # type: ignore[misc]
            report["last_zero"] += int(_wait(lambda: last.get("cmd_vel") == (0.0, 0.0)))
        stopped = _RETURNED[0] - (inside_take.sent_at if killer is None else killer.sent_at)
        if killer is not None:
            killer.thread.join(PATIENCE)
        report["runs"] += 1
        report["sigint" if signum == signal.SIGINT else "sigterm"] += 1
        report["ended_by_its_signal"] += int(ended == signum)
        report["slowest_stop"] = max(report["slowest_stop"], stopped)
        report["inside_take"] += int(inside)
    report["handled"] = handled()
    feeder.stop()
    for node in (odom, robot, feeder_node, monitor):
        if node is not None:
            node.destroy_node()
    return report


#: When the last run's loop returned (monotonic s), before the node's clean-up.
_RETURNED = [0.0]


def _spin_run(node: Any, go: Callable[[], None]) -> None:
    with signals.deferred():
        go()
        node.spin(PATIENCE)
        _RETURNED[0] = time.monotonic()


def _ik_run(report: dict[str, Any], go: Callable[[], None]) -> None:
    from robots import BOT

    from diffbot.live.inverse_kinematics import IkSettings, InverseKinematicsNode

    with signals.deferred():
        ik = InverseKinematicsNode(BOT, IkSettings(timeout=0.0))
        try:
            go()
            ik.spin(PATIENCE)
            _RETURNED[0] = time.monotonic()
            report["handled"] += sum(s.received for s in ik.subscriptions)
        finally:
            ik.destroy_node()


def _drive_run(stream: Any, report: dict[str, Any], go: Callable[[], None]) -> None:
    from diffbot.live.drive import Driver, DriveSettings

    with signals.deferred(), Driver(stream, DriveSettings()) as driver:
        assert driver.wait_for_subscriber(PATIENCE)
        go()
        driver.drive()  # returns once the final zero is sent and acknowledged
        _RETURNED[0] = time.monotonic()
        report["handled"] += driver.sent


def _robot_settings() -> Any:
    from diffbot.live.robot import RobotSettings

    return RobotSettings(rate=FEED_RATE, cmd_vel="cmd_vel", timeout=0.0)


class _EndedError(Exception):
    pass


def _ends(signum: int, frame: object) -> None:
    raise _EndedError(signum)


def test_a_signal_held_since_the_start_ends_the_run_before_the_block_makes_anything() -> None:
    """One that came while the command line loaded and set up (held, so that none raised inside
    the DDS library's import) is acted on as the node's block starts, before the node is made:
    as one during the setup, by the handler the command line set."""
    before = signal.getsignal(signal.SIGTERM)
    ran = []
    try:
        signal.signal(signal.SIGTERM, _ends)
        signal_handlers.hold([signal.SIGTERM])
        signal.raise_signal(signal.SIGTERM)
        with pytest.raises(_EndedError), signals.deferred(deliver=False, ends_run=True):
            ran.append(True)
        assert ran == []
        assert signal.getsignal(signal.SIGTERM) is _ends  # given back, not left ignored
        assert signal_handlers.release() is None
    finally:
        signal_handlers.release()
        signal.signal(signal.SIGTERM, before)


if __name__ == "__main__":
    kind, count, seed = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    print(json.dumps(harness(kind, count, seed)), flush=True)
