"""The lines of a CSV as :func:`csv.reader` takes them, a row at a time within a bound.

:func:`csv.reader` holds a row whole, as a list of cells, and a line whole before it splits it:
a row of millions of cells takes gigabytes. :class:`RowLines` hands the reader whole lines read
with a bound on their length, counts the characters since the row began, and refuses a row
longer than :data:`ROW_CHARS` by its line number before the reader holds it.
"""

from __future__ import annotations

import io
from collections.abc import Callable, Iterator
from typing import Final, TextIO

from diffbot.errors import RecordingError

__all__ = ["ROW_CHARS", "RowLines"]

#: Longest row read (characters, line ends included): 4 MiB. A recording's row, even one of a
#: tool that exports every field of every topic, holds thousands of cells, some ten kilobytes.
#: The cells of a row this long take about 85 MB as Python strings (4 MiB of two-digit cells,
#: 1.4 million of them): such a row took ``diffbot odom`` from 50 MB to 160 MB at its peak, and
#: one of 16 MiB to 480 MB.
ROW_CHARS: Final = 1 << 22


class RowLines:
    """Whole lines for :func:`csv.reader`: ``head`` (text already read, its last line perhaps
    unfinished), then the lines of ``stream`` as ``transform`` makes them.

    Call :meth:`row_done` after each row the reader gives.

    Args:
        stream: the text that follows ``head`` (opened with ``newline=""``).
        head: text read before, already transformed.
        transform: what each line read from ``stream`` becomes (decimal commas made points).
        source: the input's name in messages.
        line: the lines before ``head`` (their count).

    Attributes:
        line: the number of the last line given (from 1).
        chars: characters given so far.

    Raises:
        RecordingError: (when iterated) a row longer than :data:`ROW_CHARS`.
    """

    def __init__(
        self,
        stream: TextIO,
        head: str = "",
        transform: Callable[[str], str] = str,
        *,
        source: str,
        line: int = 0,
    ) -> None:
        self._stream = stream
        self._put_back(head)
        self._transform = transform
        self._source = source
        self.line = line
        self.chars = 0
        self._row_chars = 0
        self._row_line = line + 1

    def __iter__(self) -> Iterator[str]:
        return self

    def __next__(self) -> str:
        room = ROW_CHARS + 1 - self._row_chars  # one character beyond the bound tells it
        text = self._head.readline(room)
        if len(text) < room and self._head.tell() == self._head_end and not text.endswith("\n"):
            # The head is used up, its last line perhaps unfinished: the stream goes on with it.
            more = self._transform(self._stream.readline(room - len(text)))
            if text.endswith("\r") and not more.startswith("\n"):
                self._put_back(more)  # the head ended a line; "\r\n" would have been one end
            else:
                text += more
        if not text:
            raise StopIteration
        self.line += 1
        self.chars += len(text)
        self._row_chars += len(text)
        if self._row_chars > ROW_CHARS:
            raise RecordingError(
                f"{self._source}: line {self._row_line}: a row longer than {ROW_CHARS} "
                f"characters ({ROW_CHARS >> 20} MiB): too long for a recording's row"
            )
        return text

    def _put_back(self, text: str) -> None:
        """Read ``text`` before the rest of the stream."""
        self._head = io.StringIO(text, newline="")
        self._head_end = len(text)

    def row_done(self) -> None:
        """The reader gave a row: the next line starts another."""
        self._row_chars = 0
        self._row_line = self.line + 1
