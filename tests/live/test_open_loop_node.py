"""The open-loop odometry node: velocity commands in, the odometry of doing exactly what they
say out, as diff_drive_controller publishes it with ``open_loop: true``."""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import pytest
from live_graph import PATIENCE, deep, live_process, spare_domain, timer_periods, until
from robots import BOT

from diffbot.live import types
from diffbot.live.odometry import OdometrySettings
from diffbot.live.open_loop_node import (
    DEFAULT_PUBLISH_RATE,
    CommandSettings,
    OpenLoopOdometryNode,
)
from diffbot.live.transport import LiveError, Node

T0 = 1_700_000_000 * 10**9
S = 10**9


def twist(linear: float, angular: float) -> types.Twist:
    return types.Twist(types.Vector3(linear, 0.0, 0.0), types.Vector3(0.0, 0.0, angular))


def test_commands_move_the_odometry_each_until_the_next_or_the_timeout() -> None:
    with OpenLoopOdometryNode(BOT, commands=CommandSettings(timeout=1.0)) as node:
        node.on_tick(T0)  # starts the clock
        node.on_command((0.2, 0.0), T0)
        node.on_tick(T0 + S // 2)
        assert tuple(node.odometry.pose) == pytest.approx((0.1, 0.0, 0.0), abs=1e-12)
        node.on_command((0.0, math.nan), T0 + 3 * S // 4)  # refused: the robot is taken to stop
        node.on_command((0.0, 1.0), T0 + 2 * S)
        node.on_command((5e3, 0.0), T0 + 5 * S // 2)  # beyond any robot: refused, stop
        node.on_tick(T0 + 10 * S)
        # 0.15 m, then standing, then half a second of turning at 1 rad/s, then standing.
        assert tuple(node.odometry.pose) == pytest.approx((0.15, 0.0, 0.5), abs=1e-12)
        assert node.counts == {
            "received": 0,
            "published": 3,
            "not finite": 1,
            "out of range": 1,
        }
        assert node.commands == 4
        assert node.status() == "0 commands, 3 published; skipped: 1 not finite, 1 out of range"


def test_the_node_publishes_at_its_rate_and_reads_either_twist() -> None:
    with OpenLoopOdometryNode(BOT, OdometrySettings(publish_rate=20.0)) as node:
        assert timer_periods(node, node.on_tick) == [pytest.approx(1 / 20.0)]
        assert [(s.topic, s.type_name) for s in node.subscriptions] == [
            ("cmd_vel", "geometry_msgs::msg::dds_::TwistStamped_"),
            ("cmd_vel", "geometry_msgs::msg::dds_::Twist_"),
        ]
    with OpenLoopOdometryNode(BOT, commands=CommandSettings(stamped=True)) as node:
        assert timer_periods(node, node.on_tick) == [pytest.approx(1 / DEFAULT_PUBLISH_RATE)]
        assert [s.type_name for s in node.subscriptions] == [
            "geometry_msgs::msg::dds_::TwistStamped_"
        ]
        assert node.type_mismatch("/cmd_vel", "geometry_msgs/msg/Twist", []) == (
            "'/cmd_vel' carries geometry_msgs/msg/Twist; leave out --stamped"
        )
    with pytest.raises(LiveError, match="timeout"):
        OpenLoopOdometryNode(BOT, commands=CommandSettings(timeout=-1.0))


def test_twists_on_the_wire_come_out_as_odometry_of_their_velocity() -> None:
    seen: list[types.Odometry] = []
    with OpenLoopOdometryNode(BOT) as node, Node("probe") as probe:
        commands = probe.create_publisher(types.Twist, "cmd_vel")
        probe.create_subscription(types.Odometry, "odom", seen.append, deep())
        assert commands.wait_for_subscribers(PATIENCE)
        commands.publish(twist(0.25, -0.5))

        def moving() -> bool:
            return any(m.twist.twist.linear.x != 0.0 for m in seen)

        until((node, probe), moving)
    last = next(m for m in reversed(seen) if m.twist.twist.linear.x != 0.0)
    # The velocity of the held command, whatever the timer's moments.
    assert last.twist.twist.linear.x == pytest.approx(0.25, abs=1e-9)
    assert last.twist.twist.angular.z == pytest.approx(-0.5, abs=1e-9)
    assert (last.header.frame_id, last.child_frame_id) == ("odom", "base_link")
    assert node.counts["received"] >= 1


def test_node_odom_open_loop_follows_the_commands(tmp_path: Path) -> None:
    seen: list[tuple[float, float]] = []

    def keep(message: types.Odometry) -> None:
        seen.append((message.twist.twist.linear.x, message.twist.twist.angular.z))

    with live_process("node", "odom", "--open-loop", "--no-tf"), Node("probe") as probe:
        commands = probe.create_publisher(types.Twist, "cmd_vel")
        probe.create_subscription(types.Odometry, "odom", keep, deep())
        assert commands.wait_for_subscribers(PATIENCE)

        def turning() -> bool:
            commands.publish(twist(0.0, 0.75))
            return any(w != 0.0 for _, w in seen)

        until(probe, turning)
    assert [w for _, w in seen if w != 0.0][-1] == pytest.approx(0.75, abs=1e-9)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--open-loop", "--feedback", "velocity"], "--open-loop integrates the commands"),
        (["--cmd-vel", "x"], "--cmd-vel, --stamped and --distro go with --open-loop"),
        (["--open-loop", "--joint-states", "js"], "--open-loop reads the commands, not"),
    ],
)
def test_node_odom_refuses_open_loop_options_that_do_not_go_together(
    args: list[str], message: str
) -> None:
    done = subprocess.run(
        [sys.executable, "-m", "diffbot", "node", "odom", *args],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    assert done.returncode == 2
    assert done.stderr.startswith("error: "), done.stderr
    assert message in done.stderr, done.stderr
    assert done.stderr.count("\n") == 1


def test_the_node_s_name_domain_and_timeout_bound() -> None:
    with OpenLoopOdometryNode(BOT) as node:
        assert node.name == "diffbot_odometry"
    with OpenLoopOdometryNode(BOT, name="wheels_off", domain=spare_domain(3)) as node:
        assert node.name == "wheels_off"
        assert node.participant.domain_id == spare_domain(3)
    with pytest.raises(LiveError) as caught:
        OpenLoopOdometryNode(BOT, commands=CommandSettings(timeout=2e6))
    assert str(caught.value).startswith("timeout must be")
    assert "1e+06" in str(caught.value)


@pytest.mark.parametrize("rate", [1000.5, 1e6, 1e300])
def test_a_publish_rate_faster_than_a_node_s_timer_is_refused(rate: float) -> None:
    # The open loop publishes on its own timer: at 1e300 Hz it would only spin the processor.
    with pytest.raises(LiveError, match=r"publish_rate must be .* <= 1000"):
        OpenLoopOdometryNode(BOT, OdometrySettings(publish_rate=rate))
    with OpenLoopOdometryNode(BOT, OdometrySettings(publish_rate=1000.0)) as node:
        assert node.settings.publish_rate == 1000.0


def test_the_open_loop_reads_no_feedback_setting_and_its_twist_is_the_command() -> None:
    # A controllers file may say position_feedback: false and a rolling window beside
    # open_loop: true; neither changes what the commands do, and the twist published is the
    # held command, as the controller's open loop publishes it.
    settings = OdometrySettings(feedback="velocity", window=10)
    with OpenLoopOdometryNode(BOT, settings, CommandSettings(timeout=0.0)) as node:
        node.on_tick(T0)
        node.on_command((0.2, 0.0), T0)
        for k in range(1, 11):
            node.on_tick(T0 + k * S // 10)
        assert tuple(node.odometry.pose) == pytest.approx((0.2, 0.0, 0.0), abs=1e-12)
        assert node.odometry.twist.linear == pytest.approx(0.2, abs=1e-12)
        node.on_command((0.0, 0.0), T0 + S)
        node.on_tick(T0 + 11 * S // 10)
        assert node.odometry.twist.linear == 0.0
        assert node.odometry.feedback == "position"
        assert node.odometry.velocity_rolling_window_size == 1
