"""Child interpreters never import code from the current folder."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from hostile import hostile_folder

from diffbot.processes import clean_path, python_command, safe_starts


def test_a_child_loads_this_diffbot_and_the_standard_library_not_the_folders(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    marker = tmp_path / "marker"
    folder = hostile_folder(tmp_path / "repo", marker)
    monkeypatch.chdir(folder)
    code = "import json, diffbot, numpy\nprint(json.dumps([diffbot.__file__, numpy.__file__]))"
    done = subprocess.run(python_command(code), capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    import json

    loaded, numpy_file = json.loads(done.stdout)
    assert Path(loaded) == Path(__import__("diffbot").__file__).resolve()
    assert not Path(numpy_file).is_relative_to(folder)
    assert not marker.exists()


def test_a_plain_child_would_run_the_folders_code(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # The hazard itself, so the test above is known to be able to fail.
    marker = tmp_path / "marker"
    monkeypatch.chdir(hostile_folder(tmp_path / "repo", marker))
    subprocess.run([sys.executable, "-c", "import json"], timeout=60, check=False)
    assert marker.read_text(encoding="utf-8") == "json.py\n"


def test_the_clean_path_drops_the_current_folder_and_relative_entries(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    other = str(tmp_path.parent)
    assert clean_path(["", ".", "src", str(tmp_path), str(tmp_path) + "/", other]) == [other]


def test_safe_starts_sets_the_safe_path_for_the_block_only(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setenv("PYTHONSAFEPATH", "")
    with safe_starts():
        assert os.environ["PYTHONSAFEPATH"] == "1"
    assert os.environ["PYTHONSAFEPATH"] == ""
    monkeypatch.delenv("PYTHONSAFEPATH")
    with safe_starts():
        assert os.environ["PYTHONSAFEPATH"] == "1"
    assert "PYTHONSAFEPATH" not in os.environ
