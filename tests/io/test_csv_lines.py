"""Lines of a CSV for csv.reader: whole lines, and no row longer than ROW_CHARS."""

from __future__ import annotations

import csv
import io
from pathlib import Path

import pytest
from cli_results import assert_one_error_line
from click.testing import CliRunner
from peak_memory import peak_bytes

from diffbot.cli import main
from diffbot.errors import RecordingError
from diffbot.io.csv_chunks import open_csv_chunks
from diffbot.io.csv_lines import ROW_CHARS, RowLines

HEADER = "time,left,right,note\n"


def rows_of(lines: RowLines) -> list[list[str]]:
    rows = []
    for row in csv.reader(lines):
        lines.row_done()
        rows.append(row)
    return rows


def samples(path: Path) -> int:
    """How many samples the chunks of a file hold."""
    with open_csv_chunks(path, (["left"], ["right"])) as chunks:
        return sum(chunk.stamp_ns.size for chunk in chunks)


def test_the_head_and_the_stream_read_as_one_text() -> None:
    # The head ends in the middle of a line and of a quoted cell that holds a line break.
    text = 'a,b\r\n1,"x\ny",2\n3,4\n'
    for cut in range(len(text) + 1):
        stream = io.StringIO(text[cut:], newline="")
        lines = RowLines(stream, text[:cut], source="s")
        assert rows_of(lines) == [["a", "b"], ["1", "x\ny", "2"], ["3", "4"]], cut
        assert lines.line == 4
        assert lines.chars == len(text)


def test_the_stream_lines_are_transformed_and_the_head_is_not() -> None:
    stream = io.StringIO("1;5\n", newline="")
    lines = RowLines(stream, "0;2,5\n0;", lambda s: s.replace(",", "."), source="s")
    assert list(lines) == ["0;2,5\n", "0;1;5\n"]


def long_row(chars: int, quoted: bool = False) -> str:
    """A row of ``chars`` characters (its line ends included) of two-digit cells; ``quoted``
    spreads it over two lines with a quoted cell holding a line break."""
    start = '1,"a\nb",' if quoted else "1,x,"
    cells = "12," * ((chars - len(start) - 2) // 3)
    return start + cells + "9" * (chars - len(start) - len(cells) - 1) + "\n"


@pytest.mark.parametrize("quoted", [False, True])
def test_a_row_as_long_as_the_bound_is_read(quoted: bool) -> None:
    row = long_row(ROW_CHARS, quoted)
    assert len(row) == ROW_CHARS
    lines = RowLines(io.StringIO("a,b\n" + row + "2,y\n", newline=""), source="s")
    assert [len(r) for r in rows_of(lines)] == [2, row.count(",") + 1, 2]
    assert lines.line == 3 + quoted


@pytest.mark.parametrize("quoted", [False, True])
def test_a_row_one_character_too_long_is_refused_by_its_first_line(quoted: bool) -> None:
    # A quoted cell spreads the row over two lines: the row is counted, not each line.
    stream = io.StringIO("a,b\n\n0,1\n" + long_row(ROW_CHARS + 1, quoted) + "2,3\n", newline="")
    with pytest.raises(RecordingError, match=r"^s: line 4: a row longer than 4194304 characters"):
        rows_of(RowLines(stream, source="s"))


def test_a_long_row_is_refused_before_it_is_held(tmp_path: Path) -> None:
    path = tmp_path / "wide.csv"
    with path.open("w") as out:
        out.write(HEADER + "0,1,2,x\n")
        out.write("1,1,2," + "12," * (4 * ROW_CHARS // 3) + "x\n")  # 16 MiB, 5.6 million cells

    def refused() -> None:
        with pytest.raises(RecordingError, match="line 3: a row longer than"):
            samples(path)

    _, peak = peak_bytes(refused)
    # The text of at most one bound's worth of the row (4 bytes a character at worst), never
    # its cells (300 MB as Python strings).
    assert peak < 4 * ROW_CHARS + (8 << 20), peak


def test_a_long_header_is_refused_too(tmp_path: Path) -> None:
    path = tmp_path / "wide.csv"
    path.write_text("time,left,right," + "c," * ROW_CHARS + "\n0,1,2\n")
    with pytest.raises(RecordingError, match="line 1: a row longer than"):
        open_csv_chunks(path, (["left"], ["right"])).__enter__()


def test_odom_of_a_long_row_is_one_error_line(tmp_path: Path) -> None:
    path = tmp_path / "wide.csv"
    header = "time,front_left_wheel_joint,front_right_wheel_joint,note\n"
    path.write_text(header + '0,0,0,"x"\n' + "1,1,2," + "12," * ROW_CHARS + "\n2,2,3,x\n")
    result = CliRunner().invoke(main, ["odom", str(path)])
    assert_one_error_line(result, f"{path}: line 3: a row longer than 4194304 characters")
