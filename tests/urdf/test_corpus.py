"""The corpus: descriptions shaped like public robots' (tests/corpus/, one folder each), loaded
through the public API and checked against the values worked out by hand from their files
(tests/corpus/manifest.yaml), each within a CPU-time bound."""

from __future__ import annotations

import json
import math
import re
import signal
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import pytest
import yaml
from click.testing import CliRunner

import diffbot
from diffbot.cli import main
from diffbot.errors import DiffbotError

CORPUS = Path(__file__).resolve().parent.parent / "corpus"
MANIFEST: dict[str, dict[str, Any]] = yaml.safe_load(
    (CORPUS / "manifest.yaml").read_text(encoding="utf-8")
)
#: CPU time one description may take to load (s): generous for a slow CI machine; a reader that
#: backtracks or loops takes minutes.
CPU_BOUND = 5.0
#: Lengths compared to this (m) unless a case says otherwise.
LENGTH_TOL = 1e-9


class _OverTime(BaseException):
    """Raised by the CPU timer; a BaseException so that no ``except Exception`` swallows it."""


@contextmanager
def cpu_bound(seconds: float) -> Iterator[None]:
    """Fail when the block takes more than ``seconds`` of this process's CPU time."""

    def stop(signum: int, frame: object) -> None:
        raise _OverTime

    previous = signal.signal(signal.SIGPROF, stop)
    signal.setitimer(signal.ITIMER_PROF, seconds)
    start = time.process_time()
    try:
        yield
    except _OverTime:
        pytest.fail(f"took more than {seconds} s of CPU time", pytrace=False)
    finally:
        signal.setitimer(signal.ITIMER_PROF, 0.0)
        signal.signal(signal.SIGPROF, previous)
    assert time.process_time() - start <= seconds


def _cases() -> list[Any]:
    cases = []
    for name, case in MANIFEST.items():
        marks = []
        if "xfail" in case:
            marks.append(pytest.mark.xfail(strict=True, reason=case["xfail"]))
        cases.append(pytest.param(name, case, id=name, marks=marks))
    return cases


def _corpus_text(value: str) -> str:
    """A manifest's path in a source, as shown from the corpus folder (the tests' cwd)."""
    return value.replace("{corpus}/", "")


def _load(case: dict[str, Any]) -> diffbot.DiffDriveParams:
    packages = {name: CORPUS / folder for name, folder in case.get("packages", {}).items()}
    return diffbot.load_params(
        case["path"],
        case.get("args"),
        packages or None,
        controllers=case.get("controllers"),
        left_joint=case.get("left_joint"),
        right_joint=case.get("right_joint"),
    )


def test_the_corpus_holds_at_least_36_descriptions() -> None:
    folders = {p.name for p in CORPUS.iterdir() if p.is_dir()}
    described = {Path(case["path"]).parts[0] for case in MANIFEST.values()}
    assert folders == described  # every folder has its expectations, every case its folder
    assert len(folders) >= 36


@pytest.mark.parametrize(("name", "case"), _cases())
def test_corpus_description(name: str, case: dict[str, Any], monkeypatch: Any) -> None:
    monkeypatch.chdir(CORPUS)
    if "error" in case:
        with cpu_bound(CPU_BOUND), pytest.raises(DiffbotError) as raised:
            _load(case)
        message = str(raised.value)
        assert "\n" not in message
        assert re.search(case["error"], message), message
        return
    with cpu_bound(CPU_BOUND):
        params = _load(case)
    tol = case.get("tol", LENGTH_TOL)
    assert math.isclose(params.wheel_radius, case["radius"], rel_tol=0.0, abs_tol=tol)
    assert math.isclose(params.wheel_separation, case["separation"], rel_tol=0.0, abs_tol=tol)
    left = case.get("left_radius", case["radius"])
    right = case.get("right_radius", case["radius"])
    assert math.isclose(params.radii[0], left, rel_tol=0.0, abs_tol=tol)
    assert math.isclose(params.radii[1], right, rel_tol=0.0, abs_tol=tol)
    assert list(params.left_joints) == case["left_joints"]
    assert list(params.right_joints) == case["right_joints"]
    assert (params.left_sign, params.right_sign) == (case["left_sign"], case["right_sign"])
    if case["max_wheel_speed"] is None:
        assert params.max_wheel_speed is None
    else:
        assert params.max_wheel_speed is not None
        assert math.isclose(params.max_wheel_speed, case["max_wheel_speed"], rel_tol=1e-12)
    for field, source in case.get("sources", {}).items():
        assert params.sources[field] == _corpus_text(source), field
    if "disagree" in case:
        assert sorted(d.field for d in params.disagreements) == sorted(case["disagree"])
    for text in case.get("warn", []):
        assert any(text in warning for warning in params.warnings), params.warnings


CLI_CASES = [pytest.param(n, c, id=n) for n, c in MANIFEST.items() if c.get("cli")]


@pytest.mark.parametrize(("name", "case"), CLI_CASES)
def test_corpus_description_from_the_command_line(
    name: str, case: dict[str, Any], monkeypatch: Any
) -> None:
    if "xfail" in case:
        pytest.xfail(case["xfail"])
    monkeypatch.chdir(CORPUS)
    args = ["params", case["path"], "--json"]
    args += [f"{key}:={value}" for key, value in case.get("args", {}).items()]
    if case.get("controllers"):
        args += ["--controllers", case["controllers"]]
    for side in ("left", "right"):
        if case.get(f"{side}_joint"):
            args += [f"--{side}-joint", case[f"{side}_joint"]]
    with cpu_bound(CPU_BOUND):
        result = CliRunner().invoke(main, args)
    if "error" in case:
        assert result.exit_code == 2
        lines = result.stderr.strip().splitlines()
        assert len(lines) == 1, result.stderr
        assert lines[0].startswith("error: "), result.stderr
        assert re.search(case["error"], lines[0]), lines[0]
        return
    assert result.exit_code == 0, result.stderr
    data = json.loads(result.stdout)
    tol = case.get("tol", LENGTH_TOL)
    assert math.isclose(data["wheel_radius"], case["radius"], rel_tol=0.0, abs_tol=tol)
    assert math.isclose(data["wheel_separation"], case["separation"], rel_tol=0.0, abs_tol=tol)
    assert data["left_joints"] == case["left_joints"]
    assert data["right_joints"] == case["right_joints"]
    assert (data["left_sign"], data["right_sign"]) == (case["left_sign"], case["right_sign"])
    expected = case["max_wheel_speed"]
    assert data["max_wheel_speed"] == (None if expected is None else pytest.approx(expected))
    for field, source in case.get("sources", {}).items():
        assert data["sources"][field] == _corpus_text(source), field
