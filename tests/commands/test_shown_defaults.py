"""The options whose default --help shows: a choice and a name."""

from __future__ import annotations

import click
import pytest
from click.testing import CliRunner

from diffbot.commands.shown_defaults import choice_option, name_option


@click.command()
@choice_option("--shape", "kind", choices=["round", "square"], default="square", help="A shape.")
@name_option("--frame", "base_link", "A frame.", metavar="FRAME")
@name_option("--topic", "odom", "A topic.")
def _echo(kind: str, frame: str, topic: str) -> None:
    click.echo(f"{kind} {frame} {topic}")


def _run(*args: str) -> click.testing.Result:
    return CliRunner().invoke(_echo, list(args), terminal_width=200)


def test_the_defaults_reach_the_command_and_help_shows_them() -> None:
    assert _run().output == "square base_link odom\n"
    help_text = _run("--help").output
    assert "--shape [round|square]  A shape.  [default: square]" in help_text
    assert "--frame FRAME           A frame.  [default: base_link]" in help_text
    assert "--topic TOPIC           A topic.  [default: odom]" in help_text


def test_given_values_replace_the_defaults() -> None:
    result = _run("--shape", "round", "--frame", "map", "--topic", "/x/odom")
    assert result.output == "round map /x/odom\n"


def test_a_word_outside_the_choices_is_refused() -> None:
    result = _run("--shape", "oval")
    assert result.exit_code == 2
    assert "'oval' is not one of 'round', 'square'" in result.output


def test_a_default_outside_the_choices_is_a_mistake_of_the_declaration() -> None:
    with pytest.raises(ValueError, match="'oval' is not one of"):
        choice_option("--shape", choices=["round"], default="oval", help="A shape.")


def _choices(words: tuple[str, ...], flag: str) -> tuple[str, ...]:
    from diffbot.cli import main

    ctx = click.Context(main, info_name="diffbot")
    command: click.Command | None = main
    for word in words:
        assert isinstance(command, click.Group)
        command = command.get_command(ctx, word)
    assert command is not None
    (option,) = [p for p in command.params if flag in p.opts]
    assert isinstance(option.type, click.Choice)
    return tuple(option.type.choices)


@pytest.mark.parametrize(
    ("words", "flag", "library"),
    [
        (("params",), "--source", "diffbot.urdf.sources:SOURCE_MODES"),
        (("plan",), "--shape", "diffbot.goals:SHAPES"),
        (("simulate",), "--shape", "diffbot.goals:SHAPES"),
        (("simulate",), "--pose-source", "diffbot.closed_loop:POSE_SOURCES"),
    ],
)
def test_a_choice_the_library_defines_offers_the_library_words(
    words: tuple[str, ...], flag: str, library: str
) -> None:
    """The words a command takes are the ones its library call takes, from one list: a word
    added to the library is offered at once, and none the library would refuse is."""
    import importlib

    module, name = library.split(":")
    assert _choices(words, flag) == tuple(getattr(importlib.import_module(module), name))
