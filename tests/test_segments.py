"""Plan segments: each is checked when it is made, and its geometry is in closed form."""

from __future__ import annotations

import math
from collections.abc import Callable

import pytest

from diffbot.errors import PlanError
from diffbot.segments import Arc, Segment, Spin, Straight, as_float, describe_segment, geometry


@pytest.mark.parametrize(
    ("make", "pattern"),
    [
        (lambda: Straight(0.0), "length"),
        (lambda: Straight(-math.inf), "length"),
        (lambda: Straight(math.nan), "length"),
        (lambda: Straight(1.0, 0.0), "duration"),
        (lambda: Straight(1.0, math.inf), "duration"),
        (lambda: Arc(0.0, 1.0, "ccw"), "radius"),
        (lambda: Arc(1.0, -1.0, "ccw"), "angle"),
        (lambda: Arc(1.0, 1.0, "left"), "direction"),  # type: ignore[arg-type]
        (lambda: Spin(0.0), "angle"),
        (lambda: Spin(math.inf), "angle"),
    ],
)
def test_segments_reject_values_out_of_their_domain(
    make: Callable[[], Segment], pattern: str
) -> None:
    with pytest.raises(PlanError, match=pattern):
        make()


def test_describe_segment_is_short_and_in_degrees() -> None:
    assert describe_segment(Arc(0.25, math.pi, "cw", 10.0)) == "cw arc r 0.25 m 180 deg"
    assert describe_segment(Straight(1.0)) == "straight 1 m"
    assert describe_segment(Spin(-math.pi / 2)) == "spin -90 deg"
    assert describe_segment(Spin(1.7e308)) == "spin 1.7e+308 rad"  # too large in degrees


@pytest.mark.parametrize(
    ("segment", "expected"),
    [
        (Straight(-1.5), (-1.5, 0.0)),
        (Arc(0.25, math.pi, "ccw"), (0.25 * math.pi, math.pi)),
        (Arc(0.25, math.pi / 2, "cw"), (0.125 * math.pi, -math.pi / 2)),
        (Arc(0.5, 1.0, "ccw", reverse=True), (-0.5, 1.0)),
        (Spin(-2.0), (0.0, -2.0)),
    ],
)
def test_geometry_is_the_signed_path_length_and_heading_change(
    segment: Segment, expected: tuple[float, float]
) -> None:
    length, turn = geometry(segment)
    assert length == pytest.approx(expected[0], abs=1e-15)
    assert turn == pytest.approx(expected[1], abs=1e-15)


def test_as_float_reads_numbers_and_gives_nan_for_anything_else() -> None:
    assert as_float("2.5") == 2.5
    assert as_float(3) == 3.0
    for junk in ("x", None, True, 10**400, "1_0", "\u0663", "\uff13.5"):
        assert math.isnan(as_float(junk))


def test_values_are_stored_as_floats() -> None:
    straight = Straight(2, 4)  # type: ignore[arg-type]
    assert (type(straight.length), type(straight.duration)) == (float, float)
