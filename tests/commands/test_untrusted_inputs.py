"""Hostile and broken inputs on the command line: one ``error:`` line and exit 2, quickly, or
the documented result; nothing runs from a description and nothing hangs."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import pytest
from cli_results import assert_one_error_line as assert_one_line_error
from click.testing import CliRunner, Result
from robots import two_wheel_urdf

from diffbot.cli import main

Write = Callable[[str, str], Path]

#: Longest any hostile input may take (s); before, some ran for minutes or never ended.
QUICK = 10.0


def run(runner: CliRunner, *args: str) -> Result:
    return runner.invoke(main, list(args), catch_exceptions=False, prog_name="diffbot")


def run_process(*args: str, cwd: Path | None = None) -> subprocess.CompletedProcess[str]:
    """Run diffbot in its own process, for inputs that used to block a reader forever."""
    return subprocess.run(
        [sys.executable, "-m", "diffbot", *args],
        capture_output=True,
        text=True,
        timeout=QUICK,
        cwd=cwd,
        check=False,
    )


def assert_process_error(done: subprocess.CompletedProcess[str], fragment: str) -> None:
    assert done.returncode == 2, done.stderr
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1, done.stderr
    assert lines[0].startswith("error: ")
    assert fragment in lines[0], lines[0]


def xacro_robot(write: Write, body: str, name: str = "robot.urdf.xacro") -> Path:
    return write(name, two_wheel_urdf(body=body, xacro=True))


def evaluated(write: Write, code: str) -> Path:
    """A description whose ``$(eval)`` runs ``code`` (kept in a property: the ``$(...)`` lexer
    ends at the first closing parenthesis)."""
    code = code.replace("&", "&amp;").replace('"', "&quot;")
    body = f'<xacro:property name="c" value="{code}"/><link name="x$(eval ${{c}})"/>'
    return xacro_robot(write, body)


# --- a description runs code -----------------------------------------------------------------


def test_eval_exec_in_a_description_runs_nothing(tmp_path: Path, write: Write) -> None:
    marker = tmp_path / "PWNED"
    path = evaluated(write, f"exec('import os; os.system(\\'touch {marker}\\')', {{}})")
    result = CliRunner().invoke(main, ["params", str(path)])
    assert_one_line_error(result, "refused in an untrusted description")
    assert "--trust" in result.stderr
    assert not marker.exists()


def test_eval_open_write_runs_only_with_trust(tmp_path: Path, write: Write) -> None:
    victim = tmp_path / "written.txt"
    path = evaluated(write, f"open('{victim}', 'w').write('1')")
    assert_one_line_error(run(CliRunner(), "params", str(path)), "refused")
    assert not victim.exists()
    trusted = run(CliRunner(), "urdf", str(path), "--trust")
    assert trusted.exit_code == 0, trusted.output
    assert victim.read_text() == "1"


@pytest.mark.parametrize(
    "body",
    [
        '<xacro:property name="c" value="open(\'/etc/passwd\').read()"/>'
        '<link name="$(eval ${c})"/>',
        "<link name=\"${xacro.load_yaml('/etc/passwd')}\"/>",
    ],
)
def test_a_file_outside_the_robot_never_reaches_urdf_output(write: Write, body: str) -> None:
    path = xacro_robot(write, body)
    result = run(CliRunner(), "urdf", str(path))
    assert_one_line_error(result, "refused in an untrusted description")
    assert "root:" not in result.stdout


# --- hangs --------------------------------------------------------------------------------


def test_a_macro_that_doubles_itself_thirty_times_is_refused_quickly(write: Write) -> None:
    macros = '<xacro:macro name="m0"><link name="leaf"/></xacro:macro>' + "".join(
        f'<xacro:macro name="m{k}"><xacro:m{k - 1}/><xacro:m{k - 1}/></xacro:macro>'
        for k in range(1, 31)
    )
    path = xacro_robot(write, macros + "<xacro:m30/>")
    start = time.perf_counter()
    result = run(CliRunner(), "urdf", str(path))
    assert time.perf_counter() - start < QUICK
    assert_one_line_error(result, "expansion refused")


def test_a_huge_integer_power_is_refused_quickly(write: Write) -> None:
    path = xacro_robot(write, '<link name="${9**9**9**9}"/>')
    start = time.perf_counter()
    result = run(CliRunner(), "params", str(path))
    assert time.perf_counter() - start < QUICK
    assert_one_line_error(result, "a power of more than")


def test_a_fifo_as_the_robot_is_refused_by_type(tmp_path: Path) -> None:
    os.mkfifo(tmp_path / "robot.urdf")
    done = run_process("params", str(tmp_path / "robot.urdf"))
    assert_process_error(done, "not a regular file")


def test_a_fifo_included_by_a_description_is_refused_by_type(tmp_path: Path, write: Write) -> None:
    os.mkfifo(tmp_path / "part.xacro")
    path = xacro_robot(write, '<xacro:include filename="part.xacro"/>')
    done = run_process("urdf", str(path))
    assert_process_error(done, "not a regular file")


def test_a_fifo_as_the_plan_file_is_refused_by_type(tmp_path: Path) -> None:
    os.mkfifo(tmp_path / "plan.yaml")
    done = run_process("plan", str(tmp_path / "plan.yaml"))
    assert_process_error(done, "not a regular file")


def test_a_fifo_in_place_of_a_cache_entry_is_ignored(
    tmp_path: Path, write: Write, monkeypatch: pytest.MonkeyPatch
) -> None:
    cache = tmp_path / "cache"
    monkeypatch.setenv("DIFFBOT_CACHE_DIR", str(cache))
    path = write("robot.urdf", two_wheel_urdf())
    first = run(CliRunner(), "params", str(path), "--json")
    (entry,) = cache.glob("params-*.json")
    entry.unlink()
    os.mkfifo(entry)
    again = run_process("params", str(path), "--json")
    assert again.returncode == 0, again.stderr
    assert json.loads(again.stdout) == json.loads(first.stdout)


# --- tracebacks, and nonsense accepted -------------------------------------------------


def test_a_joint_axis_of_two_numbers_is_one_error_line(write: Write) -> None:
    path = write("axis.urdf", two_wheel_urdf(left_axis="0 1"))
    assert_one_line_error(run(CliRunner(), "params", str(path)), "axis of 2 numbers, not 3")


def test_dev_zero_as_the_robot_is_refused_by_type() -> None:
    assert_one_line_error(run(CliRunner(), "params", "/dev/zero"), "not a regular file")


@pytest.mark.parametrize("radius", ["1e-320", "2000"])
def test_an_absurd_wheel_radius_is_refused_with_where_it_came_from(
    write: Write, radius: str
) -> None:
    path = write("r.urdf", two_wheel_urdf(radius=radius))
    result = run(CliRunner(), "params", str(path))
    assert_one_line_error(result, "wheel radius")
    assert "left_wheel" in result.stderr
    assert "--wheel-radius" in result.stderr


def test_a_wheel_separation_of_a_kilometre_is_refused(write: Write) -> None:
    path = write("b.urdf", two_wheel_urdf(left_xyz="0 600 0", right_xyz="0 -600 0"))
    result = run(CliRunner(), "params", str(path))
    assert_one_line_error(result, "wheel separation 1200 m")
    assert "--wheel-separation" in result.stderr


def test_an_absurd_radius_may_still_be_given_by_the_user(write: Write) -> None:
    path = write("r.urdf", two_wheel_urdf(radius="1e-320"))
    result = run(CliRunner(), "params", str(path), "--wheel-radius", "0.04", "--json")
    assert result.exit_code == 0, result.output
    assert json.loads(result.stdout)["wheel_radius"] == 0.04


@pytest.mark.parametrize("x", ["1e308", "2e6"])
def test_joint_origins_far_beyond_a_robot_are_refused(write: Write, x: str) -> None:
    path = write("far.urdf", two_wheel_urdf(left_xyz=f"{x} 0.1 0", right_xyz=f"{x} -0.1 0"))
    assert_one_line_error(run(CliRunner(), "params", str(path)), "from its parent link")


@pytest.mark.parametrize(
    ("name", "text"),
    [
        ("deep.json", "[" * 5000 + "]" * 5000),
        ("deep.yaml", "[" * 5000 + "]" * 5000),
        ("block.yaml", "\n".join(" " * k + "- " for k in range(0, 6000, 2))),
    ],
)
def test_plan_data_nested_thousands_deep_is_one_error_line(
    write: Write, name: str, text: str
) -> None:
    path = write(name, text)
    assert_one_line_error(run(CliRunner(), "plan", str(path)), "nested more than 32 deep")


def test_wheel_positions_of_1e300_are_skipped_and_reported(write: Write) -> None:
    rows = ["0,0,0", "1,1e300,-1e300", "2,-1e308,1e308", "3,0.1,0.1"]
    text = "time,front_left_wheel_joint,front_right_wheel_joint\n" + "\n".join(rows) + "\n"
    result = run(CliRunner(), "odom", str(write("big.csv", text)), "--json")
    assert result.exit_code == 0, result.output
    assert json.loads(result.stdout)["skipped"] == {"position out of range": 2}


@pytest.mark.parametrize("name", ["joints.mcap", "joints.db3", "bag/bag.mcap"])
def test_a_fifo_as_a_recording_or_inside_a_bag_folder_is_refused_by_type(
    tmp_path: Path, name: str
) -> None:
    fifo = tmp_path / name
    fifo.parent.mkdir(exist_ok=True)
    os.mkfifo(fifo)
    if fifo.parent != tmp_path:
        (fifo.parent / "metadata.yaml").write_text("rosbag2_bagfile_information: {}\n")
    given = fifo if fifo.parent == tmp_path else fifo.parent
    assert_process_error(run_process("odom", str(given)), "not a regular file")


def test_a_fifo_as_the_controllers_file_is_refused_by_type(tmp_path: Path) -> None:
    os.mkfifo(tmp_path / "controllers.yaml")
    done = run_process("params", "--controllers", str(tmp_path / "controllers.yaml"))
    assert_process_error(done, "not a regular file")


def test_a_fifo_beside_a_description_with_a_missing_package_is_skipped(
    tmp_path: Path, write: Write
) -> None:
    os.mkfifo(tmp_path / "jam.xacro")
    path = xacro_robot(write, '<xacro:include filename="$(find nowhere)/x.xacro"/>')
    assert_process_error(run_process("urdf", str(path)), "package 'nowhere' not found")


def test_bag_wheel_positions_of_1e308_are_skipped_and_reported(tmp_path: Path) -> None:
    from bags import write_bag

    names = ["front_left_wheel_joint", "front_right_wheel_joint"]
    second = 1_000_000_000
    messages = [
        (k * second, k * second, names, positions)
        for k, positions in enumerate(
            [[0.0, 0.0], [1e308, -1e308], [-1e300, 1e300], [0.1, 0.1]], start=1
        )
    ]
    bag = write_bag(tmp_path / "huge", messages)
    result = run(CliRunner(), "odom", str(bag), "--json")
    assert result.exit_code == 0, result.output
    assert json.loads(result.stdout)["skipped"] == {"position out of range": 2}


@pytest.mark.parametrize(
    ("command", "option"),
    [(["plan"], "-o"), (["simulate"], "--out"), (["odom", "IN"], "--out")],
)
def test_no_output_goes_over_a_file_the_description_included(
    tmp_path: Path, command: list[str], option: str
) -> None:
    package = tmp_path / "rover"
    shutil.copytree(Path(__file__).resolve().parents[2] / "docs/examples/rover", package)
    included = package / "urdf" / "wheel.xacro"
    before = included.read_bytes()
    recording = tmp_path / "in.csv"
    recording.write_text(
        "time,left_wheel_joint,right_wheel_joint\n0,0,0\n1,1,1\n", encoding="utf-8"
    )
    args = [str(recording) if arg == "IN" else arg for arg in command]
    result = CliRunner().invoke(
        main,
        [
            *args,
            "--robot",
            str(package / "urdf" / "rover.urdf.xacro"),
            "--package",
            f"rover_description={package}",
            option,
            str(included),
            "--force",
        ],
    )
    assert result.exit_code == 2, result.output
    assert result.stderr.startswith("error: ")
    assert "wheel.xacro" in result.stderr
    assert included.read_bytes() == before
