"""Waypoint files and ``X,Y[,HEADING]`` poses: every number checked at the boundary."""

from __future__ import annotations

import math
import time
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from diffbot.errors import PlanError
from diffbot.io.waypoints import parse_pose, read_waypoints

HUGE = "9" * 400


def test_known_poses_in_si() -> None:
    assert parse_pose(" 1 m, -2.5m , 90 deg", "p") == (1.0, -2.5, math.pi / 2)
    assert parse_pose("1.,.5,3.5rad", "p") == (1.0, 0.5, 3.5)
    assert parse_pose("0,0,", "p") == (0.0, 0.0, None)


@pytest.mark.parametrize(
    ("name", "text", "fragment"),
    [
        ("w.yaml", f"- [{HUGE}, 0]\n", "item 1: x must be a finite number"),
        ("w.yaml", f"- {{x: 0, y: -{HUGE}}}\n", "item 1: y must be a finite number"),
        ("w.json", f"[[0, 0, {HUGE}]]", "item 1: heading must be a finite number"),
        ("w.csv", f"0,0\n{HUGE},0\n", "row 2: '9999"),
        ("w.yaml", "- [1.0e300, 0]\n", "x must be a finite number >= -1e+09 and <= 1e+09 m"),
        ("w.csv", "0,1e10\n", "y must be a finite number >= -1e+09 and <= 1e+09 m"),
        ("w.csv", "0,0,1e300rad\n", "heading must be a finite number >= -1e+09 and <= 1e+09 rad"),
        ("w.json", "[[0, 0, 1e12]]", "heading must be a finite number >= -5.72958e+10"),
        # digits of other scripts and Python's grouped digits are no written numbers
        ("w.csv", "0,0\n\u0663,0\n", "row 2: '\u0663' is not a number"),
        ("w.csv", "0,0\n1_0,0\n", "row 2: '1_0' is not a number"),
        ("w.csv", "0,0,\u0669\u0660deg\n", "is not a number"),
        ("w.yaml", "- ['\u0663', 0]\n", "item 1: '\u0663' is not a number"),
    ],
)
def test_numbers_past_the_boundary_are_plan_errors(
    tmp_path: Path, name: str, text: str, fragment: str
) -> None:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    with pytest.raises(PlanError) as caught:
        read_waypoints(path)
    message = str(caught.value)
    assert fragment in message, message
    assert len(message) < 200, message  # a 400-digit number is not printed whole


def test_an_integer_of_400_digits_names_its_size(tmp_path: Path) -> None:
    path = tmp_path / "w.yaml"
    path.write_text(f"- [{HUGE}, 0]\n", encoding="utf-8")
    with pytest.raises(PlanError, match=r"got an integer of about 40\d digits"):
        read_waypoints(path)


@given(st.floats(-1e9, 1e9), st.floats(-1e9, 1e9), st.floats(-5e10, 5e10))
def test_numbers_in_range_read_back_exactly(x: float, y: float, heading: float) -> None:
    assert parse_pose(f"{x!r},{y!r},{heading!r}", "p") == (x, y, math.radians(heading))


def test_a_long_row_of_digits_is_read_in_linear_time() -> None:
    # The number's pattern has one way to match any text: no backtracking on a near miss.
    for size in (20_000, 200_000):
        text = "1" * size + "x,0"
        start = time.process_time()
        with pytest.raises(PlanError, match="is not a number"):
            parse_pose(text, "p")
        elapsed = time.process_time() - start
        assert elapsed < 0.5, (size, elapsed)
