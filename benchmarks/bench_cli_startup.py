"""Wall time of quick CLI commands next to a bare ``python -c "import numpy"``.

Run by hand: ``python benchmarks/bench_cli_startup.py [--runs N]``. Each command runs once to warm
the parameter cache and the OS file cache, then N times; the median is reported with the ratio to
the bare NumPy import (target: within 3x).
"""

from __future__ import annotations

import argparse
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path


def median_seconds(command: list[str], runs: int) -> float:
    subprocess.run(command, check=True, capture_output=True)  # warm-up
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        subprocess.run(command, check=True, capture_output=True)
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--runs", type=int, default=15)
    parser.add_argument(
        "commands",
        nargs="*",
        default=["params", "ik 0.1 0"],
        help="diffbot commands to time (default: 'params' and 'ik 0.1 0')",
    )
    options = parser.parse_args()
    script = shutil.which("diffbot") or str(Path(sys.executable).with_name("diffbot"))
    baseline = median_seconds([sys.executable, "-c", "import numpy"], options.runs)
    print(f"python -c 'import numpy'   {baseline * 1e3:7.1f} ms  (median of {options.runs})")
    for command in options.commands:
        seconds = median_seconds([script, *command.split()], options.runs)
        print(f"diffbot {command:<18} {seconds * 1e3:7.1f} ms  = {seconds / baseline:.2f}x numpy")


if __name__ == "__main__":
    main()
