"""Velocity commands subscribed as Twist, TwistStamped or either, read into (linear, angular)."""

from __future__ import annotations

import pytest
from live_graph import PATIENCE, until

from diffbot.live import types
from diffbot.live.messages import time_of
from diffbot.live.transport import Node
from diffbot.live.twist_subscriptions import subscribe_twists

TWIST = "geometry_msgs::msg::dds_::Twist_"
STAMPED = "geometry_msgs::msg::dds_::TwistStamped_"


@pytest.mark.parametrize(
    ("stamped", "kinds"), [(True, [STAMPED]), (False, [TWIST]), (None, [STAMPED, TWIST])]
)
def test_each_kind_asked_for_is_subscribed_on_the_topic(
    stamped: bool | None, kinds: list[str]
) -> None:
    with Node("reader") as node:
        subscriptions = subscribe_twists(node, "commands", stamped, lambda command: None)
        assert [(s.topic, s.type_name) for s in subscriptions] == [
            ("commands", kind) for kind in kinds
        ]


def test_either_kind_arrives_as_linear_and_angular() -> None:
    taken: list[tuple[float, float]] = []
    velocity = types.Twist(types.Vector3(0.5, 9.0, 9.0), types.Vector3(9.0, 9.0, -1.25))
    with Node("reader") as reader, Node("writer") as writer:
        subscribe_twists(reader, "cmd_vel", None, taken.append)
        plain = writer.create_publisher(types.Twist, "cmd_vel")
        stamped = writer.create_publisher(types.TwistStamped, "cmd_vel")
        assert plain.wait_for_subscribers(PATIENCE)
        assert stamped.wait_for_subscribers(PATIENCE)
        plain.publish(velocity)
        until(reader, lambda: len(taken) == 1)
        stamped.publish(types.TwistStamped(types.Header(time_of(1), "base_link"), velocity))
        until(reader, lambda: len(taken) == 2)
    assert taken == [(0.5, -1.25), (0.5, -1.25)]
