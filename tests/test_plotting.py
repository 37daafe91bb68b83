"""Plan figures: drawn where the plan goes, with the motor limit and over-limit times marked."""

from __future__ import annotations

import itertools
import struct
import subprocess
import sys
from pathlib import Path
from typing import TYPE_CHECKING

import pytest
from extras import need
from figures import axes_labelled, colour_at, near, rendered
from robots import BOT_50_RPM

from diffbot.errors import OutputExistsError
from diffbot.kinematics import rpm_from_rad_s
from diffbot.planfile import parse_plan
from diffbot.plotting import (
    LEFT_COLOUR,
    LIMIT_COLOUR,
    MAX_MARKED_SEGMENTS,
    OVER_LIMIT_COLOUR,
    PATH_COLOUR,
    RIGHT_COLOUR,
    PlotError,
    marked_segments,
    plan_figure,
    save,
    show,
)
from diffbot.trajectory import EXAMPLES, Plan, plan

if TYPE_CHECKING:
    from matplotlib.figure import Figure

need("matplotlib")


def _plan(text: str) -> Plan:
    return plan(parse_plan(text), BOT_50_RPM)


@pytest.fixture(scope="module")
def trajectory_a() -> Figure:
    figure = plan_figure(_plan(EXAMPLES["A"]), BOT_50_RPM)
    figure.canvas.draw()
    return figure


def test_a_saved_png_has_the_figure_size_in_pixels(trajectory_a: Figure, tmp_path: Path) -> None:
    target = tmp_path / "plan.png"
    save(trajectory_a, target)
    header = target.read_bytes()[:24]
    assert header[:8] == b"\x89PNG\r\n\x1a\n"
    width, height = struct.unpack(">II", header[16:24])
    assert (width, height) == (800, 900)


@pytest.mark.parametrize(
    ("x", "y"),
    [(0.0, 0.0), (0.25, 0.25), (0.0, 0.5), (-1.0, 0.5), (-1.25, 0.75), (-1.0, 1.0), (0.0, 1.0)],
)
def test_the_path_of_trajectory_a_is_drawn_through_its_known_points(
    trajectory_a: Figure, x: float, y: float
) -> None:
    # the start, the far point of the first half circle, its end, ..., the end (0, 1)
    assert near(rendered(trajectory_a), axes_labelled(trajectory_a, "path"), x, y, PATH_COLOUR)


@pytest.mark.parametrize(("x", "y"), [(-0.63, 0.77), (-0.37, 0.23), (0.13, 0.83)])
def test_points_away_from_the_path_are_background(trajectory_a: Figure, x: float, y: float) -> None:
    path = axes_labelled(trajectory_a, "path")
    assert not near(rendered(trajectory_a), path, x, y, PATH_COLOUR, radius=6)
    assert colour_at(rendered(trajectory_a), path, x, y) == (255, 255, 255)


def test_the_footprint_is_drawn_at_every_segment_end(trajectory_a: Figure) -> None:
    path = axes_labelled(trajectory_a, "path")
    from matplotlib.patches import Rectangle

    rectangles = [patch for patch in path.patches if isinstance(patch, Rectangle)]
    wheels = [patch for patch in rectangles if patch.get_gid() == "wheel"]
    tracks = [patch for patch in rectangles if patch.get_gid() == "footprint"]
    assert (len(tracks), len(wheels)) == (4, 8)
    # the track rectangle is b wide across the heading and 2r long along it
    assert (tracks[0].get_width(), tracks[0].get_height()) == pytest.approx((0.07, 0.135))


def test_each_wheel_is_drawn_with_its_sides_radius() -> None:
    from matplotlib.patches import Rectangle

    robot = BOT_50_RPM.replace(left_wheel_radius=0.03, right_wheel_radius=0.04)
    path = axes_labelled(plan_figure(_plan("straight 1"), robot), "path")
    wheels = [p for p in path.patches if isinstance(p, Rectangle) and p.get_gid() == "wheel"]
    # (length along the heading, offset across it): left at +b/2, right at -b/2
    drawn = sorted((w.get_width(), w.get_y() + 0.5 * w.get_height()) for w in wheels)
    assert [value for wheel in drawn for value in wheel] == pytest.approx(
        [0.06, 0.0675, 0.08, -0.0675], abs=1e-12
    )


def test_segments_are_numbered_at_their_midpoints(trajectory_a: Figure) -> None:
    path = axes_labelled(trajectory_a, "path")
    from matplotlib.text import Annotation

    labels = {
        text.get_text(): text.xy
        for text in path.texts
        if isinstance(text, Annotation) and text.get_text()
    }
    assert set(labels) == {"1", "2", "3", "4"}
    assert labels["1"] == pytest.approx((0.25, 0.25), abs=1e-9)
    assert labels["2"] == pytest.approx((-0.5, 0.5), abs=1e-9)


def test_the_wheel_speed_axes_draw_the_limit_at_plus_and_minus_50_rpm(
    trajectory_a: Figure,
) -> None:
    speeds = axes_labelled(trajectory_a, "wheel speeds")
    import numpy as np

    levels = sorted(
        float(np.asarray(line.get_ydata())[0])
        for line in speeds.lines
        if line.get_color() == LIMIT_COLOUR
    )
    assert levels == pytest.approx([-50.0, 50.0], rel=1e-9)
    # and it is drawn there: the dashed line is drawn a few pixels either side of t = 15 s
    assert any(
        near(rendered(trajectory_a), speeds, t, level, LIMIT_COLOUR, radius=1, tolerance=45)
        for t in (14.6, 14.8, 15.0, 15.2, 15.4)
        for level in (50.0,)
    )
    assert near(rendered(trajectory_a), speeds, 15.0, -50.0, LIMIT_COLOUR, radius=8, tolerance=45)


def test_the_wheel_speeds_are_drawn_at_their_rpm(trajectory_a: Figure) -> None:
    speeds = axes_labelled(trajectory_a, "wheel speeds")
    # exercise 6, the counter-clockwise half circle (0 s to 10 s): left 15.6 rpm, right 27.2 rpm
    assert near(rendered(trajectory_a), speeds, 5.0, 15.64, LEFT_COLOUR)
    assert near(rendered(trajectory_a), speeds, 5.0, 27.21, RIGHT_COLOUR)
    assert not near(rendered(trajectory_a), speeds, 5.0, 21.0, LEFT_COLOUR, radius=6)


@pytest.mark.parametrize("limit", [1e308 / 9.55, 1.7e307, 1.7e308, 1e6])
def test_a_limit_far_above_the_speeds_is_named_and_the_speeds_keep_their_scale(
    limit: float,
) -> None:
    # A limit near the largest float had no axis (NaN limits, or no room for the ticks). A robot
    # holds its limit within MOTOR_LIMIT_RANGE; a plan may be checked against any finite one.
    steps = plan(parse_plan(EXAMPLES["A"]), BOT_50_RPM, limit=limit)
    figure = plan_figure(steps, BOT_50_RPM)
    figure.canvas.draw()
    speeds = axes_labelled(figure, "wheel speeds")
    assert speeds.get_ylim()[1] < 40.0  # the fastest wheel turns at 27.3 rpm
    assert near(rendered(figure), speeds, 5.0, 15.64, LEFT_COLOUR)
    assert near(rendered(figure), speeds, 5.0, 27.21, RIGHT_COLOUR)
    labels = speeds.get_legend_handles_labels()[1]
    assert f"motor limit ±{rpm_from_rad_s(limit):.3g} rpm, off the scale" in labels


def test_a_plan_over_the_limit_is_shaded_while_it_is_over() -> None:
    # The middle straight, 1 m in 2 s, turns the wheels at 136 rpm: over 50 rpm from 10 s to 12 s.
    figure = plan_figure(_plan("straight 1 10s; straight 1 2s; straight 1 10s"), BOT_50_RPM)
    figure.canvas.draw()
    speeds = axes_labelled(figure, "wheel speeds")
    white = (255, 255, 255)
    for inside in (10.3, 11.0, 11.7):
        shade = colour_at(rendered(figure), speeds, inside, -13.0)
        assert shade != white
        assert shade[0] > shade[1]
        assert shade[0] > shade[2]
    for outside in (5.3, 9.6, 12.4, 17.3):
        assert colour_at(rendered(figure), speeds, outside, -13.0) == white
    assert not near(rendered(figure), speeds, 5.3, -13.0, OVER_LIMIT_COLOUR, radius=2)


def test_a_plan_within_the_limit_has_no_shading(trajectory_a: Figure) -> None:
    speeds = axes_labelled(trajectory_a, "wheel speeds")
    labels = speeds.get_legend_handles_labels()[1]
    assert "over the limit" not in labels
    assert "left wheel" in labels


def test_a_recording_is_drawn_with_its_distance_to_the_plan_end() -> None:
    import numpy as np

    figure = plan_figure(
        _plan(EXAMPLES["A"]),
        BOT_50_RPM,
        recordings=[("odometry", np.array([0.0, -0.5, 0.03]), np.array([0.0, 0.5, 1.04]))],
    )
    labels = axes_labelled(figure, "path").get_legend_handles_labels()[1]
    assert "odometry (ends 0.05 m from the plan's end)" in labels


def test_a_recording_with_unequal_x_and_y_is_refused() -> None:
    with pytest.raises(PlotError, match=r"recording 'odom' needs as many x as y positions"):
        plan_figure(_plan(EXAMPLES["A"]), BOT_50_RPM, recordings=[("odom", [0.0, 1.0], [0.0])])


@pytest.mark.parametrize(("suffix", "magic"), [(".svg", b"<?xml"), (".PDF", b"%PDF")])
def test_svg_and_pdf_are_written_by_suffix(tmp_path: Path, suffix: str, magic: bytes) -> None:
    target = tmp_path / f"plan{suffix}"
    save(plan_figure(_plan("straight 1"), BOT_50_RPM), target)
    assert target.read_bytes().startswith(magic)
    assert [p.name for p in tmp_path.iterdir()] == [target.name]


def test_an_unknown_suffix_is_refused_and_nothing_is_written(tmp_path: Path) -> None:
    target = tmp_path / "plan.jpeg"
    with pytest.raises(PlotError, match=r"from '\.jpeg' .*: use \.png, \.svg or \.pdf"):
        save(plan_figure(_plan("straight 1"), BOT_50_RPM), target)
    assert list(tmp_path.iterdir()) == []


def test_an_existing_file_is_replaced_only_with_force(tmp_path: Path) -> None:
    target = tmp_path / "plan.svg"
    target.write_bytes(b"mine")
    figure = plan_figure(_plan("straight 1"), BOT_50_RPM)
    with pytest.raises(OutputExistsError, match=r"plan\.svg exists: use force=True"):
        save(figure, target)
    assert target.read_bytes() == b"mine"
    save(figure, target, force=True)
    assert target.read_bytes().startswith(b"<?xml")


def test_a_window_figure_is_made_through_pyplot_and_refused_without_a_display() -> None:
    import matplotlib
    from matplotlib import pyplot

    matplotlib.use("agg")
    figure = plan_figure(_plan("straight 1"), BOT_50_RPM, window=True)
    try:
        assert figure.number in pyplot.get_fignums()  # type: ignore[attr-defined]
        assert {axes.get_label() for axes in figure.axes} >= {"path", "wheel speeds"}
        assert figure.get_size_inches() == pytest.approx((8.0, 9.0))
        with pytest.raises(PlotError, match=r"cannot open a window: .* 'agg', which only writes"):
            show()
    finally:
        pyplot.close(figure)
    assert figure.number not in pyplot.get_fignums()  # type: ignore[attr-defined]


def test_missing_matplotlib_names_the_install_command(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    with pytest.raises(PlotError, match=r"pip install 'diffbot-kinematics\[plot\]'"):
        plan_figure(_plan("straight 1"), BOT_50_RPM)


def test_importing_the_module_does_not_import_matplotlib() -> None:
    code = "import sys, diffbot.plotting; print('matplotlib' in sys.modules)"
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    )
    assert result.stdout.strip() == "False"


def test_a_long_plan_gets_footprints_and_numbers_on_a_hundred_segments_spread_evenly() -> None:
    from matplotlib.patches import Rectangle
    from matplotlib.text import Annotation

    count = 500
    path = axes_labelled(
        plan_figure(_plan("; ".join(["straight 0.1", "ccw 1 5"] * 250)), BOT_50_RPM), "path"
    )
    tracks = [p for p in path.patches if isinstance(p, Rectangle) and p.get_gid() == "footprint"]
    numbers = sorted(
        int(text.get_text())
        for text in path.texts
        if isinstance(text, Annotation) and text.get_text()
    )
    assert len(tracks) == MAX_MARKED_SEGMENTS == len(numbers)
    assert numbers[-1] == count
    assert set(numbers) == {index + 1 for index in marked_segments(count)}
    gaps = {b - a for a, b in itertools.pairwise(numbers)}
    assert gaps <= {4, 5, 6}  # spread evenly


@pytest.mark.parametrize("count", [1, 2, 99, 100, 101, 1000, 10_007])
def test_marked_segments_are_all_or_a_hundred_ending_at_the_last(count: int) -> None:
    marked = marked_segments(count)
    assert len(marked) == min(count, MAX_MARKED_SEGMENTS)
    assert marked == sorted(set(marked))
    assert marked[-1] == count - 1
    assert marked[0] >= 0


def test_the_sampled_path_goes_through_every_segment_end() -> None:
    import numpy as np

    p = _plan("; ".join(["straight 0.1", "ccw 0.3 40", "spin 30", "cw 0.2 100"] * 30))
    path = axes_labelled(plan_figure(p, BOT_50_RPM), "path")
    line = next(line for line in path.lines if line.get_label() == "plan")
    xs, ys = (np.asarray(v, dtype=np.float64) for v in line.get_data())
    ends = np.array([(s.end_pose.x, s.end_pose.y) for s in p.segments])
    for x, y in ends:
        assert float(np.min(np.hypot(xs - x, ys - y))) < 1e-9
    assert (xs[-1], ys[-1]) == (p.final_pose.x, p.final_pose.y)


def test_a_recording_of_more_points_than_pixels_is_thinned_keeping_its_end() -> None:
    import numpy as np

    count = 250_001
    x = np.linspace(0.0, 1.0, count)
    y = np.sin(x)
    path = axes_labelled(
        plan_figure(_plan("straight 1"), BOT_50_RPM, recordings=[("run", x, y)]), "path"
    )
    line = next(line for line in path.lines if str(line.get_label()).startswith("run"))
    xs, ys = (np.asarray(v, dtype=np.float64) for v in line.get_data())
    assert xs.size <= 100_001
    assert (xs[0], ys[0]) == (0.0, 0.0)
    assert (xs[-1], ys[-1]) == (x[-1], y[-1])
    assert np.all(np.diff(xs) > 0.0)  # in order, each point once
