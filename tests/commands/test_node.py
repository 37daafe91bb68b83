"""``diffbot node odom|ik|robot`` take the robot as every other command does: a description
first, with its ``NAME:=VALUE`` xacro arguments."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import pytest
from cli_results import assert_one_error_line
from click.testing import CliRunner
from robots import two_wheel_urdf

import diffbot.commands.node as node_command
from diffbot.cli import main
from diffbot.commands.options import RobotOptions
from diffbot.kinematics import DiffDriveParams


@pytest.fixture
def loaded(monkeypatch: pytest.MonkeyPatch) -> list[DiffDriveParams]:
    """The parameters each node command loads; no node joins a graph."""
    seen: list[DiffDriveParams] = []
    load = RobotOptions.load

    def recording(self: RobotOptions, *args: object, **kwargs: object) -> DiffDriveParams:
        params = load(self, *args, **kwargs)  # type: ignore[arg-type]
        seen.append(params)
        return params

    def no_spin(make: Callable[[], object], *args: object, **kwargs: object) -> None:
        return None

    monkeypatch.setattr(RobotOptions, "load", recording)
    monkeypatch.setattr(node_command, "_spin", no_spin)
    return seen


@pytest.mark.parametrize("command", ["odom", "ik", "robot"])
def test_a_node_takes_the_descriptions_xacro_arguments(
    command: str, tmp_path: Path, loaded: list[DiffDriveParams]
) -> None:
    urdf = two_wheel_urdf(
        radius="$(arg r)", xacro=True, body='<xacro:arg name="r" default="0.05"/>'
    )
    description = tmp_path / "robot.urdf.xacro"
    description.write_text(urdf, encoding="utf-8")
    result = CliRunner().invoke(
        main, ["node", command, str(description), "r:=0.08", "--duration", "0.1", "-q"]
    )
    assert result.exit_code == 0, result.output
    assert [p.wheel_radius for p in loaded] == [pytest.approx(0.08)]


def test_a_node_takes_one_robot(tmp_path: Path, loaded: list[DiffDriveParams]) -> None:
    description = tmp_path / "robot.urdf"
    description.write_text(two_wheel_urdf(), encoding="utf-8")
    result = CliRunner().invoke(
        main, ["node", "odom", "--robot", str(description), "stray", "words", "--duration", "0.1"]
    )
    assert_one_error_line(result, "expected at most one ROBOT")
    assert loaded == []
