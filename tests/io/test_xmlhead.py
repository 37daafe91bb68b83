"""The root element of an XML text past its prolog, found in time linear in the text."""

from __future__ import annotations

import time

import pytest

from diffbot.io.xmlhead import prolog_end, root_name


@pytest.mark.parametrize(
    ("text", "root"),
    [
        ("<robot/>", "robot"),
        ('  <?xml version="1.0"?>\n<robot name="r">', "robot"),
        ("<!-- a --><!-- b -->\n<?pi x?><sdf version='1.9'>", "sdf"),
        ('<!DOCTYPE robot SYSTEM "r.dtd">\n<xs:robot>', "robot"),
        ("<a:>", "a"),
        ("<a.b-c_1 x='1'>", "a.b-c_1"),
    ],
)
def test_the_root_is_named_past_declarations_comments_instructions_and_doctypes(
    text: str, root: str
) -> None:
    assert root_name(text) == root


@pytest.mark.parametrize(
    "text", ["", "plain text", "<!-- never closed <robot>", "<?xml <robot>", "<!DOCTYPE", "<1a>"]
)
def test_no_root_when_the_text_does_not_start_with_an_element(text: str) -> None:
    assert root_name(text) is None


def test_the_prolog_ends_where_the_root_starts() -> None:
    text = '<?xml version="1.0"?>\n<!-- -->\t<robot/>'
    end = prolog_end(text)
    assert end is not None
    assert text[end:] == "<robot/>"


def test_thousands_of_comments_are_skipped_at_once() -> None:
    # a backtracking (<!--.*?-->\s*)* tries every grouping of them: minutes at 30 comments
    text = "<!-- banner -->\n" * 20_000 + "<robot/>"
    start = time.process_time()
    assert root_name(text) == "robot"
    assert root_name(text.replace("<robot/>", "not xml")) is None
    assert time.process_time() - start < 2.0
