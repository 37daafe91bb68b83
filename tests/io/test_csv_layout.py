"""CSV files from other tools: columns named otherwise, other delimiters, stamps in ms, us, ns."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from pioneer import COUNTS_PER_REV, PIONEER, START_NS, counts, urdf

import diffbot
from diffbot.cli import main
from diffbot.conditioning import Conditioning
from diffbot.io.csv_chunks import stamp_ns_from_text, stamps_from_digits, unit_by_magnitude
from diffbot.recordings import read_recording
from diffbot.replay import run_odometry
from diffbot.samples import ColumnSamples

COUNTS = Conditioning(counts_per_rev=COUNTS_PER_REV, wrap=65536)


def other_tool_csv(folder: Path, *, delimiter: str = ";", unit: str = "ns") -> Path:
    """The Pioneer's counts as another tool writes them: ``timestamp;left;right``."""
    stamps, left, right = counts()
    scale = {"ns": 1, "us": 1_000, "ms": 1_000_000}[unit]
    lines = [delimiter.join(("timestamp", "left", "right"))]
    for stamp, lc, rc in zip(stamps.tolist(), left.tolist(), right.tolist(), strict=True):
        lines.append(delimiter.join((str(stamp // scale), str(int(lc)), str(int(rc)))))
    path = folder / f"other_{unit}.csv"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


@pytest.mark.parametrize(
    ("text", "decimals", "expected"),
    [
        ("1764000000100000000", 0, 1_764_000_000_100_000_000),  # ns
        ("1764000000100000", 3, 1_764_000_000_100_000_000),  # us
        ("1764000000100.5", 6, 1_764_000_000_100_500_000),  # ms with a fraction
        ("1.5", 9, 1_500_000_000),  # s
        ("2.5", 0, 2),  # half a ns rounds to even
    ],
)
def test_stamps_are_read_exactly_in_every_unit(text: str, decimals: int, expected: int) -> None:
    assert stamp_ns_from_text(text, decimals) == expected
    stamps, ok = stamps_from_digits(np.array([text.encode()], dtype="S32"), decimals)
    if ok[0]:  # the fast path takes whole numbers of the unit and its decimals
        assert int(stamps[0]) == expected


@pytest.mark.parametrize(
    ("value", "unit"),
    [(1.764e9, "s"), (1.764e12, "ms"), (1.764e15, "us"), (1.764e18, "ns"), (12.5, "s")],
)
def test_the_unit_is_judged_by_the_size_of_a_stamp_since_1970(value: float, unit: str) -> None:
    assert unit_by_magnitude(value) == unit


@pytest.mark.parametrize("unit", ["ns", "us", "ms"])
def test_read_recording_maps_columns_and_judges_the_unit_and_delimiter_aloud(
    tmp_path: Path, unit: str
) -> None:
    path = other_tool_csv(tmp_path, unit=unit)
    recording = read_recording(
        path,
        PIONEER,
        conditioning=COUNTS,
        time_column="timestamp",
        left_column="left",
        right_column="right",
    )
    names = {"ns": "nanoseconds", "us": "microseconds", "ms": "milliseconds"}
    assert recording.notes == (
        "columns separated by ';', as the header is",
        f"stamps read as {names[unit]}, judged by the size of the first (too large for seconds "
        "since 1970)",
    )
    samples = recording.samples
    assert isinstance(samples, ColumnSamples)
    assert samples.stamps_ns[0] == START_NS + 100_000_000
    assert samples.stamps_ns[-1] - samples.stamps_ns[0] == 10 * 10**9
    run = run_odometry(recording, diffbot.Odometry(PIONEER))
    assert run.final_pose.x == pytest.approx(1.0, abs=1e-4)


def test_given_delimiter_and_unit_are_not_judged(tmp_path: Path) -> None:
    path = other_tool_csv(tmp_path, delimiter="\t", unit="us")
    recording = read_recording(
        path,
        PIONEER,
        conditioning=COUNTS,
        time_column="timestamp",
        left_column=["left"],
        right_column="right",
        delimiter="\t",
        time_unit="us",
    )
    assert recording.notes == ()
    assert recording.samples[0].stamp_ns == START_NS + 100_000_000


def test_mapping_errors_name_the_option_and_the_columns_found(
    runner: CliRunner, tmp_path: Path
) -> None:
    path = other_tool_csv(tmp_path)
    robot = ["--robot", str(urdf(tmp_path))]
    result = runner.invoke(main, ["odom", str(path), *robot])
    assert result.exit_code == 2
    assert result.stderr.endswith(
        "no time column (time, stamp, t, __time; or name it: --time-column); columns found: "
        "'timestamp', 'left', 'right'\n"
    )
    result = runner.invoke(
        main, ["odom", str(path), *robot, "--time-column", "timestamp", "--left-column", "lft"]
    )
    assert result.exit_code == 2
    assert result.stderr.endswith(
        "no column 'lft' (--left-column); columns found: 'timestamp', 'left', 'right'\n"
    )
    result = runner.invoke(main, ["odom", str(path), *robot, "--delimiter", ";;"])
    assert result.exit_code == 2
    assert result.stderr == "error: the delimiter must be one character, got ';;' (--delimiter)\n"


def test_odom_reads_another_tools_csv_and_says_what_it_judged(
    runner: CliRunner, tmp_path: Path
) -> None:
    path = other_tool_csv(tmp_path)
    args = ["odom", str(path), "--robot", str(urdf(tmp_path))]
    args += ["--time-column", "timestamp", "--left-column", "left", "--right-column", "right"]
    args += ["--counts-per-rev", repr(COUNTS_PER_REV), "--wrap", "65536"]
    result = runner.invoke(main, args)
    assert result.exit_code == 0, result.output
    assert "final pose  x 1.00001 m, y 0.5 m" in result.stdout
    assert result.stderr == (
        f"warning: {path}: columns separated by ';', as the header is; --delimiter to choose\n"
        f"warning: {path}: stamps read as nanoseconds, judged by the size of the first (too "
        "large for seconds since 1970); --time-unit to choose\n"
    )


@pytest.mark.parametrize("delimiter", [",", ";"])
def test_a_csv_without_a_header_line_is_told_so(
    runner: CliRunner, tmp_path: Path, delimiter: str
) -> None:
    # A data logger's export that starts with its first row of numbers: the error listed those
    # numbers as "columns found" and asked for a time column by name.
    path = other_tool_csv(tmp_path, delimiter=delimiter)
    path.write_text(path.read_text(encoding="utf-8").split("\n", 1)[1], encoding="utf-8")
    result = runner.invoke(main, ["odom", str(path), "--robot", str(urdf(tmp_path))])
    assert result.exit_code == 2
    assert result.stderr == (
        f"error: {path}: the first line holds numbers, not column names: a header line naming "
        f"the columns is needed (such as time{delimiter}left_wheel_joint{delimiter}"
        "right_wheel_joint; other names with --time-column, --left-column, --right-column)\n"
    )


@pytest.mark.parametrize("quoted", [False, True])
def test_decimal_commas_beside_semicolons_are_read_and_said(
    runner: CliRunner, tmp_path: Path, quoted: bool
) -> None:
    # A spreadsheet in a European locale writes "1764000000,1;0,25;0,5": every row was skipped
    # as "unreadable value" and the run refused with no hint why.
    stamps, left, right = counts()
    point = ["time;left_wheel_joint;right_wheel_joint"]
    comma = [point[0]]
    for stamp, lc, rc in zip(stamps.tolist(), left.tolist(), right.tolist(), strict=True):
        cells = [f"{stamp / 1e9:.3f}", f"{lc / 8:.3f}", f"{rc / 8:.3f}"]
        point.append(";".join(cells))
        decimal = [cell.replace(".", ",") for cell in cells]
        comma.append(";".join(f'"{c}"' if quoted else c for c in decimal))
    plain, european = tmp_path / "point.csv", tmp_path / "comma.csv"
    plain.write_text("\n".join(point) + "\n", encoding="utf-8")
    european.write_text("\n".join(comma) + "\n", encoding="utf-8")
    args = ["--robot", str(urdf(tmp_path)), "--counts-per-rev", repr(COUNTS_PER_REV / 8)]
    args += ["--wrap", "8192"]  # the 16-bit counter, in eighths
    expected = runner.invoke(main, ["odom", str(plain), *args, "--json"])
    result = runner.invoke(main, ["odom", str(european), *args, "--json"])
    assert result.exit_code == expected.exit_code == 0, result.output
    assert json.loads(result.stdout)["final_pose"] == json.loads(expected.stdout)["final_pose"]
    assert (
        f"warning: {european}: numbers with decimal commas, as the first row with fractions "
        "writes them\n" in result.stderr
    )


def test_whole_stamps_far_apart_are_doubted_out_loud(runner: CliRunner, tmp_path: Path) -> None:
    # A microcontroller's log, millis() since power-on beside its counts: read as seconds, a
    # 10 s run lasted 10000 s, and nothing said so.
    stamps, left, right = counts()
    rows = ["t,left_wheel_joint,right_wheel_joint"]
    for stamp, lc, rc in zip(stamps.tolist(), left.tolist(), right.tolist(), strict=True):
        rows.append(f"{(stamp - int(stamps[0])) // 10**6},{int(lc)},{int(rc)}")
    path = tmp_path / "millis.csv"
    path.write_text("\n".join(rows) + "\n", encoding="utf-8")
    args = ["odom", str(path), "--robot", str(urdf(tmp_path))]
    args += ["--counts-per-rev", repr(COUNTS_PER_REV), "--wrap", "65536"]
    result = runner.invoke(main, args)
    assert result.exit_code == 0, result.output
    assert "duration    10000 s" in result.stdout
    assert result.stderr == (
        f"warning: {path}: stamps read as seconds, though whole numbers 100 apart "
        "(milliseconds?); --time-unit to choose\n"
    )
    given = runner.invoke(main, [*args, "--time-unit", "ms"])
    assert given.exit_code == 0, given.output
    assert "duration    10 s" in given.stdout
    assert given.stderr == ""
    seconds = runner.invoke(main, [*args, "--time-unit", "s"])
    assert seconds.stderr == ""


@pytest.mark.parametrize(
    ("options", "column"),
    [
        (["--left-column", "right", "--right-column", "right"], "right"),
        (["--left-column", "timestamp", "--right-column", "right"], "timestamp"),
        (["--left-column", "left", "--right-column", "right,left"], "left"),
    ],
)
def test_a_column_read_for_two_roles_is_refused(
    runner: CliRunner, tmp_path: Path, options: list[str], column: str
) -> None:
    # The same column for both sides drove the robot straight, with exit 0.
    path = other_tool_csv(tmp_path)
    args = ["odom", str(path), "--robot", str(urdf(tmp_path)), "--time-column", "timestamp"]
    result = runner.invoke(main, [*args, *options])
    assert result.exit_code == 2, result.output
    assert result.stderr == (
        f"error: {path}: column {column!r} is named for two roles (--time-column, "
        "--left-column, --right-column): each column is one wheel or the time\n"
    )


@pytest.mark.parametrize(
    ("arguments", "named"),
    [
        ({"left_column": ""}, "left_column"),
        ({"left_column": "a,"}, "left_column"),
        ({"right_column": ["r", " "]}, "right_column"),
        ({"time_column": " "}, "time_column"),
    ],
)
def test_an_empty_column_name_is_refused_not_replaced_by_the_joints(
    arguments: dict[str, object], named: str
) -> None:
    # An empty name used to fall back to the joints' own columns: other data, read silently.
    from diffbot.errors import ParameterError
    from diffbot.io.recordings import csv_layout

    with pytest.raises(ParameterError, match="a column name is empty") as caught:
        csv_layout(**arguments)  # type: ignore[arg-type]
    assert f"{named}=" in str(caught.value)


def test_an_empty_column_option_is_one_error_line(tmp_path: Path) -> None:
    path = tmp_path / "run.csv"
    path.write_text("time,left_wheel_joint,right_wheel_joint\n0,0,0\n1,1,1\n", "utf-8")
    result = CliRunner().invoke(main, ["odom", str(path), "--right-column", "b,"])
    assert result.exit_code == 2
    assert result.stderr == "error: --right-column 'b,': a column name is empty\n"


@pytest.mark.parametrize(
    ("options", "pattern"),
    [
        ({"delimiter": ";;"}, r"the delimiter must be one character, got ';;' \(delimiter=\)"),
        ({"delimiter": ""}, r"the delimiter must be one character"),
        ({"time_unit": "min"}, r"unknown time unit 'min': give one of s, ms, us, ns"),
    ],
)
def test_a_layout_refuses_what_no_csv_reader_could_use(
    options: dict[str, str], pattern: str
) -> None:
    from diffbot.errors import RecordingError
    from diffbot.io.csv_layout import CsvLayout

    with pytest.raises(RecordingError, match=pattern):
        CsvLayout(**options)  # type: ignore[arg-type]
    assert CsvLayout(delimiter="\t", time_unit="ms").delimiter == "\t"


@pytest.mark.parametrize(
    ("header", "field", "named"),
    [
        ("left_wheel_joint", "position", True),  # the joint alone is its position
        ("left_wheel_joint", "velocity", False),
        ("/joint_states/left_wheel_joint/position", "position", True),
        ("/joint_states/left_wheel_joint/velocity", "velocity", True),
        ("/joint_states/left_wheel_joint/velocity", "position", False),
        ("/joint_states/left_wheel_joint/effort", "position", False),
        ("/joint_states/front_left_wheel_joint/position", "position", False),  # another joint
        ("left_wheel_joint/position", "position", False),  # not a field of a topic's message
    ],
)
def test_a_column_names_a_joints_field_by_its_suffix(header: str, field: str, named: bool) -> None:
    from diffbot.io.csv_layout import names_joint

    assert names_joint(header, "left_wheel_joint", field) is named
