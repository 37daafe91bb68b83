"""Settings made from a command's options by name."""

from __future__ import annotations

from dataclasses import dataclass

import click
import pytest
from click.testing import CliRunner

from diffbot.commands.settings import from_options


@dataclass(frozen=True)
class Settings:
    rate: float
    frame: str
    wait: float = 1.0


def _command(names: str, **values: object) -> click.Command:
    @click.command()
    @click.option("--rate", type=float, default=10.0)
    @click.option("--frame", default="base_link")
    @click.option("--wait", type=float)
    def command(rate: float, frame: str, wait: float | None) -> None:
        click.echo(repr(from_options(Settings, names, **values)))

    return command


def test_named_options_come_as_parsed_and_the_rest_as_given() -> None:
    done = CliRunner().invoke(_command("rate frame", wait=2.5), ["--rate", "7", "--frame", "odom"])
    assert done.output == "Settings(rate=7.0, frame='odom', wait=2.5)\n"


def test_options_not_named_are_not_taken() -> None:
    done = CliRunner().invoke(_command("rate frame"), ["--wait", "9"])
    assert done.output == "Settings(rate=10.0, frame='base_link', wait=1.0)\n"


def test_a_name_the_command_has_no_option_for_is_a_programming_error() -> None:
    done = CliRunner().invoke(_command("rate frame lead"), [])
    assert isinstance(done.exception, LookupError)
    assert str(done.exception) == "the command has no option lead"


def test_outside_a_command_there_are_no_options() -> None:
    with pytest.raises(RuntimeError):
        from_options(Settings, "rate")
