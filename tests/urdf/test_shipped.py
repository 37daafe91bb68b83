"""The bundled robot's derived parameters ship with the package and equal a fresh derivation."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from diffbot.urdf import shipped
from diffbot.urdf.cache import fields_json
from diffbot.urdf.wheels import derive_text
from diffbot.urdf.xacro import expand


def test_the_shipped_fields_equal_a_fresh_derivation_of_the_bundled_robot() -> None:
    urdf = expand(None).urdf
    derived = derive_text(urdf, shipped.BUNDLED_LABEL)
    fresh = json.loads(json.dumps(shipped.shipped_entry(urdf, derived)))
    stored = json.loads(shipped.SHIPPED_PATH.read_text(encoding="utf-8"))
    assert stored == fresh, (
        "description/derived.json is stale: run "
        "python -c 'from diffbot.urdf.shipped import write_shipped; write_shipped()'"
    )
    assert shipped.shipped_fields(urdf, shipped.BUNDLED_LABEL, None, None) is not None


def test_only_the_bundled_robot_as_shipped_is_served() -> None:
    urdf = expand(None).urdf
    assert shipped.shipped_fields(urdf, "robot.urdf", None, None) is None
    assert shipped.shipped_fields(urdf, shipped.BUNDLED_LABEL, "a", None) is None
    wider = expand(None, {"wheel_separation": "0.2"}).urdf
    assert shipped.shipped_fields(wider, shipped.BUNDLED_LABEL, None, None) is None


def test_the_digest_leaves_out_the_folder_the_package_is_installed_in() -> None:
    urdf = expand(None).urdf
    folder = str(shipped.SHIPPED_PATH.parent)
    assert folder in urdf
    moved = urdf.replace(folder, "/opt/elsewhere/diffbot/description")
    served = shipped.shipped_fields(urdf, shipped.BUNDLED_LABEL, None, None)
    assert served is not None
    assert fields_json(served)["wheel_radius"] == pytest.approx(0.035, abs=1e-15)
    assert shipped.shipped_fields(moved, shipped.BUNDLED_LABEL, None, None) is None


def test_a_first_run_with_an_empty_cache_reads_the_shipped_fields_without_yourdfpy(
    tmp_path: Path,
) -> None:
    code = (
        "import sys, diffbot; p = diffbot.load_params(); "
        "print(p.wheel_radius, p.wheel_separation, p.max_wheel_speed, "
        "'yourdfpy' in sys.modules, 'trimesh' in sys.modules)"
    )
    env = {**os.environ, "DIFFBOT_CACHE_DIR": str(tmp_path / "cache")}
    done = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
    )
    radius, separation, speed, yourdfpy, trimesh = done.stdout.split()
    assert float(radius) == pytest.approx(0.035, abs=1e-15)
    assert float(separation) == pytest.approx(0.135, abs=1e-15)
    assert float(speed) == pytest.approx(50 * 2 * 3.141592653589793 / 60, rel=1e-15)
    assert (yourdfpy, trimesh) == ("False", "False")
    assert not (tmp_path / "cache").exists() or not list((tmp_path / "cache").iterdir())
