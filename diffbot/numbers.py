"""Reading numbers from callers and files: one conversion and one range check, each error naming
where the number came from (a file and key, an option) and the value given.

Every number that enters from outside (an option, a controllers file, a plan or runs file, a
recording) passes :func:`finite_in_range` once, at the boundary, so the maths never meets an
infinity, a NaN, an integer too large for a float, or a value outside its physical range.
"""

from __future__ import annotations

import math
import re
import sys
from collections.abc import Callable, Sequence
from typing import Any

from diffbot.errors import DiffbotError, ParameterError

__all__ = [
    "MAX_ANGULAR_SPEED",
    "MAX_COORDINATE",
    "MAX_COUNT",
    "MAX_LINEAR_SPEED",
    "MAX_NOISE",
    "MAX_PLAN_DURATION",
    "MAX_PLAN_SAMPLES",
    "MAX_PLAN_TIME",
    "MAX_RECORDED_ANGLE",
    "MAX_ROLLING_WINDOW",
    "MAX_SEGMENTS",
    "MAX_TIMER_RATE",
    "MAX_TURN",
    "MAX_WAYPOINTS",
    "MAX_WHEEL_SPEED",
    "MOTOR_LIMIT_RANGE",
    "WHEEL_SIZE_RANGE",
    "as_number",
    "encoder_noise",
    "encoder_ticks",
    "finite_in_range",
    "flag",
    "motor_limit",
    "motor_limits",
    "noise_seed",
    "positive_finite",
    "positive_written",
    "shorten_numerals",
    "shown",
    "sized",
    "store_checked",
    "store_number",
    "wheel_size",
    "whole_number",
    "written_form",
    "written_number",
]

#: Longest a ramped or sampled plan may run (s): about 11.6 days; limits that need longer are
#: unit mistakes.
MAX_PLAN_DURATION = 1e6
#: Longest any plan may last (s): its commands are stamped in ROS time, int64 nanoseconds, which
#: runs out after about 292 years. A plan that lasts longer comes of a speed or limit too small
#: (``1e-300``), and its velocities print as zeros.
MAX_PLAN_TIME = 2**63 / 1e9
#: Most samples a plan may be cut into.
MAX_PLAN_SAMPLES = 10_000_000
#: Most segments a plan may have: a route through :data:`MAX_WAYPOINTS` waypoints takes at most
#: five a leg (Reeds-Shepp), and 100,000 segments of 10 s fill :data:`MAX_PLAN_DURATION`. A
#: plan of 100,000 segments plans in a few seconds; one of a million took half a minute.
MAX_SEGMENTS = 100_000
#: Most waypoints a goal plan may go through: 10,000 plan in seconds, 300,000 took minutes and
#: gigabytes.
MAX_WAYPOINTS = 10_000

#: Wheel radius and separation a robot may have (m). Outside, a value is taken for a unit mistake
#: or a hostile file (a subnormal 1e-320, a 1e308) and refused.
WHEEL_SIZE_RANGE = (1e-4, 1e3)

#: Fastest linear velocity command taken (m/s), from the wire or a recording: no wheeled robot
#: drives at 1 km/s.
MAX_LINEAR_SPEED = 1e3
#: Fastest angular velocity command taken (rad/s): about 160 turns a second.
MAX_ANGULAR_SPEED = 1e3

#: Farthest a pose may lie from its origin (m): a million km, beyond any robot's drive. The
#: bound of positions from options, files and messages alike.
MAX_COORDINATE = 1e9
#: Largest angle taken from a recording or a message (rad): a wheel's position, a heading. A
#: wheel at 100 rad/s turns this far in 300 years, and the differences of larger angles
#: overflow the odometry's arithmetic.
MAX_RECORDED_ANGLE = 1e12
#: Fastest wheel velocity taken from a recording or a message (rad/s): about 95,000 rpm.
MAX_WHEEL_SPEED = 1e4
#: Motor limits a robot may have (rad/s): no faster than a wheel turns (MAX_WHEEL_SPEED), and no
#: smaller than the smallest normal float (a subnormal limit divides wrong: a wheel at it shows
#: as over it). A description's limit outside is a placeholder (URDFs often give 1e6), not a
#: limit; an option's is refused.
MOTOR_LIMIT_RANGE = (sys.float_info.min, MAX_WHEEL_SPEED)

#: Largest standard deviation of simulated encoder noise (rad): a revolution. Beyond it a
#: reading says nothing of the angle.
MAX_NOISE = 2.0 * math.pi

#: Largest count an option takes (processes, samples per window, ticks per revolution): beyond
#: it a count is a mistake, and an integer of hundreds of digits is refused before any use.
MAX_COUNT = 2**32
#: Fastest a live node's own timer runs (Hz): its updates, or the publishing of a node that
#: publishes on a clock rather than as messages come.
MAX_TIMER_RATE = 1000.0
#: Most steps a rolling velocity window spans (a controller's velocity_rolling_window_size).
MAX_ROLLING_WINDOW = 1_000_000

#: Largest total turn a plan may make (rad): about 160 million turns, where a float still
#: holds the heading to a tenth of a microradian.
MAX_TURN = 1e9

#: Longest text of a value an error message shows (characters).
_SHOWN = 40


def shown(value: object) -> str:
    """``repr(value)`` cut to a readable length (a 5000-digit integer has no repr at all)."""
    if isinstance(value, int) and not isinstance(value, bool) and value.bit_length() > 128:
        # Python refuses to print integers of more than 4300 digits: say how long it is.
        digits = int(value.bit_length() * math.log10(2.0)) + 1
        return f"an integer of about {digits} digits"
    try:
        text = repr(value)
    except ValueError:  # a pair or list holding an integer of more than 4300 digits
        return f"a {type(value).__name__} holding an integer too long to print"
    return text if len(text) <= _SHOWN else f"{text[: _SHOWN - 3]}..."


#: A run of digits longer than an error message shows whole (a single quantifier over one
#: character class: linear time on any text).
_LONG_DIGITS = re.compile("[0-9]{41,}")


def shorten_numerals(text: str) -> str:
    """``text`` with each run of more than 40 digits cut to its first and last 18, joined by
    ``...``: what an error or warning line shows of a 400-digit number it echoes."""
    half = 18
    return _LONG_DIGITS.sub(lambda m: f"{m[0][:half]}...{m[0][-half:]}", text)


def written_number(text: str) -> float:
    """The number ``text`` writes as files write numbers (XML, a robot description): what
    ``float`` reads, less the spellings of Python alone, digits grouped by underscores
    (``1_0``) and digits of other scripts (Arabic-Indic), which a URDF parser refuses and a
    reader would take for garbage, not for ten.

    Raises:
        ValueError: ``text`` is not such a number (as ``float`` raises it).
    """
    if not written_form(text):
        raise ValueError(f"could not convert string to float: {text!r}")
    return float(text)


def written_form(text: str) -> bool:
    """Whether ``text`` is spelled as numbers are written in files, on command lines and in
    environment variables: ASCII only, no ``_`` between digits. ``float``, ``int`` and
    ``Decimal`` also read digits of other scripts (``٣`` for 3) and grouped digits (``1_0``
    for 10); every reader of numeric text asks this first, so that all refuse the same texts.
    """
    return "_" not in text and text.isascii()


def positive_written(text: str) -> float | None:
    """The finite positive number ``text`` writes (:func:`written_number`), or None: a length,
    a unit, a radius read from a file, for the caller to refuse in its own words."""
    try:
        value = written_number(text)
    except ValueError:
        return None
    return value if math.isfinite(value) and value > 0.0 else None


def reads_as_number(text: str) -> bool:
    """Whether ``text`` is a number as files write it (:func:`written_number`; NaN and
    infinities included)."""
    try:
        written_number(text)
    except ValueError:
        return False
    return True


def as_number(
    value: object,
    what: str,
    error: type[DiffbotError] = ParameterError,
    expected: str = "a number",
) -> float:
    """``float(value)``, or ``error("WHAT must be EXPECTED, got VALUE")`` when it is not one.

    NaN and infinities pass: the caller decides what they mean. Booleans are not numbers.
    """
    if isinstance(value, bool) or (isinstance(value, str) and not written_form(value)):
        raise error(f"{what} must be {expected}, got {shown(value)}")
    try:
        return float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError, OverflowError):
        raise error(f"{what} must be {expected}, got {shown(value)}") from None


def _bound(value: float) -> str:
    return f"{value:g}"


def finite_in_range(
    value: object,
    what: str,
    low: float = -math.inf,
    high: float = math.inf,
    *,
    error: type[DiffbotError] = ParameterError,
    unit: str = "",
    open_low: bool = False,
) -> float:
    """``value`` as a finite float within ``[low, high]`` (``(low, high]`` with ``open_low``).

    Args:
        value: the number as given (a float, an int of any size, a numeric string).
        what: where it came from, for the message: ``"FILE: KEY"``, ``"--option"``.
        low: the smallest physical value (``-inf``: none).
        high: the largest physical value (``inf``: none).
        error: the error class to raise.
        unit: the unit shown with the range (``"m"``, ``"s"``).
        open_low: exclude ``low`` itself (for quantities that must be > 0).

    Raises:
        error: ``"WHAT must be a finite number in RANGE, got VALUE"``.
    """
    lower = "" if math.isinf(low) else f"{'>' if open_low else '>='} {_bound(low)}"
    upper = "" if math.isinf(high) else f"<= {_bound(high)}"
    span = " and ".join(part for part in (lower, upper) if part)
    suffix = f" {unit}" if unit and span else ""
    expected = f"a finite number{f' {span}{suffix}' if span else ''}"
    number = as_number(value, what, error, expected)
    inside = number > low if open_low else number >= low
    if not (math.isfinite(number) and inside and number <= high):
        raise error(f"{what} must be {expected}, got {shown(value)}")
    return number


def flag(value: object, what: str, error: type[DiffbotError] = ParameterError) -> bool:
    """``value`` when it is ``True`` or ``False``, else ``error`` naming ``what``.

    A switch is not taken by truthiness: ``"false"``, ``"no"`` or ``0.0`` given for one
    (``trust``, which lets a description run code, first) would otherwise turn it on, or off,
    against what was written.
    """
    if isinstance(value, bool):
        return value
    raise error(f"{what} must be True or False, got {shown(value)}")


def store_checked(
    instance: object, name: str, check: Callable[[Any], object], *, optional: bool = False
) -> None:
    """Set the field ``name`` of the dataclass ``instance`` (frozen or not) to what ``check``
    returns for its value: the value as the maths takes it (a float for a numeric string, an
    int of any size or a NumPy number), or the error ``check`` raises, which names the
    parameter. With ``optional``, None stays None (unset) without being checked.

    Each dataclass of the library checks its fields by this in ``__post_init__``, so that a
    value is checked and converted once, where it is given, and never kept as given.
    """
    value = getattr(instance, name)
    if value is None and optional:
        return
    object.__setattr__(instance, name, check(value))


def store_number(
    instance: object,
    name: str,
    low: float = -math.inf,
    high: float = math.inf,
    *,
    what: str | None = None,
    unit: str = "",
    open_low: bool = False,
    optional: bool = False,
) -> None:
    """:func:`store_checked` with :func:`finite_in_range`: the field ``name`` of ``instance``
    becomes a finite float within ``[low, high]`` (``(low, high]`` with ``open_low``), or a
    :class:`~diffbot.errors.ParameterError` names it (``what``, by default ``name``)."""

    def check(value: object) -> float:
        return finite_in_range(value, what or name, low, high, unit=unit, open_low=open_low)

    store_checked(instance, name, check, optional=optional)


def whole_number(
    value: object, what: str, low: int, high: float = math.inf, *, shown_high: str = ""
) -> int:
    """``value`` when it is an integer (a bool is none) from ``low`` to ``high``, else a
    :class:`~diffbot.errors.ParameterError` naming ``what`` (``high`` written as
    ``shown_high`` when given)."""
    if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
        span = f">= {low}" if math.isinf(high) else f"from {low} to {shown_high or high}"
        raise ParameterError(f"{what} must be an integer {span}, got {shown(value)}")
    return value


def sized(value: object, count: int) -> Sequence[object] | None:
    """``value`` when it is a sequence of ``count`` items (text is not one), else None."""
    if isinstance(value, str | bytes) or not isinstance(value, Sequence) or len(value) != count:
        return None
    return value


def encoder_ticks(ticks: object) -> int:
    """``ticks``, an encoder's resolution (counts per revolution): an integer from 1 to
    :data:`MAX_COUNT`.

    Raises:
        ParameterError: anything else (a float, a string, a bool), naming ``ticks``.
    """
    return whole_number(ticks, "ticks per revolution", 1, MAX_COUNT, shown_high="2**32")


def encoder_noise(noise: object) -> float:
    """``noise``, the standard deviation of simulated encoder noise (rad), as a float from 0
    to :data:`MAX_NOISE`, or a :class:`~diffbot.errors.ParameterError` naming it."""
    return finite_in_range(noise, "noise", 0.0, MAX_NOISE, unit="rad")


def noise_seed(seed: object) -> int:
    """``seed``, the seed of simulated noise, drops and slip: an integer >= 0.

    Raises:
        ParameterError: anything else (a float, NaN, a string, a bool), naming ``seed``.
    """
    return whole_number(seed, "seed", 0)


def wheel_size(value: object, what: str, error: type[DiffbotError] = ParameterError) -> float:
    """``value`` as a wheel radius or separation (m) within :data:`WHEEL_SIZE_RANGE`, else
    ``error`` naming ``what``."""
    low, high = WHEEL_SIZE_RANGE
    return finite_in_range(value, what, low, high, error=error, unit="m")


def motor_limit(value: object, what: str, error: type[DiffbotError] = ParameterError) -> float:
    """``value`` as a motor limit (rad/s): 0 (no wheel may turn) or within
    :data:`MOTOR_LIMIT_RANGE`, else ``error`` naming ``what``. A placeholder limit of a file
    (``1e6``) is no motor limit: its reader leaves it out (:func:`motor_limits`) before it comes
    here."""
    low, high = MOTOR_LIMIT_RANGE
    expected = f"0 or a finite number >= {_bound(low)} and <= {_bound(high)} rad/s"
    number = as_number(value, what, error, expected)
    if number != 0.0 and not low <= number <= high:  # NaN fails both
        raise error(f"{what} must be {expected}, got {shown(value)}")
    return number


def positive_finite(value: object, what: str, error: type[DiffbotError] = ParameterError) -> float:
    """``value`` as a float when it is finite and > 0, else ``error`` naming ``what``.

    A subnormal float (below about 2.2e-308, such as 5e-324) is refused as too small to compute
    with: its half rounds to 0 and its reciprocal overflows, so a size or rate of it would
    divide by zero further on.
    """
    expected = "a positive finite number"
    number = as_number(value, what, error, expected)
    if not math.isfinite(number) or number <= 0.0:
        raise error(f"{what} must be {expected}, got {shown(value)}")
    if number < sys.float_info.min:
        raise error(f"{what} must be {expected}, got {shown(value)}: too small to compute with")
    return number


def motor_limits(
    where: str, limits: Sequence[tuple[str, float]], warnings: list[str]
) -> list[float]:
    """The velocity limits (rad/s) of ``limits`` (joint name, limit) that are motor limits,
    within :data:`MOTOR_LIMIT_RANGE`. Those above it are placeholders (``1e6``, ``1.7e307``),
    no motor limit: one warning in ``warnings`` names their joints, ``where`` saying what gives
    them (``"the velocity limit of"``). Those below are left out, unsaid."""
    low, high = MOTOR_LIMIT_RANGE
    above = [(name, value) for name, value in limits if value > high]
    if above:
        joints = ", ".join(repr(name) for name, _ in above)
        values = ", ".join(f"{value:g}" for value in dict.fromkeys(v for _, v in above))
        plural = len(above) > 1
        warnings.append(
            f"{where} joint{'s' if plural else ''} {joints}: {values} rad/s "
            f"{'are' if plural else 'is'} faster than any wheel turns (over {high:g} rad/s): "
            "taken for a placeholder, not a motor limit"
        )
    return [value for _, value in limits if low <= value <= high]
