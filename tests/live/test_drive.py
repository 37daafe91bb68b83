"""Driving a plan live: every command of the stream on schedule, then zero; zero on a signal too;
no subscriber is an error."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import pytest
from live_graph import PATIENCE, deep, until
from robots import BOT

from diffbot.live import types
from diffbot.live.drive import Driver, DriveSettings
from diffbot.live.transport import Node, QosProfile
from diffbot.planfile import parse_plan
from diffbot.profiles import Limits
from diffbot.ramps import ramp
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
