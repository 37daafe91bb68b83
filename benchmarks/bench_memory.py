"""Peak memory of the commands that read or write a million samples, against ``odom``.

Run by hand: ``python benchmarks/bench_memory.py [--samples N] [--keep DIR]``.

One recording of ``--samples`` joint states with a ground-truth pose track is made with
``diffbot simulate`` (Trajectory A, its wheels 0.3 % apart and its separation 0.7 % off). Then
each command below runs once in its own process, and its peak resident memory (the child's
maximum resident set, from ``os.wait4``) is printed with its wall time and its ratio to
``odom``'s peak on the same recording:

* ``odom``: the recording's odometry (streamed in chunks: the reference);
* ``simulate limiter``: Trajectory A through a controller's acceleration limit, sampled at the
  rate that gives ``--samples`` joint states, written to a CSV file;
* ``command bag``: a straight line sampled at 1 kHz into a command bag, ``--samples`` commands;
* ``calibrate fit``: the wheel radii and separation from the recording and its truth;
* ``plot --odom``: Trajectory A with the recording's odometry over it, to a PNG file.

The figure each command must stay under is printed beside it (``--limit`` MB, 150 by default).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from collections.abc import Sequence
from pathlib import Path

#: Trajectory A lasts 40 s.
PLAN_SECONDS = 40
#: A controller whose limiter every command goes through: the bundled robot, 0.05 m/s².
LIMITS = """\
controller_manager:
  ros__parameters:
    update_rate: 50
    diff_drive_controller: {type: diff_drive_controller/DiffDriveController}
diff_drive_controller:
  ros__parameters:
    left_wheel_names: [front_left_wheel_joint]
    right_wheel_names: [front_right_wheel_joint]
    wheel_separation: 0.135
    wheel_radius: 0.035
    linear.x.max_acceleration: 0.05
"""


def measured(argv: Sequence[str]) -> tuple[float, float]:
    """Run a command; its wall time (s) and peak resident memory (MB)."""
    start = time.perf_counter()
    with tempfile.TemporaryFile() as out:
        process = subprocess.Popen(list(argv), stdout=out, stderr=subprocess.PIPE)
        assert process.stderr is not None
        error = process.stderr.read()
        _, status, usage = os.wait4(process.pid, 0)
    seconds = time.perf_counter() - start
    if os.waitstatus_to_exitcode(status) not in (0, 1):
        raise RuntimeError(f"{' '.join(argv)}: {error.decode(errors='replace').strip()}")
    return seconds, usage.ru_maxrss / 1024


def diffbot(*args: str) -> list[str]:
    return [sys.executable, "-m", "diffbot", *args]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=1_000_000)
    parser.add_argument("--limit", type=float, default=150.0, help="MB each must stay under")
    parser.add_argument("--keep", type=Path, help="make the files in DIR and keep them")
    parser.add_argument("--only", nargs="*", help="measure only these commands (and odom)")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as scratch:
        folder = args.keep or Path(scratch)
        folder.mkdir(parents=True, exist_ok=True)
        recording = folder / "recording.csv"
        limits = folder / "limits.yaml"
        limits.write_text(LIMITS, encoding="utf-8")
        rate = str(args.samples / PLAN_SECONDS)
        seconds, _ = measured(
            diffbot(
                "simulate", "--example", "A", "--rate", rate, "--true-wheel-radius",
                "0.0351,0.0349", "--true-separation", "0.136", "--out", str(recording), "--force",
                "--quiet",
            )
        )  # fmt: skip
        print(f"recording: {args.samples} samples with truth, made in {seconds:.1f} s")
        commands = {
            "odom": diffbot("odom", str(recording), "--json", "--quiet"),
            "simulate limiter": diffbot(
                "simulate", "--example", "A", "--controllers", str(limits), "--rate", rate,
                "--out", str(folder / "limited.csv"), "--force", "--quiet",
            ),
            "command bag": diffbot(
                "plan", f"straight {args.samples / 10_000:g} {args.samples / 1000:g}s",
                "--rate", "1000", "--out", str(folder / "commands"), "--bag", "--force",
            ),
            "calibrate fit": diffbot("calibrate", "fit", str(recording), "--json"),
            "plot --odom": diffbot(
                "plot", "--example", "A", "--odom", str(recording), "-o",
                str(folder / "plot.png"), "--force",
            ),
        }  # fmt: skip
        peaks: dict[str, float] = {}
        print(
            f"{'command':<18} {'peak MB':>8} {'x odom':>7} {'seconds':>8}  under {args.limit:g} MB"
        )
        for name, argv in commands.items():
            if args.only and name != "odom" and name not in args.only:
                continue
            seconds, peak = measured(argv)
            peaks[name] = peak
            ratio = peak / peaks["odom"]
            verdict = "yes" if peak < args.limit else "NO"
            print(f"{name:<18} {peak:>8.1f} {ratio:>7.2f} {seconds:>8.1f}  {verdict}")


if __name__ == "__main__":
    main()
