"""QoS profiles as rclpy names them, made into cyclonedds QoS with plain CDR (XCDR1) forced in
every endpoint (a Cyclone endpoint of a ``final`` type would otherwise also offer XCDR2)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Final

from diffbot.live.cyclone import Policy, Qos

__all__ = ["LATCHED", "PUBLISHER", "SERVICE", "SUBSCRIPTION", "TF", "QosProfile"]


@dataclass(frozen=True)
class QosProfile:
    """A QoS profile as rclpy spells it: reliability, durability and history depth."""

    reliable: bool = True
    transient_local: bool = False
    depth: int = 10
    #: Keep every sample up to ``depth`` waiting ones and refuse the newer ones, counted (a
    #: reader's :attr:`Subscription.dropped`), instead of silently overwriting the oldest.
    drop_newest: bool = False

    def qos(self, user_data: bytes | None = None) -> Qos:
        """The cyclonedds QoS, with plain CDR (XCDR1) forced as ROS 2 expects, and
        ``user_data`` when given (how rmw_cyclonedds pairs a service's two endpoints)."""
        reliability = (
            Policy.Reliability.Reliable(max_blocking_time=100_000_000)
            if self.reliable
            else Policy.Reliability.BestEffort
        )
        durability = (
            Policy.Durability.TransientLocal if self.transient_local else Policy.Durability.Volatile
        )
        extra: list[Any] = [Policy.DataRepresentation(use_cdrv0_representation=True)]
        if user_data is not None:
            extra.append(Policy.Userdata(user_data))
        if self.drop_newest:
            return Qos(
                reliability,
                durability,
                Policy.History.KeepAll,
                Policy.ResourceLimits(
                    max_samples=self.depth, max_instances=-1, max_samples_per_instance=self.depth
                ),
                *extra,
            )
        return Qos(reliability, durability, Policy.History.KeepLast(depth=self.depth), *extra)


#: rclpy's default publisher profile: reliable, volatile, keep last 10.
PUBLISHER: Final = QosProfile()
#: rmw's services profile, for both of a service's topics: reliable, volatile, keep last 10.
SERVICE: Final = QosProfile()
#: /tf as tf2_ros' TransformBroadcaster publishes it: depth 100.
TF: Final = QosProfile(depth=100)
#: /tf_static and /robot_description: late joiners still get the last message.
LATCHED: Final = QosProfile(transient_local=True, depth=1)
#: Subscriptions: best effort matches reliable and best-effort (sensor data) publishers.
SUBSCRIPTION: Final = QosProfile(reliable=False)
