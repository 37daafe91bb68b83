"""The README's and docs' shell sessions run as written and print what they show.

A ```console block holds commands (``$ `` lines, ``\\`` continuing a line) each followed by its
output (stdout and stderr as a terminal shows them). A line ``...`` stands for any number of lines.

The pages are walked as a reader walks them from the repository's root: README.md, then every page
in the order the README links them, all in ONE scratch directory holding a copy of
``docs/examples`` (so what an earlier page writes is there for a later one, and two pages writing
the same file collide as they would for the reader), with the installed ``diffbot`` on the PATH.
"""

from __future__ import annotations

import os
import re
import shutil
import struct
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
LINK = re.compile(r"\]\(([^)#\s]+)(?:#[^)\s]*)?\)")


def reading_order() -> list[Path]:
    """README.md, then the docs pages in the order the README first links them."""
    readme = ROOT / "README.md"
    pages = [readme]
    for target in LINK.findall(readme.read_text(encoding="utf-8")):
        page = (ROOT / target).resolve()
        if page.suffix == ".md" and page.parent == ROOT / "docs" and page not in pages:
            pages.append(page)
    return pages


PAGES = reading_order()
BLOCK = re.compile(r"^```console\n(.*?)^```", re.MULTILINE | re.DOTALL)


def sessions(text: str) -> list[tuple[str, list[str]]]:
    """(command, expected output lines) in the order the page shows them."""
    found: list[tuple[str, list[str]]] = []
    for block in BLOCK.findall(text):
        lines = block.splitlines()
        k = 0
        while k < len(lines):
            if not lines[k].startswith("$ "):
                raise AssertionError(f"output before any command: {lines[k]!r}")
            command = lines[k][2:]
            while command.endswith("\\"):  # bash reads backslash-newline as one line
                k += 1
                command = command + "\n" + lines[k]
            k += 1
            output: list[str] = []
            while k < len(lines) and not lines[k].startswith("$ "):
                output.append(lines[k])
                k += 1
            found.append((command, output))
    return found


def matches(expected: list[str], actual: list[str]) -> bool:
    """Whether ``actual`` fits ``expected``, where a ``...`` line stands for any lines."""
    if not expected:
        return not actual
    if expected[0] == "...":
        return any(matches(expected[1:], actual[k:]) for k in range(len(actual) + 1))
    return bool(actual) and actual[0] == expected[0] and matches(expected[1:], actual[1:])


def test_the_readme_links_every_page_and_every_session_is_a_console_block() -> None:
    pages = sorted((ROOT / "docs").glob("*.md"))
    assert sorted(PAGES[1:]) == pages, "the README must link every page of docs/"
    for page in PAGES:
        text = page.read_text(encoding="utf-8")
        for fence in re.findall(r"^```(\w*)\n(.*?)^```", text, re.MULTILINE | re.DOTALL):
            kind, body = fence
            session = re.search(r"^\$ ", body, re.MULTILINE) is not None  # a prompt: a session
            assert kind == "console" or not session, f"{page.name}: a session not run: {body}"


def _tree(root: Path) -> set[Path]:
    """The files of the working tree (caches and the virtual environment aside)."""
    skip = {".git", ".venv", ".mypy_cache", ".ruff_cache", ".pytest_cache", ".hypothesis"}
    return {
        path.relative_to(root)
        for path in root.rglob("*")
        if not skip & set(path.relative_to(root).parts) and "__pycache__" not in path.parts
    }


def test_walking_the_pages_in_order_prints_what_they_show(tmp_path: Path) -> None:
    before = _tree(ROOT)
    shutil.copytree(ROOT / "docs" / "examples", tmp_path / "docs" / "examples")
    for page in PAGES:
        _walk(page, tmp_path)
    assert _tree(ROOT) == before, "the walk left files in the working tree"


def _walk(page: Path, tmp_path: Path) -> None:
    env = {
        **os.environ,
        "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ.get('PATH', '')}",
        "DIFFBOT_CACHE_DIR": str(tmp_path / ".cache"),
        "PYTHONUNBUFFERED": "1",
        "COLUMNS": "100",
        "MPLBACKEND": "agg",  # the pages show --show on a machine without a display
    }
    env.pop("AMENT_PREFIX_PATH", None)
    for command, expected in sessions(page.read_text(encoding="utf-8")):
        done = subprocess.run(
            ["bash", "-c", command],
            cwd=tmp_path,
            env=env,
            stdin=subprocess.DEVNULL,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
            timeout=300,
            check=False,
        )
        actual = [line.rstrip() for line in done.stdout.splitlines()]
        wanted = [line.rstrip() for line in expected]
        assert matches(wanted, actual), (
            f"{page.name}: $ {command}\n--- shown ---\n"
            + "\n".join(wanted)
            + "\n--- printed ---\n"
            + "\n".join(actual)
        )


def test_the_matcher_takes_ellipsis_for_any_lines() -> None:
    assert matches(["a", "...", "d"], ["a", "b", "c", "d"])
    assert matches(["a", "...", "d"], ["a", "d"])
    assert not matches(["a", "...", "d"], ["a", "b"])
    assert not matches(["a"], ["a", "b"])
    assert sessions("```console\n$ echo a \\\nb\na b\n```\n") == [("echo a \\\nb", ["a b"])]


def test_a_continued_command_runs_as_one_command() -> None:
    ((command, expected),) = sessions("```console\n$ echo a \\\n  b\na b\n```\n")
    done = subprocess.run(["bash", "-c", command], capture_output=True, text=True, check=True)
    assert done.stdout.splitlines() == expected


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.name)
def test_links_between_pages_lead_to_files_that_exist(page: Path) -> None:
    targets = [t for t in LINK.findall(page.read_text(encoding="utf-8")) if "://" not in t]
    missing = [t for t in targets if not (page.parent / t).exists()]
    assert not missing, f"{page.name} links to missing files: {missing}"


def test_the_pages_have_examples() -> None:
    for name in ("explain.md", "plot.md"):
        assert sessions((ROOT / "docs" / name).read_text(encoding="utf-8")), name


def test_the_figure_shown_is_small_and_the_size_plot_writes() -> None:
    shown = ROOT / "docs" / "img" / "trajectory_a_odometry.png"
    assert shown.stat().st_size < 40_000
    header = shown.read_bytes()[:24]
    assert header[:8] == b"\x89PNG\r\n\x1a\n"
    assert struct.unpack(">II", header[16:24]) == (800, 900)  # as tests/commands checks plot's
