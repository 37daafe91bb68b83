"""``diffbot check``: exit 0 when the sources agree, 1 when they disagree, with what differs."""

from __future__ import annotations

import json
from pathlib import Path

from click.testing import CliRunner

from diffbot.cli import main

ROBOT = """<?xml version="1.0"?>
<robot name="r">
  <link name="base_link"/>
  <link name="l"/><link name="r"/>
  <joint name="lw" type="continuous"><parent link="base_link"/><child link="l"/>
    <origin xyz="0 0.18 0"/><axis xyz="0 1 0"/></joint>
  <joint name="rw" type="continuous"><parent link="base_link"/><child link="r"/>
    <origin xyz="0 -0.18 0"/><axis xyz="0 1 0"/></joint>
  <gazebo><plugin filename="libgazebo_ros_diff_drive.so" name="dd">
    <left_joint>lw</left_joint><right_joint>rw</right_joint>
    <wheel_separation>SEP</wheel_separation><wheel_diameter>0.1</wheel_diameter>
  </plugin></gazebo>
</robot>
"""


def write_robot(tmp_path: Path, separation: str) -> Path:
    path = tmp_path / f"r{separation}.urdf"
    path.write_text(ROBOT.replace("SEP", separation), encoding="utf-8")
    return path


def test_check_exits_0_when_the_sources_agree(tmp_path: Path) -> None:
    result = CliRunner().invoke(
        main, ["check", str(write_robot(tmp_path, "0.36")), "--wheel-radius", "0.05"]
    )
    assert result.exit_code == 0, result.output
    assert "all sources agree" in result.stdout


def test_check_exits_1_and_shows_each_source_when_they_disagree(tmp_path: Path) -> None:
    path = write_robot(tmp_path, "0.40")
    result = CliRunner().invoke(main, ["check", str(path), "--wheel-radius", "0.05"])
    assert result.exit_code == 1, result.output
    assert "DISAGREE          wheel_separation:" in result.stdout
    assert "gazebo plugin" in result.stdout
    assert "40 mm" in result.stdout
    data = json.loads(
        CliRunner().invoke(main, ["check", str(path), "--wheel-radius", "0.05", "--json"]).stdout
    )
    assert data["agree"] is False
    (found,) = data["disagreements"]
    assert found["field"] == "wheel_separation"
    assert found["values"]["gazebo plugin"] == 0.4
    assert abs(found["difference"] - 0.04) < 1e-12
    assert data["sources"]["wheel_radius"] == "override"


def test_params_json_lists_the_disagreement_and_names_the_controller_flag(tmp_path: Path) -> None:
    path = write_robot(tmp_path, "0.40")
    result = CliRunner().invoke(main, ["params", str(path), "--wheel-radius", "0.05", "--json"])
    assert result.exit_code == 0, result.output
    assert json.loads(result.stdout)["disagreements"][0]["field"] == "wheel_separation"
    bad = tmp_path / "c.yaml"
    bad.write_text("", encoding="utf-8")
    missing = CliRunner().invoke(main, ["params", str(path), "--controllers", str(bad)])
    assert missing.exit_code == 2
    assert missing.stderr.startswith("error: ")
    assert len(missing.stderr.splitlines()) == 1
    assert "no diff_drive_controller" in missing.stderr
