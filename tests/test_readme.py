"""The Python examples of the README and of docs/*.md run and print what the pages show."""

from __future__ import annotations

import doctest
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]

#: How many examples a page holds at least, so that a page cannot lose its examples unnoticed.
MINIMUM_EXAMPLES = {
    "README.md": 11,
    "library.md": 28,
    "goal-plans.md": 8,
    "odometry.md": 21,
    "plan-files.md": 9,
    "robots.md": 6,
    "simulate.md": 9,
}


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.name)
def test_python_examples_print_what_the_page_shows(
    page: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(ROOT)  # the examples name files under docs/examples from the repository root
    result = doctest.testfile(
        str(page), module_relative=False, optionflags=doctest.ELLIPSIS, verbose=False
    )
    assert result.failed == 0
    assert result.attempted >= MINIMUM_EXAMPLES.get(page.name, 0)


def test_every_page_with_a_minimum_exists() -> None:
    assert {p.name for p in PAGES} >= set(MINIMUM_EXAMPLES)
