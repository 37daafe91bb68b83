"""A process's DDS participants: each domain configured once, from the environment, on first use
(Cyclone takes one configuration per domain and process)."""

from __future__ import annotations

import os
import threading
from typing import Any

from diffbot.live.cyclone import DDSException, Domain, DomainParticipant
from diffbot.live.discovery import MAX_DOMAIN_ID, cyclone_config, discovery_range, domain_id
from diffbot.live.errors import LiveError

__all__ = ["participant"]


#: The domains this process created, by id: Cyclone takes one configuration per domain.
_DOMAINS: dict[int, Any] = {}
_DOMAINS_LOCK = threading.Lock()


def participant(domain: int | None) -> DomainParticipant:
    """A participant on ``domain`` (``ROS_DOMAIN_ID`` when None), the domain configured from
    the environment on first use."""
    env = os.environ
    ident = domain_id() if domain is None else domain
    if not 0 <= ident <= MAX_DOMAIN_ID:
        raise LiveError(f"the domain id must be from 0 to {MAX_DOMAIN_ID}, got {ident}")
    with _DOMAINS_LOCK:
        if ident not in _DOMAINS:
            config = cyclone_config(discovery_range(), env.get("CYCLONEDDS_URI", ""))
            try:
                _DOMAINS[ident] = Domain(ident, config) if config else None
            except DDSException as err:
                raise LiveError(f"cannot start DDS on domain {ident}: {err}") from None
    try:
        return DomainParticipant(ident)
    except DDSException as err:
        raise LiveError(f"cannot join DDS domain {ident}: {err}") from None
