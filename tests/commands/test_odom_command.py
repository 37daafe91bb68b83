"""``diffbot odom``: summaries, outputs, and every kind of bad input."""

from __future__ import annotations

import json
import math
import sys
from itertools import pairwise
from pathlib import Path
from typing import Any

import pytest
from bags import write_bag
from cli_results import assert_one_error_line
from click.testing import CliRunner, Result
from robots import BOT, bundled_controllers, two_wheel_urdf
from rosbags.highlevel import AnyReader
from wheel_motion import TRAJECTORY_A, wheel_samples

from diffbot.cli import main

LEFT, RIGHT = BOT.left_joint, BOT.right_joint


@pytest.fixture
def trajectory_a(tmp_path: Path) -> Path:
    """Trajectory A's wheel angles at 10 Hz as CSV, with one row lacking the right wheel."""
    stamps, lefts, rights = wheel_samples(BOT, TRAJECTORY_A)
    lines = [f"time,{LEFT},{RIGHT}"]
    for k, (stamp, left, right) in enumerate(zip(stamps, lefts, rights, strict=True)):
        lines.append(f"{stamp!r},{left!r},{'' if k == 7 else repr(right)}")
    path = tmp_path / "a.csv"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def odom_json(runner: CliRunner, *args: str) -> dict[str, object]:
    result = runner.invoke(main, ["odom", *args, "--json"])
    assert result.exit_code == 0, result.output
    data: dict[str, object] = json.loads(result.stdout)
    return data


def test_odom_summary_shows_the_final_pose_and_warns_about_skips(
    runner: CliRunner, trajectory_a: Path
) -> None:
    result = runner.invoke(main, ["odom", str(trajectory_a)])
    assert result.exit_code == 0, result.output
    assert "samples     400 used, 1 skipped" in result.stdout
    assert "duration    40 s" in result.stdout
    assert "final pose  x 0 m, y 1 m, theta 0 rad (0 deg)" in result.stdout
    assert result.stderr.strip() == "warning: skipped 1 of 401 samples: 1 missing joint"


def test_odom_json_reports_pose_distance_samples_skips_and_duration(
    runner: CliRunner, trajectory_a: Path
) -> None:
    data = odom_json(runner, str(trajectory_a))
    pose = data["final_pose"]
    assert isinstance(pose, dict)
    assert pose["x"] == pytest.approx(0.0, abs=1e-9)
    assert pose["y"] == pytest.approx(1.0, abs=1e-9)
    assert pose["theta"] == pytest.approx(0.0, abs=1e-9)
    assert data["distance"] == pytest.approx(2 + 0.5 * math.pi, rel=1e-12)
    assert data["samples"] == 400
    assert data["skipped"] == {"missing joint": 1}
    assert data["duration"] == 40.0


def test_odom_uses_the_robot_options(runner: CliRunner, trajectory_a: Path) -> None:
    bigger = odom_json(runner, str(trajectory_a), "--wheel-radius", "0.07")
    assert bigger["distance"] == pytest.approx(2 * (2 + 0.5 * math.pi), rel=1e-12)
    by_xacro = odom_json(runner, str(trajectory_a), "wheel_radius:=0.07")
    assert by_xacro["distance"] == bigger["distance"]


def test_odom_writes_the_pose_series_as_csv(
    runner: CliRunner, trajectory_a: Path, tmp_path: Path
) -> None:
    out = tmp_path / "poses.csv"
    result = runner.invoke(main, ["odom", str(trajectory_a), "--out", str(out)])
    assert result.exit_code == 0, result.output
    assert f"output      {out} (CSV, 400 poses)" in result.stdout
    lines = out.read_text(encoding="utf-8").splitlines()
    assert lines[0] == "time,x,y,theta,linear,angular"
    assert len(lines) == 401
    time, x, y, theta, linear, angular = map(float, lines[-1].split(","))
    assert (time, linear, angular) == (40.0, pytest.approx(0.1), pytest.approx(0.0, abs=1e-9))
    assert (x, y, theta) == pytest.approx((0.0, 1.0, 0.0), abs=1e-9)


def test_odom_never_overwrites_an_output_without_force(
    runner: CliRunner, trajectory_a: Path, tmp_path: Path
) -> None:
    out = tmp_path / "poses.csv"
    out.write_text("keep me", encoding="utf-8")
    result = runner.invoke(main, ["odom", str(trajectory_a), "--out", str(out)])
    assert result.exit_code == 2
    assert result.stderr == f"error: {out} exists: use --force to overwrite it\n"
    assert out.read_text(encoding="utf-8") == "keep me"
    result = runner.invoke(main, ["odom", str(trajectory_a), "--out", str(out), "--force"])
    assert result.exit_code == 0, result.output
    assert out.read_text(encoding="utf-8").startswith("time,x,y,theta")


def test_odom_refuses_to_write_over_its_input(runner: CliRunner, trajectory_a: Path) -> None:
    before = trajectory_a.read_bytes()
    args = ["odom", str(trajectory_a), "--out", str(trajectory_a), "--force"]
    result = runner.invoke(main, args)
    assert result.exit_code == 2
    assert result.stderr == (
        f"error: --out {trajectory_a} is the input {trajectory_a}: inputs are never overwritten\n"
    )
    assert trajectory_a.read_bytes() == before


def test_odom_reads_a_bag_and_writes_a_bag_of_odometry_and_tf(
    runner: CliRunner, tmp_path: Path
) -> None:
    stamps, lefts, rights = wheel_samples(BOT, TRAJECTORY_A)
    epoch = 1_700_000_000 * 10**9
    messages = [
        (epoch + round(s * 1e9), epoch + round(s * 1e9), ["caster", LEFT, RIGHT], [9.0, lt, rt])
        for s, lt, rt in zip(stamps, lefts, rights, strict=True)
    ]
    bag = write_bag(tmp_path / "in", messages, topic="/bot/joint_states", storage="mcap")
    out = tmp_path / "odom_bag"
    args = ["odom", str(bag), "--topic", "/bot/joint_states", "--out", str(out), "--bag"]
    result = runner.invoke(main, [*args, "--json"])
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert data["final_pose"]["y"] == pytest.approx(1.0, abs=1e-9)
    assert data["skipped"] == {}
    with AnyReader([out]) as reader:
        counts = {c.topic: (c.msgtype, c.msgcount) for c in reader.connections}
        assert reader.start_time == epoch
    assert counts == {
        "/odom": ("nav_msgs/msg/Odometry", 401),
        "/tf": ("tf2_msgs/msg/TFMessage", 401),
    }
    again = runner.invoke(main, args)
    assert again.exit_code == 2
    assert "exists: use --force" in again.stderr


def odom_bag_of(runner: CliRunner, tmp_path: Path, messages: list[Any], *parameters: str) -> Path:
    """The bag ``odom --bag`` writes of a bag of ``messages`` for the bundled robot with a
    controllers file of these diff-drive ``parameters``."""
    bag = write_bag(tmp_path / "in", messages, topic="/joint_states")
    controllers = tmp_path / "controllers.yaml"
    controllers.write_text(bundled_controllers(*parameters), "utf-8")
    out = tmp_path / "odom_bag"
    args = ["odom", str(bag), "--controllers", str(controllers), "--out", str(out), "--bag"]
    result = runner.invoke(main, args)
    assert result.exit_code == 0, result.output
    return out


def test_odom_bag_output_is_in_the_controller_s_frames_with_its_covariances(
    runner: CliRunner, tmp_path: Path
) -> None:
    stamps, lefts, rights = wheel_samples(BOT, TRAJECTORY_A)
    messages = [
        (round(s * 1e9) + 1, round(s * 1e9) + 1, [LEFT, RIGHT], [lt, rt])
        for s, lt, rt in zip(stamps[:20], lefts, rights, strict=False)
    ]
    out = odom_bag_of(
        runner, tmp_path, messages, "tf_frame_prefix: robot", "base_frame_id: base_footprint"
    )
    with AnyReader([out]) as reader:
        odometry = [c for c in reader.connections if c.topic == "/odom"]
        first = next(reader.messages(connections=odometry))
        message = reader.deserialize(first[2], first[0].msgtype)
        tf = [c for c in reader.connections if c.topic == "/tf"]
        first_tf = next(reader.messages(connections=tf))
        transform = reader.deserialize(first_tf[2], first_tf[0].msgtype).transforms[0]
    assert (message.header.frame_id, message.child_frame_id) == (
        "robot/odom",
        "robot/base_footprint",
    )
    assert (transform.header.frame_id, transform.child_frame_id) == (
        "robot/odom",
        "robot/base_footprint",
    )
    assert not message.pose.covariance.any()
    assert not message.twist.covariance.any()


def test_odom_bag_refuses_frames_node_odom_would_refuse(
    runner: CliRunner, tmp_path: Path, trajectory_a: Path
) -> None:
    # A prefix with a tab, and one past any frame's length: no bag is written with such frames.
    for parameter, fragment in (
        ('tf_frame_prefix: "a\\tb"', "control character"),
        (f"tf_frame_prefix: {'x' * 300}", "longer than 255"),
    ):
        controllers = tmp_path / "controllers.yaml"
        controllers.write_text(bundled_controllers(parameter), "utf-8")
        out = tmp_path / "odom_bag"
        args = ["odom", str(trajectory_a), "--controllers", str(controllers), "-o", str(out)]
        assert_one_error_line(runner.invoke(main, [*args, "--bag"]), "controllers.yaml", fragment)
        assert not out.exists()
        assert runner.invoke(main, args[:4]).exit_code == 0  # no bag: the frames are not used


def test_odom_bag_twist_spans_the_controller_s_rolling_window(
    runner: CliRunner, tmp_path: Path
) -> None:
    # The controller (and node odom) publishes the velocity over its last
    # velocity_rolling_window_size steps; the bag said the last step's alone.
    stamps_ns = [0, 10**8, 3 * 10**8, 35 * 10**7, 6 * 10**8, 7 * 10**8, 9 * 10**8]
    lefts = [0.0, 0.2, 0.1, 0.4, 0.45, 0.9, 0.7]
    rights = [0.0, 0.3, 0.5, 0.5, 0.9, 1.0, 1.6]
    messages = [
        (s + 1, s + 1, [LEFT, RIGHT], [lt, rt])
        for s, lt, rt in zip(stamps_ns, lefts, rights, strict=True)
    ]
    out = odom_bag_of(runner, tmp_path, messages, "velocity_rolling_window_size: 3")
    with AnyReader([out]) as reader:
        odometry = [c for c in reader.connections if c.topic == "/odom"]
        twists = [
            reader.deserialize(raw, connection.msgtype).twist.twist
            for connection, _, raw in reader.messages(connections=odometry)
        ]
    r, b = BOT.wheel_radius, BOT.wheel_separation
    steps = [
        (r * (l1 - l0 + r1 - r0) / 2, r * (r1 - r0 - l1 + l0) / b, (t1 - t0) / 1e9)
        for (l0, l1), (r0, r1), (t0, t1) in zip(
            pairwise(lefts), pairwise(rights), pairwise(stamps_ns), strict=True
        )
    ]
    assert len(twists) == len(stamps_ns)
    assert (twists[0].linear.x, twists[0].angular.z) == (0.0, 0.0)
    for k, twist in enumerate(twists[1:]):
        window = steps[max(0, k - 2) : k + 1]
        time = sum(step[2] for step in window)
        assert twist.linear.x == pytest.approx(sum(s[0] for s in window) / time, abs=1e-12)
        assert twist.angular.z == pytest.approx(sum(s[1] for s in window) / time, abs=1e-12)


def test_odom_bag_output_needs_a_directory_name(runner: CliRunner, trajectory_a: Path) -> None:
    result = runner.invoke(main, ["odom", str(trajectory_a), "--bag"])
    assert result.exit_code == 2
    assert result.stderr == "error: --bag writes the --out directory: give --out DIR\n"


def test_odom_lists_the_topics_of_a_bag_without_the_topic(
    runner: CliRunner, tmp_path: Path
) -> None:
    bag = write_bag(tmp_path / "in", [(1, 1, [LEFT, RIGHT], [0.0, 0.0])], topic="/js")
    result = runner.invoke(main, ["odom", str(bag), "--topic", "/joint_states"])
    assert result.exit_code == 2
    assert result.stderr == (
        f"error: {bag}: no topic '/joint_states' in the bag; topics found: '/chatter', '/js'\n"
    )


@pytest.mark.parametrize(
    ("name", "text", "message"),
    [
        ("empty.csv", "", "empty.csv: empty file"),
        ("notime.csv", f"secs,{LEFT},{RIGHT}\n0,0,0\n", "no time column"),
        ("nowheel.csv", "time,a,b\n0,0,0\n", "columns found: 'time', 'a', 'b'"),
        ("nothing.csv", f"time,{LEFT},{RIGHT}\n0,nan,0\n1,,1\n", "no usable sample"),
        ("header.csv", f"time,{LEFT},{RIGHT}\n", "no usable sample"),
    ],
)
def test_odom_refuses_bad_csv_with_one_error_line(
    runner: CliRunner, tmp_path: Path, name: str, text: str, message: str
) -> None:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    result = runner.invoke(main, ["odom", str(path)])
    assert result.exit_code == 2
    assert result.stderr.startswith("error: ")
    assert message in result.stderr
    assert result.stderr.count("\n") == 1
    assert "Traceback" not in result.output


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["missing.csv"], "missing.csv: no such file or directory"),
        ([], "expected an INPUT"),
        (["a.csv", "-"], "cannot be read with other inputs"),
        (["nothing*.csv"], "nothing*.csv: no file or directory matches"),
        (["emptydir"], "emptydir: not a bag folder: no metadata.yaml"),
        (["bad.mcap"], "not a readable rosbag2 recording"),
        (["a.csv", "--wheel-radius", "-1"], "'-1' must be > 0"),
        (["a.csv", "--robot", "nope.urdf"], "nope.urdf: no such file"),
    ],
)
def test_odom_refuses_bad_arguments_with_exit_code_2(
    runner: CliRunner,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    args: list[str],
    message: str,
) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "a.csv").write_text(f"time,{LEFT},{RIGHT}\n0,0,0\n", encoding="utf-8")
    (tmp_path / "b.csv").write_text(f"time,{LEFT},{RIGHT}\n0,0,0\n", encoding="utf-8")
    (tmp_path / "emptydir").mkdir()
    (tmp_path / "bad.mcap").write_bytes(b"\x00" * 64)
    result = runner.invoke(main, ["odom", *args])
    assert result.exit_code == 2
    assert result.stderr.startswith("error: ")
    assert message in result.stderr
    assert "Traceback" not in result.output


def test_odom_without_rosbags_reads_sqlite3_and_says_what_to_install_for_mcap(
    runner: CliRunner, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # A turn of each wheel in a second (a turn in a nanosecond would be an implausible step).
    messages = [
        (10**9, 10**9, [LEFT, RIGHT], [0.0, 0.0]),
        (2 * 10**9, 2 * 10**9, [LEFT, RIGHT], [1.0, 1.0]),
    ]
    sqlite_bag = write_bag(tmp_path / "in", messages)
    mcap_bag = write_bag(tmp_path / "in_mcap", messages, storage="mcap")
    monkeypatch.setitem(sys.modules, "rosbags.typesys", None)
    monkeypatch.setitem(sys.modules, "rosbags.rosbag2", None)
    result = runner.invoke(main, ["odom", str(sqlite_bag), "--json"])
    assert result.exit_code == 0, result.output
    assert json.loads(result.stdout)["samples"] == 2
    result = runner.invoke(main, ["odom", str(mcap_bag)])
    assert result.exit_code == 2
    assert result.stderr == (
        "error: reading this ROS 2 bag needs the rosbags library: "
        "pip install 'rosbags>=0.11' (the bag extra of diffbot-kinematics)\n"
    )


def snapshot(directory: Path) -> dict[str, bytes]:
    """Every file under a directory, by relative path, with its bytes."""
    return {
        str(p.relative_to(directory)): p.read_bytes()
        for p in sorted(directory.rglob("*"))
        if p.is_file()
    }


def one_error_line(result: Result, fragment: str) -> None:
    assert result.exit_code == 2, result.output
    assert result.stderr.startswith("error: ")
    assert result.stderr.count("\n") == 1
    assert fragment in result.stderr


@pytest.mark.parametrize("storage", ["sqlite3", "mcap"])
@pytest.mark.parametrize(
    ("given", "out", "as_bag", "fragment"),
    [
        ("{bag}", "{bag}", True, "is the input"),
        ("{bag}/{storage_file}", "{bag}", True, "is the input"),
        ("{bag}", "{bag}/metadata.yaml", False, "lies inside the input"),
        ("{bag}", "{bag}/{storage_file}", False, "lies inside the input"),
        ("{bag}/{storage_file}", "{bag}/metadata.yaml", False, "lies inside the input"),
        ("{bag}/{storage_file}", "{bag}/{storage_file}", False, "lies inside the input"),
        ("{bag}", "{bag}/sub/odom.csv", False, "lies inside the input"),
        ("{bag}", "{tmp}", True, "contains the input"),
    ],
)
def test_odom_force_never_touches_the_input_bag(
    runner: CliRunner,
    tmp_path: Path,
    storage: str,
    given: str,
    out: str,
    as_bag: bool,
    fragment: str,
) -> None:
    bag = write_bag(tmp_path / "in", [(1, 1, [LEFT, RIGHT], [0.0, 0.0])], storage=storage)
    storage_file = "in.mcap" if storage == "mcap" else "in.db3"
    (tmp_path / "metadata.yaml").write_text("a bag, so that --force would replace it\n")
    names = {"bag": bag, "storage_file": storage_file, "tmp": tmp_path}
    before = snapshot(tmp_path)
    args = ["odom", given.format(**names), "--out", out.format(**names), "--force"]
    result = runner.invoke(main, [*args, "--bag"] if as_bag else args)
    one_error_line(result, fragment)
    assert snapshot(tmp_path) == before


def test_odom_force_never_writes_over_the_robot_or_through_a_link_to_the_input(
    runner: CliRunner, trajectory_a: Path, tmp_path: Path
) -> None:
    robot = tmp_path / "robot.urdf"
    assert runner.invoke(main, ["urdf", "-o", str(robot)]).exit_code == 0
    link = tmp_path / "link.csv"
    link.symlink_to(trajectory_a)
    before = snapshot(tmp_path)
    args = ["odom", str(trajectory_a), "--robot", str(robot), "--force", "--out"]
    one_error_line(runner.invoke(main, [*args, str(robot)]), f"is the input {robot}")
    one_error_line(runner.invoke(main, [*args, str(link)]), f"is the input {trajectory_a}")
    assert snapshot(tmp_path) == before


def test_odom_reads_a_simulated_bag_whose_name_ends_in_dot_bag(
    runner: CliRunner, tmp_path: Path
) -> None:
    bag = tmp_path / "sim.bag"
    result = runner.invoke(main, ["simulate", "--out", str(bag), "--bag", "--start", "1"])
    assert result.exit_code == 0, result.output
    data = odom_json(runner, str(bag))
    assert data["samples"] == 2001
    assert data["clock"] == "header"
    result = runner.invoke(main, ["odom", str(bag)])
    assert result.exit_code == 0, result.output
    assert f"input       {bag} (rosbag2, topic /joint_states, header stamps)" in result.stdout


def test_odom_says_when_a_zero_header_stamp_puts_a_bag_on_its_receive_clock(
    runner: CliRunner, tmp_path: Path
) -> None:
    epoch = 1_700_000_000 * 10**9
    messages = [
        (k * 10**8, epoch + k * 10**8, [LEFT, RIGHT], [float(k), float(k)]) for k in range(11)
    ]
    data = odom_json(runner, str(write_bag(tmp_path / "in", messages)))
    assert data["clock"] == "receive"
    assert data["samples"] == 11
    assert data["skipped"] == {}
    assert data["duration"] == 1.0


def test_odom_reads_a_csv_from_stdin(runner: CliRunner) -> None:
    simulated = runner.invoke(main, ["simulate", "straight 1; spin 90"])
    assert simulated.exit_code == 0, simulated.output
    result = runner.invoke(main, ["odom", "-", "--json"], input=simulated.stdout)
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert data["input"] == "-"
    assert data["final_pose"]["x"] == pytest.approx(1.0, abs=1e-9)
    assert data["final_pose"]["theta"] == pytest.approx(math.pi / 2, abs=1e-9)


@pytest.mark.parametrize(
    ("args", "stdin", "message"),
    [
        ([""], None, "error: INPUT is empty: give a CSV file, - for stdin, or a rosbag2 recording"),
        (["a.csv", "--out", ""], None, "error: -o/--out '': an empty name, not a file or"),
        (["a.csv", "--out", " ", "--bag"], None, "error: -o/--out ' ': an empty name"),
        (["-"], b"", "error: -: empty file"),
        (["-"], b"\xff\xfe\x00", "error: -: not a text (UTF-8) CSV file"),
        (["-"], b"time,a,b\n0,0,0\n", "error: -: no column for the left wheel joint"),
        (["-", "--out", "-"], b"time\n", "error: -o/--out -: standard output, not a file"),
    ],
)
def test_odom_refuses_empty_names_and_bad_stdin_with_one_error_line(
    runner: CliRunner,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    args: list[str],
    stdin: bytes | None,
    message: str,
) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "a.csv").write_text(f"time,{LEFT},{RIGHT}\n0,0,0\n", encoding="utf-8")
    one_error_line(runner.invoke(main, ["odom", *args], input=stdin), message)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.csv"]


def test_odom_skips_times_too_large_for_ros_time_and_fails_only_without_samples(
    runner: CliRunner, tmp_path: Path
) -> None:
    path = tmp_path / "a.csv"
    path.write_text(f"time,{LEFT},{RIGHT}\n0,0,0\n1e400,1,1\n1e100000000,1,1\n2,2,2\n")
    result = runner.invoke(main, ["odom", str(path)])
    assert result.exit_code == 0, result.output
    assert result.stderr == "warning: skipped 2 of 4 samples: 2 stamp out of range\n"
    path.write_text(f"time,{LEFT},{RIGHT}\n1e400,1,1\n1_0,1,1\n")
    one_error_line(
        runner.invoke(main, ["odom", str(path)]),
        "no usable sample (skipped: stamp out of range: 1, unreadable value: 1)",
    )


def renamed_wheels(trajectory_a: Path, left: str, right: str) -> Path:
    """Trajectory A's recording with its wheel columns renamed, as another robot's driver
    names them."""
    text = trajectory_a.read_text(encoding="utf-8").replace(LEFT, left).replace(RIGHT, right)
    path = trajectory_a.with_name("renamed.csv")
    path.write_text(text, encoding="utf-8")
    return path


def test_odom_names_the_robot_it_used_in_its_text_and_json(
    runner: CliRunner, trajectory_a: Path, tmp_path: Path
) -> None:
    result = runner.invoke(main, ["odom", str(trajectory_a)])
    assert "\nrobot       bundled\n" in result.stdout
    assert odom_json(runner, str(trajectory_a))["robot"] == "bundled"
    robot = tmp_path / "robot.urdf"
    robot.write_text(two_wheel_urdf(), encoding="utf-8")
    renamed = renamed_wheels(trajectory_a, "left_wheel_joint", "right_wheel_joint")
    given = odom_json(runner, str(renamed), "--robot", str(robot))
    assert given["robot"] == str(robot)
    assert given["samples"] == 400
    both = runner.invoke(main, ["odom", str(trajectory_a), str(trajectory_a), "--json"])
    assert [json.loads(line)["robot"] for line in both.stdout.splitlines()] == ["bundled"] * 2


def test_wheel_columns_of_another_robot_read_with_the_bundled_one_are_refused(
    runner: CliRunner, trajectory_a: Path
) -> None:
    # Read with the bundled robot's geometry, another robot's run turns by the wrong angle
    # with exit 0: the columns name none of its joints, so the robot must be said.
    renamed = renamed_wheels(trajectory_a, "wheel_left_joint", "wheel_right_joint")
    columns = ["--left-column", "wheel_left_joint", "--right-column", "wheel_right_joint"]
    result = runner.invoke(main, ["odom", str(renamed), *columns])
    assert_one_error_line(result, "'wheel_left_joint'", "--robot", "--wheel-radius")
    geometry = ["--wheel-radius", "0.035", "--wheel-separation", "0.135"]
    data = odom_json(runner, str(renamed), *columns, *geometry)
    assert data["distance"] == pytest.approx(3.5707963267948966, rel=1e-9)
    # Columns that name the bundled robot's own joints are its recording.
    exported = renamed_wheels(trajectory_a, f"/joint_states/{LEFT}/position", RIGHT)
    own = ["--left-column", f"/joint_states/{LEFT}/position", "--right-column", RIGHT]
    assert odom_json(runner, str(exported), *own)["robot"] == "bundled"
    # One column of the bundled robot's is not enough: the other wheel is another robot's.
    mixed = renamed_wheels(trajectory_a, LEFT, "wheel_right_joint")
    half = ["--left-column", LEFT, "--right-column", "wheel_right_joint"]
    result = runner.invoke(main, ["odom", str(mixed), *half])
    assert_one_error_line(result, "the wheel column 'wheel_right_joint' names none", "--robot")
    assert LEFT + "'" not in result.stderr.split("names none")[0]
