"""Each test process holds a DDS domain block no other holds: a forked child (a mutation run's
children share what their parent imported) and another process each take their own."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from live_graph import BLOCK, DOMAINS, domain, spare_domain


@pytest.mark.filterwarnings("ignore::DeprecationWarning")
def test_a_forked_child_and_another_process_take_domains_of_their_own() -> None:
    mine = domain()
    assert domain() == mine  # held for the process's life
    assert os.environ["ROS_DOMAIN_ID"] == str(mine)
    read, write = os.pipe()
    hold, release = os.pipe()
    pid = os.fork()
    if pid == 0:  # the child: a file lock, a write, then it holds its block until told
        try:
            os.write(write, str(domain()).encode())
            os.read(hold, 1)
        finally:
            os._exit(0)
    os.close(write)
    child = int(os.read(read, 16))
    try:
        other = subprocess.run(
            [sys.executable, "-c", "import live_graph; print(live_graph.domain())"],
            cwd=Path(__file__).parent.parent,
            capture_output=True,
            text=True,
            timeout=60,
            check=True,
        )
    finally:
        os.write(release, b"x")
        os.waitpid(pid, 0)
        for fd in (read, hold, release):
            os.close(fd)
    taken = [mine, child, int(other.stdout)]
    assert len(set(taken)) == 3, taken
    for first in taken:
        assert 1 <= first <= DOMAINS - BLOCK + 1
        assert (first - 1) % BLOCK == 0
    assert spare_domain(BLOCK - 1) == mine + BLOCK - 1
