"""Outputs: created exclusively, forced only over what this tool writes, never over an input,
never left half-written or as debris, and a full disk or a closed stdout is one error line."""

from __future__ import annotations

import os
import signal
import sqlite3
import stat
import subprocess
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
from click.testing import CliRunner
from robots import two_wheel_urdf

import diffbot
from diffbot.cli import main
from diffbot.errors import OutputError
from diffbot.io.outputs import check_output_name, move_new, replace_bag, write_text_atomic

Write = Callable[[str, str], Path]


def one_error_line(stderr: str, fragment: str) -> None:
    lines = stderr.strip().splitlines()
    assert len(lines) == 1, stderr
    assert lines[0].startswith("error: ")
    assert fragment in lines[0], lines[0]


def debris(folder: Path) -> list[str]:
    """Hidden temporary files or folders an output left behind."""
    return sorted(p.name for p in folder.iterdir() if p.name.startswith("."))


# --- exclusive creation -----------------------------------------------------------------------


def test_an_output_created_by_another_program_meanwhile_is_left_alone(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    target = tmp_path / "same.csv"
    chmod = os.chmod

    def other_program_writes_first(path: Any, mode: int) -> None:
        # after this program's checks, before its file is moved into place
        target.write_text("the other program's result", encoding="utf-8")
        chmod(path, mode)

    monkeypatch.setattr(os, "chmod", other_program_writes_first)
    with pytest.raises(diffbot.OutputExistsError, match="created by another program"):
        write_text_atomic(target, "mine", force=False)
    assert target.read_text(encoding="utf-8") == "the other program's result"
    assert debris(tmp_path) == []


def test_a_directory_is_moved_only_where_nothing_is(tmp_path: Path) -> None:
    new = tmp_path / "new"
    new.mkdir()
    (new / "metadata.yaml").write_text("new", encoding="utf-8")
    taken = tmp_path / "taken"
    taken.mkdir()
    (taken / "metadata.yaml").write_text("old", encoding="utf-8")
    with pytest.raises(diffbot.OutputExistsError, match="created by another program"):
        replace_bag(new, taken, force=False)
    assert (taken / "metadata.yaml").read_text(encoding="utf-8") == "old"
    move_new(new, tmp_path / "free")
    assert (tmp_path / "free" / "metadata.yaml").read_text(encoding="utf-8") == "new"
    assert not new.exists()


# --- force over a directory -------------------------------------------------------------------


def test_force_over_a_bag_folder_with_other_files_refuses_and_keeps_them(tmp_path: Path) -> None:
    folder = tmp_path / "run"
    folder.mkdir()
    (folder / "metadata.yaml").write_text("rosbag2_bagfile_information: {}\n", encoding="utf-8")
    (folder / "run.db3").write_bytes(b"old")
    (folder / "notes.txt").write_text("field notes", encoding="utf-8")
    result = CliRunner().invoke(
        main, ["simulate", "straight 1", "--out", str(folder), "--bag", "--force"]
    )
    assert result.exit_code == 2, result.output
    one_error_line(result.stderr, "it holds notes.txt")
    assert sorted(p.name for p in folder.iterdir()) == ["metadata.yaml", "notes.txt", "run.db3"]
    assert (folder / "notes.txt").read_text(encoding="utf-8") == "field notes"


def test_force_replaces_a_bag_this_tool_wrote(tmp_path: Path) -> None:
    folder = tmp_path / "run"
    for plan in ("straight 1", "spin 90"):
        args = ["simulate", plan, "--out", str(folder), "--bag", "--force", "--json"]
        result = CliRunner().invoke(main, args)
        assert result.exit_code == 0, result.output
    assert sorted(p.name for p in folder.iterdir()) == ["metadata.yaml", "run.db3"]
    assert debris(tmp_path) == []


# --- inputs of a description ------------------------------------------------------------------


def test_urdf_output_never_overwrites_a_file_the_description_included(
    tmp_path: Path, write: Write
) -> None:
    part = write("part.xacro", two_wheel_urdf(xacro=True).replace("two", "part"))
    before = part.read_text(encoding="utf-8")
    robot = write(
        "robot.urdf.xacro",
        '<?xml version="1.0"?>\n<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">'
        '<xacro:include filename="part.xacro"/></robot>\n',
    )
    result = CliRunner().invoke(main, ["urdf", str(robot), "-o", str(part), "--force"])
    assert result.exit_code == 2, result.output
    one_error_line(result.stderr, "is an input")
    assert part.read_text(encoding="utf-8") == before


def test_an_expansion_lists_every_file_it_read(tmp_path: Path, write: Write) -> None:
    write("config/sizes.yaml", "r: 0.05\n")
    write("part.xacro", two_wheel_urdf(xacro=True).replace("two", "part"))
    robot = write(
        "robot.urdf.xacro",
        '<?xml version="1.0"?>\n<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">'
        '<xacro:property name="s" value="${xacro.load_yaml(\'config/sizes.yaml\')}"/>'
        '<xacro:include filename="part.xacro"/><link name="r${s.r}"/></robot>\n',
    )
    files = {Path(f).resolve() for f in diffbot.expand(robot).files}
    expected = {tmp_path / "robot.urdf.xacro", tmp_path / "part.xacro"}
    assert files == {p.resolve() for p in expected | {tmp_path / "config" / "sizes.yaml"}}


# --- signals, full disks, closed stdout -------------------------------------------------------


#: diffbot's command line, with a pause after the temporary output is written and before it is
#: moved into place (a large output, or a slow disk), so that a signal lands in that window.
SLOW_WRITER = """
import os, sys, time
chmod = os.chmod
def slow_chmod(path, mode):
    chmod(path, mode)
    print("written", flush=True)
    time.sleep(float(os.environ.get("PAUSE", "60")))
os.chmod = slow_chmod
from diffbot.cli import main
main(sys.argv[1:], prog_name="diffbot")
"""


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGHUP])
def test_a_signal_while_an_output_is_written_leaves_no_temporary_file(
    tmp_path: Path, signum: int
) -> None:
    out = tmp_path / "o.csv"
    run = subprocess.Popen(
        [sys.executable, "-c", SLOW_WRITER, "simulate", "straight 1", "--out", str(out)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    assert run.stdout is not None
    assert run.stdout.readline() == "written\n"
    assert debris(tmp_path), "no temporary file while writing"
    run.send_signal(signum)
    assert run.wait(timeout=30) == 128 + signum
    assert debris(tmp_path) == []
    assert not out.exists()


def test_a_signal_ignored_as_under_nohup_does_not_end_the_run(tmp_path: Path) -> None:
    # nohup ignores SIGHUP, and a shell's background job SIGINT: the run goes on and writes.
    out = tmp_path / "o.csv"

    def ignored() -> None:
        signal.signal(signal.SIGHUP, signal.SIG_IGN)
        signal.signal(signal.SIGTERM, signal.SIG_IGN)

    run = subprocess.Popen(
        [sys.executable, "-c", SLOW_WRITER, "simulate", "straight 1", "--out", str(out)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "PAUSE": "1"},
        preexec_fn=ignored,
    )
    assert run.stdout is not None
    assert run.stdout.readline() == "written\n"
    run.send_signal(signal.SIGHUP)
    run.send_signal(signal.SIGTERM)
    assert run.wait(timeout=30) == 0
    assert out.read_text(encoding="utf-8").startswith("time,")


def test_a_full_disk_under_an_output_file_is_one_error_line(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    mkstemp = tempfile.mkstemp

    def on_a_full_disk(**kwargs: Any) -> tuple[int, str]:
        fd, name = mkstemp(**kwargs)
        os.close(fd)
        return os.open("/dev/full", os.O_WRONLY), name  # every write fails with ENOSPC

    monkeypatch.setattr(tempfile, "mkstemp", on_a_full_disk)
    result = CliRunner().invoke(main, ["simulate", "straight 1", "--out", str(tmp_path / "o.csv")])
    assert result.exit_code == 2, result.output
    one_error_line(result.stderr, "No space left on device")
    assert list(tmp_path.iterdir()) == []


def test_running_out_of_memory_is_one_error_line(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import diffbot.recordings

    def too_large(*args: Any, **kwargs: Any) -> None:
        raise MemoryError

    monkeypatch.setattr(diffbot.recordings, "read_recording", too_large)
    run = tmp_path / "run.csv"
    assert CliRunner().invoke(main, ["simulate", "straight 0.1", "--out", str(run)]).exit_code == 0
    result = CliRunner().invoke(main, ["calibrate", "fit", str(run)])
    assert result.exit_code == 2, result.output
    one_error_line(result.stderr, "out of memory: an input holds more than this machine can read")


def test_an_error_naming_megabytes_is_cut_to_one_readable_line(tmp_path: Path) -> None:
    deep = tmp_path.joinpath(*["x" * 200] * 15)  # 3000 characters, within PATH_MAX
    result = CliRunner().invoke(main, ["params", str(deep / "robot.urdf")])
    assert result.exit_code == 2, result.output
    one_error_line(result.stderr, "characters ...]")
    line = result.stderr.strip()
    assert len(line) < 2100
    assert line.startswith(f"error: {tmp_path}")
    assert line.rstrip().endswith("no such file")


def test_a_full_disk_under_a_bag_is_one_error_line(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from rosbags.rosbag2 import Writer

    def full(*args: Any, **kwargs: Any) -> None:
        raise sqlite3.OperationalError("database or disk is full")

    monkeypatch.setattr(Writer, "write", full)
    result = CliRunner().invoke(
        main, ["simulate", "straight 1", "--out", str(tmp_path / "bag"), "--bag"]
    )
    assert result.exit_code == 2, result.output
    one_error_line(result.stderr, "database or disk is full")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("unbuffered", [False, True])
def test_stdout_on_a_full_disk_is_one_error_line(unbuffered: bool) -> None:
    # A shell as a new user has it: stdout buffered unless PYTHONUNBUFFERED says otherwise.
    env = {name: os.environ[name] for name in ("PATH", "HOME", "LANG") if name in os.environ}
    if unbuffered:
        env["PYTHONUNBUFFERED"] = "1"
    with open("/dev/full", "w", encoding="utf-8") as full:
        done = subprocess.run(
            [sys.executable, "-m", "diffbot", "plan", "straight 1"],
            stdout=full,
            stderr=subprocess.PIPE,
            text=True,
            timeout=30,
            check=False,
            env=env,
            cwd=Path(diffbot.__file__).parent.parent,
        )
    assert done.returncode == 2, done.stderr
    one_error_line(done.stderr, "No space left on device")


def test_a_closed_stdout_is_one_error_line() -> None:
    done = subprocess.run(
        [sys.executable, "-m", "diffbot", "plan", "straight 1"],
        stderr=subprocess.PIPE,
        text=True,
        timeout=30,
        check=False,
        preexec_fn=lambda: os.close(1),  # as the shell's >&- does
    )
    assert done.returncode == 2, done.stderr
    one_error_line(done.stderr, "standard output is closed")


# --- one guard for every run: the inputs noted, and what --force may replace ---------------------


def test_an_output_checked_in_a_guarded_run_avoids_every_noted_input(tmp_path: Path) -> None:
    from diffbot.errors import OutputError
    from diffbot.io.outputs import check_bag_output, guarded_run, note_input, output_target

    folder = tmp_path / "recording"
    folder.mkdir()
    plan = tmp_path / "plan.txt"
    plan.write_text("straight 1\n", encoding="utf-8")
    with guarded_run([plan]):
        note_input(folder)
        with pytest.raises(OutputError, match="is an input"):
            output_target(plan, force=True)
        # Without force too: an input is never written, so force is not offered.
        with pytest.raises(OutputError, match="is an input") as caught:
            output_target(plan, force=False)
        assert "force" not in str(caught.value)
        with pytest.raises(OutputError, match="lies inside the input"):
            output_target(folder / "poses.csv", force=False)
        with pytest.raises(OutputError, match="contains"):
            check_bag_output(tmp_path, force=True)
    # Outside a guarded run (the library called directly) nothing is noted.
    note_input(plan)
    assert output_target(plan, force=True) == plan


def test_a_hard_link_to_an_input_is_that_input(tmp_path: Path) -> None:
    from diffbot.io.outputs import guarded_run, output_target

    plan = tmp_path / "plan.txt"
    plan.write_text("straight 1\n", encoding="utf-8")
    other = tmp_path / "other.txt"
    os.link(plan, other)
    with guarded_run([plan]), pytest.raises(OutputError, match=r"other\.txt is an input"):
        output_target(other, force=True)
    # a copy is another file
    other.unlink()
    other.write_text("straight 1\n", encoding="utf-8")
    with guarded_run([plan]):
        assert output_target(other, force=True) == other


def test_a_file_redirected_into_stdin_is_an_input(tmp_path: Path) -> None:
    made = subprocess.run(
        [sys.executable, "-m", "diffbot", "simulate", "straight 0.2", "--rate", "10"],
        capture_output=True,
        check=True,
    )
    recording = tmp_path / "a.csv"
    recording.write_bytes(made.stdout)
    for out in ("a.csv", "b.csv"):
        with recording.open("rb") as stdin:
            run = subprocess.run(
                [sys.executable, "-m", "diffbot", "odom", "-", "-o", out, "--force"],
                stdin=stdin,
                capture_output=True,
                text=True,
                cwd=tmp_path,
            )
        if out == "a.csv":
            assert run.returncode == 2
            assert run.stderr == "error: --out a.csv is the input -: inputs are never overwritten\n"
            assert recording.read_bytes() == made.stdout
        else:
            assert run.returncode == 0, run.stderr
            assert (tmp_path / "b.csv").read_text().startswith("time,x,y,theta")
    # piped, stdin is no file: the output is written
    piped = subprocess.run(
        [sys.executable, "-m", "diffbot", "odom", "-", "-o", "c.csv"],
        input=made.stdout,
        capture_output=True,
        cwd=tmp_path,
    )
    assert piped.returncode == 0
    assert (tmp_path / "c.csv").is_file()


def test_guarded_runs_do_not_leak_their_inputs(tmp_path: Path) -> None:
    from diffbot.io.outputs import guarded_run, noted_inputs

    with guarded_run([tmp_path / "a"]):
        with guarded_run([tmp_path / "b"]):
            assert noted_inputs() == (tmp_path / "b",)
        assert noted_inputs() == (tmp_path / "a",)
    assert noted_inputs() == ()


def test_a_text_input_is_noted_when_it_is_checked(tmp_path: Path) -> None:
    from diffbot.errors import PlanError
    from diffbot.io.outputs import guarded_run, noted_inputs
    from diffbot.io.textfile import read_text

    plan = tmp_path / "plan.txt"
    plan.write_text("straight 1\n", encoding="utf-8")
    with guarded_run():
        read_text(plan, PlanError, "a plan file")
        assert noted_inputs() == (plan,)


@pytest.mark.parametrize("force", [False, True])
def test_a_bag_output_over_a_fifo_is_refused_with_or_without_force(
    tmp_path: Path, force: bool
) -> None:
    from diffbot.errors import OutputError
    from diffbot.io.outputs import check_bag_output

    fifo = tmp_path / "jam"
    os.mkfifo(fifo)
    with pytest.raises(OutputError, match=r"not a regular file|exists"):
        check_bag_output(fifo, force=force)
    assert stat.S_ISFIFO(fifo.lstat().st_mode)


def test_a_fifo_put_in_place_of_a_bag_during_the_work_is_kept(tmp_path: Path) -> None:
    from diffbot.errors import OutputError

    new = tmp_path / ".staging" / "run"
    new.mkdir(parents=True)
    (new / "metadata.yaml").write_text("rosbag2_bagfile_information: {}\n", encoding="utf-8")
    fifo = tmp_path / "run"
    os.mkfifo(fifo)  # appeared after the early check
    with pytest.raises(OutputError, match="not a regular file"):
        replace_bag(new, fifo, force=True)
    assert stat.S_ISFIFO(fifo.lstat().st_mode)


def test_a_file_output_over_a_fifo_is_refused_with_force(tmp_path: Path) -> None:
    from diffbot.errors import OutputError

    fifo = tmp_path / "jam"
    os.mkfifo(fifo)
    with pytest.raises(OutputError, match="not a regular file"):
        write_text_atomic(fifo, "x", force=True)
    assert stat.S_ISFIFO(fifo.lstat().st_mode)


def test_a_command_word_is_no_input_even_where_a_folder_has_its_name(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    for name in ("plot", "plan", "straight"):
        (tmp_path / name).mkdir()
    runner = CliRunner()
    result = runner.invoke(main, ["plot", "--example", "A", "-o", "plot/a.png"])
    assert result.exit_code == 0, result.output
    assert (tmp_path / "plot" / "a.png").is_file()
    # plan text whose first word names a folder is no file of the run either
    result = runner.invoke(main, ["plan", "straight", "1", "-o", "straight/p.txt"])
    assert result.exit_code == 0, result.output
    assert (tmp_path / "straight" / "p.txt").is_file()


def test_the_inputs_are_the_arguments_parsed_as_paths(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from diffbot.io import outputs

    seen: list[tuple[Path, ...]] = []
    check = outputs.check_not_input

    def spy(*args: Any, **kwargs: Any) -> None:
        seen.append(outputs.noted_inputs())
        check(*args, **kwargs)

    monkeypatch.setattr(outputs, "check_not_input", spy)
    monkeypatch.chdir(tmp_path)
    robot = tmp_path / "robot.urdf"
    robot.write_text(two_wheel_urdf(), encoding="utf-8")
    plan = tmp_path / "plan.txt"
    plan.write_text("straight 1\n", encoding="utf-8")
    (tmp_path / "unread.csv").write_text("", encoding="utf-8")
    args = ["urdf", "robot.urdf", "wheel_radius:=0.1", "-o", "out.urdf"]
    assert CliRunner().invoke(main, args).exit_code == 0
    assert seen[-1] == (robot,)
    args = ["plan", "plan.txt", "--robot", "robot.urdf", "--out", "out.txt"]
    assert CliRunner().invoke(main, args).exit_code == 0
    assert set(seen[-1]) == {robot, plan}  # not the output, not the word "plan"


@pytest.mark.parametrize("name", ["x.csv/.", "x.csv/..", "x.csv/", "."])
def test_a_file_output_named_as_a_folder_is_refused(name: str, tmp_path: Path) -> None:
    # written out: a Path would drop a trailing "/."
    result = CliRunner().invoke(main, ["plan", "straight 1", "-o", f"{tmp_path}/{name}"])
    assert result.exit_code == 2, result.output
    one_error_line(result.stderr, f"{tmp_path}/{name}: ends with")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    "name", ["", " ", ".", "..", "/", "//", "./", "x.csv/.", "out/..", "x.csv/"]
)
def test_a_name_of_no_file_of_its_own_is_refused(name: str) -> None:
    with pytest.raises(OutputError):
        check_output_name(name)
    with pytest.raises(OutputError, match=r"a file is read there|an empty name"):
        check_output_name(name, source=True)


@pytest.mark.parametrize("name", ["", " ", ".", "/", "./", "run_bag/.", "run_bag/.."])
def test_a_folder_output_needs_a_name_of_its_own(name: str) -> None:
    with pytest.raises(OutputError):
        check_output_name(name, folder=True)


@pytest.mark.parametrize("kind", [{}, {"folder": True}, {"holder": True}, {"source": True}])
def test_a_dash_names_standard_output_not_a_file(kind: dict[str, bool]) -> None:
    with pytest.raises(OutputError, match=r"^-: standard output, not a file"):
        check_output_name("-", **kind)
    check_output_name("./-", **kind)


@pytest.mark.parametrize("name", [".", "..", "/", "./", "out/.."])
def test_a_folder_that_holds_outputs_may_be_any_folder(name: str) -> None:
    check_output_name(name, holder=True)
    for empty in ("", " "):
        with pytest.raises(OutputError, match="an empty name"):
            check_output_name(empty, holder=True)


@pytest.mark.parametrize(
    "name", ["x.csv", "./x.csv", "/tmp/x.csv", "a/../x.csv", ".x", "...", "x."]
)
def test_a_file_name_is_taken(name: str) -> None:
    check_output_name(name)
    check_output_name(name, source=True)
    check_output_name(name, folder=True)
    check_output_name(f"{name}/", folder=True)


@pytest.mark.parametrize("force", ["false", "no", 0, None])
def test_force_is_a_bool_never_a_truthy_word(tmp_path: Path, force: object) -> None:
    """``force="false"`` overwrote an existing file: every writer goes through this check."""
    from diffbot.io.outputs import check_bag_output, output_target

    kept = tmp_path / "kept.csv"
    kept.write_text("mine\n")
    for check in (
        lambda: output_target(kept, force=force),  # type: ignore[arg-type]
        lambda: check_bag_output(kept, force),  # type: ignore[arg-type]
        lambda: write_text_atomic(kept, "theirs\n", force=force),  # type: ignore[arg-type]
    ):
        with pytest.raises(OutputError, match=r"^force must be True or False"):
            check()
    assert kept.read_text() == "mine\n"
