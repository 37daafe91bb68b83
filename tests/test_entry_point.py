"""The command line's entry point holds the ending signals from its first step: one that comes
while its modules load is acted on by the command as a later one would be (Ctrl-C aborts with
exit code 130, SIGTERM ends the run with 143), never a traceback from the middle of an import;
nor from a class made later in the run, which Python 3.11 reports as a RuntimeError."""

from __future__ import annotations

import os
import signal
import time
from importlib.metadata import entry_points

import pytest
from entry import ENDINGS, Ending, signalled, started_gated
from live_graph import PATIENCE


def test_the_console_script_is_the_entry_point_that_holds_the_signals() -> None:
    (script,) = entry_points(group="console_scripts", name="diffbot")
    assert script.value == "diffbot.__main__:run"


@pytest.mark.parametrize("ending", ENDINGS)
def test_a_signal_while_the_command_line_loads_ends_the_run_as_a_later_one(ending: Ending) -> None:
    signum, code, stderr = ending
    returncode, out, err = signalled(signum, "plan", "straight 1")
    assert "Traceback" not in err
    # After Ctrl-C's "^C" on a terminal, click starts a new line.
    assert (returncode, out, err.strip()) == (code, "", stderr)


@pytest.mark.parametrize("ending", ENDINGS)
def test_a_second_signal_while_one_is_held_ends_the_process_at_once(ending: Ending) -> None:
    """The first waits for the run to act on it; whoever sends a second insists."""
    second, code, stderr = ending
    process = started_gated("plan", "straight 1", linger=PATIENCE)
    try:
        process.send_signal(signal.SIGTERM)
        assert process.stdout is not None
        assert process.stdout.readline() == "held\n"
        process.send_signal(second)
        out, err = process.communicate(timeout=PATIENCE / 2)  # not after the linger
    finally:
        process.kill()
    assert (process.returncode, out, err.strip()) == (code, "", stderr)


class _Signalling:
    """A descriptor whose ``__set_name__`` (run as a class that holds it is made, as in an
    import) has the process sent ``signum``: the handler's exception is raised inside it."""

    def __init__(self, signum: int) -> None:
        self.signum = signum

    def __set_name__(self, owner: type, name: str) -> None:
        os.kill(os.getpid(), self.signum)
        time.sleep(PATIENCE)  # the handler runs before this ends


@pytest.mark.parametrize("ending", ENDINGS)
def test_a_signal_while_a_command_makes_a_class_ends_the_run_as_anywhere_else(
    ending: Ending, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Python 3.11 wraps what ``__set_name__`` raises in a RuntimeError: the run still ends as
    the signal says, not with a traceback."""
    from click.testing import CliRunner

    from diffbot import kinematics
    from diffbot.cli import main

    signum, code, stderr = ending

    def inverse(*args: object) -> object:
        type("Loaded", (), {"field": _Signalling(signum)})
        raise AssertionError("the signal did not end the run")

    monkeypatch.setattr(kinematics, "inverse", inverse)
    result = CliRunner().invoke(main, ["ik", "0.1", "0.5"])
    assert not isinstance(result.exception, RuntimeError), result.exception
    assert (result.exit_code, result.stdout, result.stderr.strip()) == (code, "", stderr)


def test_clicks_own_abort_is_still_aborted_and_a_cause_that_loops_ends(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """click turns an end of input into its Abort, a RuntimeError too; and an exception whose
    causes loop is raised as it is, not followed for ever."""
    from click.testing import CliRunner

    from diffbot import kinematics
    from diffbot.cli import main

    def closed(*args: object) -> object:
        raise EOFError

    monkeypatch.setattr(kinematics, "inverse", closed)
    result = CliRunner().invoke(main, ["ik", "0.1", "0.5"])
    assert (result.exit_code, result.stderr.strip()) == (130, "error: aborted")

    looped = RuntimeError("looped")
    looped.__cause__ = ValueError("and back")
    looped.__cause__.__cause__ = looped

    def loops(*args: object) -> object:
        raise looped

    monkeypatch.setattr(kinematics, "inverse", loops)
    result = CliRunner().invoke(main, ["ik", "0.1", "0.5"])
    assert result.exception is looped
