"""Hostile and broken inputs on the command line: one ``error:`` line and exit 2, quickly, or
the documented result; nothing runs from a description and nothing hangs."""

from __future__ import annotations

import json
import os
import shutil
import stat
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


# --- files a description names ------------------------------------------------------------------

#: A controllers file whose separation (0.5 m) differs from the robots' joints (0.2 m).
CONTROLLERS_YAML = """controller_manager:
  ros__parameters:
    diff_cont: {type: diff_drive_controller/DiffDriveController}
diff_cont:
  ros__parameters: {wheel_separation: 0.5, wheel_radius: 0.05}
"""

#: Content no error message may ever show (it would leak a file outside the description).
SECRET = "SECRET-a1b2c3"


def plugin_body(parameters: str) -> str:
    """A ros2_control Gazebo plugin naming ``parameters`` as its controllers file."""
    return (
        '<gazebo><plugin filename="gz_ros2_control-system" name="gz_ros2_control::Plugin">'
        f"<parameters>{parameters}</parameters></plugin></gazebo>"
    )


def plugin_robot(folder: Path, parameters: str, *, xacro: bool = False) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / ("robot.urdf.xacro" if xacro else "robot.urdf")
    path.write_text(two_wheel_urdf(body=plugin_body(parameters), xacro=xacro), encoding="utf-8")
    return path


def outside_files(tmp_path: Path) -> tuple[Path, Path]:
    """A readable controllers file and a secret, both outside the description's tree."""
    outside = tmp_path / "outside"
    outside.mkdir()
    good = outside / "controllers.yaml"
    good.write_text(CONTROLLERS_YAML, encoding="utf-8")
    secret = outside / "secret.yaml"
    secret.write_text(f"{SECRET}: [\n", encoding="utf-8")  # malformed: its text would show
    return good, secret


def separation(result: Result) -> float:
    assert result.exit_code == 0, result.output
    return float(json.loads(result.stdout)["wheel_separation"])


def test_a_controllers_file_named_by_absolute_path_outside_the_tree_is_refused(
    tmp_path: Path,
) -> None:
    good, secret = outside_files(tmp_path)
    for named in (good, secret):
        robot = plugin_robot(tmp_path / "robot", str(named))
        result = run(CliRunner(), "params", str(robot), "--json")
        assert_one_line_error(result, str(named), "--trust")
        assert SECRET not in result.output
    # Trusted, the description may name any file: the old behaviour.
    robot = plugin_robot(tmp_path / "robot", str(good))
    assert separation(run(CliRunner(), "params", str(robot), "--json", "--trust")) == 0.5


@pytest.mark.parametrize("named", ["/etc/passwd", "/proc/self/environ"])
def test_system_files_named_as_controllers_are_never_read(tmp_path: Path, named: str) -> None:
    robot = plugin_robot(tmp_path / "robot", named)
    result = run(CliRunner(), "params", str(robot))
    assert_one_line_error(result, named, "--trust")
    assert "root:" not in result.output
    assert "PATH=" not in result.output


def test_a_link_in_the_tree_to_a_controllers_file_outside_is_refused(tmp_path: Path) -> None:
    _, secret = outside_files(tmp_path)
    robot = plugin_robot(tmp_path / "robot", "config/controllers.yaml")
    (robot.parent / "config").mkdir()
    (robot.parent / "config" / "controllers.yaml").symlink_to(secret)
    result = run(CliRunner(), "params", str(robot))
    assert_one_line_error(result, "config/controllers.yaml", "--trust")
    assert SECRET not in result.output


def test_find_then_dot_dot_out_of_the_package_is_refused(tmp_path: Path) -> None:
    outside_files(tmp_path)
    package = tmp_path / "pkg"
    robot = plugin_robot(package / "urdf", "$(find pkg)/../outside/controllers.yaml", xacro=True)
    (package / "package.xml").write_text("<package/>", encoding="utf-8")
    result = run(CliRunner(), "params", str(robot), "--package", f"pkg={package}")
    assert_one_line_error(result, "outside/controllers.yaml", "--trust")


def test_a_controllers_file_in_the_package_is_read(tmp_path: Path) -> None:
    package = tmp_path / "pkg"
    robot = plugin_robot(package / "urdf", "$(find pkg)/config/controllers.yaml", xacro=True)
    (package / "package.xml").write_text("<package/>", encoding="utf-8")
    (package / "config").mkdir()
    (package / "config" / "controllers.yaml").write_text(CONTROLLERS_YAML, encoding="utf-8")
    result = run(CliRunner(), "params", str(robot), "--package", f"pkg={package}", "--json")
    assert separation(result) == 0.5


def test_a_relative_controllers_path_is_taken_from_the_description_folder(
    tmp_path: Path,
) -> None:
    robot = plugin_robot(tmp_path / "robot", "config/controllers.yaml")
    (robot.parent / "config").mkdir()
    (robot.parent / "config" / "controllers.yaml").write_text(CONTROLLERS_YAML, encoding="utf-8")
    elsewhere = tmp_path / "elsewhere"
    (elsewhere / "config").mkdir(parents=True)
    (elsewhere / "config" / "controllers.yaml").write_text(
        CONTROLLERS_YAML.replace("0.5", "0.7"), encoding="utf-8"
    )
    done = run_process("params", str(robot), "--json", cwd=elsewhere)
    assert done.returncode == 0, done.stderr
    assert json.loads(done.stdout)["wheel_separation"] == 0.5


def test_a_relative_controllers_path_never_reads_the_current_folder(tmp_path: Path) -> None:
    robot = plugin_robot(tmp_path / "robot", "secret.yaml")
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    (elsewhere / "secret.yaml").write_text(f"{SECRET}: [\n", encoding="utf-8")
    done = run_process("params", str(robot), "--json", cwd=elsewhere)
    assert done.returncode == 0, done.stderr
    assert SECRET not in done.stdout + done.stderr
    data = json.loads(done.stdout)
    assert any("does not exist here" in warning for warning in data["warnings"])
    assert data["wheel_separation"] == 0.2


def nested_package(tmp_path: Path, parameters: str) -> Path:
    """pkg/urdf/robot.urdf.xacro includes pkg/control/ros2_control.xacro, whose Gazebo plugin
    names ``parameters``; pkg/control/config/controllers.yaml gives 0.5 m, and a decoy at
    pkg/urdf/config/controllers.yaml (beside the top file) 0.7 m."""
    package = tmp_path / "pkg"
    (package / "control" / "config").mkdir(parents=True)
    (package / "urdf" / "config").mkdir(parents=True)
    (package / "package.xml").write_text("<package><name>pkg</name></package>", encoding="utf-8")
    (package / "control" / "ros2_control.xacro").write_text(
        '<?xml version="1.0"?>\n<robot xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        f"{plugin_body(parameters)}\n</robot>\n",
        encoding="utf-8",
    )
    (package / "control" / "config" / "controllers.yaml").write_text(
        CONTROLLERS_YAML, encoding="utf-8"
    )
    (package / "urdf" / "config" / "controllers.yaml").write_text(
        CONTROLLERS_YAML.replace("0.5", "0.7"), encoding="utf-8"
    )
    robot = package / "urdf" / "robot.urdf.xacro"
    include = '<xacro:include filename="../control/ros2_control.xacro"/>'
    robot.write_text(two_wheel_urdf(body=include, xacro=True), encoding="utf-8")
    return robot


def test_a_relative_controllers_path_is_taken_from_the_folder_of_the_file_that_names_it(
    tmp_path: Path,
) -> None:
    robot = nested_package(tmp_path, "config/controllers.yaml")
    done = run_process("params", str(robot), "--json", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert json.loads(done.stdout)["wheel_separation"] == 0.5


def test_an_included_file_names_its_controllers_by_package_as_before(tmp_path: Path) -> None:
    robot = nested_package(tmp_path, "$(find pkg)/control/config/controllers.yaml")
    done = run_process("params", str(robot), "--json", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert json.loads(done.stdout)["wheel_separation"] == 0.5


def test_a_relative_path_from_an_included_file_is_still_held_to_the_sandbox(
    tmp_path: Path,
) -> None:
    outside_files(tmp_path)
    robot = nested_package(tmp_path, "../../outside/secret.yaml")
    done = run_process("params", str(robot), cwd=tmp_path)
    assert_process_error(done, "--trust")
    assert "outside/secret.yaml" in done.stderr
    assert SECRET not in done.stdout + done.stderr


def test_a_fifo_named_as_controllers_in_the_tree_is_refused_by_type(tmp_path: Path) -> None:
    robot = plugin_robot(tmp_path / "robot", "controllers.yaml")
    os.mkfifo(robot.parent / "controllers.yaml")
    assert_process_error(run_process("params", str(robot)), "not a regular file")


def test_meshes_a_description_names_are_never_opened(tmp_path: Path) -> None:
    os.mkfifo(tmp_path / "wheel.stl")
    mesh = f'<link name="shell"><visual><geometry><mesh filename="file://{tmp_path}/wheel.stl"/>'
    robot = tmp_path / "robot" / "robot.urdf"
    robot.parent.mkdir()
    fixed = '<joint name="shell_joint" type="fixed"><parent link="base_link"/><child link="shell"/>'
    body = f"{mesh}</geometry></visual></link>{fixed}</joint>"
    robot.write_text(two_wheel_urdf(body=body), encoding="utf-8")
    done = run_process("params", str(robot), "--json")
    assert done.returncode == 0, done.stderr
    assert json.loads(done.stdout)["wheel_separation"] == 0.2


# --- no output over any input, nor over what is not a file ------------------------------------

ROVER = Path(__file__).resolve().parents[2] / "docs" / "examples" / "rover"
#: Wheel positions for the rover's joints and the bundled robot's.
RECORDING = (
    "time,left_wheel_joint,right_wheel_joint,front_left_wheel_joint,front_right_wheel_joint\n"
    "0,0,0,0,0\n1,1,1,1,1\n2,2,2,2,2\n"
)

#: Each command that writes --out, as a CSV (or plan text) file and as a bag; IN is a recording.
WRITERS = {
    "plan": (["plan", "straight 1"], "-o"),
    "plan bag": (["plan", "straight 1", "--rate", "10", "--bag"], "--out"),
    "simulate": (["simulate", "straight 1"], "--out"),
    "simulate bag": (["simulate", "straight 1", "--bag"], "--out"),
    "odom": (["odom", "IN"], "--out"),
    "odom bag": (["odom", "IN", "--bag"], "--out"),
}
BAG_WRITERS = [name for name in WRITERS if name.endswith("bag")]


def rover(tmp_path: Path) -> tuple[Path, list[str]]:
    """A copy of the example rover package, and the options that load it."""
    package = tmp_path / "rover"
    shutil.copytree(ROVER, package)
    robot = package / "urdf" / "rover.urdf.xacro"
    return package, ["--robot", str(robot), "--package", f"rover_description={package}"]


def writing(tmp_path: Path, writer: str, output: Path, *more: str) -> Result:
    """Run ``writer`` with ``--force`` and its output option at ``output``."""
    recording = tmp_path / "in.csv"
    recording.write_text(RECORDING, encoding="utf-8")
    command, option = WRITERS[writer]
    args = [str(recording) if arg == "IN" else arg for arg in command]
    return run(CliRunner(), *args, *more, option, str(output), "--force")


def snapshot(folder: Path) -> dict[str, bytes]:
    return {
        str(path.relative_to(folder)): path.read_bytes()
        for path in sorted(folder.rglob("*"))
        if path.is_file()
    }


@pytest.mark.parametrize("writer", list(WRITERS))
def test_force_never_writes_over_the_controllers_file_given(tmp_path: Path, writer: str) -> None:
    controllers = tmp_path / "controllers.yaml"
    shutil.copy(ROVER / "config" / "controllers.yaml", controllers)
    before = controllers.read_bytes()
    result = writing(tmp_path, writer, controllers, "--controllers", str(controllers))
    assert_one_line_error(result, "controllers.yaml", "input")
    assert controllers.read_bytes() == before


@pytest.mark.parametrize("writer", list(WRITERS))
def test_force_never_writes_over_the_controllers_file_a_plugin_names(
    tmp_path: Path, writer: str
) -> None:
    package, robot = rover(tmp_path)
    before = snapshot(package)
    result = writing(tmp_path, writer, package / "config" / "controllers.yaml", *robot)
    assert_one_line_error(result, "controllers.yaml", "input")
    assert snapshot(package) == before


@pytest.mark.parametrize("name", ["rover.urdf.xacro", "wheel.xacro"])
@pytest.mark.parametrize("writer", BAG_WRITERS)
def test_bag_force_never_replaces_the_description_or_its_includes(
    tmp_path: Path, writer: str, name: str
) -> None:
    package, robot = rover(tmp_path)
    before = snapshot(package)
    result = writing(tmp_path, writer, package / "urdf" / name, *robot)
    assert_one_line_error(result, name, "input")
    assert snapshot(package) == before


def test_calibrate_apply_to_never_writes_over_the_robot(tmp_path: Path) -> None:
    import diffbot.urdf

    source = tmp_path / "robot.urdf.xacro"
    robot = tmp_path / "robot.calibrated.urdf.xacro"  # where --apply-to would write
    shutil.copy(diffbot.urdf.BUNDLED_DESCRIPTION, source)
    shutil.copy(diffbot.urdf.BUNDLED_DESCRIPTION, robot)
    before = robot.read_bytes()
    result = run(
        CliRunner(),
        *("calibrate", "umbmark", "--side", "4", "--cw", "-0.31,-0.40", "--ccw", "0.12,-0.09"),
        *("--robot", str(robot), "--apply-to", str(source), "--force"),
    )
    assert_one_line_error(result, "robot.calibrated.urdf.xacro", "input")
    assert robot.read_bytes() == before


def make_device(path: Path, kind: str) -> None:
    if kind == "fifo":
        os.mkfifo(path)
        return
    try:
        os.mknod(path, 0o666 | stat.S_IFCHR, os.makedev(1, 3))  # what /dev/null is
    except PermissionError:
        pytest.skip("making a device node needs CAP_MKNOD")


@pytest.mark.parametrize("kind", ["fifo", "device"])
@pytest.mark.parametrize("writer", list(WRITERS))
def test_force_never_replaces_a_device_or_a_fifo(tmp_path: Path, writer: str, kind: str) -> None:
    node = tmp_path / "null"
    make_device(node, kind)
    mode = node.lstat().st_mode
    result = writing(tmp_path, writer, node)
    assert_one_line_error(result, "null", "not a regular file")
    assert node.lstat().st_mode == mode


# --- odom over several inputs ------------------------------------------------------------------


def recording(path: Path) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(RECORDING, encoding="utf-8")
    return path


def joint_bag(path: Path) -> Path:
    from bags import write_bag

    names = ["front_left_wheel_joint", "front_right_wheel_joint"]
    second = 1_000_000_000
    return write_bag(path, [(k * second, k * second, names, [k, k]) for k in range(1, 4)])


def test_odom_of_several_inputs_never_replaces_a_later_input(tmp_path: Path) -> None:
    first = recording(tmp_path / "c.csv")
    bag = joint_bag(tmp_path / "d")
    (tmp_path / "out").mkdir()
    later = bag.rename(tmp_path / "out" / "c")  # where the first input's bag would go
    before = snapshot(later)
    result = run(
        CliRunner(),
        *("odom", str(first), str(later / "d.db3"), "--out", str(tmp_path / "out")),
        *("--bag", "--force"),
    )
    assert_one_line_error(result, "out/c", "input")
    assert snapshot(later) == before


def test_odom_of_several_inputs_never_replaces_the_robot(tmp_path: Path) -> None:
    import diffbot

    a, b = recording(tmp_path / "in" / "a.csv"), recording(tmp_path / "in" / "b.csv")
    robot = tmp_path / "out" / "a"
    robot.parent.mkdir()
    robot.write_text(diffbot.expand().urdf, encoding="utf-8")  # the bundled robot, as URDF
    before = robot.read_bytes()
    result = run(
        CliRunner(),
        *("odom", str(a), str(b), "--robot", str(robot), "--out", str(tmp_path / "out")),
        *("--bag", "--force"),
    )
    assert_one_line_error(result, "out/a", "input")
    assert robot.read_bytes() == before


def test_odom_of_several_inputs_writes_nothing_inside_another_input(tmp_path: Path) -> None:
    a = recording(tmp_path / "a.csv")
    bag = joint_bag(tmp_path / "b")
    before = snapshot(bag)
    result = run(CliRunner(), "odom", str(a), str(bag), "--out", str(bag))
    assert_one_line_error(result, "lies inside")
    assert snapshot(bag) == before


# --- only regular files are opened, also those named inside bags -------------------------------


def fifo_storage_bag(path: Path) -> Path:
    """A bag whose metadata.yaml names a FIFO, without a storage suffix, as its storage."""
    bag = joint_bag(path)
    (storage,) = bag.glob("*.db3")
    storage.unlink()
    os.mkfifo(bag / "pipe")
    metadata = bag / "metadata.yaml"
    metadata.write_text(metadata.read_text().replace(storage.name, "pipe"), encoding="utf-8")
    return bag


def fifo_metadata_bag(path: Path) -> Path:
    bag = joint_bag(path)
    (bag / "metadata.yaml").unlink()
    os.mkfifo(bag / "metadata.yaml")
    return bag


@pytest.mark.parametrize("make", [fifo_storage_bag, fifo_metadata_bag])
@pytest.mark.parametrize(
    "command",
    [
        ["odom", "BAG"],
        ["plot", "straight 1", "--odom", "BAG", "-o", "OUT/x.png"],
        ["calibrate", "fit", "IN", "--truth", "BAG"],
        ["calibrate", "fit", "BAG"],
        ["params", "--robot", "BAG"],
        ["plan", "straight 1", "--robot", "BAG"],
    ],
)
def test_a_fifo_named_by_a_bag_never_blocks(
    tmp_path: Path, make: Callable[[Path], Path], command: list[str]
) -> None:
    bag = make(tmp_path / "bag")
    given = recording(tmp_path / "in.csv")
    args = [
        arg.replace("BAG", str(bag)).replace("OUT", str(tmp_path)).replace("IN", str(given))
        for arg in command
    ]
    assert_process_error(run_process(*args), "not a regular file")


def test_a_fifo_named_by_a_bag_never_blocks_a_worker(tmp_path: Path) -> None:
    bag = fifo_storage_bag(tmp_path / "bag")
    given = recording(tmp_path / "in.csv")
    done = run_process("odom", str(given), str(bag), "--jobs", "2", "--json")
    assert done.returncode == 1, done.stderr
    rows = [json.loads(line) for line in done.stdout.splitlines()]
    assert "error" not in rows[0]
    assert "not a regular file" in rows[1]["error"]


def test_a_fifo_as_the_truth_never_blocks(tmp_path: Path) -> None:
    given = recording(tmp_path / "in.csv")
    os.mkfifo(tmp_path / "truth.mcap")
    done = run_process("calibrate", "fit", str(given), "--truth", str(tmp_path / "truth.mcap"))
    assert_process_error(done, "not a regular file")


def test_no_output_goes_over_the_package_xml_that_named_the_package(tmp_path: Path) -> None:
    # $(find rover_description) is resolved by the <name> of rover/package.xml: it is read.
    rover = tmp_path / "rover"
    shutil.copytree(Path(__file__).parents[2] / "docs" / "examples" / "rover", rover)
    manifest = rover / "package.xml"
    before = manifest.read_bytes()
    result = CliRunner().invoke(
        main, ["urdf", str(rover / "urdf" / "rover.urdf.xacro"), "-o", str(manifest), "--force"]
    )
    assert_one_line_error(result, "is an input")
    assert manifest.read_bytes() == before


@pytest.mark.parametrize(
    "args",
    [
        ("plan", "-o", "out.csv/"),
        ("simulate", "--out", "out.csv/"),
        ("plot", "--output", "out.png/"),
        ("urdf", "-o", "out.urdf/"),
    ],
)
def test_a_file_output_ending_in_a_slash_is_refused_not_written_without_it(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, args: tuple[str, ...]
) -> None:
    # A trailing slash asks for a folder; the file used to appear under the name without it.
    monkeypatch.chdir(tmp_path)
    assert_one_line_error(run(CliRunner(), *args), "ends with a slash")
    assert list(tmp_path.iterdir()) == []


def test_a_bag_output_may_end_in_a_slash(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    result = run(CliRunner(), "plan", "-o", "run_bag/", "--bag")
    assert result.exit_code == 0, result.output
    assert (tmp_path / "run_bag" / "metadata.yaml").is_file()


@pytest.mark.parametrize("trust", [[], ["--trust"]])
def test_no_output_goes_over_a_yaml_file_the_description_loaded(
    tmp_path: Path, trust: list[str]
) -> None:
    # Trusted, xacro loads the YAML itself; it is an input all the same.
    props = tmp_path / "props.yaml"
    props.write_text("radius: 0.05\n", encoding="utf-8")
    description = tmp_path / "r.urdf.xacro"
    description.write_text(
        '<?xml version="1.0"?>\n<robot name="t" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '<xacro:property name="p" value="${xacro.load_yaml(\'props.yaml\')}"/>\n'
        "<link name=\"base_${p['radius']}\"/>\n</robot>\n",
        encoding="utf-8",
    )
    result = CliRunner().invoke(
        main, ["urdf", str(description), "-o", str(props), "--force", *trust]
    )
    assert_one_line_error(result, "is an input")
    assert props.read_text(encoding="utf-8") == "radius: 0.05\n"
