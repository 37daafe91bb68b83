"""A recording CSV's columns found by name: the time and each wheel, and refused where two columns
could be the one meant."""

from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner

from diffbot.cli import main
from diffbot.errors import RecordingError
from diffbot.io.csv_columns import (
    TIME_COLUMNS,
    joint_columns,
    named_columns,
    preferred_time_column,
    time_column,
)


@pytest.mark.parametrize("name", [*TIME_COLUMNS, "Time", "STAMP", "__TIME"])
def test_the_one_column_named_as_a_time_is_the_time(name: str) -> None:
    assert time_column(["left", name, "right"], "f.csv") == 1


def test_no_time_column_is_none_and_a_given_name_is_taken_whatever_it_is() -> None:
    assert time_column(["left", "right", "times"], "f.csv") is None
    assert time_column(["left", "clock", "right"], "f.csv", "clock") == 1
    # A given name wins over the names a time has by default.
    assert time_column(["time", "clock"], "f.csv", "clock") == 1
    assert time_column(["t", "time"], "f.csv", "t") == 0
    assert time_column(["Clock", "left"], "f.csv", "clock") == 0  # any case, when unique


@pytest.mark.parametrize(
    ("headers", "listed"),
    [
        (["t", "time", "left"], "'t', 'time'"),
        (["stamp", "left", "Time"], "'stamp', 'Time'"),
        (["__time", "time"], "'__time', 'time'"),
    ],
)
def test_two_columns_that_may_be_the_time_are_refused_naming_both(
    headers: list[str], listed: str
) -> None:
    with pytest.raises(RecordingError) as caught:
        time_column(headers, "f.csv")
    assert str(caught.value) == (
        f"f.csv: several columns may be the time ({listed}): name the one to read (time_column=)"
    )


def test_one_name_twice_is_refused_even_when_given() -> None:
    with pytest.raises(RecordingError) as caught:
        time_column(["time", "left", "time"], "f.csv")
    assert str(caught.value) == (
        "f.csv: 2 columns are named 'time', each may be the time: rename all but the one to read"
    )
    with pytest.raises(RecordingError) as caught:
        time_column(["time", "left", "time"], "f.csv", "time")
    assert str(caught.value) == (
        "f.csv: 2 columns are named 'time' (time_column=): rename all but the one to read"
    )


def test_named_columns_are_found_exactly_else_by_case_and_never_among_two() -> None:
    headers = ["time", "Left", "right", "RIGHT", "x", "x", "x"]
    assert named_columns(headers, ["Left", "right"], "{left_column}", "f.csv") == [
        ("Left", 1),
        ("right", 2),
    ]
    assert named_columns(headers, ["left"], "{left_column}", "f.csv") == [("left", 1)]
    with pytest.raises(RecordingError, match=r"^f\.csv: several columns are named 'Right' but"):
        named_columns(headers, ["Right"], "{right_column}", "f.csv")  # two in any case
    with pytest.raises(RecordingError, match=r"^f\.csv: no column 'up' \(right_column=\)"):
        named_columns(headers, ["up"], "{right_column}", "f.csv")
    with pytest.raises(RecordingError) as caught:
        named_columns(headers, ["x"], "{right_column}", "f.csv")
    assert str(caught.value) == (
        "f.csv: 3 columns are named 'x' (right_column=): rename all but the one to read"
    )


def test_joint_columns_are_named_by_the_joint_or_its_field() -> None:
    headers = ["time", "/joint_states/l/position", "/joint_states/l/velocity", "r"]
    assert joint_columns(headers, ["l"], "left", "f.csv") == [("l", 1)]
    assert joint_columns(headers, ["l"], "left", "f.csv", "velocity") == [("l", 2)]
    assert joint_columns(headers, ["r"], "right", "f.csv") == [("r", 3)]
    with pytest.raises(RecordingError, match=r"several columns for the left wheel joint 'l'"):
        joint_columns([*headers, "l"], ["l"], "left", "f.csv")
    with pytest.raises(RecordingError, match=r"no column for the right wheel joint 'q'"):
        joint_columns(headers, ["q"], "right", "f.csv")


def test_odom_refuses_a_csv_with_two_times_in_one_line(tmp_path: Path) -> None:
    path = tmp_path / "run.csv"
    path.write_text("t,time,front_left_wheel_joint,front_right_wheel_joint\n0,5,0,0\n1,5.5,1,1\n")
    result = CliRunner().invoke(main, ["odom", str(path)], prog_name="diffbot")
    assert result.exit_code == 2
    assert result.stderr == (
        f"error: {path}: several columns may be the time ('t', 'time'): name the one to read "
        "(--time-column)\n"
    )
    chosen = CliRunner().invoke(
        main, ["odom", str(path), "--time-column", "time", "--json"], prog_name="diffbot"
    )
    assert chosen.exit_code == 0, chosen.stderr
    assert '"duration": 0.5' in chosen.stdout


def test_the_preferred_time_column_is_the_first_name_in_order_of_preference() -> None:
    assert preferred_time_column(["stamp", "x", "TIME"]) == 2
    assert preferred_time_column(["__time", "t"]) == 1
    assert preferred_time_column(["t", "T"]) == 0
    assert preferred_time_column(["x", "y"]) is None


def test_a_name_given_that_several_columns_have_but_for_case_is_refused_as_such() -> None:
    with pytest.raises(RecordingError) as caught:
        time_column(["Time", "time", "left"], "f.csv", "TIME")
    assert str(caught.value) == (
        "f.csv: several columns are named 'TIME' but for case ('Time', 'time'; time_column=): "
        "give one's exact name"
    )
    assert time_column(["Time", "time", "left"], "f.csv", "Time") == 0
