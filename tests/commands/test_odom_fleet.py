"""``diffbot odom`` over several recordings: one row each, serially, in a process pool and on a
Dask cluster, with the same results; one broken recording does not stop the others."""

from __future__ import annotations

import json
import socket
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest
from bags import write_bag
from click.testing import CliRunner
from extras import need
from robots import BOT

from diffbot.cli import main

LEFT, RIGHT = BOT.left_joint, BOT.right_joint


@pytest.fixture
def fleet(tmp_path: Path) -> list[str]:
    """Three CSV recordings and one bag of different runs, and a broken CSV (third)."""
    paths = []
    for k in range(3):
        lines = [f"time,{LEFT},{RIGHT}"]
        lines += [f"{i / 10!r},{i * 0.1 * (k + 1)!r},{i * 0.12!r}" for i in range(50)]
        path = tmp_path / f"run{k}.csv"
        path.write_text("\n".join(lines) + "\n", encoding="utf-8")
        paths.append(str(path))
    broken = tmp_path / "broken.csv"
    broken.write_text(f"when,{LEFT},{RIGHT}\n0,0,0\n", encoding="utf-8")
    messages = [
        (10**9 + i * 10**8, 10**9 + i * 10**8, [LEFT, RIGHT], [i * 0.2, i * 0.1]) for i in range(40)
    ]
    bag = write_bag(tmp_path / "bag_run", messages)
    return [paths[0], paths[1], str(broken), paths[2], str(bag)]


def json_lines(runner: CliRunner, *args: str, code: int = 1) -> list[dict[str, object]]:
    result = runner.invoke(main, ["odom", *args, "--json"])
    assert result.exit_code == code, result.output
    return [json.loads(line) for line in result.stdout.splitlines()]


def test_each_input_gets_a_json_line_and_a_broken_one_its_error(
    runner: CliRunner, fleet: list[str]
) -> None:
    rows = json_lines(runner, *fleet)
    assert [row["input"] for row in rows] == fleet
    assert "no time column" in str(rows[2]["error"])
    for k in (0, 1, 3, 4):
        alone = json.loads(runner.invoke(main, ["odom", fleet[k], "--json"]).stdout)
        assert rows[k] == alone  # the same figures as the input read on its own


def test_the_table_has_one_row_per_input_and_exit_code_1_on_a_failure(
    runner: CliRunner, fleet: list[str]
) -> None:
    result = runner.invoke(main, ["odom", *fleet])
    assert result.exit_code == 1
    robot, *lines = result.stdout.splitlines()
    assert robot == "robot bundled"
    assert lines[0].split()[:2] == ["input", "samples"]
    assert [line.split()[0] for line in lines[1:]] == fleet
    assert "error: " in lines[3]
    assert result.stderr == "warning: 1 of 5 recordings could not be read\n"


def test_globs_are_expanded_in_order(runner: CliRunner, fleet: list[str], tmp_path: Path) -> None:
    rows = json_lines(runner, str(tmp_path / "run*.csv"), code=0)
    assert [row["input"] for row in rows] == sorted(fleet[k] for k in (0, 1, 3))


def test_out_dir_gets_one_output_per_input(
    runner: CliRunner, fleet: list[str], tmp_path: Path
) -> None:
    out = tmp_path / "poses"
    rows = json_lines(runner, *fleet, "--out", str(out))
    assert sorted(p.name for p in out.iterdir()) == [
        "bag_run.csv",
        "run0.csv",
        "run1.csv",
        "run2.csv",
    ]
    text = (out / "run1.csv").read_text(encoding="utf-8").splitlines()
    assert text[0] == "time,x,y,theta,linear,angular"
    assert len(text) == 1 + int(str(rows[1]["samples"]))
    again = runner.invoke(main, ["odom", *fleet[:2], "--out", str(out), "--json"])
    assert again.exit_code == 1  # outputs exist and --force was not given
    assert "exists: use --force to overwrite it" in again.stdout


@pytest.mark.parametrize("folder", [".", "..", "./"])
def test_the_out_dir_may_be_the_current_or_the_parent_folder(
    runner: CliRunner,
    fleet: list[str],
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    folder: str,
) -> None:
    # A folder that gets one output per input may be any folder; a file or a bag may not.
    (tmp_path / "here" / "poses").mkdir(parents=True)
    monkeypatch.chdir(tmp_path / "here" / "poses" if folder == ".." else tmp_path / "here")
    result = runner.invoke(main, ["odom", fleet[0], fleet[1], "--out", folder, "--json"])
    assert result.exit_code == 0, result.output
    assert sorted(p.name for p in (tmp_path / "here").iterdir()) == [
        "poses",
        "run0.csv",
        "run1.csv",
    ]
    for alone in (["--out", folder], ["--out", folder, "--bag"]):
        refused = runner.invoke(main, ["odom", fleet[0], *alone, "--force"])
        assert refused.exit_code == 2, refused.output
        assert refused.stderr.startswith("error: -o/--out ")


def test_a_process_pool_gives_the_serial_results(runner: CliRunner, fleet: list[str]) -> None:
    assert json_lines(runner, *fleet, "--jobs", "2") == json_lines(runner, *fleet)


def test_a_dask_cluster_gives_the_serial_results(runner: CliRunner, fleet: list[str]) -> None:
    distributed = need("distributed")
    serial = json_lines(runner, *fleet)
    with distributed.LocalCluster(
        n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None
    ) as cluster:
        assert json_lines(runner, *fleet, "--dask", cluster.scheduler_address) == serial


def test_out_dir_never_replaces_an_input_even_with_force(
    runner: CliRunner, fleet: list[str], tmp_path: Path
) -> None:
    bag = Path(fleet[4])
    before = sorted((p.name, p.read_bytes()) for p in bag.iterdir())
    args = ["odom", fleet[4], fleet[0], "--out", str(tmp_path), "--bag", "--force"]
    result = runner.invoke(main, args)
    # Refused before any output is written: every output is checked against every input first.
    assert result.exit_code == 2, result.output
    assert result.stderr.startswith(f"error: {bag} is an input")
    assert sorted((p.name, p.read_bytes()) for p in bag.iterdir()) == before
    assert not (tmp_path / "run0").exists()


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


@pytest.fixture
def dask_cluster(tmp_path: Path) -> Iterator[str]:
    """A scheduler and a worker in their own processes, started in a folder of their own, as a
    cluster runs; stopped whatever happens."""
    distributed = need("distributed")
    dask = Path(sys.executable).with_name("dask")
    if not dask.exists():
        pytest.skip("no dask command beside this Python")
    home = tmp_path / "cluster"
    home.mkdir()
    address = f"tcp://127.0.0.1:{_free_port()}"
    common = {"cwd": home, "stdout": subprocess.DEVNULL, "stderr": subprocess.DEVNULL}
    processes = [
        subprocess.Popen(
            [
                str(dask),
                "scheduler",
                "--host",
                "127.0.0.1",
                "--port",
                address.rsplit(":", 1)[1],
                "--no-dashboard",
                "--no-show",
            ],
            **common,  # type: ignore[call-overload]
        )
    ]
    try:
        processes.append(
            subprocess.Popen(
                [
                    str(dask),
                    "worker",
                    address,
                    "--nworkers",
                    "1",
                    "--nthreads",
                    "2",
                    "--no-dashboard",
                    "--local-directory",
                    str(home),
                    "--death-timeout",
                    "60",
                ],
                **common,  # type: ignore[call-overload]
            )
        )
        with distributed.Client(address, timeout=60) as client:
            client.wait_for_workers(1, timeout=60)  # ready: no sleeping, a bounded wait
        yield address
    finally:
        for process in reversed(processes):
            process.terminate()
        for process in processes:
            try:
                process.wait(timeout=20)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait(timeout=20)


def test_a_cluster_in_its_own_processes_and_folder_gets_relative_paths_right(
    fleet: list[str], tmp_path: Path, dask_cluster: str
) -> None:
    names = [Path(path).name for path in fleet]
    command = [sys.executable, "-m", "diffbot", "odom", *names, "--json", "--out"]
    runs = {}
    for out, extra in (("serial", []), ("dask", ["--dask", dask_cluster])):
        done = subprocess.run(
            [*command, out, *extra], cwd=tmp_path, capture_output=True, text=True, timeout=120
        )
        assert done.returncode == 1, done.stderr  # the broken input
        runs[out] = [json.loads(line) for line in done.stdout.splitlines()]
    assert [row["input"] for row in runs["dask"]] == names
    assert "no time column" in str(runs["dask"][2]["error"])
    for k in (0, 1, 3, 4):
        serial, dask = runs["serial"][k], runs["dask"][k]
        assert dask == serial | {"output": dask["output"]}
    written = sorted(p.name for p in (tmp_path / "dask").iterdir())
    assert written == ["bag_run.csv", "run0.csv", "run1.csv", "run2.csv"]
    for name in written:
        assert (tmp_path / "dask" / name).read_text() == (tmp_path / "serial" / name).read_text()
    assert not (tmp_path / "cluster" / "dask").exists()


@pytest.mark.skipif(sys.version_info < (3, 11), reason="PYTHONSAFEPATH arrived in Python 3.11")
@pytest.mark.parametrize("method", ["spawn", "forkserver"])
def test_pool_workers_started_afresh_run_no_code_from_the_current_folder(
    tmp_path: Path, fleet: list[str], method: str
) -> None:
    # A spawned worker starts as `python -c ...`, which puts the current folder first on its
    # path before the pool hands it this process's own: a multiprocessing/ there would run.
    from hostile import CLI, hostile_folder

    marker = tmp_path / "marker"
    repo = hostile_folder(tmp_path / "repo", marker)
    code = f"import multiprocessing as m\nm.set_start_method({method!r})\n" + CLI.replace(
        "import sys\n", "", 1
    )
    code = "import sys\nsys.path[:] = [p for p in sys.path if p]\n" + code
    done = subprocess.run(
        [sys.executable, "-c", code, "odom", fleet[0], fleet[1], "--jobs", "2", "--json"],
        cwd=repo,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert not marker.exists(), marker.read_text(encoding="utf-8")
    assert done.returncode == 0, done.stderr
    rows = [json.loads(line) for line in done.stdout.splitlines()]
    assert [row["input"] for row in rows] == fleet[:2]
