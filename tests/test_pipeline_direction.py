"""The odometry pipeline flows one way: read (diffbot.io) -> condition (diffbot.conditioning)
-> integrate -> write. The readers and writers never reach forward into the conditioning or
the integrator, so a recording's trip never runs back into io/."""

from __future__ import annotations

import ast
import math
from pathlib import Path

import pytest

import diffbot

#: What comes after reading: the conditioning and the integrator with its driver.
DOWNSTREAM = (
    "diffbot.conditioning",
    "diffbot.odometry",
    "diffbot.batch_odometry",
    "diffbot.chunk_odometry",
    "diffbot.replay",
    "diffbot.recordings",
)

IO = Path(diffbot.__file__).parent / "io"


def _imports(path: Path) -> set[str]:
    """The modules a file imports when it runs (not those imported for type checking only)."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    found: set[str] = set()

    def visit(node: ast.AST) -> None:
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            for child in node.orelse:
                visit(child)
            return
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module is not None:
            found.add(node.module)
            found.update(f"{node.module}.{alias.name}" for alias in node.names)
        for child in ast.iter_child_nodes(node):
            visit(child)

    visit(tree)
    return found


def test_the_import_scan_sees_imports_inside_functions_and_skips_type_checking(
    tmp_path: Path,
) -> None:
    source = tmp_path / "m.py"
    source.write_text(
        "from typing import TYPE_CHECKING\n"
        "if TYPE_CHECKING:\n    from diffbot.replay import PoseSink\n"
        "def f():\n    from diffbot.conditioning import Conditioner\n"
    )
    found = _imports(source)
    assert "diffbot.conditioning" in found
    assert "diffbot.replay" not in found


def test_no_reader_or_writer_imports_the_conditioning_or_the_integrator() -> None:
    files = sorted(IO.glob("*.py"))
    assert len(files) > 5  # the scan looks at the real package
    offending = {
        f"{path.name} -> {name}"
        for path in files
        for name in _imports(path)
        if any(name == module or name.startswith(module + ".") for module in DOWNSTREAM)
    }
    assert offending == set()


def test_the_library_entry_conditions_what_the_reader_reads_as_recorded(tmp_path: Path) -> None:
    from robots import BOT

    from diffbot.conditioning import Conditioning
    from diffbot.io.csv_chunks import read_csv

    path = tmp_path / "counts.csv"
    left, right = BOT.left_joint, BOT.right_joint
    path.write_text(f"time,{left},{right}\n0,0,0\n0.1,100,200\n0.2,200,400\n")
    raw = read_csv(path, left, right).samples
    assert [tuple(s.positions) for s in raw] == [(0.0, 0.0), (100.0, 200.0), (200.0, 400.0)]
    # 4096 counts a revolution: 100 counts are 100 * 2 pi / 4096 rad.
    counts = Conditioning(counts_per_rev=4096, wrap=0)
    read = diffbot.read_recording(path, BOT, conditioning=counts).samples
    rad = 2 * math.pi / 4096
    for sample, (a, b) in zip(read, [(0, 0), (100, 200), (200, 400)], strict=True):
        assert sample.positions == pytest.approx([a * rad, b * rad], rel=1e-15, abs=0.0)
