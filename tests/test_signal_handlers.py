"""Signals taken for a run: ignored ones stay ignored, and every one is given back."""

from __future__ import annotations

import signal
from collections.abc import Iterator
from typing import Any

import pytest

from diffbot import signal_handlers
from diffbot.signal_handlers import ends_with_run, ignore, install, restore, settle

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


def test_ignored_signals_stay_ignored_and_one_set_outside_python_is_left_alone(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    signal.signal(signal.SIGTERM, other)
    signal.signal(signal.SIGHUP, signal.SIG_DFL)
    ignore(SIGNALS)
    assert signal.getsignal(signal.SIGTERM) is signal.SIG_IGN
    assert signal.getsignal(signal.SIGHUP) is signal.SIG_IGN
    # Python cannot put back a handler it did not install: such a signal is not touched.
    signal.signal(signal.SIGHUP, signal.SIG_DFL)
    monkeypatch.setattr(signal, "getsignal", lambda signum: None)
    ignore(SIGNALS)
    monkeypatch.undo()
    assert signal.getsignal(signal.SIGHUP) is signal.SIG_DFL


def test_only_the_entry_point_says_that_the_process_ends_with_its_run(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    assert ends_with_run() is False  # a library or a test runner keeps its signals
    monkeypatch.setattr(signal_handlers._Process, "ends_with_run", False)
    signal_handlers.process_ends_with_run()
    assert ends_with_run() is True


def test_a_run_settles_its_signals_as_its_process_goes_on_or_ends(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    signal.signal(signal.SIGTERM, other)
    signal.signal(signal.SIGHUP, other)
    saved = install([signal.SIGTERM], handler)
    settle(saved, [signal.SIGHUP])  # the process goes on: given back, the other one untouched
    assert signal.getsignal(signal.SIGTERM) is other
    assert signal.getsignal(signal.SIGHUP) is other
    monkeypatch.setattr(signal_handlers._Process, "ends_with_run", True)
    saved = install([signal.SIGTERM], handler)
    settle(saved, [signal.SIGHUP])  # the process ends: both ignored while it exits
    assert signal.getsignal(signal.SIGTERM) is signal.SIG_IGN
    assert signal.getsignal(signal.SIGHUP) is signal.SIG_IGN
