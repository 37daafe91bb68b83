"""How commands stop and speak: bad-input errors, warnings, and machine output."""

from __future__ import annotations

import difflib
import json
from typing import Any, NoReturn

import click

from diffbot.commands.said_once import quieted
from diffbot.errors import EXIT_BAD_INPUT
from diffbot.numbers import shorten_numerals

__all__ = ["InputError", "emit_json", "fail", "no_such_option", "warn"]


class InputError(click.ClickException):
    """Bad input found by a command: reported as ``error: ...`` with exit code 2."""

    exit_code = EXIT_BAD_INPUT


def fail(message: str) -> NoReturn:
    """Stop the command with a bad-input error."""
    raise InputError(message)


def no_such_option(token: str) -> NoReturn:
    """Stop with click's own usage error for an unknown option (the one click gives when it
    parses the options itself, with the ``--help`` hint), suggesting the command's closest
    option names. For commands that let unknown options through as (negative number)
    arguments."""
    ctx = click.get_current_context(silent=True)
    names = [] if ctx is None else [name for p in ctx.command.params for name in p.opts]
    close = difflib.get_close_matches(token.partition("=")[0], [n for n in names if n[:1] == "-"])
    raise click.NoSuchOption(token, possibilities=close, ctx=ctx)


def warn(message: str) -> None:
    """Tell the user something on stderr, on one line; nothing when ``-q/--quiet`` is given."""
    if quieted():
        return
    click.echo(f"warning: {shorten_numerals(' '.join(message.split()))}", err=True)


def emit_json(data: Any) -> None:
    """Print machine-readable output (strict JSON: no NaN), or a bad-input error when a result
    is not finite (inputs checked at the boundary should leave none)."""
    try:
        text = json.dumps(data, indent=2, allow_nan=False)
    except ValueError:
        fail("a result is infinite or NaN: the inputs are too large to compute with")
    click.echo(text)
