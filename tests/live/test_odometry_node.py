"""The odometry node on a live graph: joint states of a simulated plan in, the plan's exact
final pose out, stamped from the joint states; bad samples counted, never read as zero."""

from __future__ import annotations

import math
import random
import subprocess
import sys
import time
from pathlib import Path

import pytest
from live_graph import PATIENCE, ServiceClient, deep, live_process, spare_domain, until
from robots import BOT, bundled_controllers

from diffbot.controller_config import ControllerConfig
from diffbot.kinematics import forward
from diffbot.live import types
from diffbot.live.messages import stamp_ns, time_of, yaw_of
from diffbot.live.odometry import OdometryNode, OdometrySettings
from diffbot.live.transport import LiveError, Node
from diffbot.numbers import MAX_COORDINATE, MAX_RECORDED_ANGLE
from diffbot.planfile import parse_plan
from diffbot.simulation import simulate
from diffbot.trajectory import plan

#: An arbitrary wall-clock start (ns): stamps are ROS times since the epoch.
T0 = 1_700_000_000 * 10**9
#: The probe reads after the fact: it keeps every message.
DEEP = deep()


class Probe:
    """A test's own node: publishes joint states, collects odometry and /tf."""

    def __init__(self, node: Node) -> None:
        self.odometry: list[types.Odometry] = []
        self.tf: list[types.TFMessage] = []
        self.joint_states = node.create_publisher(types.JointState, "joint_states")
        node.create_subscription(types.Odometry, "odom", self.odometry.append, DEEP)
        node.create_subscription(types.TFMessage, "/tf", self.tf.append, DEEP)
        self.node = node

    def until(self, condition: object) -> None:
        end = time.monotonic() + PATIENCE
        while not condition() and time.monotonic() < end:  # type: ignore[operator]
            self.node.spin_once(0.02)
        assert condition(), "nothing arrived in time"  # type: ignore[operator]


def joint_state(names: list[str], positions: list[float], ns: int) -> types.JointState:
    return types.JointState(header=types.Header(time_of(ns), ""), name=names, position=positions)


def test_the_node_reproduces_a_plans_final_pose() -> None:
    p = plan(parse_plan("straight 0.3 3s; ccw 0.25 90 4s; spin -45 1s"), BOT)
    states = simulate(p, BOT, rate=50.0, extra_joints=("caster_joint",))
    names = list(states.names)
    with OdometryNode(BOT, OdometrySettings()) as node, Node("probe") as probe_node:
        probe = Probe(probe_node)
        assert probe.joint_states.wait_for_subscribers(PATIENCE)
        probe.until(lambda: node.odom_publisher.subscription_count >= 1)
        n = states.times.size
        for k in range(n):
            ns = T0 + round(states.times[k] * 1e9)
            probe.joint_states.publish(joint_state(names, states.positions[:, k].tolist(), ns))
            # The node spins here, taking each joint state as it comes: its queue never fills
            # (and drops), however busy the machine.
            node.spin_once()
        until(
            (node, probe_node),
            lambda: node.odometry.samples == n and len(probe.odometry) == n and len(probe.tf) == n,
        )
    last = probe.odometry[-1]
    assert stamp_ns(last.header.stamp) == T0 + round(states.times[-1] * 1e9)
    assert (last.header.frame_id, last.child_frame_id) == ("odom", "base_link")
    pose = last.pose.pose
    assert pose.position.z == 0.0
    expected = p.final_pose
    assert pose.position.x == pytest.approx(expected.x, abs=1e-9)
    assert pose.position.y == pytest.approx(expected.y, abs=1e-9)
    assert math.remainder(yaw_of(pose.orientation) - expected.theta, math.tau) == pytest.approx(
        0.0, abs=1e-9
    )
    moved = probe.tf[-1].transforms[0]
    assert (moved.header.frame_id, moved.child_frame_id) == ("odom", "base_link")
    assert moved.transform.translation.x == pose.position.x
    assert last.pose.covariance[0] == 0.001
    assert last.pose.covariance[35] == 0.01
    assert node.counts == {"received": n, "used": n, "published": n}


def velocity_state(
    names: list[str], velocities: list[float], ns: int, positions: list[float] | None = None
) -> types.JointState:
    """A joint state of wheel velocities, with no positions unless given (a driver that
    reports velocities only)."""
    return types.JointState(
        header=types.Header(time_of(ns), ""),
        name=names,
        position=positions or [],
        velocity=velocities,
    )


def test_velocity_feedback_integrates_the_wheels_velocities_over_each_step() -> None:
    # Wheel velocities held for 2 s at 50 Hz: the robot drives one exact arc, whatever the
    # positions say (here: none, then frozen at zero, as a driver without encoders sends).
    names = ["front_left_wheel_joint", "front_right_wheel_joint"]
    left, right = 2.0, 3.0
    steps = 100
    settings = OdometrySettings(feedback="velocity")
    with OdometryNode(BOT, settings) as node, Node("probe") as probe_node:
        probe = Probe(probe_node)
        assert probe.joint_states.wait_for_subscribers(PATIENCE)
        probe.until(lambda: node.odom_publisher.subscription_count >= 1)
        for k in range(steps + 1):
            frozen = [0.0, 0.0] if k % 2 else None
            probe.joint_states.publish(
                velocity_state(names, [left, right], T0 + k * 20_000_000, frozen)
            )
            node.spin_once()
        until((node, probe_node), lambda: len(probe.odometry) == steps + 1)
    twist = forward(BOT, left, right)
    turn = twist.angular * 2.0
    radius = twist.linear / twist.angular
    pose = probe.odometry[-1].pose.pose
    assert pose.position.x == pytest.approx(radius * math.sin(turn), abs=1e-12)
    assert pose.position.y == pytest.approx(radius * (1.0 - math.cos(turn)), abs=1e-12)
    assert yaw_of(pose.orientation) == pytest.approx(turn, abs=1e-12)
    moving = probe.odometry[-1].twist.twist
    assert moving.linear.x == pytest.approx(twist.linear, abs=1e-12)
    assert moving.angular.z == pytest.approx(twist.angular, abs=1e-12)
    # The first joint state only starts the clock.
    assert probe.odometry[0].pose.pose.position.x == 0.0
    assert node.counts == {"received": steps + 1, "used": steps + 1, "published": steps + 1}


def test_velocity_feedback_skips_and_counts_what_it_cannot_use() -> None:
    names = ["front_left_wheel_joint", "front_right_wheel_joint"]
    node = OdometryNode(BOT, OdometrySettings(feedback="velocity"))
    with node:
        for message in (
            velocity_state(names, [1.0, 1.0], T0),
            velocity_state(names, [], T0 + 10**8, [5.0, 5.0]),  # positions only
            velocity_state(names, [1.0], T0 + 2 * 10**8),  # mismatched lengths
            velocity_state(names, [1.0, 1.0, 1.0], T0 + 2 * 10**8),  # and the other way
            velocity_state(names, [2e4, 1.0], T0 + 3 * 10**8),  # beyond any wheel's speed
            velocity_state(names, [math.inf, 1.0], T0 + 3 * 10**8),
            # An angle beyond any wheel's, as a velocity it is only fast: used.
            velocity_state(names, [1.0, 1.0], T0 + 5 * 10**8, [1e300, 1e300]),
        ):
            node.on_joint_state(message)
    assert node.counts == {
        "received": 0,
        "used": 2,
        "published": 2,
        "no velocities": 1,
        "mismatched lengths": 2,
        "out of range": 1,
        "not finite": 1,
    }
    # Moved 0.5 s at 1 rad/s on both wheels: the whole gap since the first sample.
    assert node.odometry.pose.x == pytest.approx(0.5 * BOT.wheel_radius, abs=1e-15)
    assert node.status().endswith(
        "skipped: 1 no velocities, 1 out of range, 1 not finite, 2 mismatched lengths"
    )


def test_a_negative_stamp_is_skipped_and_does_not_start_the_clock() -> None:
    # A first joint state stamped in 1901 would start the velocity clock there: the next good
    # one would then hold its velocity over 124 years.
    names = ["front_left_wheel_joint", "front_right_wheel_joint"]
    node = OdometryNode(BOT, OdometrySettings(feedback="velocity"))
    with node:
        for message in (
            velocity_state(names, [1e4, 1e4], -(2**31) * 10**9),
            velocity_state(names, [1.0, 1.0], T0),
            velocity_state(names, [1.0, 1.0], -1),  # a nanosecond before 1970, mid-stream
            velocity_state(names, [1.0, 1.0], T0 + 10**8),
        ):
            node.on_joint_state(message)
    assert node.counts == {"received": 0, "used": 2, "published": 2, "bad stamp": 2}
    assert node.odometry.pose.x == pytest.approx(0.1 * BOT.wheel_radius, abs=1e-15)


def test_the_controller_s_position_feedback_chooses_what_is_read() -> None:
    def settings(position_feedback: bool | None, **given: str) -> OdometrySettings:
        controller = ControllerConfig(
            name="c", source="c.yaml", ros_version=2, position_feedback=position_feedback
        )
        return OdometrySettings().with_controller(controller, **given)

    assert settings(False).feedback == "velocity"
    assert settings(True).feedback == "position"
    assert settings(None).feedback == "position"
    assert settings(False, feedback="position").feedback == "position"
    assert settings(True, feedback="velocity").feedback == "velocity"
    with pytest.raises(LiveError, match=r"^feedback must be 'position' or 'velocity', got 'x'$"):
        OdometryNode(BOT, OdometrySettings(feedback="x"))


VELOCITY_CONTROLLERS = bundled_controllers("position_feedback: false")


@pytest.mark.parametrize("given", ["option", "controllers file"])
def test_node_odom_reads_velocities_when_told_or_when_its_controller_does(
    given: str, tmp_path: Path
) -> None:
    topic = "odom"
    if given == "option":
        args = ["--feedback", "velocity"]
    else:
        controllers = tmp_path / "controllers.yaml"
        controllers.write_text(VELOCITY_CONTROLLERS)
        args = ["--controllers", str(controllers)]
        topic = "/diffbot_base_controller/odom"  # the controller's ~/odom
    names = ["front_left_wheel_joint", "front_right_wheel_joint"]
    stamps: list[tuple[int, float]] = []

    def keep(message: types.Odometry) -> None:
        stamps.append((stamp_ns(message.header.stamp), message.pose.pose.position.x))

    with live_process("node", "odom", "--no-tf", *args), Node("probe") as probe:
        states = probe.create_publisher(types.JointState, "joint_states")
        probe.create_subscription(types.Odometry, topic, keep, DEEP)
        assert states.wait_for_subscribers(PATIENCE)
        # Positions that never move beside velocities that do: only velocities move the robot.
        # Each state is sent until the node has answered it (the reader is best effort).
        for k in range(2):
            stamp = T0 + k * 10**9
            message = velocity_state(names, [4.0, 4.0], stamp, [0.0, 0.0])
            end = time.monotonic() + PATIENCE
            while not any(s == stamp for s, _ in stamps) and time.monotonic() < end:
                states.publish(message)
                probe.spin_once(0.1)
    # The second state's velocity held over the second since the first: 4 rad/s x 0.035 m.
    assert dict(stamps) == {T0: 0.0, T0 + 10**9: pytest.approx(0.14, abs=1e-12)}


def test_node_odom_says_when_its_controller_integrates_commands_instead(tmp_path: Path) -> None:
    controllers = tmp_path / "controllers.yaml"
    controllers.write_text(VELOCITY_CONTROLLERS + "    open_loop: true\n")
    args = ["node", "odom", "--controllers", str(controllers), "--duration", "0.2"]
    done = subprocess.run(
        [sys.executable, "-m", "diffbot", *args],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    assert done.returncode == 0, done.stderr
    assert done.stderr.startswith(
        f"warning: {controllers}: diffbot_base_controller computes its odometry from its "
        "commands (open_loop: true); this node integrates the wheels' feedback from the joint "
        "states: --open-loop integrates the commands as the controller does\n"
    ), done.stderr


def test_bad_samples_are_skipped_and_counted() -> None:
    names = ["front_left_wheel_joint", "front_right_wheel_joint"]
    with OdometryNode(BOT).start() as node, Node("probe") as probe_node:
        probe = Probe(probe_node)
        assert probe.joint_states.wait_for_subscribers(PATIENCE)
        sent = [
            joint_state(names, [0.0, 0.0], T0),
            joint_state(names, [1.0, 1.0], T0 + 10**9),
            joint_state(names, [math.nan, 2.0], T0 + 2 * 10**9),  # not finite
            joint_state(["caster"], [5.0], T0 + 3 * 10**9),  # missing joint
            joint_state(names, [9.0, 9.0], T0),  # back in time
            joint_state(names, [1.0], T0 + 4 * 10**9),  # mismatched lengths
            joint_state(names, [1.0, 1.0, 1.0], T0 + 4 * 10**9),  # and the other way
            joint_state(names, [1e300, 1.0], T0 + 4 * 10**9),  # past any recorded angle
            joint_state(names, [3.0, 3.0], time.time_ns() + 3600 * 10**9),  # an hour ahead
            joint_state(names, [2.0, 2.0], T0 + 5 * 10**9),
        ]
        for message in sent:
            probe.joint_states.publish(message)
            time.sleep(0.002)
        probe.until(lambda: node.counts["received"] == len(sent))
    assert node.counts == {
        "received": 10,
        "used": 3,
        "published": 3,
        "not finite": 1,
        "out of range": 1,
        "stamped in the future": 1,
        "missing joint": 1,
        "stamp not after previous": 1,
        "mismatched lengths": 2,
    }
    assert node.status() == (
        "10 joint states, 3 used, 3 published; skipped: 1 not finite, 1 out of range, "
        "1 stamped in the future, 1 missing joint, 1 stamp not after previous, "
        "2 mismatched lengths"
    )
    # Two radians of each wheel forward: 2 r = 0.07 m, never a jump back to 0 or to 9 rad, and
    # the sample an hour ahead did not stop the later one.
    assert node.odometry.pose.x == pytest.approx(2 * BOT.wheel_radius, abs=1e-12)


def test_the_controller_configuration_sets_frames_rate_and_covariance() -> None:
    controller = ControllerConfig(
        name="diff_cont",
        source="c.yaml",
        ros_version=2,
        odom_frame_id="odom_wheels",
        base_frame_id="base_footprint",
        publish_rate=20.0,
        enable_odom_tf=False,
        pose_covariance_diagonal=(1, 2, 3, 4, 5, 6),
        twist_covariance_diagonal=(6, 5, 4, 3, 2, 1),
        velocity_rolling_window_size=4,
    )
    settings = OdometrySettings().with_controller(controller, publish_rate=10.0)
    assert settings.frame_id == "odom_wheels"
    assert settings.child_frame_id == "base_footprint"
    assert settings.publish_rate == 10.0  # the option wins
    assert not settings.publish_tf
    assert settings.pose_covariance == (1, 2, 3, 4, 5, 6)
    assert settings.twist_covariance == (6, 5, 4, 3, 2, 1)
    assert settings.window == 4
    assert OdometrySettings().with_controller(None) == OdometrySettings()


def test_what_the_controller_file_leaves_out_is_the_controller_s_default() -> None:
    # diff_drive_controller_parameter.yaml: odom and base_link behind the namespace's prefix,
    # zero covariances, a rolling window of 10; publish_rate stays per joint state.
    controller = ControllerConfig(
        name="diff_cont", source="c.yaml", ros_version=2, namespace="a200_0000"
    )
    settings = OdometrySettings().with_controller(controller)
    assert settings.odom_topic == "/a200_0000/diff_cont/odom"  # its ~/odom
    assert (settings.frame_id, settings.child_frame_id) == ("a200_0000/odom", "a200_0000/base_link")
    assert settings.pose_covariance == settings.twist_covariance == (0.0,) * 6
    assert (settings.window, settings.publish_rate, settings.publish_tf) == (10, None, True)
    # The options the user typed are taken as typed, without the prefix.
    typed = OdometrySettings().with_controller(
        controller, frame_id="odom", window=1, odom_topic="odom_check"
    )
    assert typed.odom_topic == "odom_check"
    assert (typed.frame_id, typed.child_frame_id, typed.window) == (
        "odom",
        "a200_0000/base_link",
        1,
    )
    with OdometryNode(BOT, settings) as node:
        assert node.describe().endswith("; frames a200_0000/odom -> a200_0000/base_link")
        assert "publishes /a200_0000/diff_cont/odom (nav_msgs/msg/Odometry)" in node.describe()
    # Without a controller the node keeps its own defaults.
    alone = OdometrySettings()
    assert (alone.frame_id, alone.window) == ("odom", 1)
    assert alone.pose_covariance != (0.0,) * 6


@pytest.mark.parametrize(
    ("settings", "message"),
    [
        (OdometrySettings(frame_id=""), "^frame_id '' is empty$"),
        (OdometrySettings(child_frame_id=""), "^child_frame_id '' is empty$"),
        (OdometrySettings(publish_rate=0.0), "^publish_rate must be a finite number >= 1e-06"),
    ],
)
def test_bad_settings_are_refused_naming_the_setting(
    settings: OdometrySettings, message: str
) -> None:
    with pytest.raises(LiveError, match=message):
        OdometryNode(BOT, settings)


def test_the_node_joins_the_domain_it_is_given() -> None:
    with OdometryNode(BOT, domain=spare_domain(2)) as node:
        assert node.participant.domain_id == spare_domain(2)


def test_the_publish_rate_thins_by_stamps() -> None:
    names = ["front_left_wheel_joint", "front_right_wheel_joint"]
    with OdometryNode(BOT, OdometrySettings(publish_rate=10.0, publish_tf=False)) as node:
        assert node.tf_publisher is None
        for k in range(101):  # 1 s at 100 Hz
            node.on_joint_state(joint_state(names, [0.01 * k, 0.01 * k], T0 + k * 10**7))
    assert node.odometry.samples == 101
    assert node.published == 11  # every 0.1 s of stamps, the first included


def test_the_publish_rate_holds_its_cadence_over_jittered_stamps() -> None:
    # 50 Hz joint states whose stamps wander by up to 1 ms, as a driver's do, and a 25 Hz
    # publish_rate: the controller publishes once per 40 ms period on average (its last publish
    # time advances by the period), never once per three joint states when a stamp comes early.
    names = ["front_left_wheel_joint", "front_right_wheel_joint"]
    jitter = random.Random(7)
    with OdometryNode(BOT, OdometrySettings(publish_rate=25.0, publish_tf=False)) as node:
        for k in range(501):  # 10 s
            stamp = T0 + k * 20_000_000 + jitter.randint(-1_000_000, 1_000_000)
            node.on_joint_state(joint_state(names, [0.01 * k, 0.01 * k], stamp))
    assert node.odometry.samples == 501
    assert 249 <= node.published <= 251


def test_joint_states_of_another_type_are_named_once() -> None:
    warnings: list[str] = []
    with OdometryNode(BOT, OdometrySettings()) as node, Node("probe") as probe:
        node.warn = warnings.append
        node.start()
        # A publisher of another type on the topic never matches the node's reader.
        other = probe.create_publisher(types.String, "joint_states")
        for _ in range(3):
            other.publish(types.String("not a joint state"))
        end = time.monotonic() + PATIENCE
        while not warnings and time.monotonic() < end:
            time.sleep(0.05)
        time.sleep(1.5)  # another check comes and goes: still one warning
    assert warnings == [
        "'/joint_states' carries std_msgs/msg/String; this node reads sensor_msgs/msg/JointState"
    ]
    assert node.subscription.received == 0


def published_odometry(node: OdometryNode) -> list[types.Odometry]:
    """Route the node's odometry messages into a list, decoded, instead of onto the graph."""
    sent: list[types.Odometry] = []
    node.odom_publisher.publish_serialized = lambda data: sent.append(  # type: ignore[method-assign]
        types.Odometry.deserialize(data)
    )
    return sent


def test_the_twist_and_both_covariances_are_published_where_ros_reads_them() -> None:
    names = ["front_left_wheel_joint", "front_right_wheel_joint"]
    pose_diagonal = (1.0, 2.0, 3.0, 4.0, 5.0, 6.0)
    twist_diagonal = (0.1, 0.2, 0.3, 0.4, 0.5, 0.6)
    settings = OdometrySettings(
        publish_tf=False, pose_covariance=pose_diagonal, twist_covariance=twist_diagonal
    )
    with OdometryNode(BOT, settings) as node:
        sent = published_odometry(node)
        node.on_joint_state(joint_state(names, [0.0, 0.0], T0))
        # 0.1 s later the left wheel turned 1 rad and the right one 2 rad.
        node.on_joint_state(joint_state(names, [1.0, 2.0], T0 + 10**8))
    assert len(sent) == 2
    twist = sent[-1].twist.twist
    r, b, dt = 0.035, 0.135, 0.1
    assert twist.linear.x == pytest.approx(r * (1.0 + 2.0) / 2 / dt, abs=1e-12)  # 0.525 m/s
    assert twist.angular.z == pytest.approx(r * (2.0 - 1.0) / b / dt, abs=1e-12)  # 2.59 rad/s
    assert (twist.linear.y, twist.linear.z) == (0.0, 0.0)
    assert (twist.angular.x, twist.angular.y) == (0.0, 0.0)
    # 6x6 row-major: variance k of (x, y, z, about x, about y, about z) at 7 k, zero elsewhere.
    for diagonal, covariance in (
        (pose_diagonal, sent[-1].pose.covariance),
        (twist_diagonal, sent[-1].twist.covariance),
    ):
        assert len(covariance) == 36
        expected = [0.0] * 36
        for k, variance in enumerate(diagonal):
            expected[7 * k] = variance
        assert list(covariance) == expected
    # The pose the same step gives: along the arc of radius v / w, turned w dt.
    v, w = r * 1.5 / dt, r / b / dt
    pose = sent[-1].pose.pose
    assert pose.position.x == pytest.approx(v / w * math.sin(w * dt), abs=1e-12)
    assert pose.position.y == pytest.approx(v / w * (1 - math.cos(w * dt)), abs=1e-12)
    assert yaw_of(pose.orientation) == pytest.approx(w * dt, abs=1e-12)
    assert (pose.orientation.x, pose.orientation.y) == (0.0, 0.0)
    assert pose.orientation.z == pytest.approx(math.sin(w * dt / 2), abs=1e-12)
    assert pose.orientation.w == pytest.approx(math.cos(w * dt / 2), abs=1e-12)
    assert stamp_ns(sent[-1].header.stamp) == T0 + 10**8
    assert (sent[-1].header.frame_id, sent[-1].child_frame_id) == ("odom", "base_link")


def test_a_spin_publishes_a_yaw_rate_and_no_linear_speed() -> None:
    names = ["front_left_wheel_joint", "front_right_wheel_joint"]
    with OdometryNode(BOT, OdometrySettings(publish_tf=False)) as node:
        sent = published_odometry(node)
        node.on_joint_state(joint_state(names, [0.0, 0.0], T0))
        node.on_joint_state(joint_state(names, [0.5, -0.5], T0 + 2 * 10**8))
    twist = sent[-1].twist.twist
    assert twist.linear.x == pytest.approx(0.0, abs=1e-15)
    assert twist.angular.z == pytest.approx(-0.035 * 1.0 / 0.135 / 0.2, abs=1e-12)
    assert (twist.angular.x, twist.angular.y) == (0.0, 0.0)
    assert list(sent[-1].twist.covariance) == [
        0.001 if k in (0, 7, 14, 21, 28) else 0.01 if k == 35 else 0.0 for k in range(36)
    ]


# --------------------------------------------------------------------------------------------
# The odometry services, called as `ros2 service call` would (rmw_cyclonedds' wire format)


def test_set_odometry_reproduces_the_controllers_service_test() -> None:
    # ros2_controllers' test of ~/set_odometry (control_msgs/srv/SetOdometry): after moving,
    # set x 5, y -2, yaw 1.57079632679; the odometry is there (1e-6, 1e-5 rad), and moving on
    # (both wheels forward) increases y from -2.
    names = ["front_left_wheel_joint", "front_right_wheel_joint"]
    with OdometryNode(BOT).start() as node, Node("probe") as probe_node:
        probe = Probe(probe_node)
        assert node.set_service == "/diffbot_odometry/set_odometry"
        client = ServiceClient(
            node.set_service, types.SetOdometryRequest, types.SetOdometryResponse, guid=0xD1FFB07
        )
        reset = ServiceClient(
            node.reset_service, types.EmptyRequest, types.EmptyResponse, guid=0xD1FFB08
        )
        try:
            client.wait_for_service()
            reset.wait_for_service()
            assert probe.joint_states.wait_for_subscribers(PATIENCE)
            probe.joint_states.publish(joint_state(names, [0.0, 0.0], T0))
            probe.joint_states.publish(joint_state(names, [1.0, 1.0], T0 + 10**8))
            probe.until(lambda: node.odometry.samples == 2)
            assert node.odometry.pose.x > 0.0
            reply = client.call(types.SetOdometryRequest(x=5.0, y=-2.0, yaw=1.57079632679))
            assert reply.success is True  # type: ignore[attr-defined]
            assert reply.message == "Odometry set request accepted"  # type: ignore[attr-defined]
            assert (reply.guid, reply.seq) == (0xD1FFB07, 1)  # type: ignore[attr-defined]
            pose = node.odometry.pose
            assert pose.x == pytest.approx(5.0, abs=1e-6)
            assert pose.y == pytest.approx(-2.0, abs=1e-6)
            assert pose.theta == pytest.approx(1.57079632679, abs=1e-5)
            probe.joint_states.publish(joint_state(names, [1.1, 1.1], T0 + 2 * 10**8))
            probe.until(lambda: node.odometry.samples == 3)
            # From the set pose by the wheels' motion since (0.1 rad x 0.035 m), heading +y.
            assert node.odometry.pose.y == pytest.approx(-2.0 + 0.0035, abs=1e-9)
            assert node.odometry.pose.x == pytest.approx(5.0, abs=1e-9)
            refused = client.call(types.SetOdometryRequest(x=math.nan))
            assert refused.success is False  # type: ignore[attr-defined]
            assert "finite" in refused.message  # type: ignore[attr-defined]
            assert node.odometry.pose.y == pytest.approx(-2.0 + 0.0035, abs=1e-9)
            reset.call(types.EmptyRequest())
            assert tuple(node.odometry.pose) == (0.0, 0.0, 0.0)
            assert node.calls == {node.set_service: 2, node.reset_service: 1}
            reset.call(types.EmptyRequest())
            assert node.calls == {node.set_service: 2, node.reset_service: 2}
        finally:
            client.close()
            reset.close()


def test_the_services_are_under_the_controllers_name() -> None:
    controller = ControllerConfig(name="diffbot_base_controller", source="c.yaml", ros_version=2)
    settings = OdometrySettings().with_controller(controller)
    with OdometryNode(BOT, settings) as node:
        assert node.set_service == "/diffbot_base_controller/set_odometry"
        assert node.reset_service == "/diffbot_base_controller/reset_odometry"


def test_odd_service_names_keep_their_letters_and_a_bad_set_is_refused_in_words() -> None:
    # Only slashes are trimmed from the name the services go under.
    with OdometryNode(BOT, OdometrySettings(services="/Xodom/")) as node:
        assert node.set_service == "/Xodom/set_odometry"
        assert node.reset_service == "/Xodom/reset_odometry"
        reply = node.on_set(types.SetOdometryRequest(x=math.nan))
        far = node.on_set(types.SetOdometryRequest(y=-1e308))
        spun = node.on_set(types.SetOdometryRequest(yaw=2e12))
        edge = node.on_set(types.SetOdometryRequest(x=-MAX_COORDINATE, yaw=MAX_RECORDED_ANGLE))
        pose = node.odometry.pose
    assert reply.success is False
    bounds = "x, y and yaw must be finite numbers within 1e+09 m and 1e+12 rad"
    assert reply.message == f"{bounds} (not finite)"
    # A pose beyond the bound of poses taken from any message is refused as they are.
    assert (far.success, far.message) == (False, f"{bounds} (out of range)")
    assert (spun.success, spun.message) == (False, f"{bounds} (out of range)")
    assert edge.success is True
    assert (pose.x, pose.y) == (-MAX_COORDINATE, 0.0)


def test_the_node_s_odometry_takes_its_frames_covariances_and_window() -> None:
    from cyclonedds.qos import Policy

    from diffbot.ros.messages import covariance_matrix

    settings = OdometrySettings(
        frame_id="odom_wheels",
        child_frame_id="base_footprint",
        pose_covariance=(1e-3, 2e-3, 3e-3, 4e-3, 5e-3, 6e-3),
        twist_covariance=(7e-3, 8e-3, 9e-3, 1e-2, 2e-2, 3e-2),
        window=3,
    )
    with OdometryNode(BOT, settings) as node:
        assert node.settings is settings
        odometry = node.odometry
        assert (odometry.frame_id, odometry.child_frame_id) == ("odom_wheels", "base_footprint")
        assert odometry.pose_covariance == covariance_matrix(settings.pose_covariance)
        assert odometry.twist_covariance == covariance_matrix(settings.twist_covariance)
        assert odometry.velocity_rolling_window_size == 3
        # /tf as tf2_ros' broadcaster keeps it: the last 100.
        assert node.tf_publisher is not None
        qos = node.tf_publisher._writer.get_qos()  # type: ignore[no-untyped-call]
        assert qos[Policy.History] == Policy.History.KeepLast(100)


def test_the_published_orientation_keeps_w_positive_past_half_a_turn() -> None:
    # A spin of 4 rad (past pi): wheels turned -theta and +theta with theta = 4 b / (2 r).
    names = ["front_left_wheel_joint", "front_right_wheel_joint"]
    theta = 4.0 * BOT.wheel_separation / (2.0 * BOT.wheel_radius)
    with OdometryNode(BOT, OdometrySettings(publish_tf=False)) as node:
        sent = published_odometry(node)
        node.on_joint_state(joint_state(names, [0.0, 0.0], T0))
        for k in range(1, 9):
            node.on_joint_state(joint_state(names, [-theta * k / 8, theta * k / 8], T0 + k * 10**8))
    q = sent[-1].pose.pose.orientation
    # The rotation by 4 rad about z, written with w >= 0: by 4 - 2 pi.
    half = 0.5 * (4.0 - 2.0 * math.pi)
    assert [q.x, q.y, q.z, q.w] == pytest.approx(
        [0.0, 0.0, math.sin(half), math.cos(half)], abs=1e-9
    )
    assert q.w > 0.0
