"""Every example in every command's ``--help`` runs as written, from a copy of the repository
(the examples name its files: docs/examples/...), and exits 0."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import click
import pytest

from diffbot.cli import main

ROOT = Path(__file__).resolve().parents[1]
_SKIP = shutil.ignore_patterns(".venv", ".git", "__pycache__", "*_cache", "*.egg-info", "build")


def commands(
    group: click.Group = main, path: tuple[str, ...] = ()
) -> Iterator[tuple[tuple[str, ...], click.Command]]:
    """Every command and group under ``group``, by its words after ``diffbot``."""
    ctx = click.Context(group, info_name="diffbot")
    for name in group.list_commands(ctx):
        command = group.get_command(ctx, name)
        assert command is not None
        yield (*path, name), command
        if isinstance(command, click.Group):
            yield from commands(command, (*path, name))


ALL = [((), main), *commands()]


def examples(help_text: str) -> list[tuple[str, int]]:
    """The shell commands of a help text's ``Example(s):`` section, continued lines joined and
    the words that explain them (after two spaces) left out, each with the exit code those words
    give (``exit code N``, on the line or the next), else 0."""
    found: list[tuple[str, int]] = []
    section = re.search(r"Examples?:\n(.*?)(?:\n\s*\n|\Z)", help_text, re.DOTALL)
    if section is None:
        return found
    lines = section.group(1).splitlines()
    k = 0
    while k < len(lines):
        text = lines[k].strip()
        k += 1
        if not text.startswith("diffbot "):
            continue
        while text.endswith("\\"):
            text = text[:-1] + lines[k].strip()
            k += 1
        command, *words = re.split(r"\s{2,}", text, maxsplit=1)
        if k < len(lines) and not lines[k].strip().startswith("diffbot "):
            words.append(lines[k])
        code = re.search(r"exit code (\d+)", " ".join(words))
        found.append((command, int(code.group(1)) if code else 0))
    return found


@pytest.mark.parametrize(
    "words", [words for words, _ in ALL], ids=lambda w: " ".join(w) or "diffbot"
)
def test_every_help_has_examples(words: tuple[str, ...]) -> None:
    command = dict(ALL)[words]
    assert examples(command.help or ""), f"'diffbot {' '.join(words)} --help' shows no example"


@pytest.mark.parametrize(
    "words", [words for words, _ in ALL], ids=lambda w: " ".join(w) or "diffbot"
)
def test_every_help_example_runs_as_written(words: tuple[str, ...], tmp_path: Path) -> None:
    command = dict(ALL)[words]
    repository = tmp_path / "diffbot"
    shutil.copytree(ROOT, repository, ignore=_SKIP)
    env = {
        **os.environ,
        "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ.get('PATH', '')}",
        "DIFFBOT_CACHE_DIR": str(tmp_path / "cache"),
        "MPLBACKEND": "agg",
    }
    env.pop("AMENT_PREFIX_PATH", None)
    for example, code in examples(command.help or ""):
        done = subprocess.run(
            ["bash", "-o", "pipefail", "-c", example],
            cwd=repository,
            env=env,
            stdin=subprocess.DEVNULL,
            capture_output=True,
            text=True,
            timeout=300,
            check=False,
        )
        assert done.returncode == code, f"$ {example}\n{done.stdout[-2000:]}{done.stderr[-2000:]}"


def test_examples_are_read_whole() -> None:
    text = "Examples:\n  diffbot a 1 \\\n      --b c   what\n  diffbot d\n    exit code 1\n\nMore."
    assert examples(text) == [("diffbot a 1 --b c", 0), ("diffbot d", 1)]
