"""Signals taken for a run: ignored ones stay ignored, and every one is given back."""

from __future__ import annotations

import signal
from collections.abc import Iterator
from typing import Any

import pytest

from diffbot.signal_handlers import install, restore

SIGNALS = (signal.SIGTERM, signal.SIGHUP)


@pytest.fixture(autouse=True)
def kept() -> Iterator[None]:
    before = {signum: signal.getsignal(signum) for signum in SIGNALS}
    yield
    for signum, handler in before.items():
        signal.signal(signum, handler)


def handler(signum: int, frame: Any) -> None:
    raise AssertionError("not called here")


def other(signum: int, frame: Any) -> None:
    raise AssertionError("not called here")


def test_a_handled_signal_is_taken_and_given_back() -> None:
    signal.signal(signal.SIGTERM, other)
    signal.signal(signal.SIGHUP, signal.SIG_DFL)
    saved = install(SIGNALS, handler)
    assert saved == {signal.SIGTERM: other, signal.SIGHUP: signal.SIG_DFL}
    assert signal.getsignal(signal.SIGTERM) is handler
    assert signal.getsignal(signal.SIGHUP) is handler
    restore(saved)
    assert signal.getsignal(signal.SIGTERM) is other
    assert signal.getsignal(signal.SIGHUP) is signal.SIG_DFL


def test_an_ignored_signal_stays_ignored() -> None:
    """As nohup starts a command: SIGHUP ignored, so the command outlives its terminal."""
    signal.signal(signal.SIGHUP, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    saved = install(SIGNALS, handler)
    assert saved == {signal.SIGTERM: signal.SIG_DFL}
    assert signal.getsignal(signal.SIGHUP) is signal.SIG_IGN
    restore(saved)
    assert signal.getsignal(signal.SIGHUP) is signal.SIG_IGN
    assert signal.getsignal(signal.SIGTERM) is signal.SIG_DFL
