"""Resolving paths: a loop of symbolic links, wherever it is met, is one error line, never a
traceback (Python 3.11 raises RuntimeError for it, others OSError)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from cli_results import assert_one_error_line
from click.testing import CliRunner, Result
from robots import two_wheel_urdf

from diffbot.cli import main
from diffbot.errors import DescriptionError, PathError
from diffbot.io.pathnames import resolved


def loop(folder: Path, name: str, suffix: str = "") -> Path:
    """``name`` -> ``name_b`` -> ``name``: a loop of two links."""
    first, second = folder / f"{name}{suffix}", folder / f"{name}_b{suffix}"
    first.symlink_to(second.name)
    second.symlink_to(first.name)
    return first


def run(*args: str) -> Result:
    return CliRunner().invoke(main, list(args), catch_exceptions=False)


def test_a_path_resolves_with_its_links_followed(tmp_path: Path) -> None:
    (tmp_path / "real.urdf").write_text("", encoding="utf-8")
    (tmp_path / "link.urdf").symlink_to("real.urdf")
    assert resolved(tmp_path / "link.urdf") == (tmp_path / "real.urdf").resolve()
    assert resolved(tmp_path / "missing" / "x") == tmp_path.resolve() / "missing" / "x"


def test_a_loop_is_an_error_of_the_callers_kind(tmp_path: Path) -> None:
    first = loop(tmp_path, "loop", ".urdf")
    with pytest.raises(PathError, match="a loop of symbolic links"):
        resolved(first)
    with pytest.raises(DescriptionError, match=r"^shown: a loop of symbolic links$"):
        resolved(first, DescriptionError, name="shown")
    with pytest.raises(PathError, match="a loop of symbolic links"):
        resolved(first / "below")


def test_a_name_that_cannot_be_resolved_is_an_error(tmp_path: Path) -> None:
    with pytest.raises(PathError, match="cannot be resolved"):
        resolved(str(tmp_path / "a\0b"))


def test_a_loop_as_the_description_is_one_error_line(tmp_path: Path) -> None:
    first = loop(tmp_path, "loop", ".urdf")
    for args in (["urdf", str(first)], ["params", str(first)], ["params", "--robot", str(first)]):
        assert_one_error_line(run(*args), "a loop of symbolic links")


def test_a_loop_as_the_output_is_one_error_line(tmp_path: Path) -> None:
    first = loop(tmp_path, "out", ".csv")
    result = run("simulate", "straight 1", "-o", str(first), "--force")
    assert_one_error_line(result, "a loop of symbolic links")
    assert sorted(os.listdir(tmp_path)) == ["out.csv", "out_b.csv"]


def test_a_loop_as_a_recording_is_one_error_line(tmp_path: Path) -> None:
    first = loop(tmp_path, "joints", ".csv")
    assert_one_error_line(run("odom", str(first)), "a loop of symbolic links")
    assert_one_error_line(run("plot", "--odom", str(first)), "a loop of symbolic links")


def test_a_loop_as_a_package_folder_is_one_error_line(tmp_path: Path) -> None:
    first = loop(tmp_path, "pkg")
    result = run("params", "--package", f"pkg={first}")
    assert_one_error_line(result, "--package", "a loop of symbolic links")


def test_a_loop_named_by_the_description_is_one_error_line(tmp_path: Path) -> None:
    package = tmp_path / "pkg"
    package.mkdir()
    loop(package, "part", ".xacro")
    robot = tmp_path / "robot.urdf.xacro"
    for included in ("$(find pkg)/part.xacro", "pkg/part.xacro"):
        body = f'<xacro:include filename="{included}"/>'
        robot.write_text(two_wheel_urdf(body=body, xacro=True), encoding="utf-8")
        result = run("params", str(robot), "--package", f"pkg={package}")
        assert_one_error_line(result, "a loop of symbolic links")
