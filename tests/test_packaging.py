"""What the install brings: every extra brings something the base install lacks."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _project() -> Any:
    tomllib = pytest.importorskip("tomllib")  # Python 3.11 and newer
    return tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]


def _name(requirement: str) -> str:
    return re.split(r"[<>=!~\[; ]", requirement, maxsplit=1)[0].lower().replace("_", "-")


def test_every_extra_brings_something_the_base_lacks() -> None:
    project = _project()
    base = {_name(r) for r in project["dependencies"]}
    for extra, requirements in project["optional-dependencies"].items():
        if extra == "test":
            continue
        assert {_name(r) for r in requirements} - base, f"the {extra!r} extra adds nothing"


def test_scipy_the_fit_uses_is_a_base_dependency() -> None:
    # yourdfpy brings it with trimesh[easy] anyway; calibrate fit uses it
    project = _project()
    assert "scipy" in {_name(r) for r in project["dependencies"]}
    assert "calibrate" not in project["optional-dependencies"]


def test_the_readme_names_what_each_extra_adds() -> None:
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    section = readme[readme.index("### What the install weighs") :].split("\n## ", 1)[0]
    for extra in _project()["optional-dependencies"]:
        if extra != "test":
            assert f"`[{extra}]`" in section, f"README omits the {extra!r} extra"
