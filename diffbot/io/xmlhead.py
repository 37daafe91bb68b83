"""Where an XML text's root element starts, found by plain string searches.

The prolog before the root (declaration, processing instructions, comments, a doctype, blanks)
is skipped left to right, each part once, so the time grows with the text only; a pattern such
as ``(<!--.*?-->\\s*)*`` would instead try every way of splitting the comments between its
repetitions before it gives up on a file that is not what it looks for.
"""

from __future__ import annotations

import string

__all__ = ["prolog_end", "root_name"]

_NAME_START = frozenset(string.ascii_letters + "_")
_NAME_CHARS = _NAME_START | frozenset(string.digits + ".-")
#: Openings of the parts of a prolog, with what closes each.
_PARTS = (("<!--", "-->"), ("<?", "?>"), ("<!DOCTYPE", ">"))


def prolog_end(text: str) -> int | None:
    """Index in ``text`` just past its prolog (where its root element should start); None when
    a comment, processing instruction or doctype of the prolog is never closed."""
    position, size = 0, len(text)
    while True:
        while position < size and text[position].isspace():
            position += 1
        for opening, closing in _PARTS:
            if text.startswith(opening, position):
                end = text.find(closing, position + len(opening))
                if end < 0:
                    return None
                position = end + len(closing)
                break
        else:
            return position


def _name_end(text: str, start: int) -> int:
    """End of the (ASCII) XML name starting at ``start``; ``start`` when there is none."""
    if start >= len(text) or text[start] not in _NAME_START:
        return start
    end = start + 1
    while end < len(text) and text[end] in _NAME_CHARS:
        end += 1
    return end


def root_name(text: str) -> str | None:
    """The name of the root element of an XML text, without its namespace prefix; None when
    the text, past its prolog, does not start with an element."""
    start = prolog_end(text)
    if start is None or not text.startswith("<", start):
        return None
    end = _name_end(text, start + 1)
    if end == start + 1:
        return None
    if text.startswith(":", end) and (local := _name_end(text, end + 1)) > end + 1:
        return text[end + 1 : local]
    return text[start + 1 : end]
