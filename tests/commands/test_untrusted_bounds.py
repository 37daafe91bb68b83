"""Hostile inputs that ask for unbounded work: refused quickly with one ``error:`` line, or done
in streaming, near-linear work."""

from __future__ import annotations

import json
import subprocess
import sys
import time
from pathlib import Path

import pytest
from cli_results import assert_one_error_line
from click.testing import CliRunner
from extras import need
from peak_memory import peak_bytes

from diffbot.cli import main

#: Longest any hostile input may take (s).
QUICK = 20.0


def run_process(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "diffbot", *args],
        capture_output=True,
        text=True,
        timeout=QUICK,
        check=False,
    )


NAMES = "abcdefghijklmnopqrstuvwxyzABCDEF"


def anchors(levels: int, last: str = "cw: *{n}") -> str:
    """YAML anchors doubling ``levels`` times: a few hundred bytes, 2**levels items."""
    parts = ["ccw: [&a [1,1]"]
    parts += [f",&{NAMES[k]} [*{NAMES[k - 1]},*{NAMES[k - 1]}]" for k in range(1, levels + 1)]
    return "".join(parts) + "]\n" + last.format(n=NAMES[levels]) + "\n"


@pytest.mark.parametrize("levels", [16, 27])
def test_a_runs_file_of_doubling_anchors_is_refused_quickly(tmp_path: Path, levels: int) -> None:
    path = tmp_path / "runs.yaml"
    path.write_text(anchors(levels), encoding="utf-8")
    assert path.stat().st_size <= 440
    done = run_process("calibrate", "umbmark", "--side", "4", "--runs", str(path))
    assert done.returncode == 2, done.stderr[:300]
    assert len(done.stderr) < 300, done.stderr[:300]
    assert done.stderr.startswith("error: ")
    assert "YAML aliases (*name) are not allowed in a runs file" in done.stderr


def test_bag_metadata_of_doubling_anchors_is_refused(tmp_path: Path) -> None:
    bag = tmp_path / "bag"
    bag.mkdir()
    (bag / "bag_0.db3").write_bytes(b"")
    text = anchors(27, "rosbag2_bagfile_information: {{storage_identifier: sqlite3, x: *{n}}}")
    (bag / "metadata.yaml").write_text(text, encoding="utf-8")
    result = CliRunner().invoke(main, ["odom", str(bag)])
    assert_one_error_line(result, "metadata.yaml: YAML aliases (*name) are not allowed")


def many_controllers(count: int) -> str:
    """A controllers file declaring ``count`` diff-drive controllers, each in its section."""
    lines = ["controller_manager:", "  ros__parameters:", "    update_rate: 100"]
    lines += [
        f"    c{k}: {{type: diff_drive_controller/DiffDriveController}}" for k in range(count)
    ]
    section = (
        "  ros__parameters: {left_wheel_names: [l], right_wheel_names: [r], "
        "wheel_separation: 0.3, wheel_radius: 0.05}"
    )
    lines += [f"c{k}:\n{section}" for k in range(count)]
    return "\n".join(lines) + "\n"


def test_twenty_thousand_controllers_are_read_in_seconds() -> None:
    from diffbot.urdf.controllers import read_controllers

    text = many_controllers(20_000)
    start = time.process_time()  # CPU time: other work on the machine does not count
    configs = read_controllers(text, "many.yaml")
    assert time.process_time() - start < QUICK  # before: 8,000 took 43 s, growing as n**2
    assert [c.name for c in configs[:2]] == ["c0", "c1"]
    assert len(configs) == 20_000
    assert configs[-1].wheel_separation == pytest.approx(0.3, abs=1e-12)
    assert configs[-1].update_rate == pytest.approx(100, abs=1e-12)


def test_a_plot_of_ten_thousand_segments_takes_seconds(tmp_path: Path) -> None:
    need("matplotlib")
    plan_file = tmp_path / "long.txt"
    plan_file.write_text("; ".join(["straight 0.1", "ccw 0.5 10"] * 5_000), encoding="utf-8")
    start = time.process_time()
    result = CliRunner().invoke(main, ["plot", str(plan_file), "-o", str(tmp_path / "p.png")])
    assert time.process_time() - start < QUICK  # before: 2,000 segments took 28.5 s
    assert result.exit_code == 0, result.output
    assert (tmp_path / "p.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_ramped_plan_of_twenty_thousand_segments_takes_seconds(tmp_path: Path) -> None:
    plan_file = tmp_path / "long.txt"
    plan_file.write_text("; ".join(["straight 0.1"] * 20_000), encoding="utf-8")
    start = time.process_time()
    result = CliRunner().invoke(main, ["plan", str(plan_file), "--max-accel", "0.5", "--json"])
    assert time.process_time() - start < QUICK  # before: about 2 ms of CPU per segment
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert len(data["segments"]) == 20_000
    # one run of 2 km at the step speed 0.1 m/s, from rest to rest at 0.5 m/s²: a trapezoid
    # of L / v + v / a seconds
    assert data["duration"] == pytest.approx(2000.0 / 0.1 + 0.1 / 0.5, rel=1e-9)


FAST_CONTROLLER = """\
controller_manager:
  ros__parameters:
    update_rate: 100000
    diff_drive_controller: {type: diff_drive_controller/DiffDriveController}
diff_drive_controller:
  ros__parameters:
    left_wheel_names: [front_left_wheel_joint]
    right_wheel_names: [front_right_wheel_joint]
    wheel_separation: 0.135
    wheel_radius: 0.035
    linear.x.max_acceleration: 0.0001
"""


def test_an_absurd_controller_execution_is_refused_up_front(tmp_path: Path) -> None:
    controllers = tmp_path / "fast.yaml"
    controllers.write_text(FAST_CONTROLLER, encoding="utf-8")
    # before: 8 million updates, each a sample time, ran out of memory at 3.9 GB
    done = run_process("simulate", "--steps", "--controllers", str(controllers), "--quiet")
    assert done.returncode == 2, done.stderr[-300:]
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1, done.stderr[-300:]
    assert lines[0].startswith("error: executing this plan through the controller's limiter")
    assert "update_rate of 100000 Hz" in lines[0]
    assert "fast.yaml" in lines[0]
    assert done.stdout == ""


def test_a_bag_naming_its_storage_file_many_times_reads_it_once(tmp_path: Path) -> None:
    bag = tmp_path / "bag"
    made = CliRunner().invoke(main, ["simulate", "straight 0.1", "--out", str(bag), "--bag"])
    assert made.exit_code == 0, made.output
    expected = json.loads(CliRunner().invoke(main, ["odom", str(bag), "--json"]).stdout)
    metadata = bag / "metadata.yaml"
    text = metadata.read_text(encoding="utf-8")
    # 100,000 copies of the one storage file: each used to be opened and read in turn (a hang).
    text = text.replace("  - bag.db3\n", "  - bag.db3\n" * 100_000, 1)
    metadata.write_text(text, encoding="utf-8")
    start = time.perf_counter()
    done = run_process("odom", str(bag), "--json")
    assert time.perf_counter() - start < QUICK
    assert done.returncode == 0, done.stderr[:300]
    assert json.loads(done.stdout)["final_pose"] == expected["final_pose"]
    assert json.loads(done.stdout)["samples"] == expected["samples"]


def test_a_waypoints_file_beyond_ten_thousand_rows_is_refused_quickly(tmp_path: Path) -> None:
    # 300,000 waypoints used to plan for minutes towards gigabytes.
    path = tmp_path / "w.csv"
    path.write_text("x,y\n" + "".join(f"{k % 7},{k % 5}\n" for k in range(300_000)), "utf-8")
    start = time.perf_counter()
    done = run_process("plan", "--waypoints", str(path), "--format", "csv")
    assert time.perf_counter() - start < QUICK
    assert done.returncode == 2, done.stderr[:300]
    assert done.stderr.startswith("error: ")
    assert "300000 waypoints, more than the 10000 a plan may go through" in done.stderr
    assert len(done.stderr.splitlines()) == 1


def test_a_runs_file_of_a_million_rows_is_refused_quickly(tmp_path: Path) -> None:
    path = tmp_path / "runs.csv"
    path.write_text("direction,x,y\n" + "cw,0.1,0.1\nccw,0.1,0.1\n" * 500_000, "utf-8")
    start = time.perf_counter()
    done = run_process("calibrate", "umbmark", "--side", "4", "--runs", str(path))
    assert time.perf_counter() - start < QUICK
    assert done.returncode == 2, done.stderr[:300]
    assert done.stderr == (
        f"error: {path}: a runs file (CSV or YAML) of more than 1000000 characters\n"
    )


def test_a_runs_file_of_more_runs_than_a_test_drives_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "runs.csv"
    path.write_text("direction,x,y\n" + "cw,0.1,0.1\n" * 10_001, "utf-8")
    done = run_process("calibrate", "umbmark", "--side", "4", "--runs", str(path))
    assert done.returncode == 2, done.stderr[:300]
    assert (
        done.stderr == f"error: {path}: 10001 runs, more than 10000: not a UMBmark test's record\n"
    )


def test_a_runs_file_is_read_no_further_than_its_bound(tmp_path: Path) -> None:
    from diffbot.commands.calibrate import MAX_RUNS_CHARS, _runs_file
    from diffbot.errors import CalibrationError

    path = tmp_path / "runs.csv"
    path.write_text("direction,x,y\n" + "cw,0.1,0.1\n" * 2_000_000, "utf-8")  # 24 MB

    def refused() -> None:
        with pytest.raises(CalibrationError, match="more than"):
            _runs_file(str(path))

    _, peak = peak_bytes(refused)
    assert peak < 20 * MAX_RUNS_CHARS  # the whole file would be over 24 MB before splitting
