"""One option vocabulary across the commands: docs/cli.md's table of every command's options is
the commands' own, every command that writes spells its output option ``-o``, ``--output`` and
``--out``, ``--max-rpm`` is the one motor limit, usage errors read alike, metavars say what an
option takes."""

from __future__ import annotations

import re
from pathlib import Path

import click
import pytest
from cli_results import assert_one_error_line
from click.testing import CliRunner
from test_help_examples import commands

from diffbot.cli import main

ROOT = Path(__file__).resolve().parents[1]
LEAVES = {" ".join(words): c for words, c in commands() if not isinstance(c, click.Group)}
#: Commands that write files.
WRITERS = ("urdf", "plan", "odom", "simulate", "plot", "calibrate fit", "calibrate umbmark")
OUTPUT = {"-o", "--output", "--out"}


def spellings(option: click.Option) -> str:
    """An option's names as the table lists them: ``-o, --output, --out``; ``--cw/--ccw``."""
    names = ", ".join(option.opts)
    return f"{names}/{', '.join(option.secondary_opts)}" if option.secondary_opts else names


def options(command: click.Command) -> set[str]:
    return {
        spellings(p)
        for p in command.params
        if isinstance(p, click.Option) and not p.hidden and p.name != "help"
    }


def table() -> str:
    """The options table of docs/cli.md, as the commands have it."""
    names = sorted({name for command in LEAVES.values() for name in options(command)})
    header = ["option", *LEAVES]
    rows = [header, ["---"] * len(header)]
    for name in names:
        marks = ["✓" if name in options(c) else "" for c in LEAVES.values()]
        rows.append([f"`{name}`", *marks])
    return "\n".join("| " + " | ".join(row) + " |" for row in rows) + "\n"


def test_the_table_of_docs_cli_is_the_commands_own() -> None:
    page = (ROOT / "docs" / "cli.md").read_text(encoding="utf-8")
    found = re.search(r"^\| option \|.*?(?=^[^|]|\Z)", page, re.MULTILINE | re.DOTALL)
    assert found is not None, "docs/cli.md has no options table"
    assert found.group(0) == table(), "docs/cli.md's table differs: print(table()) gives it"


@pytest.mark.parametrize("name", list(LEAVES))
def test_an_output_option_has_its_three_spellings(name: str) -> None:
    names = {n for p in LEAVES[name].params for n in p.opts}
    if name in WRITERS:
        assert names >= OUTPUT
    else:
        assert not (OUTPUT & names) or names >= OUTPUT


@pytest.mark.parametrize("name", list(LEAVES))
def test_max_rpm_is_the_one_motor_limit(name: str) -> None:
    names = {n for p in LEAVES[name].params for n in p.opts}
    assert "--rpm-limit" not in names
    if "--wheel-radius" in names:  # the robot options
        assert "--max-rpm" in names


@pytest.mark.parametrize("name", list(LEAVES))
def test_every_value_option_says_what_it_takes(name: str) -> None:
    for param in LEAVES[name].params:
        if isinstance(param, click.Option) and not param.is_flag and not param.count:
            assert param.metavar is not None or isinstance(param.type, click.Choice), (
                f"diffbot {name} {param.opts[0]}: no metavar"
            )
    joints = {
        p.opts[0]: p.metavar
        for p in LEAVES[name].params
        if p.opts[0] in ("--left-joint", "--right-joint")
    }
    assert set(joints.values()) <= {"NAME[,NAME]"}


@pytest.mark.parametrize("name", list(LEAVES))
def test_an_unknown_option_is_clicks_usage_error_with_the_help_hint(
    name: str, runner: CliRunner
) -> None:
    result = runner.invoke(main, [*name.split(), "--bogus"], prog_name="diffbot")
    assert_one_error_line(result, "No such option '--bogus'", f"(see 'diffbot {name} --help')")


def test_fk_over_the_motor_limit_exits_1_as_ik_does(runner: CliRunner) -> None:
    # 100 rad/s is 955 rpm, over the bundled robot's 50 rpm
    for command in ("fk", "ik"):
        result = runner.invoke(main, [command, "100", "0" if command == "ik" else "100"])
        assert result.exit_code == 1, result.output
        assert "exceeds the motor limit of 50 rpm" in result.stderr
        assert result.stdout


def test_example_names_are_told_as_the_help_spells_them(runner: CliRunner) -> None:
    result = runner.invoke(main, ["plan", "--example", "C"], prog_name="diffbot")
    assert_one_error_line(result, "'C' is not one of A, B, umbmark")
    assert runner.invoke(main, ["plan", "--example", "b", "--json"]).exit_code == 0


def test_commands_and_segment_kinds_get_a_did_you_mean(runner: CliRunner) -> None:
    assert_one_error_line(
        runner.invoke(main, ["pln"]), "No such command 'pln'. Did you mean 'plan'?"
    )
    result = runner.invoke(main, ["explain", "ikk", "1", "0"])
    assert_one_error_line(result, "Did you mean 'ik'?")
    result = runner.invoke(main, ["plan", "stright 1"])
    assert_one_error_line(result, "straight, ccw, cw, spin or reverse", "did you mean 'straight'?")
    result = runner.invoke(main, ["plan", "--exampl", "A"])
    assert_one_error_line(result, "No such option '--exampl'", "Did you mean '--example'?")
