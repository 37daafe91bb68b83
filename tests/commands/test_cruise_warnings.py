"""Warnings about cruise options: given where they change nothing, or over the body limits."""

from __future__ import annotations

import pytest
from robots import BOT

from diffbot.body_limits import BodyLimits
from diffbot.commands.cruise_warnings import warn_over_body, warn_slowed_runs, warn_unused
from diffbot.commands.plan_options import PlanOptions
from diffbot.planfile import parse_plan
from diffbot.profiles import Limits, PathLimits
from diffbot.ramps import ramp
from diffbot.trajectory import Spin, Straight, plan

LIMITS = BodyLimits((-0.1, 0.3), (-1.0, 1.0))


def options(*given: str, fastest: bool = False, max_linear: float | None = None) -> PlanOptions:
    return PlanOptions(
        example=None,
        speed=0.4,
        spin_rate=2.0,
        fastest=fastest,
        max_linear=max_linear,
        given=given,
    )


def test_options_that_change_nothing_are_said_and_returned(
    capsys: pytest.CaptureFixture[str],
) -> None:
    timed = [Straight(1.0, duration=10.0), Spin(1.0)]
    assert warn_unused(options("--speed", "--spin-rate"), timed) == {"--speed"}
    assert capsys.readouterr().err == (
        "warning: --speed changes nothing: every straight or arc of the plan has its own duration\n"
    )
    assert warn_unused(options("--speed", fastest=True), [Straight(1.0)]) == {"--speed"}
    assert "with --fastest" in capsys.readouterr().err
    assert warn_unused(options("--spin-rate"), [Straight(1.0)]) == {"--spin-rate"}
    assert capsys.readouterr().err.endswith("the plan has no spin\n")
    assert warn_unused(options(), timed) == set()
    assert capsys.readouterr().err == ""


def test_a_cruise_speed_over_the_limits_names_the_limit_and_where_it_comes_from(
    capsys: pytest.CaptureFixture[str],
) -> None:
    warn_over_body(options("--speed", "--spin-rate"), LIMITS, set())
    assert capsys.readouterr().err.splitlines() == [
        "warning: --speed 0.4 m/s is over the body velocity limit of 0.3 m/s (the controllers "
        "file's linear.x): the segments it times run at 0.3 m/s",
        "warning: --spin-rate 2 rad/s is over the body velocity limit of 1 rad/s (the "
        "controllers file's angular.z): the segments it times run at 1 rad/s",
    ]
    warn_over_body(options("--speed", max_linear=0.3), LIMITS, set())
    assert "(--max-linear)" in capsys.readouterr().err
    # Not given, said to change nothing, within the limit, or no limit: nothing more is said.
    warn_over_body(options(), LIMITS, set())
    warn_over_body(options("--speed"), LIMITS, {"--speed"})
    warn_over_body(options("--speed"), BodyLimits((-1.0, 1.0), None), set())
    warn_over_body(options("--speed"), BodyLimits(), set())
    assert capsys.readouterr().err == ""


def test_segments_a_run_drives_slower_than_written_are_named(
    capsys: pytest.CaptureFixture[str],
) -> None:
    text = "straight 1 10s; straight 1 20s; straight 2 40s; spin 90 4s; spin 90 2s; spin -90 1s"
    ramped = ramp(plan(parse_plan(text), BOT), Limits(linear=PathLimits(None, 1.0, None)))
    warn_slowed_runs(ramped)
    assert capsys.readouterr().err.splitlines() == [
        "warning: segments 1-3 are one run (one direction, no stop between them), at the "
        "slowest one's 0.05 m/s: segment 1 takes longer than written (--steps drives each at "
        "its own speed, without ramps)",
        "warning: segments 4-5 are one run (one direction, no stop between them), at the "
        "slowest one's 0.3927 rad/s: segment 5 takes longer than written (--steps drives each "
        "at its own speed, without ramps)",
    ]
    # Segment 1 cruises at segment 2's speed: 20 s (and its ramp), not its own 10 s.
    assert ramped.summary.segments[0].duration > 20.0
    warn_slowed_runs(ramp(plan(parse_plan("straight 1; straight 2"), BOT), ramped.limits))
    assert capsys.readouterr().err == ""
