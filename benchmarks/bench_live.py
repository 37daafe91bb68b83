"""Live node benchmarks on loopback, in a DDS domain of their own.

Run by hand: ``python benchmarks/bench_live.py [--seconds S] [--rates HZ,HZ,...]
[--memory-minutes M] [--skip-drive] [--skip-odom]``.

(a) ``node odom`` throughput and latency: a publisher sends JointState messages at each rate for
    ``--seconds`` to a ``diffbot node odom`` process; the figures are the share of joint states
    that came back as odometry (loss), and the latency from a joint state's publication (its
    header stamp, the wall clock) to its odometry's receipt here, p50 and p99. The peer, run in
    turns with the node (interleaved, order reversed every other round): a bare relay process
    that republishes each JointState as it comes, so the ratio is what the odometry costs over
    DDS's own round trip. Goals: no loss at 5 kHz; p99 under 2 ms at 1 kHz.
(b) ``drive`` timing over Trajectory A at 20 Hz (40 s): the p99 lateness of each publication
    against its schedule and the error of the total duration. Goals: p99 under 1 ms; total
    within 2 ms. The yardstick, run just after in the same way: a bare Python process that
    sleeps until each time of the same schedule and notes how late it wakes (no DDS, no
    work): the scheduler's own lateness, which no publisher on the machine goes below.
(c) Memory of a ``node odom`` process fed at 1 kHz for ``--memory-minutes``: its resident size
    sampled every 10 s; flat means the last sample within 5 % of the first after warm-up.
"""

from __future__ import annotations

import argparse
import os
import statistics
import struct
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
# Domains 1-101: a domain's ports (7400 + 250 per domain) stay below Linux's ephemeral range.
os.environ.setdefault("ROS_DOMAIN_ID", str(1 + os.getpid() % 101))
os.environ["ROS_LOCALHOST_ONLY"] = "1"

from diffbot.live import types
from diffbot.live.cdr import encode_joint_state
from diffbot.live.drive import Driver
from diffbot.live.messages import now_ns
from diffbot.live.transport import Node, QosProfile

NAMES = ["front_left_wheel_joint", "front_right_wheel_joint"]
STAMP = struct.Struct("<iI")
DEEP = QosProfile(reliable=False, depth=100_000)
#: The peer: for each JointState on joint_states, an Odometry of fixed bytes on odom (its header
#: stamp copied from the joint state's, so that the bench reads the latency the same way), with
#: the node's QoS on both ends: the cost of DDS's own round trip and nothing else.
RELAY = """
from diffbot.live import types
from diffbot.live.cdr import encode_odometry
from diffbot.live.odometry import JOINT_STATES
from diffbot.live.transport import Node
body = encode_odometry(0, "odom", "base_link", (0.0,) * 7, (0.0,) * 36, (0.0,) * 6, (0.0,) * 36)
head, tail = body[:4], body[12:]
with Node("relay") as node:
    out = node.create_publisher(types.Odometry, "odom")
    write = out.publish_serialized
    node.create_subscription(
        types.JointState,
        "joint_states",
        lambda data: write(head + data[4:12] + tail),
        JOINT_STATES,
        bytes,
    )
    node.spin()
"""


def joint_state(k: int) -> bytes:
    """The k-th joint state of a robot rolling forward, stamped now, serialized."""
    angle = 0.001 * k
    return encode_joint_state(now_ns(), "", NAMES, (angle, angle))


def stamp_of(data: bytes) -> int:
    """The header stamp (ns) of a serialized message that starts with a std_msgs/Header."""
    sec, nanosec = STAMP.unpack_from(data, 4)
    return int(sec) * 1_000_000_000 + int(nanosec)


def pace(due: float) -> None:
    """Wait for the monotonic clock to reach ``due``: sleeping (which lets the receiving thread
    run) until the last 0.2 ms."""
    left = due - time.monotonic()
    if left > 0.0002:
        time.sleep(left - 0.0002)
    while time.monotonic() < due:
        pass


def start(kind: str) -> subprocess.Popen[bytes]:
    """The node under test (``odom``) or the peer (``relay``) as a process."""
    if kind == "odom":
        args = [sys.executable, "-m", "diffbot", "node", "odom", "--no-tf", "--quiet"]
    else:
        args = [sys.executable, "-c", RELAY]
    return subprocess.Popen(args, env=os.environ.copy(), stderr=subprocess.DEVNULL)


def feed(kind: str, rate: float, seconds: float) -> tuple[float, list[float]]:
    """Publish joint states at ``rate`` for ``seconds`` to a fresh ``kind`` process; the share
    lost and the latencies (s) of those that came back.

    Before the measured messages, probes go out every 20 ms until one comes back: a writer
    learns of a reader before that reader has learnt of the writer, and a best-effort reader
    drops what comes from a writer it does not know yet, so only an answer shows that the whole
    path has matched. Answers to probes (stamped before the first measured message) are not
    counted."""
    process = start(kind)
    latencies: list[float] = []
    count = 0
    try:
        with Node("bench") as node:
            first = [0]

            def back(stamp: int) -> None:
                if stamp >= first[0]:
                    latencies.append((now_ns() - stamp) / 1e9)

            # Only the header stamp is read back: the bench's own decoding stays out of the way.
            back_sub = node.create_subscription(types.Odometry, "odom", back, DEEP, stamp_of)  # type: ignore[arg-type]
            publisher = node.create_publisher(
                types.JointState, "joint_states", QosProfile(depth=1000)
            )
            assert publisher.wait_for_subscribers(30.0), f"{kind} did not come up"
            assert back_sub.wait_for_publishers(30.0), f"{kind} does not answer"
            first[0] = 1 << 62  # probes: none counted, the first answer seen
            seen = [False]
            node.create_subscription(
                types.Odometry, "odom", lambda _: seen.__setitem__(0, True), DEEP, bytes
            )
            node.start()
            end = time.monotonic() + 30.0
            k = 0
            while not seen[0]:
                assert time.monotonic() < end, f"{kind} never answered a probe"
                publisher.publish_serialized(joint_state(k))
                k += 1
                time.sleep(0.02)
            time.sleep(0.1)
            first[0] = now_ns()
            count = int(rate * seconds)
            begin = time.monotonic()
            for j in range(count):
                pace(begin + j / rate)
                publisher.publish_serialized(joint_state(k + j))
            end = time.monotonic() + 2.0
            while len(latencies) < count and time.monotonic() < end:
                time.sleep(0.01)
            node.shutdown()
    finally:
        process.terminate()
        process.wait(timeout=30)
    return 1.0 - len(latencies) / max(count, 1), latencies


def percentile(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(q * len(ordered)))] if ordered else float("nan")


def load() -> str:
    """The machine's load averages over 1, 5 and 15 minutes, for every figure printed."""
    return "load " + "/".join(f"{x:.1f}" for x in os.getloadavg())


def bench_odom(rates: list[float], seconds: float, rounds: int) -> None:
    print(f"(a) node odom: {seconds:g} s per rate, {rounds} interleaved rounds against a relay")
    clean: dict[str, float] = {"odom": 0.0, "relay": 0.0}
    for rate in rates:
        results: dict[str, list[tuple[float, float, float]]] = {"odom": [], "relay": []}
        for r in range(rounds):
            order = ["odom", "relay"] if r % 2 == 0 else ["relay", "odom"]
            for kind in order:
                loss, lat = feed(kind, rate, seconds)
                results[kind].append((loss, percentile(lat, 0.5), percentile(lat, 0.99)))
        for kind, rows in results.items():
            loss = max(row[0] for row in rows)
            if loss == 0.0 and clean[kind] == rate_below(rates, rate):
                clean[kind] = rate
            p50 = statistics.median(row[1] for row in rows)
            p99 = statistics.median(row[2] for row in rows)
            print(
                f"  {rate:7.0f} Hz {kind:5s}: loss {loss * 100:5.2f} % (worst round), "
                f"latency p50 {p50 * 1e3:.3f} ms, p99 {p99 * 1e3:.3f} ms"
            )
        ratio = statistics.median(
            o[2] / r[2] for o, r in zip(results["odom"], results["relay"], strict=True)
        )
        print(f"  {rate:7.0f} Hz p99 odom / relay: {ratio:.2f} ({load()})")
    print(
        f"  highest rate without loss in every round: odom {clean['odom']:.0f} Hz, relay "
        f"{clean['relay']:.0f} Hz, odom / relay "
        f"{clean['odom'] / clean['relay'] if clean['relay'] else float('nan'):.2f} ({load()})"
    )


def rate_below(rates: list[float], rate: float) -> float:
    """The rate measured before ``rate`` (0 for the first): a side's loss-free rate only rises
    through rates it met one after the other."""
    index = rates.index(rate)
    return rates[index - 1] if index else 0.0


#: A subscriber in a process of its own: the monotonic time each command on cmd_vel arrived,
#: one per line on stdout once ``count`` have come (or the time is up).
SINK = """
import sys, time
from diffbot.live import types
from diffbot.live.transport import Node
count, seconds = int(sys.argv[1]), float(sys.argv[2])
arrivals = []
with Node("sink") as node:
    sub = node.create_subscription(
        types.Twist, "cmd_vel", lambda m: arrivals.append(time.monotonic())
    )
    sub.wait_for_publishers(60.0)
    print("ready", flush=True)
    end = time.monotonic() + seconds
    while len(arrivals) < count and time.monotonic() < end:
        node.spin_once(0.05)
print("\\n".join(repr(t) for t in arrivals))
"""


def bench_drive() -> None:
    """Trajectory A at 20 Hz: how late each command arrives at a subscriber in another process,
    against the drive's schedule (the monotonic clock is the same for both processes)."""
    from diffbot.planfile import parse_plan
    from diffbot.ramps import sampled
    from diffbot.trajectory import EXAMPLES, plan
    from diffbot.urdf import load_params

    stream = sampled(plan(parse_plan(EXAMPLES["A"]), load_params())).commands(20.0)
    count = int(stream.times.size) + 1  # and the stop
    sink = subprocess.Popen(
        [sys.executable, "-c", SINK, str(count), str(float(stream.times[-1]) + 60.0)],
        env=os.environ.copy(),
        stdout=subprocess.PIPE,
        text=True,
    )
    starts: list[float] = []

    class Timed(Driver):
        def _drive_piece(self, piece, start, lateness, progress):  # type: ignore[no-untyped-def]
            starts.append(start)
            return super()._drive_piece(piece, start, lateness, progress)

    with Timed(stream) as driver:
        assert driver.wait_for_subscriber(30.0)
        assert sink.stdout is not None
        # The sink's reader has learnt of this writer too: nothing is dropped as unknown.
        assert sink.stdout.readline().strip() == "ready"
        report = driver.drive()
    out, _ = sink.communicate(timeout=120)
    arrivals = [float(line) for line in out.split()]
    assert len(arrivals) == count, f"{count - len(arrivals)} commands lost"
    late = sorted(
        t - (starts[0] + float(due)) for t, due in zip(arrivals, stream.times, strict=False)
    )
    print(
        f"(b) drive Trajectory A at 20 Hz: {report.sent} commands over {stream.times[-1]:g} s; "
        f"{len(arrivals)} arrived; lateness at the subscriber p50 "
        f"{percentile(late, 0.5) * 1e3:.3f} ms, p99 {percentile(late, 0.99) * 1e3:.3f} ms, max "
        f"{late[-1] * 1e3:.3f} ms; at the publisher p50 {report.percentile(0.5) * 1e3:.3f} ms, "
        f"p99 {report.percentile(0.99) * 1e3:.3f} ms; total duration error "
        f"{report.duration_error * 1e3:.3f} ms ({load()})"
    )
    bench_wakeups(float(stream.times[1] - stream.times[0]), count)


WAKER = """
import sys, time
period, count = float(sys.argv[1]), int(sys.argv[2])
late = []
start = time.monotonic() + period
for k in range(count):
    due = start + k * period
    ahead = due - time.monotonic()
    if ahead > 0:
        time.sleep(ahead)
    late.append(time.monotonic() - due)
print(" ".join(repr(t) for t in late))
"""


def bench_wakeups(period: float, count: int) -> None:
    """The yardstick of (b): a bare process's lateness waking up on the same schedule."""
    done = subprocess.run(
        [sys.executable, "-c", WAKER, repr(period), str(count)],
        capture_output=True,
        text=True,
        check=True,
    )
    late = sorted(float(t) for t in done.stdout.split())
    print(
        f"(b) yardstick, a bare process waking on the same schedule: {count} wake-ups; lateness "
        f"p50 {percentile(late, 0.5) * 1e3:.3f} ms, p99 {percentile(late, 0.99) * 1e3:.3f} ms, "
        f"max {late[-1] * 1e3:.3f} ms ({load()})"
    )


def rss(pid: int) -> int:
    """Resident size (kB) of a process, from /proc."""
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1])
    return 0


def bench_memory(minutes: float) -> None:
    process = start("odom")
    samples: list[int] = []
    try:
        with Node("feeder") as node:
            publisher = node.create_publisher(types.JointState, "joint_states")
            assert publisher.wait_for_subscribers(30.0)
            begin = time.monotonic()
            next_sample = begin
            k = 0
            while time.monotonic() - begin < minutes * 60.0:
                pace(begin + k / 1000.0)
                publisher.publish_serialized(joint_state(k))
                k += 1
                if time.monotonic() >= next_sample:
                    samples.append(rss(process.pid))
                    next_sample += 10.0
    finally:
        process.terminate()
        process.wait(timeout=30)
    shown = ", ".join(f"{s / 1024:.1f}" for s in samples)
    warm = samples[min(1, len(samples) - 1)]
    print(
        f"(c) node odom at 1 kHz for {minutes:g} min, {k} joint states: resident MB every 10 s: "
        f"{shown}; last / after warm-up {samples[-1] / warm:.3f} ({load()})"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=3.0)
    parser.add_argument("--rates", default="1000,2000,3000,5000,7500,10000")
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--memory-minutes", type=float, default=10.0)
    parser.add_argument("--skip-drive", action="store_true")
    parser.add_argument("--skip-odom", action="store_true")
    args = parser.parse_args()
    print(f"domain {os.environ['ROS_DOMAIN_ID']}, loopback only, cpus {os.cpu_count()}")
    if not args.skip_odom:
        bench_odom([float(r) for r in args.rates.split(",")], args.seconds, args.rounds)
    if not args.skip_drive:
        bench_drive()
    if args.memory_minutes > 0:
        bench_memory(args.memory_minutes)


if __name__ == "__main__":
    main()
