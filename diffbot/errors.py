"""The errors diffbot raises: one hierarchy under :class:`DiffbotError`.

Every message is a complete sentence fragment fit for one line of a terminal. An error knows its
exit code (2: bad input; 1: a result that fails a check) and carries structured fields (the path,
the offending value, candidate joints) for programs that want more than the text.

A message that tells the user which setting to change names it as a marker such as ``{force}``
or ``{wheel_radius}``: ``str(error)`` spells it as the library parameter (``force=True``), and
the command line spells it as its option (``--force``) through :meth:`DiffbotError.render`.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any, ClassVar

#: Exit code of bad input or usage.
EXIT_BAD_INPUT = 2
#: Exit code of a result that fails a check (for example a wheel over the motor limit).
EXIT_CHECK_FAILED = 1

#: The parameters a message may name as a ``{name}`` marker, with their spelling in the library.
PARAMETERS: Mapping[str, str] = {
    "force": "force=True",
    "left_joint": "left_joint=",
    "right_joint": "right_joint=",
    "wheel_radius": "wheel_radius=",
    "wheel_separation": "wheel_separation=",
    "max_wheel_speed": "max_wheel_speed=",
    "packages": "packages:",
    "trust": "trust=True",
    "controllers": "controllers=",
    "controller": "controller=",
    "no_controllers": "no_controllers=True",
    "window": "window=",
    "window_duration": "window_duration=",
    "max_relative_stderr": "max_relative_stderr=",
    "min_radius": "min_radius=",
    "forward_only": "forward_only=True",
    "topic": "topic=",
    "time_column": "time_column=",
    "left_column": "left_column=",
    "right_column": "right_column=",
    "delimiter": "delimiter=",
    "time_unit": "time_unit=",
    "time_offset": "time_offset=",
    "dask_address": "dask_address=",
    "dask_timeout": "dask_timeout=",
    "wrap": "wrap=",
    "counts_per_rev": "counts_per_rev=",
    "feedback": "feedback=",
    "open_loop": "open_loop=True",
    "left_topic": "left_topic=",
    "right_topic": "right_topic=",
    "robot": "params=load_params(PATH)",
}

__all__ = [
    "EXIT_BAD_INPUT",
    "EXIT_CHECK_FAILED",
    "PARAMETERS",
    "CalibrationError",
    "DescriptionError",
    "DiffbotError",
    "DriveWheelError",
    "ExpansionLimitError",
    "NotDifferentialError",
    "OutputError",
    "OutputExistsError",
    "OutsideRootsError",
    "PackageNotFoundError",
    "ParameterError",
    "PathError",
    "PlanError",
    "RecordingError",
    "RefusedExpressionError",
    "SandboxError",
    "XacroError",
]


class DiffbotError(Exception):
    """Base of every error raised by diffbot for bad input.

    Args:
        message: the message; ``{name}`` markers for the names in :data:`PARAMETERS`.
        **fields: structured details (``path``, ``value``, ``candidates``, ...), kept in
            :attr:`fields`.
    """

    exit_code: ClassVar[int] = EXIT_BAD_INPUT

    def __init__(self, message: str, **fields: Any) -> None:
        super().__init__(message)
        self.template = message
        self.fields: dict[str, Any] = fields

    def render(self, spell: Callable[[str], str]) -> str:
        """The message with each parameter marker spelled by ``spell(name)``."""
        text = self.template
        if "{" in text:
            for name in PARAMETERS:
                text = text.replace("{" + name + "}", spell(name))
        return text

    def __str__(self) -> str:
        return self.render(PARAMETERS.__getitem__)


class ParameterError(DiffbotError, ValueError):
    """A number is out of its domain: NaN, infinite, zero or negative where it must be positive."""


class DescriptionError(DiffbotError):
    """A robot description cannot be read, expanded or understood."""


class XacroError(DescriptionError):
    """xacro failed to expand a description (bad macro, missing argument, bad expression)."""


class PackageNotFoundError(DescriptionError):
    """A ``$(find PKG)`` or ``package://PKG`` refers to a package that is not known."""


class SandboxError(DescriptionError):
    """An untrusted description tried something the sandbox does not allow, or grew too large."""


class RefusedExpressionError(SandboxError):
    """An expression uses something outside the sandbox (a name, call, attribute or size)."""


class OutsideRootsError(SandboxError):
    """An untrusted description tried to read a file outside its own folders and packages."""


class ExpansionLimitError(SandboxError):
    """An expansion went over its limit of text, elements or nesting depth."""


class DriveWheelError(DescriptionError):
    """No drive wheels, or more than two without a way to choose, or a wheel without a radius."""


class NotDifferentialError(DescriptionError):
    """The robot is no differential drive: its wheels steer, or it runs a steering, mecanum or
    omnidirectional controller."""


class PathError(DiffbotError):
    """A path cannot be resolved: a loop of symbolic links, a name too long, no permission."""


class PlanError(DiffbotError):
    """A plan is malformed or cannot be executed (bad segment, unknown unit, zero limit)."""


class RecordingError(DiffbotError):
    """A recording (CSV, rosbag2) cannot be read or holds no usable sample."""


class OutputError(DiffbotError):
    """An output cannot be written where it was asked for (it is an input, not a file, ...)."""


class OutputExistsError(OutputError):
    """An output file exists and overwriting it was not asked for."""


class CalibrationError(RecordingError):
    """Calibration data cannot determine the robot (too little motion, errors too large)."""
