"""The path types of the commands: what they read and where they write.

The input/output guard of :mod:`diffbot.io.outputs` learns a run's inputs from these types only:
click converts every option and argument of an :class:`InputPath` type while it parses the
command line, before the command runs, and the conversion notes the path as an input of the run
(:func:`diffbot.io.outputs.note_input`). No word of the command line is taken for a path unless
click parsed it as one, or a command took one of its arguments for a file (:func:`input_path`,
through the same type). Every output option is an :class:`OutputPath`, checked by
:mod:`diffbot.io.outputs`, which keeps outputs off every noted input. A file a command writes a
changed copy of is an :class:`EditedPath`: an input whose name is checked as an output's, since
the copy's name is made from it. Every name that stands for no file or folder of its own (empty,
``.``, ``/``, ``x.csv/.``) is refused here, as click parses it, by
:func:`diffbot.io.outputs.check_output_name`.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import click

from diffbot.commands.messages import fail
from diffbot.commands.option_groups import F, option_group
from diffbot.errors import DiffbotError
from diffbot.io.outputs import check_output_name, input_clash, note_input, note_stdin
from diffbot.io.pathnames import resolved

__all__ = [
    "OUTPUT_NAMES",
    "EditedPath",
    "InputPath",
    "OutOptions",
    "OutputPath",
    "PackageDir",
    "check_out",
    "input_path",
    "named_output",
    "out_options",
    "output_option",
]


class InputPath(click.Path):
    """A file or folder a command reads (``-`` for stdin where ``allow_dash``).

    Converting it notes it as an input of the run, so that no output goes over it, inside it or
    around it, and turns a path that cannot be resolved (a loop of symbolic links) into one
    error line. The checks of :class:`click.Path` (``exists``, ``dir_okay``, ...) apply after.
    """

    def __init__(
        self,
        *,
        exists: bool = False,
        file_okay: bool = True,
        dir_okay: bool = True,
        allow_dash: bool = False,
    ) -> None:
        super().__init__(
            exists=exists, file_okay=file_okay, dir_okay=dir_okay, allow_dash=allow_dash
        )

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> Any:
        text = os.fspath(value) if isinstance(value, os.PathLike) else str(value)
        if param is not None and not text.strip():
            self.fail(f"{text!r}: an empty name, not a file or folder name", param, ctx)
        if text.strip() and not (self.allow_dash and text == "-"):
            try:
                resolved(text)
            except DiffbotError as err:
                if param is None:  # an argument a command took for a path: no option to name
                    fail(str(err))
                self.fail(str(err), param, ctx)
            note_input(text)
        elif text == "-":
            note_stdin()
        return super().convert(text, param, ctx)


class EditedPath(InputPath):
    """A file a command reads to write a changed copy of it, beside it under a name made from
    its own (``robot.urdf`` -> ``robot.calibrated.urdf``) unless the output option names the
    copy: an input, whose name must name a file as an output's must (no ``.``, ``/``, empty
    name, or name ending in a slash or ``/.``)."""

    def __init__(self) -> None:
        super().__init__(dir_okay=False)

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> Any:
        text = os.fspath(value) if isinstance(value, os.PathLike) else str(value)
        checked_name(text, _shown(param), source=True)
        return super().convert(text, param, ctx)


def _shown(param: click.Parameter | None, default: str = "-o/--out") -> str:
    """The option's names, as messages give them (``-o/--out`` for the output option)."""
    if param is None or not param.opts:
        return default
    if tuple(param.opts) == OUTPUT_NAMES:
        return "-o/--out"
    return "/".join(param.opts)


#: A file or folder read, as a command's own arguments name one (see :func:`input_path`).
INPUT = InputPath(allow_dash=True)


def input_path(token: str) -> str:
    """Note a positional argument a command has taken for a file or folder it reads (a robot
    description, a plan file, a recording) as the path types note theirs: an input of the run.

    Raises:
        InputError: the path cannot be resolved (a loop of symbolic links).
    """
    converted: str = INPUT.convert(token, None, click.get_current_context(silent=True))
    return converted


class PackageDir(click.ParamType):  # type: ignore[type-arg,unused-ignore]
    """``NAME=DIR``: the folder of a ROS package, for ``$(find NAME)``.

    The folder is searched, not read whole: only the files the description reads from it are
    inputs (noted as they are read), so an output may still go into a package's folder.
    """

    name = "NAME=DIR"

    def convert(
        self, value: Any, param: click.Parameter | None, ctx: click.Context | None
    ) -> tuple[str, str]:
        if isinstance(value, tuple):
            return value
        text = str(value)
        name, sep, directory = text.partition("=")
        if not sep or not name or not directory:
            fail(f"--package {text!r}: expected NAME=DIR")
        try:
            folder = resolved(directory)
        except DiffbotError as err:
            fail(f"--package {text!r}: {err}")
        if not folder.is_dir():
            fail(f"--package {text!r}: {directory} is not a directory")
        return name, directory


class OutputPath(click.ParamType):  # type: ignore[type-arg,unused-ignore]
    """Where a command writes: a file (a name that asks for a folder is refused, see
    :func:`diffbot.io.outputs.check_output_name`) or, where ``folder_ok``, a file, a bag or a
    folder that gets one output per input: only an empty name is refused as click parses it,
    and the rest once the command knows which (:func:`named_output`). Written through
    :mod:`diffbot.io.outputs`, which keeps it off every input of the run."""

    name = "path"

    def __init__(self, *, folder_ok: bool = False) -> None:
        self.folder_ok = folder_ok

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> str:
        text = os.fspath(value) if isinstance(value, os.PathLike) else str(value)
        checked_name(text, _shown(param), holder=self.folder_ok)
        return text


#: The one output option of every command that writes, in its three spellings.
OUTPUT_NAMES = ("-o", "--output", "--out")


def checked_name(
    text: str, option: str, *, folder: bool = False, source: bool = False, holder: bool = False
) -> None:
    """Bad input, one line naming ``option``, when ``text`` names no output of its own (see
    :func:`diffbot.io.outputs.check_output_name`, which ``folder``, ``source`` and ``holder``
    are passed to): the one check of the names of outputs and of the files whose copies are
    written."""
    try:
        check_output_name(text, folder=folder, source=source, holder=holder)
    except DiffbotError as err:
        fail(f"{option} {err}")


def named_output(value: str | None, *, bag: bool = False, option: str = "-o/--out") -> str | None:
    """``value`` unless it names no output of its own: for a file (a trailing slash, ``/.`` or
    ``/..``, the root, or an empty name: the file would appear under another name than the one
    asked for), or with ``bag`` for a bag (``.``, ``..`` or the root: a folder that exists,
    which the bag would replace). An output option that may name a folder is checked only for
    an empty name as click parses it, and here once the command knows what it writes."""
    if value is not None:
        checked_name(value, option, folder=bag)
    return value


def output_option(
    help_text: str, *, metavar: str = "FILE", dest: str = "output"
) -> Callable[[F], F]:
    """The output option, ``-o``, ``--output`` or ``--out`` alike, received as ``dest``
    (a file: a name that asks for a folder is refused; any other ``metavar`` may also name a
    folder, as ``--out`` of :func:`out_options` a bag)."""
    return click.option(
        *OUTPUT_NAMES,
        dest,
        type=OutputPath(folder_ok=metavar != "FILE"),
        metavar=metavar,
        help=help_text,
    )


def check_out(out: str | None, inputs: Sequence[Path], force: bool) -> Path | None:
    """The --out path, refused early when it exists (without --force), or is, holds or lies
    inside an input (compared as resolved paths, links followed). Its name was checked as click
    parsed it (:class:`OutputPath`)."""
    if out is None:
        return None
    path = Path(out)
    clash = input_clash(path, inputs)
    if clash is not None:
        relation, given = clash
        if relation == "inside":
            fail(f"--out {out} lies inside the input {given}: inputs are never modified")
        what = "is the input" if relation == "is" else "contains the input"
        fail(f"--out {out} {what} {given}: inputs are never overwritten")
    if (path.exists() or path.is_symlink()) and not force:
        fail(f"{out} exists: use --force to overwrite it")
    return path


@dataclass(frozen=True)
class OutOptions:
    """Where a command writes its samples: ``--out`` (a CSV file or, with ``--bag``, a rosbag2
    directory) and ``--force``."""

    out: str | None
    as_bag: bool
    force: bool

    def path(self, inputs: Sequence[Path]) -> Path | None:
        """The --out path of one output, checked early against ``inputs`` (see
        :func:`check_out`); a file's name may not ask for a folder."""
        named_output(self.out, bag=self.as_bag)
        return check_out(self.out, inputs, self.force)

    def require_out_for_bag(self) -> None:
        """Bad input when --bag is given without --out."""
        if self.as_bag and self.out is None:
            fail("--bag writes the --out directory: give --out DIR")


def out_options(out_help: str, bag_help: str) -> Callable[[F], F]:
    """Add the output option, ``--bag`` and ``--force``; the command receives
    ``out: OutOptions``."""
    options = [
        output_option(out_help, metavar="PATH", dest="out"),
        click.option("--bag", "as_bag", is_flag=True, help=bag_help),
        click.option("--force", is_flag=True, help="Overwrite --out if it exists."),
    ]

    return option_group(
        options, "out", lambda kw: OutOptions(kw.pop("out"), kw.pop("as_bag"), kw.pop("force"))
    )
