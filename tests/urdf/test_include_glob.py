"""A wildcard include's files: the same as :func:`glob.glob` finds, with every folder passed to
the caller's check before it is listed, and none listed that the check refuses."""

from __future__ import annotations

import glob
import os
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from diffbot.urdf.include_glob import include_files

#: Names of a small tree: some hidden, some alike, so that wildcards match several or none.
NAMES = ["a", "ab", "b.xacro", "a.xacro", ".hidden.xacro", "c1", "c2"]
PATTERN_PARTS = ["*", "a*", "*.xacro", "?", "c?", "[ab]*", "[!a]*", ".*", "a", "c1", ".."]


def tree(root: Path, files: list[str], folders: list[str]) -> None:
    for folder in folders:
        if not (root / folder).exists():
            (root / folder).mkdir(parents=True)
    for name in files:
        target = root / name
        if not target.parent.is_dir() or target.exists():
            continue
        target.write_text("", encoding="utf-8")


@settings(
    max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    folders=st.lists(st.lists(st.sampled_from(NAMES[:2] + NAMES[5:]), min_size=1, max_size=2)),
    files=st.lists(st.lists(st.sampled_from(NAMES), min_size=1, max_size=3)),
    pattern=st.lists(st.sampled_from(PATTERN_PARTS), min_size=1, max_size=3),
)
def test_the_files_are_globs_own(
    tmp_path_factory: pytest.TempPathFactory,
    folders: list[list[str]],
    files: list[list[str]],
    pattern: list[str],
) -> None:
    root = tmp_path_factory.mktemp("tree")
    tree(root, ["/".join(f) for f in files], ["/".join(f) for f in folders])
    spelled = os.path.join(str(root), *pattern)
    listed: list[str] = []
    assert include_files(spelled, listed.append) == sorted(glob.glob(spelled))


def test_relative_and_root_patterns_are_globs_own(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    tree(tmp_path, ["one.xacro", "two.xacro", "sub/three.xacro"], ["sub"])
    monkeypatch.chdir(tmp_path)
    for pattern in ("*.xacro", "*/*.xacro", "sub/*", "o*"):
        assert include_files(pattern, lambda folder: None) == sorted(glob.glob(pattern))
    assert include_files("/*", lambda folder: None) == sorted(glob.glob("/*"))


class RefusedError(Exception):
    """What the check raises to refuse a folder."""


def test_each_folder_is_checked_before_it_is_listed_and_a_refusal_lists_nothing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    tree(tmp_path, ["in/a.xacro", "out/secret.xacro"], ["in", "out"])
    order: list[str] = []
    real = os.listdir

    def listdir(folder: str) -> list[str]:
        order.append(f"list {folder}")
        return real(folder)

    def check(folder: str) -> None:
        order.append(f"check {folder}")
        if folder.endswith("out"):
            raise RefusedError(folder)

    monkeypatch.setattr(os, "listdir", listdir)
    assert include_files(f"{tmp_path}/in/*.xacro", check) == [f"{tmp_path}/in/a.xacro"]
    assert order[:2] == [f"check {tmp_path}/in", f"list {tmp_path}/in"]
    order.clear()
    with pytest.raises(RefusedError):
        include_files(f"{tmp_path}/out/*.xacro", check)
    assert order == [f"check {tmp_path}/out"]
    # A name spelled out after a wildcard is checked by its folder, before it is looked at.
    order.clear()
    with pytest.raises(RefusedError):
        include_files(f"{tmp_path}/i*/../out/secret.xacro", check)
    assert f"list {tmp_path}/in/../out" not in order


def test_a_hidden_name_matches_only_a_pattern_that_begins_with_a_dot(tmp_path: Path) -> None:
    tree(tmp_path, [".hidden.xacro", "shown.xacro"], [])
    for pattern, names in [
        ("*.xacro", ["shown.xacro"]),
        (".*.xacro", [".hidden.xacro"]),
        ("[.s]*", ["shown.xacro"]),  # glob's rule: the pattern's first character, not a class
    ]:
        spelled = f"{tmp_path}/{pattern}"
        assert include_files(spelled, lambda folder: None) == [f"{tmp_path}/{n}" for n in names]
        assert include_files(spelled, lambda folder: None) == sorted(glob.glob(spelled))


def test_a_folder_the_pattern_spells_is_checked_whether_or_not_it_exists(tmp_path: Path) -> None:
    """Else a refusal for one that exists, and none for one that does not, would tell which;
    also where the pattern spells it after a wildcard."""
    tree(tmp_path, ["there/a.xacro"], ["there"])
    for spelled in ("there", "nowhere", "th*/../there", "th*/../nowhere"):
        target = f"{tmp_path}/{spelled.replace('th*', 'there')}"

        def check(path: str, target: str = target) -> None:
            if path == target:
                raise RefusedError(path)

        with pytest.raises(RefusedError):
            include_files(f"{tmp_path}/{spelled}/*.xacro", check)


def test_a_spelled_folder_missing_under_one_match_does_not_end_the_others(tmp_path: Path) -> None:
    tree(tmp_path, ["b/sub/x.xacro", "c/sub/y.xacro"], ["a", "b/sub", "c/sub"])
    pattern = f"{tmp_path}/*/sub/*.xacro"
    assert include_files(pattern, lambda folder: None) == sorted(glob.glob(pattern))
    assert len(glob.glob(pattern)) == 2


def test_a_listed_name_that_is_no_folder_is_passed_over_unchecked(tmp_path: Path) -> None:
    """As glob does: ``*/x`` looks into folders only, so a file (or a link to one elsewhere)
    beside them is neither descended into nor refused."""
    tree(tmp_path, ["arm/macros.xacro", "LICENSE"], ["arm"])
    checked: list[str] = []

    def check(path: str) -> None:
        checked.append(path)
        if path.endswith("LICENSE"):
            raise RefusedError(path)

    pattern = f"{tmp_path}/*/macros.xacro"
    assert include_files(pattern, check) == glob.glob(pattern) == [f"{tmp_path}/arm/macros.xacro"]
    assert not any(path.endswith("LICENSE") for path in checked)
