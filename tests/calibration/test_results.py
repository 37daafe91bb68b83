"""Calibration results in the forms a configuration takes, and the calibrated copies."""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml
from calibration_data import B0, fit_result
from hypothesis import given, settings
from hypothesis import strategies as st
from robots import BOT, sized_by_properties

from diffbot.calibration import (
    UmbmarkResult,
    apply_to,
    calibrated_path,
    controller_yaml_lines,
    multiplier_base,
    params_json,
    umbmark,
    xacro_arguments,
)
from diffbot.controller_config import ControllerConfig
from diffbot.errors import CalibrationError, OutputError
from diffbot.urdf.controllers import load_controllers

CALIBRATED = fit_result(0.0349, 0.0352, 0.1377)

CONTROLLERS = """\
controller_manager:
  ros__parameters:
    update_rate: 50
    diff_drive_base_controller:
      type: diff_drive_controller/DiffDriveController

diff_drive_base_controller:
  ros__parameters:
    left_wheel_names: ["front_left_wheel_joint"]
    right_wheel_names: ["front_right_wheel_joint"]
    wheel_separation: 0.135  # centre to centre
    wheel_radius: 0.035
    left_wheel_radius_multiplier: 1.0
"""


def test_controller_yaml_lines_give_multipliers_of_the_nominal_values() -> None:
    assert controller_yaml_lines(CALIBRATED, 0.035, 0.135) == [
        "wheel_separation_multiplier: 1.02",
        "left_wheel_radius_multiplier: 0.997142857",
        "right_wheel_radius_multiplier: 1.00571429",
    ]


@settings(max_examples=40, deadline=None)
@given(
    left=st.floats(0.01, 0.5),
    right=st.floats(0.01, 0.5),
    separation=st.floats(0.05, 2.0),
    nominal=st.floats(0.01, 0.5),
)
def test_controller_multipliers_bring_the_nominal_values_to_the_calibrated_ones(
    left: float, right: float, separation: float, nominal: float
) -> None:
    result = UmbmarkResult(1.0, 1.0, 0.0, 0.0, left, right, separation, (0, 0), (0, 0))
    lines = controller_yaml_lines(result, nominal, B0)
    values = {key: float(value) for key, value in (line.split(": ") for line in lines)}
    assert values["left_wheel_radius_multiplier"] * nominal == pytest.approx(left, rel=1e-8)
    assert values["right_wheel_radius_multiplier"] * nominal == pytest.approx(right, rel=1e-8)
    assert values["wheel_separation_multiplier"] * B0 == pytest.approx(separation, rel=1e-8)


def test_xacro_arguments_use_the_mean_radius_and_note_unequal_radii() -> None:
    arguments = xacro_arguments(CALIBRATED)
    assert arguments.arguments == "wheel_radius:=0.03505 wheel_separation:=0.1377"
    assert arguments.note is not None
    assert "left 0.0349 m, right 0.0352 m" in arguments.note
    assert "multipliers" in arguments.note


def test_xacro_arguments_of_equal_radii_need_no_note() -> None:
    result = umbmark(4.0, [(0.0, 0.0)], [(0.0, 0.0)], BOT)
    assert xacro_arguments(result) == ("wheel_radius:=0.035 wheel_separation:=0.135", None)


def test_xacro_arguments_are_only_those_the_description_declares() -> None:
    both = xacro_arguments(CALIBRATED, declared=("wheel_radius", "wheel_separation", "prefix"))
    assert both == xacro_arguments(CALIBRATED)
    separation = xacro_arguments(CALIBRATED, declared=("wheel_separation",))
    # No wheel_radius to give the mean radius to: the multipliers say it all, no note.
    assert separation == ("wheel_separation:=0.1377", None)
    assert xacro_arguments(CALIBRATED, declared=()) == (None, None)


def test_params_json_of_a_fit_has_the_three_geometry_keys() -> None:
    assert params_json(CALIBRATED) == {
        "left_wheel_radius": 0.0349,
        "right_wheel_radius": 0.0352,
        "wheel_separation": 0.1377,
    }


def test_params_json_of_umbmark_adds_the_error_ratios() -> None:
    result = umbmark(4.0, [(-0.3, -0.4)], [(0.1, -0.1)], BOT)
    data = params_json(result)
    assert set(data) == {"left_wheel_radius", "right_wheel_radius", "wheel_separation", "ed", "eb"}
    assert (data["ed"], data["eb"]) == (result.ed, result.eb)


@pytest.mark.parametrize(
    ("name", "expected"),
    [
        ("robot.urdf.xacro", "robot.calibrated.urdf.xacro"),
        ("controllers.yaml", "controllers.calibrated.yaml"),
        (".hidden", ".hidden.calibrated"),
    ],
)
def test_calibrated_copies_sit_beside_the_original(name: str, expected: str) -> None:
    assert calibrated_path(Path("conf") / name) == Path("conf") / expected


@pytest.mark.parametrize("name", [".", "/", "", "conf/.."])
def test_a_path_without_a_file_name_has_no_calibrated_copy(name: str) -> None:
    with pytest.raises(OutputError, match="a file is read there"):
        calibrated_path(Path(name))


def test_a_calibrated_controllers_yaml_reads_back_as_the_calibration(tmp_path: Path) -> None:
    source = tmp_path / "controllers.yaml"
    source.write_text(CONTROLLERS, encoding="utf-8")
    applied = apply_to(source, CALIBRATED)
    target = tmp_path / "out.yaml"
    target.write_text(applied.text, encoding="utf-8")
    (config,) = load_controllers(target)
    assert config.effective_separation == pytest.approx(0.1377, rel=1e-8)
    assert config.left_radius == pytest.approx(0.0349, rel=1e-8)
    assert config.right_radius == pytest.approx(0.0352, rel=1e-8)
    assert "wheel_separation: 0.135  # centre to centre" in applied.text  # comments kept
    assert applied.text.count("left_wheel_radius_multiplier") == 1  # replaced, not added
    assert source.read_text(encoding="utf-8") == CONTROLLERS
    assert applied.changed == controller_yaml_lines(CALIBRATED, 0.035, 0.135)
    assert yaml.safe_load(applied.text)["controller_manager"] is not None
    lines = applied.text.splitlines()
    at = lines.index("    wheel_separation: 0.135  # centre to centre")
    assert lines[at + 1 : at + 3] == [  # added after it, in the order printed
        "    wheel_separation_multiplier: 1.02",
        "    right_wheel_radius_multiplier: 1.00571429",
    ]


#: A robot whose wheels take their size from xacro arguments (b = 0.135 m, r = 0.035 m).
ARGUMENTS = (
    '<xacro:arg name="wheel_radius" default="0.035"/>\n'
    "<xacro:arg name='wheel_separation' default='0.135'/>\n"
    '<xacro:property name="wheel_radius" value="$(arg wheel_radius)"/>\n'
    '<xacro:property name="wheel_separation" value="$(arg wheel_separation)"/>\n'
)


def test_a_calibrated_description_sets_the_argument_defaults(tmp_path: Path) -> None:
    source = tmp_path / "robot.urdf.xacro"
    text = sized_by_properties(ARGUMENTS)
    source.write_text(text, encoding="utf-8")
    applied = apply_to(source, CALIBRATED)
    assert '<xacro:arg name="wheel_radius" default="0.03505"/>' in applied.text
    assert "<xacro:arg name='wheel_separation' default='0.1377'/>" in applied.text
    assert applied.changed == ["wheel_radius: 0.03505", "wheel_separation: 0.1377"]
    assert applied.note is not None
    assert applied.text.replace("0.03505", "0.035").replace("0.1377", "0.135") == text
    assert source.read_text(encoding="utf-8") == text
    assert [p.name for p in tmp_path.iterdir()] == ["robot.urdf.xacro"]  # no read-back left


def test_a_controllers_yaml_without_a_diff_drive_controller_is_refused(tmp_path: Path) -> None:
    source = tmp_path / "controllers.yaml"
    source.write_text("left_wheel_velocity_controller:\n  ros__parameters: {}\n", "utf-8")
    with pytest.raises(CalibrationError, match="0 diff-drive controllers configured"):
        apply_to(source, CALIBRATED)


def test_a_description_without_the_arguments_is_refused(tmp_path: Path) -> None:
    source = tmp_path / "robot.urdf"
    source.write_text("<robot name='r'/>\n", encoding="utf-8")
    with pytest.raises(CalibrationError, match='no <xacro:arg name="wheel_radius"'):
        apply_to(source, CALIBRATED)


def test_other_files_are_refused(tmp_path: Path) -> None:
    with pytest.raises(CalibrationError, match="applies to a controllers YAML"):
        apply_to(tmp_path / "notes.txt", CALIBRATED)


def test_multipliers_scale_the_controllers_own_radius_and_separation() -> None:
    config = ControllerConfig(
        "diff",
        "c.yaml",
        2,
        wheel_separation=0.3,
        wheel_radius=0.05,
        wheel_separation_multiplier=1.1,
    )
    robot = BOT.replace(wheel_radius=0.05, wheel_separation=0.33, controller=config)
    assert multiplier_base(robot) == (0.05, 0.3)
    assert multiplier_base(BOT) == (0.035, 0.135)
    assert multiplier_base(BOT.replace(controller=ControllerConfig("d", "c.yaml", 2))) == (
        0.035,
        0.135,
    )
