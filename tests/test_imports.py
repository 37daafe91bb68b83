"""What each quick command loads: start-up cannot regress silently (heavy modules load only
where a command needs them)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
from extras import need

HEAVY = (
    "numpy",
    "yourdfpy",
    "trimesh",
    "rosbags",
    "matplotlib",
    "scipy",
    "dask",
    "distributed",
    "ruamel",
    "cyclonedds",
)

PROBE = """
import contextlib, io, json, sys
from diffbot.cli import main
with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
    try:
        main(sys.argv[1:], standalone_mode=False)
    except SystemExit:
        pass
print(json.dumps(sorted({name.split(".")[0] for name in sys.modules})))
"""


def loaded_by(args: list[str], cache: Path) -> set[str]:
    """The top-level modules loaded by one run of ``diffbot ARGS`` in a fresh interpreter."""
    env = {"DIFFBOT_CACHE_DIR": str(cache), "PATH": "/usr/bin:/bin"}
    done = subprocess.run(
        [sys.executable, "-c", PROBE, *args], capture_output=True, text=True, env=env, check=True
    )
    return set(json.loads(done.stdout)) & set(HEAVY)


@pytest.fixture(scope="module")
def warm_cache(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A parameter cache as a first run leaves it: the bundled robot's parameters ship with the
    package, so the first run derives nothing, loads no yourdfpy and writes no entry."""
    cache = tmp_path_factory.mktemp("cache")
    assert "yourdfpy" not in loaded_by(["params"], cache)
    assert list(cache.glob("params-*.json")) == []
    return cache


@pytest.mark.parametrize(
    "args",
    [
        ["--version"],
        ["--help"],
        ["params"],
        ["params", "--json"],
        ["params", "--trust"],
        ["urdf"],
        ["ik", "0.1", "0"],
        ["fk", "2.86", "2.86"],
        ["plan"],
        ["plan", "--format", "ros2"],
        ["plan", "--stamped", "--format", "twist"],
        ["plan", "reverse ccw 0.25 90; straight -1"],
        ["plan", "--to", "0,1,0", "--min-radius", "0.25"],
        ["plan", "--to", "1,1", "--to", "0,2,90", "--shape", "reeds-shepp", "--min-radius", "0.2"],
        ["odom", "--help"],
        ["simulate", "--help"],
        ["check"],
        ["plot", "--help"],
        ["explain", "--help"],
        ["explain", "ik", "0.1", "0", "--lang", "es"],
        ["explain", "fk", "2.86", "2.86", "--format", "md"],
        ["explain", "plan", "--example", "B"],
        ["explain", "odom", "0", "0", "1", "1.5", "0.1"],
        ["calibrate", "--help"],
        ["calibrate", "fit", "--help"],
        ["calibrate", "umbmark", "--help"],
        ["node", "--help"],
        ["node", "odom", "--help"],
        ["node", "ik", "--help"],
        ["drive", "--help"],
        ["node", "robot", "--help"],
    ],
)
def test_quick_commands_load_no_heavy_module(args: list[str], warm_cache: Path) -> None:
    assert loaded_by(args, warm_cache) == set()


def test_simulating_loads_numpy_but_not_bags_or_plots(warm_cache: Path) -> None:
    assert loaded_by(["simulate", "straight 0.1"], warm_cache) == {"numpy"}


def test_ramped_plans_load_numpy_but_not_bags(warm_cache: Path) -> None:
    assert loaded_by(["plan", "--max-accel", "0.1"], warm_cache) == {"numpy"}


def test_odometry_of_a_csv_loads_numpy_but_not_bags_or_dask(
    warm_cache: Path, tmp_path: Path
) -> None:
    path = tmp_path / "a.csv"
    path.write_text("time,front_left_wheel_joint,front_right_wheel_joint\n0,0,0\n1,1,1\n")
    assert loaded_by(["odom", str(path)], warm_cache) == {"numpy"}
    assert loaded_by(["odom", str(path), str(path), "--jobs", "2"], warm_cache) == {"numpy"}


def test_plotting_loads_matplotlib_and_numpy_but_not_bags(warm_cache: Path, tmp_path: Path) -> None:
    assert loaded_by(["plot", "-o", str(tmp_path / "a.png")], warm_cache) == {"matplotlib", "numpy"}
    assert (tmp_path / "a.png").stat().st_size > 0


def test_umbmark_loads_numpy_but_not_scipy(warm_cache: Path) -> None:
    args = ["calibrate", "umbmark", "--side", "4", "--cw", "0,0", "--ccw", "0,0"]
    assert loaded_by(args, warm_cache) == {"numpy"}


def test_odometry_of_a_sqlite_bag_loads_numpy_but_not_rosbags_asyncio_or_a_process_pool(
    warm_cache: Path, tmp_path: Path
) -> None:
    need("rosbags")  # only to write the bag
    bag = tmp_path / "a_bag"
    env = {"DIFFBOT_CACHE_DIR": str(warm_cache), "PATH": "/usr/bin:/bin"}
    subprocess.run(
        [sys.executable, "-m", "diffbot", "simulate", "straight 0.1", "-o", str(bag), "--bag"],
        check=True,
        capture_output=True,
        env=env,
    )
    assert loaded_by(["odom", str(bag)], warm_cache) == {"numpy"}
    probe = PROBE.replace(
        'name.split(".")[0] for name in sys.modules', "name for name in sys.modules"
    )
    done = subprocess.run(
        [sys.executable, "-c", probe, "odom", str(bag)],
        capture_output=True,
        text=True,
        env=env,
        check=True,
    )
    loaded = set(json.loads(done.stdout))
    assert "sqlite3" in loaded  # the probe sees the reading
    assert not loaded & {"asyncio", "concurrent.futures", "multiprocessing"}
