"""CPU time per joint state in ``node odom``: this tree's position and velocity paths against a
git revision's position path.

Each side is a fresh process importing its own tree's package: it makes an ``OdometryNode``
(no /tf) in a domain of its own on loopback, reads ``--messages`` pre-encoded JointState
payloads as DDS hands them over (the node's ``JointStateReader``, then its sample handler:
check, integrate, encode, write) and prints the thread's CPU time per message
(``time.thread_time``; DDS's wait and take are not in it). The sides take turns round by round
(the order reversed every other round) after one untimed round; the report gives each side's
median and the per-round ratios to the revision's position path.

Run by hand: ``python benchmarks/bench_node_messages.py [--baseline REV] [--rounds N]
[--messages N]``.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
from collections.abc import Callable

from checkout import Tree, revision_tree, working_tree
from interleave import interleave

#: What each side runs: argv[1] is the feedback ("position" or "velocity"), argv[2] the count.
SNIPPET = """
import sys, time
from diffbot.live.cdr import JointStateReader, encode_joint_state
from diffbot.live.odometry import OdometryNode, OdometrySettings
from diffbot.kinematics import DiffDriveParams

feedback, count = sys.argv[1], int(sys.argv[2])
params = DiffDriveParams(wheel_radius=0.035, wheel_separation=0.135)
names = ["front_left_wheel_joint", "front_right_wheel_joint"]
t0 = time.time_ns() - 3600 * 10**9
payloads = [
    encode_joint_state(t0 + k * 10**6, "", names, [0.001 * k, 0.002 * k], [1.0, 2.0])
    for k in range(count)
]
if feedback == "position":
    settings, reader = OdometrySettings(publish_tf=False), JointStateReader()
else:
    settings = OdometrySettings(publish_tf=False, feedback=feedback)
    reader = JointStateReader(feedback)
with OdometryNode(params, settings) as node:
    handle, read = node._on_sample, reader.read
    start = time.thread_time()
    for payload in payloads:
        handle(read(payload))
    spent = time.thread_time() - start
    assert node.odometry.samples == count, node.counts
print(spent / count)
"""


def side(tree: Tree, feedback: str, messages: int) -> Callable[[], float]:
    """A side: one process on ``tree``'s package; its CPU time per message (s)."""
    environment = dict(os.environ)
    environment["PYTHONPATH"] = str(tree.root)
    environment["ROS_LOCALHOST_ONLY"] = "1"
    environment.setdefault("ROS_DOMAIN_ID", str(1 + os.getpid() % 101))

    def run() -> float:
        done = subprocess.run(
            [sys.executable, "-c", SNIPPET, feedback, str(messages)],
            cwd=tree.root,
            env=environment,
            capture_output=True,
            text=True,
            check=False,
        )
        if done.returncode != 0:
            raise SystemExit(f"{tree.label} {feedback}: {done.stderr.strip()}")
        return float(done.stdout)

    return run


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--baseline", default="HEAD~1", help="git revision compared against")
    parser.add_argument("--rounds", type=int, default=7)
    parser.add_argument("--messages", type=int, default=20_000)
    options = parser.parse_args()
    here = working_tree()
    with revision_tree(options.baseline) as before:
        sides = {
            f"{before.label} position": side(before, "position", options.messages),
            f"{here.label} position": side(here, "position", options.messages),
            f"{here.label} velocity": side(here, "velocity", options.messages),
        }
        timings = interleave(sides, options.rounds)
    base = f"{before.label} position"
    print(f"load {os.getloadavg()[0]:.1f}, {options.messages} messages a round")
    for name in sides:
        line = f"{name:40} {timings.median(name) * 1e6:6.2f} us/message"
        if name != base:
            line += f"   / {base}: {timings.ratio(name, base).describe()}"
        print(line)


if __name__ == "__main__":
    main()
