"""First contact: commands on an empty parameter cache, next to ``python -c 'import numpy'``.

Run by hand: ``python benchmarks/bench_first_run.py [--rounds N] [--cpu]``.

Each run is a fresh process with a parameter cache folder of its own, empty
(``DIFFBOT_CACHE_DIR``), as right after ``pip install``: ``diffbot plan`` (the bundled robot,
Trajectory A) and ``diffbot params`` of a description diffbot has not seen
(``docs/examples/pioneer.urdf``). The sides take turns round by round (:mod:`interleave`); each
ratio is the median of the per-round ratios to the NumPy import. Goals: the first ``plan``
within 3x, the first ``params`` of a new description within 6x. The machine's load is printed
beside the figures.
"""

from __future__ import annotations

import argparse
import os
import shutil
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from interleave import CPU_HELP, Side, command, interleave

ROOT = Path(__file__).resolve().parents[1]
DESCRIPTION = ROOT / "docs" / "examples" / "pioneer.urdf"
GOALS = {"plan": 3.0, "params": 6.0}


def load() -> str:
    """The machine's load averages over 1, 5 and 15 minutes."""
    return "load " + "/".join(f"{x:.1f}" for x in os.getloadavg())


def cold(argv: list[str], env: dict[str, str], cpu: bool) -> Side:
    """A side that runs ``argv`` with a new, empty cache folder each time."""

    def run() -> float:
        folder = tempfile.mkdtemp(prefix="diffbot-cache-")
        try:
            return command(argv, env={**env, "DIFFBOT_CACHE_DIR": folder}, cpu=cpu)()
        finally:
            shutil.rmtree(folder, ignore_errors=True)

    return run


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--cpu", action="store_true", help=CPU_HELP)
    args = parser.parse_args()
    env = dict(os.environ)
    env.pop("DIFFBOT_NO_CACHE", None)
    env.pop("PYTHONDONTWRITEBYTECODE", None)  # from cached bytecode, as installed
    diffbot = [sys.executable, "-m", "diffbot"]
    sides = {
        "numpy": command([sys.executable, "-c", "import numpy"], env=env, cpu=args.cpu),
        "plan": cold([*diffbot, "plan"], env, args.cpu),
        "params": cold([*diffbot, "params", "--robot", str(DESCRIPTION)], env, args.cpu),
    }
    before = load()
    timings = interleave(sides, args.rounds)
    print(f"first runs on an empty parameter cache ({args.rounds} rounds, {before} before):")
    print(f"  python -c 'import numpy'   {timings.median('numpy') * 1e3:7.0f} ms")
    for name, goal in GOALS.items():
        ratio = timings.ratio(name, "numpy").describe()
        print(
            f"  diffbot {name:<18} {timings.median(name) * 1e3:7.0f} ms = {ratio} x numpy "
            f"(goal <= {goal:g})"
        )
    print(f"  ({load()} after)")


if __name__ == "__main__":
    main()
