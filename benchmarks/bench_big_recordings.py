"""Big recordings: throughput against the storage floor, memory and time by length, and fleets.
Run by hand: ``python benchmarks/bench_big_recordings.py [--samples N] [--sizes N ...]
[--rounds R] [--baseline REV]``.

1. Goals, at ``--samples`` joint states (Trajectory A written by ``diffbot simulate`` as a
   sqlite3 rosbag2 and as CSV), interleaved round by round, each run a fresh process timed
   from launch to exit: ``sqlite`` (every message blob read with :mod:`sqlite3` in stamp
   order, the bag's floor), ``odom bag``, ``loadtxt`` (:func:`numpy.loadtxt` of the whole CSV,
   the CSV's floor) and ``odom csv``. The ratios are medians of the per-round ratios.
2. Growth: for each of ``--sizes``, wall time and peak resident memory of ``simulate`` (CSV
   and bag) and ``odom`` (bag and CSV), for the baseline revision (before) and this checkout
   (after), one run each; the final poses of both ``odom`` runs must be equal bit for bit.
3. Fleets: ``odom`` of 8 recordings (copies of the CSV) serially and with ``--jobs 2``.

Peak memory is the child's maximum resident set (``os.wait4``).
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator, Sequence
from pathlib import Path

from checkout import Tree, revision_tree, working_tree
from interleave import interleave

#: Trajectory A lasts 40 s; simulate samples it at --rate plus once at each segment end.
PLAN_SECONDS = 40

SQLITE_FLOOR = """
import sqlite3, sys, time
from pathlib import Path
start = time.perf_counter()
db = next(Path(sys.argv[1]).glob("*.db3"))
connection = sqlite3.connect(db.resolve().as_uri() + "?mode=ro&immutable=1", uri=True)
cursor = connection.execute("SELECT data FROM messages ORDER BY timestamp")
count = 0
while rows := cursor.fetchmany(65536):
    count += sum(len(r[0]) for r in rows)
print(time.perf_counter() - start)
"""
LOADTXT_FLOOR = """
import sys, time, numpy
start = time.perf_counter()
numpy.loadtxt(sys.argv[1], delimiter=",", skiprows=1)
print(time.perf_counter() - start)
"""
#: The odometry of a recording in the library, timed after the imports.
ODOMETRY = """
import sys, time, diffbot
from diffbot.replay import recording_odometry
params = diffbot.load_params()
start = time.perf_counter()
recording_odometry(sys.argv[1], params)
print(time.perf_counter() - start)
"""


def run(argv: Sequence[str], tree: Tree | None = None) -> tuple[float, float, str]:
    """Run a command once: wall time (s), peak resident memory (MB), standard output."""
    env = dict(os.environ)
    # Timed as an installed package runs: from cached bytecode, not compiled afresh each run.
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    if tree is not None:
        env["PYTHONPATH"] = str(tree.root)
    start = time.perf_counter()
    with tempfile.TemporaryFile() as out:
        process = subprocess.Popen(list(argv), stdout=out, stderr=subprocess.PIPE, env=env)
        assert process.stderr is not None
        error = process.stderr.read()
        _, status, usage = os.wait4(process.pid, 0)
        seconds = time.perf_counter() - start
        process.returncode = os.waitstatus_to_exitcode(status)
        if process.returncode != 0:
            raise RuntimeError(f"{' '.join(argv)}: {error.decode(errors='replace').strip()}")
        out.seek(0)
        text = out.read().decode()
    return seconds, usage.ru_maxrss / 1024, text


def diffbot(*args: str) -> list[str]:
    return [sys.executable, "-m", "diffbot", *args]


def make_inputs(folder: Path, samples: int) -> tuple[Path, Path]:
    """Trajectory A as ``samples`` joint states: a sqlite3 bag and a CSV."""
    rate = str((samples - 3) / PLAN_SECONDS)
    bag, csv = folder / f"a{samples}_bag", folder / f"a{samples}.csv"
    if not bag.exists():
        run(
            diffbot(
                "simulate",
                "--rate",
                rate,
                "--start",
                "1700000000",
                "--out",
                str(bag),
                "--bag",
                "-q",
            )
        )
    if not csv.exists():
        run(diffbot("simulate", "--rate", rate, "--out", str(csv), "-q"))
    return bag, csv


def goals(folder: Path, samples: int, rounds: int, before: Tree | None = None) -> None:
    bag, csv = make_inputs(folder, samples)
    peaks: dict[str, float] = {}
    inner: dict[str, list[float]] = {}

    def side(name: str, argv: list[str], tree: Tree | None = None):
        def once() -> float:
            seconds, peak, text = run(argv, tree)
            peaks[name] = max(peaks.get(name, 0.0), peak)
            if not name.startswith("odom"):  # the others print their time after the imports
                inner.setdefault(name, []).append(float(text))
            return seconds

        return once

    python = sys.executable
    sides = {
        "sqlite": side("sqlite", [python, "-c", SQLITE_FLOOR, str(bag)]),
        "odom bag": side("odom bag", diffbot("odom", str(bag), "-q")),
        "lib bag": side("lib bag", [python, "-c", ODOMETRY, str(bag)]),
    }
    if before is not None:  # the baseline's bag odometry, in the same rounds
        sides["odom bag before"] = side("odom bag before", diffbot("odom", str(bag)), before)
    sides |= {
        "loadtxt": side("loadtxt", [python, "-c", LOADTXT_FLOOR, str(csv)]),
        "odom csv": side("odom csv", diffbot("odom", str(csv), "-q")),
        "lib csv": side("lib csv", [python, "-c", ODOMETRY, str(csv)]),
    }
    timings = interleave(sides, rounds)
    print(f"\n## Goals at {samples} samples ({rounds} rounds, interleaved)")
    print("side            launch to exit (s), after the imports (s), peak memory (MB)")
    for name in sides:
        after = f"{statistics.median(inner[name][-rounds:]):7.2f}" if name in inner else "      -"
        print(f"{name:<15} {timings.median(name):7.2f} {after}  {peaks[name]:6.0f} MB")
    print("Launch to exit (the commands as a user runs them):")
    print(f"odom bag / sqlite : {timings.ratio('odom bag', 'sqlite').describe()}  (goal < 2)")
    if before is not None:
        ratio = timings.ratio("odom bag before", "sqlite").describe()
        print(f"  before ({before.label}): {ratio}")
    print(f"odom csv / loadtxt: {timings.ratio('odom csv', 'loadtxt').describe()}  (goal < 1.5)")
    print("After the imports (the reading and the odometry alone):")
    for lib, floor, goal in (("lib bag", "sqlite", 3), ("lib csv", "loadtxt", 1.5)):
        pairs = zip(inner[lib][-rounds:], inner[floor][-rounds:], strict=True)
        ratios = [a / b for a, b in pairs]
        print(
            f"{lib} / {floor}: median {statistics.median(ratios):.2f}, "
            f"range {min(ratios):.2f}-{max(ratios):.2f}  (goal < {goal})"
        )


def growth(
    folder: Path, sizes: Sequence[int], before: Tree | None, only: Sequence[str] = ()
) -> None:
    print("\n## Growth: wall time (s) and peak memory (MB), one run each")
    print(f"{'work':<16} {'samples':>9} {'before':>18} {'after':>18}")
    trees = {"after": working_tree()} | ({"before": before} if before is not None else {})
    for samples in sizes:
        rate = str((samples - 3) / PLAN_SECONDS)
        poses: dict[str, dict[str, str]] = {}
        work: dict[str, list[str]] = {
            "simulate csv": ["simulate", "--rate", rate, "--out", "{out}.csv", "--force"],
            "simulate bag": [
                "simulate",
                "--rate",
                rate,
                "--out",
                "{out}_bag",
                "--bag",
                "--force",
                "--start",
                "1700000000",
            ],
            "odom bag": ["odom", "{input}_bag", "--json"],
            "odom csv": ["odom", "{input}.csv", "--json"],
        }
        for name, args in work.items():
            if only and name not in only:
                if name.startswith("simulate"):  # the odometry still needs the recordings
                    out = str(folder / f"after{samples}")
                    run(diffbot(*[a.replace("{out}", out) for a in args], "-q"))
                continue
            cells = {}
            for label in ("before", "after"):
                tree = trees.get(label)
                if tree is None:
                    cells[label] = "-"
                    continue
                if label == "before" and name.startswith("simulate bag") and samples > 2_000_000:
                    cells[label] = "skipped"  # minutes of rosbags serialisation, as after
                    continue
                out = str(folder / f"{label}{samples}")
                given = str(folder / f"after{samples}")  # the same data, whoever wrote it
                argv = [a.replace("{out}", out).replace("{input}", given) for a in args]
                quiet = ["-q"] if label == "after" else []
                seconds, peak, text = run(diffbot(*argv, *quiet), tree)
                cells[label] = f"{seconds:7.2f} s {peak:6.0f} MB"
                if name.startswith("odom"):
                    poses.setdefault(name, {})[label] = json.dumps(json.loads(text)["final_pose"])
            print(f"{name:<16} {samples:>9} {cells['before']:>18} {cells['after']:>18}")
        for name, by_label in poses.items():
            if len(by_label) == 2:
                same = by_label["before"] == by_label["after"]
                verdict = "bit-identical" if same else "DIFFER"
                print(f"{'':<27} final poses of {name}: {verdict}")
        for label in ("before", "after"):
            for path in folder.glob(f"{label}{samples}*"):
                shutil.rmtree(path) if path.is_dir() else path.unlink()


def fleet(folder: Path, samples: int, rounds: int) -> None:
    _, csv = make_inputs(folder, samples)
    copies = []
    for k in range(8):
        copy = folder / f"fleet{k}.csv"
        shutil.copyfile(csv, copy)
        copies.append(str(copy))
    sides = {
        "serial": lambda: run(diffbot("odom", *copies, "-q"))[0],
        "jobs 2": lambda: run(diffbot("odom", *copies, "-q", "--jobs", "2"))[0],
    }
    timings = interleave(sides, rounds)
    print(f"\n## Fleet: 8 recordings of {samples} samples ({os.cpu_count()} cores)")
    print(f"serial {timings.median('serial'):.2f} s, --jobs 2 {timings.median('jobs 2'):.2f} s")
    print(f"speed-up (serial / jobs 2): {timings.ratio('serial', 'jobs 2').describe()}")


@contextlib.contextmanager
def baseline(revision: str | None) -> Iterator[Tree | None]:
    if revision is None:
        yield None
        return
    with revision_tree(revision) as tree:
        yield tree


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--samples", type=int, default=1_000_001, help="samples for the goals")
    parser.add_argument("--sizes", type=int, nargs="*", default=[100_001, 1_000_001, 9_999_991])
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--baseline", default="main", help="revision for 'before' ('' for none)")
    parser.add_argument("--work", nargs="*", default=[], help="growth rows to measure (all)")
    parser.add_argument(
        "--parts", nargs="*", default=["goals", "fleet", "growth"], help="what to measure"
    )
    args = parser.parse_args()
    with (
        tempfile.TemporaryDirectory(prefix="diffbot-big-") as tmp,
        baseline(args.baseline or None) as before,
    ):
        folder = Path(tmp)
        if "goals" in args.parts:
            goals(folder, args.samples, args.rounds, before)
        if "fleet" in args.parts:
            fleet(folder, args.samples, max(1, args.rounds // 2))
        if "growth" in args.parts:
            growth(folder, args.sizes, before, args.work)


if __name__ == "__main__":
    main()
