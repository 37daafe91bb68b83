"""Progress bars: on stderr when it is a terminal (a pseudo-terminal here), never when stderr
is a pipe, and not with --quiet."""

from __future__ import annotations

import os
import pty
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.skipif(sys.platform == "win32", reason="pseudo-terminals are POSIX")

SIMULATE = ["simulate", "straight 1 100s", "--rate", "2000"]


def stderr_of(args: list[str], cwd: Path, *, terminal: bool) -> tuple[int, str]:
    """Run ``diffbot ARGS`` with stderr on a pseudo-terminal (or a pipe): exit code, stderr."""
    command = [sys.executable, "-m", "diffbot", *args]
    if not terminal:
        done = subprocess.run(command, cwd=cwd, capture_output=True, text=True, check=False)
        return done.returncode, done.stderr
    master, slave = pty.openpty()
    try:
        process = subprocess.Popen(command, cwd=cwd, stdout=subprocess.DEVNULL, stderr=slave)
        os.close(slave)
        chunks = []
        while True:
            try:
                data = os.read(master, 65536)
            except OSError:  # the other end closed: EIO on Linux
                break
            if not data:
                break
            chunks.append(data)
        code = process.wait()
    finally:
        os.close(master)
    return code, b"".join(chunks).decode("utf-8", "replace")


def test_simulate_shows_progress_on_a_terminal(tmp_path: Path) -> None:
    code, err = stderr_of([*SIMULATE, "--out", "a.csv"], tmp_path, terminal=True)
    assert code == 0
    assert "simulate" in err
    assert "100%" in err
    assert "200001/200001" in err  # samples done of all
    assert "samples/s" in err  # the rate


def test_odom_shows_progress_on_a_terminal_and_never_in_a_pipe(tmp_path: Path) -> None:
    code, _ = stderr_of([*SIMULATE, "--out", "a.csv"], tmp_path, terminal=False)
    assert code == 0
    code, err = stderr_of(["odom", "a.csv", "--out", "o.csv"], tmp_path, terminal=True)
    assert code == 0
    assert "a.csv" in err
    assert "100%" in err
    assert "B/s" in err
    code, err = stderr_of(["odom", "a.csv"], tmp_path, terminal=False)
    assert (code, err) == (0, "")


def test_quiet_silences_the_bar_on_a_terminal(tmp_path: Path) -> None:
    code, err = stderr_of([*SIMULATE, "--out", "a.csv", "--quiet"], tmp_path, terminal=True)
    assert (code, err) == (0, "")


def test_a_followed_simulation_shows_progress_on_a_terminal(tmp_path: Path) -> None:
    # The run streams chunk by chunk; the bar's length is the most samples it may take.
    args = ["simulate", "straight 1 20s", "--rate", "2000", "--follow", "--motor-lag", "0.1"]
    code, err = stderr_of([*args, "--out", "a.csv"], tmp_path, terminal=True)
    assert code == 0, err
    assert "simulate" in err
    assert "samples/s" in err
    rows = (tmp_path / "a.csv").read_text(encoding="utf-8").count("\n") - 1
    assert rows > 40_000  # 20 s at 2 kHz, and the arrival
    code, err = stderr_of([*args, "--out", "b.csv", "--quiet"], tmp_path, terminal=True)
    assert code == 0
    assert "samples/s" not in err
