"""How soon a Fast DDS participant sees a diffbot node leave (a check by hand: it needs eProsima
Fast DDS, Debian's ``libfastrtps-dev``, and ``g++``).

    python tools/fastdds_leave.py [--domain N] [--rounds K]

Each round starts a Fast DDS peer (tools/fastdds_peer.cpp, built on first use into .fastdds/),
then a diffbot node in a process of its own, ended in two ways: ``diffbot node odom --duration 2``
as a user runs it, and a process that ends at once (``os._exit``) right after its node is
destroyed. It prints, for each, the seconds from the process's end to the peer's event:
``removed`` (the node said it left) within a fraction of a second, or ``dropped`` (Fast DDS
waited for the lease to run out, about 10 s).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
BUILT = HERE.parent / ".fastdds" / "fastdds_peer"

AT_ONCE = """
import os, time
from diffbot.live.transport import Node
node = Node("leaver")
time.sleep(1.5)
node.destroy_node()
os._exit(0)
"""


def peer() -> Path:
    if not BUILT.exists():
        BUILT.parent.mkdir(exist_ok=True)
        source = HERE / "fastdds_peer.cpp"
        command = ["g++", "-O1", "-o", str(BUILT), str(source), "-lfastrtps", "-lfastcdr"]
        subprocess.run(command, check=True)
    return BUILT


def round_trip(domain: int, ending: list[str]) -> str:
    env = {k: v for k, v in os.environ.items() if not k.startswith(("ROS_", "CYCLONEDDS"))}
    env["ROS_DOMAIN_ID"] = str(domain)
    watcher = subprocess.Popen([str(peer()), str(domain), "14"], stdout=subprocess.PIPE, text=True)
    assert watcher.stdout is not None
    if watcher.stdout.readline().split()[1:] != ["ready"]:
        return "the Fast DDS peer did not start"
    node = subprocess.run(ending, env=env, capture_output=True, text=True, check=False)
    ended = time.monotonic()  # CLOCK_MONOTONIC, as the peer's steady_clock on Linux
    out, _ = watcher.communicate(timeout=60)
    events = [line.split() for line in out.splitlines()]
    gone = [f"{what} {float(t) - ended:+.3f} s" for t, what in events if what != "discovered"]
    return f"exit {node.returncode}: " + (", ".join(gone) or "never seen to leave")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--domain", type=int, default=57)
    parser.add_argument("--rounds", type=int, default=2)
    args = parser.parse_args()
    odom = [sys.executable, "-m", "diffbot", "node", "odom", "--duration", "2"]
    endings = {
        "diffbot node odom --duration 2": odom,
        "a process that ends at once": [sys.executable, "-c", AT_ONCE],
    }
    for _ in range(args.rounds):
        for name, ending in endings.items():
            print(f"{name}: {round_trip(args.domain, ending)}", flush=True)


if __name__ == "__main__":
    main()
