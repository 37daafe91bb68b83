"""Calibration benchmarks, run by hand: ``python benchmarks/bench_calibration.py [--seeds N]``.

How well, and how fast, the calibration recovers a simulated robot whose truth is known. The
nominal robot is the bundled diffbot (r = 0.035 m, b = 0.135 m); the commands come from it, the
true robot moves by its own radii and separation (exact arcs).

(a) Least-squares fit on the seed's Trajectory A driven five times (40 s a lap, at
    50 Hz), radii 0.5 % apart (mean kept) and separation 2 % off; ground truth is the true
    robot's exact pose at the wheel stamps. Without and with encoder errors (4096 counts per
    revolution, Gaussian noise of 1 mrad on each reading), over several noise seeds.
(b) UMBmark: a 4 m square, 5 runs each way, radii 0.1 % apart and separation 1 % off, with the
    first-order formulas and with the exact square model (``exact=True``). Without and with
    encoder errors: the robot stops each segment when its encoders read the command,
    so its wheels are off by the reading error (noise and quantisation), different in each run.

Errors are relative to the true values: ``|estimate - truth| / truth``. Times are the best of a
few repeats.
"""

from __future__ import annotations

import argparse
import math
import time
from collections.abc import Callable, Sequence

import numpy as np
from numpy.typing import NDArray

from diffbot.batch_odometry import integrate
from diffbot.calibration import fit, true_robot, umbmark, umbmark_segments
from diffbot.kinematics import DiffDriveParams
from diffbot.planfile import parse_plan
from diffbot.simulation import simulate
from diffbot.trajectory import EXAMPLES, plan, wheel_positions

NOMINAL = DiffDriveParams(wheel_radius=0.035, wheel_separation=0.135)
R0 = NOMINAL.wheel_radius
B0 = NOMINAL.wheel_separation
TICKS = 4096
NOISE = 1e-3  # rad


def best_of(repeats: int, run: Callable[[], object]) -> float:
    """The shortest wall time (s) of ``repeats`` runs."""
    best = math.inf
    for _ in range(repeats):
        start = time.perf_counter()
        run()
        best = min(best, time.perf_counter() - start)
    return best


def true_track(
    left: NDArray[np.float64], right: NDArray[np.float64], truth: tuple[float, float, float]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Exact poses of the true robot (left radius, right radius, separation) for wheel angles."""
    left_radius, right_radius, separation = truth
    track = integrate(true_robot(NOMINAL, (left_radius, right_radius), separation), left, right)
    return track.x, track.y, track.theta


def relative_errors(estimate: Sequence[float], truth: Sequence[float]) -> str:
    """``|estimate - truth| / truth`` of r_L, r_R and b, as text."""
    return describe([abs(e - t) / t for e, t in zip(estimate, truth, strict=True)])


def describe(errors: Sequence[float]) -> str:
    """Relative errors of r_L, r_R and b, as text."""
    return "  ".join(f"{name} {e:.2e}" for name, e in zip(("r_L", "r_R", "b"), errors, strict=True))


def bench_fit(seeds: int) -> None:
    truth = (R0 * (1 - 0.0025), R0 * (1 + 0.0025), B0 * 1.02)
    laps = 5
    commanded = plan(parse_plan(EXAMPLES["A"]) * laps, NOMINAL)
    exact = simulate(commanded, NOMINAL, rate=50.0)
    x, y, theta = true_track(exact.positions[0], exact.positions[1], truth)
    print(
        f"(a) fit: Trajectory A x{laps} ({commanded.duration:g} s, {exact.times.size} samples at "
        "50 Hz), radii 0.5 % apart, separation 2 % off; windows of 50 intervals (1 s)"
    )

    def run(left: NDArray[np.float64], right: NDArray[np.float64]) -> tuple[float, float, float]:
        result = fit(exact.times, left, right, exact.times, x, y, theta, NOMINAL, window=50)
        return result.left_wheel_radius, result.right_wheel_radius, result.wheel_separation

    estimate = run(exact.positions[0], exact.positions[1])
    seconds = best_of(5, lambda: run(exact.positions[0], exact.positions[1]))
    print(f"    exact readings:  {relative_errors(estimate, truth)}   ({seconds * 1e3:.1f} ms)")
    worst = np.zeros(3)
    squares = np.zeros(3)
    for seed in range(seeds):
        noisy = simulate(commanded, NOMINAL, rate=50.0, ticks=TICKS, noise=NOISE, seed=seed)
        errors = np.abs(np.subtract(run(noisy.positions[0], noisy.positions[1]), truth))
        errors /= np.asarray(truth)
        worst = np.maximum(worst, errors)
        squares += errors**2
    rms = np.sqrt(squares / seeds)
    print(f"    {TICKS} ticks + {NOISE:g} rad noise, {seeds} seeds: RMS {describe(list(rms))}")
    print(f"        worst {describe(list(worst))}")


def square_end(
    direction: str, truth: tuple[float, float, float], rng: np.random.Generator | None
) -> tuple[float, float]:
    side = 4.0
    commanded = plan(umbmark_segments(side, "cw" if direction == "cw" else "ccw"), NOMINAL)
    times = np.concatenate(([0.0], np.cumsum([s.duration for s in commanded.segments])))
    left, right = wheel_positions(commanded, times)
    if rng is not None:
        # Each segment ends when the encoders read the command: the wheels are off by the
        # reading error, a Gaussian noise plus the rounding to a count.
        step = 2.0 * math.pi / TICKS
        for wheel in (left, right):
            wheel[1:] -= rng.normal(0.0, NOISE, wheel.size - 1)
            wheel[1:] -= rng.uniform(-0.5 * step, 0.5 * step, wheel.size - 1)
    x, y, _ = true_track(left, right, truth)
    return float(x[-1]), float(y[-1])


def bench_umbmark(seeds: int) -> None:
    truth = (R0 * (1 - 0.0005), R0 * (1 + 0.0005), B0 * 1.01)
    runs = 5
    print(f"(b) UMBmark: 4 m square, {runs} runs each way, radii 0.1 % apart, separation 1 % off")
    cw = [square_end("cw", truth, None)] * runs
    ccw = [square_end("ccw", truth, None)] * runs
    result = umbmark(4.0, cw, ccw, NOMINAL)
    estimate = (result.left_wheel_radius, result.right_wheel_radius, result.wheel_separation)
    seconds = best_of(20, lambda: umbmark(4.0, cw, ccw, NOMINAL))
    print(f"    exact runs:      {relative_errors(estimate, truth)}   ({seconds * 1e6:.0f} us)")
    print(
        f"        error of the separation's deviation "
        f"{abs(estimate[2] - truth[2]) / (truth[2] - B0):.1%}, of the radius difference "
        f"{abs((estimate[1] - estimate[0]) - (truth[1] - truth[0])) / (truth[1] - truth[0]):.1%}"
    )
    result = umbmark(4.0, cw, ccw, NOMINAL, exact=True)
    estimate = (result.left_wheel_radius, result.right_wheel_radius, result.wheel_separation)
    seconds = best_of(20, lambda: umbmark(4.0, cw, ccw, NOMINAL, exact=True))
    print(
        f"    exact runs, exact=True: {relative_errors(estimate, truth)}   ({seconds * 1e3:.2f} ms)"
    )
    for exact in (False, True):
        worst = np.zeros(3)
        for seed in range(seeds):
            rng = np.random.default_rng(seed)
            cw = [square_end("cw", truth, rng) for _ in range(runs)]
            ccw = [square_end("ccw", truth, rng) for _ in range(runs)]
            result = umbmark(4.0, cw, ccw, NOMINAL, exact=exact)
            estimate = (
                result.left_wheel_radius,
                result.right_wheel_radius,
                result.wheel_separation,
            )
            errors = np.abs(np.subtract(estimate, truth)) / np.asarray(truth)
            worst = np.maximum(worst, errors)
        print(
            f"    {TICKS} ticks + {NOISE:g} rad noise, {seeds} seeds, exact={exact}: worst "
            f"{describe(list(worst))}"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=20, help="noise seeds (default 20)")
    args = parser.parse_args()
    start = time.perf_counter()
    bench_fit(args.seeds)
    bench_umbmark(args.seeds)
    print(f"total {time.perf_counter() - start:.1f} s")


if __name__ == "__main__":
    main()
