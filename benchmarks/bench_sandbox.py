"""Time to expand the bundled description with plain xacro, in the sandbox, and trusted.

Run by hand: ``python benchmarks/bench_sandbox.py [--rounds N]``. ``$(find)`` is mapped to the
bundled packages in every case, as ``diffbot.urdf`` maps them. The three ways take turns round
by round (:mod:`interleave`), so a busy spell of the machine hits them alike; each is reported
with its median time and the median of its per-round ratios to plain xacro.
"""

from __future__ import annotations

import argparse

import xacro
import xacro.substitution_args as subst
from interleave import interleave, timed

from diffbot.urdf import BUNDLED_DESCRIPTION, BUNDLED_PACKAGES
from diffbot.urdf.sandbox import process

PACKAGES = {name: str(folder) for name, folder in BUNDLED_PACKAGES.items()}


def plain() -> str:
    saved = subst._eval_find
    subst._eval_find = PACKAGES.__getitem__
    try:
        document = xacro.process_file(str(BUNDLED_DESCRIPTION), mappings={})
        return str(document.toprettyxml(indent="  "))
    finally:
        subst._eval_find = saved


def sandboxed() -> str:
    return process(BUNDLED_DESCRIPTION, find=PACKAGES.__getitem__)


def trusted() -> str:
    return process(BUNDLED_DESCRIPTION, find=PACKAGES.__getitem__, trust=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rounds", type=int, default=200, help="timed rounds (default 200)")
    rounds = max(1, parser.parse_args().rounds)
    ways = {"plain xacro": plain, "sandbox": sandboxed, "trust=True": trusted}
    assert len({run() for run in ways.values()}) == 1, "the three ways disagree"
    timings = interleave({name: timed(run) for name, run in ways.items()}, rounds, warmup=3)
    for name in ways:
        ratio = timings.ratio(name, "plain xacro").describe()
        print(f"{name:12s} {timings.median(name) * 1e3:7.2f} ms  ratio to plain xacro {ratio}")


if __name__ == "__main__":
    main()
