"""docs/odometry.md's interactive examples run and print what it says they print."""

from __future__ import annotations

import doctest
from pathlib import Path

DOC = Path(__file__).resolve().parents[1] / "docs" / "odometry.md"


def test_odometry_docs_python_examples_print_what_the_docs_show() -> None:
    result = doctest.testfile(str(DOC), module_relative=False, optionflags=doctest.ELLIPSIS)
    assert result.attempted >= 20
    assert result.failed == 0
