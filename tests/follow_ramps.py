"""Ramped plans followed on a perfect simulated robot, shared by the follower's test modules:
each law must bring such a robot to the plan's end within its tolerances, whatever limits the
plan was ramped with."""

from __future__ import annotations

import math

from hypothesis import strategies as st
from robots import BOT_50_RPM

from diffbot.closed_loop import LoopSettings, run
from diffbot.follow import DEFAULT_XY_TOLERANCE, DEFAULT_YAW_TOLERANCE, Follower, delay_lead
from diffbot.planfile import parse_plan
from diffbot.profiles import Limits, PathLimits
from diffbot.ramps import ramp
from diffbot.trajectory import plan

ROBOT = BOT_50_RPM
NO_LIMITS = PathLimits()


def ramped(text: str, linear: PathLimits, angular: PathLimits = NO_LIMITS):
    return ramp(plan(parse_plan(text), ROBOT), Limits(linear=linear, angular=angular))


def followed(made, law: str) -> tuple[bool, float, float]:
    """Whether the follower said done, and the true pose's distance (m) and heading error (rad)
    from the plan's end, on an undisturbed robot at the defaults of ``simulate --follow``."""
    settings = LoopSettings()
    lead = delay_lead(0.0, 0.0, settings.control_rate) if law == "tracking" else 0.0
    result = run(made, ROBOT, settings, Follower(ROBOT, made, law=law, lead=lead))
    goal = made.steps.final_pose
    x, y, theta = result.truth[:, -1]
    heading = abs(math.remainder(theta - goal.theta, 2.0 * math.pi))
    return result.arrived, math.hypot(x - goal.x, y - goal.y), heading


def drawn(text: str, linear: PathLimits, angular: PathLimits):
    """The ramped plan of drawn limits; a plan drawn with none gets a linear jerk of 1e-3 m/s³
    (a ramp is what is tested)."""
    if linear.acceleration is None and linear.jerk is None and angular.acceleration is None:
        linear = linear._replace(jerk=1e-3)
    return ramped(text, linear, angular)


def known_arrives(known: tuple[str, str, PathLimits, PathLimits]) -> bool:
    """Whether one of :data:`KNOWN` ends within the tolerances, said done."""
    text, law, linear, angular = known
    return within(followed(ramped(text, linear, angular), law))


def within(outcome: tuple[bool, float, float]) -> bool:
    arrived, distance, heading = outcome
    return arrived and distance <= DEFAULT_XY_TOLERANCE and heading <= DEFAULT_YAW_TOLERANCE


#: The commands that swung out of control, as (plan, law, linear, angular limits).
KNOWN = [
    ("straight 1", "tracking", PathLimits(jerk=0.001), PathLimits()),
    ("straight 1", "pure-pursuit", PathLimits(jerk=0.001), PathLimits()),
    ("spin 90", "pure-pursuit", PathLimits(), PathLimits(acceleration=0.1)),
    ("straight 1; spin -180", "pure-pursuit", PathLimits(), PathLimits(acceleration=0.1)),
    ("ccw 0.3 90", "pure-pursuit", PathLimits(), PathLimits(acceleration=0.01)),
    ("ccw 0.3 90", "tracking", PathLimits(), PathLimits(acceleration=0.01)),
    ("straight 1; ccw 0.3 90; spin -180", "tracking", PathLimits(jerk=1e-9), PathLimits()),
]

_pieces = st.one_of(
    st.floats(0.05, 0.5).map(lambda d: f"straight {d:.3f}"),
    st.floats(-0.4, -0.05).map(lambda d: f"reverse straight {-d:.3f}"),
    st.tuples(st.floats(0.15, 0.5), st.floats(20.0, 180.0)).map(
        lambda ra: f"ccw {ra[0]:.3f} {ra[1]:.1f}"
    ),
    st.floats(-180.0, 180.0).filter(lambda a: abs(a) >= 5.0).map(lambda a: f"spin {a:.1f}"),
)
#: Short plans: one to three straights, arcs and spins.
PLANS = st.lists(_pieces, min_size=1, max_size=3).map("; ".join)
_rate = st.one_of(st.none(), st.floats(0.01, 2.0), st.sampled_from([0.002, 0.005]))
#: Linear limits: acceleration (m/s²) and jerk (m/s³), either may be tiny or absent.
LINEAR = st.tuples(
    _rate, st.one_of(st.none(), st.floats(1e-4, 5.0), st.sampled_from([1e-4, 1e-3]))
).map(lambda aj: PathLimits(None, aj[0], aj[1]))
#: Angular limits: acceleration (rad/s²).
ANGULAR = st.one_of(st.none(), st.floats(0.01, 3.0)).map(lambda a: PathLimits(None, a, None))
