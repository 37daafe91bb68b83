"""Odometry benchmarks: streaming and batch speed against the seed and C, and exactness.

Run by hand: ``python benchmarks/bench_odometry.py [--messages N] [--samples N] [--rounds N]
[--cpu]``.

(a) Streaming, per JointState message (fresh name strings each, as rclpy delivers them), like
    for like against the seed's callback written the seed's way (a loop over the names of every
    message, Euler integration on the old heading with NumPy scalar ``np.cos``/``np.sin``):
    (i) the pose update alone: ``Odometry.update_joint_state`` against the callback's arithmetic
    without its message; (ii) the full per-message work: ``update_joint_state`` + ``message()``
    against the whole callback, which fills in a new nav_msgs/Odometry (as plain objects).
    Stated aim: ours at most 1/2 of the seed's time, in both (i) and (ii).
(b) Batch: ``integrate`` over 10 million samples, against a plain C loop doing the same
    arithmetic, compiled at run time with ``cc -O2`` and called in-process through ctypes
    (skipped when there is no compiler). Like ``integrate``, the C side writes into new output
    arrays each round. Goal: within 2x of C.
(c) Exactness: the seed's Trajectory A sampled at 10 Hz, with exact arcs and with Euler's rule.

The compared sides of (a) and (b) take turns round by round (the order reversed every other
round), so a busy spell of the machine hits them alike; ratios are medians of the per-round
ratios, with their interquartile range and extremes.
"""

from __future__ import annotations

import argparse
import array
import ctypes
import importlib.metadata
import math
import os
import shutil
import subprocess
import sys
import tempfile
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from interleave import CPU_HELP, Ratio, interleave, timed

from diffbot.kinematics import DiffDriveParams
from diffbot.odometry import Odometry, integrate
from diffbot.trajectory import Arc, Straight, plan, wheel_positions

PARAMS = DiffDriveParams(wheel_radius=0.035, wheel_separation=0.135)
NAMES = ("caster_rotation_joint", "caster_wheel_joint", PARAMS.left_joint, PARAMS.right_joint)
AIM = "stated aim"
STREAMING_AIM = 0.5
GOAL = "goal"
BATCH_GOAL = 2.0


def print_ratio(label: str, ratio: Ratio, goal: str, bound: float, indent: str) -> None:
    """Print a ratio as the median of per-round ratios, then the goal it is held to and whether
    that median keeps it."""
    kept = "kept" if ratio.median <= bound else "not kept"
    print(f"{indent}ratio {label}, median of per-round ratios: {ratio.describe(3)}")
    print(f"{indent}  {goal}: {label} <= {bound:g}; {kept} by the median {ratio.median:.3f}")


# --------------------------------------------------------------------------------------------
# (a) the seed's callback, as the class material wrote it


class _Msg:
    """Stands for a received ROS message: attribute containers, nothing more."""

    def __init__(self, **fields: object) -> None:
        self.__dict__.update(fields)


# nav_msgs/msg/Odometry as plain Python objects: the fields, nesting and defaults of the rclpy
# message (covariances as lists of 36 zeros, cheaper than rclpy's NumPy arrays), without rclpy's
# type checks in the setters, so the seed's message costs no more than its shape demands.


class Time:
    __slots__ = ("nanosec", "sec")

    def __init__(self) -> None:
        self.sec = 0
        self.nanosec = 0


class Header:
    __slots__ = ("frame_id", "stamp")

    def __init__(self) -> None:
        self.stamp = Time()
        self.frame_id = ""


class Point:
    __slots__ = ("x", "y", "z")

    def __init__(self) -> None:
        self.x = 0.0
        self.y = 0.0
        self.z = 0.0


class Quaternion:
    __slots__ = ("w", "x", "y", "z")

    def __init__(self) -> None:
        self.x = 0.0
        self.y = 0.0
        self.z = 0.0
        self.w = 1.0


class Pose:
    __slots__ = ("orientation", "position")

    def __init__(self) -> None:
        self.position = Point()
        self.orientation = Quaternion()


class PoseWithCovariance:
    __slots__ = ("covariance", "pose")

    def __init__(self) -> None:
        self.pose = Pose()
        self.covariance = [0.0] * 36


class Twist:
    __slots__ = ("angular", "linear")

    def __init__(self) -> None:
        self.linear = Point()
        self.angular = Point()


class TwistWithCovariance:
    __slots__ = ("covariance", "twist")

    def __init__(self) -> None:
        self.twist = Twist()
        self.covariance = [0.0] * 36


class OdometryMsg:
    __slots__ = ("child_frame_id", "header", "pose", "twist")

    def __init__(self) -> None:
        self.header = Header()
        self.child_frame_id = ""
        self.pose = PoseWithCovariance()
        self.twist = TwistWithCovariance()


class SeedOdometry:
    """Exercise 9's node without ROS: the same statements, the same flaws."""

    def __init__(self) -> None:
        self.wheel_sep = 0.135
        self.wheel_r = 0.07 / 2
        self.left_wheel_name = "front_left_wheel_joint"
        self.right_wheel_name = "front_right_wheel_joint"
        self.lwheel_ang_old = 0.0
        self.rwheel_ang_old = 0.0
        self.x_k = 0.0
        self.y_k = 0.0
        self.w_k = 0.0
        self.published: object = None

    def sub_callback(self, msg: _Msg) -> None:
        """The whole callback: the pose update, then a new Odometry message filled in."""
        lwheel_ang, rwheel_ang = 0.0, 0.0
        for name, position in zip(msg.name, msg.position):  # type: ignore[attr-defined]  # noqa: B905
            if name == self.left_wheel_name:
                lwheel_ang = position
            if name == self.right_wheel_name:
                rwheel_ang = position

        dl_k = (lwheel_ang - self.lwheel_ang_old) * self.wheel_r
        dr_k = (rwheel_ang - self.rwheel_ang_old) * self.wheel_r

        dA_k = (dr_k + dl_k) / 2  # noqa: N806 - the seed's names
        Dw_k = (dr_k - dl_k) / self.wheel_sep  # noqa: N806

        x_k_new = self.x_k + dA_k * np.cos(self.w_k)
        y_k_new = self.y_k + dA_k * np.sin(self.w_k)
        w_k_new = self.w_k + Dw_k

        odom_msg = OdometryMsg()
        odom_msg.pose.pose.position.x = x_k_new
        odom_msg.pose.pose.position.y = y_k_new

        odom_msg.pose.pose.orientation.x = 0.0
        odom_msg.pose.pose.orientation.y = 0.0
        odom_msg.pose.pose.orientation.z = np.sin(w_k_new / 2)
        odom_msg.pose.pose.orientation.w = np.cos(w_k_new / 2)
        self.published = odom_msg

        self.lwheel_ang_old = lwheel_ang
        self.rwheel_ang_old = rwheel_ang
        self.x_k = x_k_new
        self.y_k = y_k_new
        self.w_k = w_k_new

    def pose_update(self, msg: _Msg) -> None:
        """The callback's arithmetic alone: the same statements, no message built."""
        lwheel_ang, rwheel_ang = 0.0, 0.0
        for name, position in zip(msg.name, msg.position):  # type: ignore[attr-defined]  # noqa: B905
            if name == self.left_wheel_name:
                lwheel_ang = position
            if name == self.right_wheel_name:
                rwheel_ang = position

        dl_k = (lwheel_ang - self.lwheel_ang_old) * self.wheel_r
        dr_k = (rwheel_ang - self.rwheel_ang_old) * self.wheel_r

        dA_k = (dr_k + dl_k) / 2  # noqa: N806 - the seed's names
        Dw_k = (dr_k - dl_k) / self.wheel_sep  # noqa: N806

        x_k_new = self.x_k + dA_k * np.cos(self.w_k)
        y_k_new = self.y_k + dA_k * np.sin(self.w_k)
        w_k_new = self.w_k + Dw_k

        self.lwheel_ang_old = lwheel_ang
        self.rwheel_ang_old = rwheel_ang
        self.x_k = x_k_new
        self.y_k = y_k_new
        self.w_k = w_k_new


def joint_state_messages(n: int) -> list[tuple[list[str], array.array[float], float]]:
    """JointState fields as rclpy delivers them: a new list of new name strings (decoded from
    the wire, so equal names are never the same object) and a float64 array per message."""
    rng = np.random.default_rng(7)
    left = np.cumsum(rng.normal(0.06, 0.02, n)).tolist()
    right = np.cumsum(rng.normal(0.06, 0.02, n)).tolist()
    wire = [name.encode() for name in NAMES]
    return [
        (
            [raw.decode() for raw in wire],
            array.array("d", [0.0, 0.0, left[k], right[k]]),
            0.02 * k,
        )
        for k in range(n)
    ]


def bench_streaming(n: int, rounds: int, cpu: bool) -> None:
    messages = joint_state_messages(n)
    assert messages[0][0][2] is not messages[1][0][2]  # fresh strings, no identity shortcut
    seed_msgs = [_Msg(name=names, position=positions) for names, positions, _ in messages]

    def seed_pose() -> None:
        node = SeedOdometry()
        for msg in seed_msgs:
            node.pose_update(msg)

    def seed_full() -> None:
        node = SeedOdometry()
        for msg in seed_msgs:
            node.sub_callback(msg)

    def ours_update() -> None:
        odom = Odometry(PARAMS)
        for names, positions, stamp in messages:
            odom.update_joint_state(names, positions, stamp)

    def ours_with_message() -> None:
        odom = Odometry(PARAMS)
        for names, positions, stamp in messages:
            odom.update_joint_state(names, positions, stamp)
            odom.message()

    # Each pair runs back to back within a round, so its ratio compares neighbouring moments.
    timings = interleave(
        {
            "seed pose": timed(seed_pose, cpu=cpu),
            "ours update": timed(ours_update, cpu=cpu),
            "seed full": timed(seed_full, cpu=cpu),
            "ours message": timed(ours_with_message, cpu=cpu),
        },
        rounds,
    )

    def us(side: str) -> float:
        return timings.median(side) / n * 1e6

    print(
        f"(a) streaming, {n} JointState messages of {len(NAMES)} joints, fresh name strings "
        f"each; {rounds} rounds (median us/message)"
    )
    print("    (i) pose update only")
    print(
        f"        seed callback's arithmetic (name loop, Euler, np.cos/np.sin): "
        f"{us('seed pose'):7.3f}"
    )
    print(
        f"        Odometry.update_joint_state:                                  "
        f"{us('ours update'):7.3f}"
    )
    print_ratio("ours/seed", timings.ratio("ours update", "seed pose"), AIM, STREAMING_AIM, " " * 8)
    print("    (ii) full per-message work: pose update and a nav_msgs/Odometry built")
    print(
        f"        seed callback, Odometry() filled in the seed's way:           "
        f"{us('seed full'):7.3f}"
    )
    print(
        f"        Odometry.update_joint_state + message():                      "
        f"{us('ours message'):7.3f}"
    )
    print_ratio(
        "ours/seed", timings.ratio("ours message", "seed full"), AIM, STREAMING_AIM, " " * 8
    )


# --------------------------------------------------------------------------------------------
# (b) batch integration against C

C_SOURCE = r"""
#include <math.h>

/* The same arithmetic as diffbot.integrate: per step the wheel displacements, the half heading
   change, the chord ds*sinc(h) along theta + h, and the heading from the angles since the start. */
void integrate(long n, const double *L, const double *R, double cl, double cr, double b,
               double *X, double *Y, double *T) {
    const double turn = 1.0 / b, half_turn = 0.5 / b;
    double x = 0.0, y = 0.0, th = 0.0;
    X[0] = x; Y[0] = y; T[0] = th;
    for (long i = 1; i < n; i++) {
        double dl = (L[i] - L[i - 1]) * cl, dr = (R[i] - R[i - 1]) * cr;
        double ds = (dl + dr) * 0.5, h = (dr - dl) * half_turn;
        double chord = ds * (h != 0.0 ? sin(h) / h : 1.0);
        double along = th + h;
        x += chord * cos(along);
        y += chord * sin(along);
        th = ((R[i] - R[0]) * cr - (L[i] - L[0]) * cl) * turn;
        X[i] = x; Y[i] = y; T[i] = th;
    }
}
"""

FloatArray = np.ndarray[tuple[int], np.dtype[np.float64]]


def compile_c_loop(folder: Path) -> ctypes.CDLL | str:
    """The C loop built as a shared library in ``folder``, or why it could not be built."""
    compiler = shutil.which(os.environ.get("CC", "cc"))
    if compiler is None:
        return "no C compiler (cc) found"
    source = folder / "odom.c"
    library = folder / "libodom.so"
    source.write_text(C_SOURCE, encoding="utf-8")
    build = subprocess.run(
        [compiler, "-O2", "-shared", "-fPIC", "-o", str(library), str(source), "-lm"],
        capture_output=True,
        text=True,
        check=False,
    )
    if build.returncode != 0:
        return f"compilation failed: {build.stderr.strip()}"
    lib = ctypes.CDLL(str(library))
    array_arg = np.ctypeslib.ndpointer(dtype=np.float64, ndim=1, flags="C_CONTIGUOUS")
    lib.integrate.argtypes = [
        ctypes.c_long,
        array_arg,
        array_arg,
        ctypes.c_double,
        ctypes.c_double,
        ctypes.c_double,
        array_arg,
        array_arg,
        array_arg,
    ]
    lib.integrate.restype = None
    return lib


def bench_batch(n: int, rounds: int, cpu: bool) -> None:
    rng = np.random.default_rng(11)
    left = np.cumsum(rng.normal(0.1, 0.05, n))
    right = np.cumsum(rng.normal(0.1, 0.05, n))
    radius, separation = PARAMS.wheel_radius, PARAMS.wheel_separation
    print(f"(b) batch integration of {n} samples; {rounds} rounds (median ns/sample)")
    with tempfile.TemporaryDirectory() as tmp:
        lib = compile_c_loop(Path(tmp))
        if isinstance(lib, str):
            alone = interleave(
                {"numpy": timed(lambda: integrate(PARAMS, left, right), cpu=cpu)}, rounds
            )
            per_sample = alone.median("numpy") / n * 1e9
            print(
                f"    integrate (NumPy, float64):                                {per_sample:7.2f}"
            )
            print(f"    C reference skipped: {lib}")
            return

        def c_loop(x: FloatArray, y: FloatArray, theta: FloatArray) -> None:
            lib.integrate(n, left, right, radius, radius, separation, x, y, theta)

        def c_new_arrays() -> None:
            # integrate returns new arrays, so the C side pays for fresh memory (page faults) too.
            c_loop(np.empty(n), np.empty(n), np.empty(n))

        x_out, y_out, theta_out = np.empty(n), np.empty(n), np.empty(n)
        timings = interleave(
            {
                "numpy": timed(lambda: integrate(PARAMS, left, right), cpu=cpu),
                "c": timed(c_new_arrays, cpu=cpu),
                "c reused": timed(lambda: c_loop(x_out, y_out, theta_out), cpu=cpu),
            },
            rounds,
        )

    def ns(side: str) -> float:
        return timings.median(side) / n * 1e9

    print(f"    integrate (NumPy, float64), new output arrays:             {ns('numpy'):7.2f}")
    print(f"    plain C loop (cc -O2, libm, ctypes), new output arrays:    {ns('c'):7.2f}")
    print(f"    the same C loop writing into arrays it reuses:              {ns('c reused'):7.2f}")
    print_ratio("NumPy/C", timings.ratio("numpy", "c"), GOAL, BATCH_GOAL, " " * 4)
    reused = timings.ratio("numpy", "c reused").describe(3)
    print(f"    ratio NumPy/C writing into reused arrays (no bound): {reused}")
    series = integrate(PARAMS, left, right)
    gap = max(
        abs(x_out[-1] - series.x[-1]),
        abs(y_out[-1] - series.y[-1]),
        abs(theta_out[-1] - series.theta[-1]),
    )
    print(f"    final poses of NumPy and C differ by {gap:.1e} (m, rad)")


# --------------------------------------------------------------------------------------------
# (c) exactness on Trajectory A


#: The seed's Trajectory A (``EXAMPLES["A"]``: ccw 0.25 180 10s; straight 1 10s; cw 0.25 180 10s;
#: straight 1 10s) as segments, which every layout of the package spells the same way.
TRAJECTORY_A = (
    Arc(0.25, math.pi, "ccw", 10.0),
    Straight(1.0, 10.0),
    Arc(0.25, math.pi, "cw", 10.0),
    Straight(1.0, 10.0),
)


def trajectory_a_wheels(rate: float) -> tuple[np.ndarray, np.ndarray]:
    """Wheel joint angles (rad) of the planned Trajectory A, sampled at ``rate`` Hz."""
    p = plan(TRAJECTORY_A, PARAMS)
    times = np.arange(round(p.duration * rate) + 1) / rate
    return wheel_positions(p, times)


def euler(left: Sequence[float], right: Sequence[float]) -> tuple[float, float]:
    """The seed's rule: each step straight along the heading before it."""
    x = y = theta = 0.0
    r, b = PARAMS.wheel_radius, PARAMS.wheel_separation
    for k in range(1, len(left)):
        dl = (left[k] - left[k - 1]) * r
        dr = (right[k] - right[k - 1]) * r
        x += (dl + dr) / 2 * math.cos(theta)
        y += (dl + dr) / 2 * math.sin(theta)
        theta += (dr - dl) / b
    return x, y


def bench_exactness() -> None:
    print("(c) Trajectory A (ends at x 0, y 1, theta 0): final position error (m)")
    for rate in (10.0, 50.0):
        left, right = trajectory_a_wheels(rate)
        odom = Odometry(PARAMS)
        for k, (lw, rw) in enumerate(zip(left.tolist(), right.tolist(), strict=True)):
            odom.update(lw, rw, k / rate)
        series = integrate(PARAMS, left, right)
        ours = math.hypot(odom.pose.x, odom.pose.y - 1.0)
        batch = math.hypot(series.x[-1], series.y[-1] - 1.0)
        ex, ey = euler(left.tolist(), right.tolist())
        seed = math.hypot(ex, ey - 1.0)
        print(
            f"    {rate:4.0f} Hz: exact arcs {ours:.1e} (batch {batch:.1e}), "
            f"seed's Euler {seed:.1e}"
        )


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        description=__doc__.splitlines()[0],
        epilog="Aims: streaming ours/seed <= 0.5 like for like; batch NumPy/C <= 2.",
    )
    parser.add_argument("--messages", type=int, default=100_000, help="for (a), default 100000")
    parser.add_argument("--samples", type=int, default=10_000_000, help="for (b), default 1e7")
    parser.add_argument("--rounds", type=int, default=15, help="timed rounds, default 15")
    parser.add_argument("--cpu", action="store_true", help=CPU_HELP)
    args = parser.parse_args(argv)
    if args.messages < 2 or args.samples < 2 or args.rounds < 1:
        parser.error("--messages and --samples must be at least 2, --rounds at least 1")
    try:
        version = importlib.metadata.version("diffbot-kinematics")
    except importlib.metadata.PackageNotFoundError:
        version = "(not installed)"
    print(f"Python {sys.version.split()[0]}, NumPy {np.__version__}, diffbot {version}")
    clock = "CPU time of this thread" if args.cpu else "wall time"
    print(f"(a) and (b) time {clock}")
    bench_streaming(args.messages, args.rounds, args.cpu)
    bench_batch(args.samples, args.rounds, args.cpu)
    bench_exactness()
    return 0


if __name__ == "__main__":
    sys.exit(main())
