"""The live commands at the edges: bad input is one error line, a node ends on a signal with its
counts, the missing extra is named."""

from __future__ import annotations

import contextlib
import os
import random
import select
import signal
import subprocess
import sys
import time
from typing import Any

import pytest
from click.testing import CliRunner
from entry import ENDINGS, Ending, signalled
from live_graph import PATIENCE

from diffbot import signal_handlers
from diffbot.cli import main
from diffbot.live import types
from diffbot.live.transport import Node, QosProfile
from diffbot.wheel_commands import LEFT_TOPIC, RIGHT_TOPIC


def test_a_bad_domain_is_one_error_line() -> None:
    done = subprocess.run(
        [sys.executable, "-m", "diffbot", "node", "odom"],
        capture_output=True,
        text=True,
        env={"ROS_DOMAIN_ID": "300", "PATH": "/usr/bin:/bin"},
        timeout=60,
        check=False,
    )
    assert done.returncode == 2
    assert done.stderr == "error: ROS_DOMAIN_ID must be a whole number from 0 to 232, got '300'\n"


@pytest.mark.parametrize("command", [("node", "odom"), ("node", "ik"), ("node", "robot")])
@pytest.mark.parametrize("duration", ["1e300", "0", "-1", "nan"])
@pytest.mark.timeout(30)  # an accepted 1e300 would run the node for good
def test_a_duration_past_the_longest_plan_or_not_positive_is_refused(
    command: tuple[str, str], duration: str
) -> None:
    # Refused while the options are read, before anything joins the graph.
    result = CliRunner().invoke(main, [*command, "--duration", duration], prog_name="diffbot")
    assert result.exit_code == 2
    assert result.stderr.count("\n") == 1, result.stderr
    assert "--duration" in result.stderr


@pytest.mark.parametrize(
    ("args", "option"),
    [
        (["node", "odom", "--window", "1000001", "--duration", "0.1"], "--window"),
        (["node", "odom", "--window", "4294967296", "--duration", "0.1"], "--window"),
        (["node", "odom", "--open-loop", "--publish-rate", "1e300"], "--publish-rate"),
        (["node", "odom", "--publish-rate", "1001", "--duration", "0.1"], "--publish-rate"),
        (
            ["drive", "straight 0.2", "--follow", "--pose-topic", "", "--wait", "0.1"],
            "--pose-topic",
        ),
    ],
)
@pytest.mark.timeout(30)  # an accepted rate or window would run the node for good
def test_a_window_or_rate_past_what_a_node_can_run_is_one_error_line(
    args: list[str], option: str
) -> None:
    result = CliRunner().invoke(main, args, prog_name="diffbot")
    assert result.exit_code == 2, result.output
    assert result.stderr.count("\n") == 1, result.stderr
    assert option in result.stderr


@pytest.mark.parametrize(
    ("args", "first"),
    [
        (
            ("node", "odom", "--no-tf"),
            "odom: reads /joint_states (sensor_msgs/msg/JointState); "
            "publishes /odom (nav_msgs/msg/Odometry); "
            "serves /diffbot_odometry/set_odometry, /diffbot_odometry/reset_odometry; "
            "frames odom -> base_link",
        ),
        (
            ("node", "ik", "--stamped", "--cmd-vel", "~/cmd_vel"),
            "ik: reads /diffbot_ik/cmd_vel (geometry_msgs/msg/TwistStamped); "
            "publishes /left_wheel_velocity_controller/commands (std_msgs/msg/Float64MultiArray), "
            "/right_wheel_velocity_controller/commands (std_msgs/msg/Float64MultiArray)",
        ),
    ],
)
def test_a_node_command_says_its_topics_first_unless_quiet(
    args: tuple[str, ...], first: str
) -> None:
    result = CliRunner().invoke(main, [*args, "--duration", "0.1"], prog_name="diffbot")
    assert result.exit_code == 0, result.stderr
    lines = result.stderr.splitlines()
    assert lines[0] == first
    assert len(lines) == 2  # then the status line
    quiet = CliRunner().invoke(main, [*args, "--duration", "0.1", "-q"], prog_name="diffbot")
    assert quiet.stderr.splitlines() == lines[1:]


def test_without_cyclonedds_the_live_commands_say_how_to_install_it() -> None:
    probe = (
        "import sys; sys.modules['cyclonedds'] = None\n"
        "from diffbot.cli import main\n"
        "main(['node', 'odom'])\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", probe], capture_output=True, text=True, timeout=60, check=False
    )
    assert done.returncode == 2
    assert done.stderr == (
        "error: the live commands need cyclonedds (DDS for Python): "
        "pip install 'diffbot-kinematics[live]'\n"
    )


def test_a_plan_over_the_motor_limit_is_refused_before_anything_moves() -> None:
    done = subprocess.run(
        [sys.executable, "-m", "diffbot", "drive", "straight 1 1s", "--wait", "0"],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    assert done.returncode == 1
    assert done.stderr == (
        "error: segment 1 (straight 1 m, 1 s): left and right wheels at 272.8 rpm exceed the "
        "50 rpm limit; shortest duration that fits: 5.457 s\n"
    )


def until_seen(seen: dict[str, int], topics: tuple[str, ...]) -> None:
    """Wait until 50 more messages came on each of ``topics``."""
    start = {t: seen.get(t, 0) for t in topics}
    end = time.monotonic() + 3 * PATIENCE
    while time.monotonic() < end and not all(seen.get(t, 0) > start[t] + 50 for t in topics):
        time.sleep(0.01)
    assert all(seen.get(t, 0) > start[t] + 50 for t in topics), f"nothing on {topics}: {seen}"


def _live(*args: str) -> subprocess.Popen[str]:
    return subprocess.Popen(
        [sys.executable, "-m", "diffbot", *args, "--quiet"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=os.environ.copy(),
    )


@pytest.mark.parametrize("seed", [3])
def test_every_live_command_ends_cleanly_on_a_signal_under_load(seed: int) -> None:
    """The whole loop at 1 kHz (drive -> ik -> robot -> odom), each process then sent SIGINT
    or SIGTERM at a seeded random moment: the nodes exit 0 with their status line, drive as a
    signal ends a run (130, 143) saying where it stopped; the last commands are zero."""
    rng = random.Random(seed)
    last: dict[str, Any] = {}
    seen: dict[str, int] = {}

    def keep(topic: str, value: Any) -> None:
        last[topic] = value
        seen[topic] = seen.get(topic, 0) + 1

    reliable = QosProfile(reliable=True, depth=100_000)
    with Node("monitor") as monitor:
        for topic in (LEFT_TOPIC, RIGHT_TOPIC):
            monitor.create_subscription(
                types.Float64MultiArray,
                topic,
                lambda m, topic=topic: keep(topic, list(m.data)),
                reliable,
            )
        monitor.create_subscription(
            types.Twist, "cmd_vel", lambda m: keep("cmd_vel", (m.linear.x, m.angular.z)), reliable
        )
        monitor.create_subscription(types.Odometry, "odom", lambda m: keep("odom", 1))
        monitor.start()
        processes = {
            "odom": _live("node", "odom", "--no-tf"),
            "robot": _live("node", "robot", "--rate", "1000"),
            "ik": _live("node", "ik"),
        }
        outcomes: dict[str, tuple[int, str]] = {}
        try:
            # The drive starts once the nodes are up (it waits for its first subscriber only).
            until_seen(seen, ("odom",))
            time.sleep(0.5)  # for node ik, which shows nothing before a command comes
            processes["drive"] = _live(
                "drive", "straight 2 20s", "--rate", "1000", "--wait", str(PATIENCE)
            )
            until_seen(seen, ("cmd_vel", LEFT_TOPIC, RIGHT_TOPIC, "odom"))
            assert all(p.poll() is None for p in processes.values()), "a command ended early"
            order = list(processes)
            rng.shuffle(order)
            sent = {}
            for name in order:
                time.sleep(rng.uniform(0.0, 0.2))
                sent[name] = rng.choice((signal.SIGINT, signal.SIGTERM))
                processes[name].send_signal(sent[name])
            for name, process in processes.items():
                _, err = process.communicate(timeout=PATIENCE)
                outcomes[name] = (process.returncode, err)
        finally:
            for process in processes.values():
                process.kill()
        zero = [0.0]
        end = time.monotonic() + PATIENCE
        while time.monotonic() < end and not (
            last.get(LEFT_TOPIC) == zero
            and last.get(RIGHT_TOPIC) == zero
            and last.get("cmd_vel") == (0.0, 0.0)
        ):
            time.sleep(0.01)
    for name in ("odom", "robot", "ik"):
        code, err = outcomes[name]
        assert code == 0, (name, sent[name], err)
        assert err.splitlines()[-1].startswith(f"{name}: "), (name, err)
    code, err = outcomes["drive"]
    assert code == 128 + sent["drive"], err
    assert "commands: commanded zero" in err, err
    assert "Traceback" not in "".join(err for _, err in outcomes.values())
    assert last[LEFT_TOPIC] == zero
    assert last[RIGHT_TOPIC] == zero
    assert last["cmd_vel"] == (0.0, 0.0)


@pytest.mark.parametrize("ending", ENDINGS)
def test_a_signal_while_the_command_line_loads_ends_a_node_command_before_its_node(
    ending: Ending,
) -> None:
    """As one during its setup: the command ends, nothing joins the graph, no traceback."""
    signum, code, stderr = ending
    returncode, _, err = signalled(signum, "node", "odom", "--no-tf")
    assert (returncode, err.strip()) == (code, stderr)


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
def test_a_signal_while_the_command_line_loads_stops_a_drive_before_it_commands(
    signum: int,
) -> None:
    returncode, _, err = signalled(signum, "drive", "straight 1", "--wait", str(PATIENCE))
    assert returncode == 128 + signum, err
    assert "Traceback" not in err
    assert "drove" not in err


@pytest.mark.parametrize("second", [signal.SIGINT, signal.SIGTERM, signal.SIGHUP])
def test_a_second_signal_while_a_node_shuts_down_does_not_end_it(second: int) -> None:
    """Ctrl-C twice: the second signal comes while the interpreter shuts down after the status
    line (DDS torn down, a few tenths of a second, the default actions of signals back), and is
    ignored: the exit code stays the first signal's clean 0."""
    process = subprocess.Popen(
        [sys.executable, "-m", "diffbot", "node", "ik"],
        stderr=subprocess.PIPE,
        text=True,
        env=os.environ.copy(),
    )
    try:
        assert process.stderr is not None
        assert process.stderr.readline().startswith("ik: reads ")
        process.send_signal(signal.SIGINT)
        status = process.stderr.readline()
        process.send_signal(second)
        _, rest = process.communicate(timeout=PATIENCE)
    finally:
        process.kill()
    assert status.startswith("ik: 0 commands"), status + rest
    assert (process.returncode, rest) == (0, "")


def test_the_command_line_ignores_ending_signals_once_its_outcome_is_decided(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    ending = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)
    before = {signum: signal.getsignal(signum) for signum in ending}
    try:
        # Run inside another program (as click's test runner does): the signals are given back.
        for standalone in (False, True):
            with contextlib.suppress(SystemExit):
                main.main(["ik", "nan", "0"], prog_name="diffbot", standalone_mode=standalone)
            assert {s: signal.getsignal(s) for s in ending} == before
        # As the process's entry point: it only exits after the command, signals ignored.
        monkeypatch.setattr(signal_handlers._Process, "ends_with_run", True)
        with pytest.raises(SystemExit) as done:
            main.main(["ik", "nan", "0"], prog_name="diffbot")
        assert done.value.code == 2
        assert {s: signal.getsignal(s) for s in ending} == dict.fromkeys(ending, signal.SIG_IGN)
    finally:
        for signum, handler in before.items():
            signal.signal(signum, handler)


@pytest.mark.parametrize(
    ("command", "topic", "reads"),
    [
        ("odom", "joint_states", "sensor_msgs/msg/JointState"),
        ("ik", "cmd_vel", "a velocity command"),
        ("robot", LEFT_TOPIC, "std_msgs/msg/Float64MultiArray"),
    ],
)
def test_a_node_command_prints_its_node_warnings(command: str, topic: str, reads: str) -> None:
    """A publisher of another type on a topic the node reads is one ``warning:`` line on the
    command's stderr, printed while it runs."""
    with Node("stranger") as stranger:
        other = stranger.create_publisher(types.String, topic)
        process = subprocess.Popen(
            [sys.executable, "-m", "diffbot", "node", command],
            stderr=subprocess.PIPE,
            text=True,
            env=os.environ.copy(),
        )
        other.publish(types.String("not for this node"))
        try:
            assert process.stderr is not None
            first = ""
            end = time.monotonic() + 2 * PATIENCE
            while time.monotonic() < end and not first.startswith("warning: "):
                ready, _, _ = select.select([process.stderr], [], [], 0.1)
                if ready:
                    first = process.stderr.readline()
            process.send_signal(signal.SIGINT)
            _, rest = process.communicate(timeout=PATIENCE)
        finally:
            process.kill()
    assert process.returncode == 0, first + rest
    assert first.startswith(f"warning: '/{topic}' carries std_msgs/msg/String"), first + rest
    assert reads in first
    assert "warning: " not in rest
