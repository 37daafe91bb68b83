"""Every figure of docs/speed.md, measured in one go.

Run: ``python benchmarks/run_all.py [--quick]`` (about 8 minutes on a quiet two-core machine,
plus a few minutes the first time, to write the rosbags bag). Each benchmark runs as a child
process and prints its own figures, each beside its yardstick measured in the same rounds and
the machine's load; ``--quick`` runs fewer rounds. The live benchmarks use a DDS domain of their
own, on loopback only.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer rounds, shorter runs")
    args = parser.parse_args()
    rounds = "2" if args.quick else "3"
    runs = [
        [
            "bench_live.py",
            "--rates", "1000,2000,3000,5000,7500",
            "--seconds", "2",
            "--rounds", "1" if args.quick else "2",
            "--memory-minutes", "0.5" if args.quick else "1",
        ],
        ["bench_bag_floor.py", "--rounds", rounds],
        [
            "bench_goals.py", "--goals", "2000", "--rounds", "5" if args.quick else "7",
            "--cpu", "--profile",
        ],
        ["bench_first_run.py", "--rounds", rounds],
    ]  # fmt: skip
    failed = 0
    began = time.monotonic()
    for argv in runs:
        print(f"\n$ python benchmarks/{' '.join(argv)}", flush=True)
        start = time.monotonic()
        done = subprocess.run([sys.executable, str(HERE / argv[0]), *argv[1:]], check=False)
        failed += done.returncode != 0
        print(f"({time.monotonic() - start:.0f} s)", flush=True)
    print(f"\nall in {time.monotonic() - began:.0f} s; load {os.getloadavg()[0]:.1f} at the end")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
