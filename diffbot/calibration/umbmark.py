"""UMBmark (Borenstein and Feng, IEEE Trans. Robotics and Automation 12(6), 1996): the wheel
diameter ratio and the separation from where square test runs end.

The robot drives a square of side L clockwise and counter-clockwise (:func:`umbmark_segments`)
several times; where each run ends relative to its start (REP-103: x forward, y left) gives the
turn error per corner (``alpha``, from the separation) and the heading change along each side
(``beta``, from unequal wheel radii), by a small-error approximation or an exact model of the
runs. The derivations are in ``docs/calibration.md``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal

from diffbot.calibration.checks import check_geometry
from diffbot.errors import CalibrationError, ParameterError
from diffbot.kinematics import DiffDriveParams
from diffbot.numbers import MAX_COORDINATE, finite_in_range, flag
from diffbot.trajectory import Spin, Straight

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import ArrayLike, NDArray

__all__ = ["UmbmarkResult", "umbmark", "umbmark_segments"]


def umbmark_segments(side: float, direction: Literal["cw", "ccw"]) -> list[Straight | Spin]:
    """The UMBmark test path: a square driven with turns in place.

    The first side runs straight ahead (+x from the start pose); each side is followed by a
    quarter turn in place, clockwise (negative, REP-103) or counter-clockwise, the last one
    bringing the robot back to its start heading.

    Args:
        side: length of a side (m), > 0.
        direction: ``"cw"`` or ``"ccw"``.

    Returns:
        Eight segments: ``Straight(side)``, ``Spin(-+pi/2)``, four times, without durations.

    Raises:
        ParameterError: ``side`` not a positive finite number, or an unknown direction.
    """
    length = finite_in_range(side, "side", 0.0, MAX_COORDINATE, unit="m", open_low=True)
    if direction not in ("cw", "ccw"):
        raise ParameterError(f"direction must be 'cw' or 'ccw', got {direction!r}")
    turn = 0.5 * math.pi if direction == "ccw" else -0.5 * math.pi
    segments: list[Straight | Spin] = []
    for _ in range(4):
        segments += [Straight(length), Spin(turn)]
    return segments


@dataclass(frozen=True)
class UmbmarkResult:
    """What a UMBmark experiment says about the robot.

    Attributes:
        ed: ratio of the right to the left wheel diameter, ``D_R / D_L`` (1 when equal).
        eb: ratio of the actual to the nominal wheel separation, ``b_actual / b_nominal``.
        alpha: extra turn (rad) of each nominal quarter turn, counted in the direction of the
            turn (positive: the robot turns too far, as when the separation is shorter than
            nominal), from the separation error.
        beta: heading change (rad, positive counter-clockwise) along each side of the square,
            from unequal wheel diameters (positive when the right wheel is larger).
        left_wheel_radius: corrected left wheel radius (m): the nominal left radius scaled so
            that the two sides' scale factors average 1 (UMBmark cannot see a common scale
            error); with equal nominal radii, the mean of the two radii is the nominal radius.
        right_wheel_radius: corrected right wheel radius (m).
        wheel_separation: corrected wheel separation (m).
        cw_centre: centre of gravity (x, y) of the clockwise runs' end positions (m).
        ccw_centre: the same for the counter-clockwise runs (m).
    """

    ed: float
    eb: float
    alpha: float
    beta: float
    left_wheel_radius: float
    right_wheel_radius: float
    wheel_separation: float
    cw_centre: tuple[float, float]
    ccw_centre: tuple[float, float]


def _centre(
    name: str, ends: Sequence[tuple[float, float]] | ArrayLike, side: float
) -> tuple[float, float]:
    """The mean end (m) of runs around a square of ``side`` (m); each end must lie within the
    square's perimeter, the farthest a run can stop from its start."""
    import numpy as np

    try:
        array = np.asarray(ends, dtype=np.float64)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be (x, y) pairs of real numbers (m)") from None
    if array.ndim != 2 or array.shape[1] != 2 or array.shape[0] == 0:
        raise ParameterError(
            f"{name} must be a non-empty sequence of (x, y) pairs (m), got shape {array.shape}"
        )
    if not np.isfinite(array).all():
        raise ParameterError(f"{name} must be finite")
    reach = 4.0 * side
    distances = np.hypot(array[:, 0], array[:, 1])
    if not (distances <= reach).all():
        k = int(np.argmax(~(distances <= reach)))
        x, y = (float(v) for v in array[k])
        raise CalibrationError(
            f"{name}: the run ending at x {x:.6g} m, y {y:.6g} m stopped farther from its start "
            f"than the {reach:.6g} m it drove around a {side:.6g} m square: not a UMBmark run "
            "(ends are measured in m from the start pose)"
        )
    mean = array.mean(axis=0)
    return float(mean[0]), float(mean[1])


def umbmark(
    side: float,
    cw_ends: Sequence[tuple[float, float]] | ArrayLike,
    ccw_ends: Sequence[tuple[float, float]] | ArrayLike,
    params: DiffDriveParams,
    *,
    exact: bool = False,
) -> UmbmarkResult:
    """Wheel diameter ratio and separation from UMBmark runs.

    Each run drives :func:`umbmark_segments` with the nominal ``params``; its end is where the
    robot actually stopped, relative to its start pose (x forward, y left, m): the return
    position error, since the commanded square closes. To first order in the errors (see
    ``docs/calibration.md``) the centres of gravity are::

        cw:  (2 L (alpha - beta), 2 L (alpha - beta))
        ccw: (2 L (alpha + beta), -2 L (alpha + beta))

    so each of alpha and beta has an estimate from the x and one from the y coordinates; their
    mean is used. Then ``eb = (pi/2) / (pi/2 + alpha)``, ``b = eb b_nominal``, and, as each side
    is an arc of length L turning by beta, the ratio of the right side's scale error to the
    left's is ``(L + beta b / 2) / (L - beta b / 2)``: each side's nominal radius (a controller's
    multipliers applied) is scaled by its own, the two averaging 1, and ``ed`` is the ratio of
    the radii so found (the same ratio when the nominal radii are equal).

    The approximation's error is of second order: for the bundled robot on a 4 m square with
    radii 0.1 % apart and the separation 1 % off, the separation comes out within 0.05 % and the
    radii within 0.001 %. ``exact=True`` removes it: alpha and beta are then fitted (Gauss-Newton,
    from the first-order values) to the ends of squares driven exactly along arcs, turns in place
    included (which move the robot a little when the radii differ).

    Args:
        side: length of the square's side (m).
        cw_ends: end positions (x, y) of the clockwise runs (m), at least one.
        ccw_ends: end positions of the counter-clockwise runs (m), at least one.
        params: the nominal robot the runs were commanded with.
        exact: fit the exact model of the runs instead of using the first-order formulas.

    Returns:
        The errors and the corrected geometry.

    Raises:
        ParameterError: a bad side length or end positions.
        CalibrationError: errors too large for the method (a corner turn or a side's arc
            reversed: the runs do not look like squares).
    """
    exact = flag(exact, "exact")
    length = finite_in_range(side, "side", 0.0, MAX_COORDINATE, unit="m", open_low=True)
    x_cw, y_cw = _centre("cw_ends", cw_ends, length)
    x_ccw, y_ccw = _centre("ccw_ends", ccw_ends, length)
    alpha = ((x_cw + x_ccw) + (y_cw - y_ccw)) / (8.0 * length)
    beta = ((x_ccw - x_cw) - (y_cw + y_ccw)) / (8.0 * length)
    if exact:
        alpha, beta = _exact_errors(
            length, (x_cw, y_cw, x_ccw, y_ccw), params.wheel_separation, alpha, beta
        )
    quarter = 0.5 * math.pi
    if not quarter + alpha > 0.0:
        raise CalibrationError(
            f"the runs imply corners turned by {math.degrees(quarter + alpha):.3g} deg instead "
            "of 90: errors this large are beyond UMBmark's small-error approximation"
        )
    eb = quarter / (quarter + alpha)
    separation = eb * params.wheel_separation
    lean = 0.5 * beta * separation / length
    if not abs(lean) < 1.0:
        raise CalibrationError(
            f"the runs imply sides bent by {math.degrees(beta):.3g} deg, more than wheels "
            f"{separation:.3g} m apart can turn along {length:.3g} m: errors this large are "
            "beyond UMBmark's small-error approximation"
        )
    # The runs were commanded with each side's own nominal radius (a controller's multipliers
    # applied), so the bend gives the ratio of the two sides' scale errors, not of their radii:
    # each side's radius is scaled by its own.
    scale = (1.0 + lean) / (1.0 - lean)
    left, right = params.radii
    result = UmbmarkResult(
        ed=scale * (right / left),
        eb=eb,
        alpha=alpha,
        beta=beta,
        left_wheel_radius=2.0 * left / (scale + 1.0),
        right_wheel_radius=2.0 * right * scale / (scale + 1.0),
        wheel_separation=separation,
        cw_centre=(x_cw, y_cw),
        ccw_centre=(x_ccw, y_ccw),
    )
    check_geometry(result, "the runs give")
    return result


def _square_end(
    side: float, turn: float, separation: float, alpha: float, beta: float
) -> tuple[float, float]:
    """Where a UMBmark square ends, exactly, for corner error alpha and side bend beta (rad).

    ``turn`` is +1 for ccw, -1 for cw runs. Each side is an arc of length ``side`` turning by
    beta; each corner turns by ``turn (pi/2 + alpha)``. With unequal radii a turn in place also
    moves the centre, by ``(r_R - r_L) psi / 2`` where each wheel turns by
    ``psi = (pi/4) b_nominal / r``, and ``(r_R - r_L) / r = beta b / L`` with the true
    ``b = b_nominal (pi/2) / (pi/2 + alpha)``.
    """
    quarter = 0.5 * math.pi
    true_separation = separation * quarter / (quarter + alpha)
    corner_path = turn * 0.125 * math.pi * beta * true_separation * separation / side
    x = y = heading = 0.0
    for _ in range(4):
        for ds, dtheta in ((side, beta), (corner_path, turn * (quarter + alpha))):
            half = 0.5 * dtheta
            chord = ds * (math.sin(half) / half if half != 0.0 else 1.0)
            x += chord * math.cos(heading + half)
            y += chord * math.sin(heading + half)
            heading += dtheta
    return x, y


def _exact_errors(
    side: float,
    centres: tuple[float, float, float, float],
    separation: float,
    alpha: float,
    beta: float,
) -> tuple[float, float]:
    """alpha and beta (rad) whose exact squares end nearest the centres (x_cw, y_cw, x_ccw,
    y_ccw), by Gauss-Newton from a first guess."""
    import numpy as np

    target = np.asarray(centres, dtype=np.float64)
    quarter = 0.5 * math.pi

    def residual(a: float, b: float) -> NDArray[np.float64]:
        cw = _square_end(side, -1.0, separation, a, b)
        ccw = _square_end(side, 1.0, separation, a, b)
        return np.array([*cw, *ccw], dtype=np.float64) - target

    step = 1e-7
    change = math.inf
    for _ in range(50):
        # Corners turned backwards or sides bent by more than half a turn: not squares any
        # more, and sin() of the huge angles of a diverging fit fails.
        if not (abs(alpha) + step < quarter and abs(beta) + step < math.pi):
            change = math.inf
            break
        jac = np.column_stack(
            (
                (residual(alpha + step, beta) - residual(alpha - step, beta)) / (2.0 * step),
                (residual(alpha, beta + step) - residual(alpha, beta - step)) / (2.0 * step),
            )
        )
        delta = np.linalg.lstsq(jac, -residual(alpha, beta), rcond=None)[0]
        alpha += float(delta[0])
        beta += float(delta[1])
        change = float(np.abs(delta).sum())
        if not math.isfinite(change) or change <= 1e-14 * (1.0 + abs(alpha) + abs(beta)):
            break
    if not change <= 1e-9:
        raise CalibrationError(
            "the exact square model does not converge for these runs: the errors are too large "
            "or the runs disagree with each other"
        )
    return alpha, beta
