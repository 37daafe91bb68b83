"""The Python examples of the README and of docs/*.md run and print what the pages show.

Each ```python block runs alone in a fresh interpreter from the repository root, as a reader who
copies that one block runs it: a block holds its own imports and data.
"""

from __future__ import annotations

import doctest
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
BLOCK = re.compile(r"^```python\n(.*?)^```", re.MULTILINE | re.DOTALL)

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

#: Runs the doctest on stdin in this fresh interpreter; prints "attempted failed".
RUN_BLOCK = """
import doctest, sys
test = doctest.DocTestParser().get_doctest(sys.stdin.read(), {"__name__": "__main__"}, "block",
                                           None, 0)
runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
runner.run(test)
print(runner.tries, runner.failures)
"""


def blocks() -> list[tuple[Path, int, str]]:
    return [
        (page, k, block)
        for page in PAGES
        for k, block in enumerate(BLOCK.findall(page.read_text(encoding="utf-8")))
    ]


@pytest.mark.parametrize(
    ("page", "index", "block"), blocks(), ids=lambda v: v.name if isinstance(v, Path) else ""
)
def test_each_python_block_runs_alone_in_a_fresh_interpreter(
    page: Path, index: int, block: str
) -> None:
    done = subprocess.run(
        [sys.executable, "-c", RUN_BLOCK],
        input=block,
        capture_output=True,
        text=True,
        cwd=ROOT,
        timeout=120,
        check=False,
    )
    *report, counts = done.stdout.splitlines() or [""]
    assert done.returncode == 0, done.stderr
    tries, failures = map(int, counts.split())
    assert failures == 0, f"{page.name} block {index + 1}:\n" + "\n".join(report)
    assert tries == block.count(">>> ")


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.name)
def test_a_page_keeps_its_examples(page: Path) -> None:
    parser = doctest.DocTestParser()
    text = page.read_text(encoding="utf-8")
    examples = sum(len(parser.get_examples(block)) for block in BLOCK.findall(text))
    assert examples >= MINIMUM_EXAMPLES.get(page.name, 0)
    assert len(parser.get_examples(BLOCK.sub("", text))) == 0, "an example outside a block"


def test_every_page_with_a_minimum_exists() -> None:
    assert {p.name for p in PAGES} >= set(MINIMUM_EXAMPLES)
