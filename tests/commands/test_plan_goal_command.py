"""`diffbot plan --to`: goal plans in every format and command, waypoint files, bad input."""

from __future__ import annotations

import csv
import io
import json
import math
from collections.abc import Callable
from pathlib import Path

import pytest
from cli_results import assert_one_error_line as assert_bad_input
from click.testing import CliRunner, Result

from diffbot.cli import main
from diffbot.planfile import parse_plan

Write = Callable[[str, str], Path]


def run(runner: CliRunner, *args: str) -> Result:
    return runner.invoke(main, list(args))


def final_pose(runner: CliRunner, *args: str) -> tuple[float, float, float]:
    result = run(runner, "plan", *args, "--json")
    assert result.exit_code == 0, result.output
    pose = json.loads(result.stdout)["final_pose"]
    return pose["x"], pose["y"], pose["theta"]


def test_table_names_the_shape_and_the_others_times(runner: CliRunner) -> None:
    result = run(runner, "plan", "--to", "0,1,0", "--min-radius", "0.25")
    assert result.exit_code == 0, result.output
    lines = result.stdout.splitlines()
    assert lines[0] == "to (0, 1, 0 deg): spin 90; straight 1; spin -90"
    # pi/2 at 2.715 rad/s twice and 1 m at 0.1833 m/s (both wheels at 50 rpm): 6.614 s
    assert "total 6.61388 s; final pose x 0.0000 m, y 1.0000 m, theta 0.00 deg" in lines
    assert lines[-1] == (
        "shape fastest (the least time at the motor limit): 6.614 s; spin-straight-spin "
        "6.614 s, dubins 10.89 s, reeds-shepp 8.881 s"
    )


@pytest.mark.parametrize(
    ("args", "note"),
    [
        # 1 m at the cruise speed of 0.1 m/s: 10 s, whatever the shape; not the 5.457 s it
        # takes at the motor limit.
        (
            ("--to", "1,0,0", "--shape", "spin-straight-spin"),
            "shape spin-straight-spin (as asked); at the cruise speeds it takes 10 s, fastest "
            "10 s, dubins (needs --min-radius), reeds-shepp (needs --min-radius)",
        ),
        # Arcs of 1 m through 60 + 300 + 60 deg at 0.1 m/s: 73.3 s (42.7 s at the motor limit).
        (
            ("--to", "0,0,180", "--shape", "dubins", "--min-radius", "1"),
            "shape dubins (as asked); at the cruise speeds it takes 73.3 s, fastest 6.283 s, "
            "spin-straight-spin 6.283 s, reeds-shepp 31.42 s",
        ),
        # --fastest: every shape at the motor limit, the one asked included.
        (
            ("--to", "1,0,0", "--shape", "spin-straight-spin", "--fastest"),
            "shape spin-straight-spin (as asked); at the motor limit it takes 5.457 s, fastest "
            "5.457 s, dubins (needs --min-radius), reeds-shepp (needs --min-radius)",
        ),
    ],
)
def test_the_time_said_for_the_shape_asked_is_the_plans(
    runner: CliRunner, args: tuple[str, ...], note: str
) -> None:
    result = run(runner, "plan", *args)
    assert result.exit_code == 0, result.output
    lines = result.stdout.splitlines()
    assert lines[-1] == note
    total = next(line for line in lines if line.startswith("total "))
    data = run(runner, "plan", *args, "--json")
    duration = json.loads(data.stdout)["duration"]
    said = float(note.split(" it takes ")[1].split(" s,")[0])
    assert said == pytest.approx(duration, rel=1e-3), total


def test_the_table_header_rounds_the_plan_and_json_keeps_every_digit(runner: CliRunner) -> None:
    # 0.1 m sideways: a turn of atan2(...) = -74.97388624088052 deg (not a round number).
    table = run(runner, "plan", "--to", "0,0.1,0")
    assert table.exit_code == 0, table.output
    assert table.stdout.splitlines()[0] == (
        "to (0, 0.1, 0 deg): spin -74.9739; straight -0.10354; spin 74.9739; straight 0.0268438"
    )
    data = run(runner, "plan", "--to", "0,0.1,0", "--json")
    plan_text = json.loads(data.stdout)["plan"]
    assert plan_text.startswith("spin -74.97388624088052; straight -0.10354027349439501; ")
    # The full text reads back to the same segments.
    turn = parse_plan(plan_text)[0].angle
    assert math.degrees(turn) == -74.97388624088052


@pytest.mark.parametrize(
    ("args", "expected"),
    [
        (("--to", "0,1,0"), (0.0, 1.0, 0.0)),
        (("--to", "2,-1,135"), (2.0, -1.0, math.radians(135))),
        (("--to", "0.5,0.5,1.5rad"), (0.5, 0.5, 1.5)),
        (("--to", "1,1,-90", "--shape", "dubins", "--min-radius", "0.2"), (1, 1, -math.pi / 2)),
        (("--to", "-1,0,180", "--shape", "reeds-shepp", "--min-radius", "0.5"), (-1, 0, math.pi)),
        (("--to", "-1,0,0", "--forward-only"), (-1.0, 0.0, 0.0)),
        (("--to", "1,1", "--to", "2,0,0", "--shape", "spin-straight-spin"), (2.0, 0.0, 0.0)),
        # From (1, 2) heading 90 deg, the goal (1, 3) heading 90 deg is 1 m straight ahead.
        (("--from", "1,2,90", "--to", "1,3,90"), (1.0, 0.0, 0.0)),
    ],
)
def test_plans_end_at_the_goal(
    runner: CliRunner, args: tuple[str, ...], expected: tuple[float, float, float]
) -> None:
    x, y, theta = final_pose(runner, *args)
    assert x == pytest.approx(expected[0], abs=1e-12)
    assert y == pytest.approx(expected[1], abs=1e-12)
    assert abs(math.remainder(theta - expected[2], 2 * math.pi)) <= 1e-12


@pytest.mark.parametrize(
    ("args", "start", "goal"),
    [
        (("--from", "1,2,90", "--to", "1,3,90"), (1.0, 2.0, math.pi / 2), (1.0, 3.0, math.pi / 2)),
        # A heading past a turn is the same start: said in (-pi, pi], as every pose is.
        (
            ("--from", "-0.5,1,450", "--to", "2,0,-30"),
            (-0.5, 1.0, math.pi / 2),
            (2, 0, -math.pi / 6),
        ),
        (("--to", "0,1,0"), (0.0, 0.0, 0.0), (0.0, 1.0, 0.0)),
        (("--to", "0,1,0", "--rate", "10"), (0.0, 0.0, 0.0), (0.0, 1.0, 0.0)),
        (("--from", "1,0,0", "--to", "2,1,0", "--max-accel", "0.5"), (1.0, 0.0, 0.0), (2, 1, 0)),
    ],
)
def test_the_json_gives_the_start_the_poses_are_relative_to(
    runner: CliRunner,
    args: tuple[str, ...],
    start: tuple[float, float, float],
    goal: tuple[float, float, float],
) -> None:
    # The poses of a goal plan are relative to --from, which its JSON did not give: a reader
    # could not tell where the plan goes.
    result = run(runner, "plan", *args, "--json")
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    given = data["start_pose"]
    assert list(given) == ["x", "y", "theta"]
    assert (given["x"], given["y"]) == pytest.approx(start[:2], abs=1e-15)
    assert given["theta"] == pytest.approx(start[2], abs=1e-15)
    assert data["segments"][0]["start_pose"] == {"x": 0.0, "y": 0.0, "theta": 0.0}
    # The start composed with the plan's final pose is the goal, in the goals' frame.
    end = data["final_pose"]
    c, s = math.cos(given["theta"]), math.sin(given["theta"])
    x = given["x"] + c * end["x"] - s * end["y"]
    y = given["y"] + s * end["x"] + c * end["y"]
    assert (x, y) == pytest.approx(goal[:2], abs=1e-12)
    turn = math.remainder(given["theta"] + end["theta"] - goal[2], 2 * math.pi)
    assert abs(turn) <= 1e-12


def test_a_plan_of_segments_has_no_start_pose_of_its_own(runner: CliRunner) -> None:
    result = run(runner, "plan", "straight 1; spin 90", "--json")
    assert result.exit_code == 0, result.output
    assert "start_pose" not in json.loads(result.stdout)


def test_forward_only_never_backs_up(runner: CliRunner) -> None:
    result = run(runner, "plan", "--to", "-1,0,0", "--forward-only", "--format", "csv")
    rows = list(csv.DictReader(io.StringIO(result.stdout)))
    assert rows
    assert all(float(row["linear"]) >= 0.0 for row in rows)
    backwards = run(runner, "plan", "--to", "-1,0,0", "--format", "csv")
    assert [float(r["linear"]) < 0 for r in csv.DictReader(io.StringIO(backwards.stdout))] == [True]


@pytest.mark.parametrize("fmt", ["csv", "twist", "wheels", "ros2"])
def test_every_format(runner: CliRunner, fmt: str) -> None:
    result = run(runner, "plan", "--to", "0,1,0", "--format", fmt)
    assert result.exit_code == 0, result.output
    assert "2.71495" in result.stdout or "5.23598" in result.stdout  # spins at the limit


def test_ramps_and_rate(runner: CliRunner) -> None:
    result = run(runner, "plan", "--to", "0,1,0", "--max-accel", "0.5")
    assert result.exit_code == 0, result.output
    assert "ramps:" in result.stdout
    sampled = run(runner, "plan", "--to", "0,1,0", "--rate", "10", "--format", "csv")
    assert sampled.exit_code == 0, sampled.output
    assert len(sampled.stdout.splitlines()) > 60  # 6.6 s at 10 Hz


def test_simulate_and_explain_take_a_goal(runner: CliRunner, tmp_path: Path) -> None:
    out = tmp_path / "g.csv"
    result = run(runner, "simulate", "--to", "0,1,0", "--out", str(out), "--quiet")
    assert result.exit_code == 0, result.output
    odom = run(runner, "odom", str(out), "--json")
    pose = json.loads(odom.stdout)["final_pose"]
    assert pose["x"] == pytest.approx(0.0, abs=1e-9)
    assert pose["y"] == pytest.approx(1.0, abs=1e-9)
    explained = run(runner, "explain", "plan", "--to", "0,1,0")
    assert explained.exit_code == 0, explained.output
    assert "segments: 3" in explained.stdout


def test_goal_at_the_start_is_an_empty_plan(runner: CliRunner) -> None:
    result = run(runner, "plan", "--from", "1,2,30", "--to", "1,2,390")
    assert result.exit_code == 0, result.output
    assert (
        result.stdout == "the goal (1, 2, 390 deg) is the start: an empty plan, nothing to drive\n"
    )


@pytest.mark.parametrize(
    "args",
    [
        ["plan", "--json"],
        ["plan", "--format", "csv"],
        ["plan", "--format", "ros2", "-o", "run.sh", "--force"],
        ["simulate", "-o", "run.sh", "--force"],
        ["plot", "-o", "run.png", "--force"],
    ],
)
def test_goal_at_the_start_writes_nothing_and_says_why(
    runner: CliRunner, args: list[str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "run.sh").write_text("# an older plan\n", encoding="utf-8")
    result = runner.invoke(main, [*args, "--from", "1,2,30", "--to", "1,2,390"])
    assert result.exit_code == 2, result.output
    assert result.stdout == ""
    assert result.stderr == (
        "error: the goal (1, 2, 390 deg) is the start: an empty plan, nothing to write\n"
    )
    assert (tmp_path / "run.sh").read_text(encoding="utf-8") == "# an older plan\n"
    assert not (tmp_path / "run.png").exists()


@pytest.mark.parametrize(
    ("name", "text"),
    [
        ("w.csv", "x,y,heading\n1,0\n# a comment\n1,1,90\n"),
        ("w.yaml", "- [1, 0]\n- {x: 1, y: 1, heading: 90}\n"),
        ("w.json", '[[1, 0], {"x": 1, "y": 1, "heading": "1.5707963267948966rad"}]'),
    ],
)
def test_waypoint_files(runner: CliRunner, write: Write, name: str, text: str) -> None:
    path = write(name, text)
    x, y, theta = final_pose(runner, "--waypoints", str(path), "--shape", "spin-straight-spin")
    assert (x, y) == (pytest.approx(1.0, abs=1e-12), pytest.approx(1.0, abs=1e-12))
    assert theta == pytest.approx(math.pi / 2, abs=1e-12)


@pytest.mark.parametrize(
    ("args", "fragments"),
    [
        (("--to", "nan,1,0"), ("--to nan,1,0", "not a finite number")),
        (("--to", "1,inf,0"), ("--to 1,inf,0", "not a finite number")),
        (("--to", "1,1,1e999"), ("not a finite number",)),
        (("--to", "1"), ("give x,y or x,y,heading",)),
        (("--to", "1,1,0", "--min-radius", "0"), ("--min-radius",)),
        (("--to", "1,1,0", "--min-radius", "-1"), ("--min-radius",)),
        (("--to", "1,1,0", "--min-radius", "nan"), ("--min-radius",)),
        (
            ("--to", "1,1,0", "--shape", "dubins"),
            ("needs a minimum turning radius", "--min-radius"),
        ),
        (("--to", "1,1,0", "--from", "0,nan,0"), ("--from 0,nan,0",)),
        (("--shape", "dubins", "--min-radius", "1"), ("give --to",)),
        (("--to", "1,1,0", "straight 1"), ("not both",)),
        (
            ("--to", "1,1,0", "--shape", "reeds-shepp", "--min-radius", "1", "--forward-only"),
            ("--forward-only", "dubins"),
        ),
    ],
)
def test_bad_input(runner: CliRunner, args: tuple[str, ...], fragments: tuple[str, ...]) -> None:
    assert_bad_input(run(runner, "plan", *args), *fragments)


@pytest.mark.parametrize(
    ("name", "text", "fragments"),
    [
        ("empty.csv", "x,y\n# nothing\n", ("no waypoints",)),
        ("bad.csv", "1,0\n2,zero\n", ("bad.csv: row 2", "'zero' is not a number")),
        ("long.csv", "1,0,0,0\n", ("row 1", "4 values")),
        ("bad.yaml", "- [1, 0]\n- {x: 1}\n", ("item 2",)),
        ("none.yaml", "{x: 1}\n", ("is a list",)),
        ("bad.json", "[[1, 0], [1, NaN]]", ("not a finite number",)),
        ("empty.json", "[]", ("no waypoints",)),
    ],
)
def test_bad_waypoint_files(
    runner: CliRunner, write: Write, name: str, text: str, fragments: tuple[str, ...]
) -> None:
    assert_bad_input(run(runner, "plan", "--waypoints", str(write(name, text))), *fragments)


def test_missing_waypoint_file(runner: CliRunner, tmp_path: Path) -> None:
    assert_bad_input(run(runner, "plan", "--waypoints", str(tmp_path / "nope.csv")), "nope.csv")


def test_output_never_over_the_waypoints_file(runner: CliRunner, write: Write) -> None:
    path = write("w.csv", "1,0\n1,1,90\n")
    result = run(runner, "plan", "--waypoints", str(path), "-o", str(path), "--force")
    assert_bad_input(result, "is the plan file itself")
    assert path.read_text(encoding="utf-8") == "1,0\n1,1,90\n"
    inside = run(runner, "plan", "--waypoints", str(path), "-o", f"{path}/x.csv")
    assert_bad_input(inside, f"{path}/x.csv lies inside the input {path}: refusing to overwrite it")
