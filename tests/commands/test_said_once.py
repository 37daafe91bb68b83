"""Warnings said once: -q silences them on every command; a description's warnings, shown in
full once, come back as one line saying how many and how to see them; params and check show them
all every time."""

from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner

from diffbot.cli import COMMANDS, main
from diffbot.commands import said_once

CORPUS = Path(__file__).resolve().parent.parent / "corpus"
#: A ROS 1 controller without wheel_separation nor wheel_radius: two warnings.
ROBOT = "husky_like/husky_like_description/urdf/husky_like.urdf.xacro"
CONTROLLERS = "husky_like/husky_like_control/config/control.yaml"
WARNINGS = ("has no wheel_separation", "has no wheel_radius")


def warnings_of(stderr: str) -> list[str]:
    return [line for line in stderr.splitlines() if line.startswith("warning: ")]


def run(*args: str) -> tuple[int, list[str]]:
    result = CliRunner().invoke(main, list(args))
    return result.exit_code, warnings_of(result.stderr)


@pytest.fixture(autouse=True)
def in_corpus(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(CORPUS)


def test_a_descriptions_warnings_are_shown_in_full_once_then_counted() -> None:
    code, first = run("ik", ROBOT, "0.1", "0", "--controllers", CONTROLLERS)
    assert code == 0
    assert len(first) == 2
    assert all(any(w in line for line in first) for w in WARNINGS)
    # the same description by another name, another command: one line
    code, again = run("plan", str(CORPUS / ROBOT), "straight 1", "--controllers", CONTROLLERS)
    assert code == 0
    assert again == [
        f"warning: 2 warnings about {CORPUS / ROBOT}, shown before: diffbot params "
        f"{CORPUS / ROBOT} --controllers={CONTROLLERS} shows them; -q silences warnings"
    ]
    # params shows them all, every time
    for _ in range(2):
        code, shown = run("params", ROBOT, "--controllers", CONTROLLERS)
        assert code == 0
        assert len(shown) == 2


def test_other_warnings_of_the_same_description_are_shown_in_full() -> None:
    run("ik", ROBOT, "0.1", "0", "--controllers", CONTROLLERS)
    # without the controllers file: other warnings (or none), never the count of the first ones
    _, other = run("ik", ROBOT, "0.1", "0")
    assert not any("shown before" in line for line in other)


def test_without_a_cache_every_warning_is_shown_every_time(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setenv("DIFFBOT_NO_CACHE", "1")
    for _ in range(2):
        _, shown = run("ik", ROBOT, "0.1", "0", "--controllers", CONTROLLERS)
        assert len(shown) == 2


def test_a_mark_that_cannot_be_written_shows_them_again(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    blocked = tmp_path / "cache"
    blocked.write_text("a file where the folder should be", encoding="utf-8")
    monkeypatch.setenv("DIFFBOT_CACHE_DIR", str(blocked))
    assert not said_once.shown_before("robot.urdf", ["w"])
    assert not said_once.shown_before("robot.urdf", ["w"])


def test_the_mark_is_per_description_and_warnings(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("DIFFBOT_CACHE_DIR", str(tmp_path))
    assert not said_once.shown_before("a.urdf", ["w1"])
    assert said_once.shown_before("a.urdf", ["w1"])
    assert not said_once.shown_before("a.urdf", ["w1", "w2"])
    assert not said_once.shown_before("b.urdf", ["w1"])
    marks = list((tmp_path / said_once.SHOWN_FOLDER).iterdir())
    assert len(marks) == 3
    assert all(m.stat().st_size == 0 for m in marks)


@pytest.mark.parametrize("flag", ["-q", "--quiet"])
@pytest.mark.parametrize(
    "args",
    [
        ["ik", ROBOT, "0.1", "0"],
        ["params", ROBOT],
        ["check", ROBOT],
        ["plan", ROBOT, "straight 1"],
        ["simulate", ROBOT, "straight 1"],
        ["fk", ROBOT, "1", "1"],
    ],
    ids=lambda a: a[0],
)
def test_quiet_silences_warnings_on_every_command(flag: str, args: list[str]) -> None:
    result = CliRunner().invoke(main, [*args, "--controllers", CONTROLLERS, flag])
    assert result.exit_code in (0, 1), result.output
    assert warnings_of(result.stderr) == []
    loud = CliRunner().invoke(main, [*args, "--controllers", CONTROLLERS])
    assert len(warnings_of(loud.stderr)) >= 1


def test_every_command_takes_quiet() -> None:
    for name in COMMANDS:
        command = main.get_command(None, name)  # type: ignore[arg-type]
        assert command is not None
        commands = list(command.commands.values()) if hasattr(command, "commands") else [command]
        for one in commands:
            opts = {opt for param in one.params for opt in param.opts}
            assert {"-q", "--quiet"} <= opts, (name, one.name)


@pytest.mark.parametrize("shower", ["params", "check"])
def test_params_and_check_count_as_having_shown_them(shower: str) -> None:
    _, shown = run(shower, ROBOT, "--controllers", CONTROLLERS)
    assert len(shown) == 2
    _, later = run("ik", ROBOT, "0.1", "0", "--controllers", CONTROLLERS)
    assert len(later) == 1
    assert later[0].startswith(f"warning: 2 warnings about {ROBOT}, shown before: ")


def test_quiet_params_marks_nothing() -> None:
    run("params", ROBOT, "--controllers", CONTROLLERS, "-q")
    _, later = run("ik", ROBOT, "0.1", "0", "--controllers", CONTROLLERS)
    assert len(later) == 2


def test_the_command_that_shows_them_again_repeats_the_options_that_load_the_description() -> None:
    from diffbot.commands.options import RobotOptions

    given = RobotOptions(
        robot="my robot.xacro",
        xacro_args={"prefix": "a_", "wheels": "4"},
        packages={"my_pkg": "/opt/my pkg"},
        left_joint="l",
        right_joint="r",
        wheel_radius=0.1,
        wheel_separation=None,
        max_rpm=None,
        controllers="c.yaml",
        trust=True,
    )
    assert given.params_command() == [
        "diffbot",
        "params",
        "my robot.xacro",
        "prefix:=a_",
        "wheels:=4",
        "--package=my_pkg=/opt/my pkg",
        "--controllers=c.yaml",
    ]
    bundled = RobotOptions(None, {}, {}, None, None, None, None, None)
    assert bundled.params_command() == ["diffbot", "params"]
