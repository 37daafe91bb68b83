"""Velocity commands read as the course's nodes read them: geometry_msgs/Twist, TwistStamped, or
either, whichever the publisher sends, straight into (linear.x, angular.z)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, cast

from diffbot.live import types
from diffbot.live.cdr import decode_twist, decode_twist_stamped
from diffbot.live.transport import Node, Subscription

__all__ = ["subscribe_twists"]


def subscribe_twists(
    node: Node, topic: str, stamped: bool | None, take: Callable[[tuple[float, float]], None]
) -> list[Subscription[Any]]:
    """Subscribe ``node`` to the velocity commands on ``topic``: TwistStamped (``stamped``
    True), Twist (False) or a subscription of each kind (None: only the one of the publisher's
    type matches). ``take`` gets each command as (linear.x (m/s), angular.z (rad/s)), read
    from the payload without a message object."""
    subscriptions: list[Subscription[Any]] = []
    callback = cast(Any, take)
    if stamped is not False:
        subscriptions.append(
            node.create_subscription(
                types.TwistStamped, topic, callback, decode=cast(Any, decode_twist_stamped)
            )
        )
    if stamped is not True:
        subscriptions.append(
            node.create_subscription(types.Twist, topic, callback, decode=cast(Any, decode_twist))
        )
    return subscriptions
