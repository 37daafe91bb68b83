"""A process's DDS participants: a domain configured from the environment when the first of the
process's participants joins it (Cyclone takes one configuration per domain and process), and
deleted when the last one leaves."""

from __future__ import annotations

import contextlib
import os
import sys
import tempfile
import threading
from collections.abc import Iterator
from typing import Any

from diffbot.live.cyclone import DDSException, Domain, DomainParticipant
from diffbot.live.discovery import MAX_DOMAIN_ID, cyclone_config, discovery_range, domain_id
from diffbot.live.errors import LiveError

__all__ = ["leave", "participant"]


#: The most of what Cyclone writes to stderr while starting that an error repeats (bytes).
_MOST_SAID = 4096

#: The domains this process created, by id: Cyclone takes one configuration per domain.
_DOMAINS: dict[int, Any] = {}
#: The domain id of each participant made here and not yet left, by the participant's ``id``.
_MEMBERS: dict[int, int] = {}
_DOMAINS_LOCK = threading.Lock()


@contextlib.contextmanager
def _cyclone_says() -> Iterator[list[str]]:
    """Within the block, what Cyclone's C code writes to stderr (file descriptor 2) is held
    back: on an exception its messages are in the list, for the one error line to say; else it
    goes on to stderr as it was written. Without a stderr to hold (closed), nothing is held."""
    said: list[str] = []
    with contextlib.suppress(OSError, ValueError, AttributeError):
        sys.stderr.flush()
    try:
        saved = os.dup(2)
    except OSError:
        yield said
        return
    with tempfile.TemporaryFile() as held:
        os.dup2(held.fileno(), 2)
        try:
            yield said
        except BaseException:
            held.seek(0)
            text = held.read(_MOST_SAID).decode("utf-8", "replace")
            # "<time> [<domain>] <thread>: <message>": the message alone.
            for line in text.splitlines():
                said.append(line.partition("]")[2].partition(": ")[2].strip())
            raise
        finally:
            os.dup2(saved, 2)
            os.close(saved)
        held.seek(0)
        while chunk := held.read(1 << 16):
            os.write(2, chunk)


def _why(err: DDSException, said: list[str]) -> str:
    """Cyclone's own words when it wrote any, else the exception's."""
    return "; ".join(message for message in said if message) or str(err)


def participant(domain: int | None) -> DomainParticipant:
    """A participant on ``domain`` (``ROS_DOMAIN_ID`` when None), the domain configured from
    the environment when none of the process's participants is on it; :func:`leave` ends it.

    Raises:
        LiveError: a domain id out of range, or Cyclone cannot start (its own messages, such as
            a ``CYCLONEDDS_URI`` it cannot read, are in the error, not on stderr).
    """
    env = os.environ
    ident = domain_id() if domain is None else domain
    if not 0 <= ident <= MAX_DOMAIN_ID:
        raise LiveError(f"the domain id must be from 0 to {MAX_DOMAIN_ID}, got {ident}")
    with _DOMAINS_LOCK:
        if ident not in _DOMAINS:
            config = cyclone_config(discovery_range(), env.get("CYCLONEDDS_URI", ""))
            try:
                with _cyclone_says() as said:
                    _DOMAINS[ident] = Domain(ident, config)
            except DDSException as err:
                raise LiveError(f"cannot start DDS on domain {ident}: {_why(err, said)}") from None
        try:
            with _cyclone_says() as said:
                member = DomainParticipant(ident)
        except DDSException as err:
            _close_if_empty(ident)
            raise LiveError(f"cannot join DDS domain {ident}: {_why(err, said)}") from None
        _MEMBERS[id(member)] = ident
        return member


def leave(member: DomainParticipant) -> None:
    """Delete ``member`` (a participant :func:`participant` made) with all it holds. The last
    of the process's participants on a domain takes the domain with it, which returns only once
    the participant's disposals are on the wire: Cyclone sends them from a thread of its own,
    which a process ending at once would cut short, and its peers would then keep the
    participant until its lease ran out. A second call does nothing."""
    with _DOMAINS_LOCK:
        ident = _MEMBERS.pop(id(member), None)
        member.__del__()  # a no-op when the participant is already gone
        if ident is not None:
            _close_if_empty(ident)


def _close_if_empty(ident: int) -> None:
    """Delete domain ``ident`` when none of the process's participants is on it (the caller
    holds the lock); the next participant configures it anew."""
    if ident not in _MEMBERS.values():
        _DOMAINS.pop(ident).__del__()
