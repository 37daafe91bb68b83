"""Where ROS 2 nodes meet: the DDS domain and how far discovery reaches, as the ROS environment
variables say and rmw_cyclonedds reads them, and the DDS topic of a ROS topic (pure: no DDS here).

- ``ROS_DOMAIN_ID`` picks the domain (0..232);
- ``ROS_LOCALHOST_ONLY=1`` or ``ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST`` keep discovery and
  traffic on the loopback interface (unicast to the local peers, no multicast), ``OFF`` keeps it
  in the process (:func:`cyclone_config`);
- topic ``/name`` is the DDS topic ``rt/name`` (:func:`dds_topic`).
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from typing import Final

from diffbot.live.errors import LiveError
from diffbot.numbers import written_form

__all__ = [
    "DISCOVERY_TOPIC",
    "INTERNAL",
    "MAX_DOMAIN_ID",
    "cyclone_config",
    "dds_topic",
    "discovery_range",
    "domain_id",
]

#: The DDS topic (no ``rt/`` prefix) where ROS 2 participants list their nodes.
DISCOVERY_TOPIC: Final = "ros_discovery_info"
#: The highest domain id ROS 2 allows (the RTPS port formula overflows above it).
MAX_DOMAIN_ID: Final = 232


def domain_id(environ: Mapping[str, str] | None = None) -> int:
    """The domain of ``ROS_DOMAIN_ID`` (0 when unset or empty).

    Raises:
        LiveError: not a whole number in 0..232.
    """
    env = os.environ if environ is None else environ
    text = env.get("ROS_DOMAIN_ID", "").strip()
    if not text:
        return 0
    try:
        value = int(text) if written_form(text) else -1
    except ValueError:
        value = -1
    if not 0 <= value <= MAX_DOMAIN_ID:
        raise LiveError(
            f"ROS_DOMAIN_ID must be a whole number from 0 to {MAX_DOMAIN_ID}, got {text!r}"
        )
    return value


def discovery_range(environ: Mapping[str, str] | None = None) -> str:
    """How far discovery reaches: ``SUBNET`` (Cyclone's default), ``LOCALHOST`` or ``OFF``.

    ``ROS_AUTOMATIC_DISCOVERY_RANGE`` (Iron and later) decides when set; else
    ``ROS_LOCALHOST_ONLY=1`` (Humble) means ``LOCALHOST``.

    Raises:
        LiveError: an unknown range.
    """
    env = os.environ if environ is None else environ
    text = env.get("ROS_AUTOMATIC_DISCOVERY_RANGE", "").strip().upper()
    if text in ("", "SYSTEM_DEFAULT"):
        return "LOCALHOST" if env.get("ROS_LOCALHOST_ONLY", "").strip() == "1" else "SUBNET"
    if text not in ("SUBNET", "LOCALHOST", "OFF"):
        raise LiveError(
            "ROS_AUTOMATIC_DISCOVERY_RANGE must be SUBNET, LOCALHOST, OFF or SYSTEM_DEFAULT, "
            f"got {text!r}"
        )
    return text


#: What every domain of diffbot's sets, whatever the range: a key hash in every sample of a
#: keyed topic (discovery's disposals included). Fast DDS (ROS 2's default middleware) reads a
#: participant's or endpoint's disposal by its key hash only: without one it kept a diffbot
#: node on its graph until the lease ran out (10 s), with one it drops it at once.
INTERNAL = "<Internal><GenerateKeyhash>true</GenerateKeyhash></Internal>"


def cyclone_config(reach: str, user_config: str = "") -> str:
    """The Cyclone DDS configuration of a discovery range, after the user's own
    (``CYCLONEDDS_URI``), so that ours wins where both set something.

    Every range: key hashes sent (:data:`INTERNAL`). ``LOCALHOST``: the loopback interface
    only, no multicast, the local participants found by unicast (``Peers``: localhost,
    participant indices assigned automatically). ``OFF``: the same without peers, so only this
    process's participants meet. ``SUBNET``: nothing more than the user's configuration
    (Cyclone's defaults: multicast discovery on the default interface).
    """
    if reach == "SUBNET":
        ours = f"<CycloneDDS><Domain Id='any'>{INTERNAL}</Domain></CycloneDDS>"
    else:
        peers = (
            "<Peers><Peer address='localhost'/></Peers>"
            "<ParticipantIndex>auto</ParticipantIndex>"
            "<MaxAutoParticipantIndex>64</MaxAutoParticipantIndex>"
            if reach == "LOCALHOST"
            else ""
        )
        ours = (
            "<CycloneDDS><Domain Id='any'><General>"
            "<Interfaces><NetworkInterface name='lo'/></Interfaces>"
            "<AllowMulticast>false</AllowMulticast></General>"
            f"<Discovery>{peers}</Discovery>{INTERNAL}</Domain></CycloneDDS>"
        )
    return f"{user_config},{ours}" if user_config else ours


def dds_topic(name: str) -> str:
    """The DDS topic of a ROS topic in the root namespace: ``/odom`` and ``odom`` ->
    ``rt/odom``."""
    return "rt/" + name.lstrip("/")
