"""The QoS of each profile, policy by policy: what rclpy's profile of the same name sets, with
plain CDR forced."""

from __future__ import annotations

import pytest

from diffbot.live.cyclone import Policy
from diffbot.live.qos import LATCHED, PUBLISHER, SERVICE, SUBSCRIPTION, TF, QosProfile

RELIABLE = Policy.Reliability.Reliable(max_blocking_time=100_000_000)
PLAIN_CDR = Policy.DataRepresentation(use_cdrv0_representation=True)


@pytest.mark.parametrize(
    ("profile", "reliability", "durability", "depth"),
    [
        (PUBLISHER, RELIABLE, Policy.Durability.Volatile, 10),
        (SERVICE, RELIABLE, Policy.Durability.Volatile, 10),
        (TF, RELIABLE, Policy.Durability.Volatile, 100),
        (LATCHED, RELIABLE, Policy.Durability.TransientLocal, 1),
        (SUBSCRIPTION, Policy.Reliability.BestEffort, Policy.Durability.Volatile, 10),
    ],
    ids=["publisher", "service", "tf", "latched", "subscription"],
)
def test_each_profile_keeps_the_last_depth_samples(
    profile: QosProfile, reliability: object, durability: object, depth: int
) -> None:
    assert sorted(map(repr, profile.qos())) == sorted(
        map(repr, [reliability, durability, Policy.History.KeepLast(depth=depth), PLAIN_CDR])
    )


def test_dropping_the_newest_keeps_all_up_to_depth_in_every_instance() -> None:
    qos = QosProfile(drop_newest=True, depth=7).qos()
    assert qos[Policy.History] == Policy.History.KeepAll
    assert qos[Policy.ResourceLimits] == Policy.ResourceLimits(
        max_samples=7, max_instances=-1, max_samples_per_instance=7
    )
    assert qos[Policy.DataRepresentation] == PLAIN_CDR
    assert qos[Policy.Reliability] == RELIABLE


@pytest.mark.parametrize("drop_newest", [False, True])
def test_user_data_is_added_to_the_other_policies(drop_newest: bool) -> None:
    qos = QosProfile(drop_newest=drop_newest).qos(b"serviceid=1;")
    assert qos[Policy.Userdata] == Policy.Userdata(b"serviceid=1;")
    assert qos[Policy.DataRepresentation] == PLAIN_CDR
    assert len(list(qos)) == (6 if drop_newest else 5)
