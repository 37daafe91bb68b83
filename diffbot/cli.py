"""The ``diffbot`` command line: a thin layer over the library.

Exit codes: 0 success, 1 a result that fails a check (a wheel over the motor limit), 2 bad input or
usage. Errors are one line on stderr starting with ``error:``; machine output goes to stdout.

Each command lives in a module of :mod:`diffbot.commands`, loaded only when it runs (or when the
help lists it), so that a quick command pays for nothing it does not use.
"""

from __future__ import annotations

import importlib
import os
import signal
import sys
import threading
from collections.abc import Sequence
from typing import Any, NoReturn

import click

from diffbot import signal_handlers
from diffbot.commands.groups import SuggestingGroup
from diffbot.commands.said_once import with_quiet
from diffbot.errors import DiffbotError
from diffbot.io.outputs import guarded_run
from diffbot.numbers import shorten_numerals

#: Each command's module and function, in the order ``diffbot --help`` lists them.
COMMANDS = {
    "params": "diffbot.commands.robot:params",
    "urdf": "diffbot.commands.robot:urdf",
    "ik": "diffbot.commands.robot:ik",
    "fk": "diffbot.commands.robot:fk",
    "check": "diffbot.commands.check:check",
    "plan": "diffbot.commands.plan:plan_command",
    "odom": "diffbot.commands.odom:odom",
    "simulate": "diffbot.commands.simulate:simulate",
    "plot": "diffbot.commands.plot:plot",
    "explain": "diffbot.commands.explain:explain",
    "calibrate": "diffbot.commands.calibrate:calibrate",
    "node": "diffbot.commands.node:node",
    "drive": "diffbot.commands.drive:drive",
}

#: How the command line spells a library parameter named in an error message.
FLAGS = {
    "force": "--force",
    "left_joint": "--left-joint",
    "right_joint": "--right-joint",
    "wheel_radius": "--wheel-radius",
    "wheel_separation": "--wheel-separation",
    "max_wheel_speed": "--max-rpm",
    "packages": "--package",
    "trust": "--trust",
    "controllers": "--controllers",
    "controller": "--controller",
    "no_controllers": "--no-controllers",
    "window": "--window",
    "window_duration": "--window-duration",
    "max_relative_stderr": "--max-stderr",
    "min_radius": "--min-radius",
    "forward_only": "--forward-only",
    "topic": "--topic",
    "time_column": "--time-column",
    "left_column": "--left-column",
    "right_column": "--right-column",
    "delimiter": "--delimiter",
    "time_unit": "--time-unit",
    "time_offset": "--time-offset",
    "dask_address": "--dask",
    "dask_timeout": "--dask-timeout",
    "wrap": "--wrap",
    "counts_per_rev": "--counts-per-rev",
    "feedback": "--feedback",
    "open_loop": "--open-loop",
    "left_topic": "--left-topic",
    "right_topic": "--right-topic",
    "lead": "--lead",
    "robot": "--robot PATH",
}


#: Signals that end a run as Ctrl-C does: by an exception, so that temporary files are removed.
#: Ctrl-C itself raises KeyboardInterrupt, which click turns into its Abort.
_ENDING_SIGNALS = tuple(s for s in signal_handlers.ENDING_SIGNALS if s != signal.SIGINT)


def _end_run(signum: int, frame: object) -> None:
    raise SystemExit(128 + signum)  # the exit status of a process the signal ended


#: The commands that run nodes: they take ending signals themselves, from the node's making on
#: (:func:`diffbot.live.signals.deferred`), and hold them until then, so that none raises inside
#: the DDS library's import or setup; one held acts there, before the node is made.
_TAKE_SIGNALS_THEMSELVES = frozenset({"node", "drive"})


class _PipeClosedError(Exception):
    """The reader of stdout went away (click would turn the EPIPE into exit code 1)."""


class DiffbotGroup(SuggestingGroup):
    """The command group: loads commands on demand and turns every error into one ``error:``
    line and an exit code."""

    def list_commands(self, ctx: click.Context) -> list[str]:
        return list(COMMANDS)

    def get_command(self, ctx: click.Context, cmd_name: str) -> click.Command | None:
        target = COMMANDS.get(cmd_name)
        if target is None:
            return None
        module, _, name = target.partition(":")
        command = getattr(importlib.import_module(module), name)
        assert isinstance(command, click.Command)
        return with_quiet(command)

    def resolve_command(
        self, ctx: click.Context, args: list[str]
    ) -> tuple[str | None, click.Command | None, list[str]]:
        name, command, rest = super().resolve_command(ctx, args)
        if name not in _TAKE_SIGNALS_THEMSELVES:
            # Signals held while the command line loaded end here: one that came acts now, as
            # it would have then (Ctrl-C aborts, SIGTERM ends the run).
            signal_handlers.act_on_held()
        return name, command, rest

    def invoke(self, ctx: click.Context) -> Any:
        try:
            result = super().invoke(ctx)
            sys.stdout.flush()
        except BrokenPipeError:
            raise _PipeClosedError from None
        return result

    def main(
        self,
        args: Sequence[str] | None = None,
        prog_name: str | None = None,
        complete_var: str | None = None,
        standalone_mode: bool = True,
        **extra: Any,
    ) -> Any:
        if sys.stdout is None:  # started with stdout closed (``>&-``)
            _error("standard output is closed: nowhere to write the results", 2)
        ending = _ENDING_SIGNALS if threading.current_thread() is threading.main_thread() else ()
        saved = signal_handlers.install(ending, _end_run)
        try:
            # The inputs are noted as click converts the arguments of path types, and as the
            # readers open files: all within the guarded run.
            with guarded_run():
                code = self._run(args, prog_name, complete_var, **extra)
        finally:
            # The exit code is decided (an error's too) and the outputs are written: a signal
            # while the interpreter shuts down (which puts back the default actions that end a
            # process) must not turn that into a death by the signal; nor one still held.
            signal_handlers.release()
            signal_handlers.settle(saved, (signal.SIGINT,) if ending else ())
        if not standalone_mode:
            return code
        sys.exit(code if isinstance(code, int) else 0)

    def _run(
        self,
        args: Sequence[str] | None,
        prog_name: str | None,
        complete_var: str | None,
        **extra: Any,
    ) -> Any:
        try:
            code = super().main(args, prog_name, complete_var, standalone_mode=False, **extra)
        except click.exceptions.NoArgsIsHelpError as err:
            click.echo(err.ctx.get_help() if err.ctx else err.format_message())
            code = 0
        except click.UsageError as err:
            hint = ""
            if err.ctx is not None:
                hint = f" (see '{err.ctx.command_path} --help')"
            _error(f"{err.format_message()}{hint}", err.exit_code)
        except click.ClickException as err:
            _error(err.format_message(), err.exit_code)
        except DiffbotError as err:
            _error(err.render(FLAGS.__getitem__), err.exit_code)
        except click.Abort:
            _error("aborted", 130)
        except RuntimeError as err:  # click.Abort is one too: it comes first
            ending = _signal_behind(err)
            if ending is None:
                raise
            if isinstance(ending, KeyboardInterrupt):
                _error("aborted", 130)
            raise ending from None
        except (BrokenPipeError, _PipeClosedError):
            # The reader went away (``| head``): exit as a process killed by SIGPIPE would.
            _drop_stdout()
            sys.exit(128 + 13)
        except OSError as err:
            _flush_or_drop_stdout()
            _error(f"{err.filename + ': ' if err.filename else ''}{err.strerror or err}", 2)
        except MemoryError:
            _flush_or_drop_stdout()
            _error("out of memory: an input holds more than this machine can read at once", 2)
        return code


def _signal_behind(err: BaseException) -> BaseException | None:
    """The exit a signal's handler raised (:func:`_end_run`, or Python's KeyboardInterrupt)
    that ``err`` wraps, if any: Python 3.11 wraps what ``__set_name__`` raises, as during the
    making of a class in an import the command does on demand, in a RuntimeError."""
    seen: set[int] = set()
    cause = err.__cause__
    while cause is not None and id(cause) not in seen:
        if isinstance(cause, (SystemExit, KeyboardInterrupt)):
            return cause
        seen.add(id(cause))
        cause = cause.__cause__
    return None


def _drop_stdout() -> None:
    """Point stdout at /dev/null, so that the flush at exit of what it still holds cannot fail
    again (and print a traceback and exit 120)."""
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, sys.stdout.fileno())
    os.close(devnull)


def _flush_or_drop_stdout() -> None:
    """Write out what stdout holds, or drop it when stdout cannot take it (a full disk)."""
    try:
        sys.stdout.flush()
    except OSError:
        _drop_stdout()


#: Longest error line shown (characters): a name of megabytes (a crafted link, a key) is cut
#: in its middle, so that the line stays one a person can read.
_LONGEST_ERROR = 2000


def _error(message: str, code: int) -> NoReturn:
    text = shorten_numerals(" ".join(str(message).split()))
    if len(text) > _LONGEST_ERROR:
        half = _LONGEST_ERROR // 2
        text = f"{text[:half]} [... {len(text) - 2 * half} characters ...] {text[-half:]}"
    click.echo(f"error: {text}", err=True)
    sys.exit(code)


def run() -> None:
    """The command line (``diffbot``, ``python -m diffbot``, through :func:`diffbot.__main__.run`,
    which holds the signals first): one command, then the process ends."""
    signal_handlers.process_ends_with_run()
    main(prog_name="diffbot")


@click.group(
    cls=DiffbotGroup,
    context_settings={"help_option_names": ["-h", "--help"], "max_content_width": 100},
)
@click.version_option(package_name="diffbot-kinematics", prog_name="diffbot")
def main() -> None:
    """Kinematics, odometry and motion plans for differential-drive robots.

    Robot parameters (wheel radius, separation, joints, motor limit) come from a URDF/xacro
    description; the default is the bundled diffbot (r = 0.035 m, b = 0.135 m, 50 rpm). SI units
    inside; rpm and degrees only where labelled.

    \b
    Examples:
      diffbot params                          the bundled robot's parameters
      diffbot params docs/examples/tutorial_bot/tutorial_bot.urdf
      diffbot ik 0.1 0.5                      wheel speeds for v = 0.1 m/s, w = 0.5 rad/s
      diffbot fk 2.86 2.86                    body velocity from wheel speeds (rad/s)
    """
