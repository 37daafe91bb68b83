"""Synthetic calibration data, for tests: the commands come from the nominal robot (``BOT``),
the true robot moves by its own radii and separation (exact arcs), so the truth is known."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from robots import BOT

from diffbot.calibration import FitResult, ground_truth, true_robot, umbmark_segments
from diffbot.planfile import parse_plan
from diffbot.simulation import simulate
from diffbot.trajectory import EXAMPLES, Plan, plan

R0 = BOT.wheel_radius
B0 = BOT.wheel_separation
#: The fit's test robot: radii 0.5 % apart (mean kept), separation 2 % off.
TRUE_LEFT = R0 * (1.0 - 0.0025)
TRUE_RIGHT = R0 * (1.0 + 0.0025)
TRUE_SEPARATION = B0 * 1.02
TRUE_ROBOT = true_robot(BOT, (TRUE_LEFT, TRUE_RIGHT), TRUE_SEPARATION)
#: Trajectory A twice, commanded with the nominal robot.
TRAJECTORY_A = plan(parse_plan(EXAMPLES["A"]) * 2, BOT)


def fit_result(left: float, right: float, separation: float) -> FitResult:
    """A fit's result with these radii and separation (m) and small made-up errors."""
    return FitResult(
        left_wheel_radius=left,
        right_wheel_radius=right,
        wheel_separation=separation,
        left_wheel_radius_stderr=1e-6,
        right_wheel_radius_stderr=1e-6,
        wheel_separation_stderr=1e-5,
        position_rms_before=0.01,
        heading_rms_before=0.1,
        position_rms_after=0.001,
        heading_rms_after=0.01,
        windows=10,
    )


Track = tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]


def square_end(
    side: float, direction: str, left: float, right: float, separation: float
) -> tuple[float, float]:
    """Where the true robot ends a UMBmark square commanded with the nominal robot (m)."""
    commanded = plan(umbmark_segments(side, "cw" if direction == "cw" else "ccw"), BOT)
    times = np.concatenate(([0.0], np.cumsum([s.duration for s in commanded.segments])))
    x, y, _ = ground_truth(commanded, times, true_robot(BOT, (left, right), separation))
    return float(x[-1]), float(y[-1])


def recording(
    p: Plan = TRAJECTORY_A, ticks: int | None = None, noise: float = 0.0, rate: float = 50.0
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], Track]:
    """A plan's stamps, encoder readings and the true robot's exact poses."""
    read = simulate(p, BOT, rate=rate, ticks=ticks, noise=noise, seed=7)
    truth = ground_truth(p, read.times, TRUE_ROBOT)
    return read.times, read.positions[0], read.positions[1], (truth.x, truth.y, truth.theta)
