"""``diffbot drive PLAN --follow``: the plan followed live from the robot's pose."""

from __future__ import annotations

import math
import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal

import click

from diffbot.commands.options import fail
from diffbot.errors import EXIT_CHECK_FAILED
from diffbot.formats.text import fmt

if TYPE_CHECKING:
    from diffbot.body_limits import BodyLimits
    from diffbot.kinematics import DiffDriveParams
    from diffbot.live.follow_drive import FollowDriver, FollowReport
    from diffbot.ramps import RampedPlan
    from diffbot.trajectory import Plan

__all__ = ["LiveFollow", "drive_follow"]

#: Terminal progress lines per second at most.
_PROGRESS_RATE = 10.0


@dataclass(frozen=True)
class LiveFollow:
    """The options of a followed live drive, as given (topics already checked)."""

    law: Literal["tracking", "pure-pursuit"]
    rate: float
    pose_topic: str
    from_odometry: bool
    pose_timeout: float
    cmd_vel: str
    stamped: bool
    frame_id: str
    wait: float
    lead: float = 0.0


def drive_follow(
    request: LiveFollow,
    made: Plan | RampedPlan,
    params: DiffDriveParams,
    label: str,
    *,
    announce: bool,
    quiet: bool,
    body: BodyLimits | None = None,
) -> None:
    """Follow ``made`` live; exit 2 when no pose or no subscriber came within the wait (the
    robot never commanded), 1 when it did not arrive in time."""
    from diffbot.follow import Follower
    from diffbot.live.follow_drive import FollowDriver, FollowSettings
    from diffbot.live.signals import caught, deferred

    follower = Follower(params, made, law=request.law, lead=request.lead, body=body)
    settings = FollowSettings(
        rate=request.rate,
        pose_topic=request.pose_topic,
        pose_kind="odometry" if request.from_odometry else None,
        pose_timeout=request.pose_timeout,
        cmd_vel=request.cmd_vel,
        stamped=request.stamped,
        frame_id=request.frame_id,
    )
    # From the node's making on, a signal only stops the run between two commands; it is
    # handed on (exit status 130, 143 or 129) once the robot was commanded zero.
    with deferred(), FollowDriver(follower, settings) as driver:
        if announce:
            driver.announce()
        if not driver.wait_until_ready(request.wait):
            if caught() is not None:
                return
            fail(_not_ready(driver, request))
        with _progress(driver.cap, quiet=quiet) as show:
            report = driver.follow(show)
        _say(report, request, label)


def _not_ready(driver: FollowDriver, request: LiveFollow) -> str:
    """Why the run could not start, naming the topic."""
    wait = fmt(request.wait)
    if driver.pose is None:
        kind = (
            "nav_msgs/Odometry"
            if request.from_odometry
            else "geometry_msgs/PoseStamped or PoseWithCovarianceStamped"
        )
        refused = f" ({driver.refusals.total} refused)" if driver.refusals.total else ""
        return (
            f"no pose ({kind}) on {request.pose_topic!r}{refused} after {wait} s: "
            "nothing was commanded"
        )
    return f"no subscriber on {request.cmd_vel} after {wait} s"


def _say(report: FollowReport, request: LiveFollow, label: str) -> None:
    how = f"followed {label} ({request.law}) at {fmt(request.rate)} Hz"
    end = (
        f"{fmt(report.position_error * 1e3, 4)} mm, "
        f"{fmt(math.degrees(report.heading_error), 3)} deg from the plan's end by the pose"
    )
    extra = f"; {report.stale} commands zero on a stale pose" if report.stale else ""
    if report.refused:
        extra += f"; {report.refused} poses refused"
    if not report.completed:
        click.echo(
            f"{how}: stopped after {fmt(report.duration, 4)} s, {end}{extra}; commanded zero",
            err=True,
        )
        return
    if report.arrived:
        click.echo(f"{how}: arrived after {fmt(report.duration, 4)} s, {end}{extra}", err=True)
        return
    click.echo(
        f"{how}: did not arrive within {fmt(report.duration, 4)} s, {end}{extra}; commanded zero",
        err=True,
    )
    sys.exit(EXIT_CHECK_FAILED)


@contextmanager
def _progress(cap: float, *, quiet: bool) -> Iterator[Callable[[float, float], None] | None]:
    """A progress line on a terminal's stderr: the time and the tracking error."""
    if quiet or not sys.stderr.isatty():
        yield None
        return
    shown = -math.inf

    def show(t: float, error: float) -> None:
        nonlocal shown
        now = time.monotonic()
        if now - shown >= 1.0 / _PROGRESS_RATE:
            shown = now
            click.echo(
                f"\r{t:7.2f} s of at most {cap:.1f} s, tracking error {error * 1e3:8.1f} mm",
                err=True,
                nl=False,
            )

    try:
        yield show
    finally:
        if shown > -math.inf:
            click.echo("", err=True)
