"""Every derivation equals its command, for every robot: mirrored joint axes and per-wheel radii
included. ``diffbot explain X`` and ``diffbot X --json`` are run on the same random robot and the
numbers compared at the precision the derivation prints."""

from __future__ import annotations

import json
import tempfile
from pathlib import Path

from click.testing import CliRunner
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from rendered import Printed, numbers

from diffbot.cli import main

RADII = st.floats(0.02, 0.2)
SEPARATIONS = st.floats(0.1, 0.8)
SIGNS = st.sampled_from([1, -1])
SPEEDS = st.floats(-5.0, 5.0).filter(lambda x: abs(x) > 1e-3)


def robot_urdf(
    left_radius: float, right_radius: float, separation: float, signs: tuple[int, int]
) -> str:
    """Two drive wheels of their own radii, ``separation`` apart, each axis along +y (sign 1) or
    mirrored along -y (sign -1)."""
    wheels = []
    for side, radius, y, sign in (
        ("left", left_radius, separation / 2, signs[0]),
        ("right", right_radius, -separation / 2, signs[1]),
    ):
        wheels.append(
            f'<joint name="{side}_joint" type="continuous"><parent link="base_link"/>'
            f'<child link="{side}_wheel"/><origin xyz="0 {y!r} 0"/><axis xyz="0 {sign} 0"/>'
            f'</joint><link name="{side}_wheel"><collision><origin rpy="1.5707963267948966 0 0"/>'
            f'<geometry><cylinder radius="{radius!r}" length="0.02"/></geometry></collision></link>'
        )
    return (
        '<?xml version="1.0"?>\n<robot name="r"><link name="base_link"/>'
        + "".join(wheels)
        + "</robot>\n"
    )


robots = st.tuples(RADII, RADII, SEPARATIONS, st.tuples(SIGNS, SIGNS))


def run(folder: Path, *args: str) -> str:
    result = CliRunner().invoke(main, [*args], catch_exceptions=False, prog_name="diffbot")
    assert result.exit_code in (0, 1), result.output
    return result.stdout


def results(text: str) -> list[dict[str, Printed]]:
    """Each section of a text derivation: its steps' results by symbol."""
    sections: list[dict[str, Printed]] = []
    for line in text.splitlines():
        if line and not line.startswith(" "):
            sections.append({})
        elif line.startswith("    ") and " = " in line:
            symbol, *_, result = line.strip().split(" = ")
            sections[-1][symbol] = numbers(result)[0]
    return sections


def joint(section: dict[str, Printed], side: str) -> Printed:
    """A side's joint velocity: q when the axis is mirrored, else ω."""
    return section.get(f"q_{side}", section[f"ω_{side}"])


def with_robot(
    robot: tuple[float, float, float, tuple[int, int]],
) -> tempfile.TemporaryDirectory[str]:
    folder = tempfile.TemporaryDirectory()
    (Path(folder.name) / "robot.urdf").write_text(robot_urdf(*robot), encoding="utf-8")
    return folder


SETTINGS = settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@SETTINGS
@given(robots, SPEEDS, SPEEDS)
def test_explain_fk_equals_fk(
    robot: tuple[float, float, float, tuple[int, int]], left: float, right: float
) -> None:
    with with_robot(robot) as name:
        path = str(Path(name) / "robot.urdf")
        fk = json.loads(run(Path(name), "fk", path, repr(left), repr(right), "--json"))
        (*_, body) = results(run(Path(name), "explain", "fk", path, repr(left), repr(right)))
    assert body["v"].matches(fk["linear"])
    assert body["ω"].matches(fk["angular"])


@SETTINGS
@given(robots, st.floats(-0.5, 0.5), st.floats(-2.0, 2.0))
def test_explain_ik_equals_ik(
    robot: tuple[float, float, float, tuple[int, int]], linear: float, angular: float
) -> None:
    with with_robot(robot) as name:
        path = str(Path(name) / "robot.urdf")
        ik = json.loads(run(Path(name), "ik", path, repr(linear), repr(angular), "--json"))
        wheels = results(run(Path(name), "explain", "ik", path, repr(linear), repr(angular)))[2]
    assert joint(wheels, "L").matches(ik["left"])
    assert joint(wheels, "R").matches(ik["right"])


@SETTINGS
@given(robots, st.sampled_from(["A", "B"]))
def test_explain_plan_equals_plan(
    robot: tuple[float, float, float, tuple[int, int]], example: str
) -> None:
    with with_robot(robot) as name:
        path = str(Path(name) / "robot.urdf")
        planned = json.loads(run(Path(name), "plan", path, "--example", example, "--json"))
        sections = results(run(Path(name), "explain", "plan", path, "--example", example))[2:]
    assert len(sections) == len(planned["segments"])
    for section, segment in zip(sections, planned["segments"], strict=True):
        assert joint(section, "L").matches(segment["left"])
        assert joint(section, "R").matches(segment["right"])
        assert section["x₁"].matches(segment["end_pose"]["x"])
        assert section["y₁"].matches(segment["end_pose"]["y"])


@SETTINGS
@given(robots, st.tuples(SPEEDS, SPEEDS, SPEEDS, SPEEDS), st.floats(0.01, 1.0))
def test_explain_odom_equals_odom(
    robot: tuple[float, float, float, tuple[int, int]],
    angles: tuple[float, float, float, float],
    dt: float,
) -> None:
    l0, r0, l1, r1 = angles
    with with_robot(robot) as name:
        path = str(Path(name) / "robot.urdf")
        recording = Path(name) / "run.csv"
        recording.write_text(
            f"time,left_joint,right_joint\n0,{l0!r},{r0!r}\n{dt!r},{l1!r},{r1!r}\n"
        )
        odom = json.loads(run(Path(name), "odom", path, str(recording), "--json"))
        args = [repr(v) for v in (l0, r0, l1, r1, dt)]
        *_, pose = results(run(Path(name), "explain", "odom", path, *args))
    final = odom["final_pose"]
    assert pose["x₁"].matches(final["x"])
    assert pose["y₁"].matches(final["y"])
    assert pose["θ₁"].matches(final["theta"], angle=True)
