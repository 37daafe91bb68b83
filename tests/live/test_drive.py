"""Driving a plan live: every command of the stream on schedule, then zero; zero on a signal too;
no subscriber is an error."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Iterator

import pytest
from live_graph import PATIENCE, deep, spare_domain, until
from robots import BOT

from diffbot.live import types
from diffbot.live.drive import Driver, DriveSettings, Lateness
from diffbot.live.signals import deferred
from diffbot.live.transport import LiveError, Node, QosProfile
from diffbot.planfile import parse_plan
from diffbot.profiles import Limits, PathLimits
from diffbot.ramps import CommandStream, ramp
from diffbot.trajectory import plan

DEEP = deep()


def test_a_stream_goes_out_on_schedule_and_ends_with_zero() -> None:
    stream = ramp(plan(parse_plan("straight 0.1 0.5s; spin 90 0.5s"), BOT), Limits()).commands(20.0)
    got: list[tuple[float, float]] = []
    with Node("probe") as probe, Driver(stream, DriveSettings(stamped=True)) as driver:
        probe.create_subscription(
            types.TwistStamped,
            "cmd_vel",
            lambda m: got.append((m.twist.linear.x, m.twist.angular.z)),
            DEEP,
        )
        assert driver.wait_for_subscriber(PATIENCE)
        probe.start()
        started = time.monotonic()
        report = driver.drive()
        took = time.monotonic() - started
        until(probe, lambda: len(got) == stream.times.size + 1)
    assert got[:-1] == [
        (float(v), float(w)) for v, w in zip(stream.linear, stream.angular, strict=True)
    ]
    assert got[-1] == (0.0, 0.0)
    assert report.completed
    assert report.sent == stream.times.size
    # The last command (the stream's own zero) goes out at its time, never early.
    assert took == pytest.approx(float(stream.times[-1]), abs=0.05)
    assert report.lateness.earliest >= 0.0
    assert report.lateness.count == stream.times.size
    assert report.percentile(0.5) < 0.01


def test_wheel_commands_go_to_each_side_once_per_joint() -> None:
    stream = ramp(plan(parse_plan("spin 90 0.5s"), BOT), Limits()).commands(20.0)
    left: list[list[float]] = []
    right: list[list[float]] = []
    settings = DriveSettings(wheels=True, joints=(2, 1))
    with Node("probe") as probe, Driver(stream, settings) as driver:
        assert driver.name == "diffbot_drive"
        probe.create_subscription(
            types.Float64MultiArray, settings.left_topic, lambda m: left.append(m.data), DEEP
        )
        probe.create_subscription(
            types.Float64MultiArray, settings.right_topic, lambda m: right.append(m.data), DEEP
        )
        assert driver.wait_for_subscriber(PATIENCE)
        k = stream.times.size // 2  # turning: the sides differ
        driver.send(stream, k)
        until(probe, lambda: left and right)
    assert stream.left[k] != stream.right[k]
    assert left == [[float(stream.left[k])] * 2]
    assert right == [[float(stream.right[k])]]


def test_a_wheel_drive_ends_with_zero_on_every_joint_and_counts_each_command() -> None:
    stream = ramp(plan(parse_plan("spin 90 0.5s"), BOT), Limits()).commands(20.0)
    left: list[list[float]] = []
    right: list[list[float]] = []
    settings = DriveSettings(wheels=True, joints=(2, 1))
    counted: list[int] = []
    with Node("probe") as probe, Driver(stream, settings) as driver:
        probe.create_subscription(
            types.Float64MultiArray, settings.left_topic, lambda m: left.append(m.data), DEEP
        )
        probe.create_subscription(
            types.Float64MultiArray, settings.right_topic, lambda m: right.append(m.data), DEEP
        )
        assert driver.wait_for_subscriber(PATIENCE)
        report = driver.drive(counted.append)
        n = stream.times.size
        until(probe, lambda: len(left) == len(right) == n + 1)
    assert left[:-1] == [[float(v)] * 2 for v in stream.left]
    assert right[:-1] == [[float(v)] for v in stream.right]
    assert (left[-1], right[-1]) == ([0.0, 0.0], [0.0])
    assert counted == [1] * n
    assert (report.sent, report.total, report.completed) == (n, n, True)
    assert report.duration_error == report.lateness.last


def test_a_signal_in_a_drive_stops_it_early_with_zero() -> None:
    stream = ramp(plan(parse_plan("straight 1 20s"), BOT), Limits()).commands(20.0)
    got: list[tuple[float, float]] = []
    with (
        Node("probe") as probe,
        Driver(stream, DriveSettings()) as driver,
        deferred(deliver=False),
    ):
        probe.create_subscription(
            types.Twist, "cmd_vel", lambda m: got.append((m.linear.x, m.angular.z)), DEEP
        )
        assert driver.wait_for_subscriber(PATIENCE)
        threading.Timer(0.3, os.kill, (os.getpid(), signal.SIGINT)).start()
        report = driver.drive()
        until(probe, lambda: len(got) == report.sent + 1)
    assert not report.completed
    assert 0 < report.sent < stream.times.size
    assert report.duration_error == 0.0  # not the plan's end: no duration to compare
    assert got[-1] == (0.0, 0.0)
    assert got[-2] != (0.0, 0.0)  # cut short while moving


def test_one_topic_for_both_sides_is_refused_with_wheel_commands_only() -> None:
    stream = ramp(plan(parse_plan("straight 0.1 0.5s"), BOT), Limits()).commands(20.0)
    same = DriveSettings(wheels=True, left_topic="w", right_topic="/w")
    with pytest.raises(LiveError, match=r"^left_topic= and right_topic= are both /w: "):
        Driver(stream, same)
    with Driver(stream, DriveSettings(left_topic="w", right_topic="w")) as driver:
        assert driver.topics == ("cmd_vel",)


def test_a_bad_frame_id_is_refused_naming_it() -> None:
    stream = ramp(plan(parse_plan("straight 0.1 0.5s"), BOT), Limits()).commands(20.0)
    with pytest.raises(LiveError, match=r"^frame_id '' is empty$"):
        Driver(stream, DriveSettings(stamped=True, frame_id=""))


def test_a_percentile_is_the_nearest_ranks_bin() -> None:
    lateness = Lateness()
    for ms in (4, 2, 1, 3, 2):
        lateness.add(ms / 1000)
    # Nearest rank: ceil(q n) of the sorted values (1, 2, 2, 3, 4 ms), as its 1 us bin's
    # upper edge.
    for q, ms in ((0.0, 1), (0.2, 1), (0.21, 2), (0.6, 2), (0.61, 3), (0.8, 3), (0.81, 4)):
        assert lateness.percentile(q) == pytest.approx(ms / 1000, abs=1e-6), q
    assert lateness.percentile(1.0) == 0.004  # never past the latest
    assert (lateness.count, lateness.earliest, lateness.latest, lateness.last) == (
        5,
        0.001,
        0.004,
        0.002,
    )
    assert Lateness().percentile(0.5) == 0.0


def test_without_a_subscriber_the_wait_lasts_its_timeout_in_the_drivers_domain() -> None:
    stream = ramp(plan(parse_plan("straight 0.1 0.5s"), BOT), Limits()).commands(20.0)
    domain = spare_domain(1)
    with Driver(stream, DriveSettings(cmd_vel="nobody_reads_this"), domain=domain) as driver:
        assert driver.participant.domain_id == domain
        assert (driver.total, driver.sent) == (stream.times.size, 0)
        started = time.monotonic()
        assert not driver.wait_for_subscriber(0.3)
        assert time.monotonic() - started >= 0.3


def run_drive(*args: str) -> subprocess.Popen[str]:
    return subprocess.Popen(
        [sys.executable, "-m", "diffbot", "drive", *args],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=os.environ.copy(),
    )


def test_no_subscriber_is_an_error() -> None:
    done = run_drive("straight 0.1", "--wait", "0.2")
    _, err = done.communicate(timeout=60)
    assert done.returncode == 2
    assert err == "error: no subscriber on cmd_vel after 0.2 s\n"


def test_a_signal_stops_the_robot() -> None:
    got: list[tuple[float, float]] = []
    with Node("probe") as probe:
        probe.create_subscription(
            types.Twist, "cmd_vel", lambda m: got.append((m.linear.x, m.angular.z)), DEEP
        )
        process = run_drive("straight 1 10s", "--rate", "20", "--wait", str(PATIENCE))
        try:
            until(probe, lambda: len(got) >= 5)
            assert got[-1] == pytest.approx((0.1, 0.0))
            process.send_signal(signal.SIGTERM)
            _, err = process.communicate(timeout=PATIENCE)
        finally:
            process.kill()
        until(probe, lambda: got[-1] == (0.0, 0.0))
    assert process.returncode == 128 + signal.SIGTERM
    assert "commanded zero" in err
    assert len(got) < 150  # cut short: 10 s at 20 Hz is 201 commands


def test_a_goal_plan_is_driven_to_its_goal() -> None:
    got: list[float] = []
    with Node("probe") as probe:
        # Reliable: the sum below needs every command, also on a machine busy enough for a
        # best-effort reader to lose one.
        probe.create_subscription(
            types.Twist,
            "cmd_vel",
            lambda m: got.append(m.linear.x),
            QosProfile(reliable=True, depth=100_000),
        )
        probe.start()
        process = run_drive("--to", "0.05,0,0", "--rate", "50", "--wait", str(PATIENCE))
        try:
            _, err = process.communicate(timeout=60)
        finally:
            process.kill()
        until(probe, lambda: bool(got) and got[-1] == 0.0)
    assert process.returncode == 0, err
    # Each command holds for one period: the commanded speeds add up to the goal's distance.
    assert sum(got) / 50.0 == pytest.approx(0.05, abs=1e-9)


@pytest.mark.parametrize(
    "limits",
    [Limits(), Limits(linear=PathLimits(None, 0.5, None), angular=PathLimits(None, 4.0, None))],
)
def test_a_plan_in_pieces_goes_out_as_the_whole_stream(limits: Limits) -> None:
    # Pieces of 7 commands (as the command line streams them, in pieces of 65,536): the same
    # commands at the same times as the whole stream, step plan and ramped alike.
    ramped = ramp(plan(parse_plan("straight 0.05 0.5s; spin 45 0.5s"), BOT), limits)
    whole = ramped.commands(100.0)
    got: list[tuple[float, float]] = []
    with (
        Node("probe") as probe,
        Driver(ramped.command_chunks(100.0, chunk=7), DriveSettings()) as driver,
    ):
        probe.create_subscription(
            types.Twist,
            "cmd_vel",
            lambda m: got.append((m.linear.x, m.angular.z)),
            QosProfile(reliable=True, depth=100_000),
        )
        assert driver.wait_for_subscriber(PATIENCE)
        probe.start()
        report = driver.drive()
        until(probe, lambda: len(got) == whole.times.size + 1)
    assert got[:-1] == [
        (float(v), float(w)) for v, w in zip(whole.linear, whole.angular, strict=True)
    ]
    assert got[-1] == (0.0, 0.0)
    assert report.completed
    assert report.sent == report.total == whole.times.size
    assert report.lateness.count == whole.times.size


def test_pieces_are_made_as_they_are_driven() -> None:
    # Ten million commands (all but a thousand): only the pieces driven so far are ever made.
    ramped = ramp(plan(parse_plan("straight 1 9999s"), BOT), Limits())
    assert ramped.command_count(1000.0) == 9_999_001
    made: list[int] = []

    def pieces() -> Iterator[CommandStream]:
        for piece in ramped.command_chunks(1000.0, chunk=100):
            made.append(int(piece.times.size))
            yield piece

    with Node("probe") as probe, Driver(pieces(), DriveSettings()) as driver:
        probe.create_subscription(types.Twist, "cmd_vel", lambda m: None)
        assert driver.wait_for_subscriber(PATIENCE)
        assert made == []
        with deferred(deliver=False):
            threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
            report = driver.drive()
    assert not report.completed
    assert 0 < report.sent <= 100 * len(made)
    assert len(made) <= report.sent // 100 + 1


def test_a_ten_million_command_drive_runs_in_little_memory() -> None:
    with Node("probe") as probe:
        probe.create_subscription(types.Twist, "cmd_vel", lambda m: None)
        process = run_drive("straight 1 9999s", "--rate", "1000", "--wait", str(PATIENCE))
        try:
            got = []
            probe.create_subscription(types.Twist, "cmd_vel", got.append)
            until(probe, lambda: len(got) >= 200)
            peak = _peak_memory(process.pid)
            process.send_signal(signal.SIGTERM)
            _, err = process.communicate(timeout=PATIENCE)
        finally:
            process.kill()
    assert "stopped after" in err
    assert "of 9999001 commands: commanded zero" in err
    # Whole, the stream's five arrays alone took 400 MB (and a gigabyte while they were made).
    assert peak < 250 * 2**20, f"peak resident memory {peak / 2**20:.0f} MB"


def _peak_memory(pid: int) -> int:
    """The peak resident memory of process ``pid`` so far (bytes)."""
    with open(f"/proc/{pid}/status") as status:
        for line in status:
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) * 1024
    raise AssertionError("no VmHWM")


#: Another program's publisher, as a teleop is, until its stdin closes. It keeps its
#: publishers: one dropped is disposed at once, and no node sees it.
PUBLISHER = """
import sys
from diffbot.live import types
from diffbot.live.transport import Node
with Node("teleop") as node:
    publishers = [node.create_publisher(types.Twist, topic) for topic in sys.argv[1:]]
    sys.stdin.read()
"""


def test_another_publisher_on_the_command_topic_is_counted() -> None:
    # A teleop (or a second drive) on cmd_vel would mix its commands with the plan's: the
    # driver counts the publishers besides its own on the topics it commands.
    stream = ramp(plan(parse_plan("straight 0.1 0.2s"), BOT), Limits()).commands(20.0)
    for settings, topics in (
        (DriveSettings(), ["cmd_vel"]),
        (DriveSettings(wheels=True), [DriveSettings().left_topic, DriveSettings().right_topic]),
    ):
        with Driver(stream, settings) as driver:
            assert driver.other_publishers() == 0
            other = subprocess.Popen(
                [sys.executable, "-c", PUBLISHER, *topics],
                stdin=subprocess.PIPE,
                env=os.environ.copy(),
            )
            try:
                end = time.monotonic() + PATIENCE
                while driver.other_publishers() < len(topics) and time.monotonic() < end:
                    driver.spin_once(0.05)
                assert driver.other_publishers() == len(topics)
            finally:
                assert other.stdin is not None
                other.stdin.close()
                other.wait(timeout=60)
