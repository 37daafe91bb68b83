"""The examples of docs/*.md run and print what the pages say they print.

Console blocks (```console) hold ``$ diffbot ...`` lines, each followed by its output (stdout
and stderr as a terminal shows them); a page's blocks run in order in one empty directory.
Python blocks are doctests.
"""

from __future__ import annotations

import doctest
import shlex
import struct
from pathlib import Path

import pytest
from click.testing import CliRunner

from diffbot.cli import main

DOCS = Path(__file__).resolve().parents[1] / "docs"
PAGES = sorted(DOCS.glob("*.md"))


def console_examples(page: Path) -> list[tuple[str, str]]:
    """Each ``$ diffbot ...`` line of the page's console blocks, with the output shown."""
    examples: list[tuple[str, list[str]]] = []
    inside = False
    for line in page.read_text(encoding="utf-8").splitlines():
        if line.startswith("```"):
            inside = line == "```console"
        elif inside and line.startswith("$ "):
            examples.append((line[2:], []))
        elif inside:
            examples[-1][1].append(line)
    return [(command, "".join(f"{line}\n" for line in output)) for command, output in examples]


def test_the_pages_have_examples() -> None:
    assert {page.name for page in PAGES} >= {"explain.md", "plot.md"}
    assert all(console_examples(DOCS / name) for name in ("explain.md", "plot.md"))


@pytest.mark.parametrize("page", PAGES, ids=[page.name for page in PAGES])
def test_console_examples_print_what_the_page_shows(
    page: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    pytest.importorskip("matplotlib", reason="the plot examples need the 'plot' extra")
    import matplotlib

    matplotlib.use("agg")  # the pages show --show on a machine without a display
    monkeypatch.chdir(tmp_path)
    for command, shown in console_examples(page):
        args = shlex.split(command)
        assert args[0] == "diffbot", command
        result = CliRunner().invoke(main, args[1:], prog_name="diffbot")
        assert result.output == shown, command
        assert result.exit_code == (2 if shown.startswith("error: ") else 0), command


@pytest.mark.parametrize("page", PAGES, ids=[page.name for page in PAGES])
def test_python_examples_print_what_the_page_shows(page: Path) -> None:
    result = doctest.testfile(str(page), module_relative=False, optionflags=doctest.ELLIPSIS)
    assert result.failed == 0


def test_the_figure_shown_is_small_and_the_size_plot_writes() -> None:
    shown = DOCS / "img" / "trajectory_a_odometry.png"
    assert shown.stat().st_size < 40_000
    header = shown.read_bytes()[:24]
    assert header[:8] == b"\x89PNG\r\n\x1a\n"
    assert struct.unpack(">II", header[16:24]) == (800, 900)  # as tests/commands checks plot's
