"""Hostile inputs that ask for unbounded work: refused quickly with one ``error:`` line, or done
in streaming, near-linear work."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from cli_results import assert_one_error_line
from click.testing import CliRunner

from diffbot.cli import main

#: Longest any hostile input may take (s).
QUICK = 20.0


def run_process(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "diffbot", *args],
        capture_output=True,
        text=True,
        timeout=QUICK,
        check=False,
    )


NAMES = "abcdefghijklmnopqrstuvwxyzABCDEF"


def anchors(levels: int, last: str = "cw: *{n}") -> str:
    """YAML anchors doubling ``levels`` times: a few hundred bytes, 2**levels items."""
    parts = ["ccw: [&a [1,1]"]
    parts += [f",&{NAMES[k]} [*{NAMES[k - 1]},*{NAMES[k - 1]}]" for k in range(1, levels + 1)]
    return "".join(parts) + "]\n" + last.format(n=NAMES[levels]) + "\n"


@pytest.mark.parametrize("levels", [16, 27])
def test_a_runs_file_of_doubling_anchors_is_refused_quickly(tmp_path: Path, levels: int) -> None:
    path = tmp_path / "runs.yaml"
    path.write_text(anchors(levels), encoding="utf-8")
    assert path.stat().st_size <= 440
    done = run_process("calibrate", "umbmark", "--side", "4", "--runs", str(path))
    assert done.returncode == 2, done.stderr[:300]
    assert len(done.stderr) < 300, done.stderr[:300]
    assert done.stderr.startswith("error: ")
    assert "YAML aliases (*name) are not allowed in a runs file" in done.stderr


def test_bag_metadata_of_doubling_anchors_is_refused(tmp_path: Path) -> None:
    bag = tmp_path / "bag"
    bag.mkdir()
    (bag / "bag_0.db3").write_bytes(b"")
    text = anchors(27, "rosbag2_bagfile_information: {{storage_identifier: sqlite3, x: *{n}}}")
    (bag / "metadata.yaml").write_text(text, encoding="utf-8")
    result = CliRunner().invoke(main, ["odom", str(bag)])
    assert_one_error_line(result, "metadata.yaml: YAML aliases (*name) are not allowed")
