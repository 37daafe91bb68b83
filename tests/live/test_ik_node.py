"""The inverse-kinematics node on a live graph: Twist or TwistStamped in, one Float64MultiArray
per side out; quiet commands and NaN stop the wheels; the wrong kind of twist is named."""

from __future__ import annotations

import math
import time
from pathlib import Path
from typing import Any

import pytest
from live_graph import PATIENCE, deep, spare_domain, timer_periods, until
from robots import BOT

from diffbot.body_limits import BodyLimits
from diffbot.controller_config import AxisLimits, ControllerConfig
from diffbot.live import inverse_kinematics, types
from diffbot.live.inverse_kinematics import IkSettings, InverseKinematicsNode
from diffbot.live.messages import twist_command
from diffbot.live.transport import Node
from diffbot.urdf.controllers import load_command_controllers
from diffbot.wheel_commands import LEFT_TOPIC, RIGHT_TOPIC

DEEP = deep()


def test_twists_become_wheel_commands_and_silence_stops_them() -> None:
    left: list[list[float]] = []
    right: list[list[float]] = []
    settings = IkSettings(timeout=0.3)
    # The node spins in this thread, before the probe: what it sends for a command or a timeout
    # is all at the probe before the next check, however busy the machine.
    with InverseKinematicsNode(BOT, settings) as node, Node("probe") as probe:
        graph = (node, probe)
        cmd_vel = probe.create_publisher(types.Twist, "cmd_vel")
        probe.create_subscription(
            types.Float64MultiArray, LEFT_TOPIC, lambda m: left.append(m.data), DEEP
        )
        probe.create_subscription(
            types.Float64MultiArray, RIGHT_TOPIC, lambda m: right.append(m.data), DEEP
        )
        assert cmd_vel.wait_for_subscribers(PATIENCE)
        until(graph, lambda: node.left.subscription_count > 0 and node.right.subscription_count > 0)
        started = time.monotonic()
        cmd_vel.publish(twist_command(0.1, 0.5))
        until(graph, lambda: len(left) >= 1 and len(right) >= 1)
        assert left[0] == pytest.approx([1.8928571428571428], abs=1e-12)
        assert right[0] == pytest.approx([3.8214285714285716], abs=1e-12)
        until(graph, lambda: len(left) >= 2 and len(right) >= 2)  # the timeout's zero
        assert time.monotonic() - started > 0.3  # quiet for longer than the timeout
        assert left[-1] == [0.0]
        assert right[-1] == [0.0]
        assert node.timeouts == 1
        cmd_vel.publish(twist_command(math.nan, 0.0))
        until(graph, lambda: node.refused == 1)
        until(graph, lambda: len(left) >= 3)
        assert left[-1] == [0.0]
    assert node.status() == "2 commands, 1 refused (not finite), 1 timeouts, 0 malformed"


def test_stamped_commands_and_the_wrong_kind_named() -> None:
    left: list[list[float]] = []
    warnings: list[str] = []
    with (
        InverseKinematicsNode(BOT, IkSettings(stamped=True, timeout=0.0)) as node,
        Node("probe") as probe,
    ):
        node.warn = warnings.append
        node.start()
        stamped = probe.create_publisher(types.TwistStamped, "cmd_vel")
        probe.create_subscription(
            types.Float64MultiArray, LEFT_TOPIC, lambda m: left.append(m.data), DEEP
        )
        assert stamped.wait_for_subscribers(PATIENCE)
        until(probe, lambda: node.left.subscription_count > 0)
        stamped.publish(types.TwistStamped(twist=twist_command(0.07, 0.0)))
        until(probe, lambda: len(left) == 1)
        assert left[0] == pytest.approx([2.0], abs=1e-12)
        # A plain Twist publisher on the same topic does not match; the node names it.
        plain = probe.create_publisher(types.Twist, "/cmd_vel")
        assert plain.subscription_count == 0
        until(probe, lambda: bool(warnings))
    assert warnings == ["'/cmd_vel' carries geometry_msgs/msg/Twist; leave out --stamped"]


def test_the_controllers_file_names_the_command_topics() -> None:
    bundled = Path(__file__).parents[2] / "diffbot" / "description" / "config" / "controllers.yaml"
    found = load_command_controllers(bundled)
    assert found == {
        "left_wheel_velocity_controller": ("front_left_wheel_joint",),
        "right_wheel_velocity_controller": ("front_right_wheel_joint",),
    }


def test_by_default_either_kind_of_twist_is_read() -> None:
    left: list[list[float]] = []
    with InverseKinematicsNode(BOT, IkSettings(timeout=0.0)).start() as node, Node("p") as probe:
        assert node.settings.stamped is None
        stamped = probe.create_publisher(types.TwistStamped, "cmd_vel")
        plain = probe.create_publisher(types.Twist, "cmd_vel")
        probe.create_subscription(
            types.Float64MultiArray, LEFT_TOPIC, lambda m: left.append(m.data), DEEP
        )
        assert stamped.wait_for_subscribers(PATIENCE)
        assert plain.wait_for_subscribers(PATIENCE)
        until(probe, lambda: node.left.subscription_count > 0)
        stamped.publish(types.TwistStamped(twist=twist_command(0.07, 0.0)))
        until(probe, lambda: len(left) == 1)
        plain.publish(twist_command(0.035, 0.0))
        until(probe, lambda: len(left) == 2)
    assert left == [
        pytest.approx([2.0], abs=1e-12),
        pytest.approx([1.0], abs=1e-12),
    ]
    assert node.warnings == []


class Clock:
    """A monotonic clock the test moves by hand (s)."""

    def __init__(self) -> None:
        self.now = 100.0

    def monotonic(self) -> float:
        return self.now


@pytest.fixture
def clock(monkeypatch: pytest.MonkeyPatch) -> Clock:
    """The IK node's clock, moved by hand."""
    clock = Clock()
    monkeypatch.setattr(inverse_kinematics, "time", clock)
    return clock


#: The bundled robot behind a controller that ramps: 0.5 m/s² and 2 rad/s².
LIMITED = BOT.replace(
    controller=ControllerConfig(
        name="diff",
        source="c.yaml",
        ros_version=2,
        linear=AxisLimits(max_acceleration=0.5),
        angular=AxisLimits(max_acceleration=2.0),
    )
)


def capture(publisher: Any, into: list[list[float]]) -> None:
    """Route a wheel command publisher's messages into a list of their ``data``, decoded,
    whether the node publishes a message or its bytes."""
    publisher.publish = lambda m: into.append(list(m.data))
    publisher.publish_serialized = lambda data: into.append(
        list(types.Float64MultiArray.deserialize(data).data)
    )


def test_the_limiter_ramps_on_each_update_and_a_stale_command_ramps_down_to_zero(
    clock: Clock,
) -> None:
    left: list[list[float]] = []
    right: list[list[float]] = []
    with InverseKinematicsNode(LIMITED, IkSettings(timeout=0.3, rate=10.0)) as node:
        assert node.commander.limited
        capture(node.left, left)
        capture(node.right, right)
        node.on_twist(twist_command(0.2, 0.0))
        assert left == []  # limited: sent on the controller's updates only
        for _ in range(2):
            clock.now += 0.1
            node.update()
        # 0.5 m/s² for 0.1 s per update: 0.05 then 0.1 m/s, 0.035 m wheels.
        assert [v for (v,) in left] == pytest.approx([0.05 / 0.035, 0.1 / 0.035], abs=1e-12)
        assert right == left
        assert node.timeouts == 0
        clock.now += 0.35  # quiet for longer than the timeout
        node.update()
        assert node.timeouts == 1
        for _ in range(3):
            clock.now += 0.1
            node.update()
        assert node.timeouts == 1  # counted once, then the command is zero
        # Down at 0.5 m/s² too: 0.05 m/s, then stopped.
        assert [v for (v,) in left[2:]] == pytest.approx([0.05 / 0.035, 0.0, 0.0, 0.0], abs=1e-12)
        # A turn ramps at 2 rad/s²: 0.2 rad/s after one update, wheels opposite.
        node.on_twist(twist_command(0.0, 1.0))
        clock.now += 0.1
        node.update()
        w = 0.2 * 0.135 / 2 / 0.035
        assert left[-1] == pytest.approx([-w], abs=1e-12)
        assert right[-1] == pytest.approx([w], abs=1e-12)
        # A NaN stops the wheels at once, without the ramp, and forgets the ramp's history;
        # the updates after it command zero.
        node.on_twist(twist_command(math.nan, 1.0))
        assert (left[-1], right[-1]) == ([0.0], [0.0])
        clock.now += 0.1
        node.update()
        assert (left[-1], right[-1]) == ([0.0], [0.0])
        node.on_twist(twist_command(0.2, 0.0))
        clock.now += 0.1
        node.update()
        assert left[-1] == pytest.approx([0.05 / 0.035], abs=1e-12)
        clock.now += 0.35  # quiet again: a second timeout
        node.update()
    assert node.status() == "4 commands, 1 refused (not finite), 2 timeouts, 0 malformed"


def test_limited_before_any_command_the_updates_command_zero(clock: Clock) -> None:
    left: list[list[float]] = []
    right: list[list[float]] = []
    with InverseKinematicsNode(LIMITED, domain=spare_domain(3)) as node:
        assert node.participant.domain_id == spare_domain(3)
        capture(node.left, left)
        capture(node.right, right)
        for _ in range(3):
            clock.now += 0.1
            node.update()
        assert left == right == [[0.0]] * 3
        assert node.timeouts == 0


def test_without_limits_a_quiet_command_stops_the_wheels_once(clock: Clock) -> None:
    left: list[list[float]] = []
    with InverseKinematicsNode(BOT, IkSettings(timeout=0.3)) as node:
        assert not node.commander.limited
        capture(node.left, left)
        node.watch()
        assert left == []  # nothing commanded yet: nothing to stop
        node.on_twist(twist_command(0.07, 0.0))
        assert left == [[2.0]]
        clock.now += 0.2
        node.watch()
        assert left == [[2.0]]  # not quiet for long enough
        clock.now += 0.2
        node.watch()
        node.watch()
        assert left == [[2.0], [0.0]]
        assert node.timeouts == 1
        node.on_twist(twist_command(0.07, 0.0))
        clock.now += 0.4
        node.watch()
        assert left == [[2.0], [0.0], [2.0], [0.0]]
        assert node.timeouts == 2


def test_a_timeout_of_zero_never_stops_a_limited_command(clock: Clock) -> None:
    left: list[list[float]] = []
    with InverseKinematicsNode(LIMITED, IkSettings(timeout=0.0, rate=10.0)) as node:
        capture(node.left, left)
        node.on_twist(twist_command(0.05, 0.0))
        for _ in range(3):
            clock.now += 100.0
            node.update()
        # 0.05 m/s reached in the first update (0.5 m/s² for 0.1 s), then held.
        assert [v for (v,) in left] == pytest.approx([0.05 / 0.035] * 3, abs=1e-12)
        assert node.timeouts == 0


def test_updates_run_at_the_rate_and_the_watch_at_a_quarter_timeout_at_most() -> None:
    with InverseKinematicsNode(LIMITED, IkSettings(rate=25.0)) as node:
        assert timer_periods(node, node.update) == [pytest.approx(0.04, rel=1e-12)]
        assert timer_periods(node, node.watch) == []
    # Without limits no updates, a watch: a quarter of the timeout where shorter than the
    # rate's period, else the period; none without a timeout.
    for settings, period in (
        (IkSettings(rate=25.0, timeout=0.1), 0.025),
        (IkSettings(rate=10.0, timeout=2.0), 0.1),
    ):
        with InverseKinematicsNode(BOT, settings) as node:
            assert timer_periods(node, node.update) == []
            assert timer_periods(node, node.watch) == [pytest.approx(period, rel=1e-12)]
    with InverseKinematicsNode(BOT, IkSettings(timeout=0.0)) as node:
        assert timer_periods(node, node.watch) == []
    # A limiting controller, told not to limit.
    with InverseKinematicsNode(LIMITED, IkSettings(use_limits=False)) as node:
        assert not node.commander.limited
        assert timer_periods(node, node.update) == []


@pytest.mark.usefixtures("clock")
def test_body_limits_clamp_each_axis_before_the_wheels_and_refusals_are_listed_by_reason() -> None:
    left: list[list[float]] = []
    right: list[list[float]] = []
    body = BodyLimits(linear=(-0.05, 0.05), angular=(-0.5, 0.5))
    with InverseKinematicsNode(BOT, IkSettings(body=body, use_limits=False)) as node:
        assert node.name == "diffbot_ik"
        capture(node.left, left)
        capture(node.right, right)
        node.on_twist(twist_command(0.07, 0.0))  # 0.05 m/s on 0.035 m wheels
        node.on_twist(twist_command(-0.01, -2.0))  # -0.5 rad/s over 0.135 m
        node.on_twist(twist_command(math.inf, 0.0))
        node.on_twist(twist_command(1e9, 0.0))
    w = 0.5 * 0.135 / 2
    lefts = [v for (v,) in left]
    rights = [v for (v,) in right]
    assert lefts[:2] == pytest.approx([0.05 / 0.035, (w - 0.01) / 0.035], abs=1e-12)
    assert rights[:2] == pytest.approx([0.05 / 0.035, -(w + 0.01) / 0.035], abs=1e-12)
    # Each refusal stops the wheels, as does the node's end.
    assert lefts[2:] == rights[2:] == [0.0, 0.0, 0.0]
    assert node.status() == (
        "4 commands, 2 refused (1 not finite, 1 out of range), 0 timeouts, 0 malformed"
    )


@pytest.mark.parametrize(
    ("settings", "message"),
    [
        (IkSettings(left_topic="w", right_topic="/w"), "left_topic= and right_topic= are both /w"),
        (
            IkSettings(cmd_vel="w", right_topic="w"),
            "the command topic and right_topic= are both /w",
        ),
    ],
)
def test_one_topic_for_two_of_the_nodes_topics_is_refused(
    settings: IkSettings, message: str
) -> None:
    from diffbot.live.transport import LiveError

    with pytest.raises(LiveError, match=f"^{message}: each needs a topic of its own$"):
        InverseKinematicsNode(BOT, settings)


def test_a_negative_timeout_or_a_rate_not_above_zero_is_refused() -> None:
    from diffbot.live.transport import LiveError

    for settings in (IkSettings(timeout=-0.1), IkSettings(rate=0.0), IkSettings(rate=math.nan)):
        with pytest.raises(LiveError, match=r"(timeout|rate) must be a finite number >= "):
            InverseKinematicsNode(BOT, settings)
    with pytest.raises(LiveError, match=r"^timeout must be a finite number >= 0 and <= 1e\+06"):
        InverseKinematicsNode(BOT, IkSettings(timeout=2e6))
    with pytest.raises(LiveError, match=r"^rate must be a finite number >= 1e-06, got 5e-07"):
        InverseKinematicsNode(BOT, IkSettings(rate=5e-7))
