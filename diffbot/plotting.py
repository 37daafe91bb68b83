"""Figures of plans: the path in the odom frame and the wheel speeds against the motor limit.

matplotlib is an optional extra (``pip install 'diffbot-kinematics[plot]'``); it is imported only
when a figure is made, never with this module. Figures are drawn on the Agg canvas, without
pyplot, so that nothing opens a window or needs a display; only a figure asked for with
``window=True`` goes through pyplot, for :func:`show`.
"""

from __future__ import annotations

import math
import os
import warnings
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, Final

from diffbot.errors import DiffbotError
from diffbot.io.outputs import atomic_text
from diffbot.kinematics import DiffDriveParams, Pose, rad_s_from_rpm, rpm_from_rad_s
from diffbot.trajectory import Plan, pose_at

if TYPE_CHECKING:
    import numpy as np
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from numpy.typing import ArrayLike, NDArray

__all__ = [
    "FIGURE_DPI",
    "FIGURE_SIZE",
    "FILE_BACKENDS",
    "INSTALL_COMMAND",
    "LEFT_COLOUR",
    "LIMIT_COLOUR",
    "MAX_MARKED_SEGMENTS",
    "OVER_LIMIT_COLOUR",
    "PATH_COLOUR",
    "RECORDING_COLOURS",
    "RIGHT_COLOUR",
    "SUFFIXES",
    "PlotError",
    "Recording",
    "end_distance",
    "file_format",
    "marked_segments",
    "plan_figure",
    "recordings_figure",
    "require_matplotlib",
    "require_window",
    "save",
    "show",
]

#: How to install what plotting needs.
INSTALL_COMMAND: Final = "pip install 'diffbot-kinematics[plot]'"
#: The size of a plan figure (inches) and its resolution (dots per inch): 800 x 900 pixels.
FIGURE_SIZE: Final = (8.0, 9.0)
FIGURE_DPI: Final = 100
#: matplotlib backends that draw into files only: :func:`show` cannot open a window with them.
FILE_BACKENDS: Final = ("agg", "cairo", "pdf", "pgf", "ps", "svg", "template")
#: The file types :func:`save` writes, by suffix.
SUFFIXES: Final = (".png", ".svg", ".pdf")

PATH_COLOUR: Final = "#1f77b4"
LEFT_COLOUR: Final = "#2ca02c"
RIGHT_COLOUR: Final = "#9467bd"
LIMIT_COLOUR: Final = "#d62728"
OVER_LIMIT_COLOUR: Final = "#ff9896"
#: Colours of recordings, in turn: none is the path's.
RECORDING_COLOURS: Final = ("#ff7f0e", "#8c564b", "#e377c2", "#17becf", "#bcbd22", "#7f7f7f")
_POSE_COLOUR: Final = "#333333"
_FOOTPRINT_COLOUR: Final = "#7f7f7f"

#: Points sampled along each segment of the path (segments are arcs: 100 points draw a half
#: circle within a fraction of a pixel of its true shape at any usual size) ...
_SAMPLES_PER_SEGMENT: Final = 100
#: ... and along the whole path at most: a plan of thousands of segments gets fewer per segment.
#: A recording drawn over the path is thinned to as many points, evenly spread, its end kept.
_MAX_PATH_SAMPLES: Final = 100_000
#: Segments that get a footprint and a number at most: on longer plans, this many spread evenly
#: (always the last), as thousands would cover the path and cost minutes to draw.
MAX_MARKED_SEGMENTS: Final = 100

#: An odometry path drawn over a plan: a label, and the x and y positions (m) in the odom frame.
Recording = tuple[str, "ArrayLike", "ArrayLike"]


class PlotError(DiffbotError):
    """A figure cannot be made or saved: matplotlib is missing, or an output type is unknown."""


def require_matplotlib() -> None:
    """Check that matplotlib can be imported (without importing pyplot).

    Raises:
        PlotError: it is not installed; the message names the install command.
    """
    try:
        import matplotlib  # noqa: F401
    except ImportError as err:
        raise PlotError(
            f"plotting needs matplotlib, which is not installed: {INSTALL_COMMAND}"
        ) from err


def plan_figure(
    plan: Plan,
    params: DiffDriveParams,
    *,
    recordings: Iterable[Recording] = (),
    window: bool = False,
) -> Figure:
    """A figure of a plan: its path above, its wheel speeds below.

    The top axes (label ``"path"``) show the path in the odom frame with equal scales, sampled
    from :func:`~diffbot.trajectory.pose_at`; the start (square) and end (circle) poses with
    arrows along their headings; the robot's footprint at the end of each segment (the track,
    ``wheel_separation`` wide, and both wheels, ``2 wheel_radius`` long, at ``±b/2``); and each
    segment's number at its midpoint (footprints and numbers on :data:`MAX_MARKED_SEGMENTS`
    segments at most, spread evenly, see :func:`marked_segments`). The work is near linear in
    the number of segments. The bottom axes (label ``"wheel speeds"``) show both wheels'
    speeds (rpm, with rad/s on the right) over time, the motor limit as ``±limit`` lines, and the
    segments over the limit shaded.

    Args:
        plan: the plan (see :func:`diffbot.trajectory.plan`).
        params: the robot whose footprint is drawn.
        recordings: odometry paths to draw over the plan: ``(label, x, y)`` with x and y in m;
            each one's legend entry gives the distance (m) from its last position to the plan's
            end.
        window: make the figure through pyplot, so that :func:`show` opens it in a window;
            by default it is drawn on an Agg canvas, which needs no display.

    Returns:
        A matplotlib Figure (``figure.canvas.draw()`` renders it).

    Raises:
        PlotError: matplotlib is not installed, or a recording is empty or has x and y of
            different lengths.
    """
    require_matplotlib()
    figure = _figure(window)
    path_axes, speed_axes = figure.subplots(2, 1, height_ratios=(2, 1))
    path_axes.set_label("path")
    speed_axes.set_label("wheel speeds")
    _draw_path(path_axes, plan, params, list(recordings))
    _draw_speeds(speed_axes, plan)
    return figure


def _recorded_path(
    label: str, x: ArrayLike, y: ArrayLike
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """A recording's x and y (m) as float64 arrays; PlotError when empty or unequal."""
    import numpy as np

    rx = np.asarray(x, dtype=np.float64).ravel()
    ry = np.asarray(y, dtype=np.float64).ravel()
    if rx.size == 0 or rx.size != ry.size:
        raise PlotError(
            f"recording {label!r} needs as many x as y positions, and some: "
            f"got {rx.size} and {ry.size}"
        )
    return rx, ry


def _figure(window: bool) -> Figure:
    """An empty figure: through pyplot for a window, else on an Agg canvas (no display)."""
    if window:
        from matplotlib import pyplot

        return pyplot.figure(figsize=FIGURE_SIZE, dpi=FIGURE_DPI, layout="constrained")
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    figure = Figure(figsize=FIGURE_SIZE, dpi=FIGURE_DPI, layout="constrained")
    FigureCanvasAgg(figure)
    return figure


def recordings_figure(
    recordings: Iterable[Recording],
    *,
    differences: Iterable[Recording] = (),
    window: bool = False,
) -> Figure:
    """A figure of odometry paths alone, with no plan: each recording's path in the odom frame
    (equal scales, axes label ``"path"``), its start (square) and end (circle); and, when
    given, distances over time below (axes label ``"difference"``). A recording with a
    difference curve of the same label (a reference) is drawn dashed above the others.

    Args:
        recordings: ``(label, x, y)`` with x and y in m.
        differences: ``(label, t, d)``: times (s) and distances (m), such as between the
            odometry and a reference.
        window: make the figure through pyplot (see :func:`plan_figure`).

    Raises:
        PlotError: matplotlib is not installed, or a recording is empty or has x and y of
            different lengths.
    """
    require_matplotlib()
    figure = _figure(window)
    curves = list(differences)
    if curves:
        axes, below = figure.subplots(2, 1, height_ratios=(2, 1))
        below.set_label("difference")
        for number, (label, t, d) in enumerate(curves):
            colour = RECORDING_COLOURS[(2 * number + 1) % len(RECORDING_COLOURS)]
            below.plot(t, d, color=colour, linewidth=1.2, label=label)
        below.set_xlabel("time (s)")
        below.set_ylabel("distance (m)")
        below.set_title("Distance from the odometry")
        below.grid(True, color="#e0e0e0", linewidth=0.6)
        below.legend(loc="best", fontsize=8)
    else:
        axes = figure.subplots()
    axes.set_label("path")
    # A path with a difference curve is a reference: dashed above the others, so that where it
    # agrees with its odometry (on the same pixels) the odometry still shows between the dashes.
    compared = {label for label, _, _ in curves}
    for number, (label, x, y) in enumerate(recordings):
        rx, ry = _recorded_path(label, x, y)
        colour = RECORDING_COLOURS[number % len(RECORDING_COLOURS)]
        if label in compared:
            axes.plot(rx, ry, color=colour, linewidth=1.5, linestyle="--", label=label, zorder=4)
        else:
            axes.plot(rx, ry, color=colour, linewidth=1.5, label=label, zorder=3)
        axes.plot(rx[0], ry[0], "s", color=colour, markersize=7, zorder=2)
        axes.plot(rx[-1], ry[-1], "o", color=colour, markersize=7, zorder=2)
    _frame_axes(axes, "Odometry in the odom frame (start: square, end: circle)")
    return figure


def _draw_path(
    axes: Axes, plan: Plan, params: DiffDriveParams, recordings: list[Recording]
) -> None:
    import numpy as np

    starts = np.concatenate(([0.0], np.cumsum([s.duration for s in plan.segments])[:-1]))
    xs, ys = _path_points(plan)
    # The path is drawn above the markers, arrows and footprints so that it stays visible
    # through them; recordings go above it.
    axes.plot(xs, ys, color=PATH_COLOUR, linewidth=2.0, label="plan", zorder=3)
    final = plan.final_pose
    axes.plot(0.0, 0.0, "s", color=_POSE_COLOUR, markersize=9, label="start", zorder=2)
    axes.plot(final.x, final.y, "o", color=_POSE_COLOUR, markersize=9, label="end", zorder=2)
    extent = max(max(xs) - min(xs), max(ys) - min(ys), 4.0 * params.wheel_separation)
    for pose in (Pose(0.0, 0.0, 0.0), final):
        _heading_arrow(axes, pose, 0.08 * extent)
    for planned in (plan.segments[index] for index in marked_segments(len(plan.segments))):
        _footprint(axes, planned.end_pose, params)
        middle = pose_at(plan, float(starts[planned.index]) + 0.5 * planned.duration)
        axes.annotate(
            str(planned.index + 1),
            (middle.x, middle.y),
            xytext=(6, 6),
            textcoords="offset points",
            fontsize=9,
            zorder=2,
            bbox={"boxstyle": "round,pad=0.2", "facecolor": "white", "edgecolor": "none"},
        )
    for number, (label, x, y) in enumerate(recordings):
        rx, ry = _recorded_path(label, x, y)
        miss = end_distance(plan, float(rx[-1]), float(ry[-1]))
        if rx.size > _MAX_PATH_SAMPLES:  # far more points than pixels: every k-th, and the end
            keep = np.unique(
                np.append(
                    np.linspace(0, rx.size - 1, _MAX_PATH_SAMPLES, dtype=np.int64), rx.size - 1
                )
            )
            rx, ry = rx[keep], ry[keep]
        axes.plot(
            rx,
            ry,
            color=RECORDING_COLOURS[number % len(RECORDING_COLOURS)],
            linestyle="--",
            linewidth=1.2,
            label=f"{label} (ends {miss:.3g} m from the plan's end)",
            zorder=4,
        )
    _frame_axes(axes, "Path in the odom frame")


def marked_segments(count: int) -> list[int]:
    """The indexes of the segments, of ``count``, that get a footprint and a number: all of
    them up to :data:`MAX_MARKED_SEGMENTS`, else that many spread evenly, the last among them."""
    if count <= MAX_MARKED_SEGMENTS:
        return list(range(count))
    step = count / MAX_MARKED_SEGMENTS
    return sorted({count - 1 - int(k * step) for k in range(MAX_MARKED_SEGMENTS)})


def _path_points(plan: Plan) -> tuple[list[float], list[float]]:
    """Positions (m) sampled along the path, the segments' ends among them: each segment's
    exact arc (:func:`~diffbot.trajectory.advance`) evaluated at once for all samples."""
    import numpy as np

    segments = plan.segments
    per = max(2, min(_SAMPLES_PER_SEGMENT, _MAX_PATH_SAMPLES // len(segments)))
    fraction = np.linspace(0.0, 1.0, per)
    x0 = np.array([s.start_pose.x for s in segments])
    y0 = np.array([s.start_pose.y for s in segments])
    heading = np.array([0.0, *(s.end_heading for s in segments[:-1])])
    length = np.array([float(s.twist.linear) * s.duration for s in segments])
    turn = np.array([float(s.twist.angular) * s.duration for s in segments])
    half = 0.5 * turn[:, None] * fraction
    chord = length[:, None] * fraction * np.sinc(half / math.pi)
    mean = heading[:, None] + half
    xs = x0[:, None] + chord * np.cos(mean)
    ys = y0[:, None] + chord * np.sin(mean)
    xs[-1, -1], ys[-1, -1] = plan.final_pose.x, plan.final_pose.y
    return xs.ravel().tolist(), ys.ravel().tolist()


def _heading_arrow(axes: Axes, pose: Pose, length: float) -> None:
    tip = (pose.x + length * math.cos(pose.theta), pose.y + length * math.sin(pose.theta))
    axes.annotate(
        "",
        xy=tip,
        xytext=(pose.x, pose.y),
        arrowprops={"arrowstyle": "-|>", "color": _POSE_COLOUR, "linewidth": 1.2},
        zorder=2,
    )


def _footprint(axes: Axes, pose: Pose, params: DiffDriveParams) -> None:
    """The track (b wide, 2r long) and both wheels (each 2r long, with its side's radius) of the
    robot at a pose."""
    from matplotlib.patches import Rectangle
    from matplotlib.transforms import Affine2D

    r, b = params.wheel_radius, params.wheel_separation
    place = Affine2D().rotate(pose.theta).translate(pose.x, pose.y) + axes.transData
    track = Rectangle(
        (-r, -0.5 * b),
        2.0 * r,
        b,
        fill=False,
        edgecolor=_FOOTPRINT_COLOUR,
        linewidth=0.8,
        transform=place,
        zorder=1,
        gid="footprint",
    )
    axes.add_patch(track)
    width = 0.25 * r
    for side, radius in zip((1.0, -1.0), params.radii, strict=True):  # left (+y), then right
        wheel = Rectangle(
            (-radius, side * 0.5 * b - 0.5 * width),
            2.0 * radius,
            width,
            facecolor=_FOOTPRINT_COLOUR,
            edgecolor="none",
            transform=place,
            zorder=1,
            gid="wheel",
        )
        axes.add_patch(wheel)


#: How many times the fastest wheel speed (or 1 rpm) a motor limit may be and still be drawn.
_OFF_SCALE = 1000.0


def _draw_speeds(axes: Axes, plan: Plan) -> None:
    import numpy as np

    edges = np.concatenate(([0.0], np.cumsum([s.duration for s in plan.segments])))
    left = [rpm_from_rad_s(float(s.wheels.left)) for s in plan.segments]
    right = [rpm_from_rad_s(float(s.wheels.right)) for s in plan.segments]
    axes.stairs(left, edges, baseline=None, color=LEFT_COLOUR, linewidth=1.8, label="left wheel")
    axes.stairs(right, edges, baseline=None, color=RIGHT_COLOUR, linewidth=1.8, label="right wheel")
    peak = max(abs(v) for v in [*left, *right])
    if plan.limit is not None:
        limit = rpm_from_rad_s(plan.limit)
        label: str | None = f"motor limit ±{limit:.3g} rpm"
        if limit > _OFF_SCALE * max(peak, 1.0):
            # The speeds would be a flat line at zero beside it (and a limit near the largest
            # float has no axis at all): the legend names it, the axis scales to the wheels.
            axes.plot([], [], color=LIMIT_COLOUR, linestyle="--", label=f"{label}, off the scale")
        else:
            peak = max(peak, limit)
            for level in (limit, -limit):
                axes.axhline(level, color=LIMIT_COLOUR, linestyle="--", linewidth=1.2, label=label)
                label = None
        over_label: str | None = "over the limit"
        for first, last in _runs(sorted({found.index for found in plan.violations()})):
            axes.axvspan(
                float(edges[first]),
                float(edges[last + 1]),
                color=OVER_LIMIT_COLOUR,
                alpha=0.5,
                linewidth=0,
                zorder=0,
                label=over_label,
            )
            over_label = None
    margin = 0.15 * peak if peak > 0 else 1.0
    axes.set_ylim(min(-peak, *left, *right) - margin, max(*left, *right, peak) + margin)
    axes.set_xlim(0.0, float(edges[-1]))
    axes.set_xlabel("time (s)")
    axes.set_ylabel("wheel speed (rpm)")
    axes.set_title("Wheel speeds")
    axes.secondary_yaxis("right", functions=(_rad_s, _rpm)).set_ylabel("rad/s")
    axes.grid(True, color="#e0e0e0", linewidth=0.6)
    axes.legend(loc="best", fontsize=8)


def _runs(indexes: list[int]) -> list[tuple[int, int]]:
    """Sorted indexes as runs of consecutive ones, ``(first, last)``: one shaded span each."""
    runs: list[tuple[int, int]] = []
    for index in indexes:
        if runs and runs[-1][1] == index - 1:
            runs[-1] = (runs[-1][0], index)
        else:
            runs.append((index, index))
    return runs


def end_distance(plan: Plan, x: float, y: float) -> float:
    """How far (m) a position is from where the plan ends: a recording's miss."""
    final = plan.final_pose
    return math.hypot(x - final.x, y - final.y)


def require_window() -> None:
    """Check that matplotlib can open a window here (this imports pyplot).

    Raises:
        PlotError: matplotlib is not installed, or its backend only writes files (no display).
    """
    require_matplotlib()
    import matplotlib
    from matplotlib import pyplot  # noqa: F401  (picks the backend)

    backend = matplotlib.get_backend().lower()
    if backend in FILE_BACKENDS:
        raise PlotError(
            f"cannot open a window: matplotlib's backend here is {backend!r}, which only writes "
            "files (is there a display?); save the figure to a .png, .svg or .pdf file instead"
        )


def show() -> None:
    """Open the figures made with ``window=True`` in windows; return when they are closed.

    Raises:
        PlotError: see :func:`require_window`.
    """
    require_window()
    from matplotlib import pyplot

    pyplot.show()


def _rad_s(rpm: Any) -> Any:
    return rad_s_from_rpm(rpm)


def _rpm(rad_s: Any) -> Any:
    return rpm_from_rad_s(rad_s)


def file_format(path: str | os.PathLike[str]) -> str:
    """The type of figure file a path asks for by its suffix: ``"png"``, ``"svg"`` or ``"pdf"``.

    Raises:
        PlotError: a suffix other than ``.png``, ``.svg`` or ``.pdf`` (in any case), or none.
    """
    suffix = Path(path).suffix.lower()
    if suffix not in SUFFIXES:
        shown = repr(suffix) if suffix else "no suffix"
        raise PlotError(
            f"cannot tell what type of file to write from {shown} in {os.fspath(path)!r}: "
            "use .png, .svg or .pdf"
        )
    return suffix[1:]


def save(
    figure: Figure,
    path: str | os.PathLike[str],
    *,
    force: bool = False,
    inputs: Sequence[Path] = (),
) -> None:
    """Write a figure to a file, whole or not at all (see :func:`diffbot.io.outputs.atomic_text`).

    Args:
        figure: from :func:`plan_figure`.
        path: the file; its suffix (``.png``, ``.svg`` or ``.pdf``, any case) picks the type.
        force: replace the file if it exists.
        inputs: files the figure was made from, which it must never replace.

    Raises:
        PlotError: an unknown suffix.
        OutputExistsError: the file exists and ``force`` is not given.
        OutputError: it is not a regular file, lies in a missing directory, or is an input.
    """
    kind = file_format(path)
    # atomic_text's temporary file is opened for text; the figure goes to its byte stream.
    with atomic_text(Path(path), force=force, inputs=inputs) as out, warnings.catch_warnings():
        # matplotlib's notes on its layout (a legend of many recordings squeezes the axes) are
        # no business of the user's terminal: the figure is written all the same.
        warnings.simplefilter("ignore", UserWarning)
        figure.savefig(out.buffer, format=kind)


def _frame_axes(axes: Axes, title: str) -> None:
    """An x-y axes of the odom frame: equal scales in metres, a light grid, the legend."""
    axes.set_aspect("equal", adjustable="datalim")
    axes.set_xlabel("x (m)")
    axes.set_ylabel("y (m)")
    axes.set_title(title)
    axes.grid(True, color="#e0e0e0", linewidth=0.6)
    axes.legend(loc="best", fontsize=8)
