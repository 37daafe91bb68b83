"""The pieces of a motion plan: straight lines, arcs and turns in place, each checked when it is
made (finite, non-zero, positive where it must be), and their geometry in closed form."""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal, TypeVar

from diffbot.errors import PlanError
from diffbot.formats.text import brief
from diffbot.numbers import MAX_SEGMENTS, written_form

if TYPE_CHECKING:
    from typing import TypeAlias

__all__ = [
    "Arc",
    "Segment",
    "Spin",
    "Straight",
    "as_float",
    "describe_segment",
    "geometry",
    "kind",
    "positive",
    "too_many_segments",
    "up_to_the_limit",
]


def as_float(value: object) -> float:
    """``float(value)`` (numeric text too, as files write it:
    :func:`~diffbot.numbers.written_form`), or NaN for a boolean and for what ``float`` cannot
    read (other text, None, an int too large)."""
    if isinstance(value, bool) or (isinstance(value, str) and not written_form(value)):
        return math.nan
    try:
        return float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError, OverflowError):
        return math.nan


def too_many_segments() -> PlanError:
    """The error of a plan of more than :data:`~diffbot.numbers.MAX_SEGMENTS` segments."""
    return PlanError(
        f"more than {MAX_SEGMENTS:,} segments, the most a plan may have "
        "(MAX_SEGMENTS): split it into several plans"
    )


_Item = TypeVar("_Item")


def up_to_the_limit(items: Iterable[_Item]) -> list[_Item]:
    """``items`` as a list, taken one by one and refused (:func:`too_many_segments`) at the
    first past :data:`~diffbot.numbers.MAX_SEGMENTS`: an endless iterator is not consumed."""
    taken = list(itertools.islice(items, MAX_SEGMENTS + 1))
    if len(taken) > MAX_SEGMENTS:
        raise too_many_segments()
    return taken


def positive(value: float, what: str) -> float:
    number = as_float(value)
    if not math.isfinite(number) or number <= 0.0:
        raise PlanError(f"{what} must be a positive finite number, got {brief(value)}")
    return number


def _optional_duration(value: float | None) -> float | None:
    return None if value is None else positive(value, "a segment duration (s)")


def _check_signed(segment: Straight | Spin, name: str, what: str) -> None:
    """Check a segment whose one value is signed (finite, not zero) and its duration."""
    value = getattr(segment, name)
    if type(value) is float and segment.duration is None and math.isfinite(value) and value:
        return  # already what the checks below would make of it (plans build many segments)
    number = as_float(value)
    if not math.isfinite(number) or number == 0.0:
        raise PlanError(f"{what} must be finite and not zero, got {brief(value)}")
    object.__setattr__(segment, name, number)
    object.__setattr__(segment, "duration", _optional_duration(segment.duration))


@dataclass(frozen=True)
class Straight:
    """Drive straight ahead, or backwards.

    Attributes:
        length: distance (m), not zero: positive drives forward, negative backwards.
        duration: time to take (s), > 0; None to run at the plan's cruise speed.
    """

    length: float
    duration: float | None = None

    def __post_init__(self) -> None:
        _check_signed(self, "length", "a straight's length (m)")


@dataclass(frozen=True)
class Arc:
    """Drive along a circular arc, forward or backwards.

    Attributes:
        radius: radius of the path of the robot's centre (m), > 0.
        angle: heading change along the arc (rad), > 0; the direction says which way.
        direction: the way the heading turns: ``"ccw"`` counter-clockwise (positive angular.z),
            ``"cw"`` clockwise, whichever way the robot drives.
        duration: time to take (s), > 0; None to run at the plan's cruise speed.
        reverse: drive backwards (negative linear.x). A reverse ``ccw`` arc retraces a forward
            ``cw`` arc: its end pose is the forward ``cw`` arc's mirrored front to back.
    """

    radius: float
    angle: float
    direction: Literal["cw", "ccw"]
    duration: float | None = None
    reverse: bool = False

    def __post_init__(self) -> None:
        object.__setattr__(self, "radius", positive(self.radius, "an arc's radius (m)"))
        object.__setattr__(self, "angle", positive(self.angle, "an arc's angle (rad)"))
        if self.direction not in ("cw", "ccw"):
            raise PlanError(
                f"an arc's direction must be 'cw' or 'ccw', got {brief(self.direction)}"
            )
        object.__setattr__(self, "duration", _optional_duration(self.duration))
        if not isinstance(self.reverse, bool):
            raise PlanError(f"an arc's reverse must be True or False, got {brief(self.reverse)}")


@dataclass(frozen=True)
class Spin:
    """Turn in place.

    Attributes:
        angle: heading change (rad), positive counter-clockwise, not zero.
        duration: time to take (s), > 0; None to turn at the plan's spin rate.
    """

    angle: float
    duration: float | None = None

    def __post_init__(self) -> None:
        _check_signed(self, "angle", "a spin's angle (rad)")


Segment: TypeAlias = Straight | Arc | Spin


def geometry(segment: Segment) -> tuple[float, float]:
    """Signed path length of the robot's centre (m, negative backwards) and signed heading
    change (rad)."""
    if isinstance(segment, Straight):
        return segment.length, 0.0
    if isinstance(segment, Arc):
        turn = segment.angle if segment.direction == "ccw" else -segment.angle
        length = segment.radius * segment.angle
        return -length if segment.reverse else length, turn
    return 0.0, segment.angle


def kind(segment: Segment) -> str:
    if isinstance(segment, Arc):
        return segment.direction
    return "straight" if isinstance(segment, Straight) else "spin"


def describe_segment(segment: Segment) -> str:
    """A short description of a segment for people (6 significant digits, degrees)."""

    def short(value: float) -> str:
        text = f"{value:.6g}"
        return "0" if text == "-0" else text

    if isinstance(segment, Straight):
        return f"straight {short(segment.length)} m"

    def angle(value: float) -> str:
        degrees = math.degrees(value)
        return f"{short(degrees)} deg" if math.isfinite(degrees) else f"{short(value)} rad"

    if isinstance(segment, Arc):
        way = "reverse " if segment.reverse else ""
        return f"{way}{segment.direction} arc r {short(segment.radius)} m {angle(segment.angle)}"
    return f"spin {angle(segment.angle)}"
