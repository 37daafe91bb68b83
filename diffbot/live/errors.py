"""Why a live node cannot start, and what to install when cyclonedds is missing."""

from __future__ import annotations

from typing import Final

from diffbot.errors import DiffbotError

__all__ = ["INSTALL_HINT", "LiveError"]

#: What the live commands say when cyclonedds is not installed.
INSTALL_HINT: Final = (
    "the live commands need cyclonedds (DDS for Python): pip install 'diffbot-kinematics[live]'"
)


class LiveError(DiffbotError):
    """A live node cannot start: no cyclonedds, a bad domain id or topic, no peer in time."""
