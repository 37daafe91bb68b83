"""The robot without hardware: commanded wheels turn, the description and its fixed links are
latched for late joiners, the wheels' links move on /tf, silence stops the robot."""

from __future__ import annotations

import itertools
import math
import subprocess
import sys
import time
from dataclasses import replace

import pytest
from live_graph import PATIENCE, deep, spare_domain, timer_periods, until
from robots import BOT, two_wheel_urdf

from diffbot.controller_config import AxisLimits, ControllerConfig
from diffbot.kinematics import DiffDriveParams
from diffbot.live import types
from diffbot.live.messages import commands, yaw_of
from diffbot.live.robot import RobotNode, RobotSettings
from diffbot.live.transport import LATCHED, LiveError, Node, QosProfile
from diffbot.simulation import Disturbances
from diffbot.wheel_commands import LEFT_TOPIC, RIGHT_TOPIC, WheelCommander

TWO = DiffDriveParams(
    wheel_radius=0.05,
    wheel_separation=0.2,
    left_joint="left_wheel_joint",
    right_joint="right_wheel_joint",
)
DEEP = deep()


def stamp(header: types.Header) -> int:
    return header.stamp.sec * 10**9 + header.stamp.nanosec


def test_commanded_wheels_turn_and_silence_stops_them() -> None:
    states: list[types.JointState] = []
    truth: list[types.Odometry] = []
    tf: list[types.TFMessage] = []
    settings = RobotSettings(rate=100.0, timeout=0.3)
    # The robot spins in this thread, before the probe: both commands reach it in one spin, and
    # each update's messages reach the probe before the next check, however busy the machine.
    with RobotNode(TWO, two_wheel_urdf(), settings) as robot, Node("probe") as probe:
        graph = (robot, probe)
        left = probe.create_publisher(types.Float64MultiArray, LEFT_TOPIC)
        right = probe.create_publisher(types.Float64MultiArray, RIGHT_TOPIC)
        probe.create_subscription(types.JointState, "joint_states", states.append)
        probe.create_subscription(types.Odometry, "ground_truth/odom", truth.append)
        probe.create_subscription(types.TFMessage, "/tf", tf.append)
        assert left.wait_for_subscribers(PATIENCE)
        assert right.wait_for_subscribers(PATIENCE)
        # The robot integrates from its last update: the commands come after one, which comes
        # after `since`.
        since = time.monotonic()
        updates = robot.updates
        until(graph, lambda: robot.updates > updates)
        # Opposite wheel speeds: a spin in place at (r / b) * 2 * 2 rad/s = 1 rad/s.
        left.publish(commands([-2.0]))
        right.publish(commands([2.0]))
        until(graph, lambda: robot.timeouts == 1)
        held = time.monotonic() - since  # the commands held for less than this
        stopped = dict(robot.positions)
        at_rest = robot.updates
        until(graph, lambda: robot.updates > at_rest + 5)
        assert robot.positions == stopped  # at rest after the timeout
        # The probe has the last update's joint state, pose and transforms, at rest.
        until(
            graph,
            lambda: (
                bool(states and truth and tf)
                and stamp(truth[-1].header) == stamp(states[-1].header)
                and stamp(tf[-1].transforms[0].header) == stamp(states[-1].header)
            ),
        )
        status = robot.status()
        counts = (robot.updates, robot.timeouts)
    # The two commands counted among the robot's own counts.
    assert status == (
        f"{counts[0]} updates, 2 commands, 0 refused, {counts[1]} timeouts, 0 malformed"
    )
    assert states[-1].name == ["left_wheel_joint", "right_wheel_joint"]
    assert states[-1].header.frame_id == ""  # joint states name no frame, as ros2_control's
    assert (truth[-1].header.frame_id, truth[-1].child_frame_id) == ("odom", "base_link")
    assert truth[-1].pose.pose.position.z == 0.0
    assert states[-1].velocity == [0.0, 0.0]
    assert states[-1].position == [stopped["left_wheel_joint"], stopped["right_wheel_joint"]]
    turned = stopped["right_wheel_joint"]
    back = stopped["left_wheel_joint"]
    # Both commands came in one spin: each side turned over the same updates.
    assert back == -turned
    # Held at least the timeout (0.3 s), at most from before the command to the timeout seen:
    # 2 rad/s for that long.
    assert 2.0 * 0.3 - 1e-9 <= turned <= 2.0 * held
    pose = truth[-1].pose.pose
    # Opposite wheels: the robot turned on the spot.
    assert math.hypot(pose.position.x, pose.position.y) <= 1e-12
    # The heading is exactly r (right - left) / b of the wheel angles the robot integrated.
    assert yaw_of(pose.orientation) == pytest.approx(
        math.remainder(0.05 * (turned - back) / 0.2, math.tau), abs=1e-9
    )
    wheel = next(t for t in tf[-1].transforms if t.child_frame_id == "right_wheel")
    assert wheel.header.frame_id == "base_link"
    # The right wheel turned by `turned` about +y.
    assert 2.0 * math.atan2(wheel.transform.rotation.y, wheel.transform.rotation.w) == (
        pytest.approx(math.remainder(turned, math.tau), abs=1e-9)
    )


def test_late_joiners_get_the_description_and_the_fixed_links() -> None:
    urdf = two_wheel_urdf(
        body='<link name="lidar"/><joint name="lidar_joint" type="fixed">'
        '<parent link="base_link"/><child link="lidar"/>'
        '<origin xyz="0.1 0 0.2" rpy="0 0 1.5707963267948966"/></joint>'
    )
    described: list[str] = []
    static: list[types.TFMessage] = []
    with RobotNode(TWO, urdf, RobotSettings(rate=10.0)), Node("late") as late:
        latched_reader = QosProfile(reliable=True, transient_local=True, depth=1)
        late.create_subscription(
            types.String, "/robot_description", lambda m: described.append(m.data), latched_reader
        )
        late.create_subscription(types.TFMessage, "/tf_static", static.append, latched_reader)
        until(late, lambda: bool(described) and bool(static))
    assert described == [urdf]
    (lidar,) = static[0].transforms
    assert (lidar.header.frame_id, lidar.child_frame_id) == ("base_link", "lidar")
    assert lidar.transform.translation == types.Vector3(0.1, 0.0, 0.2)
    # Turned a quarter turn about z: (0, 0, sin 45 deg, cos 45 deg).
    rotation = lidar.transform.rotation
    assert [rotation.x, rotation.y, rotation.z, rotation.w] == pytest.approx(
        [0.0, 0.0, math.sqrt(0.5), math.sqrt(0.5)], abs=1e-12
    )
    assert LATCHED.transient_local


def test_encoder_ticks_quantise_the_reported_angles() -> None:
    with RobotNode(BOT, None, RobotSettings(ticks=4, noise=0.0)) as robot:
        assert robot._encoder(1.0) == pytest.approx(math.pi / 2)
        assert robot._encoder(0.7) == 0.0
        assert robot.names == ["front_left_wheel_joint", "front_right_wheel_joint"]
        assert robot.name == "diffbot_robot"
        # One update per period of the rate.
        assert timer_periods(robot, robot.update) == [
            pytest.approx(1.0 / RobotSettings().rate, rel=1e-12)
        ]


def encoder_errors(seed: int) -> list[float]:
    """200 readings of an angle of 1 rad by an encoder with 0.01 rad of noise, less the angle."""
    with RobotNode(BOT, None, RobotSettings(noise=0.01, seed=seed)) as robot:
        return [robot._encoder(1.0) - 1.0 for _ in range(200)]


def test_encoder_noise_is_seeded_and_of_its_size() -> None:
    errors = encoder_errors(seed=3)
    assert encoder_errors(seed=3) == errors
    assert encoder_errors(seed=4) != errors
    # Seeded: these are fixed numbers. Gaussian with sigma 0.01: the mean within four standard
    # errors of 0, the spread within four of its own standard errors of 0.01.
    mean = sum(errors) / len(errors)
    spread = math.sqrt(sum((e - mean) ** 2 for e in errors) / (len(errors) - 1))
    assert abs(mean) < 4.0 * 0.01 / math.sqrt(200)
    assert abs(spread - 0.01) < 4.0 * 0.01 / math.sqrt(2 * 200)


def test_a_bad_wheel_command_is_refused_as_zero() -> None:
    with RobotNode(TWO) as robot:
        robot.on_wheels(0, [1.0, 2.0])  # two values for one joint
        robot.on_wheels(1, [math.nan])
        assert robot.refused == 2
        assert robot.velocities == {"left_wheel_joint": 0.0, "right_wheel_joint": 0.0}


@pytest.mark.parametrize("cmd_vel", [None, "cmd_vel"])
def test_undisturbed_wheels_never_turn_faster_than_the_motor_limit(cmd_vel: str | None) -> None:
    # The limit is 10 rad/s: wheel commands of 1000 and -1e4 rad/s, or a twist asking 40 rad/s.
    with RobotNode(LIMITED, None, RobotSettings(cmd_vel=cmd_vel)) as robot:
        assert robot.motors is None
        if cmd_vel is None:
            robot.on_wheels(0, [1000.0])
            robot.on_wheels(1, [-1e4])
        else:
            robot.on_twist(types.Twist(types.Vector3(2.0, 0.0, 0.0)))
        assert max(abs(v) for v in robot.velocities.values()) == pytest.approx(10.0, rel=1e-12)
        assert max(abs(v) for v in robot.velocities.values()) <= 10.0
        time.sleep(0.05)
        before = dict(robot.positions)
        started = time.monotonic()
        robot.update()
        robot.update()
        turned = max(abs(robot.positions[j] - before[j]) for j in before)
        assert turned <= 10.0 * (time.monotonic() - started + 0.1)


def test_a_bad_velocity_command_is_refused_as_a_stop_in_the_robots_domain() -> None:
    settings = RobotSettings(cmd_vel="cmd_vel")
    with RobotNode(TWO, settings=settings, domain=spare_domain(3)) as robot:
        assert robot.participant.domain_id == spare_domain(3)
        robot.on_command((0.1, 0.0))
        assert robot.velocities == {"left_wheel_joint": 2.0, "right_wheel_joint": 2.0}
        robot.on_command((math.nan, 0.0))
        assert robot.refused == 1
        assert robot.velocities == {"left_wheel_joint": 0.0, "right_wheel_joint": 0.0}


@pytest.mark.parametrize("stamped", [False, True])
def test_velocity_commands_read_from_the_wire_turn_the_wheels_as_ik_does(stamped: bool) -> None:
    settings = RobotSettings(rate=50.0, cmd_vel="cmd_vel", stamped=stamped)
    twist = types.Twist(types.Vector3(0.2, 0.0, 0.0), types.Vector3(0.0, 0.0, 1.5))
    message = types.TwistStamped(types.Header(), twist) if stamped else twist
    with RobotNode(TWO, None, settings) as robot:
        robot.subscriptions[0].deliver([message.serialize(), b"\x00\x01\x00\x00"])
        assert robot.subscriptions[0].malformed == 1
        assert robot.status().endswith(", 1 malformed")
        expected = WheelCommander(TWO).step(0.2, 1.5, 1.0 / 50.0)
        assert robot.velocities["left_wheel_joint"] == pytest.approx(expected.left[0], abs=1e-12)
        assert robot.velocities["right_wheel_joint"] == pytest.approx(expected.right[0], abs=1e-12)
        assert robot.velocities["left_wheel_joint"] < robot.velocities["right_wheel_joint"]


def test_a_twist_topic_of_the_other_kind_is_named() -> None:
    warnings: list[str] = []
    settings = RobotSettings(rate=50.0, cmd_vel="cmd_vel")
    with RobotNode(TWO, None, settings) as robot, Node("probe") as probe:
        robot.warn = warnings.append
        robot.start()
        stamped = probe.create_publisher(types.TwistStamped, "cmd_vel")
        until(probe, lambda: bool(warnings))
        assert stamped.subscription_count == 0
    assert warnings == ["'/cmd_vel' carries geometry_msgs/msg/TwistStamped; use --stamped"]


def test_wheel_commands_of_another_type_are_named() -> None:
    warnings: list[str] = []
    with RobotNode(TWO, None, RobotSettings(rate=50.0)) as robot, Node("probe") as probe:
        robot.warn = warnings.append
        robot.start()
        twist = probe.create_publisher(types.Twist, LEFT_TOPIC)
        until(probe, lambda: bool(warnings))
        assert twist.subscription_count == 0
    assert warnings == [
        f"'/{LEFT_TOPIC}' carries geometry_msgs/msg/Twist; this node reads "
        "std_msgs/msg/Float64MultiArray"
    ]


def test_the_ground_truth_moves_by_the_true_geometry() -> None:
    states: list[types.JointState] = []
    truth: list[types.Odometry] = []
    # Described: r = 0.05 m, b = 0.2 m; really 0.06 m and 0.04 m wheels 0.25 m apart.
    settings = RobotSettings(rate=100.0, timeout=0.3, true_radii=(0.06, 0.04), true_separation=0.25)
    with RobotNode(TWO, None, settings) as robot, Node("probe") as probe:
        graph = (robot, probe)
        left = probe.create_publisher(types.Float64MultiArray, LEFT_TOPIC)
        right = probe.create_publisher(types.Float64MultiArray, RIGHT_TOPIC)
        probe.create_subscription(types.JointState, "joint_states", states.append, DEEP)
        probe.create_subscription(types.Odometry, "ground_truth/odom", truth.append, DEEP)
        assert left.wait_for_subscribers(PATIENCE)
        assert right.wait_for_subscribers(PATIENCE)
        # The robot integrates from its last update: the commands come after its first.
        until(graph, lambda: robot.updates > 0)
        left.publish(commands([1.0]))
        right.publish(commands([3.0]))
        # The update of the timeout: its joint state at rest, and its pose.
        until(
            graph,
            lambda: (
                robot.timeouts == 1
                and bool(states and truth)
                and stamp(states[-1].header) == stamp(truth[-1].header)
            ),
        )
        stopped = dict(robot.positions)
    state, last = states[-1], truth[-1]
    assert state.velocity == [0.0, 0.0]
    # joint_states report what the wheels turned, as commanded: 1 and 3 rad/s for as long (both
    # commands came in one spin of the robot).
    turned_left, turned_right = state.position
    assert [turned_left, turned_right] == list(stopped.values())
    assert turned_right == pytest.approx(3.0 * turned_left, rel=1e-9)
    assert turned_left >= 0.3 - 1e-9  # the timeout
    # The heading depends on the wheel angles alone: (r_R theta_R - r_L theta_L) / b, with the
    # true radii and separation, not the described ones.
    expected = (0.04 * turned_right - 0.06 * turned_left) / 0.25
    assert yaw_of(last.pose.pose.orientation) == pytest.approx(
        math.remainder(expected, math.tau), abs=1e-9
    )
    described = 0.05 * (turned_right - turned_left) / 0.2
    # 0.26 theta_L apart, theta_L >= 0.3: told apart.
    assert abs(math.remainder(expected - described, math.tau)) > 0.05


def left_velocities(params: DiffDriveParams, limit_wheels: bool) -> list[float]:
    """The left wheel's reported velocities (rad/s), update by update, as a step command of
    2 rad/s on both sides comes in (in one spin of the robot), until they reach it."""
    states: list[types.JointState] = []
    settings = RobotSettings(rate=100.0, timeout=0.0, limit_wheels=limit_wheels)
    with RobotNode(params, None, settings) as robot, Node("probe") as probe:
        graph = (robot, probe)
        left = probe.create_publisher(types.Float64MultiArray, LEFT_TOPIC)
        right = probe.create_publisher(types.Float64MultiArray, RIGHT_TOPIC)
        probe.create_subscription(types.JointState, "joint_states", states.append, DEEP)
        assert left.wait_for_subscribers(PATIENCE)
        assert right.wait_for_subscribers(PATIENCE)
        until(graph, lambda: bool(states))
        left.publish(commands([2.0]))
        right.publish(commands([2.0]))
        until(graph, lambda: robot.velocities["left_wheel_joint"] == pytest.approx(2.0))
        until(graph, lambda: states[-1].velocity == pytest.approx([2.0, 2.0]))
    return [s.velocity[0] for s in states]


def test_wheel_commands_go_through_the_limiter_when_asked() -> None:
    controller = ControllerConfig(
        name="diff", source="c.yaml", ros_version=2, linear=AxisLimits(max_acceleration=0.5)
    )
    limited = TWO.replace(controller=controller)
    # 0.5 m/s^2 at r = 0.05 m: the joints gain at most 10 rad/s^2, 0.1 rad/s per update.
    step = 0.5 / 0.05 / 100.0
    ramp = left_velocities(limited, limit_wheels=True)
    assert max(b - a for a, b in itertools.pairwise(ramp)) <= step + 1e-9
    assert sum(1 for v in ramp if 0.0 < v < 2.0) >= 2.0 / step - 2
    # Without --limit-wheels the command applies at once.
    direct = left_velocities(limited, limit_wheels=False)
    assert max(b - a for a, b in itertools.pairwise(direct)) == pytest.approx(2.0)


def test_limited_wheels_stop_at_the_timeout_and_ramp_again_from_rest() -> None:
    controller = ControllerConfig(
        name="diff", source="c.yaml", ros_version=2, linear=AxisLimits(max_acceleration=0.5)
    )
    limited = TWO.replace(controller=controller)
    settings = RobotSettings(rate=100.0, timeout=1.0, limit_wheels=True)
    rest = {"left_wheel_joint": 0.0, "right_wheel_joint": 0.0}
    with RobotNode(limited, None, settings) as robot:
        robot.on_wheels(0, [2.0])
        robot.on_wheels(1, [2.0])
        for _ in range(3):
            robot.update()
        # 0.5 m/s² at r = 0.05 m: 0.1 rad/s more per update.
        assert robot.velocities["left_wheel_joint"] == pytest.approx(0.3, abs=1e-12)
        assert robot.timeouts == 0
        time.sleep(1.1)  # quiet for longer than the timeout: the watchdog stops the wheels
        robot.update()
        assert robot.timeouts == 1
        assert robot.targets == rest
        assert robot.velocities == rest
        robot.update()
        assert robot.velocities == rest
        robot.on_wheels(0, [2.0])
        robot.on_wheels(1, [2.0])
        robot.update()
        assert robot.velocities["left_wheel_joint"] == pytest.approx(0.1, abs=1e-12)


LIMITED = DiffDriveParams(
    wheel_radius=0.05,
    wheel_separation=0.2,
    left_joint="left_wheel_joint",
    right_joint="right_wheel_joint",
    right_sign=-1,
    max_wheel_speed=10.0,
)


def disturbed(params: DiffDriveParams, **given: float | int) -> RobotNode:
    settings = RobotSettings(
        rate=50.0,
        cmd_vel="cmd_vel",
        timeout=0.0,
        disturbances=Disturbances(**given),  # type: ignore[arg-type]
    )
    return RobotNode(params, None, settings)


def test_a_disturbed_robot_takes_commands_late_lags_and_saturates() -> None:
    # 2 m/s asks 40 rad/s of each wheel, four times the motor limit of 10 rad/s.
    with disturbed(LIMITED, latency=0.5, motor_lag=0.05) as robot:
        robot.on_twist(types.Twist(types.Vector3(2.0, 0.0, 0.0)))
        sent = time.monotonic()
        robot.update()
        if time.monotonic() - sent < 0.5:  # the command has not reached the motors yet
            assert robot.positions == {"left_wheel_joint": 0.0, "right_wheel_joint": 0.0}
        # Past the latency and twenty motor time constants: the wheels turn at the limit.
        time.sleep(0.5 + 20 * 0.05 - (time.monotonic() - sent))
        robot.update()
        assert robot.motors is not None
        assert robot.motors.speeds == pytest.approx([10.0, 10.0], abs=1e-6)
        # joint_states' signs: the right joint turns backwards to roll forwards.
        left, right = robot.positions["left_wheel_joint"], robot.positions["right_wheel_joint"]
        assert left > 0.0
        assert right == -left
        x, y, heading = robot.motors.pose
        # The ground moves by the wheel's turn (a straight line: no slip, equal radii).
        assert x == pytest.approx(0.05 * left, rel=1e-9)
        assert y == heading == 0.0


def arrivals(seed: int) -> list[bool]:
    """Which of 100 distinct commands reached the motors of a robot that drops half of them."""
    reached = []
    with disturbed(TWO, drop=0.5, seed=seed) as robot:
        assert robot.motors is not None
        for k in range(1, 101):
            robot.on_twist(types.Twist(types.Vector3(0.001 * k, 0.0, 0.0)))
            time.sleep(0.002)
            robot.update()  # without a lag the wheels take an arrived command at once
            wheel = 0.001 * k / 0.05
            reached.append(robot.motors.speeds[0] == pytest.approx(wheel, rel=1e-9))
    return reached


def test_a_disturbed_robot_drops_a_seeded_share_of_commands() -> None:
    first = arrivals(seed=7)
    # Binomial(100, 0.5): outside 25..75 once in about a million runs.
    assert 25 <= sum(first) <= 75
    assert arrivals(seed=7) == first
    assert arrivals(seed=8) != first


def test_one_topic_for_both_sides_is_refused_unless_commands_come_on_cmd_vel() -> None:
    same = RobotSettings(left_topic="~/w", right_topic="/diffbot_robot/w")
    with pytest.raises(
        LiveError, match=r"^left_topic= and right_topic= are both /diffbot_robot/w: "
    ):
        RobotNode(BOT, None, same)
    with RobotNode(BOT, None, replace(same, cmd_vel="cmd_vel")) as node:
        assert len(node.subscriptions) >= 1


@pytest.mark.parametrize(
    ("settings", "message"),
    [
        (RobotSettings(rate=0.0), r"^rate must be a finite number >= 1e-06, got 0\.0"),
        (RobotSettings(timeout=-1.0), r"^timeout must be a finite number >= 0 and <= 1e\+06"),
    ],
)
def test_a_rate_or_timeout_out_of_range_is_refused_naming_it(
    settings: RobotSettings, message: str
) -> None:
    with pytest.raises(LiveError, match=message):
        RobotNode(BOT, None, settings)


def test_disturbance_flags_out_of_range_are_one_error_line() -> None:
    for flag, value in (("--drop", "1"), ("--motor-lag", "-0.1"), ("--slip", "nan")):
        done = subprocess.run(
            [sys.executable, "-m", "diffbot", "node", "robot", flag, value, "--duration", "0"],
            capture_output=True,
            text=True,
            timeout=60,
            check=False,
        )
        assert done.returncode == 2, flag
        assert done.stderr.startswith("error: "), done.stderr
        assert done.stderr.count("\n") == 1, done.stderr
        assert flag in done.stderr


CASTER = (
    '<link name="caster"/><joint name="{name}" type="continuous"><parent link="base_link"/>'
    '<child link="caster"/></joint></robot>'
)


@pytest.mark.parametrize(
    ("urdf", "named"),
    [
        # A character reference keeps a tab or newline in an attribute; a name may be any
        # length: /tf and JointState carry neither.
        (two_wheel_urdf().replace("base_link", "base&#9;link"), "link of joint"),
        (two_wheel_urdf().replace("base_link", "b" * 300), "link of joint"),
        (
            two_wheel_urdf().replace("</robot>", CASTER.format(name="caster&#10;joint")),
            "joint name",
        ),
    ],
)
def test_names_of_the_description_that_no_message_may_carry_are_refused(
    urdf: str, named: str
) -> None:
    with pytest.raises(LiveError, match=named):
        RobotNode(TWO, urdf, RobotSettings(rate=10.0))


def test_a_description_with_plain_names_and_a_caster_is_taken() -> None:
    urdf = two_wheel_urdf().replace("</robot>", CASTER.format(name="caster_joint"))
    with RobotNode(TWO, urdf, RobotSettings(rate=10.0)) as robot:
        assert robot.names[-1] == "caster_joint"


def test_a_disturbed_robot_moves_by_the_true_geometry_and_holds_other_joints_still() -> None:
    # Described: r = 0.05 m, b = 0.2 m; really 0.06 m and 0.04 m wheels 0.25 m apart. The
    # caster is reported, never turned.
    urdf = two_wheel_urdf().replace("</robot>", CASTER.format(name="caster_joint"))
    settings = RobotSettings(
        rate=50.0,
        timeout=0.0,
        true_radii=(0.06, 0.04),
        true_separation=0.25,
        disturbances=Disturbances(motor_lag=0.01),
    )
    with RobotNode(TWO, urdf, settings) as robot:
        motors = robot.motors
        assert motors is not None
        robot.on_wheels(0, [1.0])
        robot.on_wheels(1, [3.0])
        time.sleep(0.2)
        (x, y, heading, linear, angular), velocities = robot._move_motors(time.monotonic())
    left, right = motors.speeds
    assert left == pytest.approx(1.0, rel=1e-6)
    assert right == pytest.approx(3.0, rel=1e-6)
    assert velocities == [left, right, 0.0]
    assert robot.positions["caster_joint"] == 0.0
    # The ground moves by the true radii and separation, not the described ones.
    turned_left, turned_right = motors.angles
    assert heading == pytest.approx((0.04 * turned_right - 0.06 * turned_left) / 0.25, rel=1e-9)
    assert linear == pytest.approx((0.06 * left + 0.04 * right) / 2.0, rel=1e-12)
    assert angular == pytest.approx((0.04 * right - 0.06 * left) / 0.25, rel=1e-12)
    assert math.hypot(x, y) > 0.0
