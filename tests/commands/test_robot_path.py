"""A path given as the robot that is no description: a package folder lists its descriptions,
a controllers YAML is sent to --controllers, a launch file is told apart."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from cli_results import assert_one_error_line
from click.testing import CliRunner, Result

from diffbot.cli import main
from diffbot.commands import robot_path
from diffbot.commands.robot_path import descriptions_in, not_a_description

CONTROLLERS = """controller_manager:
  ros__parameters:
    update_rate: 100
    diff_cont:
      type: diff_drive_controller/DiffDriveController
diff_cont:
  ros__parameters:
    wheel_separation: 0.297
    wheel_radius: 0.033
"""


def error_line(result: Result) -> str:
    """The one error line of a run that met bad input."""
    assert_one_error_line(result)
    return result.stderr.strip()


def package(root: Path) -> Path:
    """Shaped like a description package: urdf/ with a top-level xacro and its parts, a model."""
    folder = root / "my_bot_description"
    (folder / "urdf" / "parts").mkdir(parents=True)
    (folder / "package.xml").write_text("<package><name>my_bot_description</name></package>")
    for name in ("urdf/my_bot.urdf.xacro", "urdf/parts/wheel.urdf.xacro", "urdf/my_bot.urdf"):
        (folder / name).write_text("<robot/>", encoding="utf-8")
    (folder / "models" / "my_bot").mkdir(parents=True)
    (folder / "models" / "my_bot" / "model.sdf").write_text("<sdf/>", encoding="utf-8")
    (folder / "launch").mkdir()
    (folder / "launch" / "rsp.launch.py").write_text("", encoding="utf-8")
    (folder / "build" / "x").mkdir(parents=True)
    (folder / "build" / "x" / "copy.urdf").write_text("<robot/>", encoding="utf-8")
    (folder / ".hidden.urdf").mkdir()
    return folder


def test_a_package_folder_lists_its_descriptions_urdf_first(tmp_path: Path) -> None:
    folder = package(tmp_path)
    listed, total = descriptions_in(folder)
    assert [p.as_posix() for p in listed] == [
        "urdf/my_bot.urdf",
        "urdf/my_bot.urdf.xacro",
        "urdf/parts/wheel.urdf.xacro",
        "models/my_bot/model.sdf",
    ]
    assert total == 4


def test_a_batch_layout_lists_the_robots_own_urdf_folder_before_the_parts(
    tmp_path: Path,
) -> None:
    """Shaped like a description package of several robots: each top-level description four
    folders down (``description/batch/<robot>/urdf/``), its parts shallower elsewhere."""
    for name in (
        "description/batch/rosbot_xl/urdf/rosbot_xl.urdf.xacro",
        "description/batch/rosbot/urdf/rosbot.urdf.xacro",
        "description/components/bumper.urdf.xacro",
        "wheel.urdf.xacro",
    ):
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_text("<robot/>", encoding="utf-8")
    listed, total = descriptions_in(tmp_path)
    assert [p.as_posix() for p in listed] == [
        "description/batch/rosbot/urdf/rosbot.urdf.xacro",
        "description/batch/rosbot_xl/urdf/rosbot_xl.urdf.xacro",
        "wheel.urdf.xacro",
        "description/components/bumper.urdf.xacro",
    ]
    assert total == 4


def test_the_list_is_bounded(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    (tmp_path / "urdf").mkdir()
    for k in range(20):
        (tmp_path / "urdf" / f"r{k:02d}.urdf").write_text("<robot/>", encoding="utf-8")
    listed, total = descriptions_in(tmp_path)
    assert (len(listed), total) == (robot_path.MAX_LISTED, 20)
    monkeypatch.setattr(robot_path, "MAX_ENTRIES", 5)
    assert descriptions_in(tmp_path)[1] < 20


def test_a_package_folder_given_as_the_robot_asks_for_one_of_them(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    package(tmp_path)
    monkeypatch.chdir(tmp_path)
    result = CliRunner().invoke(main, ["params", "my_bot_description"])
    line = error_line(result)
    assert line == (
        "error: my_bot_description: is a ROS package folder, not a robot description: give one "
        "of its descriptions: my_bot_description/urdf/my_bot.urdf, "
        "my_bot_description/urdf/my_bot.urdf.xacro, "
        "my_bot_description/urdf/parts/wheel.urdf.xacro, "
        "my_bot_description/models/my_bot/model.sdf"
    )
    # as the first argument of a command that also takes plan text
    plan = CliRunner().invoke(main, ["plan", "my_bot_description", "straight 1"])
    assert "is a ROS package folder" in error_line(plan)


def test_a_folder_without_descriptions_says_so(tmp_path: Path) -> None:
    message = not_a_description(str(tmp_path))
    assert message is not None
    assert message.startswith(f"{tmp_path}: is a directory, not a robot description, and holds")


def test_a_model_folder_or_a_bag_is_left_to_the_readers(tmp_path: Path) -> None:
    (tmp_path / "model.config").write_text("<model/>", encoding="utf-8")
    assert not_a_description(str(tmp_path)) is None
    assert not_a_description(str(tmp_path / "robot.urdf")) is None


def test_a_controllers_file_given_as_the_robot_goes_to_controllers(tmp_path: Path) -> None:
    config = tmp_path / "my_controllers.yaml"
    config.write_text(CONTROLLERS, encoding="utf-8")
    for args in (["params", str(config)], ["plan", str(config), "straight 1"]):
        line = error_line(CliRunner().invoke(main, args))
        assert line == (
            f"error: {config}: is a controllers file, not a robot description: give it with "
            f"--controllers {config}, beside the description (.urdf, .urdf.xacro or .sdf)"
        )
    other = tmp_path / "waypoints.yaml"
    other.write_text("- [0, 0]\n- [1, 0]\n", encoding="utf-8")
    assert not_a_description(str(other)) is None


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
def test_a_fifo_named_like_yaml_is_not_read(tmp_path: Path) -> None:
    fifo = tmp_path / "controllers.yaml"
    os.mkfifo(fifo)
    assert not robot_path.is_controllers_file(fifo)


@pytest.mark.parametrize("name", ["bringup.launch.py", "robot.launch.xml", "gz.launch"])
def test_a_launch_file_given_as_the_robot_is_told_apart(tmp_path: Path, name: str) -> None:
    launch = tmp_path / name
    launch.write_text("<launch/>", encoding="utf-8")
    line = error_line(CliRunner().invoke(main, ["check", str(launch)]))
    assert line.startswith(f"error: {launch}: is a launch file, which diffbot does not run")
    assert "--controllers FILE" in line
