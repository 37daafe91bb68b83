"""Hostile numbers on the command line and in the files it reads: each is one ``error:`` line
naming where it came from (file, key, option), exit 2, and never a traceback, an ``inf`` in
the output or a NumPy warning on the terminal."""

from __future__ import annotations

import csv
import json
import math
import sqlite3
from collections.abc import Callable
from pathlib import Path

import click
import pytest
from cli_results import assert_one_error_line
from click.testing import CliRunner, Result
from extras import need

from diffbot.cli import main
from diffbot.commands.messages import warn
from diffbot.commands.options import InputError, emit_json

Write = Callable[[str, str], Path]

#: A diff-drive controller for the bundled robot; ``{extra}`` adds lines to its parameters.
CONTROLLERS = """\
controller_manager:
  ros__parameters:
    update_rate: 50
    diff_cont: {{type: diff_drive_controller/DiffDriveController}}
diff_cont:
  ros__parameters:
    left_wheel_names: [front_left_wheel_joint]
    right_wheel_names: [front_right_wheel_joint]
    wheel_separation: {separation}
    wheel_radius: 0.035
{extra}"""


def run(*args: str) -> Result:
    return CliRunner().invoke(main, list(args), catch_exceptions=False, prog_name="diffbot")


def assert_clean_error(result: Result, *fragments: str) -> None:
    """One error line with the fragments, and no warning of any library before it."""
    assert_one_error_line(result, *fragments)
    assert "Warning" not in result.stderr


def controllers(write: Write, separation: str = "0.135", extra: str = "") -> Path:
    return write("controllers.yaml", CONTROLLERS.format(separation=separation, extra=extra))


# --- controllers files ------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("separation", "fragments"),
    [
        ("1" * 400, ("wheel_separation", "an integer of about 400 digits")),
        ("1" * 5000, ("controllers.yaml", "a number too long to read")),
    ],
)
def test_a_controllers_integer_too_large_for_a_float_is_one_error(
    write: Write, separation: str, fragments: tuple[str, ...]
) -> None:
    path = controllers(write, separation)
    assert_clean_error(run("params", "--controllers", str(path)), str(path), *fragments)


def test_a_controllers_type_given_as_a_list_is_no_diff_drive_controller(write: Write) -> None:
    path = write(
        "controllers.yaml",
        "controller_manager:\n  ros__parameters:\n    diff_cont: {type: [a, b]}\n"
        "diff_cont:\n  ros__parameters:\n    type: [x]\n    wheel_separation: 0.1\n",
    )
    assert_clean_error(run("params", "--controllers", str(path)), "no diff_drive_controller")


def test_a_radius_multiplier_gets_the_size_check_of_a_radius(write: Write) -> None:
    path = controllers(write, extra="    left_wheel_radius_multiplier: 1.0e308\n")
    assert_clean_error(
        run("params", "--controllers", str(path)),
        "left wheel radius 3.5e+306 m",
        "left_wheel_radius_multiplier",
        "outside 0.0001..1000 m",
    )


def test_a_jerk_limit_of_1e_300_from_a_controllers_file_is_refused(write: Write) -> None:
    path = controllers(write, extra="    linear.x.max_jerk: 1.0e-300\n")
    result = run("plan", "straight 1", "--controllers", str(path))
    assert_clean_error(
        result, "jerk limit of 1e-300", "more than 1e+06 s", f"the controller 'diff_cont' in {path}"
    )


# --- limits of ramped plans -----------------------------------------------------------------


@pytest.mark.parametrize("command", [["plan"], ["explain", "plan"], ["plot", "-o", "p.png"]])
def test_a_jerk_limit_of_1e_300_is_refused_by_every_command_that_ramps(
    command: list[str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    need("matplotlib")
    monkeypatch.chdir(tmp_path)
    result = run(*command, "straight 1", "--max-jerk", "1e-300")
    assert_clean_error(result, "jerk limit of 1e-300", "more than 1e+06 s", "--max-jerk 1e-300")
    assert not (tmp_path / "p.png").exists()


@pytest.mark.parametrize(
    ("limits", "fragment"),
    [
        (["--max-accel", "1e-300"], "acceleration limit of 1e-300"),
        (["--max-wheel-accel", "1e-300"], "acceleration limit of 3.5e-302"),
        (["--speed", "1e-7", "--max-accel", "1"], "speed limit of 1e-07"),
    ],
)
def test_limits_that_make_a_plan_run_past_a_million_seconds_are_refused(
    limits: list[str], fragment: str
) -> None:
    assert_clean_error(run("plan", "straight 1", *limits), fragment, "more than 1e+06 s")


def test_a_huge_acceleration_with_a_small_jerk_plans_as_the_jerk_allows() -> None:
    # 1e200 m/s² is never reached: at 0.1 m/s and 0.001 m/s³ the speed limit binds from
    # sqrt(v·j) = 0.01 m/s² on, so the plan is the one of that acceleration limit.
    huge = run("plan", "straight 1", "--max-accel", "1e200", "--max-jerk", "0.001", "--json")
    exact = run("plan", "straight 1", "--max-accel", "0.01", "--max-jerk", "0.001", "--json")
    assert huge.exit_code == 0, huge.output
    assert json.loads(huge.stdout)["duration"] == pytest.approx(
        json.loads(exact.stdout)["duration"], rel=1e-12
    )


def test_a_command_rate_of_5e_324_is_refused() -> None:
    result = run("plan", "straight 1", "--rate", "5e-324", "--format", "csv")
    assert_clean_error(result, "--rate", "5e-324", ">= 1e-06")
    assert "inf" not in result.stdout


# --- calibrate umbmark ----------------------------------------------------------------------


@pytest.mark.parametrize("corner", ["1e10,0", "1e300,1e300", "-1e300,-1e300", "1e308,1e308"])
@pytest.mark.parametrize("exact", [[], ["--exact"]])
def test_umbmark_runs_ending_beyond_the_square_are_refused(corner: str, exact: list[str]) -> None:
    result = run(
        "calibrate", "umbmark", "--side", "1", "--cw", corner, "--ccw", corner, "--json", *exact
    )
    assert_clean_error(result, "farther from its start than the 4 m")
    assert result.stdout == ""


@pytest.mark.parametrize("corner", ["3.9,0", "2,2", "-2,1"])
def test_umbmark_exact_fit_that_leaves_the_model_is_one_error(corner: str) -> None:
    result = run("calibrate", "umbmark", "--side", "1", "--cw", corner, "--ccw", corner, "--exact")
    assert_clean_error(result, "does not converge")


@pytest.mark.parametrize(
    ("text", "fragment"),
    [
        ("cw: 5\nccw: [[0.1, 0.1]]\n", "cw must be a list of [x, y] (m), got 5"),
        (f"cw: [[{'9' * 5000}, 0]]\nccw: [[0, 0]]\n", "a number too long to read"),
        (f"cw: [[{'1' * 400}, 0]]\nccw: [[0, 0]]\n", "cw x must be a finite number"),
        ("cw: " + "[" * 50_000 + "]" * 50_000 + "\n", "nested more than 32 deep"),
        ("cw: [[true, 0]]\nccw: [[0, 0]]\n", "cw x must be a finite number, got True"),
    ],
)
def test_a_hostile_runs_file_is_one_error_naming_it(write: Write, text: str, fragment: str) -> None:
    path = write("runs.yaml", text)
    assert_clean_error(run("calibrate", "umbmark", "--side", "1", "--runs", str(path)), fragment)


def test_a_runs_csv_with_an_infinite_end_names_the_file(write: Write) -> None:
    path = write("runs.csv", "direction,x,y\ncw,1e999,0\nccw,0,0\n")
    result = run("calibrate", "umbmark", "--side", "1", "--runs", str(path))
    assert_clean_error(result, f"{path}: cw x must be a finite number")


# --- calibrate fit --------------------------------------------------------------------------


@pytest.fixture(scope="module")
def recording(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The bundled robot driving Trajectory A with wheels off nominal, truth columns included."""
    path = tmp_path_factory.mktemp("fit") / "run.csv"
    result = run(
        "simulate", "--example", "A", "--true-wheel-radius", "0.0352,0.0348",
        "--true-separation", "0.138", "--out", str(path),
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    return path


def truth_file(recording: Path, path: Path, change: Callable[[int, list[str]], list[str]]) -> Path:
    """The recording's truth columns as a truth CSV, each row changed by ``change``."""
    with recording.open(newline="") as stream:
        rows = list(csv.reader(stream))
    columns = [rows[0].index(name) for name in ("time", "x", "y", "theta")]
    with path.open("w", newline="") as stream:
        out = csv.writer(stream)
        out.writerow(["time", "x", "y", "theta"])
        for k, row in enumerate(rows[1:]):
            out.writerow(change(k, [row[i] for i in columns]))
    return path


def test_fit_with_a_window_duration_of_1e_300_is_refused(recording: Path) -> None:
    need("scipy")
    result = run("calibrate", "fit", str(recording), "--window-duration", "1e-300")
    assert_clean_error(result, "--window-duration 1e-300 s", "give at least 0.02 s")


@pytest.mark.parametrize("offset", [1e10, -1e10])
def test_fit_with_truth_stamps_beyond_int64_nanoseconds_is_refused(
    recording: Path, tmp_path: Path, offset: float
) -> None:
    need("scipy")
    truth = truth_file(
        recording, tmp_path / "truth.csv", lambda k, row: [repr(float(row[0]) + offset), *row[1:]]
    )
    result = run("calibrate", "fit", str(recording), "--truth", str(truth))
    assert_clean_error(result, f"{truth}: line 2: time", "int64 nanosecond")


@pytest.mark.parametrize(
    ("column", "fragment"), [(1, "line 3: x must be a finite number"), (3, "line 3: theta")]
)
def test_fit_with_truth_poses_beyond_any_drive_is_refused_before_numpy_warns(
    recording: Path, tmp_path: Path, column: int, fragment: str
) -> None:
    need("scipy")

    def huge(k: int, row: list[str]) -> list[str]:
        row[column] = repr(float(row[column]) * 1e306)
        return row

    truth = truth_file(recording, tmp_path / "truth.csv", huge)
    assert_clean_error(run("calibrate", "fit", str(recording), "--truth", str(truth)), fragment)


# --- explain odom -----------------------------------------------------------------------------


def test_explain_odom_with_wheel_angles_of_1e308_is_refused() -> None:
    result = run("explain", "odom", "1e308", "-1e308", "-1e308", "1e308", "1")
    assert_clean_error(result, "left0", "<= 1e+12 rad", "1e+308")


def test_explain_odom_prints_a_finite_heading_change_in_finite_degrees() -> None:
    # dθ = 2·0.035·1e12/0.135 rad: large but finite, and so in degrees.
    result = run("explain", "odom", "0", "0", "-1e12", "1e12", "1")
    assert result.exit_code == 0, result.output
    assert "inf" not in result.stdout
    assert "5.185e+11 rad" in result.stdout


def test_explain_odom_of_angles_beyond_a_recordings_range_is_refused_not_inf() -> None:
    result = run("explain", "odom", "0", "0", "-1e307", "1e307", "1")
    assert_clean_error(result, "left1", "-1e+307")
    assert "inf" not in result.stdout


# --- bags ---------------------------------------------------------------------------------------


@pytest.mark.parametrize("jobs", ["1", "2"])
def test_text_cells_in_a_bags_messages_are_skipped_as_unreadable(tmp_path: Path, jobs: str) -> None:
    need("rosbags")
    bag = tmp_path / "bag"
    made = run("simulate", "straight 0.2", "--out", str(bag), "--bag")
    assert made.exit_code == 0, made.output
    (database,) = bag.glob("*.db3")
    with sqlite3.connect(database) as connection:
        total = connection.execute("SELECT count(*) FROM messages").fetchone()[0]
        connection.execute("UPDATE messages SET data = 'hello' WHERE id % 7 = 3")
        connection.execute("UPDATE messages SET data = 1.5 WHERE id % 7 = 5")
        hit = connection.execute("SELECT count(*) FROM messages WHERE typeof(data) != 'blob'")
        spoiled = hit.fetchone()[0]
    connection.close()
    result = run("odom", str(bag), "--json", "--jobs", jobs)
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert data["skipped"] == {"unreadable value": spoiled}
    assert data["samples"] == total - spoiled


# --- options ------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("option", "value", "fragment"),
    [
        ("--true-wheel-radius", "1e308,1e308", "both must be from 0.0001 to 1000 m"),
        ("--true-wheel-radius", "0.035,1e-9", "both must be from 0.0001 to 1000 m"),
        ("--true-separation", "1e-5", "must be >= 0.0001"),
        ("--true-separation", "1e308", "must be <= 1000"),
    ],
)
def test_a_true_robot_of_no_real_size_is_refused(option: str, value: str, fragment: str) -> None:
    assert_clean_error(run("simulate", "straight 1", option, value), option, fragment)


@pytest.mark.parametrize("command", [("simulate", "straight 1"), ("node", "robot")])
@pytest.mark.parametrize("value", ["1e308", "7", "-1"])
def test_encoder_noise_beyond_a_revolution_is_refused(command: tuple[str, str], value: str) -> None:
    # Noise of more than a revolution says nothing of the angle (1e308 wrote angles of 1e307).
    result = run(*command, "--noise", value)
    assert_clean_error(result, "--noise", "6.28319" if value != "-1" else ">= 0")


def test_json_that_cannot_hold_a_result_is_an_error_not_a_traceback() -> None:
    with pytest.raises(InputError, match="infinite or NaN"):
        emit_json({"wheel_separation": math.inf})


# --- plans beyond any drive ---------------------------------------------------------------------


@pytest.mark.parametrize("command", ["plan", "simulate", "plot", "explain plan"])
@pytest.mark.parametrize(
    ("spec", "fragment"),
    [
        # A heading of 1.7e18 rad has no digit left below a turn: the end heading is noise.
        ("spin 1e20", "turns more than 1e+09 rad"),
        ("straight 1e200", "ends more than 1e+09 m from its start"),
        ("ccw 1e12 90", "ends more than 1e+09 m from its start"),
    ],
)
def test_a_plan_beyond_any_drive_is_refused_not_printed(
    command: str, spec: str, fragment: str, tmp_path: Path
) -> None:
    out = ["-o", str(tmp_path / "p.png")] if command == "plot" else []
    result = run(*command.split(), spec, *out)
    assert_clean_error(result, fragment)
    assert not (tmp_path / "p.png").exists()


@pytest.mark.parametrize(
    ("option", "value"), [("--counts-per-rev", "1e-320"), ("--wrap", "1e-320")]
)
def test_encoder_settings_of_no_real_size_are_refused_before_numpy_warns(
    option: str, value: str, tmp_path: Path
) -> None:
    joints = tmp_path / "joints.csv"
    joints.write_text(
        "time,front_left_wheel_joint,front_right_wheel_joint\n0,0,0\n0.1,5,7\n0.2,9,14\n",
        "utf-8",
    )
    assert_clean_error(run("odom", str(joints), option, value), option.lstrip("-").split("-")[0])


@pytest.mark.parametrize("side", ["1e308", "2e9"])
def test_umbmark_square_beyond_any_drive_is_refused(side: str) -> None:
    # A side of 1e308 m gave the nominal robot back, its errors lost below rounding, exit 0.
    result = run("calibrate", "umbmark", "--side", side, "--cw", "-0.3,-0.4", "--ccw", "0.1,-0.1")
    assert_clean_error(result, "side must be a finite number > 0 and <= 1e+09 m")


@pytest.mark.parametrize(
    ("args", "flag"),
    [
        (["odom", "RECORDING", "--wrap", "1e300"], "--wrap (0 for none) must be"),
        (["odom", "RECORDING", "--counts-per-rev", "1e300"], "--counts-per-rev (encoder counts"),
        (
            ["plan", "--to", "1,1,0", "--shape", "dubins", "--min-radius", "1e-300"],
            "--min-radius (the minimum turning radius) must be",
        ),
    ],
)
def test_values_refused_past_the_options_own_checks_name_the_option(
    tmp_path: Path, args: list[str], flag: str
) -> None:
    recording = tmp_path / "r.csv"
    recording.write_text("t,front_left_wheel_joint,front_right_wheel_joint\n0,0,0\n1,1,1\n")
    result = run(*[str(recording) if a == "RECORDING" else a for a in args])
    assert_clean_error(result, flag)


# --- what the error line shows of a long number ------------------------------------------------


@pytest.mark.parametrize(
    "args",
    [
        ("fk", "9" * 400, "1"),
        ("ik", "1", "7" * 400),
        ("plan", "--max-linear", "3" * 400, "straight 1"),
        ("odom", "--wrap", "5" * 400, "-"),
    ],
    ids=["fk", "ik", "plan-option", "odom-wrap"],
)
def test_an_error_line_shows_a_400_digit_number_cut_short(args: tuple[str, ...]) -> None:
    result = run(*args)
    assert result.exit_code == 2
    line = result.stderr.strip()
    assert line.startswith("error: ")
    assert "\n" not in line
    assert "..." in line
    # The number's ends stay, its middle goes: the line is about as long as for a short number.
    assert len(line) < 200
    assert max(len(run_) for run_ in line.replace(".", " ").replace("'", " ").split()) <= 40


def test_a_warning_line_shows_a_400_digit_number_cut_short() -> None:
    @click.command()
    def speak() -> None:
        warn(f"odd value {'8' * 400} kept")

    result = CliRunner().invoke(speak, [])
    assert result.stderr == f"warning: odd value {'8' * 18}...{'8' * 18} kept\n"


@pytest.mark.parametrize("number", ["\u0665\u0660", "5_0", "\uff15\uff10"])
@pytest.mark.parametrize(
    "args",
    [
        ["plan", "straight 1", "--max-rpm", "{}"],
        ["ik", "{}", "0"],
        ["plan", "--to", "{},0"],
        ["simulate", "--example", "A", "--ticks", "{}"],
        ["calibrate", "umbmark", "--side", "4", "--cw", "{},0", "--ccw", "0,0"],
    ],
)
def test_a_number_in_another_scripts_digits_or_grouped_is_refused_by_every_option(
    args: list[str], number: str
) -> None:
    result = run(*(a.format(number) for a in args))
    assert_clean_error(result, repr(number).strip("'"))
