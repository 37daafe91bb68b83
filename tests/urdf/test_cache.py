"""The parameter cache: entries are checked on read, and any entry that fails is derived again."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

import pytest
from robots import two_wheel_urdf

import diffbot

Write = Callable[[str, str], Path]


@pytest.fixture
def cache(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    folder = tmp_path / "cache"
    monkeypatch.setenv("DIFFBOT_CACHE_DIR", str(folder))
    return folder


def only_entry(cache: Path) -> Path:
    (entry,) = cache.glob("params-*.json")
    return entry


def test_an_entry_holds_only_json_data_and_no_temporary_file_is_left(
    cache: Path, write: Write
) -> None:
    diffbot.load_params(write("robot.urdf", two_wheel_urdf()))
    entry = json.loads(only_entry(cache).read_text(encoding="utf-8"))
    assert set(entry) == {"key", "digest", "fields"}
    assert entry["fields"]["wheel_radius"] == pytest.approx(0.05, abs=1e-12)
    assert [p.name for p in cache.iterdir() if not p.name.startswith("params-")] == []


@pytest.mark.parametrize("edited", ["0.5", "-0.05", "1e-320"])
def test_a_hand_edited_entry_is_not_trusted(cache: Path, write: Write, edited: str) -> None:
    path = write("robot.urdf", two_wheel_urdf())
    first = diffbot.load_params(path)
    entry = only_entry(cache)
    text = entry.read_text(encoding="utf-8")
    assert '"wheel_radius": 0.05' in text
    entry.write_text(text.replace('"wheel_radius": 0.05', f'"wheel_radius": {edited}'), "utf-8")
    again = diffbot.load_params(path)
    assert again.wheel_radius == pytest.approx(0.05, abs=1e-12)
    assert again == first


@pytest.mark.parametrize(
    "broken",
    ["[" * 100_000 + "]" * 100_000, "\xff not json", "", '{"wheel_radius": "0.05"}'],
)
def test_an_entry_that_fails_validation_is_derived_again(
    cache: Path, write: Write, broken: str
) -> None:
    path = write("robot.urdf", two_wheel_urdf())
    first = diffbot.load_params(path)
    entry = only_entry(cache)
    entry.write_text(broken, encoding="utf-8")
    assert diffbot.load_params(path) == first
    assert entry.read_text(encoding="utf-8") != broken  # and written again, whole


def test_a_directory_where_an_entry_should_be_is_ignored(cache: Path, write: Write) -> None:
    path = write("robot.urdf", two_wheel_urdf())
    first = diffbot.load_params(path)
    entry = only_entry(cache)
    entry.unlink()
    entry.mkdir()
    assert diffbot.load_params(path) == first
    assert entry.is_dir()


def run_python(code: str, cache: Path) -> str:
    import os
    import subprocess
    import sys

    env = {**os.environ, "DIFFBOT_CACHE_DIR": str(cache)}
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=120
    )
    assert done.returncode == 0, done.stderr
    return done.stdout


def test_a_missing_entry_is_derived_apart_and_numpy_stays_out_of_this_process(
    cache: Path, write: Write
) -> None:
    # params and check need no NumPy but to derive: derived in a child, it never loads here
    # (nor do yourdfpy and trimesh, which deriving does not use at all).
    path = write("robot.urdf", two_wheel_urdf())
    code = (
        "import sys, diffbot\n"
        f"p = diffbot.load_params({str(path)!r})\n"
        "print(p.wheel_radius, p.wheel_separation, "
        "*(name in sys.modules for name in ('numpy', 'yourdfpy', 'trimesh')))\n"
    )
    radius, separation, *loaded = run_python(code, cache).split()
    assert (float(radius), float(separation)) == (0.05, 0.2)
    assert loaded == ["False", "False", "False"]
    entry = json.loads(only_entry(cache).read_text(encoding="utf-8"))
    assert entry["fields"]["wheel_radius"] == 0.05
    from diffbot.urdf.wheels import derive_text

    here = derive_text(path.read_text(encoding="utf-8"), str(path))
    assert diffbot.load_params(path).wheel_separation == here.wheel_separation


def test_a_description_the_child_cannot_derive_raises_its_error_here(
    cache: Path, write: Write
) -> None:
    from diffbot.errors import DescriptionError

    path = write("robot.urdf", two_wheel_urdf().replace("continuous", "fixed"))
    with pytest.raises(DescriptionError) as caught:
        diffbot.load_params(path)
    assert "robot.urdf" in str(caught.value)
    assert list(cache.glob("params-*.json")) == []


@pytest.mark.parametrize("command", ["params", "check"])
def test_no_code_in_the_descriptions_folder_runs_when_a_missing_entry_is_derived(
    tmp_path: Path, command: str
) -> None:
    # A description's repository may hold a json.py, numpy.py or diffbot/ of its own; deriving
    # apart must not import them (a plain child process has the current folder on its path).
    import os
    import subprocess
    import sys

    from hostile import CLI, hostile_folder

    marker = tmp_path / "marker"
    repo = hostile_folder(tmp_path / "repo", marker)
    (repo / "robot.urdf").write_text(two_wheel_urdf(), encoding="utf-8")
    cache = tmp_path / "cache"
    env = {**os.environ, "DIFFBOT_CACHE_DIR": str(cache)}
    done = subprocess.run(
        [sys.executable, "-c", CLI, command, "robot.urdf"],
        cwd=repo,
        env=env,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert not marker.exists(), marker.read_text(encoding="utf-8")
    assert done.returncode == 0, done.stderr
    if command == "params":
        assert "wheel radius      0.05 m" in done.stdout
        assert "wheel separation  0.2 m" in done.stdout
    entry = json.loads(only_entry(cache).read_text(encoding="utf-8"))
    assert entry["fields"]["wheel_radius"] == 0.05


def test_the_cache_folder_is_the_environments_or_none(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from diffbot.urdf.cache import cache_dir

    monkeypatch.setenv("DIFFBOT_CACHE_DIR", str(tmp_path / "c"))
    assert cache_dir() == tmp_path / "c"
    monkeypatch.setenv("DIFFBOT_NO_CACHE", "1")
    assert cache_dir() is None
