"""``diffbot calibrate umbmark|fit``, the UMBmark plans and simulate's ground truth, end to end."""

from __future__ import annotations

import json
import shutil
import sys
from pathlib import Path
from xml.etree import ElementTree

import pytest
from click.testing import CliRunner, Result
from robots import BOT

from diffbot.cli import main
from diffbot.io.poses import read_pose_track
from diffbot.urdf import BUNDLED_DESCRIPTION, load_params
from diffbot.urdf.xacro import expand

TRUE = {"left_wheel_radius": 0.0352, "right_wheel_radius": 0.0348, "wheel_separation": 0.138}
SIMULATE_TRUTH = ["--true-wheel-radius", "0.0352,0.0348", "--true-separation", "0.138"]


def run(runner: CliRunner, *args: str) -> Result:
    result = runner.invoke(main, list(args))
    assert result.exit_code == 0, result.output
    return result


def bad_input(runner: CliRunner, *args: str) -> str:
    """The one error line of a run that fails with exit code 2."""
    result = runner.invoke(main, list(args))
    assert result.exit_code == 2, result.output
    assert result.stdout == ""
    (line,) = result.stderr.splitlines()
    assert line.startswith("error: ")
    return line


@pytest.fixture
def run_csv(runner: CliRunner, tmp_path: Path) -> Path:
    """Trajectory A driven by the robot whose real geometry is TRUE, as CSV."""
    path = tmp_path / "run.csv"
    run(runner, "simulate", "--example", "A", *SIMULATE_TRUTH, "--out", str(path))
    return path


# --------------------------------------------------------------------------------------------
# plan --example umbmark


@pytest.mark.parametrize(("flag", "turn"), [("--cw", -90.0), ("--ccw", 90.0), (None, 90.0)])
def test_plan_gives_the_umbmark_square(runner: CliRunner, flag: str | None, turn: float) -> None:
    args = ["plan", "--example", "umbmark", "--side", "4", "--json"]
    data = json.loads(run(runner, *args, *([flag] if flag else [])).stdout)
    segments = data["segments"]
    assert len(segments) == 8
    first, corner = segments[0], segments[1]
    assert first["end_pose"]["x"] == pytest.approx(4.0, abs=1e-12)
    assert first["end_pose"]["y"] == pytest.approx(0.0, abs=1e-12)
    assert corner["end_pose"]["theta"] == pytest.approx(turn * 3.141592653589793 / 180, abs=1e-12)
    end = data["final_pose"]
    assert (end["x"], end["y"]) == pytest.approx((0.0, 0.0), abs=1e-12)


def test_plan_of_the_umbmark_square_needs_its_side(runner: CliRunner) -> None:
    line = bad_input(runner, "plan", "--example", "umbmark")
    assert line == "error: --example umbmark needs --side M, the side of the square (m)"


def test_the_side_belongs_to_the_umbmark_square(runner: CliRunner) -> None:
    line = bad_input(runner, "plan", "--example", "A", "--side", "4")
    assert "give --example umbmark" in line


# --------------------------------------------------------------------------------------------
# simulate --true-wheel-radius --true-separation, then calibrate fit


def test_simulate_adds_the_ground_truth_columns(run_csv: Path) -> None:
    header = run_csv.read_text(encoding="utf-8").splitlines()[0].split(",")
    assert header[-3:] == ["x", "y", "theta"]
    track = read_pose_track(run_csv)
    # The real robot's right wheel is smaller: it ends off the plan's (0, 1).
    assert abs(track.x[-1]) > 1e-3


@pytest.mark.parametrize(
    ("value", "message"),
    [("0.035", "'0.035' is not L,R"), ("0.035,0", "'0.035,0': both must be > 0")],
)
def test_simulate_refuses_true_radii_that_are_not_two_positive_numbers(
    runner: CliRunner, value: str, message: str
) -> None:
    assert message in bad_input(runner, "simulate", "--true-wheel-radius", value)


def test_fit_recovers_the_simulated_truth(runner: CliRunner, run_csv: Path) -> None:
    data = json.loads(run(runner, "calibrate", "fit", str(run_csv), "--json").stdout)
    for key, value in TRUE.items():
        assert data[key] == pytest.approx(value, rel=1e-9)  # the goal is 1e-6
    assert (
        data["residuals"]["position_rms_after"] < 1e-12 < data["residuals"]["position_rms_before"]
    )
    assert data["controller_yaml"][0] == "wheel_separation_multiplier: 1.02222222"
    assert data["xacro_arguments"] == "wheel_radius:=0.035 wheel_separation:=0.138"
    assert data["robot"] == "bundled"


def test_fit_suggests_no_xacro_argument_a_description_does_not_declare(
    runner: CliRunner, run_csv: Path, tmp_path: Path
) -> None:
    # The bundled robot's geometry as a plain URDF: it declares no xacro argument, which
    # wheel_radius:= would be ignored by (a warning says so when it is given).
    root = ElementTree.fromstring(expand().urdf)
    for child in [c for c in root if c.tag in ("gazebo", "ros2_control")]:
        root.remove(child)
    urdf = tmp_path / "diffbot.urdf"
    urdf.write_text(ElementTree.tostring(root, encoding="unicode"), encoding="utf-8")
    args = ["calibrate", "fit", str(run_csv), "--robot", str(urdf)]
    data = json.loads(run(runner, *args, "--json").stdout)
    assert data["wheel_separation"] == pytest.approx(TRUE["wheel_separation"], rel=1e-9)
    assert data["xacro_arguments"] is None
    assert data["note"] is None
    text = run(runner, *args).stdout
    assert "xacro arguments" not in text
    assert "wheel_separation_multiplier: 1.02222222" in text


def velocities_only(run_csv: Path, target: Path) -> Path:
    """The run with its wheel positions replaced by velocities: each the angle advanced over the
    interval that ends at its sample, over that interval (what a controller with
    ``position_feedback: false`` reads), the positions themselves gone."""
    lines = run_csv.read_text().splitlines()
    header = lines[0].split(",")
    left, right = header.index("front_left_wheel_joint"), header.index("front_right_wheel_joint")
    rows = [[float(cell) for cell in line.split(",")] for line in lines[1:]]
    out = ["time,/j/front_left_wheel_joint/velocity,/j/front_right_wheel_joint/velocity,x,y,theta"]
    before = rows[0]
    for row in rows:
        dt = row[0] - before[0]
        speeds = [(row[k] - before[k]) / dt if dt > 0 else 0.0 for k in (left, right)]
        out.append(",".join(repr(v) for v in [row[0], *speeds, *row[-3:]]))
        before = row
    target.write_text("\n".join(out) + "\n")
    return target


def test_fit_of_wheel_velocities_recovers_the_simulated_truth(
    runner: CliRunner, run_csv: Path, tmp_path: Path
) -> None:
    csv = str(velocities_only(run_csv, tmp_path / "velocities.csv"))
    data = json.loads(
        run(runner, "calibrate", "fit", csv, "--feedback", "velocity", "--json").stdout
    )
    for key, value in TRUE.items():
        assert data[key] == pytest.approx(value, rel=1e-9)
    assert data["feedback"] == "velocity"
    text = run(runner, "calibrate", "fit", csv, "--feedback", "velocity").stdout.splitlines()
    assert "feedback      wheel velocities, integrated" in text
    # Read for positions, the file has none: one error line naming what is missing.
    assert "front_left_wheel_joint" in bad_input(runner, "calibrate", "fit", csv)


def test_fit_recovers_the_truth_through_noisy_encoders(runner: CliRunner, tmp_path: Path) -> None:
    path = tmp_path / "noisy.csv"
    noise = ["--ticks", "4096", "--noise", "0.001", "--seed", "3"]
    run(runner, "simulate", "--example", "A", *SIMULATE_TRUTH, *noise, "--out", str(path))
    data = json.loads(run(runner, "calibrate", "fit", str(path), "--json").stdout)
    for key, value in TRUE.items():
        assert data[key] == pytest.approx(value, rel=2e-3)


def test_fit_reads_a_bag_with_its_ground_truth_topic(runner: CliRunner, tmp_path: Path) -> None:
    bag = tmp_path / "run_bag"
    run(runner, "simulate", "--example", "A", *SIMULATE_TRUTH, "--out", str(bag), "--bag")
    data = json.loads(run(runner, "calibrate", "fit", str(bag), "--json").stdout)
    for key, value in TRUE.items():
        assert data[key] == pytest.approx(value, rel=1e-9)


def test_fit_prints_the_geometry_and_how_to_apply_it(runner: CliRunner, run_csv: Path) -> None:
    lines = run(runner, "calibrate", "fit", str(run_csv)).stdout.splitlines()
    assert lines[0] == "robot         bundled"
    assert lines[1] == "windows       40"
    assert lines[3].startswith("left radius   0.0352 m ± ")
    assert "  left_wheel_radius_multiplier: 1.00571429" in lines
    assert lines[-1].startswith("note: the radii differ")


def test_fit_takes_the_truth_from_another_file(
    runner: CliRunner, run_csv: Path, tmp_path: Path
) -> None:
    rows = [line.split(",") for line in run_csv.read_text(encoding="utf-8").splitlines()]
    joints = tmp_path / "joints.csv"
    joints.write_text("\n".join(",".join(r[:3]) for r in rows) + "\n", encoding="utf-8")
    truth = tmp_path / "truth.csv"
    truth.write_text("\n".join(",".join([r[0], *r[-3:]]) for r in rows[::3]) + "\n", "utf-8")
    args = ["calibrate", "fit", str(joints), "--truth", str(truth), "--json"]
    data = json.loads(run(runner, *args).stdout)
    for key, value in TRUE.items():  # the truth interpolated between its samples
        assert data[key] == pytest.approx(value, rel=1e-4)
    line = bad_input(runner, "calibrate", "fit", str(joints))
    assert "no ground truth: needs x, y, theta" in line


def test_fit_says_how_many_samples_the_reader_skipped_and_why(
    runner: CliRunner, run_csv: Path, tmp_path: Path
) -> None:
    rows = [line.split(",") for line in run_csv.read_text(encoding="utf-8").splitlines()]
    joints = tmp_path / "joints.csv"
    rows[7][1] = "seven"  # one unreadable wheel cell: that row is skipped, as odom skips it
    joints.write_text("\n".join(",".join(r[:3]) for r in rows) + "\n", encoding="utf-8")
    truth = tmp_path / "truth.csv"
    truth.write_text("\n".join(",".join([r[0], *r[-3:]]) for r in rows) + "\n", "utf-8")
    result = run(runner, "calibrate", "fit", str(joints), "--truth", str(truth), "--json")
    samples = len(rows) - 1
    want = f"warning: {joints}: skipped 1 of {samples} samples: 1 unreadable value"
    assert want in result.stderr.splitlines()


def test_fit_of_a_recording_with_a_wheel_jump_exits_1_with_odom_s_warning(
    runner: CliRunner, run_csv: Path, tmp_path: Path
) -> None:
    rows = [line.split(",") for line in run_csv.read_text(encoding="utf-8").splitlines()]
    for row in rows[len(rows) // 2 :]:
        row[1] = repr(float(row[1]) + 50.0)  # the left encoder jumps by 50 rad, mid-run
    jumped = tmp_path / "jumped.csv"
    jumped.write_text("\n".join(",".join(r) for r in rows) + "\n", encoding="utf-8")
    fitted = runner.invoke(main, ["calibrate", "fit", str(jumped), "--json"])
    odom = runner.invoke(main, ["odom", str(jumped), "--json"])
    assert (fitted.exit_code, odom.exit_code) == (1, 1), fitted.output
    warning = next(line for line in odom.stderr.splitlines() if "implausible step" in line)
    assert warning in fitted.stderr.splitlines()
    # The fit is still reported, for what it is worth.
    assert "wheel_separation" in json.loads(fitted.stdout)
    assert run(runner, "calibrate", "fit", str(run_csv)).exit_code == 0


def test_fit_writes_a_calibrated_copy_beside_the_file(
    runner: CliRunner, run_csv: Path, tmp_path: Path
) -> None:
    folder = tmp_path / "description"
    shutil.copytree(BUNDLED_DESCRIPTION.parent, folder)
    source = folder / "robot.urdf.xacro"
    (folder / BUNDLED_DESCRIPTION.name).rename(source)
    text = source.read_text(encoding="utf-8")
    packages = [f"--package=diffbot_{name}={folder}" for name in ("description", "control")]
    args = ["calibrate", "fit", str(run_csv), *packages, "--apply-to", str(source)]
    result = run(runner, *args)
    copy = folder / "robot.calibrated.urdf.xacro"
    assert f"wrote {copy}" in result.stdout
    assert '<xacro:arg name="wheel_separation" default="0.138"/>' in copy.read_text("utf-8")
    params = load_params(copy, packages={"diffbot_description": folder, "diffbot_control": folder})
    assert params.wheel_separation == pytest.approx(0.138, rel=1e-9)
    assert source.read_text(encoding="utf-8") == text
    line = bad_input(runner, *args)
    assert line == f"error: {copy} exists: use --force to overwrite it"
    line = bad_input(runner, "calibrate", "fit", str(run_csv), "--apply-to", "none.yaml")
    assert line == "error: --apply-to none.yaml: no such file"
    run(runner, *args, "--force")


@pytest.mark.parametrize(
    ("name", "fragment"),
    [
        (".", "ends with '.', a folder"),
        ("/", "the root, a folder"),
        ("", "an empty name"),
        ("controllers.yaml/.", "ends with '.', a folder"),
        ("controllers.yaml/", "ends with a slash"),
    ],
)
def test_apply_to_a_name_of_no_file_is_one_error_line(
    runner: CliRunner, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, name: str, fragment: str
) -> None:
    # controllers.yaml/. once read controllers.yaml; "." and "/" ended in a traceback
    monkeypatch.chdir(tmp_path)
    (tmp_path / "controllers.yaml").write_text("a: 1\n", encoding="utf-8")
    for words in (["fit", "run.csv"], ["umbmark", "--side", "4", "--cw", "0,0", "--ccw", "0,0"]):
        line = bad_input(runner, "calibrate", *words, "--apply-to", name)
        assert line.startswith(f"error: --apply-to {name or repr(name)}"), line
        assert fragment in line, line
    assert sorted(p.name for p in tmp_path.iterdir()) == ["controllers.yaml"]


ROVER = Path(__file__).resolve().parents[2] / "docs" / "examples" / "rover"


def test_fit_of_a_robot_with_a_controller_rewrites_its_multipliers(
    runner: CliRunner, tmp_path: Path
) -> None:
    # The rover's controller scales wheel_radius 0.05 m by 1.002 and 0.998; the real robot
    # rolls on 0.0503 m and 0.0497 m, 0.306 m apart.
    robot = ["--robot", str(ROVER / "urdf" / "rover.urdf.xacro")]
    robot += ["--package", f"rover_description={ROVER}"]
    path = tmp_path / "rover.csv"
    truth = ["--true-wheel-radius", "0.0503,0.0497", "--true-separation", "0.306"]
    run(runner, "simulate", *robot, "--example", "A", *truth, "--out", str(path))
    controllers = tmp_path / "controllers.yaml"
    controllers.write_bytes((ROVER / "config" / "controllers.yaml").read_bytes())
    args = ["calibrate", "fit", str(path), *robot, "--apply-to", str(controllers), "--json"]
    data = json.loads(run(runner, *args).stdout)
    assert data["nominal"]["left_wheel_radius"] == pytest.approx(0.0501, rel=1e-12)
    assert data["left_wheel_radius"] == pytest.approx(0.0503, rel=1e-9)
    assert data["controller_yaml"] == [
        "wheel_separation_multiplier: 1.02",
        "left_wheel_radius_multiplier: 1.006",
        "right_wheel_radius_multiplier: 0.994",
    ]
    copy = (tmp_path / "controllers.calibrated.yaml").read_text(encoding="utf-8")
    assert "      left_wheel_radius_multiplier: 1.006\n" in copy


def test_fit_refuses_both_kinds_of_window(runner: CliRunner, run_csv: Path) -> None:
    line = bad_input(
        runner, "calibrate", "fit", str(run_csv), "--window", "5", "--window-duration", "1"
    )
    assert line == "error: give --window or --window-duration, not both"


def test_fit_spells_the_window_as_its_option(runner: CliRunner, run_csv: Path) -> None:
    line = bad_input(runner, "calibrate", "fit", str(run_csv), "--window", "100000")
    assert line.endswith("at least two are needed (shorten --window)")


def test_fit_without_scipy_says_what_to_install(
    runner: CliRunner, run_csv: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setitem(sys.modules, "scipy", None)
    monkeypatch.setitem(sys.modules, "scipy.optimize", None)
    line = bad_input(runner, "calibrate", "fit", str(run_csv))
    assert line == (
        "error: the least-squares fit needs SciPy: pip install scipy (a dependency of "
        "diffbot-kinematics: the environment lacks it)"
    )


# --------------------------------------------------------------------------------------------
# calibrate umbmark

RUNS = ["--cw", "-0.31,-0.40", "--cw", "-0.36,-0.39", "--ccw", "0.12,-0.09", "--ccw", "0.10,-0.12"]


def test_umbmark_json_has_the_params_keys_and_the_errors(runner: CliRunner) -> None:
    data = json.loads(run(runner, "calibrate", "umbmark", "--side", "4", *RUNS, "--json").stdout)
    assert list(data)[:5] == [
        "left_wheel_radius",
        "right_wheel_radius",
        "wheel_separation",
        "ed",
        "eb",
    ]
    assert data["cw_centre"] == pytest.approx([-0.335, -0.395], abs=1e-12)
    assert data["eb"] == pytest.approx(data["wheel_separation"] / BOT.wheel_separation, rel=1e-12)
    assert data["ed"] == pytest.approx(
        data["right_wheel_radius"] / data["left_wheel_radius"], rel=1e-12
    )
    assert data["applied_to"] is None


def test_umbmark_of_simulated_squares_recovers_the_truth(runner: CliRunner, tmp_path: Path) -> None:
    # Radii 0.1 % apart, separation 1 % off: the squares simulate drives end where UMBmark
    # measures; --exact recovers the robot to rounding, the first-order formulas within their
    # bound (docs/calibration.md: 5 % of the separation's error).
    truth = ["--true-wheel-radius", "0.0349825,0.0350175", "--true-separation", "0.13635"]
    ends = []
    for direction in ("--cw", "--ccw"):
        path = tmp_path / f"{direction[2:]}.csv"
        square = ["--example", "umbmark", "--side", "4", direction, "--rate", "1"]
        run(runner, "simulate", *square, *truth, "--out", str(path))
        last = path.read_text(encoding="utf-8").splitlines()[-1].split(",")
        ends += [direction, f"{last[-3]},{last[-2]}"]
    exact = json.loads(
        run(runner, "calibrate", "umbmark", "--side", "4", *ends, "--exact", "--json").stdout
    )
    assert exact["left_wheel_radius"] == pytest.approx(0.0349825, rel=1e-9)
    assert exact["right_wheel_radius"] == pytest.approx(0.0350175, rel=1e-9)
    assert exact["wheel_separation"] == pytest.approx(0.13635, rel=1e-9)
    first = json.loads(run(runner, "calibrate", "umbmark", "--side", "4", *ends, "--json").stdout)
    assert abs(first["wheel_separation"] - 0.13635) < 0.05 * (0.13635 - 0.135)


def test_umbmark_reads_its_runs_from_yaml_and_csv(runner: CliRunner, tmp_path: Path) -> None:
    given = json.loads(run(runner, "calibrate", "umbmark", "--side", "4", *RUNS, "--json").stdout)
    runs_yaml = tmp_path / "runs.yaml"
    runs_yaml.write_text("cw: [[-0.31, -0.40], [-0.36, -0.39]]\nccw:\n  - [0.12, -0.09]\n", "utf-8")
    runs_csv = tmp_path / "runs.csv"
    runs_csv.write_text("direction,x,y\nccw,0.10,-0.12\n", "utf-8")
    args = ["--runs", str(runs_yaml), "--ccw", "0.10,-0.12", "--json"]
    from_yaml = json.loads(run(runner, "calibrate", "umbmark", "--side", "4", *args).stdout)
    assert from_yaml == given
    args = [*RUNS[:6], "--runs", str(runs_csv), "--json"]
    from_csv = json.loads(run(runner, "calibrate", "umbmark", "--side", "4", *args).stdout)
    assert from_csv == given


def test_umbmark_prints_the_errors_for_people(runner: CliRunner) -> None:
    lines = run(runner, "calibrate", "umbmark", "--side", "4", *RUNS).stdout.splitlines()
    assert lines[0] == "cw centre     x -0.335 m, y -0.395 m"
    assert lines[4].startswith("Ed            1.00100")
    assert lines[5].startswith("Eb            1.0103")


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--cw", "0,0"], "needs at least one clockwise and one counter-clockwise run"),
        (["--cw", "1", "--ccw", "0,0"], "'1' is not X,Y"),
        (["--cw", "a,0", "--ccw", "0,0"], "'--cw': 'a,0': 'a' is not a number"),
        (["--cw", "0,0", "--ccw", "0,-inf"], "'--ccw': '0,-inf': '-inf' is not a finite"),
        (
            ["--cw", "-0.14,-0.14", "--ccw", "0.14,-0.14", "--side", "0.05"],
            "small-error approximation",
        ),
        (["--cw", "-7,-7", "--ccw", "-7,7", "--side", "1"], "farther from its start than the 4 m"),
    ],
)
def test_umbmark_refuses_bad_runs(runner: CliRunner, args: list[str], message: str) -> None:
    side = [] if "--side" in args else ["--side", "4"]
    assert message in bad_input(runner, "calibrate", "umbmark", *side, *args)


def test_umbmark_refuses_a_runs_file_of_another_shape(runner: CliRunner, tmp_path: Path) -> None:
    path = tmp_path / "runs.yaml"
    path.write_text("left: [[0, 0]]\n", "utf-8")
    line = bad_input(runner, "calibrate", "umbmark", "--side", "4", "--runs", str(path))
    assert "a runs YAML maps cw and ccw to lists of [x, y]" in line


def test_the_output_option_says_where_the_calibrated_copy_goes(
    runner: CliRunner, tmp_path: Path
) -> None:
    source = tmp_path / "controllers.yaml"
    # the controllers file of docs/plans.md: one diff_drive_controller
    source.write_text(
        (Path(__file__).parents[2] / "docs" / "examples" / "slow.yaml").read_text(), "utf-8"
    )
    umbmark = ["calibrate", "umbmark", "--side", "4", "--cw", "-0.3356,-0.3958"]
    umbmark += ["--ccw", "0.1133,-0.1056", "--apply-to", str(source)]
    for spelling in ("-o", "--output", "--out"):
        target = tmp_path / f"copy{spelling}.yaml"
        result = runner.invoke(main, [*umbmark, spelling, str(target)])
        assert result.exit_code == 0, result.output
        assert "wheel_separation_multiplier: 1.01030089" in target.read_text(encoding="utf-8")
    assert not (tmp_path / "controllers.calibrated.yaml").exists()
    result = runner.invoke(main, [*umbmark[:-2], "-o", str(tmp_path / "x.yaml")])
    assert result.exit_code == 2
    assert "give --apply-to FILE too" in result.stderr
