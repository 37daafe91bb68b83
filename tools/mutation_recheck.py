"""Run again, by hand and without mutmut's time limits, the mutants a mutation run
(tools/mutation.sh) marked as timed out or left unrun (all, or a seeded sample), and say what
each one really does.

mutmut stops a mutant at a wall time of (the tests' recorded time + timeout_constant) x
timeout_multiplier. Live tests spend most of their time starting DDS and waiting for discovery,
which the recorded time can leave out: an unchanged node then runs past the limit, and a
mutant its tests would pass is counted as a timeout. This script runs each sampled mutant's
tests in the run's scratch copy with only pytest-timeout's per-test bound, and reports:

- killed: a test failed (``-x``: the first failure ends the run);
- hung: a test ran past --hang seconds (a test that takes a few seconds unchanged);
- survived: every test passed.

    python tools/mutation_recheck.py .mutation/live-nodes/mutants --sample 40 --seed 1

The counts go to stdout, one line per mutant then a summary; the names of the survivors are
listed for ``mutmut show``.
"""

from __future__ import annotations

import argparse
import json
import os
import random
import subprocess
import sys
import time
from collections import Counter
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

#: mutmut's exit codes for a mutant stopped at its time limit (SIGXCPU).
TIMEOUT_CODES = {-24, 24, 152}


def marked(mutants: Path, unrun: bool) -> list[str]:
    """The names of the mutants a run marked as timed out (or, with ``unrun``, did not run
    before it was stopped), sorted."""
    names: list[str] = []
    for meta in sorted(mutants.rglob("*.meta")):
        codes = json.loads(meta.read_text(encoding="utf-8"))["exit_code_by_key"]
        names += [
            name
            for name, code in codes.items()
            if (code is None if unrun else code in TIMEOUT_CODES)
        ]
    return sorted(names)


def tests_by_function(mutants: Path) -> dict[str, list[str]]:
    """The tests mutmut's first run found calling each (mangled) function."""
    stats = json.loads((mutants / "mutmut-stats.json").read_text(encoding="utf-8"))
    found: dict[str, list[str]] = stats["tests_by_mangled_function_name"]
    return {function: sorted(tests) for function, tests in found.items()}


def run(mutants: Path, name: str, tests: list[str], hang: float) -> tuple[str, float]:
    """One mutant's tests: (outcome, seconds)."""
    if not tests:
        return "no tests", 0.0
    start = time.monotonic()
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "pytest",
            *tests,
            "-x",
            "-q",
            "-p",
            "no:randomly",
            "-p",
            "no:cacheprovider",
            "-n",
            "0",
            f"--timeout={hang:g}",
            "--timeout-method=thread",
        ],
        cwd=mutants,
        env={**os.environ, "MUTANT_UNDER_TEST": name},
        capture_output=True,
        text=True,
        check=False,
    )
    seconds = time.monotonic() - start
    if done.returncode == 0:
        return "survived", seconds
    if "Timeout (" in done.stdout or "Timeout (" in done.stderr:
        return "hung", seconds
    if done.returncode == 1:
        return "killed", seconds
    return f"exit {done.returncode}", seconds


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("mutants", type=Path, help="a run's mutants folder")
    parser.add_argument("--sample", type=int, default=40, help="how many (0: all)")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument(
        "--unrun", action="store_true", help="the mutants a stopped run left, not the timed out"
    )
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--hang", type=float, default=60.0, help="per-test bound (s)")
    parser.add_argument(
        "--exclude",
        nargs="+",
        type=Path,
        default=[],
        help="earlier logs of this script: their mutants are not drawn again (a second sample "
        "stays apart from the first)",
    )
    parser.add_argument(
        "--also",
        nargs="+",
        default=[],
        help="tests to run for every mutant besides those mutmut's first run picked (its map "
        "misses tests written since)",
    )
    args = parser.parse_args()
    mutants: Path = args.mutants.resolve()
    drawn = {
        line.split()[-1]
        for log in args.exclude
        for line in log.read_text(encoding="utf-8").splitlines()
        if "  diffbot." in line
    }
    names = [name for name in marked(mutants, args.unrun) if name not in drawn]
    kind = "unrun" if args.unrun else "timed-out"
    if args.sample and args.sample < len(names):
        picked = random.Random(args.seed).sample(names, args.sample)
    else:
        picked = names
    if not picked:
        print(f"no {kind} mutants in {mutants}")
        return
    mapped_tests = tests_by_function(mutants)

    def tests(name: str) -> list[str]:
        mapped = mapped_tests.get(name.rsplit("__mutmut_", 1)[0], [])
        return [*mapped, *args.also] if mapped else []

    clean, seconds = run(mutants, "none", tests(picked[0]), args.hang)
    print(f"unchanged code, first mutant's tests: {clean} in {seconds:.1f} s", flush=True)
    outcomes: dict[str, str] = {}

    def one(name: str) -> None:
        outcome, took = run(mutants, name, tests(name), args.hang)
        outcomes[name] = outcome
        print(f"{outcome:9} {took:6.1f} s  {name}", flush=True)

    with ThreadPoolExecutor(args.jobs) as pool:
        list(pool.map(one, picked))
    counts = dict(sorted(Counter(outcomes.values()).items()))
    print(f"{len(picked)} of {len(names)} {kind} mutants run: {counts}")
    for name in sorted(n for n, o in outcomes.items() if o == "survived"):
        print(f"survived: {name}")


if __name__ == "__main__":
    main()
