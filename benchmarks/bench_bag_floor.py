"""Bag odometry against the storage floor, on a bag that diffbot did not write.

Run by hand: ``python benchmarks/bench_bag_floor.py [--samples N] [--rounds R] [--folder DIR]
[--cpu]``.

The bag: ``--samples`` sensor_msgs/JointState messages at 1 kHz, each serialized by rosbags'
own serializer and written by rosbags' rosbag2 writer (sqlite3), four joints each (the bundled
robot's two wheels with an arm and a caster joint between and after them), a ``base_link``
frame id and velocities, as a ``ros2 bag record`` of a robot's joint_state_broadcaster holds
them. It is made once in ``--folder`` (a few minutes for a million) and kept.

The compared sides, each a fresh process timed from launch to exit, run in turns round by
round (:mod:`interleave`):

- ``sqlite``: ``SELECT data FROM messages ORDER BY timestamp`` with :mod:`sqlite3`, every blob
  fetched: what any reader of the bag in stamp order pays at least;
- ``odom``: ``diffbot odom BAG -q``, the whole command (imports, the robot, the decoding, the
  odometry, the summary).

Goal: ``odom`` within 2 times ``sqlite``. The machine's load averages are printed beside the
figures.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from interleave import CPU_HELP, command, interleave

#: The floor: every message blob in stamp order, in a fresh Python.
SQLITE_FLOOR = """
import sqlite3, sys
from pathlib import Path
db = next(Path(sys.argv[1]).glob("*.db3"))
connection = sqlite3.connect(db.resolve().as_uri() + "?mode=ro&immutable=1", uri=True)
cursor = connection.execute("SELECT data FROM messages ORDER BY timestamp")
count = 0
while rows := cursor.fetchmany(65536):
    count += len(rows)
print(count)
"""
#: The joints of each message: the wheels with other joints beside them.
JOINTS = ("front_left_wheel_joint", "arm_joint", "front_right_wheel_joint", "caster_joint")
#: The first stamp (ns) and the period (ns) of the recording.
START_NS = 1_700_000_000_000_000_000
PERIOD_NS = 1_000_000


def make_bag(path: Path, samples: int) -> None:
    """Write the rosbags bag of ``samples`` joint states to ``path`` (not there yet)."""
    import numpy as np
    from rosbags.rosbag2 import Writer
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS2_HUMBLE)
    joint_state = store.types["sensor_msgs/msg/JointState"]
    header = store.types["std_msgs/msg/Header"]
    stamp = store.types["builtin_interfaces/msg/Time"]
    msgtype = joint_state.__msgtype__
    velocity = np.array([10.0, 0.0, 11.0, 0.0])
    effort = np.zeros(0)
    partial = path.with_name(path.name + ".partial")
    with Writer(partial, version=8) as writer:
        connection = writer.add_connection("/joint_states", msgtype, typestore=store)
        for k in range(samples):
            ns = START_NS + k * PERIOD_NS
            when = stamp(sec=ns // 10**9, nanosec=ns % 10**9)
            message = joint_state(
                header=header(stamp=when, frame_id="base_link"),
                name=list(JOINTS),
                position=np.array([0.01 * k, 0.3, 0.011 * k, 0.1]),
                velocity=velocity,
                effort=effort,
            )
            writer.write(connection, ns, store.serialize_cdr(message, msgtype))
    # The database keeps the name it was written under; the folder is renamed when whole.
    partial.rename(path)


def load() -> str:
    """The machine's load averages over 1, 5 and 15 minutes."""
    return "load " + "/".join(f"{x:.1f}" for x in os.getloadavg())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=1_000_000)
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument(
        "--folder", type=Path, default=Path(os.environ.get("TMPDIR", "/tmp")) / "diffbot-bench"
    )
    parser.add_argument("--cpu", action="store_true", help=CPU_HELP)
    args = parser.parse_args()
    args.folder.mkdir(parents=True, exist_ok=True)
    bag = args.folder / f"rosbags_joint_states_{args.samples}"
    if not bag.exists():
        began = time.perf_counter()
        make_bag(bag, args.samples)
        print(f"wrote {bag} with rosbags in {time.perf_counter() - began:.0f} s")
    env = dict(os.environ)
    # Timed as an installed package runs: from cached bytecode, not compiled afresh each run.
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    python = sys.executable
    sides = {
        "sqlite": command([python, "-c", SQLITE_FLOOR, str(bag)], env=env, cpu=args.cpu),
        "odom": command([python, "-m", "diffbot", "odom", str(bag), "-q"], env=env, cpu=args.cpu),
    }
    before = load()
    timings = interleave(sides, args.rounds)
    kind = "CPU time" if args.cpu else "launch to exit"
    print(f"bag odometry, {args.samples} joint states of 4 joints written by rosbags ({kind}):")
    for name in sides:
        print(f"  {name:<7} {timings.median(name):7.2f} s")
    print(
        f"  odom / sqlite: {timings.ratio('odom', 'sqlite').describe()} (goal <= 2; "
        f"{before} before, {load()} after)"
    )


if __name__ == "__main__":
    main()
