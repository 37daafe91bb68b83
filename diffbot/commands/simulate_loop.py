"""``diffbot simulate`` on a disturbed robot: open loop, or closed by ``--follow``."""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from diffbot.commands.options import OutOptions, emit_json, fail
from diffbot.commands.progress import progress
from diffbot.formats.plan_data import start_json
from diffbot.formats.plan_table import violation_lines
from diffbot.formats.text import fmt

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import ArrayLike, NDArray

    from diffbot.body_limits import BodyLimits
    from diffbot.closed_loop import LoopResult, LoopSettings
    from diffbot.kinematics import DiffDriveParams, Pose
    from diffbot.ramps import RampedPlan
    from diffbot.trajectory import Plan

__all__ = ["LoopRequest", "end_errors", "run_loop", "summary"]


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


def end_errors(goal: Pose, end: tuple[float, float, float]) -> tuple[float, float]:
    """How far the true pose ``end`` (x, y in m, theta in rad) ended from the plan's end
    ``goal``: the distance (m) and the heading difference (rad, in [0, pi])."""
    x, y, theta = end
    distance = math.hypot(x - goal.x, y - goal.y)
    return distance, abs(math.remainder(theta - goal.theta, 2.0 * math.pi))


class _Truth:
    """The true poses of the chunk the writer has just taken (x, y, theta rows)."""

    def __init__(self) -> None:
        self.current: NDArray[np.float64] | None = None

    def rows(self, times: ArrayLike) -> NDArray[np.float64]:
        assert self.current is not None
        return self.current


class _Figures:
    """The run's figures, gathered chunk by chunk of true poses: the cross-track error of each
    against the plan's path (m)."""

    def __init__(self, made: Plan | RampedPlan) -> None:
        from diffbot.trajectory import Plan

        self.steps = made if isinstance(made, Plan) else made.steps
        self.worst = 0.0
        self.squares = 0.0
        self.count = 0

    def add(self, truth: NDArray[np.float64]) -> None:
        from diffbot.closed_loop import path_distance

        cross = path_distance(self.steps, truth[0], truth[1])
        if cross.size:
            self.worst = max(self.worst, float(cross.max()))
            self.squares += float((cross * cross).sum())
            self.count += int(cross.size)

    def figures(
        self,
        final: tuple[float, float, float],
        peak: float | None,
        duration: float,
        arrived: bool,
    ) -> dict[str, Any]:
        """Final errors (m, rad) of the true pose ``final`` against the plan's end, the
        cross-track errors (m), the peak share of the motor limit commanded, the duration (s),
        whether it arrived."""
        position, heading = end_errors(self.steps.final_pose, final)
        return {
            "final_position_error": position,
            "final_heading_error": heading,
            "max_cross_track_error": self.worst,
            "rms_cross_track_error": math.sqrt(self.squares / self.count) if self.count else 0.0,
            "peak_limit_fraction": peak,
            "duration": duration,
            "arrived": arrived,
        }


def summary(made: Plan | RampedPlan, result: LoopResult) -> dict[str, Any]:
    """The figures of a whole run: final errors (m, rad) of the true pose against the plan's
    end, the true path's cross-track error against the plan's path (m), the peak share of the
    motor limit commanded, the duration (s), whether it arrived."""
    gathered = _Figures(made)
    gathered.add(result.truth)
    x, y, theta = (float(v) for v in result.truth[:, -1])
    return gathered.figures(
        (x, y, theta), result.peak_limit_fraction, result.duration, result.arrived
    )


def _check_length(made: Plan | RampedPlan, settings: LoopSettings, *, closed: bool) -> None:
    """Refuse a run of more samples than simulate makes, saying how many and the highest
    --rate that fits (the --control-rate sets how long the run is, --rate only how densely
    it is sampled)."""
    from diffbot.closed_loop import run_size
    from diffbot.simulation import MAX_SAMPLES

    seconds, count, highest = run_size(made, settings, closed=closed)
    if count <= MAX_SAMPLES:
        return
    digits = 10.0 ** (math.floor(math.log10(highest)) - 3)
    highest = math.floor(highest / digits) * digits  # four digits, rounded down to fit
    how = (
        f"lower --rate to at most {highest:.4g} Hz for this plan"
        if highest >= settings.control_rate
        else f"that is too long even at --rate {fmt(settings.control_rate)} Hz, the "
        "--control-rate: lower both, or shorten the plan"
    )
    up_to = "up to " if closed else ""
    fail(
        f"the run's {up_to}{fmt(seconds)} s at {fmt(settings.rate)} Hz would take "
        f"{math.ceil(count) if count < 1e12 else f'{count:.4g}'} samples, more than the "
        f"{MAX_SAMPLES} simulate makes: {how}"
    )


def run_loop(
    request: LoopRequest,
    made: Plan | RampedPlan,
    params: DiffDriveParams,
    sampling: tuple[float, int | None, float, int | None],
    true_params: DiffDriveParams | None,
    write: Callable[[Any, Any, Callable[[int], None]], None],
    out: OutOptions,
    label: str,
    as_json: bool,
    quiet: bool = False,
    body: BodyLimits | None = None,
    start: Pose | None = None,
) -> None:
    """Run the plan on the disturbed robot a chunk at a time, write the samples through
    ``write(states, truth, advance)`` as they come (a progress bar on a terminal unless
    ``quiet``), and say how it went (``start``: a goal plan's start pose, which its poses are
    relative to)."""
    from diffbot.closed_loop import LoopSettings, run_chunks
    from diffbot.follow import MAX_LEAD, Follower, delay_lead
    from diffbot.simulation import Disturbances, JointStateChunks
    from diffbot.trajectory import Plan

    rate, ticks, noise, seed = sampling
    steps = made if isinstance(made, Plan) else made.steps
    if request.follow is not None and not steps.within_limit:
        # bad input, so one line: the first segment over the limit, and how many more
        first, *others = violation_lines(steps)
        count = f"{len(others)} more segment" + ("s" if len(others) > 1 else "")
        more = f" (and {count}: 'diffbot plan' lists them)" if others else ""
        fail(first.removeprefix("error: ") + more)
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
    _check_length(made, settings, closed=request.follow is not None)
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
        follower = Follower(params, made, law=request.follow, lead=lead, body=body)
    outcome, chunks = run_chunks(made, params, settings, follower)
    truth = _Truth()
    gathered = _Figures(made)

    def samples() -> Iterator[tuple[NDArray[np.float64], NDArray[np.float64]]]:
        for times, positions, true_poses, _ in chunks:
            truth.current = true_poses
            gathered.add(true_poses)
            yield times, positions

    # The run ends when it arrives: the bar's length is the most it may take.
    with progress(outcome.most_samples, "simulate", "samples", quiet=quiet) as advance:
        write(JointStateChunks(outcome.names, outcome.most_samples, samples()), truth, advance)
    figures = gathered.figures(
        outcome.final_truth, outcome.peak_limit_fraction, outcome.duration, outcome.arrived
    )
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
                "samples": outcome.samples,
                "rate": rate,
                "joints": list(outcome.names),
                **start_json(start),
                "final_pose": {"x": goal.x, "y": goal.y, "theta": goal.theta},
                "true_final_pose": dict(zip(("x", "y", "theta"), outcome.final_truth, strict=True)),
                "within_limit": steps.within_limit,
                "output": out.out,
                **figures,
            }
        )
        return
    rows = [
        ("plan", f"{label}, {how} at {fmt(request.control_rate)} Hz"),
        ("samples", f"{outcome.samples} at {fmt(rate)} Hz, {len(outcome.names)} joints"),
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
            f"{fmt(outcome.duration, 6)} s, {'arrived' if outcome.arrived else 'not arrived'}",
        ),
        ("output", str(Path(out.out))),
    ]
    for name, value in rows:
        click.echo(f"{name:<11} {value}")
