"""Every live test runs on loopback in a DDS domain of its own: a domain no other test process
on the machine holds (:func:`live_graph.domain`); discovery stays on the machine
(ROS_LOCALHOST_ONLY=1: interface lo, no multicast, the local peers by unicast), and processes
the tests start inherit both."""

from __future__ import annotations

import os
from collections.abc import Iterator

import pytest
from live_graph import domain


@pytest.fixture(autouse=True, scope="session")
def loopback_domain() -> Iterator[int]:
    """ROS_DOMAIN_ID and ROS_LOCALHOST_ONLY for this process and those it starts."""
    saved = {
        k: os.environ.get(k)
        for k in (
            "ROS_DOMAIN_ID",
            "ROS_LOCALHOST_ONLY",
            "ROS_AUTOMATIC_DISCOVERY_RANGE",
            "CYCLONEDDS_URI",
        )
    }
    here = domain()
    os.environ["ROS_DOMAIN_ID"] = str(here)
    os.environ["ROS_LOCALHOST_ONLY"] = "1"
    os.environ.pop("ROS_AUTOMATIC_DISCOVERY_RANGE", None)
    os.environ.pop("CYCLONEDDS_URI", None)
    yield here
    for key, value in saved.items():
        if value is None:
            os.environ.pop(key, None)
        else:
            os.environ[key] = value
