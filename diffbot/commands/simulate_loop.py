"""``diffbot simulate`` on a disturbed robot: open loop, or closed by ``--follow``."""

from __future__ import annotations

import math
import sys
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from diffbot.commands.options import OutOptions, emit_json, fail
from diffbot.errors import EXIT_BAD_INPUT
from diffbot.formats.plan_table import violation_lines
from diffbot.formats.text import fmt

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import ArrayLike, NDArray

    from diffbot.closed_loop import LoopResult
    from diffbot.kinematics import DiffDriveParams
    from diffbot.ramps import RampedPlan
    from diffbot.trajectory import Plan

__all__ = ["LoopRequest", "run_loop", "summary"]


@dataclass(frozen=True)
class LoopRequest:
    """The options of a disturbed or followed simulation, as given."""

    follow: str | None
    control_rate: float
    pose_source: str
    pose_noise: tuple[float, float] | None
    motor_lag: float
    latency: float
    drop: float
    slip: float
    lead: float | None = None

    @property
    def wanted(self) -> bool:
        """Whether the run needs the stepped robot (a follower, or a disturbance)."""
        return self.follow is not None or any((self.motor_lag, self.latency, self.drop, self.slip))

    def check(self, rate: float) -> None:
        """Refuse options that do not go together."""
        if self.follow is None and (self.pose_source != "odom" or self.pose_noise is not None):
            fail("--pose-source and --pose-noise choose what --follow is given: add --follow")
        if self.lead is not None and self.follow is None:
            fail("--lead is the tracking follower's: add --follow")
        if self.lead and self.follow == "pure-pursuit":
            fail("--lead is the tracking law's; pure-pursuit takes none")
        if self.pose_noise is not None and self.pose_source != "truth":
            fail("--pose-noise is noise on the true pose: add --pose-source truth")
        if self.wanted and self.control_rate > rate:
            fail(
                f"--control-rate {fmt(self.control_rate)} Hz is above the simulation's --rate "
                f"{fmt(rate)} Hz: the controller sees one pose a sample"
            )
        if self.pose_noise is not None and self.pose_noise[1] > 180.0:
            fail(f"--pose-noise: {fmt(self.pose_noise[1])} degrees is more than half a turn")


class _Truth:
    """The run's true poses, as the writer asks for them (one chunk)."""

    def __init__(self, rows: NDArray[np.float64]) -> None:
        self._rows = rows

    def rows(self, times: ArrayLike) -> NDArray[np.float64]:
        return self._rows


def summary(made: Plan | RampedPlan, result: LoopResult) -> dict[str, Any]:
    """The run's figures: final errors (m, rad) of the true pose against the plan's end, the
    true path's cross-track error against the plan's path (m), the peak share of the motor
    limit commanded, the duration (s), whether it arrived."""
    import numpy as np

    from diffbot.closed_loop import path_distance
    from diffbot.trajectory import Plan

    steps = made if isinstance(made, Plan) else made.steps
    goal = steps.final_pose
    x, y, theta = (float(v) for v in result.truth[:, -1])
    cross = path_distance(steps, result.truth[0], result.truth[1])
    return {
        "final_position_error": math.hypot(x - goal.x, y - goal.y),
        "final_heading_error": abs(math.remainder(theta - goal.theta, 2.0 * math.pi)),
        "max_cross_track_error": float(cross.max()),
        "rms_cross_track_error": float(np.sqrt(np.mean(cross * cross))),
        "peak_limit_fraction": result.peak_limit_fraction,
        "duration": result.duration,
        "arrived": result.arrived,
    }


def run_loop(
    request: LoopRequest,
    made: Plan | RampedPlan,
    params: DiffDriveParams,
    sampling: tuple[float, int | None, float, int | None],
    true_params: DiffDriveParams | None,
    write: Callable[[Any, Any], None],
    out: OutOptions,
    label: str,
    as_json: bool,
) -> None:
    """Run the plan on the disturbed robot, write the samples through ``write(states,
    truth)``, and say how it went."""
    from diffbot.closed_loop import LoopSettings, run
    from diffbot.follow import MAX_LEAD, Follower, delay_lead
    from diffbot.simulation import Disturbances, JointStateChunks
    from diffbot.trajectory import Plan

    rate, ticks, noise, seed = sampling
    steps = made if isinstance(made, Plan) else made.steps
    if request.follow is not None and not steps.within_limit:
        for line in violation_lines(steps):
            click.echo(line, err=True)
        sys.exit(EXIT_BAD_INPUT)
    disturbances = Disturbances(
        request.motor_lag, request.latency, request.drop, request.slip, seed=seed
    )
    metres, degrees = request.pose_noise or (0.0, 0.0)
    settings = LoopSettings(
        rate=rate,
        control_rate=request.control_rate,
        ticks=ticks,
        noise=noise,
        seed=seed,
        disturbances=disturbances,
        true_params=true_params,
        pose_source="truth" if request.pose_source == "truth" else "odom",
        pose_noise=(metres, math.radians(degrees)),
    )
    follower = None
    lead = 0.0
    if request.follow is not None:
        # By default the tracking law leads by the delay the simulated robot has, as one
        # measured on a real base would be given.
        if request.follow == "tracking":
            if request.lead is not None:
                lead = request.lead
            else:
                lead = delay_lead(request.latency, request.motor_lag, request.control_rate)
                if lead > MAX_LEAD:
                    fail(
                        f"the simulated robot's delay (--latency plus --motor-lag plus half a "
                        f"control period, {fmt(lead)} s) is more than the longest --lead, "
                        f"{fmt(MAX_LEAD)} s: give --lead"
                    )
        follower = Follower(params, made, law=request.follow, lead=lead)
    result = run(made, params, settings, follower)
    states = JointStateChunks(
        result.names, result.times.size, iter([(result.times, result.positions)])
    )
    write(states, _Truth(result.truth))
    figures = summary(made, result)
    if out.out is None:
        return
    how = f"followed ({request.follow})" if request.follow else "open loop"
    if as_json:
        goal = steps.final_pose
        emit_json(
            {
                "plan": label,
                "control": request.follow or "open-loop",
                **({"lead": lead} if request.follow is not None else {}),
                "samples": int(result.times.size),
                "rate": rate,
                "joints": list(result.names),
                "final_pose": {"x": goal.x, "y": goal.y, "theta": goal.theta},
                "true_final_pose": dict(
                    zip(("x", "y", "theta"), (float(v) for v in result.truth[:, -1]), strict=True)
                ),
                "within_limit": steps.within_limit,
                "output": out.out,
                **figures,
            }
        )
        return
    rows = [
        ("plan", f"{label}, {how} at {fmt(request.control_rate)} Hz"),
        ("samples", f"{result.times.size} at {fmt(rate)} Hz, {len(result.names)} joints"),
        (
            "final",
            f"{fmt(figures['final_position_error'] * 1000.0, 4)} mm, "
            f"{fmt(math.degrees(figures['final_heading_error']), 3)} deg from the plan's end",
        ),
        (
            "cross-track",
            f"max {fmt(figures['max_cross_track_error'] * 1000.0, 4)} mm, RMS "
            f"{fmt(figures['rms_cross_track_error'] * 1000.0, 4)} mm",
        ),
        (
            "duration",
            f"{fmt(result.duration, 6)} s, {'arrived' if result.arrived else 'not arrived'}",
        ),
        ("output", str(Path(out.out))),
    ]
    for name, value in rows:
        click.echo(f"{name:<11} {value}")
