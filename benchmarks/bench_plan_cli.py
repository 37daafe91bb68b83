"""Wall time of ``diffbot plan`` (the default plan, Trajectory A) next to ``import numpy``.

Each command runs as a fresh process. The commands take turns round by round (the order
reversed every other round), after one untimed round that also fills the parameter caches, so
yourdfpy is not imported by the timed runs. Ratios are medians of the per-round ratios, with
their spread. Target: ``diffbot plan`` within 3x the time Python takes to import NumPy.

With ``--baseline REV`` the start-up of ``python -m diffbot plan`` from this working tree is also
compared with the same command from the files of git revision REV (exported to a temporary
folder, removed afterwards), each importing its own package (checked once): the layout goal is
start-up within 1.2x of the revision's.

Run by hand::

    python benchmarks/bench_plan_cli.py [--rounds 15] [--baseline REV] [--cpu]
"""

from __future__ import annotations

import argparse
import contextlib
import os
import shutil
import sys
import tempfile
from collections.abc import Sequence
from pathlib import Path

from checkout import diffbot_side, revision_tree, working_tree
from interleave import CPU_HELP, Side, command, interleave

NUMPY_TARGET = 3.0
BASELINE_GOAL = 1.2


def installed_diffbot() -> list[str]:
    """The installed ``diffbot`` script beside this Python, else ``python -m diffbot``."""
    script = Path(sys.executable).with_name("diffbot")
    if script.exists():
        return [str(script)]
    found = shutil.which("diffbot")
    return [found] if found else [sys.executable, "-m", "diffbot"]


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0],
        epilog="Start-up goals: diffbot plan <= 3x import numpy; with --baseline, <= 1.2x REV.",
    )
    parser.add_argument("--rounds", type=int, default=15, help="timed rounds (>= 5, default 15)")
    parser.add_argument(
        "--baseline",
        metavar="REV",
        help="also compare with python -m diffbot plan from git revision REV (e.g. HEAD~3)",
    )
    parser.add_argument("--cpu", action="store_true", help=CPU_HELP)
    args = parser.parse_args(argv)
    rounds = max(5, args.rounds)
    with contextlib.ExitStack() as stack:
        cache = stack.enter_context(tempfile.TemporaryDirectory())
        env = {**os.environ, "DIFFBOT_CACHE_DIR": cache}
        env.pop("DIFFBOT_NO_CACHE", None)
        plan = installed_diffbot()
        sides: dict[str, Side] = {
            "numpy": command([sys.executable, "-c", "import numpy"], env=env, cpu=args.cpu),
            "plan": command([*plan, "plan"], env=env, cpu=args.cpu),
        }
        if args.baseline:
            tree = working_tree()
            base = stack.enter_context(revision_tree(args.baseline))
            # Separate caches: two cache formats in one folder could evict each other.
            for name, source in (("tree", tree), ("base", base)):
                side_env = {**env, "DIFFBOT_CACHE_DIR": str(Path(cache) / name)}
                sides[name] = diffbot_side(source, ["plan"], side_env, cpu=args.cpu)
        timings = interleave(sides, rounds)

    print(f"{rounds} rounds, the commands taking turns (order reversed every other round)")
    clock = "CPU time (user + system)" if args.cpu else "wall time"
    print(f"after one untimed round; median {clock} of each command:")
    print(f"  {sys.executable} -c 'import numpy'")
    print(f"    {timings.median('numpy') * 1e3:7.1f} ms")
    print(f"  {' '.join(plan)} plan")
    print(f"    {timings.median('plan') * 1e3:7.1f} ms")
    if args.baseline:
        print(f"  python -m diffbot plan, working tree {tree.label} ({tree.root})")
        print(f"    {timings.median('tree') * 1e3:7.1f} ms")
        print(f"  python -m diffbot plan, revision {base.label}")
        print(f"    {timings.median('base') * 1e3:7.1f} ms")
    print("median of per-round ratios:")
    print(
        f"  diffbot plan / import numpy: {timings.ratio('plan', 'numpy').describe()}"
        f"; target <= {NUMPY_TARGET:g}"
    )
    if args.baseline:
        print(
            f"  working tree / {args.baseline}: {timings.ratio('tree', 'base').describe()}"
            f"; goal <= {BASELINE_GOAL:g}"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
