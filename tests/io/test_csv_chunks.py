"""Recording CSVs read in chunks: the same samples, skips and odometry as row by row."""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Sequence
from decimal import ROUND_HALF_EVEN, Decimal, InvalidOperation
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from peak_memory import peak_bytes
from robots import NAMED
from sinks import Collect

from diffbot.errors import RecordingError
from diffbot.io.csv_chunks import (
    CsvChunks,
    CsvLayout,
    open_csv_chunks,
    stamp_ns_from_text,
    stamps_from_digits,
)
from diffbot.odometry import Odometry
from diffbot.reading import Reading
from diffbot.replay import csv_odometry

Row = tuple[int, float, float, int]


def exact_ns(text: str) -> int | str | None:
    """The documented stamp rule, spelled out: exact decimal seconds written in ASCII digits,
    ties to even, in int64."""
    if not text.strip():
        return "missing stamp"
    if "_" in text or not text.isascii():  # Python's grouped digits, other scripts' digits
        return "unreadable value"
    try:
        seconds = Decimal(text.strip())
    except InvalidOperation:
        return "unreadable value"
    if not seconds.is_finite():
        return "not finite"
    if abs(seconds) >= Decimal(2**63) / 10**9 + 1:
        return "stamp out of range"
    ns = int((seconds * 10**9).quantize(Decimal(1), rounding=ROUND_HALF_EVEN))
    return ns if -(2**63) <= ns < 2**63 else "stamp out of range"


def reference(text: str) -> tuple[list[Row], dict[str, int]]:
    """Samples and skips of a CSV whose header is ``time,left,x,right``, row by row."""
    rows = csv.reader(io.StringIO(text, newline=""))
    next(rows)
    samples: list[Row] = []
    skipped: dict[str, int] = {}
    for row in rows:
        if not any(c.strip() for c in row):
            continue
        cells = [row[i] if i < len(row) else "" for i in (0, 1, 3)]
        stamp = exact_ns(cells[0])
        if not isinstance(stamp, int):
            reason = stamp if isinstance(stamp, str) else "not finite"
            skipped[reason] = skipped.get(reason, 0) + 1
            continue
        values, bits = [0.0, 0.0], 0
        try:
            for k, cell in enumerate(cells[1:]):
                if cell.strip():
                    if "_" in cell or not cell.isascii():
                        raise ValueError(cell)
                    values[k] = float(cell)
                    bits += 1 << k
        except ValueError:
            skipped["unreadable value"] = skipped.get("unreadable value", 0) + 1
            continue
        if any(math.isfinite(v) and abs(v) > 1e12 for v in values):
            skipped["position out of range"] = skipped.get("position out of range", 0) + 1
            continue
        samples.append((stamp, values[0], values[1], bits))
    return samples, skipped


def chunked(text: str, chunk_bytes: int) -> tuple[list[Row], dict[str, int]]:
    samples: list[Row] = []
    skipped: dict[str, int] = {}
    stream = io.StringIO(text, newline="")
    for chunk in CsvChunks(stream, (["left"], ["right"]), chunk_bytes=chunk_bytes):
        samples += zip(
            chunk.stamp_ns.tolist(),
            chunk.positions[:, 0].tolist(),
            chunk.positions[:, 1].tolist(),
            (chunk.present[:, 0] + 2 * chunk.present[:, 1].astype(np.uint8)).tolist(),
            strict=True,
        )
        for reason, n in chunk.skipped.items():
            skipped[reason] = skipped.get(reason, 0) + n
    return samples, skipped


def read_all(path: Path) -> int:
    """How many samples the chunks of a file hold."""
    with open_csv_chunks(path, (["left"], ["right"])) as chunks:
        return sum(chunk.stamp_ns.size for chunk in chunks)


def bits(values: Sequence[float]) -> list[int]:
    return [int(v) for v in np.array(values, dtype=np.float64).view(np.int64)]


stamp_cells = st.one_of(
    st.integers(0, 10**10).map(str),
    st.builds(
        lambda s, f: f"{s}.{f}",
        st.integers(0, 9_999_999_999),
        st.text("0123456789", min_size=1, max_size=12),
    ),
    st.sampled_from(
        [
            "",
            " ",
            "nan",
            "-inf",
            "1e3",
            "-1.5",
            ".5",
            "5.",
            " 7 ",
            "1_0",
            "x",
            "9223372036.854775807",
            "9223372036.854775808",
            "1e400",
            "0.0000000005",
            "0.0000000015",
            "١٢",
        ]
    ),
)
position_cells = st.one_of(
    st.floats(allow_nan=False).map(repr),
    st.sampled_from(
        ["", " ", "nan", "-inf", "1e5", " 2.5 ", "1_0", "abc", "-0.0", "0x1", "1e-400", "\u0663.5"]
    ),
)


@st.composite
def csv_texts(draw: st.DrawFn) -> str:
    lines = ["time,left,x,right"]
    for _ in range(draw(st.integers(0, 30))):
        kind = draw(st.sampled_from(["row"] * 6 + ["blank", "short", "commas", "quoted"]))
        if kind == "blank":
            lines.append("")
        elif kind == "short":
            lines.append(f"{draw(stamp_cells)},{draw(position_cells)}")
        elif kind == "commas":
            lines.append(",,,")
        else:
            cells = [draw(stamp_cells), draw(position_cells), "0", draw(position_cells)]
            if kind == "quoted":
                cells[2] = '"a,\nb"'
            lines.append(",".join(cells))
    ending = draw(st.sampled_from(["\n", "\r\n"]))
    return ending.join(lines) + ending


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(csv_texts(), st.integers(1, 200))
def test_chunks_give_the_row_by_row_samples_and_skips_bit_for_bit(
    text: str, chunk_bytes: int
) -> None:
    want, want_skipped = reference(text)
    got, got_skipped = chunked(text, chunk_bytes)
    assert [(s, p) for s, _, _, p in got] == [(s, p) for s, _, _, p in want]
    assert bits([v for row in got for v in row[1:3]]) == bits([v for row in want for v in row[1:3]])
    assert got_skipped == want_skipped


@settings(max_examples=60, deadline=None)
@given(csv_texts())
def test_csv_odometry_equals_the_streaming_run_over_the_same_rows(text: str) -> None:
    rows, _ = reference(text)
    odom = Odometry(NAMED)
    origin = rows[0][0] if rows else 0
    want_rows = []
    for stamp, left, right, present in rows:
        if present == 3 and odom.update(left, right, (stamp - origin) / 10**9):
            want_rows.append((stamp, odom.pose.x, odom.pose.y, odom.heading))
    sink = Collect()

    if odom.samples == 0:
        with pytest.raises(RecordingError, match="no usable sample"):
            csv_odometry(io.StringIO(text, newline=""), NAMED, chunk_bytes=64)
        return
    stream = io.StringIO(text, newline="")
    got = csv_odometry(stream, NAMED, Reading(sink=sink), chunk_bytes=64).summary
    streamed = sink.rows
    assert [r[0] for r in streamed] == [r[0] for r in want_rows]
    for k in (1, 2, 3):
        assert bits([r[k] for r in streamed]) == bits([r[k] for r in want_rows])
    assert bits([*got.final_pose, got.distance]) == bits([*odom.pose, odom.distance])
    assert got.samples == odom.samples


@given(st.integers(0, 9_999_999_999), st.integers(0, 999_999_999), st.integers(0, 9))
def test_digit_stamps_are_exact_integer_nanoseconds(whole: int, frac: int, cut: int) -> None:
    text = f"{whole}.{frac:09d}"[: 11 + len(str(whole)) - cut] if cut else f"{whole}.{frac:09d}"
    text = text.rstrip(".")
    stamps, ok = stamps_from_digits(np.array([text.encode()], dtype="S32"))
    want = stamp_ns_from_text(text)
    assert want is not None
    assert bool(ok[0]) == (want < 2**63)
    if ok[0]:
        assert int(stamps[0]) == want


def test_known_stamps_follow_the_documented_rounding() -> None:
    assert stamp_ns_from_text("1700000000.123456789") == 1_700_000_000_123_456_789
    assert stamp_ns_from_text("0.0000000005") == 0  # a tie rounds to even
    assert stamp_ns_from_text("0.0000000015") == 2
    assert stamp_ns_from_text("nan") is None
    with pytest.raises(ValueError, match="1_0"):
        stamp_ns_from_text("1_0")


def test_columns_are_found_by_joint_name_or_position_suffix(tmp_path: Path) -> None:
    path = tmp_path / "r.csv"
    path.write_text("\ufeff__time,/js/right/position,/js/left/position\n1.5,2.0,3.0\n", "utf-8")
    with open_csv_chunks(path, (["left"], ["right"])) as chunks:
        (chunk,) = list(chunks)
    assert chunk.stamp_ns.tolist() == [1_500_000_000]
    assert chunk.positions.tolist() == [[3.0, 2.0]]


def test_velocity_columns_are_found_by_their_suffix_only(tmp_path: Path) -> None:
    path = tmp_path / "r.csv"
    path.write_text("t,left,right,/js/left/velocity,/js/right/velocity\n1,2,3,0.5,-0.5\n", "utf-8")
    with open_csv_chunks(path, (["left"], ["right"]), layout=CsvLayout(field="velocity")) as chunks:
        (chunk,) = list(chunks)
    assert chunk.positions.tolist() == [[0.5, -0.5]]
    path.write_text("t,left,right\n1,2,3\n", "utf-8")
    with pytest.raises(RecordingError, match=r"\(ending with '/<joint>/velocity'\)") as caught:
        open_csv_chunks(path, (["left"], ["right"]), layout=CsvLayout(field="velocity")).__enter__()
    assert "positions" in str(caught.value)
    path.write_text("t,a,b\n1,2,3\n", "utf-8")  # neither velocities nor positions
    with pytest.raises(RecordingError) as caught:
        open_csv_chunks(path, (["left"], ["right"]), layout=CsvLayout(field="velocity")).__enter__()
    assert "positions" not in str(caught.value)
    assert caught.value.template.endswith(
        "; another robot's recording? give its description ({robot}), or name the columns "
        "({left_column}, {right_column})"
    )


@pytest.mark.parametrize("header", ["t,left,right", "t,/js/left/position,/js/right/position"])
def test_velocities_asked_of_a_file_of_positions_name_the_feedback_to_read_them(
    tmp_path: Path, header: str
) -> None:
    path = tmp_path / "positions.csv"
    path.write_text(f"{header}\n1,2,3\n", "utf-8")
    layout = CsvLayout(field="velocity")
    with pytest.raises(RecordingError) as caught:
        open_csv_chunks(path, (["left"], ["right"]), layout=layout).__enter__()
    assert caught.value.template.endswith(
        "; the file holds the wheels' positions: read them with {feedback} position"
    )


def test_a_file_without_a_time_column_names_the_columns_found(tmp_path: Path) -> None:
    path = tmp_path / "r.csv"
    path.write_text("when,left,right\n1,2,3\n", "utf-8")
    with pytest.raises(
        RecordingError, match=r"no time column .*columns found: 'when', 'left', 'right'"
    ):
        read_all(path)


def test_a_missing_wheel_column_is_named(tmp_path: Path) -> None:
    path = tmp_path / "r.csv"
    path.write_text("t,left\n1,2\n", "utf-8")
    with pytest.raises(RecordingError, match="no column for the right wheel joint 'right'"):
        read_all(path)


def test_a_binary_file_is_not_a_text_csv(tmp_path: Path) -> None:
    path = tmp_path / "r.csv"
    path.write_bytes(b"t,left,right\n1,2,3\n\xff\xfe\x00\x01\n")
    with pytest.raises(RecordingError, match="not a text"):
        read_all(path)


def test_an_empty_file_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "r.csv"
    path.write_text("", "utf-8")
    with pytest.raises(RecordingError, match="empty file"):
        read_all(path)


def test_a_straight_run_ends_at_its_length(tmp_path: Path) -> None:
    path = tmp_path / "r.csv"
    angle = 1.0 / NAMED.wheel_radius  # 1 m of travel
    path.write_text(
        f"time,left,right\n0,0,0\n0.5,{angle / 2!r},{angle / 2!r}\n1,{angle!r},{angle!r}\n"
    )
    summary = csv_odometry(path, NAMED).summary
    assert summary.final_pose.x == pytest.approx(1.0, abs=1e-12)
    assert summary.final_pose.y == 0.0
    assert math.remainder(summary.final_pose.theta, math.tau) == 0.0
    assert summary.duration == 1.0


@pytest.mark.parametrize("first", ["0;0;0", "0;0;", ";0,5;0,5"])
def test_decimal_commas_are_judged_by_the_first_row_with_a_fraction(first: str) -> None:
    # A run that starts at rest, 0;0;0 (or with a cell empty, or no stamp), then goes on in a
    # European spreadsheet's numbers: judged by the first row, which reads alike either way,
    # every later row was skipped as unreadable and the run came out as two samples, exit 0.
    rows = [f"{k / 50:.2f};{k * 0.01:.3f};{k * 0.02:.3f}" for k in range(1, 200)]
    point = "time;left;right\n" + first.replace(",", ".") + "\n" + "\n".join(rows) + "\n"
    comma = "time;left;right\n" + first + "\n" + "\n".join(r.replace(".", ",") for r in rows)

    def read(text: str) -> tuple[list[int], list[list[float]], dict[str, int]]:
        chunks = CsvChunks(io.StringIO(text), (["left"], ["right"]), source="r.csv")
        stamps: list[int] = []
        positions: list[list[float]] = []
        skipped: dict[str, int] = {}
        for chunk in chunks:
            stamps += chunk.stamp_ns.tolist()
            positions += chunk.positions.tolist()
            for reason, count in chunk.skipped.items():
                skipped[reason] = skipped.get(reason, 0) + count
        return stamps, positions, skipped

    expected = read(point)
    assert len(expected[0]) >= 199
    assert read(comma) == expected


def quoted_wide_csv(path: Path, rows: int, columns: int = 200) -> None:
    """A CSV whose first row quotes a cell (so that every row is read with csv), each row with
    ``columns`` more cells of two digits."""
    extra = ",".join(["12"] * columns)
    with path.open("w") as out:
        out.write("time,left,right,note," + ",".join(f"c{i}" for i in range(columns)) + "\n")
        for k in range(rows):
            note = '"x"' if k == 0 else "x"
            out.write(f"{k * 0.01:.2f},{k * 0.001},{k * 0.002},{note},{extra}\n")


def samples_and_peak(path: Path, chunk_bytes: int) -> tuple[int, int]:
    """Samples read from ``path`` and the peak of the memory allocated meanwhile (bytes)."""

    def read() -> int:
        with open_csv_chunks(path, (["left"], ["right"]), chunk_bytes=chunk_bytes) as chunks:
            return sum(chunk.stamp_ns.size for chunk in chunks)

    return peak_bytes(read)


def test_quoted_rows_are_read_in_memory_that_does_not_grow_with_the_file(tmp_path: Path) -> None:
    budget = 1 << 16
    small, large = tmp_path / "small.csv", tmp_path / "large.csv"
    quoted_wide_csv(small, 1000)
    quoted_wide_csv(large, 8000)  # 4.8 MB of text; 1.6 million cells, 100 MB as Python strings
    small_count, small_peak = samples_and_peak(small, budget)
    large_count, large_peak = samples_and_peak(large, budget)
    assert (small_count, large_count) == (1000, 8000)
    # A chunk holds about `budget` characters' rows as samples and one row's cells; the text
    # grows by 4.2 MB from the small file to the large one, the peak by less than the budget.
    assert large_peak - small_peak < budget, (small_peak, large_peak)
    assert large_peak < 2 << 20, large_peak


def test_quoted_rows_come_in_chunks_of_about_the_chunk_size(tmp_path: Path) -> None:
    budget = 1 << 16
    path = tmp_path / "run.csv"
    quoted_wide_csv(path, 1000)
    header, *lines = path.read_text().splitlines(keepends=True)
    longest = max(map(len, lines))
    with open_csv_chunks(path, (["left"], ["right"]), chunk_bytes=budget) as chunks:
        sizes = [(chunk.stamp_ns.size, chunk.chars) for chunk in chunks]
    assert len(sizes) > 5
    assert all(budget <= chars < budget + longest for _, chars in sizes[:-1]), sizes
    assert 0 < sizes[-1][1] < budget + longest
    assert sum(n for n, _ in sizes) == 1000
    assert sum(chars for _, chars in sizes) == path.stat().st_size - len(header)
