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


@pytest.fixture
def no_hold() -> Iterator[None]:
    """Whatever a test holds is released after it."""
    yield
    signal_handlers.release()


def test_a_held_signal_is_only_recorded_and_the_first_is_acted_on_after_release(
    no_hold: None,
) -> None:
    """As the command line's first step: a signal while its modules load raises nothing (no
    traceback from the middle of an import); the run takes the first one after."""
    calls: list[int] = []
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    signal.signal(signal.SIGHUP, signal.SIG_DFL)
    signal_handlers.hold(SIGNALS)
    signal.raise_signal(signal.SIGTERM)  # under the default action it would end this process
    saved = install(SIGNALS, lambda signum, frame: calls.append(signum))
    assert saved == {signal.SIGTERM: signal.SIG_DFL, signal.SIGHUP: signal.SIG_DFL}
    assert calls == []  # installed during the hold: takes effect at its end
    assert signal_handlers.release() == signal.SIGTERM
    signal.raise_signal(signal.SIGHUP)
    assert calls == [signal.SIGHUP]
    assert signal_handlers.release() is None  # nothing held any more
    restore(saved)
    assert signal.getsignal(signal.SIGTERM) is signal.SIG_DFL


def test_handlers_put_back_during_a_hold_are_the_ones_its_release_leaves(no_hold: None) -> None:
    signal.signal(signal.SIGTERM, other)
    signal.signal(signal.SIGHUP, signal.SIG_IGN)  # as under nohup: not held, stays ignored
    signal_handlers.hold(SIGNALS)
    assert signal.getsignal(signal.SIGHUP) is signal.SIG_IGN
    restore(install(SIGNALS, handler))
    assert signal_handlers.release() is None
    assert signal.getsignal(signal.SIGTERM) is other
    assert signal.getsignal(signal.SIGHUP) is signal.SIG_IGN


def test_a_signal_is_handed_on_as_its_handler_would_take_it(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    calls: list[int] = []
    signal_handlers.hand_on(signal.SIGTERM, lambda signum, frame: calls.append(signum))
    assert calls == [signal.SIGTERM]
    raised: list[int] = []
    monkeypatch.setattr(signal, "raise_signal", raised.append)
    signal_handlers.hand_on(signal.SIGTERM, signal.SIG_DFL)  # the default action: again
    signal_handlers.hand_on(signal.SIGHUP, signal.SIG_IGN)  # ignored: nothing
    assert raised == [signal.SIGTERM]


def test_a_second_signal_during_a_hold_ends_the_process_at_once(
    monkeypatch: pytest.MonkeyPatch, capfd: pytest.CaptureFixture[str], no_hold: None
) -> None:
    class ExitedError(Exception):
        pass

    def exit_(code: int) -> None:
        raise ExitedError(code)

    monkeypatch.setattr(signal_handlers.os, "_exit", exit_)
    signal_handlers.hold([signal.SIGINT, signal.SIGTERM])
    signal.raise_signal(signal.SIGTERM)
    with pytest.raises(ExitedError) as exited:
        signal.raise_signal(signal.SIGINT)
    assert exited.value.args == (128 + signal.SIGINT,)
    assert capfd.readouterr().err == "\nerror: aborted\n"  # as a Ctrl-C during a run says
    with pytest.raises(ExitedError) as exited:
        signal.raise_signal(signal.SIGTERM)
    assert exited.value.args == (128 + signal.SIGTERM,)
    assert capfd.readouterr().err == ""


def test_acting_on_a_held_signal_gives_it_to_the_handler_now_in_place(no_hold: None) -> None:
    calls: list[int] = []
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    signal_handlers.hold([signal.SIGTERM])
    signal_handlers.act_on_held()  # nothing came: nothing done, the hold ended
    assert signal.getsignal(signal.SIGTERM) is signal.SIG_DFL
    signal_handlers.hold([signal.SIGTERM])
    install([signal.SIGTERM], lambda signum, frame: calls.append(signum))
    signal.raise_signal(signal.SIGTERM)
    assert calls == []
    signal_handlers.act_on_held()
    assert calls == [signal.SIGTERM]
    assert signal_handlers.release() is None
