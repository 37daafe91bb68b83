"""Shared fixtures: a DDS domain of its own, an isolated parameter cache, the bundled robot, a CLI
runner."""

from __future__ import annotations

import os
import signal
from collections.abc import Iterator
from pathlib import Path

import pytest
from click.testing import CliRunner
from hypothesis import settings
from live_graph import domain

import diffbot

# Examples are judged by what they compute; time is bounded where it is the point (the readers'
# linear-time tests, the CPU bounds of the corpus), not by a wall-clock deadline per example that
# a busy machine overruns.
settings.register_profile("diffbot", deadline=None)
settings.load_profile("diffbot")


@pytest.fixture(autouse=True, scope="session")
def _signals_as_in_a_terminal() -> Iterator[None]:
    """SIGINT, SIGTERM and SIGHUP act as they do for a command typed at a terminal, also when
    the tests run in the background (`pytest &` ignores SIGINT, `nohup` SIGHUP): the live tests
    stop nodes, theirs and those they start (which inherit the dispositions), with signals."""
    saved = {}
    for name, action in (
        ("SIGINT", signal.default_int_handler),
        ("SIGTERM", signal.SIG_DFL),
        ("SIGHUP", signal.SIG_DFL),
    ):
        signum = getattr(signal, name, None)
        if signum is not None and signal.getsignal(signum) is signal.SIG_IGN:
            saved[signum] = signal.signal(signum, action)
    yield
    for signum, previous in saved.items():
        signal.signal(signum, previous)


@pytest.fixture(autouse=True, scope="session")
def loopback_domain() -> Iterator[int]:
    """Every test talks DDS, if at all, on loopback in a domain of its own: one no other test
    process on the machine holds (:func:`live_graph.domain`), with discovery kept on the machine
    (ROS_LOCALHOST_ONLY=1: interface lo, no multicast, the local peers by unicast). Processes
    the tests start inherit both, so a command run as a help or doc example never meets
    another run's nodes."""
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


@pytest.fixture(autouse=True, scope="session")
def _isolated_cache(tmp_path_factory: pytest.TempPathFactory) -> Iterator[None]:
    """Keep the parameter cache of the tests out of the user's home."""
    mp = pytest.MonkeyPatch()
    mp.setenv("DIFFBOT_CACHE_DIR", str(tmp_path_factory.mktemp("cache")))
    mp.delenv("DIFFBOT_NO_CACHE", raising=False)
    mp.delenv("AMENT_PREFIX_PATH", raising=False)
    # A process that has loaded NumPy derives parameters itself: the tests' thousands of
    # descriptions would each start a child otherwise (tests/urdf/test_cache.py runs the child).
    import numpy  # noqa: F401

    yield
    mp.undo()


@pytest.fixture(autouse=True)
def _warnings_never_shown(monkeypatch: pytest.MonkeyPatch) -> None:
    """Each test starts with no description's warnings shown before (the marks of a test that
    runs a command twice stay its own)."""
    import uuid

    from diffbot.commands import said_once

    monkeypatch.setattr(said_once, "SHOWN_FOLDER", f"warned-{uuid.uuid4().hex}")


@pytest.fixture(scope="session")
def params() -> diffbot.DiffDriveParams:
    """The bundled diffbot: r = 0.035 m, b = 0.135 m, 50 rpm."""
    return diffbot.load_params()


@pytest.fixture
def runner() -> CliRunner:
    """A click test runner (stdout and stderr kept apart)."""
    return CliRunner()


@pytest.fixture
def write(tmp_path: Path) -> object:
    """Write a text file under tmp_path and return its path."""

    def _write(name: str, text: str) -> Path:
        path = tmp_path / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
        return path

    return _write
