"""Telling a description's kind from its text: SDF, plain URDF or xacro."""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path

import pytest
from click.testing import CliRunner
from robots import two_wheel_urdf

import diffbot
from diffbot.cli import main
from diffbot.errors import ParameterError
from diffbot.urdf.xacro import _is_sdf_text

Write = Callable[[str, str], Path]
BANNER = "<!-- =================================================================== -->\n"


@pytest.mark.parametrize(
    ("text", "sdf"),
    [
        ("<sdf version='1.9'>", True),
        ('<?xml version="1.0"?>\n<!-- a -->\n<!-- b -->\n<sdf>', True),
        ("<sdf\nversion='1.6'>", True),
        ("<robot name='r'>", False),
        ("<sdfx>", False),
        ("<sdf", False),
        ("<!-- never closed <sdf>", False),
        ("<!-- <sdf> --><robot/>", False),
    ],
)
def test_sdf_is_told_by_its_root_element(text: str, sdf: bool) -> None:
    assert _is_sdf_text(text) is sdf


def test_a_urdf_with_thousands_of_comments_is_not_sdf_at_once() -> None:
    text = BANNER * 5000 + "<robot name='r'/>"
    start = time.process_time()
    assert not _is_sdf_text(text)
    assert _is_sdf_text(BANNER * 5000 + "<sdf version='1.9'/>")
    assert time.process_time() - start < 1.0


def test_a_generated_urdf_with_banner_comments_gives_its_parameters(
    write: Write, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("DIFFBOT_NO_CACHE", "1")
    urdf = two_wheel_urdf()
    body = urdf.replace("<robot", BANNER * 3000 + "<robot", 1)
    path = write("generated.urdf", body)
    start = time.process_time()
    params = diffbot.load_params(path)
    result = CliRunner().invoke(main, ["params", str(path)], catch_exceptions=False)
    assert time.process_time() - start < 20.0
    assert params.wheel_radius == pytest.approx(0.05, abs=1e-12)
    assert params.wheel_separation == pytest.approx(0.2, abs=1e-12)
    assert result.exit_code == 0, result.output
    assert "0.05" in result.output


@pytest.mark.parametrize("trust", ["false", "no", 0, None])
def test_trust_is_a_bool_never_a_truthy_word(trust: object) -> None:
    """``trust="false"`` is refused before anything is read: taken by truthiness it ran the
    description's Python, which here reads /etc/passwd."""
    untrusted = Path(__file__).resolve().parents[2] / "docs" / "examples" / "untrusted"
    with pytest.raises(ParameterError, match=r"^trust must be True or False"):
        diffbot.expand(untrusted / "etc.urdf.xacro", trust=trust)  # type: ignore[arg-type]
