"""The CLI's first commands: params, urdf, ik, fk; output, exit codes, one-line errors."""

from __future__ import annotations

import json
import math
import re
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

import pytest
from cli_results import assert_one_error_line as assert_one_line_error
from click.testing import CliRunner, Result

from diffbot.cli import main

Write = Callable[[str, str], Path]

TWO_WHEELS = """<robot name="r">
  <link name="base_link"/>
  <joint name="lw" type="continuous"><parent link="base_link"/><child link="l"/>
    <origin xyz="0 0.1 0"/><axis xyz="0 1 0"/></joint>
  <link name="l"><collision><origin rpy="1.5707963 0 0"/>
    <geometry><cylinder radius="0.05" length="0.02"/></geometry></collision></link>
  <joint name="rw" type="continuous"><parent link="base_link"/><child link="r"/>
    <origin xyz="0 -0.1 0"/><axis xyz="0 -1 0"/></joint>
  <link name="r"><collision><origin rpy="1.5707963 0 0"/>
    <geometry><cylinder radius="0.05" length="0.02"/></geometry></collision></link>
</robot>
"""


def run(runner: CliRunner, *args: str) -> Result:
    return runner.invoke(main, list(args), catch_exceptions=False, prog_name="diffbot")


def test_version_names_the_program(runner: CliRunner) -> None:
    result = run(runner, "--version")
    assert result.exit_code == 0
    assert result.stdout.startswith("diffbot, version ")


def test_help_lists_the_commands_with_examples(runner: CliRunner) -> None:
    result = run(runner, "--help")
    assert result.exit_code == 0
    for command in ("params", "urdf", "ik", "fk"):
        assert command in result.stdout
    assert "diffbot ik 0.1 0.5" in result.stdout


# --- params ---------------------------------------------------------------------------------


def test_params_json_has_exactly_the_contract_keys(runner: CliRunner) -> None:
    result = run(runner, "params", "--json")
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert set(data) == {
        "wheel_radius",
        "wheel_separation",
        "left_joint",
        "right_joint",
        "left_sign",
        "right_sign",
        "max_wheel_speed",
        "max_wheel_rpm",
        "source",
        "warnings",
        "left_joints",
        "right_joints",
        "left_wheel_radius",
        "right_wheel_radius",
        "sources",
        "disagreements",
    }
    assert data["wheel_radius"] == pytest.approx(0.035)
    assert data["left_joints"] == ["front_left_wheel_joint"]
    assert data["left_wheel_radius"] == data["right_wheel_radius"] == data["wheel_radius"]
    assert set(data["sources"].values()) == {"description"}
    assert data["disagreements"] == []
    assert data["max_wheel_rpm"] == pytest.approx(50.0)
    assert data["warnings"] == []


def test_params_human_output_names_joints_and_limit(runner: CliRunner) -> None:
    result = run(runner, "params")
    assert result.exit_code == 0
    assert "front_left_wheel_joint (direction +1)" in result.stdout
    assert "50 rpm (5.23599 rad/s)" in result.stdout


def test_params_takes_a_path_and_xacro_args(runner: CliRunner, write: Write) -> None:
    from diffbot.urdf import BUNDLED_DESCRIPTION

    result = run(runner, "params", str(BUNDLED_DESCRIPTION), "wheel_radius:=0.05", "--json")
    assert result.exit_code == 0, result.output
    assert json.loads(result.stdout)["wheel_radius"] == pytest.approx(0.05)


def test_params_of_a_urdf_with_a_mirrored_axis(runner: CliRunner, write: Write) -> None:
    result = run(runner, "params", "--robot", str(write("r.urdf", TWO_WHEELS)), "--json")
    data = json.loads(result.stdout)
    assert (data["left_sign"], data["right_sign"]) == (1, -1)
    assert data["max_wheel_speed"] is None
    assert data["max_wheel_rpm"] is None


def test_params_overrides_apply(runner: CliRunner) -> None:
    result = run(runner, "params", "--wheel-radius", "0.1", "--max-rpm", "120", "--json")
    data = json.loads(result.stdout)
    assert data["wheel_radius"] == 0.1
    assert data["max_wheel_rpm"] == pytest.approx(120.0)


def test_params_warnings_go_to_stderr_for_people_and_into_json(runner: CliRunner) -> None:
    human = run(runner, "params", "wheel_radiuss:=1")
    assert "warning: xacro argument 'wheel_radiuss' is not declared" in human.stderr
    machine = run(runner, "params", "wheel_radiuss:=1", "--json")
    assert machine.stderr == ""
    assert "wheel_radiuss" in json.loads(machine.stdout)["warnings"][0]


def test_the_fastest_motor_limit_help_names_is_taken_and_one_above_is_not(
    runner: CliRunner,
) -> None:
    helped = runner.invoke(main, ["params", "--help"]).output
    most = re.search(r"at most ([0-9.]+) rpm \(10000 rad/s\)", " ".join(helped.split()))
    assert most is not None, helped
    assert most[1] == "95492.96"
    taken = run(runner, "params", "--max-rpm", most[1], "--json")
    assert json.loads(taken.stdout)["max_wheel_speed"] == pytest.approx(1e4, rel=1e-6)
    # the refusal names the same bound as --help: 95492.97 is above the limit
    for given in ("95493", "95492.97"):
        above = runner.invoke(main, ["params", "--max-rpm", given])
        assert above.exit_code == 2
        assert "a motor limit is at most 95492.96 rpm (10000 rad/s)" in above.stderr


@pytest.mark.parametrize(
    ("args", "fragment"),
    [
        (["params", "missing.urdf"], "missing.urdf: no such file"),
        (["params", "--wheel-radius", "-1"], "'-1' must be > 0"),
        (["params", "--wheel-radius", "nan"], "'nan' is not a finite number"),
        (["params", "--wheel-separation", "inf"], "'inf' is not a finite number"),
        (["params", "--max-rpm", "-5"], "'-5' must be > 0"),
        # a motor limit a wheel can have: not 0 ("inf% used"), not subnormal ("OVER 100.5%"),
        # no faster than 1e4 rad/s (1e308 rpm left the plot no axis)
        (["ik", "1", "1", "--max-rpm", "0", "--saturate"], "'0' must be > 0"),
        (["ik", "1", "1", "--max-rpm", "1e-320", "--saturate"], "too small to compute with"),
        (["ik", "1", "1", "--max-rpm", "2e-307", "--saturate"], "too small to compute with"),
        (["plan", "straight 1", "--max-rpm", "1e308"], "at most 95492.96 rpm (10000 rad/s)"),
        (["params", "--max-rpm", "95493"], "'95493' is faster than any wheel turns"),
        (["params", "wheel_radius:=0"], "wheel_radius must be a finite number >= 0.0001"),
        (["params", "--package", "nodir"], "expected NAME=DIR"),
        (["params", "--bogus"], "No such option '--bogus'"),
        (["params", "a.urdf", "b.urdf"], "two robots given"),
        (["nosuchcommand"], "No such command"),
    ],
)
def test_params_bad_input_is_one_error_line_exit_2(
    runner: CliRunner, args: list[str], fragment: str
) -> None:
    assert_one_line_error(run(runner, *args), fragment)


def test_params_of_malformed_and_ambiguous_descriptions(runner: CliRunner, write: Write) -> None:
    bad = write("bad.urdf", TWO_WHEELS.replace("</robot>", ""))
    assert_one_line_error(run(runner, "params", str(bad)), "malformed XML")
    four = TWO_WHEELS.replace("</robot>", "") + TWO_WHEELS.split('<link name="base_link"/>')[
        1
    ].replace('"lw"', '"lw2"').replace('"rw"', '"rw2"').replace('link="l"', 'link="l2"').replace(
        'link="r"', 'link="r2"'
    ).replace('name="l"', 'name="l2"').replace('name="r"', 'name="r2"')
    path = write(
        "four.urdf", four.replace('name="rw2" type="continuous"', 'name="rw2" type="fixed"')
    )
    assert_one_line_error(run(runner, "params", str(path)), "--left-joint/--right-joint")
    ok = run(runner, "params", str(path), "--left-joint", "lw2", "--right-joint", "rw", "--json")
    assert ok.exit_code == 0, ok.output
    assert json.loads(ok.stdout)["left_joint"] == "lw2"


def test_missing_package_names_the_option_to_fix_it(runner: CliRunner, write: Write) -> None:
    path = write(
        "p.urdf.xacro",
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">'
        '<xacro:include filename="$(find nowhere_pkg)/x.xacro"/></robot>',
    )
    assert_one_line_error(run(runner, "params", str(path)), "--package nowhere_pkg=DIR")


# --- urdf -----------------------------------------------------------------------------------


def test_urdf_prints_the_expanded_description(runner: CliRunner) -> None:
    result = run(runner, "urdf", "wheel_radius:=0.05")
    assert result.exit_code == 0
    assert '<cylinder length="0.02" radius="0.05"/>' in result.stdout
    assert "xacro:" not in result.stdout.replace("autogenerated by xacro", "")


def test_urdf_output_file_is_not_overwritten_without_force(
    runner: CliRunner, tmp_path: Path
) -> None:
    out = tmp_path / "robot.urdf"
    assert run(runner, "urdf", "-o", str(out)).exit_code == 0
    first = out.read_text()
    assert first.startswith("<?xml")
    out.write_text("keep me")
    assert_one_line_error(run(runner, "urdf", "-o", str(out)), "exists: use --force")
    assert out.read_text() == "keep me"
    assert run(runner, "urdf", "-o", str(out), "--force").exit_code == 0
    assert out.read_text() == first
    assert sorted(p.name for p in tmp_path.iterdir()) == ["robot.urdf"]


def test_urdf_error_leaves_no_output(runner: CliRunner, tmp_path: Path, write: Write) -> None:
    bad = write("bad.urdf.xacro", '<robot xmlns:xacro="http://www.ros.org/wiki/xacro">${x}</robot>')
    out = tmp_path / "out.urdf"
    assert_one_line_error(run(runner, "urdf", str(bad), "-o", str(out)), "xacro:")
    assert not out.exists()


# --- ik / fk --------------------------------------------------------------------------------


def test_ik_json_gives_the_seed_wheel_speeds(runner: CliRunner) -> None:
    result = run(runner, "ik", "0.1", "0", "--json")
    assert result.exit_code == 0
    data = json.loads(result.stdout)
    assert set(data) == {"left", "right", "left_rpm", "right_rpm", "within_limit"}
    assert data["left"] == pytest.approx(2.857142857, abs=1e-9)
    assert data["right_rpm"] == pytest.approx(27.28, abs=0.01)
    assert data["within_limit"] is True


def test_ik_accepts_negative_numbers_and_applies_joint_signs(
    runner: CliRunner, write: Write
) -> None:
    path = write("r.urdf", TWO_WHEELS)
    result = run(runner, "ik", "-0.1", "-0.0", "--robot", str(path), "--json")
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert data["left"] == pytest.approx(-2.0)
    assert data["right"] == pytest.approx(2.0)  # right axis mirrored: joint turns the other way
    assert data["within_limit"] is True  # no limit in that description


def test_ik_over_the_limit_prints_results_and_exits_1(runner: CliRunner) -> None:
    result = run(runner, "ik", "0.2", "0")
    assert result.exit_code == 1
    assert "OVER" in result.stdout
    assert result.stderr.startswith("error: left wheel at 54.57 rpm exceeds the motor limit")


def test_a_share_of_a_tiny_motor_limit_is_written_short(runner: CliRunner) -> None:
    result = run(runner, "ik", "0.2", "0", "--max-rpm", "1e-290")
    assert result.exit_code == 1
    line = next(line for line in result.stdout.splitlines() if line.startswith("motor limit"))
    assert line.endswith("OVER, 5.45674e+293% used"), line


def test_ik_saturate_keeps_the_radius_and_fits_the_limit(runner: CliRunner) -> None:
    result = run(runner, "ik", "1", "2", "--saturate", "--json")
    assert result.exit_code == 0
    data = json.loads(result.stdout)
    assert data["saturated"] is True
    assert max(abs(data["left_rpm"]), abs(data["right_rpm"])) == pytest.approx(50.0, rel=1e-9)
    # the ratio of the wheels is that of the unsaturated command
    assert data["left"] / data["right"] == pytest.approx((1 - 0.135) / (1 + 0.135), rel=1e-12)


def test_ik_xacro_args_follow_the_numbers(runner: CliRunner) -> None:
    result = run(runner, "ik", "0.1", "0", "wheel_radius:=0.05", "--json")
    assert json.loads(result.stdout)["left"] == pytest.approx(2.0)


@pytest.mark.parametrize(
    ("args", "fragment"),
    [
        (["ik", "0.1"], "expected LINEAR and ANGULAR, got 1"),
        (["ik", "fast", "0"], "LINEAR: 'fast' is not a number"),
        (["ik", "0.1", "inf"], "ANGULAR: 'inf' is not a finite number"),
        (["ik", "0.1", "0", "=1"], "ANGULAR"),
        (["fk", "1"], "expected LEFT and RIGHT, got 1"),
        (["fk", "1", "nan"], "RIGHT: 'nan' is not a finite number"),
        (["ik", "0.1", "0", ":=3"], "bad xacro argument"),
    ],
)
def test_ik_and_fk_bad_input_is_one_error_line_exit_2(
    runner: CliRunner, args: list[str], fragment: str
) -> None:
    assert_one_line_error(run(runner, *args), fragment)


def test_fk_gives_the_seed_arc(runner: CliRunner) -> None:
    result = run(runner, "fk", "1.637", "2.848", "--json")
    data = json.loads(result.stdout)
    assert set(data) == {"linear", "angular"}
    assert data["linear"] == pytest.approx(0.0785, abs=1e-4)
    assert data["angular"] == pytest.approx(0.314, abs=1e-3)


def test_fk_human_output_gives_the_turning_radius(runner: CliRunner) -> None:
    result = run(runner, "fk", "1.637", "2.848")
    assert "radius   0.2499" in result.stdout
    assert "counter-clockwise" in result.stdout
    spin = run(runner, "fk", "-1", "1")
    assert "spin in place" in spin.stdout


@pytest.mark.parametrize("scale", [1e-320, 1e-310, 1.0, 1e300])
def test_fk_turning_radius_does_not_depend_on_the_wheels_scale(
    runner: CliRunner, scale: float
) -> None:
    # One wheel still: the robot pivots about it, half the separation (0.135 m) from the middle.
    result = run(runner, "fk", repr(scale), "0")
    assert "radius   -0.0675 m (clockwise)" in result.stdout


def test_fk_in_rpm_inverts_ik(runner: CliRunner) -> None:
    ik = json.loads(run(runner, "ik", "0.05", "-0.3", "--json").stdout)
    fk = json.loads(
        run(runner, "fk", str(ik["left_rpm"]), str(ik["right_rpm"]), "--rpm", "--json").stdout
    )
    assert fk["linear"] == pytest.approx(0.05, rel=1e-12)
    assert fk["angular"] == pytest.approx(-0.3, rel=1e-12)
    assert math.isfinite(fk["linear"])


def test_python_dash_m_runs_the_cli() -> None:
    result = subprocess.run(
        [sys.executable, "-m", "diffbot", "ik", "0.1", "0", "--json"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert result.returncode == 0, result.stderr
    assert json.loads(result.stdout)["right"] == pytest.approx(2.857142857, abs=1e-9)


def test_bad_input_from_a_real_process_has_no_traceback(tmp_path: Path) -> None:
    bad = tmp_path / "bad.urdf"
    bad.write_text("<robot><link></robot>")
    result = subprocess.run(
        [sys.executable, "-m", "diffbot", "params", str(bad)],
        capture_output=True,
        text=True,
        check=False,
    )
    assert result.returncode == 2
    assert result.stderr.startswith("error: ")
    assert result.stderr.count("\n") == 1
    assert result.stdout == ""


def test_no_arguments_prints_the_help(runner: CliRunner) -> None:
    result = run(runner)
    assert result.exit_code == 0
    assert result.stdout.startswith("Usage: diffbot")


@pytest.mark.parametrize(
    ("args", "fragment"),
    [
        (["ik", "1e308", "0", "--json"], "overflow"),
        (["ik", "1e306", "0"], "overflow"),
        (["fk", "1e308", "-1e308", "--json"], "overflow"),
        (["ik", "0.1", "0", "--saturat"], "No such option '--saturat'"),
        (["fk", "-x", "1"], "No such option '-x'"),
        (["params", "max_wheel_rpm:=nan"], "non-finite velocity limit"),
        (["params", "wheel_separation:=inf"], "non-finite origin"),
    ],
)
def test_overflow_mistyped_options_and_bad_limits_are_one_error_line(
    runner: CliRunner, args: list[str], fragment: str
) -> None:
    assert_one_line_error(run(runner, *args), fragment)


def test_urdf_output_gets_ordinary_permissions_and_keeps_existing_ones(
    runner: CliRunner, tmp_path: Path
) -> None:
    import os

    out = tmp_path / "a.urdf"
    old = os.umask(0o022)
    try:
        assert run(runner, "urdf", "-o", str(out)).exit_code == 0
        assert out.stat().st_mode & 0o777 == 0o644
        out.chmod(0o640)
        assert run(runner, "urdf", "-o", str(out), "--force").exit_code == 0
        assert out.stat().st_mode & 0o777 == 0o640
    finally:
        os.umask(old)


def test_urdf_output_writes_through_a_link_and_never_over_the_input(
    runner: CliRunner, tmp_path: Path
) -> None:
    from diffbot.urdf import BUNDLED_DESCRIPTION

    real = tmp_path / "real.urdf"
    real.write_text("old")
    link = tmp_path / "link.urdf"
    link.symlink_to(real)
    assert_one_line_error(run(runner, "urdf", "-o", str(link)), "exists: use --force")
    assert run(runner, "urdf", "-o", str(link), "--force").exit_code == 0
    assert link.is_symlink()
    assert real.read_text().startswith("<?xml")
    dangling = tmp_path / "dangling.urdf"
    dangling.symlink_to(tmp_path / "nowhere.urdf")
    assert_one_line_error(run(runner, "urdf", "-o", str(dangling)), "exists: use --force")
    copy = tmp_path / "copy.urdf.xacro"
    copy.write_text(BUNDLED_DESCRIPTION.read_text())
    assert_one_line_error(run(runner, "urdf", str(copy), "-o", str(copy), "--force"), "is an input")
    assert copy.read_text() == BUNDLED_DESCRIPTION.read_text()
    assert_one_line_error(run(runner, "urdf", "-o", str(tmp_path), "--force"), "not a regular file")


def test_the_package_option_says_which_folders_it_takes() -> None:
    result = CliRunner().invoke(main, ["params", "--help"], terminal_width=200)
    text = " ".join(result.output.split())
    assert "the folder holding its package.xml, an install prefix (install/NAME, holding" in text
    assert "share/NAME) or a share folder (holding NAME)" in text
