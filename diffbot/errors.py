"""The errors diffbot raises: one hierarchy under :class:`DiffbotError`.

Every message is a complete sentence fragment fit for one line of a terminal, so callers (the CLI
among them) can show ``str(error)`` as it is.
"""

from __future__ import annotations

__all__ = [
    "DescriptionError",
    "DiffbotError",
    "DriveWheelError",
    "OutputExistsError",
    "PackageNotFoundError",
    "ParameterError",
    "PlanError",
    "RecordingError",
    "XacroError",
]


class DiffbotError(Exception):
    """Base of every error raised by diffbot for bad input."""


class ParameterError(DiffbotError, ValueError):
    """A number is out of its domain: NaN, infinite, zero or negative where it must be positive."""


class DescriptionError(DiffbotError):
    """A robot description cannot be read, expanded or understood."""


class XacroError(DescriptionError):
    """xacro failed to expand a description (bad macro, missing argument, bad expression)."""


class PackageNotFoundError(DescriptionError):
    """A ``$(find PKG)`` or ``package://PKG`` refers to a package that is not known."""


class DriveWheelError(DescriptionError):
    """No drive wheels, or more than two without a way to choose, or a wheel without a radius."""


class PlanError(DiffbotError):
    """A plan is malformed or cannot be executed (bad segment, unknown unit, zero limit)."""


class RecordingError(DiffbotError):
    """A recording (CSV, rosbag2) cannot be read or holds no usable sample."""


class OutputExistsError(DiffbotError):
    """An output file exists and overwriting it was not asked for."""
