"""``diffbot plot --odom`` without a plan, with encoder counts; ``--example umbmark --side``."""

from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner, Result
from extras import need
from figures import axes_labelled, near, rendered
from pioneer import COUNTS_PER_REV, counts_csv, reference_bag, urdf

from diffbot.cli import main
from diffbot.plotting import PATH_COLOUR, RECORDING_COLOURS, recordings_figure

need("matplotlib")


def run(runner: CliRunner, *args: str) -> Result:
    return runner.invoke(main, ["plot", *args], prog_name="diffbot")


def test_the_umbmark_square_takes_its_side(runner: CliRunner, tmp_path: Path) -> None:
    target = tmp_path / "square.png"
    result = run(runner, "--example", "umbmark", "--side", "1.13", "-o", str(target))
    assert result.exit_code == 0, result.output
    assert target.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_recordings_without_a_plan_are_drawn_alone_in_counts(
    runner: CliRunner, tmp_path: Path
) -> None:
    csv = counts_csv(tmp_path)
    target = tmp_path / "run.png"
    args = ["--odom", str(csv), "--robot", str(urdf(tmp_path)), "-o", str(target)]
    result = run(runner, *args, "--counts-per-rev", repr(COUNTS_PER_REV), "--wrap", "65536")
    assert result.exit_code == 0, result.output
    # The run ends 1 m along x and 0.5 m along y (pioneer.RUN_END); no plan's end is named.
    robot = tmp_path / "pioneer.urdf"
    assert result.stdout == f"robot {robot}\n{csv}: odometry ends at x 1 m, y 0.5 m\n"
    assert result.stderr == ""


@pytest.mark.parametrize("plan", [[], ["--example", "A"]], ids=["alone", "over a plan"])
def test_a_recording_with_implausible_steps_exits_1_with_the_warning_odom_gives(
    runner: CliRunner, tmp_path: Path, plan: list[str]
) -> None:
    # Raw counts read as radians: 'diffbot odom' warns of 100 implausible steps and exits 1, as
    # the pose is not to be trusted; plot --odom of the same recording exited 0.
    csv = counts_csv(tmp_path)
    robot = ["--robot", str(urdf(tmp_path))]
    odom = runner.invoke(main, ["odom", str(csv), *robot], prog_name="diffbot")
    assert odom.exit_code == 1, odom.output
    target = tmp_path / "raw.png"
    result = run(runner, *plan, "--odom", str(csv), *robot, "-o", str(target))
    assert result.exit_code == odom.exit_code, result.output + result.stderr
    assert result.stderr == odom.stderr
    assert "100 implausible steps" in result.stderr
    assert target.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"  # drawn all the same
    # Read as counts, the same recording is plausible and both exit 0.
    counts = ["--counts-per-rev", repr(COUNTS_PER_REV), "--wrap", "65536"]
    again = run(runner, *plan, "--odom", str(csv), *robot, *counts, "-o", str(target), "--force")
    assert again.exit_code == 0, again.output + again.stderr
    # Of several recordings, the last line says how many are not to be trusted, as odom's does.
    plausible = tmp_path / "plausible.csv"
    header = csv.read_text(encoding="utf-8").splitlines()[0]
    plausible.write_text(f"{header}\n0,0,0\n1,0.1,0.1\n", encoding="utf-8")
    several = ["--odom", str(plausible), "--odom", str(csv)]
    both = run(runner, *plan, *several, *robot, "-o", str(target), "--force")
    assert both.exit_code == 1, both.output + both.stderr
    assert both.stderr.splitlines()[-1] == "warning: 1 of 2 recordings have implausible steps"


def test_the_recordings_figure_has_no_plan_in_it() -> None:
    figure = recordings_figure([("run", [0.0, 1.0, 1.0], [0.0, 0.0, 0.5])])
    figure.canvas.draw()
    axes = axes_labelled(figure, "path")
    image = rendered(figure)
    assert near(image, axes, 0.5, 0.0, RECORDING_COLOURS[0])
    assert not near(image, axes, 0.5, 0.0, PATH_COLOUR)
    assert [text.get_text() for text in axes.get_legend().get_texts()] == ["run"]


def test_a_reference_is_drawn_beside_the_odometry_with_their_distance_over_time(
    runner: CliRunner, tmp_path: Path
) -> None:
    bag = reference_bag(tmp_path, drift=0.002)
    target = tmp_path / "ref.png"
    args = ["--odom", str(bag), "--robot", str(urdf(tmp_path)), "--reference", "/odom"]
    args += ["--counts-per-rev", repr(COUNTS_PER_REV), "--wrap", "65536", "-o", str(target)]
    result = run(runner, *args)
    assert result.exit_code == 0, result.output
    # Known values: the reference runs 0.002 m * k ahead at sample k (see test_odom_recordings).
    assert result.stdout.splitlines() == [
        f"{bag} /odom: final 0.2 m, max 0.2 m, RMS 0.116 m from the odometry",
        f"robot {tmp_path / 'pioneer.urdf'}",
        f"{bag}: odometry ends at x 1 m, y 0.5 m",
        f"{bag} /odom: ends at x 1.2 m, y 0.5 m",
    ]


def test_the_difference_axes_show_the_distance_over_time() -> None:
    figure = recordings_figure(
        [("run", [0.0, 1.0], [0.0, 0.0]), ("run /odom", [0.0, 1.1], [0.0, 0.0])],
        differences=[("run /odom", [0.0, 1.0], [0.0, 0.1])],
    )
    figure.canvas.draw()
    below = axes_labelled(figure, "difference")
    assert [line.get_ydata().tolist() for line in below.get_lines()] == [[0.0, 0.1]]
    assert near(rendered(figure), below, 0.5, 0.05, RECORDING_COLOURS[1])


def test_a_reference_on_top_of_its_odometry_leaves_the_odometry_visible() -> None:
    # A controller's /odom that agrees with diffbot's odometry lies on the same pixels: drawn
    # solid over it, the odometry vanished from the picture and only its legend entry remained.
    along = [0.1 * k for k in range(11)]
    flat = [0.0] * 11
    figure = recordings_figure(
        [("run", along, flat), ("run /odom", along, flat)],
        differences=[("run /odom", along, flat)],
    )
    figure.canvas.draw()
    axes = axes_labelled(figure, "path")
    image = rendered(figure)
    seen = [
        (
            near(image, axes, x, 0.0, RECORDING_COLOURS[0]),
            near(image, axes, x, 0.0, RECORDING_COLOURS[1]),
        )
        for x in along[1:-1]
    ]
    assert sum(odometry for odometry, _ in seen) >= 5, seen
    assert sum(reference for _, reference in seen) >= 5, seen


def test_a_reference_named_without_its_leading_slash_is_drawn_as_the_reference(
    runner: CliRunner, tmp_path: Path
) -> None:
    bag = reference_bag(tmp_path, drift=0.002)
    args = ["--odom", str(bag), "--robot", str(urdf(tmp_path)), "--reference", "odom"]
    args += ["--counts-per-rev", repr(COUNTS_PER_REV), "--wrap", "65536"]
    result = run(runner, *args, "-o", str(tmp_path / "ref.png"))
    assert result.exit_code == 0, result.output
    assert result.stdout.splitlines()[1:] == [
        f"robot {tmp_path / 'pioneer.urdf'}",
        f"{bag}: odometry ends at x 1 m, y 0.5 m",
        f"{bag} /odom: ends at x 1.2 m, y 0.5 m",
    ]


VELOCITIES = Path(__file__).parents[2] / "docs" / "examples" / "wheel_velocities.csv"


def test_odom_recordings_are_read_for_their_velocities_with_feedback_velocity(
    runner: CliRunner, tmp_path: Path
) -> None:
    """A recording of wheel velocities only (positions stuck at 0): 0.2 m straight, then a
    quarter turn in place, as ``diffbot odom --feedback velocity`` reads it."""
    target = tmp_path / "velocities.png"
    result = run(runner, "--odom", str(VELOCITIES), "--feedback", "velocity", "-o", str(target))
    assert result.exit_code == 0, result.output
    assert result.stdout.splitlines()[-1] == f"{VELOCITIES}: odometry ends at x 0.2 m, y 0 m"
    # Read for positions, the same file is refused, naming the option.
    refused = run(runner, "--odom", str(VELOCITIES), "-o", str(tmp_path / "other.png"))
    assert refused.exit_code == 2
    assert refused.stderr.count("\n") == 1
    assert "--feedback velocity" in refused.stderr
    assert not (tmp_path / "other.png").exists()


def test_a_controllers_position_feedback_false_reads_the_velocities(
    runner: CliRunner, tmp_path: Path
) -> None:
    controllers = tmp_path / "controllers.yaml"
    controllers.write_text(
        "controller_manager:\n  ros__parameters:\n    diff_drive_base_controller:\n"
        "      type: diff_drive_controller/DiffDriveController\n"
        "diff_drive_base_controller:\n  ros__parameters:\n"
        "    left_wheel_names: [front_left_wheel_joint]\n"
        "    right_wheel_names: [front_right_wheel_joint]\n"
        "    position_feedback: false\n"
    )
    args = ["--odom", str(VELOCITIES), "--controllers", str(controllers)]
    result = run(runner, *args, "-o", str(tmp_path / "a.png"))
    assert result.exit_code == 0, result.output
    assert result.stdout.splitlines()[-1] == f"{VELOCITIES}: odometry ends at x 0.2 m, y 0 m"
    # --feedback overrides the file.
    overridden = run(runner, *args, "--feedback", "position", "-o", str(tmp_path / "b.png"))
    assert overridden.exit_code == 2
    assert "--feedback velocity" in overridden.stderr


def test_feedback_without_a_recording_is_one_error(runner: CliRunner, tmp_path: Path) -> None:
    result = run(runner, "--feedback", "velocity", "-o", str(tmp_path / "a.png"))
    assert result.exit_code == 2
    assert result.stderr == (
        "error: --feedback says how --odom recordings are read: give one with --odom\n"
    )
