"""Goal-plan benchmarks: planning time per goal for every shape, against OMPL's Reeds-Shepp and
Dubins.

Run by hand: ``python benchmarks/bench_goals.py [--goals N] [--rounds N] [--cpu]`` (OMPL from
``pip install ompl``; without it the OMPL side and its ratio are left out).

The same goals (default 10,000: x, y uniform in [-2, 2] m, heading uniform, from the origin) go
through every side in each round, the sides taking turns round by round (the order reversed every
other round), so a busy spell of the machine hits them alike. Each goal's result is dropped
as soon as it is made, on every side: the time is planning, not keeping 10,000 plans alive for
the garbage collector to walk. ``--profile`` adds, after the figures, where ``plan_to``'s
time goes for each shape under cProfile: its path search, the planned segments
(``trajectory.plan``) and the rest. What each side does, per goal unless said otherwise:

- ``ompl reeds-shepp``, ``ompl dubins``: ``ReedsSheppStateSpace.distance`` and
  ``DubinsStateSpace.distance`` (OMPL's C++, radius 0.25 m) through its Python bindings, on
  states made beforehand: the length of the shortest path only (OMPL finds the words and
  lengths inside, and returns their sum). The binding's call is part of it, as a call of ours
  is part of ours. Reeds-Shepp sides are compared with the first, Dubins sides with the second.
- ``plan_to <shape>``: :func:`diffbot.goals.plan_to` from Python, the whole plan for the bundled
  robot (turning radius 0.25 m): the checked goal, the path (words and lengths), its segments,
  each segment's duration, twist, wheel and joint speeds, share of the motor limit and exact
  end pose, the plan's duration and final pose.
- ``reeds-shepp path``, ``dubins path``, ``fastest path``: the closed forms of
  :mod:`diffbot.planning` alone (the words and lengths as pieces, no plan).
- ``reeds-shepp distances``: :func:`diffbot.planning.reeds_shepp.distances`, all goals in one
  NumPy call (lengths only).
- ``python floor: one dubins word``: the yardstick of what Python costs here: one call that
  solves one Dubins word (LSL, the operations :func:`diffbot.planning.dubins.path` spends on
  it: a sine and cosine of the heading, an ``atan2``, a ``hypot``, two angle wraps) and returns
  its three lengths, nothing else. Every path solves at least two words (LSL and RSR always
  exist, and one is needed to rule the other out), so its ratio to OMPL's Dubins call bounds
  from below what a Python path can reach.
- ``reeds-shepp paths, batched``: :func:`diffbot.planning.reeds_shepp.paths`, all goals in one
  NumPy call: for every goal the word chosen (the one :func:`~diffbot.planning.reeds_shepp.path`
  chooses) and all its piece lengths, as arrays; its time per goal is the call's time divided
  by the number of goals. It does more than the OMPL side (the word and each length, not their
  sum), but all goals at once rather than one call per goal.

The goals, and the lines that say whether they are kept: ``plan_to fastest`` under 50 us per
goal (median over rounds); per goal, as the median of the per-round ratios to OMPL's side of
the same family: ``reeds-shepp path`` and ``dubins path`` within 3x, ``reeds-shepp paths,
batched`` within 2.1x, ``plan_to reeds-shepp`` and ``plan_to dubins`` within 10x. Times are
given as the median with the interquartile range over the rounds, with the machine's load
(1-minute average) before and after: the ratios hold on a busy machine, the times do not.
"""

from __future__ import annotations

import argparse
import math
import os
import statistics
import sys
from collections.abc import Callable, Sequence

import numpy as np
from interleave import CPU_HELP, Side, interleave, timed

from diffbot.goals import SHAPES, plan_to
from diffbot.kinematics import DiffDriveParams
from diffbot.planning import balkcom_mason, dubins, reeds_shepp

PARAMS = DiffDriveParams(0.035, 0.135, max_wheel_speed=50 * 2 * math.pi / 60)
RADIUS = 0.25  # m
TWO_PI = 2.0 * math.pi
FLOOR = "python floor: one dubins word"
OMPL = "ompl reeds-shepp"
OMPL_DUBINS = "ompl dubins"
BATCHED = "reeds-shepp paths, batched"
FASTEST_GOAL_US = 50.0
#: (side, OMPL side it is compared with, the most times OMPL's time it may take).
GOALS = (
    ("reeds-shepp path", OMPL, 3.0),
    ("dubins path", OMPL_DUBINS, 3.0),
    (BATCHED, OMPL, 2.1),
    ("plan_to reeds-shepp", OMPL, 10.0),
    ("plan_to dubins", OMPL_DUBINS, 10.0),
)


def one_word(x: float, y: float, phi: float) -> tuple[float, float, float]:
    """The LSL word's three lengths (radii) to ``(x, y, phi)``, as :mod:`dubins` solves it."""
    sp, cp = math.sin(phi), math.cos(phi)
    lx, vy = x - sp, y + cp - 1.0
    h = math.atan2(vy, lx)
    return h % TWO_PI, math.hypot(lx, vy), (phi - h) % TWO_PI


def profile(points: np.ndarray, shape: str) -> dict[str, float]:
    """The shares (0-1) of ``plan_to``'s time under cProfile by part, for one shape: the path
    search (the cumulative time of the planning modules' ``path``), the planned segments (of
    ``trajectory.plan``, the calls it makes included) and the rest (checks, legs, the Plan)."""
    import cProfile
    import pstats

    parts = {"path search": ("/planning/", "path"), "planned segments": ("/trajectory.py", "plan")}
    rows = points.tolist()
    profiler = cProfile.Profile()
    profiler.enable()
    for x, y, h in rows:
        plan_to((x, y, h), PARAMS, shape=shape, min_radius=RADIUS)
    profiler.disable()
    stats = pstats.Stats(profiler).stats  # type: ignore[attr-defined]
    total = next(entry[3] for key, entry in stats.items() if key[2] == "plan_to")
    shares = dict.fromkeys([*parts, "the rest"], 0.0)
    for (filename, _, function), entry in stats.items():
        for part, (tail, name) in parts.items():
            if tail in filename and function == name:
                shares[part] += entry[3] / total
    shares["the rest"] = 1.0 - shares["path search"] - shares["planned segments"]
    return shares


def goals(count: int) -> np.ndarray:
    rng = np.random.default_rng(2002)
    return np.column_stack(
        (rng.uniform(-2.0, 2.0, (count, 2)), rng.uniform(-math.pi, math.pi, count))
    )


def ompl_side(points: np.ndarray, cpu: bool, family: str = "ReedsSheppStateSpace") -> Side | None:
    """OMPL's ``family`` state space's distance, goal by goal (None without OMPL)."""
    try:
        from ompl import base as ob
    except ImportError:
        return None
    space = getattr(ob, family)(RADIUS)
    start = space.allocState()
    start.setX(0.0)
    start.setY(0.0)
    start.setYaw(0.0)
    states = []
    for x, y, heading in points.tolist():
        state = space.allocState()
        state.setX(x)
        state.setY(y)
        state.setYaw(heading)
        states.append(state)
    distance = space.distance

    def run() -> None:
        for state in states:
            distance(start, state)

    return timed(run, cpu=cpu)


def each(points: np.ndarray, work: Callable[[float, float, float], object], cpu: bool) -> Side:
    """A side that calls ``work`` goal by goal, each result dropped at once (as OMPL's are)."""
    rows = points.tolist()

    def run() -> None:
        for x, y, h in rows:
            work(x, y, h)

    return timed(run, cpu=cpu)


def per_goal(seconds: Sequence[float], goals: int) -> str:
    """Median (IQR) of the rounds' times, in microseconds per goal."""
    us = [t / goals * 1e6 for t in seconds]
    q1, q3 = (
        statistics.quantiles(us, n=4, method="inclusive") if len(us) > 1 else (us[0], us[0], us[0])
    )[::2]
    return f"{statistics.median(us):8.2f} us per goal (IQR {q1:.2f}-{q3:.2f})"


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--goals", type=int, default=10_000, help="goals, default 10000")
    parser.add_argument("--rounds", type=int, default=7, help="timed rounds, default 7")
    parser.add_argument("--cpu", action="store_true", help=CPU_HELP)
    parser.add_argument(
        "--profile", action="store_true", help="also print where plan_to's time goes (cProfile)"
    )
    args = parser.parse_args(argv)
    points = goals(args.goals)
    scaled = points / np.array([RADIUS, RADIUS, 1.0])
    half = 0.5 * PARAMS.wheel_separation
    sides: dict[str, Side] = {}
    ompl = ompl_side(points, args.cpu)
    if ompl is not None:
        sides[OMPL] = ompl
        dubins_side = ompl_side(points, args.cpu, "DubinsStateSpace")
        assert dubins_side is not None  # OMPL imported a line above
        sides[OMPL_DUBINS] = dubins_side
    for shape in SHAPES:
        sides[f"plan_to {shape}"] = each(
            points,
            lambda x, y, h, s=shape: plan_to((x, y, h), PARAMS, shape=s, min_radius=RADIUS),
            args.cpu,
        )
    sides["reeds-shepp path"] = each(scaled, reeds_shepp.path, args.cpu)
    sides["dubins path"] = each(scaled, dubins.path, args.cpu)
    sides[FLOOR] = each(scaled, one_word, args.cpu)
    sides["fastest path"] = each(points / np.array([half, half, 1.0]), balkcom_mason.path, args.cpu)
    xs, ys, hs = scaled[:, 0].copy(), scaled[:, 1].copy(), scaled[:, 2].copy()
    sides["reeds-shepp distances"] = timed(lambda: reeds_shepp.distances(xs, ys, hs), cpu=args.cpu)
    sides[BATCHED] = timed(lambda: reeds_shepp.paths(xs, ys, hs), cpu=args.cpu)
    clock = "CPU" if args.cpu else "wall"
    print(f"{args.goals} goals, {args.rounds} rounds interleaved ({clock} time), radius {RADIUS} m")
    load = os.getloadavg()[0]
    timings = interleave(sides, args.rounds)
    print(f"load (1-minute average): {load:.2f} before, {os.getloadavg()[0]:.2f} after")
    width = max(len(name) for name in sides)
    for name in sides:
        print(f"  {name:<{width}}  {per_goal(timings.seconds[name], args.goals)}")
    if OMPL in sides:
        print("ratios per goal to OMPL's side of the same family, median of per-round ratios:")
        for name in sides:
            if not name.startswith("ompl"):
                reference = OMPL_DUBINS if "dubins" in name else OMPL
                ratio = timings.ratio(name, reference).describe(2)
                print(f"  {name:<{width}}  {ratio} x {reference}")
    fastest = timings.median("plan_to fastest") / args.goals * 1e6
    kept = "kept" if fastest < FASTEST_GOAL_US else "NOT kept"
    print(
        f"goal: plan_to fastest < {FASTEST_GOAL_US:g} us per goal: {kept} "
        f"({per_goal(timings.seconds['plan_to fastest'], args.goals).strip()})"
    )
    if OMPL in sides:
        for name, reference, most in GOALS:
            ratio = timings.ratio(name, reference)
            kept = "kept" if ratio.median <= most else "NOT kept"
            print(f"goal: {name} <= {most:g}x {reference} per goal: {kept} ({ratio.describe(2)})")
    else:
        print("goals against OMPL: not measured (pip install ompl)")
    if args.profile:
        print(
            "where plan_to's time goes (share of its own time under cProfile, times that share"
            " of its median above, and that part alone against OMPL's side):"
        )
        for shape in SHAPES:
            whole = timings.median(f"plan_to {shape}")
            reference = OMPL_DUBINS if shape == "dubins" else OMPL
            parts = []
            for part, share in profile(points, shape).items():
                text = f"{part} {100 * share:.0f} % ({share * whole / args.goals * 1e6:.1f} us"
                if reference in sides:
                    text += f", {share * whole / timings.median(reference):.1f}x"
                parts.append(text + ")")
            print(f"  plan_to {shape}: {'; '.join(parts)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
