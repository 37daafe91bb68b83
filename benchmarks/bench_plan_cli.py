"""Wall time of ``diffbot plan`` (the default plan, Trajectory A) next to ``import numpy``.

Each command runs as a fresh process: one warm-up run (it also fills the parameter cache, so
yourdfpy is not imported by the timed runs), then the median of ``--runs`` runs. The target is
``diffbot plan`` within 3x the time Python takes to import NumPy.

Run by hand::

    python benchmarks/bench_plan_cli.py [--runs 11]
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

TARGET_RATIO = 3.0


def median_wall_times(commands: list[list[str]], runs: int, env: dict[str, str]) -> list[float]:
    """Median wall time (s) of each command over ``runs`` runs, after one warm-up run each.

    The commands take turns, so a slow spell of the machine hits them alike.
    """
    for command in commands:
        subprocess.run(command, check=True, env=env, stdout=subprocess.DEVNULL)
    times: list[list[float]] = [[] for _ in commands]
    for _ in range(runs):
        for command, spent in zip(commands, times, strict=True):
            start = time.perf_counter()
            subprocess.run(command, check=True, env=env, stdout=subprocess.DEVNULL)
            spent.append(time.perf_counter() - start)
    return [statistics.median(spent) for spent in times]


def diffbot_command() -> list[str]:
    """The installed ``diffbot`` script beside this Python, else ``python -m diffbot``."""
    script = Path(sys.executable).with_name("diffbot")
    if script.exists():
        return [str(script), "plan"]
    found = shutil.which("diffbot")
    return [found, "plan"] if found else [sys.executable, "-m", "diffbot", "plan"]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=11, help="timed runs per command (>= 7)")
    args = parser.parse_args()
    runs = max(7, args.runs)
    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "DIFFBOT_CACHE_DIR": cache}
        env.pop("DIFFBOT_NO_CACHE", None)
        plan_command = diffbot_command()
        numpy_command = [sys.executable, "-c", "import numpy"]
        plan_time, numpy_time = median_wall_times([plan_command, numpy_command], runs, env)
    ratio = plan_time / numpy_time
    verdict = "within" if ratio <= TARGET_RATIO else "OVER"
    print(f"median of {runs} runs each (taking turns), after one warm-up run")
    print(f"  {' '.join(plan_command)}")
    print(f"    {plan_time * 1e3:7.1f} ms")
    print(f"  {sys.executable} -c 'import numpy'")
    print(f"    {numpy_time * 1e3:7.1f} ms")
    print(f"ratio {ratio:.2f}x ({verdict} the {TARGET_RATIO:g}x target)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
