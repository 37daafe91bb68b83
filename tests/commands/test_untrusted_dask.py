"""``odom --dask`` against malformed addresses and hostile schedulers: one ``error:`` line and
exit 2, within the timeout, never a traceback or a hang."""

from __future__ import annotations

import contextlib
import socket
import struct
import subprocess
import sys
import threading
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest
from cli_results import assert_one_error_line
from click.testing import CliRunner
from extras import need

from diffbot.cli import main
from diffbot.errors import RecordingError
from diffbot.fleet import dask_address

#: Longest a run against a hostile scheduler may take (s), with --dask-timeout 1.
QUICK = 30.0


@pytest.fixture
def inputs(tmp_path: Path) -> list[str]:
    paths = []
    for name in ("a.csv", "b.csv"):
        path = tmp_path / name
        path.write_text("time,left_wheel_joint,right_wheel_joint\n0,0,0\n1,1,1\n", "utf-8")
        paths.append(str(path))
    return paths


@pytest.mark.parametrize(
    ("address", "message"),
    [
        ("foo://127.0.0.1:8786", "unknown scheme 'foo'"),
        ("http://127.0.0.1:8786", "unknown scheme 'http'"),
        ("tcp://:8786", "the host is missing or malformed"),
        ("tcp://a b:8786", "the host is missing or malformed"),
        ("tcp://127.0.0.1:0", "the port must be a number from 1 to 65535"),
        ("tcp://127.0.0.1:65536", "the port must be a number from 1 to 65535"),
        ("tcp://127.0.0.1:" + "9" * 5000, "the port must be a number from 1 to 65535"),
        ("tcp://127.0.0.1:-1", "the port must be a number from 1 to 65535"),
        ("tcp://127.0.0.1:x", "the port must be a number from 1 to 65535"),
    ],
)
def test_a_malformed_address_is_one_error_line(
    inputs: list[str], address: str, message: str
) -> None:
    result = CliRunner().invoke(main, ["odom", *inputs, "--dask", address])
    assert_one_error_line(result, "--dask", message)


@pytest.mark.parametrize(
    ("given", "whole"),
    [
        ("127.0.0.1", "tcp://127.0.0.1:8786"),
        ("tcp://sched.example.org:9000", "tcp://sched.example.org:9000"),
        ("tls://[::1]:8786", "tls://[::1]:8786"),
        ("[fe80::1]", "tcp://[fe80::1]:8786"),
        ("inproc://10.0.0.1/123/1", "inproc://10.0.0.1/123/1"),
    ],
)
def test_addresses_dask_accepts_are_made_whole(given: str, whole: str) -> None:
    assert dask_address(given) == whole


def test_an_inproc_address_needs_its_parts() -> None:
    with pytest.raises(RecordingError, match="inproc address names HOST/PID/N"):
        dask_address("inproc://")


Serve = Callable[[socket.socket], None]


def _garbage(conn: socket.socket) -> None:
    conn.sendall(b"HTTP/1.1 200 OK\r\nContent-Length: 5000\r\n\r\n" + b"x" * 5000)


def _huge_frame(conn: socket.socket) -> None:
    conn.sendall(struct.pack("<Q", 2**62) + bytes(64))


def _bad_message(conn: socket.socket) -> None:
    # a well-framed message whose content is not msgpack
    conn.sendall(struct.pack("<QQQ", 24, 1, 8) + b"\xc1" * 8)


def _silent(conn: socket.socket) -> None:
    pass


def _hang_up(conn: socket.socket) -> None:
    conn.close()


@pytest.fixture
def server(request: pytest.FixtureRequest) -> Iterator[str]:
    """A tiny TCP server on 127.0.0.1 that answers every connection with ``request.param``."""
    serve: Serve = request.param
    listener = socket.socket()
    listener.bind(("127.0.0.1", 0))
    listener.listen()
    listener.settimeout(0.2)
    accepted: list[socket.socket] = []
    stop = threading.Event()

    def loop() -> None:
        while not stop.is_set():
            try:
                conn, _ = listener.accept()
            except OSError:
                continue
            accepted.append(conn)
            with contextlib.suppress(OSError):
                serve(conn)

    thread = threading.Thread(target=loop, daemon=True)
    thread.start()
    try:
        yield f"tcp://127.0.0.1:{listener.getsockname()[1]}"
    finally:
        stop.set()
        thread.join(timeout=5)
        for conn in accepted:
            conn.close()
        listener.close()


@pytest.mark.parametrize(
    ("server", "message"),
    [
        (_garbage, "cannot talk to the Dask scheduler at"),
        (_huge_frame, "it sent a message of absurd size"),
        (_bad_message, "a malformed answer"),
        (_silent, "did not answer within 1 s (--dask-timeout)"),
        (_hang_up, "cannot talk to the Dask scheduler at"),
    ],
    indirect=["server"],
)
def test_a_hostile_scheduler_is_one_error_line_within_the_timeout(
    inputs: list[str], server: str, message: str
) -> None:
    need("distributed")
    # A scheduler that answers, if only with nonsense, is given time to: on a busy machine its
    # answer may take longer than the second the silent one is given.
    timeout = "1" if "did not answer" in message else "10"
    start = time.monotonic()
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "diffbot",
            "odom",
            *inputs,
            "--dask",
            server,
            "--dask-timeout",
            timeout,
        ],
        capture_output=True,
        text=True,
        timeout=QUICK,
        check=False,
    )
    assert done.returncode == 2, done.stderr
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1, done.stderr
    assert lines[0].startswith("error: ")
    assert message in lines[0]
    assert done.stdout == ""
    assert time.monotonic() - start < QUICK


def test_the_dask_timeout_must_be_positive_and_finite(inputs: list[str]) -> None:
    for value in ("0", "nan", "inf", "-1"):
        result = CliRunner().invoke(main, ["odom", *inputs, "--dask-timeout", value])
        assert result.exit_code == 2, result.output
        assert "--dask-timeout" in result.stderr
