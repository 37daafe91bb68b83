"""Wall time of quick CLI commands next to a bare ``python -c "import numpy"``.

Every command runs as a fresh process; the commands take turns round by round (the order reversed
every other round), after one untimed round that warms the parameter cache and the OS file
cache. Each command's median time is reported, and its ratio to the bare NumPy import as the
median of per-round ratios with their spread (target: within 3x).

With ``--baseline REV`` each command is also run as ``python -m diffbot`` from this working tree
and from the files of git revision REV (exported to a temporary folder, removed afterwards), each
importing its own package (checked once); the working tree's time over the revision's is
reported the same way (the layout goal: within 1.2x).

With ``--cold`` every run of a command starts with an empty parameter cache, as the first
command after ``pip install`` and the first on a new description do (``params ROBOT`` then
derives the robot; the bundled robot's parameters ship with the package).

Run by hand: ``python benchmarks/bench_cli_startup.py [--rounds N] [--baseline REV] [--cpu]
[--cold] [COMMAND ...]``.
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

from checkout import Tree, diffbot_side, revision_tree, working_tree
from interleave import CPU_HELP, Side, command, interleave

NUMPY_TARGET = 3.0
BASELINE_GOAL = 1.2


def cold(argv: Sequence[str], *, env: dict[str, str], cpu: bool = False) -> Side:
    """A side that runs ``argv`` with a new, empty parameter cache each time (made and removed
    outside the timing)."""

    def run() -> float:
        with tempfile.TemporaryDirectory() as cache:
            return command(argv, env={**env, "DIFFBOT_CACHE_DIR": cache}, cpu=cpu)()

    return run


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0],
        epilog="Start-up goals: each command <= 3x import numpy; with --baseline, <= 1.2x REV.",
    )
    parser.add_argument("--rounds", type=int, default=15, help="timed rounds (>= 5, default 15)")
    parser.add_argument(
        "--baseline",
        metavar="REV",
        help="also compare each command with python -m diffbot from git revision REV",
    )
    parser.add_argument("--cpu", action="store_true", help=CPU_HELP)
    parser.add_argument(
        "--cold", action="store_true", help="an empty parameter cache for every run of a command"
    )
    parser.add_argument(
        "commands",
        nargs="*",
        default=["params", "ik 0.1 0"],
        help="diffbot commands to time (default: 'params' and 'ik 0.1 0')",
    )
    args = parser.parse_args(argv)
    rounds = max(5, args.rounds)
    script = shutil.which("diffbot") or str(Path(sys.executable).with_name("diffbot"))
    with contextlib.ExitStack() as stack:
        cache = stack.enter_context(tempfile.TemporaryDirectory())
        env = {**os.environ, "DIFFBOT_CACHE_DIR": cache}
        env.pop("DIFFBOT_NO_CACHE", None)
        sides: dict[str, Side] = {
            "numpy": command([sys.executable, "-c", "import numpy"], env=env, cpu=args.cpu)
        }
        trees: list[tuple[str, Tree]] = []
        if args.baseline:
            trees = [
                ("tree", working_tree()),
                ("base", stack.enter_context(revision_tree(args.baseline))),
            ]
        for index, line in enumerate(args.commands):
            words = line.split()
            run = cold if args.cold else command
            sides[f"{index}"] = run([script, *words], env=env, cpu=args.cpu)
            for name, tree in trees:
                # Separate caches: two cache formats in one folder could evict each other.
                side_env = {**env, "DIFFBOT_CACHE_DIR": str(Path(cache) / name)}
                sides[f"{index} {name}"] = diffbot_side(tree, words, side_env, cpu=args.cpu)
        timings = interleave(sides, rounds)

    print(f"{rounds} rounds, commands taking turns (order reversed every other round), after one")
    clock = "CPU time (user + system)" if args.cpu else "wall time"
    cache_state = "an empty parameter cache every run" if args.cold else "a warm parameter cache"
    print(f"untimed round, {cache_state}; median {clock}, then the median of per-round ratios:")
    print(f"python -c 'import numpy'   {timings.median('numpy') * 1e3:7.1f} ms")
    for index, line in enumerate(args.commands):
        ratio = timings.ratio(f"{index}", "numpy").describe()
        print(
            f"diffbot {line:<18} {timings.median(f'{index}') * 1e3:7.1f} ms"
            f"  = {ratio} x numpy; target <= {NUMPY_TARGET:g}"
        )
    if trees:
        (_, tree), (_, base) = trees
        print(f"python -m diffbot, working tree {tree.label} against revision {base.label}:")
        for index, line in enumerate(args.commands):
            tree_ms = timings.median(f"{index} tree") * 1e3
            base_ms = timings.median(f"{index} base") * 1e3
            ratio = timings.ratio(f"{index} tree", f"{index} base").describe()
            print(
                f"  {line:<18} {tree_ms:7.1f} ms against {base_ms:7.1f} ms"
                f"  = {ratio}; goal <= {BASELINE_GOAL:g}"
            )
    return 0


if __name__ == "__main__":
    sys.exit(main())
