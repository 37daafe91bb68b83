"""``diffbot plot``: the figure file it writes (read back pixel by pixel), and bad input."""

from __future__ import annotations

import itertools
import math
import struct
import sys
from pathlib import Path

import pytest
from cli_results import assert_one_error_line as assert_bad_input
from click.testing import CliRunner, Result
from extras import need
from figures import axes_labelled, colour_at, near, png_pixels

from diffbot.cli import main
from diffbot.kinematics import DiffDriveParams
from diffbot.planfile import parse_plan
from diffbot.plotting import (
    LEFT_COLOUR,
    PATH_COLOUR,
    RECORDING_COLOURS,
    RIGHT_COLOUR,
    plan_figure,
)
from diffbot.trajectory import EXAMPLES, plan

need("matplotlib")


def run(runner: CliRunner, *args: str) -> Result:
    return runner.invoke(main, ["plot", *args], catch_exceptions=False, prog_name="diffbot")


def test_example_a_draws_the_path_and_the_wheel_speeds(
    runner: CliRunner, params: DiffDriveParams, tmp_path: Path
) -> None:
    target = tmp_path / "a.png"
    result = run(runner, "--example", "A", "-o", str(target))
    assert result.exit_code == 0, result.output
    assert target.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert struct.unpack(">II", target.read_bytes()[16:24]) == (800, 900)
    image = png_pixels(target)
    # The same figure made in the library places the axes: where its data points fall in pixels.
    layout = plan_figure(plan(parse_plan(EXAMPLES["A"]), params), params)
    layout.canvas.draw()
    path = axes_labelled(layout, "path")
    for x, y in [(0.0, 0.0), (0.25, 0.25), (-0.5, 0.5), (-1.25, 0.75), (-0.5, 1.0), (0.0, 1.0)]:
        assert near(image, path, x, y, PATH_COLOUR), (x, y)
    for x, y in [(-0.63, 0.77), (-0.37, 0.23), (0.13, 0.83)]:
        assert colour_at(image, path, x, y) == (255, 255, 255), (x, y)
    speeds = axes_labelled(layout, "wheel speeds")
    # the first half circle: left 15.6 rpm, right 27.2 rpm; the straight after it: both 27.3 rpm
    assert near(image, speeds, 5.0, 15.64, LEFT_COLOUR)
    assert near(image, speeds, 5.0, 27.21, RIGHT_COLOUR)
    assert not near(image, speeds, 15.0, 15.64, LEFT_COLOUR, radius=6)


def test_a_recording_is_drawn_over_the_plan_and_its_miss_reported(
    runner: CliRunner, params: DiffDriveParams, tmp_path: Path
) -> None:
    # The wheels roll 1 m straight ahead in 10 s while the plan turns a quarter circle of 0.5 m
    # (in 1 s, no wheel turns that fast: 'diffbot odom' and plot --odom exit 1 on it).
    turns = 1.0 / params.wheel_radius
    rows = [f"{k},{k / 10 * turns!r},{k / 10 * turns!r}" for k in range(11)]
    csv = tmp_path / "straight.csv"
    csv.write_text(f"time,{params.left_joint},{params.right_joint}\n" + "\n".join(rows) + "\n")
    target = tmp_path / "run.png"
    result = run(runner, "ccw 0.5 90 10s", "--odom", str(csv), "-o", str(target))
    assert result.exit_code == 0, result.output
    miss = math.hypot(1.0 - 0.5, 0.0 - 0.5)
    assert (
        result.stdout == f"robot bundled\n{csv}: odometry ends {miss:.3g} m from the plan's end\n"
    )
    image = png_pixels(target)
    drawn = plan(parse_plan("ccw 0.5 90 10s"), params)
    layout = plan_figure(drawn, params, recordings=[(str(csv), [0.0, 1.0], [0.0, 0.0])])
    layout.canvas.draw()
    path = axes_labelled(layout, "path")
    # a thin dashed line, antialiased across two pixel rows: its colour is never reached exactly
    assert near(image, path, 0.8, 0.0, RECORDING_COLOURS[0], tolerance=45)
    assert not near(image, path, 0.8, 0.2, RECORDING_COLOURS[0], tolerance=45)
    assert near(image, path, 0.5, 0.5, PATH_COLOUR)
    assert not near(image, path, 0.8, 0.0, PATH_COLOUR, radius=5)


def test_svg_by_suffix_and_over_limit_segments_warned(runner: CliRunner, tmp_path: Path) -> None:
    result = run(runner, "straight 1 2s", "-o", str(tmp_path / "p.SVG"))
    assert result.exit_code == 0, result.output
    assert (tmp_path / "p.SVG").read_bytes().startswith(b"<?xml")
    assert result.stderr == (
        "warning: segment 1 (straight) is over the motor limit: shaded in the figure\n"
    )
    assert [p.name for p in tmp_path.iterdir()] == ["p.SVG"]


def test_an_existing_file_is_replaced_only_with_force(runner: CliRunner, tmp_path: Path) -> None:
    target = tmp_path / "a.png"
    target.write_bytes(b"mine")
    assert_bad_input(run(runner, "-o", str(target)), "a.png exists: use --force to overwrite it")
    assert target.read_bytes() == b"mine"
    assert run(runner, "-o", str(target), "--force").exit_code == 0
    assert target.read_bytes()[:4] == b"\x89PNG"


@pytest.mark.parametrize("option", ["--odom", "--controllers", "--robot"])
def test_an_input_is_never_overwritten(runner: CliRunner, tmp_path: Path, option: str) -> None:
    given = tmp_path / "input.png"
    given.write_text("not a figure\n")
    result = run(runner, option, str(given), "-o", str(given), "--force")
    assert_bad_input(result, "input.png is an input: refusing to overwrite it")
    assert given.read_text() == "not a figure\n"


@pytest.mark.parametrize(
    ("args", "fragment"),
    [
        ([], "nothing to do: give -o FILE (.png, .svg or .pdf) to write the figure, or --show"),
        (["-o", "a.jpg"], "from '.jpg' in 'a.jpg': use .png, .svg or .pdf"),
        (["-o", "a"], "from no suffix in 'a'"),
        (["-o", "no/such/dir/a.png"], "directory no/such/dir does not exist"),
        (["--odom", "missing.csv", "-o", "x.png"], "missing.csv: no such file or directory"),
        (["straight 1 zz", "-o", "x.png"], "zz"),
    ],
)
def test_bad_input_is_one_error_line_and_writes_nothing(
    runner: CliRunner,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    args: list[str],
    fragment: str,
) -> None:
    monkeypatch.chdir(tmp_path)
    assert_bad_input(run(runner, *args), fragment)
    assert list(tmp_path.iterdir()) == []


def test_missing_matplotlib_names_the_install_command(
    runner: CliRunner, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    result = run(runner, "-o", str(tmp_path / "a.png"))
    assert_bad_input(result, "pip install 'diffbot-kinematics[plot]'")
    assert list(tmp_path.iterdir()) == []


def test_show_without_a_display_says_so_before_writing(runner: CliRunner, tmp_path: Path) -> None:
    import matplotlib

    matplotlib.use("agg")
    result = run(runner, "--show", "-o", str(tmp_path / "a.png"))
    assert_bad_input(result, "cannot open a window: matplotlib's backend here is 'agg'")
    assert list(tmp_path.iterdir()) == []


def test_a_ramped_plan_is_drawn_at_its_cruise_speeds(runner: CliRunner, tmp_path: Path) -> None:
    result = run(runner, "straight 1", "--max-accel", "0.1", "-o", str(tmp_path / "r.svg"))
    assert result.exit_code == 0, result.output
    assert result.stderr == (
        "warning: a ramped plan is drawn at its cruise speeds: the ramps are not drawn\n"
    )
    assert (tmp_path / "r.svg").read_bytes().startswith(b"<?xml")


def test_a_recording_is_read_in_chunks_as_odom_reads_it(
    runner: CliRunner, params: DiffDriveParams, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import json

    from diffbot import recordings

    rows = [f"{k / 10},{k * 0.05!r},{k * 0.07!r}" for k in range(300)]
    csv = tmp_path / "curve.csv"
    csv.write_text(f"time,{params.left_joint},{params.right_joint}\n" + "\n".join(rows) + "\n")
    odom = runner.invoke(main, ["odom", str(csv), "--json"], catch_exceptions=False)
    final = json.loads(odom.stdout)["final_pose"]

    def whole(*args: object, **kwargs: object) -> object:
        raise AssertionError("the whole recording was read into memory")

    monkeypatch.setattr(recordings, "read_recording", whole)
    result = run(runner, "straight 1", "--odom", str(csv), "-o", str(tmp_path / "p.png"))
    assert result.exit_code == 0, result.output
    miss = math.hypot(final["x"] - 1.0, final["y"])
    assert (
        result.stdout == f"robot bundled\n{csv}: odometry ends {miss:.3g} m from the plan's end\n"
    )


def test_a_figure_of_many_recordings_prints_no_matplotlib_warning(tmp_path: Path) -> None:
    import subprocess

    # Sixty legend entries squeeze the axes to nothing: matplotlib said so on the terminal.
    joints = Path(__file__).parents[2] / "docs" / "examples" / "joints.csv"
    odom = [arg for _ in range(60) for arg in ("--odom", str(joints))]
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "diffbot",
            "plot",
            "straight 1",
            *odom,
            "-o",
            str(tmp_path / "p.png"),
        ],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    assert done.returncode == 0, done.stderr[-300:]
    assert "Warning" not in done.stderr
    assert (tmp_path / "p.png").stat().st_size > 0


@pytest.mark.parametrize(
    ("cell", "message"),
    [
        ("1e308", "line 4: y must be a finite number >= -1e+09 and <= 1e+09 m, got 1e+308"),
        ("nan", "line 4: not a finite time and pose"),
        ("inf", "line 4: not a finite time and pose"),
    ],
)
def test_a_true_pose_past_the_boundary_is_one_error_naming_its_line(
    runner: CliRunner, params: DiffDriveParams, tmp_path: Path, cell: str, message: str
) -> None:
    # matplotlib failed with a traceback on 1e308, and NaN was drawn as nothing, silently.
    turns = 1.0 / params.wheel_radius
    rows = [f"{k},{k / 10 * turns!r},{k / 10 * turns!r},{k / 10},0,0" for k in range(11)]
    rows[2] = rows[2].rsplit(",", 2)[0] + f",{cell},0"
    csv = tmp_path / "run.csv"
    csv.write_text(f"time,{params.left_joint},{params.right_joint},x,y,theta\n" + "\n".join(rows))
    target = tmp_path / "run.png"
    result = run(runner, "straight 1 10s", "--odom", str(csv), "-o", str(target))
    assert result.exit_code == 2, result.output
    assert result.stderr == f"error: {csv}: {message}\n"
    assert not target.exists()


def test_a_simulated_runs_true_path_is_drawn_beside_its_odometry(
    runner: CliRunner, params: DiffDriveParams, tmp_path: Path
) -> None:
    # The wheels report 1 m straight ahead in 10 s; the true pose went along a line 0.3 m to
    # the left.
    turns = 1.0 / params.wheel_radius
    rows = [f"{k},{k / 10 * turns!r},{k / 10 * turns!r},{k / 10},0.3,0" for k in range(11)]
    csv = tmp_path / "run.csv"
    header = f"time,{params.left_joint},{params.right_joint},x,y,theta"
    csv.write_text(header + "\n" + "\n".join(rows) + "\n")
    target = tmp_path / "run.png"
    result = run(runner, "straight 1 10s", "--odom", str(csv), "-o", str(target))
    assert result.exit_code == 0, result.output
    assert result.stdout.splitlines() == [
        "robot bundled",
        f"{csv}: odometry ends 0 m from the plan's end",
        f"{csv} true pose: ends 0.3 m from the plan's end",
    ]
    image = png_pixels(target)
    drawn = plan(parse_plan("straight 1 10s"), params)
    recordings = [(str(csv), [0.0, 1.0], [0.0, 0.0]), (f"{csv} true pose", [0.0, 1.0], [0.3, 0.3])]
    layout = plan_figure(drawn, params, recordings=recordings)
    layout.canvas.draw()
    path = axes_labelled(layout, "path")
    assert near(image, path, 0.5, 0.3, RECORDING_COLOURS[1], tolerance=45)
    assert not near(image, path, 0.5, 0.15, RECORDING_COLOURS[1], tolerance=45)
    assert near(image, path, 0.5, 0.0, PATH_COLOUR)


def test_a_run_on_stdin_is_drawn_with_its_true_path(
    runner: CliRunner, params: DiffDriveParams, tmp_path: Path
) -> None:
    # As `diffbot simulate ... | diffbot plot --odom -`: read once for the odometry and once for
    # the true path, both named '-'.
    turns = 1.0 / params.wheel_radius
    rows = [f"{k},{k / 10 * turns!r},{k / 10 * turns!r},{k / 10},0.3,0" for k in range(11)]
    header = f"time,{params.left_joint},{params.right_joint},x,y,theta"
    target = tmp_path / "run.png"
    args = ["plot", "straight 1 10s", "--odom", "-", "-o", str(target)]
    result = runner.invoke(main, args, input=header + "\n" + "\n".join(rows) + "\n")
    assert result.exit_code == 0, result.output
    assert result.stdout.splitlines() == [
        "robot bundled",
        "-: odometry ends 0 m from the plan's end",
        "- true pose: ends 0.3 m from the plan's end",
    ]
    image = png_pixels(target)
    drawn = plan(parse_plan("straight 1 10s"), params)
    recordings = [("-", [0.0, 1.0], [0.0, 0.0]), ("- true pose", [0.0, 1.0], [0.3, 0.3])]
    layout = plan_figure(drawn, params, recordings=recordings)
    layout.canvas.draw()
    path = axes_labelled(layout, "path")
    assert near(image, path, 0.5, 0.3, RECORDING_COLOURS[1], tolerance=45)
    twice = runner.invoke(main, [*args, "--odom", "-", "--force"], input=header + "\n")
    assert_bad_input(twice, "--odom - reads standard input, which can be read once")


def test_a_long_recording_is_kept_thinned_as_it_is_read(
    runner: CliRunner, params: DiffDriveParams, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # A recording of any length takes the same memory: evenly spread poses, its first and its
    # last among them, at most twice KEPT_POSES.
    from diffbot import plotting
    from diffbot.commands import plot as command

    monkeypatch.setattr(command, "KEPT_POSES", 25, raising=False)
    drawn: list[tuple[str, object, object]] = []

    def figure(*args: object, recordings: list[tuple[str, object, object]], **kw: object) -> object:
        drawn.extend(recordings)
        return plan_figure(*args, recordings=recordings, **kw)  # type: ignore[arg-type]

    monkeypatch.setattr(plotting, "plan_figure", figure)
    turns = 1.0 / params.wheel_radius
    rows = [f"{k / 100},{k / 1000 * turns!r},{k / 1000 * turns!r}" for k in range(1001)]
    csv = tmp_path / "run.csv"
    csv.write_text(f"time,{params.left_joint},{params.right_joint}\n" + "\n".join(rows) + "\n")
    result = run(runner, "straight 1 10s", "--odom", str(csv), "-o", str(tmp_path / "run.png"))
    assert result.exit_code == 0, result.output
    ((label, x, _),) = drawn
    assert label == str(csv)
    xs = [float(v) for v in x]  # type: ignore[attr-defined]
    assert len(xs) <= 2 * 25 + 1
    assert xs[0] == 0.0
    assert xs[-1] == pytest.approx(1.0, abs=1e-12)
    steps = {round(b - a, 9) for a, b in itertools.pairwise(xs[:-1])}
    assert len(steps) == 1, steps
