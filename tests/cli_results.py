"""What a CLI test checks of a run that met bad input."""

from __future__ import annotations

from click.testing import Result


def assert_one_error_line(result: Result, *fragments: str, code: int = 2) -> None:
    """Exit ``code``, one ``error:`` line on stderr holding every fragment, no traceback."""
    assert result.exit_code == code, result.output
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1, result.stderr
    assert lines[0].startswith("error: ")
    for fragment in fragments:
        assert fragment in lines[0], lines[0]
    assert "Traceback" not in result.output
