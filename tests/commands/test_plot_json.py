"""``diffbot plot --json``: the robot, the plan, the figure and where each path drawn ends, for
programs (``plot --odom --json`` names the robot as ``odom --json`` and ``calibrate fit
--json`` do)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner, Result
from extras import need
from pioneer import COUNTS_PER_REV, counts_csv, reference_bag, urdf

from diffbot.cli import main

need("matplotlib")


def run(runner: CliRunner, *args: str) -> Result:
    return runner.invoke(main, ["plot", *args], prog_name="diffbot")


def test_recordings_alone_name_their_robot_and_ends(runner: CliRunner, tmp_path: Path) -> None:
    csv = counts_csv(tmp_path)
    target = tmp_path / "run.png"
    args = ["--odom", str(csv), "--robot", str(urdf(tmp_path)), "-o", str(target), "--json"]
    result = run(runner, *args, "--counts-per-rev", repr(COUNTS_PER_REV), "--wrap", "65536")
    assert result.exit_code == 0, result.output + result.stderr
    summary = json.loads(result.stdout)
    assert summary["robot"] == str(tmp_path / "pioneer.urdf")
    assert summary["plan"] is None
    assert summary["output"] == str(target)
    [odometry] = summary["paths"]
    assert odometry["input"] == str(csv)
    assert odometry["path"] == "odometry"
    assert odometry["plan_end_distance"] is None
    assert odometry["implausible_steps"] == 0
    # The run ends 1 m along x and 0.5 m along y (pioneer.RUN_END), within a count or so.
    assert odometry["end"] == pytest.approx({"x": 1.0, "y": 0.5}, abs=1e-4)
    assert target.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_over_a_plan_each_path_says_how_far_it_ends_from_the_plan(
    runner: CliRunner, tmp_path: Path
) -> None:
    runs = tmp_path / "a.csv"
    simulated = runner.invoke(
        main, ["simulate", "--example", "A", "--true-separation", "0.14", "-o", str(runs)]
    )
    assert simulated.exit_code == 0, simulated.output
    result = run(runner, "--example", "A", "--odom", str(runs), "-o", str(tmp_path / "a.png"))
    text = result.stdout
    result = run(
        runner, "--example", "A", "--odom", str(runs), "-o", str(tmp_path / "b.png"), "--json"
    )
    assert result.exit_code == 0, result.output + result.stderr
    summary = json.loads(result.stdout)
    assert summary["robot"] == "bundled"
    assert summary["plan"] == "Trajectory A"
    odometry, truth = summary["paths"]
    assert (odometry["path"], truth["path"]) == ("odometry", "true pose")
    assert odometry["plan_end_distance"] == pytest.approx(0.0, abs=1e-9)
    # The text says the same distances.
    assert f"ends {truth['plan_end_distance']:.3g} m from the plan's end" in text
    assert truth["end"].keys() == {"x", "y"}


def test_a_reference_gives_the_fields_of_odom_json(runner: CliRunner, tmp_path: Path) -> None:
    bag = reference_bag(tmp_path, drift=0.002)
    args = ["--odom", str(bag), "--robot", str(urdf(tmp_path)), "--reference", "/odom"]
    args += ["--counts-per-rev", repr(COUNTS_PER_REV), "--wrap", "65536"]
    result = run(runner, *args, "-o", str(tmp_path / "ref.png"), "--json")
    assert result.exit_code == 0, result.output + result.stderr
    odom = runner.invoke(main, ["odom", str(bag), "--json", *args[2:]], prog_name="diffbot")
    assert odom.exit_code == 0, odom.output
    odometry, reference = json.loads(result.stdout)["paths"]
    assert odometry["path"] == "odometry"
    assert reference["path"] == "reference"
    expected = json.loads(odom.stdout)["reference"]
    assert {key: reference[key] for key in expected} == pytest.approx(expected)
    assert reference["end"] == pytest.approx({"x": 1.2, "y": 0.5}, abs=1e-4)
