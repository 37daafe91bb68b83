"""Closing the loop: plans run on a disturbed simulated robot, open loop and followed, against
the trackers users would pick instead. Run by hand: ``python benchmarks/bench_follow.py
[--plans N] [--seed S]``.

The bundled robot runs Trajectory A, Trajectory B and ``--plans`` random plans of straights,
arcs and spins within its motor limit, commanded at 20 Hz, in two scenarios, every controller
on the same seeded disturbances:

1. ``odom``: ``--motor-lag 0.15 --latency 0.04 --drop 0.05``, 4096-tick encoders, the
   follower fed by the wheel odometry;
2. ``truth``: the same, and the real wheels 0.0357 and 0.0343 m, separation 0.139 m, slip
   0.02; the follower fed by the true pose with 1 mm and 0.2 degree noise at 50 Hz.

Controllers: open loop (the plan's commands), diffbot's ``tracking`` (with ``--lead``, by
default the robot's latency plus motor lag plus half a control period, 0.215 s, and without
one) and ``pure-pursuit``, wpimath's ``LTVUnicycleController`` and ``RamseteController``
(robotpy-wpimath, when it is installed; their commands saturated to the motor limit as
diffbot's are, and given the same knowledge of the delay: their feed-forward velocity taken
``--lead`` ahead of their reference pose), and a textbook pure pursuit (fixed lookahead and
the plan's speed, no regulation, stopping at the path's end).

Figures: per scenario and controller, the median and worst final position error, the worst
final heading error, the worst and median RMS cross-track error, the peak share of the motor
limit commanded, and the runs that arrived; then the cost of one ``Follower.command`` call,
without and with the lead.
"""

from __future__ import annotations

import argparse
import math
import random
import statistics
import time
from collections.abc import Callable
from typing import Any

import diffbot
from diffbot.calibration.truth import true_robot
from diffbot.closed_loop import LoopSettings, run
from diffbot.commands.simulate_loop import summary
from diffbot.follow import DWELL, Follower, Gains, delay_lead
from diffbot.kinematics import DiffDriveParams, Pose, Twist
from diffbot.planfile import parse_plan
from diffbot.pursuit import Pursuit
from diffbot.simulation import Disturbances
from diffbot.trajectory import EXAMPLES, Arc, Plan, Segment, Spin, Straight, plan

LAG, LATENCY, DROP = 0.15, 0.04, 0.05
CONTROL_RATE = 20.0


def random_plan(rng: random.Random, params: DiffDriveParams) -> Plan:
    """3 to 6 straights, arcs and spins, forward and reverse, within the motor limit."""
    while True:
        items: list[Segment] = []
        for _ in range(rng.randint(3, 6)):
            kind = rng.random()
            if kind < 0.35:
                items.append(Straight(rng.choice((1.0, 1.0, -1.0)) * rng.uniform(0.2, 1.0)))
            elif kind < 0.8:
                items.append(
                    Arc(
                        rng.uniform(0.15, 0.8),
                        math.radians(rng.uniform(30.0, 180.0)),
                        rng.choice(("cw", "ccw")),
                        reverse=rng.random() < 0.2,
                    )
                )
            else:
                items.append(Spin(rng.choice((1.0, -1.0)) * math.radians(rng.uniform(30, 180))))
        made = plan(items, params, speed=rng.uniform(0.06, 0.12))
        if made.within_limit:
            return made


def _saturated(params: DiffDriveParams, v: float, w: float) -> Twist:
    lim = params.max_wheel_speed
    if lim is None:
        return Twist(v, w)
    left, right = params.radii
    half = 0.5 * params.wheel_separation
    peak = max(abs((v - half * w) / left), abs((v + half * w) / right))
    scale = lim / peak if peak > lim else 1.0
    return Twist(v * scale, w * scale)


class _Timed:
    """A tracker of the timed reference (wpimath's), done as diffbot's follower is: past the
    plan's end and within its tolerances for the dwell."""

    def __init__(
        self, params: DiffDriveParams, made: Plan, law: Callable[..., Any], lead: float
    ) -> None:
        self.params = params
        self.reference = Follower(params, made)
        self.law = law
        self.lead = lead

    def command(self, t: float, pose: Pose) -> Twist:
        from wpimath.geometry import Pose2d

        x, y, heading, v, w = self.reference.reference(t)
        if self.lead:
            v, w = self.reference.reference(t + self.lead)[3:]
        speeds = self.law(Pose2d(pose[0], pose[1], pose[2]), Pose2d(x, y, heading), v, w)
        return _saturated(self.params, speeds.vx, speeds.omega)

    def done(self, t: float, pose: Pose) -> bool:
        return self.reference.done(t, pose)


class _Textbook:
    """Pure pursuit as textbooks give it: a fixed lookahead, the plan's speed, no regulation;
    it stops where the path ends."""

    def __init__(self, params: DiffDriveParams, made: Plan, lookahead: float) -> None:
        base = Follower(params, made).gains
        gains = Gains(base.kx, base.ky, base.ktheta, base.kspin, 1e-9, 1e-9, 0.0)
        self.params = params
        self.pursuit = Pursuit(made, gains, lookahead, 0.005)
        self.since: float | None = None

    def command(self, t: float, pose: Pose) -> Twist:
        if self.pursuit.finished or self.pursuit.update(*pose):
            return Twist(0.0, 0.0)
        return _saturated(self.params, *self.pursuit.command(*pose))

    def done(self, t: float, pose: Pose) -> bool:
        if not self.pursuit.finished:
            return False
        if self.since is None:
            self.since = t
        return t - self.since >= DWELL


def controllers(params: DiffDriveParams, lead: float) -> dict[str, Callable[[Plan], Any]]:
    """The controllers compared: diffbot's tracking law predicts ``lead`` s ahead, wpimath's
    take their feed-forward that far ahead."""
    made: dict[str, Callable[[Plan], Any]] = {
        "open loop": lambda p: None,
        "diffbot tracking": lambda p: Follower(params, p, lead=lead),
        "diffbot tracking, no lead": lambda p: Follower(params, p),
        "diffbot pure-pursuit": lambda p: Follower(params, p, law="pure-pursuit"),
        "textbook pure pursuit": lambda p: _Textbook(params, p, 0.15),
    }
    try:
        from wpimath.controller import LTVUnicycleController, RamseteController
    except ImportError:
        print("robotpy-wpimath is not installed: its controllers are left out")
        return made
    v_max = params.max_wheel_speed * params.wheel_radius
    w_max = 2.0 * v_max / params.wheel_separation

    def ltv(p: Plan) -> _Timed:
        # Bryson's rule at the robot's scale: 2 cm along and across, 0.2 rad, the top speeds
        # (the best of a small grid of tolerances on Trajectories A and B).
        controller = LTVUnicycleController((0.02, 0.02, 0.2), (v_max, w_max), 0.05)
        return _Timed(params, p, controller.calculate, lead)

    def ramsete(p: Plan) -> _Timed:
        # b scaled from its default 2 rad²/m² (for robots of about a metre) toward this robot's
        # size; 2, 20 and 200 end alike.
        controller = RamseteController(20.0, 0.7)
        return _Timed(params, p, controller.calculate, lead)

    made["wpimath LTV unicycle"] = ltv
    made["wpimath Ramsete"] = ramsete
    return made


def scenarios(params: DiffDriveParams) -> dict[str, Callable[[int], LoopSettings]]:
    real = true_robot(params, (0.0357, 0.0343), 0.139)
    return {
        "odom": lambda seed: LoopSettings(
            ticks=4096, seed=seed, disturbances=Disturbances(LAG, LATENCY, DROP, seed=seed)
        ),
        "truth": lambda seed: LoopSettings(
            ticks=4096,
            seed=seed,
            disturbances=Disturbances(LAG, LATENCY, DROP, 0.02, seed=seed),
            true_params=real,
            pose_source="truth",
            pose_noise=(0.001, math.radians(0.2)),
        ),
    }


def figures(
    made: Plan, settings: LoopSettings, controller: Any, params: DiffDriveParams
) -> dict[str, float]:
    """The figures ``simulate --follow --json`` reports for the run, under short names."""
    data = summary(made, run(made, params, settings, controller))
    return {
        "position": data["final_position_error"],
        "heading": data["final_heading_error"],
        "max_cross": data["max_cross_track_error"],
        "rms_cross": data["rms_cross_track_error"],
        "peak": data["peak_limit_fraction"] or 0.0,
        "arrived": float(data["arrived"]),
    }


def command_cost(
    params: DiffDriveParams, law: str, lead: float = 0.0, calls: int = 20_000
) -> float:
    """Seconds per Follower.command call on Trajectory A, poses a few mm off the reference."""
    made = plan(parse_plan(EXAMPLES["A"]), params)
    follower = Follower(params, made, law=law, lead=lead)
    period = made.duration / calls
    poses = []
    for k in range(calls):
        x, y, heading, _, _ = follower.reference(k * period)
        poses.append(Pose(x + 0.003, y - 0.002, heading + 0.01))
    best = math.inf
    for _ in range(5):
        follower = Follower(params, made, law=law, lead=lead)
        start = time.process_time()
        for k, pose in enumerate(poses):
            follower.command(k * period, pose)
        best = min(best, (time.process_time() - start) / calls)
    return best


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--plans", type=int, default=20, help="random plans (default 20)")
    parser.add_argument("--seed", type=int, default=2026, help="seed of the plans and runs")
    default_lead = delay_lead(LATENCY, LAG, CONTROL_RATE)
    parser.add_argument(
        "--lead",
        type=float,
        default=default_lead,
        help="lead of the timed trackers (s; default the latency plus the motor lag plus half "
        f"a control period, {default_lead:g})",
    )
    args = parser.parse_args()
    params = diffbot.load_params()
    rng = random.Random(args.seed)
    plans = [("A", plan(parse_plan(EXAMPLES["A"]), params))]
    plans.append(("B", plan(parse_plan(EXAMPLES["B"]), params)))
    plans += [(f"random {k + 1}", random_plan(rng, params)) for k in range(args.plans)]
    laws = controllers(params, args.lead)
    print(
        f"{len(plans)} plans; lag {LAG} s, latency {LATENCY} s, drop {DROP}, 4096 ticks, 20 Hz; "
        f"lead {args.lead:g} s"
    )
    for scenario, settings_of in scenarios(params).items():
        print(f"\nscenario {scenario}")
        print(
            f"{'controller':<22} {'median mm':>9} {'worst mm':>8} {'worst deg':>9} "
            f"{'max xtrack mm':>13} {'med rms mm':>10} {'peak':>6} {'arrived':>8} "
            f"{'<=1cm,1deg':>10}"
        )
        for name, make in laws.items():
            rows = [
                figures(made, settings_of(args.seed + index), make(made), params)
                for index, (_, made) in enumerate(plans)
            ]
            positions = [r["position"] for r in rows]
            good = sum(r["position"] <= 0.01 and r["heading"] <= math.radians(1.0) for r in rows)
            print(
                f"{name:<22} {statistics.median(positions) * 1e3:9.2f} "
                f"{max(positions) * 1e3:8.2f} "
                f"{math.degrees(max(r['heading'] for r in rows)):9.2f} "
                f"{max(r['max_cross'] for r in rows) * 1e3:13.2f} "
                f"{statistics.median(r['rms_cross'] for r in rows) * 1e3:10.2f} "
                f"{max(r['peak'] for r in rows):6.3f} "
                f"{int(sum(r['arrived'] for r in rows)):>5}/{len(rows):<2} "
                f"{good:>7}/{len(rows):<2}"
            )
    for law, lead in (("tracking", 0.0), ("tracking", args.lead), ("pure-pursuit", 0.0)):
        cost = command_cost(params, law, lead) * 1e6
        print(f"\nFollower.command ({law}, lead {lead:g} s): {cost:.1f} us a call")


if __name__ == "__main__":
    main()
