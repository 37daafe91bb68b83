"""``diffbot explain``: the library's derivations on the command line, and bad input."""

from __future__ import annotations

from pathlib import Path

import pytest
from cli_results import assert_one_error_line
from click.testing import CliRunner, Result
from rendered import equations

from diffbot.cli import main
from diffbot.explain import explain_fk, explain_ik, explain_odom, explain_plan, render
from diffbot.explain.notation import MINUS
from diffbot.kinematics import DiffDriveParams, rad_s_from_rpm
from diffbot.planfile import parse_plan
from diffbot.trajectory import EXAMPLES, plan
from diffbot.urdf import load_params


def run(runner: CliRunner, *args: str) -> Result:
    return runner.invoke(main, ["explain", *args], catch_exceptions=False, prog_name="diffbot")


def assert_bad_input(result: Result, fragment: str) -> None:
    assert_one_error_line(result, fragment)
    assert result.stdout == ""


def test_spanish_ik_of_0_1_m_s_gives_2_857_rad_s_and_27_3_rpm(runner: CliRunner) -> None:
    result = run(runner, "ik", "0.1", "0", "--lang", "es")
    assert result.exit_code == 0, result.output
    assert "Cinemática inversa" in result.stdout
    line = "ω_L = (v - ω·b/2) / r = (0.1 - 0·0.135/2) / 0.035 = 2.857 rad/s (27.3 rpm)"
    assert line.replace(" - ", f" {MINUS} ") in result.stdout
    assert "27.3 rpm ≤ 50 rpm: dentro del límite del motor" in result.stdout


@pytest.mark.parametrize("lang", ["en", "es"])
@pytest.mark.parametrize("fmt", ["text", "md"])
def test_each_subcommand_prints_the_librarys_derivation_of_the_bundled_robot(
    runner: CliRunner, params: DiffDriveParams, lang: str, fmt: str
) -> None:
    cases = [
        (["ik", "0.157", "-0.314"], explain_ik(params, 0.157, -0.314)),
        (["fk", "-1", "2.5"], explain_fk(params, -1.0, 2.5)),
        (["odom", "0", "0", "1", "1.5", "0.1"], explain_odom(params, 0.0, 0.0, 1.0, 1.5, 0.1)),
        (["plan", "--example", "B"], explain_plan(plan(parse_plan(EXAMPLES["B"]), params))),
        (["plan"], explain_plan(plan(parse_plan(EXAMPLES["A"]), params))),
    ]
    for args, derivation in cases:
        result = run(runner, *args, "--lang", lang, "--format", fmt)
        assert result.exit_code == 0, result.output
        assert result.stdout == render(derivation, fmt, lang)


def test_the_plan_options_and_a_plan_text_are_those_of_diffbot_plan(
    runner: CliRunner, params: DiffDriveParams
) -> None:
    text = "straight 1; cw 0.5 90"
    fastest = plan(parse_plan(text), params, fastest=True, limit=rad_s_from_rpm(30.0))
    result = run(runner, "plan", "straight 1", "cw", "0.5", "90", "--fastest", "--max-rpm", "30")
    assert result.exit_code == 0, result.output
    assert result.stdout == render(explain_plan(fastest))
    # --fastest runs the faster wheel of every segment at the 30 rpm limit: f = 1
    shares = [e for e in equations(result.stdout, "text") if e.line.startswith("f = ")]
    assert [share.result[0].value for share in shares] == pytest.approx([1.0, 1.0], abs=5e-5)


def test_the_robot_options_change_the_numbers(runner: CliRunner) -> None:
    result = run(runner, "ik", "0.1", "0", "--wheel-radius", "0.05", "--max-rpm", "20")
    assert result.exit_code == 0, result.output
    assert "= 2 rad/s (19.1 rpm)" in result.stdout
    assert "19.1 rpm ≤ 20 rpm: within the motor limit" in result.stdout
    over = run(runner, "ik", "0.5", "0")
    assert over.exit_code == 0, over.output
    assert "136 rpm > 50 rpm: over the motor limit" in over.stdout


def test_xacro_arguments_are_given_as_name_value_tokens(runner: CliRunner) -> None:
    result = run(runner, "fk", "1", "1", "wheel_radius:=0.04")
    assert result.exit_code == 0, result.output
    assert "v = r·(ω_L + ω_R) / 2 = 0.04·(1 + 1) / 2 = 0.04 m/s" in result.stdout


@pytest.mark.parametrize(
    ("args", "fragment"),
    [
        (["ik", "0.1"], "expected LINEAR ANGULAR, got 1 value(s)"),
        (["fk", "1", "x"], "RIGHT: 'x' is not a number"),
        (["odom", "0", "0", "1", "1", "nan"], "DT: 'nan' is not a finite number"),
        (["odom", "0", "0", "1", "1", "0"], "dt must be > 0 (s)"),
        (["ik", "1e308", "1e308"], "the results overflow"),
        (["ik", "0.1", "0", "--lang", "fr"], "'fr' is not one of 'en', 'es'"),
        (["ik", "0.1", "0", "--format", "html"], "'html' is not one of 'text', 'md'"),
        (["ik", "0.1", "0", "--bogus"], "No such option '--bogus'"),
        (["plan", "straight 1 zz"], "zz"),
        (["fit", "1"], "No such command 'fit'"),
    ],
)
def test_bad_input_is_one_error_line_with_exit_code_2(
    runner: CliRunner, args: list[str], fragment: str
) -> None:
    assert_bad_input(run(runner, *args), fragment)


def test_without_a_subcommand_the_help_lists_them(runner: CliRunner) -> None:
    result = run(runner)
    assert result.exit_code == 0
    for name in ("ik", "fk", "plan", "odom"):
        assert f"  {name} " in result.stdout
    assert "diffbot explain ik 0.1 0 --lang es" in result.stdout


def test_a_ramped_plan_is_derived_at_its_cruise_speeds(
    runner: CliRunner, params: DiffDriveParams
) -> None:
    result = run(runner, "plan", "straight 1", "--max-accel", "0.1")
    assert result.exit_code == 0, result.output
    assert result.stdout == render(explain_plan(plan(parse_plan("straight 1"), params)))
    assert result.stderr == (
        "warning: a ramped plan is derived at its cruise speeds: the ramps are not derived\n"
    )


def test_a_robot_whose_controller_scales_each_side_shows_both_radii(runner: CliRunner) -> None:
    rover = Path(__file__).resolve().parents[2] / "docs" / "examples" / "rover"
    description = rover / "urdf" / "rover.urdf.xacro"
    controllers = rover / "config" / "controllers.yaml"
    robot = load_params(description, packages={"rover_description": rover}, controllers=controllers)
    args = ["--robot", str(description), "--package", f"rover_description={rover}"]
    result = run(runner, "ik", "0.5", "0.5", *args, "--controllers", str(controllers))
    assert result.exit_code == 0, result.output
    assert result.stdout == render(explain_ik(robot, 0.5, 0.5))
    # the controller's radius multipliers, 1.002 and 0.998, of a 0.05 m wheel
    assert "r_L = 0.0501 m" in result.stdout
    assert "r_R = 0.0499 m" in result.stdout
