"""Calibrated copies edit the place that defines each value and nothing else, and read back as
the calibration, or nothing is written."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import pytest
from calibration_data import fit_result
from cli_results import assert_one_error_line
from click.testing import CliRunner
from robots import sized_by_properties

from diffbot.calibration import apply_to
from diffbot.cli import main
from diffbot.errors import CalibrationError, DiffbotError
from diffbot.urdf import load_params
from diffbot.urdf.controllers import choose_controller, read_controllers

CALIBRATED = fit_result(0.0349, 0.0352, 0.138)

#: A tricycle controller first, whose wheel_separation a text search would find first.
TRICYCLE_FIRST = """\
controller_manager:
  ros__parameters:
    update_rate: 50
    tricycle_controller: {type: tricycle_controller/TricycleController}
    diff_cont: {type: diff_drive_controller/DiffDriveController}

tricycle_controller:
  ros__parameters:
    wheel_separation: 0.5  # the rear axle
    wheel_radius: 0.1

diff_cont:
  ros__parameters:
    left_wheel_names: [left_wheel_joint]   # the drive wheels
    right_wheel_names: [right_wheel_joint]
    wheel_separation: 0.135
    wheel_radius: 0.035
"""


def calibrated_controller(text: str, name: str | None = None) -> tuple[float, float, float]:
    config = choose_controller(read_controllers(text, "copy.yaml"), name)
    assert config.effective_separation is not None
    return config.effective_separation, config.left_radius or 0.0, config.right_radius or 0.0


def test_the_multipliers_go_to_the_diff_drive_controller_not_the_first_separation(
    tmp_path: Path,
) -> None:
    source = tmp_path / "controllers.yaml"
    source.write_text(TRICYCLE_FIRST, encoding="utf-8")
    applied = apply_to(source, CALIBRATED)
    assert calibrated_controller(applied.text) == pytest.approx((0.138, 0.0349, 0.0352))
    lines = applied.text.splitlines()
    at = lines.index("    wheel_separation: 0.135")
    assert lines[at + 1 : at + 4] == [
        "    wheel_separation_multiplier: 1.02222222",
        "    left_wheel_radius_multiplier: 0.997142857",
        "    right_wheel_radius_multiplier: 1.00571429",
    ]
    # Nothing else changed: the tricycle's section and the comments are as they were.
    assert [line for line in lines if "multiplier" not in line] == TRICYCLE_FIRST.splitlines()


def test_of_two_diff_drive_controllers_the_one_calibrated_gets_the_multipliers(
    tmp_path: Path,
) -> None:
    text = TRICYCLE_FIRST.replace(
        "tricycle_controller/TricycleController", "diff_drive_controller/DiffDriveController"
    )
    text = text.replace(
        "    wheel_radius: 0.1\n", "    wheel_radius: 0.1\n    wheel_separation_multiplier: 1.5\n"
    )
    source = tmp_path / "controllers.yaml"
    source.write_text(text, encoding="utf-8")
    with pytest.raises(DiffbotError, match="several diff-drive controllers"):
        apply_to(source, CALIBRATED)
    applied = apply_to(source, CALIBRATED, controller="diff_cont")
    assert calibrated_controller(applied.text, "diff_cont") == pytest.approx(
        (0.138, 0.0349, 0.0352)
    )
    assert calibrated_controller(applied.text, "tricycle_controller")[0] == pytest.approx(0.75)
    assert applied.text.count("wheel_separation_multiplier: 1.5\n") == 1


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        (  # a flow mapping takes the new keys inside its braces
            "diff_cont:\n  ros__parameters: {type: diff_drive_controller/DiffDriveController, "
            "wheel_separation: 0.135, wheel_radius: 0.035}\n",
            "diff_cont:\n  ros__parameters: {type: diff_drive_controller/DiffDriveController, "
            "wheel_separation_multiplier: 1.02222222, left_wheel_radius_multiplier: 0.997142857, "
            "right_wheel_radius_multiplier: 1.00571429, wheel_separation: 0.135, "
            "wheel_radius: 0.035}\n",
        ),
        (  # CRLF line breaks and no final one
            "diff_cont:\r\n  ros__parameters:\r\n"
            "    type: diff_drive_controller/DiffDriveController\r\n"
            "    wheel_radius: 0.035\r\n    wheel_separation: 0.135",
            "diff_cont:\r\n  ros__parameters:\r\n"
            "    type: diff_drive_controller/DiffDriveController\r\n"
            "    wheel_radius: 0.035\r\n    wheel_separation: 0.135\r\n"
            "    wheel_separation_multiplier: 1.02222222\r\n"
            "    left_wheel_radius_multiplier: 0.997142857\r\n"
            "    right_wheel_radius_multiplier: 1.00571429\r\n",
        ),
        (  # set values are replaced in place, their comments kept
            "diff_cont:\n  ros__parameters:\n    type: diff_drive_controller/DiffDriveController\n"
            "    wheel_separation_multiplier:   0.9   # tuned\n"
            "    left_wheel_radius_multiplier: +1.0e+0\n    wheel_radius: 0.035\n"
            "    wheel_separation: 0.135\n    right_wheel_radius_multiplier: 1\n",
            "diff_cont:\n  ros__parameters:\n    type: diff_drive_controller/DiffDriveController\n"
            "    wheel_separation_multiplier:   1.02222222   # tuned\n"
            "    left_wheel_radius_multiplier: 0.997142857\n    wheel_radius: 0.035\n"
            "    wheel_separation: 0.135\n    right_wheel_radius_multiplier: 1.00571429\n",
        ),
    ],
)
def test_a_controllers_copy_changes_only_the_multipliers(
    tmp_path: Path, text: str, expected: str
) -> None:
    source = tmp_path / "controllers.yaml"
    source.write_bytes(text.encode("utf-8"))
    applied = apply_to(source, CALIBRATED)
    assert applied.text == expected
    assert calibrated_controller(applied.text) == pytest.approx((0.138, 0.0349, 0.0352))


def test_a_multiplier_of_exactly_one_is_written_as_a_double(tmp_path: Path) -> None:
    # ROS 2 refuses an integer for a double parameter: 1 must be written 1.0.
    source = tmp_path / "controllers.yaml"
    source.write_text(TRICYCLE_FIRST, encoding="utf-8")
    same = dataclasses.replace(CALIBRATED, left_wheel_radius=0.035, right_wheel_radius=0.035)
    applied = apply_to(source, same)
    assert "    left_wheel_radius_multiplier: 1.0\n" in applied.text


# --- descriptions -----------------------------------------------------------------------------


#: A commented-out argument first, then the real one with default= before name=.
COMMENTED_FIRST = """\
<!-- <xacro:arg name="wheel_separation" default="0.2"/> -->
<xacro:arg default="0.135" name="wheel_separation"/>
<xacro:arg name="wheel_radius"
           default="0.035"/>
<xacro:property name="wheel_radius" value="$(arg wheel_radius)"/>
<xacro:property name="wheel_separation" value="$(arg wheel_separation)"/>
"""


def test_the_argument_that_defines_the_value_is_edited_whatever_its_attribute_order(
    tmp_path: Path,
) -> None:
    source = tmp_path / "robot.urdf.xacro"
    text = sized_by_properties(COMMENTED_FIRST)
    source.write_text(text, encoding="utf-8")
    applied = apply_to(source, CALIBRATED)
    assert '<!-- <xacro:arg name="wheel_separation" default="0.2"/> -->' in applied.text
    assert '<xacro:arg default="0.138" name="wheel_separation"/>' in applied.text
    assert '<xacro:arg name="wheel_radius"\n           default="0.03505"/>' in applied.text
    copy = tmp_path / "copy.urdf.xacro"
    copy.write_text(applied.text, encoding="utf-8")
    params = load_params(copy)
    assert (params.wheel_radius, params.wheel_separation) == pytest.approx((0.03505, 0.138))


def test_a_property_with_a_number_is_the_definition_when_there_is_no_argument(
    tmp_path: Path,
) -> None:
    source = tmp_path / "robot.urdf.xacro"
    body = (
        "<xacro:property value='0.135' name='wheel_separation'/>\n"
        '<xacro:property name="wheel_radius" value="0.035"/>\n'
    )
    source.write_text(sized_by_properties(body), encoding="utf-8")
    applied = apply_to(source, CALIBRATED)
    assert "<xacro:property value='0.138' name='wheel_separation'/>" in applied.text
    assert '<xacro:property name="wheel_radius" value="0.03505"/>' in applied.text


#: wheel_separation is defined by its argument, but the wheels sit 0.2 m apart whatever it says.
UNUSED_ARGUMENT = """\
<xacro:arg name="wheel_separation" default="0.135"/>
<xacro:property name="wheel_radius" value="0.035"/>
<xacro:property name="track" value="0.2"/>
<xacro:property name="wheel_separation" value="${track}"/>
"""


def test_a_copy_that_does_not_read_back_as_the_calibration_is_refused(tmp_path: Path) -> None:
    source = tmp_path / "robot.urdf.xacro"
    source.write_text(sized_by_properties(UNUSED_ARGUMENT), encoding="utf-8")
    with pytest.raises(
        CalibrationError, match=r"gives wheel_separation 0\.2 m .*not the calibrated 0\.138 m"
    ):
        apply_to(source, CALIBRATED)
    assert [p.name for p in tmp_path.iterdir()] == ["robot.urdf.xacro"]


def test_two_definitions_of_a_value_are_refused(tmp_path: Path) -> None:
    body = COMMENTED_FIRST + '<xacro:arg name="wheel_separation" default="0.14"/>\n'
    source = tmp_path / "robot.urdf.xacro"
    source.write_text(sized_by_properties(body), encoding="utf-8")
    with pytest.raises(CalibrationError, match='2 <xacro:arg name="wheel_separation"'):
        apply_to(source, CALIBRATED)


@pytest.mark.parametrize(
    "change",
    [
        {"wheel_separation": 0.0},
        {"wheel_separation": -0.138},
        {"wheel_separation": 8.48e-11},
        {"left_wheel_radius": float("inf")},
        {"right_wheel_radius": float("nan")},
    ],
)
def test_a_degenerate_calibration_is_never_applied(
    tmp_path: Path, change: dict[str, float]
) -> None:
    source = tmp_path / "controllers.yaml"
    source.write_text(TRICYCLE_FIRST, encoding="utf-8")
    with pytest.raises(CalibrationError, match=r"outside 0\.0001\.\.1000 m"):
        apply_to(source, dataclasses.replace(CALIBRATED, **change))


def test_the_command_applies_to_the_controller_the_robot_was_loaded_with(tmp_path: Path) -> None:
    text = TRICYCLE_FIRST.replace(
        "tricycle_controller/TricycleController", "diff_drive_controller/DiffDriveController"
    )
    text = text.replace("[left_wheel_joint]", "[front_left_wheel_joint]")
    text = text.replace("[right_wheel_joint]", "[front_right_wheel_joint]")
    source = tmp_path / "controllers.yaml"
    source.write_text(text, encoding="utf-8")
    args = [
        "calibrate", "umbmark", "--side", "4", "--cw", "-0.31,-0.40", "--ccw", "0.12,-0.09",
        "--controllers", str(source), "--controller", "diff_cont", "--apply-to", str(source),
        "--json",
    ]  # fmt: skip
    result = CliRunner().invoke(main, args)
    assert result.exit_code == 0, result.output
    copy = (tmp_path / "controllers.calibrated.yaml").read_text(encoding="utf-8")
    separation, left, right = calibrated_controller(copy, "diff_cont")
    data = json.loads(result.stdout)
    assert separation == pytest.approx(data["wheel_separation"], rel=1e-8)
    assert (left, right) == pytest.approx(
        (data["left_wheel_radius"], data["right_wheel_radius"]), rel=1e-8
    )
    assert calibrated_controller(copy, "tricycle_controller")[0] == pytest.approx(0.5)


def test_the_command_writes_no_copy_that_does_not_read_back(tmp_path: Path) -> None:
    source = tmp_path / "robot.urdf.xacro"
    source.write_text(sized_by_properties(UNUSED_ARGUMENT), encoding="utf-8")
    args = ["calibrate", "umbmark", "--side", "4", "--cw", "-0.31,-0.40", "--ccw", "0.12,-0.09"]
    result = CliRunner().invoke(main, [*args, "--apply-to", str(source)])
    assert_one_error_line(result, "not the calibrated", "nothing written")
    assert [p.name for p in tmp_path.iterdir()] == ["robot.urdf.xacro"]


@pytest.mark.parametrize("name", ["controllers.yaml", "robot.urdf.xacro"])
def test_a_leading_byte_order_mark_stays_in_the_copy(tmp_path: Path, name: str) -> None:
    # Only the calibrated values change: a BOM the editor wrote is kept like every other byte.
    text = TRICYCLE_FIRST if name.endswith(".yaml") else sized_by_properties(COMMENTED_FIRST)
    source = tmp_path / name
    source.write_bytes(b"\xef\xbb\xbf" + text.encode("utf-8"))
    applied = apply_to(source, CALIBRATED)
    plain = tmp_path / f"plain.{name}"
    plain.write_text(text, encoding="utf-8")
    assert applied.text == "\ufeff" + apply_to(plain, CALIBRATED).text
