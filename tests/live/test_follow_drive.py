"""Following a plan live: poses relative to the first one, refused at the wire, zero on a stale
pose and when none comes; and the whole loop, where ``drive --follow`` arrives on a robot that
lags, delays and drops its commands and the open-loop ``drive`` does not.

Where the loop test's bound comes from: the follower says done once its pose (the odometry) has
stayed within its tolerances (:data:`DEFAULT_XY_TOLERANCE`, :data:`DEFAULT_YAW_TOLERANCE`) for a
second, and then commands zero; the odometry integrates exact encoder angles (no ticks, no slip),
so it agrees with the ground truth to far under a millimetre. What can move the robot after that
is the last command before the zero, held for the robot's timeout if the zero is dropped: a
command that had kept the robot within the tolerances for a second, at crawl speed. So the true
pose ends within twice the tolerances.

The open loop is the same plan on the same robot with the same seed: the robot draws its drops
per command message in order, and with :data:`SEED` the plan's two final zeros are lost (the
simulation of the same run, :func:`diffbot.closed_loop.run` open loop, says so too), so the robot
spins on for its timeout, tens of degrees beyond the bound.
"""

from __future__ import annotations

import math
import os
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Callable
from dataclasses import replace

import pytest
from live_graph import PATIENCE, deep, spare_domain, until

from diffbot.closed_loop import LoopSettings, run
from diffbot.follow import DEFAULT_XY_TOLERANCE, DEFAULT_YAW_TOLERANCE, Follower
from diffbot.live import types
from diffbot.live.follow_drive import FollowDriver, FollowSettings
from diffbot.live.messages import odometry, stamp_ns, time_of, yaw_of, yaw_quaternion
from diffbot.live.odometry import OdometryNode
from diffbot.live.robot import RobotNode, RobotSettings
from diffbot.live.transport import LiveError, Node
from diffbot.planfile import parse_plan
from diffbot.simulation import Disturbances
from diffbot.trajectory import plan
from diffbot.urdf import load_params

PLAN = "straight 0.2 2s; spin 90 2s"
RATE = 20.0
ROBOT_RATE = 50.0
DISTURBANCES = {"motor_lag": 0.15, "latency": 0.04, "drop": 0.2}
ZERO = [0.0] * 36
#: A seed whose drops take both final zeros of the open-loop plan at 20 Hz.
SEED = 7
#: The motors of the robot the live loop drives: weaker than its description says (20 of 50
#: rpm, rad/s), so the plan's straight (27 rpm) saturates them whatever the drops: open loop
#: ends a fixed distance short, whichever commands a busy machine's timing lets the seed drop.
WEAK_MOTORS = 20.0 * math.tau / 60.0


def pose_stamped(x: float, y: float, heading: float) -> types.PoseStamped:
    return types.PoseStamped(
        types.Header(time_of(time.time_ns()), "map"),
        types.Pose(types.Point(x, y, 0.0), yaw_quaternion(heading)),
    )


@pytest.mark.parametrize(
    ("field", "value", "bounds"),
    [
        ("overtime", -1.0, ">= 0 and <= 1e+06 s"),
        ("overtime", 2e6, ">= 0 and <= 1e+06 s"),
        ("overtime", math.nan, ">= 0 and <= 1e+06 s"),
        ("pose_timeout", 0.0, "> 0 and <= 1e+06 s"),
        ("rate", 0.0, ">= 1e-06 and <= 10000 Hz"),
    ],
)
def test_settings_out_of_range_are_refused(field: str, value: float, bounds: str) -> None:
    with pytest.raises(LiveError) as caught:
        FollowSettings(**{field: value})  # type: ignore[arg-type]
    assert str(caught.value) == f"{field} must be a finite number {bounds}, got {value!r}"
    assert FollowSettings(overtime=1e6).overtime == 1e6


def test_a_frame_id_or_pose_kind_that_cannot_be_is_refused_naming_the_setting() -> None:
    with pytest.raises(LiveError) as caught:
        FollowSettings(frame_id="base\tlink")
    assert str(caught.value) == "frame_id 'base\\tlink' holds a control character"
    with pytest.raises(LiveError) as caught:
        FollowSettings(pose_kind="twist")  # type: ignore[arg-type]
    assert str(caught.value) == "pose_kind must be odometry, pose or pose-covariance, got 'twist'"


def test_a_pose_read_on_the_command_topic_is_refused() -> None:
    params = load_params()
    follower = Follower(params, plan(parse_plan("straight 0.1 1s"), params))
    settings = FollowSettings(pose_topic="/cmd_vel")
    with pytest.raises(LiveError) as caught:
        FollowDriver(follower, settings)
    assert str(caught.value) == (
        "the pose topic and the command topic are both /cmd_vel: each needs a topic of its own"
    )


def test_poses_are_taken_from_the_first_and_bad_ones_refused() -> None:
    params = load_params()
    follower = Follower(params, plan(parse_plan("straight 0.1 1s"), params))
    with FollowDriver(follower, FollowSettings(pose_kind="pose")) as driver:
        first = pose_stamped(1.0, 2.0, math.pi / 2)
        driver.on_pose(first.header, first.pose)
        assert driver.pose is not None
        assert (driver.pose.x, driver.pose.y, driver.pose.theta) == (0.0, 0.0, 0.0)
        # 0.1 m along the first pose's heading (+y) and a quarter turn more: ahead, turned.
        ahead = pose_stamped(1.0, 2.1, math.pi)
        driver.on_pose(ahead.header, ahead.pose)
        assert driver.pose.x == pytest.approx(0.1, abs=1e-12)
        assert driver.pose.y == pytest.approx(0.0, abs=1e-12)
        assert driver.pose.theta == pytest.approx(math.pi / 2, abs=1e-12)
        # 0.1 m towards -x is to the left of a robot first heading +y.
        left = pose_stamped(0.9, 2.0, math.pi / 2)
        driver.on_pose(left.header, left.pose)
        assert driver.pose.x == pytest.approx(0.0, abs=1e-12)
        assert driver.pose.y == pytest.approx(0.1, abs=1e-12)
        assert driver.pose.theta == pytest.approx(0.0, abs=1e-12)
        driver.on_pose(ahead.header, ahead.pose)
        bad = pose_stamped(math.nan, 0.0, 0.0)
        driver.on_pose(bad.header, bad.pose)
        zero = types.Pose(types.Point(0.0, 0.0, 0.0), types.Quaternion(0.0, 0.0, 0.0, 0.0))
        driver.on_pose(bad.header, zero)
        assert driver.refusals.total == 2
        assert driver.pose.x == pytest.approx(0.1, abs=1e-12)  # the refused ones changed nothing
        (subscription,) = driver._subscriptions
        subscription.deliver([b"\x00\x01\x00\x00"])  # a truncated payload
        assert driver.status() == "2 poses refused, 1 malformed"


def commands_seen(probe: Node) -> list[types.Twist]:
    seen: list[types.Twist] = []
    probe.create_subscription(types.Twist, "cmd_vel", seen.append, deep())
    return seen


def test_no_pose_means_nothing_commanded() -> None:
    params = load_params()
    follower = Follower(params, plan(parse_plan("straight 0.1 1s"), params))
    with Node("probe") as probe, FollowDriver(follower, FollowSettings()) as driver:
        seen = commands_seen(probe)
        end = time.monotonic() + PATIENCE
        while driver.command_count == 0 and time.monotonic() < end:
            probe.spin_once(0.02)
        assert driver.command_count == 1
        assert not driver.wait_until_ready(0.5)
        probe.spin_once(0.2)
    assert seen == []


def test_a_pose_without_a_command_subscriber_is_not_ready() -> None:
    params = load_params()
    follower = Follower(params, plan(parse_plan("straight 0.1 1s"), params))
    domain = spare_domain(2)
    with FollowDriver(follower, FollowSettings(pose_kind="pose"), domain=domain) as driver:
        assert driver.name == "diffbot_follow"
        assert driver.participant.domain_id == domain
        first = pose_stamped(0.0, 0.0, 0.0)
        driver.on_pose(first.header, first.pose)
        assert driver.command_count == 0
        assert not driver.wait_until_ready(0.3)


def test_never_a_pose_is_stale_to_the_end_and_reported_from_the_start() -> None:
    params = load_params()
    follower = Follower(params, plan(parse_plan("straight 0.1 0.2s"), params))
    settings = FollowSettings(overtime=0.0)
    with Node("probe") as probe, FollowDriver(follower, settings) as driver:
        seen = commands_seen(probe)
        until(probe, lambda: driver.command_count == 1)
        report = driver.follow()
        until(probe, lambda: len(seen) == report.sent + 1)
    assert report.sent == report.stale > 0
    assert report.completed
    assert not report.arrived
    # Measured from the plan's start, where the robot was never seen to leave.
    assert report.position_error == pytest.approx(0.1, abs=1e-12)
    assert report.heading_error == 0.0
    assert {(c.linear.x, c.angular.z) for c in seen} == {(0.0, 0.0)}


def test_a_signal_in_the_run_ends_it_with_a_report_and_zero() -> None:
    from diffbot.live.signals import caught, deferred

    params = load_params()
    follower = Follower(params, plan(parse_plan("straight 1 20s"), params))
    settings = FollowSettings(pose_kind="pose", pose_timeout=30.0)
    with (
        Node("probe") as probe,
        FollowDriver(follower, settings) as driver,
        deferred(deliver=False),
    ):
        seen = commands_seen(probe)
        until(probe, lambda: driver.command_count == 1)
        first = pose_stamped(0.0, 0.0, 0.0)
        driver.on_pose(first.header, first.pose)
        threading.Timer(0.3, os.kill, (os.getpid(), signal.SIGINT)).start()
        report = driver.follow()
        assert caught() == signal.SIGINT
        until(probe, lambda: len(seen) == report.sent + 1)
    assert not report.completed
    assert 0 < report.sent < 20 * 20
    assert report.duration < PATIENCE
    assert (seen[-1].linear.x, seen[-1].angular.z) == (0.0, 0.0)


def test_a_robot_at_the_plan_s_end_arrives_and_stamped_commands_carry_the_frame() -> None:
    # The second pose puts the robot at the plan's end, a quarter circle of 0.2 m to the left:
    # past the plan, once it has stayed there for the follower's dwell, it has arrived, and the
    # run ends long before its time cap.
    params = load_params()
    follower = Follower(params, plan(parse_plan("ccw 0.2 90 0.3s"), params))
    settings = FollowSettings(
        pose_kind="pose", pose_timeout=30.0, stamped=True, frame_id="base_footprint"
    )
    seen: list[types.TwistStamped] = []
    with Node("localization") as node, FollowDriver(follower, settings) as driver:
        node.create_subscription(types.TwistStamped, "cmd_vel", seen.append, deep())
        poses = node.create_publisher(types.PoseStamped, "odom")
        assert poses.wait_for_subscribers(PATIENCE)
        poses.publish(pose_stamped(0.0, 0.0, 0.0))  # the origin
        assert driver.wait_until_ready(PATIENCE)
        poses.publish(pose_stamped(0.2, 0.2, math.pi / 2))
        end = time.monotonic() + PATIENCE
        while (driver.pose is None or driver.pose.x == 0.0) and time.monotonic() < end:
            driver.spin_once(0.02)
        poses.publish(pose_stamped(math.nan, 0.0, 0.0))  # refused, counted in the report
        while driver.refusals.total == 0 and time.monotonic() < end:
            driver.spin_once(0.02)
        before = time.time_ns()
        report = driver.follow()
        after = time.time_ns()
        while len(seen) < report.sent + 1 and time.monotonic() < end:
            node.spin_once(0.02)
    assert report.arrived
    assert report.completed
    assert report.refused == 1
    assert report.duration < driver.cap
    assert report.position_error == pytest.approx(0.0, abs=1e-9)
    assert report.heading_error == pytest.approx(0.0, abs=1e-9)
    assert len(seen) == report.sent + 1
    assert {c.header.frame_id for c in seen} == {"base_footprint"}
    stamps = [stamp_ns(c.header.stamp) for c in seen]
    assert stamps == sorted(stamps)
    assert before <= stamps[0]
    assert stamps[-1] <= after
    assert (seen[-1].twist.linear.x, seen[-1].twist.angular.z) == (0.0, 0.0)


def test_a_signal_caught_before_the_run_leaves_only_the_stop() -> None:
    from diffbot.live.signals import deferred

    params = load_params()
    follower = Follower(params, plan(parse_plan("straight 0.1 1s"), params))
    with FollowDriver(follower, FollowSettings()) as driver, deferred(deliver=False):
        signal.raise_signal(signal.SIGINT)
        report = driver.follow()
    assert (report.sent, report.stale, report.duration) == (0, 0, 0.0)
    assert not report.completed
    assert not report.arrived


class StopsCounted(Follower):
    """A follower with a lead that counts the stops it is told of."""

    stops = 0

    def stopped_at(self, t: float) -> None:
        self.stops += 1
        super().stopped_at(t)


def test_a_stale_pose_commands_zero_until_the_end() -> None:
    params = load_params()
    follower = StopsCounted(params, plan(parse_plan("straight 0.1 0.5s"), params), lead=0.2)
    settings = FollowSettings(pose_kind="pose", pose_timeout=0.1, overtime=0.5)
    with (
        Node("probe") as probe,
        FollowDriver(follower, settings) as driver,
    ):
        seen = commands_seen(probe)
        poses = probe.create_publisher(types.PoseStamped, "odom")
        assert poses.wait_for_subscribers(PATIENCE)
        poses.publish(pose_stamped(0.0, 0.0, 0.0))
        assert driver.wait_until_ready(PATIENCE)
        time.sleep(0.2)  # the one pose is stale from the start
        report = driver.follow()
        end = time.monotonic() + PATIENCE
        while len(seen) < report.sent + 1 and time.monotonic() < end:
            probe.spin_once(0.02)
    assert report.completed
    assert not report.arrived
    assert report.sent == report.stale >= 15  # 0.5 s plan + 0.5 s overtime at 20 Hz
    assert len(seen) == report.sent + 1
    assert all(t.linear.x == 0.0 and t.angular.z == 0.0 for t in seen)
    assert follower.stops == report.stale  # its prediction counts every zero sent


class Truth:
    """The test's node: the robot's last true pose."""

    def __init__(self, node: Node) -> None:
        self.last: types.Odometry | None = None
        self.node = node
        node.create_subscription(types.Odometry, "ground_truth/odom", self._take)

    def _take(self, message: types.Odometry) -> None:
        self.last = message

    def until(self, condition: Callable[[], bool]) -> None:
        end = time.monotonic() + PATIENCE
        while not condition() and time.monotonic() < end:
            self.node.spin_once(0.02)
        assert condition(), "the graph did not get there in time"

    def at_rest(self) -> tuple[float, float]:
        """The true pose's distance (m) and heading error (rad) from the plan's end, once the
        robot stopped (its reported twist zero, stamped after now)."""
        now = time.time_ns()

        def still() -> bool:
            last = self.last
            return (
                last is not None
                and stamp_ns(last.header.stamp) > now
                and abs(last.twist.twist.linear.x) < 1e-6
                and abs(last.twist.twist.angular.z) < 1e-6
            )

        self.until(still)
        assert self.last is not None
        goal = plan(parse_plan(PLAN), load_params()).final_pose
        pose = self.last.pose.pose
        return (
            math.hypot(pose.position.x - goal.x, pose.position.y - goal.y),
            abs(math.remainder(yaw_of(pose.orientation) - goal.theta, math.tau)),
        )


def drive_on_a_disturbed_robot(*extra: str) -> tuple[float, float, str]:
    """Run ``drive PLAN EXTRA`` as a process against a fresh disturbed robot and odometry in
    this process; the true end's errors and the drive's stderr."""
    params = load_params()
    settings = RobotSettings(
        rate=ROBOT_RATE,
        cmd_vel="cmd_vel",
        disturbances=Disturbances(**DISTURBANCES, seed=SEED),
    )
    weak = replace(params, max_wheel_speed=WEAK_MOTORS)
    with (
        Node("truth") as node,
        RobotNode(weak, None, settings).start() as robot,
        OdometryNode(params).start(),
    ):
        truth = Truth(node)
        truth.until(lambda: truth.last is not None)
        driven = subprocess.run(
            [
                sys.executable,
                "-m",
                "diffbot",
                "drive",
                PLAN,
                "--rate",
                str(RATE),
                "--wait",
                str(PATIENCE),
                *extra,
            ],
            capture_output=True,
            text=True,
            env=os.environ.copy(),
            timeout=180,
            check=False,
        )
        assert driven.returncode == 0, driven.stderr
        distance, heading = truth.at_rest()
        assert robot.refused == 0
    return distance, heading, driven.stderr


def test_the_seed_drops_the_open_loop_stop() -> None:
    # The offline run of the same robot, commands and seed: the lost stop spins it on.
    params = load_params()
    made = plan(parse_plan(PLAN), params)
    settings = LoopSettings(
        rate=ROBOT_RATE,
        control_rate=RATE,
        disturbances=Disturbances(**DISTURBANCES, seed=SEED),
    )
    result = run(made, params, settings)
    heading = abs(math.remainder(float(result.truth[2, -1]) - made.final_pose.theta, math.tau))
    assert heading > math.radians(20.0)


def test_followed_live_the_robot_arrives_and_open_loop_it_does_not() -> None:
    xy_bound, yaw_bound = 2.0 * DEFAULT_XY_TOLERANCE, 2.0 * DEFAULT_YAW_TOLERANCE
    distance, heading, said = drive_on_a_disturbed_robot("--follow")
    assert said.startswith("followed plan (tracking) at 20 Hz: arrived after "), said
    assert distance <= xy_bound, (distance, said)
    assert heading <= yaw_bound, (math.degrees(heading), said)
    distance, heading, said = drive_on_a_disturbed_robot()
    assert said.startswith("drove plan: 81 commands"), said
    # The straight at 20 of 27 rpm: about 5 cm short.
    assert distance > 3.0 * xy_bound, (distance, math.degrees(heading))


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM, signal.SIGHUP])
def test_a_signal_stops_a_followed_drive_with_zero(signum: int) -> None:
    last: list[tuple[float, float]] = []
    with Node("odometry") as probe:
        poses = probe.create_publisher(types.Odometry, "odom")
        probe.create_subscription(
            types.Twist, "cmd_vel", lambda m: last.append((m.linear.x, m.angular.z)), deep()
        )
        probe.create_timer(
            0.05,
            lambda: poses.publish(
                odometry((0.0, 0.0, 0.0, 0.0, 0.0), time.time_ns(), "odom", "base_link", ZERO, ZERO)
            ),
        )
        probe.start()
        process = subprocess.Popen(
            [
                sys.executable,
                "-m",
                "diffbot",
                "drive",
                "straight 1 20s",
                "--follow",
                "--wait",
                str(PATIENCE),
            ],
            stderr=subprocess.PIPE,
            text=True,
            env=os.environ.copy(),
        )
        try:
            end = time.monotonic() + 3 * PATIENCE
            while not any(v > 0.0 for v, _ in last) and time.monotonic() < end:
                time.sleep(0.01)
            assert any(v > 0.0 for v, _ in last), "no command came"
            process.send_signal(signum)
            _, err = process.communicate(timeout=PATIENCE)
        finally:
            process.kill()
        end = time.monotonic() + PATIENCE
        while last[-1] != (0.0, 0.0) and time.monotonic() < end:
            time.sleep(0.01)
    assert process.returncode == 128 + signum, err
    assert "stopped after" in err, err
    assert "commanded zero" in err, err
    assert "Traceback" not in err
    assert last[-1] == (0.0, 0.0)


@pytest.mark.parametrize(
    ("kind", "message"),
    [
        ("pose", lambda: pose_stamped(0.3, 0.0, 0.0)),
        (
            "pose-covariance",
            lambda: types.PoseWithCovarianceStamped(
                pose_stamped(0.3, 0.0, 0.0).header,
                types.PoseWithCovariance(pose_stamped(0.3, 0.0, 0.0).pose, ZERO),
            ),
        ),
        (
            "odometry",
            lambda: odometry(
                (0.3, 0.0, 0.0, 0.0, 0.0), time.time_ns(), "odom", "base_link", ZERO, ZERO
            ),
        ),
    ],
)
def test_the_pose_s_type_is_the_one_its_publisher_sends(
    kind: str, message: Callable[[], object]
) -> None:
    # No type given: the driver subscribes by what the pose topic's publisher sends.
    params = load_params()
    follower = Follower(params, plan(parse_plan("straight 0.1 1s"), params))
    with (
        Node("localization") as node,
        FollowDriver(follower, FollowSettings(pose_kind=None)) as driver,
    ):
        sample = message()
        poses = node.create_publisher(type(sample), "odom")
        assert driver.pose_kind is None
        end = time.monotonic() + PATIENCE
        while driver.pose is None and time.monotonic() < end:
            poses.publish(message())
            driver.wait_until_ready(0.05)
        assert driver.pose_kind == kind
        assert driver.pose is not None
        assert (driver.pose.x, driver.pose.y) == (0.0, 0.0)  # the first pose is the origin


@pytest.mark.parametrize("law", ["tracking", "pure-pursuit"])
def test_progress_is_the_distance_from_the_reference_or_the_goal(law: str) -> None:
    # The robot stays where the first pose put it, 0.1 m left of the plan's start: the error
    # shown is its distance from the timed reference (tracking), or from the goal (pure
    # pursuit, a quarter circle of 0.2 m to the left: 0.2 m ahead and 0.2 m left), at each
    # command.
    params = load_params()
    follower = Follower(params, plan(parse_plan("ccw 0.2 90 0.5s"), params), law=law)
    settings = FollowSettings(pose_kind="pose", pose_timeout=30.0, overtime=0.0, stamped=True)
    seen: list[tuple[float, float]] = []
    commanded: list[types.TwistStamped] = []
    with Node("localization") as node, FollowDriver(follower, settings) as driver:
        node.create_subscription(types.TwistStamped, "cmd_vel", commanded.append, deep())
        poses = node.create_publisher(types.PoseStamped, "odom")
        assert poses.wait_for_subscribers(PATIENCE)
        until(node, lambda: driver.command_count == 1)
        poses.publish(pose_stamped(0.0, 0.0, 0.0))  # the origin
        end = time.monotonic() + PATIENCE
        while driver.pose is None and time.monotonic() < end:
            driver.spin_once(0.02)
        poses.publish(pose_stamped(0.05, 0.1, 0.0))
        while (driver.pose is None or driver.pose.y == 0.0) and time.monotonic() < end:
            driver.spin_once(0.02)
        report = driver.follow(lambda t, error: seen.append((t, error)))
        until(node, lambda: len(commanded) == report.sent + 1)
    assert len(seen) >= 5
    for t, error in seen:
        if law == "tracking":
            x, y = follower.reference(t)[:2]
        else:
            x, y = 0.2, 0.2
        assert error == pytest.approx(math.hypot(x - 0.05, y - 0.1), abs=1e-12)
    if law == "tracking":
        assert seen[-1][1] > seen[0][1] + 0.05  # the reference drives on, away from it
    # The k-th command goes out at k / rate, never early.
    period = 1.0 / settings.rate
    assert all(t >= k * period - 1e-9 for k, (t, _) in enumerate(seen))
    assert len(seen) <= driver.cap / period + 1
    # The robot never moved: its report is its distance and heading from the plan's end.
    assert not report.arrived
    assert report.completed
    assert report.position_error == pytest.approx(math.hypot(0.15, 0.1), abs=1e-12)
    assert report.heading_error == pytest.approx(math.pi / 2, abs=1e-12)
    assert any(c.twist.linear.x > 0.0 for c in commanded)  # stamped commands carry the twist
    assert (commanded[-1].twist.linear.x, commanded[-1].twist.angular.z) == (0.0, 0.0)
