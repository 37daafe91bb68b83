"""Odometry held against a reference: the robot's own odometry (a controller's ``/odom``) or a
motion-capture track, recorded beside the wheel joints.

The reference is interpolated linearly at the odometry's stamps (its heading unwrapped first, so
that it never goes the long way round); stamps outside the reference's span are not compared.
Both start in their own frames, so the reference is moved rigidly onto the odometry at the
first compared stamp: the errors measure how the two drift apart, not where each frame began.
The poses arrive chunk by chunk (:meth:`ReferenceComparison.add`), in constant memory beyond the
reference itself.

Pure: arrays in, numbers out.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from diffbot.kinematics import norm_angle
from diffbot.samples import NS_PER_S

if TYPE_CHECKING:
    from numpy.typing import ArrayLike, NDArray

__all__ = ["ReferenceComparison", "ReferenceResult"]


@dataclass(frozen=True)
class ReferenceResult:
    """How far the odometry is from the reference.

    Attributes:
        topic: the reference's topic (or file), for people.
        samples: how many odometry poses were compared (those within the reference's span).
        final_position_error: distance (m) between the two at the last compared stamp.
        final_heading_error: odometry minus reference heading (rad, in (-pi, pi]) there.
        max_position_error: the largest distance (m).
        rms_position_error: the root mean square of the distances (m).
        span_ns: the reference's first and last stamps (ns); None when it has none.
        odometry_span_ns: the first and last odometry stamps seen (ns); None before any.
    """

    topic: str
    samples: int
    final_position_error: float
    final_heading_error: float
    max_position_error: float
    rms_position_error: float
    span_ns: tuple[int, int] | None = None
    odometry_span_ns: tuple[int, int] | None = None

    def no_overlap_text(self) -> str:
        """Why no pose was compared, for people: the two time spans side by side."""
        from diffbot.samples import seconds_text

        if self.span_ns is None:
            return f"{self.topic} holds no pose"
        start, end = self.span_ns
        reference = f"{seconds_text(start)} to {seconds_text(end)} s"
        if self.odometry_span_ns is None:
            return f"no odometry pose to compare with {self.topic} ({reference})"
        first, last = self.odometry_span_ns
        return (
            f"no pose within the odometry's time span (the odometry {seconds_text(first)} to "
            f"{seconds_text(last)} s, {self.topic} {reference}: two clocks?)"
        )

    def as_dict(self) -> dict[str, str | int | float | None]:
        """The fields by name (``odom --json``'s ``reference``); None for an error not known
        (no pose compared)."""

        def known(value: float) -> float | None:
            return None if math.isnan(value) else value

        return {
            "topic": self.topic,
            "samples": self.samples,
            "final_position_error": known(self.final_position_error),
            "final_heading_error": known(self.final_heading_error),
            "max_position_error": known(self.max_position_error),
            "rms_position_error": known(self.rms_position_error),
        }


class ReferenceComparison:
    """Odometry poses compared with a reference track as they come.

    Args:
        topic: the reference's name, for the result.
        stamps_ns: the reference's stamps (ns), int64, shape (m,), not decreasing.
        x: its x (m), shape (m,).
        y: its y (m), shape (m,).
        theta: its heading (rad), wrapped or not, shape (m,).
    """

    def __init__(
        self, topic: str, stamps_ns: ArrayLike, x: ArrayLike, y: ArrayLike, theta: ArrayLike
    ) -> None:
        self.topic = topic
        stamps = np.asarray(stamps_ns, dtype=np.int64)
        order = np.argsort(stamps, kind="stable")
        self._origin = int(stamps[order[0]]) if stamps.size else 0
        self._t = (stamps[order] - self._origin).astype(np.float64) / NS_PER_S
        self._x = np.asarray(x, dtype=np.float64)[order]
        self._y = np.asarray(y, dtype=np.float64)[order]
        self._theta = np.unwrap(np.asarray(theta, dtype=np.float64)[order])
        self._span = (int(stamps[order[0]]), int(stamps[order[-1]])) if stamps.size else None
        self.reset()

    def reset(self) -> None:
        """Forget the poses compared so far (the run starts again)."""
        self._shift: tuple[float, float, float, float, float, float] | None = None
        self._count = 0
        self._sum_squares = 0.0
        self._max = 0.0
        self._last: tuple[float, float] = (math.nan, math.nan)
        self._seen: tuple[int, int] | None = None

    def at(self, stamps_ns: ArrayLike) -> tuple[NDArray[np.float64], ...]:
        """The reference interpolated at these stamps and moved onto the odometry's frame:
        x, y (m), heading (rad, unwrapped) and whether each stamp is within its span; NaN
        where not, or before the first pose is compared."""
        stamps = np.asarray(stamps_ns, dtype=np.int64)
        t = (stamps - self._origin).astype(np.float64) / NS_PER_S
        inside = (t >= self._t[0]) & (t <= self._t[-1]) if self._t.size else t != t
        x = np.interp(t, self._t, self._x) if self._t.size else np.full(t.shape, np.nan)
        y = np.interp(t, self._t, self._y) if self._t.size else np.full(t.shape, np.nan)
        th = np.interp(t, self._t, self._theta) if self._t.size else np.full(t.shape, np.nan)
        if self._shift is None:
            nan = np.full(t.shape, np.nan)
            return nan, nan, nan, inside.astype(np.float64)
        rx, ry, rth, ox, oy, oth = self._shift
        # The reference relative to its pose at the first compared stamp, then placed at the
        # odometry's pose there.
        dx, dy = x - rx, y - ry
        c, s = math.cos(oth - rth), math.sin(oth - rth)
        ax = ox + c * dx - s * dy
        ay = oy + s * dx + c * dy
        ath = th - rth + oth
        nan = np.full(t.shape, np.nan)
        return (
            np.where(inside, ax, nan),
            np.where(inside, ay, nan),
            np.where(inside, ath, nan),
            inside.astype(np.float64),
        )

    def add(
        self, stamps_ns: ArrayLike, x: ArrayLike, y: ArrayLike, heading: ArrayLike
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """Compare the next odometry poses, in order.

        Args:
            stamps_ns: their stamps (ns), shape (n,).
            x: x (m), shape (n,).
            y: y (m), shape (n,).
            heading: heading (rad), shape (n,).

        Returns:
            The reference at those stamps in the odometry's frame: x, y (m) and heading (rad,
            in (-pi, pi]); NaN where it has no pose.
        """
        stamps = np.asarray(stamps_ns, dtype=np.int64)
        if stamps.size:
            first = int(stamps[0]) if self._seen is None else self._seen[0]
            self._seen = (first, int(stamps[-1]))
        ox = np.asarray(x, dtype=np.float64)
        oy = np.asarray(y, dtype=np.float64)
        oth = np.asarray(heading, dtype=np.float64)
        if self._shift is None and self._t.size:
            t = (stamps - self._origin).astype(np.float64) / NS_PER_S
            inside = np.flatnonzero((t >= self._t[0]) & (t <= self._t[-1]))
            if inside.size:
                k = int(inside[0])
                self._shift = (
                    float(np.interp(t[k], self._t, self._x)),
                    float(np.interp(t[k], self._t, self._y)),
                    float(np.interp(t[k], self._t, self._theta)),
                    float(ox[k]),
                    float(oy[k]),
                    float(oth[k]),
                )
        rx, ry, rth, _ = self.at(stamps)
        compared = ~np.isnan(rx)
        if compared.any():
            distance = np.hypot(ox[compared] - rx[compared], oy[compared] - ry[compared])
            self._count += int(distance.size)
            self._sum_squares += float(np.dot(distance, distance))
            self._max = max(self._max, float(distance.max()))
            last = int(np.flatnonzero(compared)[-1])
            self._last = (
                float(distance[-1]),
                norm_angle(float(oth[last]) - float(rth[last])),
            )
        return rx, ry, norm_angle(rth)

    def result(self) -> ReferenceResult:
        """The comparison so far (NaN errors when no pose was compared)."""
        count = self._count
        return ReferenceResult(
            topic=self.topic,
            samples=count,
            final_position_error=self._last[0],
            final_heading_error=self._last[1],
            max_position_error=self._max if count else math.nan,
            rms_position_error=math.sqrt(self._sum_squares / count) if count else math.nan,
            span_ns=self._span,
            odometry_span_ns=self._seen,
        )
