"""A robot description as the first argument of every command that takes a robot: the same as
``--robot``, told apart from plan text, plan files, recordings and numbers by what the file is."""

from __future__ import annotations

from pathlib import Path

import pytest
from cli_results import assert_one_error_line
from click.testing import CliRunner, Result
from extras import need
from robots import two_wheel_urdf

from diffbot.cli import main
from diffbot.commands.options import is_description, xml_root

# r = 0.05 m, b = 0.2 m, right axis mirrored: nothing like the bundled robot.
MIRRORED = two_wheel_urdf(left_axis="0 -1 0")


def invoke(folder: Path, args: list[str], monkeypatch: pytest.MonkeyPatch) -> Result:
    monkeypatch.chdir(folder)
    return CliRunner().invoke(main, args, catch_exceptions=False, prog_name="diffbot")


#: Each command that takes a robot, with the arguments that follow the description.
COMMANDS = {
    "params": [],
    "check": [],
    "ik": ["0.1", "0.5"],
    "fk": ["2", "-2"],
    "plan": ["straight 1; spin 90"],
    "plan-file": ["path.yaml"],
    "simulate": ["straight 0.1", "--rate", "5"],
    "odom": ["run.csv"],
    "explain ik": ["0.1", "0"],
    "explain fk": ["2", "-2"],
    "explain plan": ["spin", "90"],
    "explain odom": ["0", "0", "1", "1.5", "0.1"],
    "plot": ["straight", "1", "-o", "out.png"],
    "calibrate umbmark": ["--side", "4", "--cw", "0.1,0.2", "--ccw", "0.1,-0.2"],
}


@pytest.fixture
def folder(tmp_path: Path) -> Path:
    (tmp_path / "robot.urdf").write_text(MIRRORED, encoding="utf-8")
    (tmp_path / "path.yaml").write_text("- straight: 1\n- spin: 90\n", encoding="utf-8")
    (tmp_path / "run.csv").write_text(
        "time,left_wheel_joint,right_wheel_joint\n0,0,0\n0.1,-1,1.5\n", encoding="utf-8"
    )
    return tmp_path


@pytest.mark.parametrize("name", list(COMMANDS))
def test_a_description_first_is_the_same_as_robot(
    name: str, folder: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    if name == "plot":
        need("matplotlib")
    command = name.removesuffix("-file").split()
    rest = COMMANDS[name]
    first = invoke(folder, [*command, "robot.urdf", *rest], monkeypatch)
    if name == "plot":
        (folder / "out.png").unlink()
    named = invoke(folder, [*command, *rest, "--robot", "robot.urdf"], monkeypatch)
    bundled = invoke(folder, [*command, *rest], monkeypatch)
    assert first.exit_code == named.exit_code, first.output
    assert first.exit_code in (0, 1), first.output
    assert first.stdout == named.stdout
    if name != "plot":  # plot writes a figure, and says nothing
        assert first.stdout != bundled.stdout  # the description was used, not the bundled robot


def test_a_description_is_told_by_its_xml_root_whatever_its_name(
    folder: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    (folder / "robot.xml").write_text(MIRRORED, encoding="utf-8")
    first = invoke(folder, ["ik", "robot.xml", "0.1", "0"], monkeypatch)
    named = invoke(folder, ["ik", "0.1", "0", "--robot", "robot.urdf"], monkeypatch)
    assert first.exit_code == 0, first.output
    assert first.stdout == named.stdout


def test_a_missing_description_is_reported_as_missing_not_as_a_plan(
    folder: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    result = invoke(folder, ["plan", "nowhere.urdf.xacro"], monkeypatch)
    assert_one_error_line(result, "nowhere.urdf.xacro: no such file")


def test_two_different_robots_are_refused(folder: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    (folder / "other.urdf").write_text(MIRRORED, encoding="utf-8")
    result = invoke(folder, ["fk", "robot.urdf", "1", "1", "--robot", "other.urdf"], monkeypatch)
    assert_one_error_line(result, "two robots given")


@pytest.mark.parametrize(
    ("text", "root"),
    [
        ('<?xml version="1.0"?>\n<!-- a robot -->\n<robot name="x"/>', "robot"),
        ("\ufeff<sdf version='1.9'><model/></sdf>", "sdf"),
        ("<!DOCTYPE x>\n<xacro:robot xmlns:xacro='u'/>", "robot"),
        ("- straight: 1\n", None),
        ("time,left,right\n", None),
    ],
)
def test_the_xml_root_is_read_from_the_head_of_the_file(
    tmp_path: Path, text: str, root: str | None
) -> None:
    path = tmp_path / "file"
    path.write_text(text, encoding="utf-8")
    assert xml_root(path) == root


def test_plan_text_numbers_and_plan_files_are_not_descriptions(folder: Path) -> None:
    assert not is_description("straight 1")
    assert not is_description("-0.5")
    assert not is_description(str(folder / "path.yaml"))
    assert not is_description(str(folder / "run.csv"))
    assert not is_description("wheel_radius:=0.04.urdf")
    assert is_description(str(folder / "robot.urdf"))
    assert is_description("not_yet.sdf")


def test_a_model_folder_is_a_description_and_a_bag_folder_is_not(tmp_path: Path) -> None:
    model = tmp_path / "rover_model"
    model.mkdir()
    (model / "model.config").write_text("<model><sdf>model.sdf</sdf></model>\n", "utf-8")
    bag = tmp_path / "run_bag"
    bag.mkdir()
    (bag / "metadata.yaml").write_text("rosbag2_bagfile_information: {}\n", "utf-8")
    assert is_description(str(model))
    assert not is_description(str(bag))
