"""Robot parameters from URDF/xacro: the bundled robot, descriptions written here, every error."""

from __future__ import annotations

import json
import math
from collections.abc import Callable
from pathlib import Path

import pytest
from robots import two_wheel_urdf

import diffbot
from diffbot import urdf as urdf_module

Write = Callable[[str, str], Path]


def wheel(
    name: str,
    xyz: str,
    *,
    parent: str = "base_link",
    rpy: str = "0 0 0",
    axis: str = "0 1 0",
    radius: float | None = 0.05,
    shape_rpy: str = f"{math.pi / 2} 0 0",
    limit: float | None = None,
    joint_type: str = "continuous",
    visual_only: bool = False,
) -> str:
    """A wheel joint and link; its cylinder lies along the joint axis unless told otherwise."""
    limit_xml = f'<limit effort="1" velocity="{limit}"/>' if limit is not None else ""
    geometry = (
        f'<geometry><cylinder radius="{radius}" length="0.02"/></geometry>'
        if radius is not None
        else '<geometry><box size="0.1 0.02 0.1"/></geometry>'
    )
    element = "visual" if visual_only else "collision"
    return f"""
  <joint name="{name}" type="{joint_type}">
    <parent link="{parent}"/><child link="{name}_link"/>
    <origin xyz="{xyz}" rpy="{rpy}"/><axis xyz="{axis}"/>{limit_xml}
  </joint>
  <link name="{name}_link">
    <{element}><origin xyz="0 0 0" rpy="{shape_rpy}"/>{geometry}</{element}>
  </link>"""


def robot(*parts: str, links: str = '<link name="base_link"/>') -> str:
    return f'<?xml version="1.0"?>\n<robot name="test">\n  {links}{"".join(parts)}\n</robot>\n'


TWO_WHEELS = robot(wheel("left_wheel_joint", "0 0.1 0"), wheel("right_wheel_joint", "0 -0.1 0"))


# --- the bundled robot --------------------------------------------------------------------


def test_bundled_robot_has_the_class_values(params: diffbot.DiffDriveParams) -> None:
    assert params.wheel_radius == pytest.approx(0.035, abs=1e-15)
    assert params.wheel_separation == pytest.approx(0.135, abs=1e-15)
    assert (params.left_joint, params.right_joint) == (
        "front_left_wheel_joint",
        "front_right_wheel_joint",
    )
    assert (params.left_sign, params.right_sign) == (1, 1)
    assert params.max_wheel_speed == pytest.approx(5.23599, abs=1e-5)
    assert params.warnings == ()


def test_bundled_robot_takes_radius_separation_and_limit_as_xacro_args() -> None:
    params = diffbot.load_params(
        args={"wheel_radius": "0.04", "wheel_separation": 0.2, "max_wheel_rpm": "100"}
    )
    assert params.wheel_radius == pytest.approx(0.04, abs=1e-15)
    assert params.wheel_separation == pytest.approx(0.2, abs=1e-15)
    assert params.max_wheel_rpm == pytest.approx(100.0, rel=1e-12)


def test_bundled_expansion_holds_ros2_control_and_resolves_the_controllers_path() -> None:
    text = diffbot.expand().urdf
    assert '<ros2_control name="GazeboSystem" type="system">' in text
    assert "caster_rotation_joint" in text
    controllers = Path(text.split("<parameters>")[1].split("</parameters>")[0].strip())
    assert controllers.is_file()
    assert "JointGroupVelocityController" in controllers.read_text()


def test_undeclared_xacro_argument_is_reported_as_ignored() -> None:
    params = diffbot.load_params(args={"wheel_radiuss": "0.04"})
    assert params.wheel_radius == pytest.approx(0.035)
    assert any("'wheel_radiuss' is not declared" in w for w in params.warnings)
    # The arguments it does declare are known, a plain URDF's none.
    assert params.xacro_arguments == ("max_wheel_rpm", "wheel_radius", "wheel_separation")
    assert diffbot.expand().arguments == params.xacro_arguments


def test_a_plain_urdf_declares_no_xacro_argument(tmp_path: Path) -> None:
    path = tmp_path / "two.urdf"
    path.write_text(two_wheel_urdf(), encoding="utf-8")
    assert diffbot.load_params(path).xacro_arguments == ()


def test_overrides_replace_what_the_description_says() -> None:
    params = diffbot.load_params(wheel_radius=0.05, wheel_separation=0.3, max_wheel_speed=1.0)
    assert (params.wheel_radius, params.wheel_separation, params.max_wheel_speed) == (
        0.05,
        0.3,
        1.0,
    )


# --- structure ------------------------------------------------------------------------------


def test_plain_urdf_wheels_give_radius_separation_and_no_limit(write: Write) -> None:
    params = diffbot.load_params(write("r.urdf", TWO_WHEELS))
    assert params.wheel_radius == pytest.approx(0.05)
    assert params.wheel_separation == pytest.approx(0.2)
    assert (params.left_joint, params.right_joint) == ("left_wheel_joint", "right_wheel_joint")
    assert params.max_wheel_speed is None


def test_rotated_joint_frames_and_mirrored_axes_give_direction_signs(write: Write) -> None:
    # The common ROS style: each joint frame rolled so that its z axis is the axle.
    text = robot(
        wheel("l_joint", "0 0.15 0", rpy=f"{-math.pi / 2} 0 0", axis="0 0 1", shape_rpy="0 0 0"),
        wheel("r_joint", "0 -0.15 0", rpy=f"{math.pi / 2} 0 0", axis="0 0 1", shape_rpy="0 0 0"),
    )
    params = diffbot.load_params(write("rolled.urdf", text))
    assert params.wheel_separation == pytest.approx(0.3, abs=1e-12)
    # left axle points to +y (forward for positive velocity); right one to -y (backward)
    assert (params.left_sign, params.right_sign) == (1, -1)
    assert params.warnings == ()


def test_mirrored_axis_on_the_left_wheel_gives_a_negative_sign(write: Write) -> None:
    text = robot(
        wheel("left_wheel_joint", "0 0.1 0", axis="0 -1 0"),
        wheel("right_wheel_joint", "0 -0.1 0"),
    )
    params = diffbot.load_params(write("m.urdf", text))
    assert (params.left_sign, params.right_sign) == (-1, 1)


def test_wheels_found_through_a_yawed_chain_below_a_footprint(write: Write) -> None:
    # base_footprint -> base_link (raised) -> chassis (yawed 90 deg) -> wheels placed along the
    # chassis x axis, which is the base's y axis.
    links = """<link name="base_footprint"/><link name="base_link"/><link name="chassis"/>
  <joint name="footprint_joint" type="fixed"><parent link="base_footprint"/>
    <child link="base_link"/><origin xyz="0 0 0.05"/></joint>
  <joint name="chassis_joint" type="fixed"><parent link="base_link"/>
    <child link="chassis"/><origin xyz="0.1 0 0" rpy="0 0 1.5707963267948966"/></joint>"""
    text = robot(
        wheel("a_joint", "0.125 0 0", parent="chassis", axis="1 0 0", shape_rpy="0 1.5708 0"),
        wheel("b_joint", "-0.125 0 0", parent="chassis", axis="1 0 0", shape_rpy="0 1.5708 0"),
        links=links,
    )
    params = diffbot.load_params(write("chain.urdf", text))
    assert (params.left_joint, params.right_joint) == ("a_joint", "b_joint")
    assert params.wheel_separation == pytest.approx(0.25, abs=1e-12)
    assert (params.left_sign, params.right_sign) == (1, 1)


def test_caster_wheel_under_a_swivel_is_not_a_drive_wheel(write: Write) -> None:
    links = """<link name="base_link"/><link name="swivel"/>
  <joint name="caster_rotation_joint" type="continuous"><parent link="base_link"/>
    <child link="swivel"/><origin xyz="-0.2 0 0"/><axis xyz="0 0 1"/></joint>"""
    text = robot(
        wheel("left_joint", "0 0.1 0"),
        wheel("right_joint", "0 -0.1 0"),
        wheel("caster_wheel_joint", "-0.02 0.05 -0.03", parent="swivel"),
        links=links,
    )
    params = diffbot.load_params(write("caster.urdf", text))
    assert (params.left_joint, params.right_joint) == ("left_joint", "right_joint")


def test_separation_is_measured_at_the_wheels_mid_planes(write: Write) -> None:
    # Link frames at the motor flanges; the cylinders sit 1 cm further out along the axle.
    text = robot(
        wheel("left_wheel_joint", "0 0.1 0").replace(
            '<origin xyz="0 0 0" rpy', '<origin xyz="0 0.01 0" rpy'
        ),
        wheel("right_wheel_joint", "0 -0.1 0").replace(
            '<origin xyz="0 0 0" rpy', '<origin xyz="0 -0.01 0" rpy'
        ),
    )
    params = diffbot.load_params(write("flange.urdf", text))
    assert params.wheel_separation == pytest.approx(0.22, abs=1e-12)


def test_prefixed_xacro_macro_robot_is_found_by_structure(write: Write) -> None:
    text = """<?xml version="1.0"?>
<robot name="twin" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:arg name="prefix" default="robot1_"/>
  <xacro:property name="prefix" value="$(arg prefix)"/>
  <xacro:macro name="wheel" params="side y">
    <joint name="${prefix}${side}_drive" type="continuous">
      <parent link="${prefix}base_link"/><child link="${prefix}${side}_tyre"/>
      <origin xyz="0 ${y} 0"/><axis xyz="0 1 0"/><limit effort="1" velocity="3"/>
    </joint>
    <link name="${prefix}${side}_tyre"><collision><origin rpy="${pi/2} 0 0"/>
      <geometry><cylinder radius="0.06" length="0.03"/></geometry></collision></link>
  </xacro:macro>
  <link name="${prefix}base_link"/>
  <xacro:wheel side="left" y="0.12"/>
  <xacro:wheel side="right" y="-0.12"/>
</robot>
"""
    path = write("twin.urdf.xacro", text)
    params = diffbot.load_params(path, args={"prefix": "r2_"})
    assert (params.left_joint, params.right_joint) == ("r2_left_drive", "r2_right_drive")
    assert params.wheel_radius == pytest.approx(0.06)
    assert params.wheel_separation == pytest.approx(0.24)
    assert params.max_wheel_speed == pytest.approx(3.0)


def test_xacro_include_through_find_resolves_from_packages(tmp_path: Path, write: Write) -> None:
    write(
        "my_pkg/urdf/wheel.xacro",
        """<?xml version="1.0"?>
<robot xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:macro name="wheel" params="side y">
    <joint name="${side}_wheel_joint" type="continuous">
      <parent link="base_link"/><child link="${side}_wheel"/>
      <origin xyz="0 ${y} 0"/><axis xyz="0 1 0"/>
    </joint>
    <link name="${side}_wheel"><collision><origin rpy="${pi/2} 0 0"/>
      <geometry><cylinder radius="0.07" length="0.03"/></geometry></collision></link>
  </xacro:macro>
</robot>
""",
    )
    main = write(
        "robot.urdf.xacro",
        """<?xml version="1.0"?>
<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:include filename="$(find my_pkg)/urdf/wheel.xacro"/>
  <link name="base_link"/>
  <xacro:wheel side="left" y="0.2"/>
  <xacro:wheel side="right" y="-0.2"/>
</robot>
""",
    )
    params = diffbot.load_params(main, packages={"my_pkg": tmp_path / "my_pkg"})
    assert params.wheel_radius == pytest.approx(0.07)
    assert params.wheel_separation == pytest.approx(0.4)
    with pytest.raises(diffbot.PackageNotFoundError, match=r"package 'my_pkg' not found"):
        diffbot.load_params(main)


def test_find_falls_back_to_the_ament_prefix_path(
    tmp_path: Path, write: Write, monkeypatch: pytest.MonkeyPatch
) -> None:
    write("prefix/share/pkg_a/wheels.xacro", '<robot xmlns:xacro="http://www.ros.org/wiki/xacro"/>')
    main = write(
        "a.urdf.xacro",
        robot()
        .replace("<robot name", '<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name')
        .replace("</robot>", '<xacro:include filename="$(find pkg_a)/wheels.xacro"/></robot>'),
    )
    monkeypatch.setenv("AMENT_PREFIX_PATH", str(tmp_path / "prefix"))
    assert "<robot" in diffbot.expand(main).urdf


def test_a_joint_named_left_on_the_right_side_is_warned_about(write: Write) -> None:
    text = robot(
        wheel("right_wheel_joint", "0 0.1 0"),
        wheel("left_wheel_joint", "0 -0.1 0"),
    )
    params = diffbot.load_params(write("swapped.urdf", text))
    assert params.left_joint == "right_wheel_joint"
    assert any(
        "'right_wheel_joint' is named right but sits on the left side" in w for w in params.warnings
    )


def test_sphere_wheels_give_their_radius_and_visual_only_wheels_are_warned(write: Write) -> None:
    spheres = robot(
        wheel("left_joint", "0 0.1 0").replace(
            'cylinder radius="0.05" length="0.02"', 'sphere radius="0.04"'
        ),
        wheel("right_joint", "0 -0.1 0").replace(
            'cylinder radius="0.05" length="0.02"', 'sphere radius="0.04"'
        ),
    )
    assert diffbot.load_params(write("s.urdf", spheres)).wheel_radius == pytest.approx(0.04)
    visual = robot(
        wheel("left_joint", "0 0.1 0", visual_only=True),
        wheel("right_joint", "0 -0.1 0", visual_only=True),
    )
    params = diffbot.load_params(write("v.urdf", visual))
    assert params.wheel_radius == pytest.approx(0.05)
    assert any("no collision cylinder" in w for w in params.warnings)


def test_a_cylinder_lying_flat_is_warned_about(write: Write) -> None:
    text = robot(
        wheel("left_joint", "0 0.1 0", shape_rpy="0 0 0"),
        wheel("right_joint", "0 -0.1 0"),
    )
    params = diffbot.load_params(write("flat.urdf", text))
    assert any("not aligned with the axis of 'left_joint'" in w for w in params.warnings)


def test_different_limits_use_the_lower_one_with_a_warning(write: Write) -> None:
    text = robot(
        wheel("left_joint", "0 0.1 0", limit=4.0), wheel("right_joint", "0 -0.1 0", limit=6.0)
    )
    params = diffbot.load_params(write("lim.urdf", text))
    assert params.max_wheel_speed == pytest.approx(4.0)
    assert any("different velocity limits" in w for w in params.warnings)


def test_a_skid_steer_uses_every_wheel_with_a_warning(write: Write) -> None:
    text = robot(
        wheel("front_left", "0.1 0.12 0"),
        wheel("rear_left", "-0.1 0.12 0"),
        wheel("front_right", "0.1 -0.12 0"),
        wheel("rear_right", "-0.1 -0.12 0"),
    )
    path = write("skid.urdf", text)
    params = diffbot.load_params(path)
    assert params.left_joints == ("front_left", "rear_left")
    assert params.right_joints == ("front_right", "rear_right")
    assert (params.left_joint, params.right_joint) == ("front_left", "front_right")
    assert params.wheel_separation == pytest.approx(0.24, abs=1e-15)
    assert any("skid steer" in w for w in params.warnings)
    chosen = diffbot.load_params(path, left_joint="rear_left", right_joint="rear_right")
    assert (chosen.left_joints, chosen.right_joints) == (("rear_left",), ("rear_right",))
    listed = diffbot.load_params(path, left_joint="rear_left, front_left", right_joint="rear_right")
    assert listed.left_joints == ("rear_left", "front_left")


def test_uneven_sides_still_need_a_choice(write: Write) -> None:
    text = robot(
        wheel("front_left", "0.1 0.1 0"),
        wheel("rear_left", "-0.1 0.1 0"),
        wheel("right", "0 -0.1 0"),
    )
    path = write("three.urdf", text)
    with pytest.raises(diffbot.DriveWheelError, match=r"3 candidate drive wheels .*left_joint="):
        diffbot.load_params(path)
    params = diffbot.load_params(path, left_joint="rear_left")
    assert (params.left_joints, params.right_joints) == (("rear_left",), ("right",))


def test_wheels_behind_suspension_are_taken_at_rest_with_a_warning(write: Write) -> None:
    links = (
        '<link name="base_link"/><link name="arm"/>'
        '<joint name="drop" type="prismatic"><parent link="base_link"/><child link="arm"/>'
        '<axis xyz="0 0 1"/><limit lower="-0.02" upper="0.0" effort="1" velocity="1"/></joint>'
    )
    text = robot(wheel("left", "0 0.11 0", parent="arm"), wheel("right", "0 -0.11 0"), links=links)
    params = diffbot.load_params(write("drop.urdf", text))
    assert params.wheel_separation == pytest.approx(0.22, abs=1e-15)
    assert any("suspension" in w and "'drop'" in w for w in params.warnings)
    assert "drop" in params.passive_joints
    # A rest position outside the limits is clamped into them: the left wheel rises by 0.01 m,
    # which leaves the lateral separation alone, and a joint that leans it sideways moves it.
    leaning = links.replace('type="prismatic"', 'type="revolute"').replace(
        '<axis xyz="0 0 1"/><limit lower="-0.02" upper="0.0"',
        '<axis xyz="1 0 0"/><limit lower="0.1" upper="0.2"',
    )
    text = robot(
        wheel("left", "0 0.11 0", parent="arm"), wheel("right", "0 -0.11 0"), links=leaning
    )
    tilted = diffbot.load_params(write("lean.urdf", text))
    # Rotated by 0.1 rad about x, the wheel centre at y = 0.11 m moves to 0.11 cos(0.1).
    assert tilted.wheel_separation == pytest.approx(0.11 + 0.11 * math.cos(0.1), abs=1e-12)


def test_fixed_wheel_joints_count_when_named(write: Write) -> None:
    text = robot(
        wheel("wl", "0 0.2 0", joint_type="fixed"), wheel("wr", "0 -0.2 0", joint_type="fixed")
    )
    path = write("fixed_wheels.urdf", text)
    with pytest.raises(diffbot.DriveWheelError, match="no drive wheels"):
        diffbot.load_params(path)
    params = diffbot.load_params(path, left_joint="wl", right_joint="wr")
    assert params.wheel_separation == pytest.approx(0.4, abs=1e-15)
    assert (params.left_sign, params.right_sign) == (1, 1)
    assert any("'wl' is fixed" in w for w in params.warnings)


def test_the_other_moving_joints_are_the_robots_passive_joints(
    params: diffbot.DiffDriveParams,
) -> None:
    assert params.passive_joints == ("caster_rotation_joint", "caster_wheel_joint")
    assert params.left_joints == ("front_left_wheel_joint",)


# --- errors ---------------------------------------------------------------------------------


def test_missing_file_is_a_description_error(tmp_path: Path) -> None:
    with pytest.raises(diffbot.DescriptionError, match="no such file"):
        diffbot.load_params(tmp_path / "nothing.urdf")


def test_malformed_urdf_is_rejected_not_recovered(write: Write) -> None:
    with pytest.raises(diffbot.DescriptionError, match="malformed XML: mismatched tag"):
        diffbot.load_params(write("bad.urdf", TWO_WHEELS.replace("</link>", "</linkk>", 1)))


def test_malformed_xacro_is_rejected(write: Write) -> None:
    bad = '<robot xmlns:xacro="http://www.ros.org/wiki/xacro"><link name="a"></robot>'
    with pytest.raises(diffbot.DescriptionError, match="malformed XML"):
        diffbot.load_params(write("bad.urdf.xacro", bad))


def test_a_root_that_is_not_robot_is_rejected(write: Write) -> None:
    with pytest.raises(diffbot.DescriptionError, match="root element is <sdf>"):
        diffbot.load_params(write("x.urdf", "<sdf/>"))


def test_xacro_errors_name_the_problem_and_the_file(write: Write) -> None:
    text = (
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro"><link name="${nope}"/></robot>'
    )
    with pytest.raises(diffbot.XacroError, match=r"xacro: .*nope.*\(in .*undefined.urdf.xacro\)"):
        diffbot.load_params(write("undefined.urdf.xacro", text))


def test_no_drive_wheels_lists_the_continuous_joints(write: Write) -> None:
    text = robot(wheel("steer", "0 0 0", axis="0 0 1"))
    with pytest.raises(diffbot.DriveWheelError, match=r"no drive wheels.*\['steer'\]"):
        diffbot.load_params(write("none.urdf", text))


def test_wheels_on_one_side_only_are_rejected(write: Write) -> None:
    text = robot(wheel("a", "0 0.1 0"), wheel("b", "0.2 0.1 0"))
    with pytest.raises(diffbot.DriveWheelError, match="no drive wheel on the right side"):
        diffbot.load_params(write("oneside.urdf", text))


def test_a_chosen_joint_on_the_wrong_side_or_unknown_is_rejected(write: Write) -> None:
    path = write("two.urdf", TWO_WHEELS)
    with pytest.raises(diffbot.DriveWheelError, match="not on the left side"):
        diffbot.load_params(path, left_joint="right_wheel_joint")
    with pytest.raises(diffbot.DriveWheelError, match="no joint named 'ghost'"):
        diffbot.load_params(path, right_joint="ghost")


def test_wheels_without_a_cylinder_need_the_radius_given(write: Write) -> None:
    path = write(
        "box.urdf",
        robot(wheel("l", "0 0.1 0", radius=None), wheel("r", "0 -0.1 0", radius=None)),
    )
    with pytest.raises(diffbot.DriveWheelError, match=r"no cylinder .*wheel_radius="):
        diffbot.load_params(path)
    assert diffbot.load_params(path, wheel_radius=0.03).wheel_radius == 0.03


def test_a_joint_with_an_unknown_link_is_rejected(write: Write) -> None:
    text = TWO_WHEELS.replace(
        '<parent link="base_link"/><child link="left', '<parent link="ghost"/><child link="left'
    )
    with pytest.raises(diffbot.DescriptionError, match="unknown parent link 'ghost'"):
        diffbot.load_params(write("ghost.urdf", text))


def test_a_zero_wheel_radius_in_the_description_is_rejected(write: Write) -> None:
    text = robot(wheel("l", "0 0.1 0", radius=0.0), wheel("r", "0 -0.1 0", radius=0.0))
    with pytest.raises(diffbot.ParameterError, match="wheel_radius must be a finite number"):
        diffbot.load_params(write("zero.urdf", text))


@pytest.mark.parametrize(
    ("name", "value"),
    [
        ("wheel_radius", 1e308),
        ("wheel_radius", "abc"),
        ("wheel_radius", 10**400),
        ("wheel_separation", 1e-300),
        ("max_wheel_speed", 5e-324),
        ("max_wheel_speed", 1e6),
    ],
)
def test_an_override_no_robot_has_is_refused_by_name(name: str, value: object) -> None:
    with pytest.raises(diffbot.ParameterError, match=rf"^{name} must be .*, got "):
        diffbot.load_params(**{name: value})  # type: ignore[arg-type]


def test_numeric_string_overrides_are_their_numbers() -> None:
    text = diffbot.load_params(
        wheel_radius="0.04",  # type: ignore[arg-type]
        wheel_separation="0.2",  # type: ignore[arg-type]
        max_wheel_speed="5",  # type: ignore[arg-type]
    )
    number = diffbot.load_params(wheel_radius=0.04, wheel_separation=0.2, max_wheel_speed=5.0)
    assert text == number
    assert text.radii == number.radii == (0.04, 0.04)


def test_non_numeric_origin_is_an_invalid_urdf(write: Write) -> None:
    text = TWO_WHEELS.replace('xyz="0 0.1 0"', 'xyz="0 abc 0"')
    with pytest.raises(diffbot.DescriptionError, match="invalid URDF"):
        diffbot.load_params(write("nan.urdf", text))


# --- cache ----------------------------------------------------------------------------------


def test_derived_parameters_are_cached_and_a_broken_cache_is_ignored(
    tmp_path: Path, write: Write, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("DIFFBOT_CACHE_DIR", str(tmp_path / "cache"))
    path = write("c.urdf", TWO_WHEELS)
    first = diffbot.load_params(path)
    entries = list((tmp_path / "cache").glob("params-*.json"))
    assert len(entries) == 1
    assert json.loads(entries[0].read_text())["fields"]["wheel_radius"] == pytest.approx(0.05)
    assert diffbot.load_params(path) == first
    entries[0].write_text("{not json")
    assert diffbot.load_params(path) == first


def test_the_cache_can_be_turned_off(
    tmp_path: Path, write: Write, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("DIFFBOT_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.setenv("DIFFBOT_NO_CACHE", "1")
    diffbot.load_params(write("n.urdf", TWO_WHEELS))
    assert not (tmp_path / "cache").exists()


def test_derive_params_reads_urdf_text_directly() -> None:
    params = urdf_module.derive_params(TWO_WHEELS, left_joint="left_wheel_joint")
    assert params.wheel_separation == pytest.approx(0.2)
    assert params.source == "(URDF text)"


# --- structure that is not a tree, and other regressions ------------------------------------


def test_a_detached_cycle_is_rejected_not_looped_over(write: Write) -> None:
    cycle = """<link name="a"/><link name="b"/>
  <joint name="ab" type="continuous"><parent link="a"/><child link="b"/></joint>
  <joint name="ba" type="fixed"><parent link="b"/><child link="a"/></joint>"""
    text = TWO_WHEELS.replace("</robot>", cycle + "</robot>")
    with pytest.raises(diffbot.DescriptionError, match="a cycle through"):
        diffbot.load_params(write("cycle.urdf", text))


def test_a_link_with_two_parents_is_rejected(write: Write) -> None:
    extra = """<joint name="again" type="fixed"><parent link="base_link"/>
    <child link="left_wheel_joint_link"/></joint>"""
    text = TWO_WHEELS.replace("</robot>", extra + "</robot>")
    with pytest.raises(diffbot.DescriptionError, match="has two parent joints"):
        diffbot.load_params(write("two.urdf", text))


def test_links_defined_twice_are_rejected(write: Write) -> None:
    text = TWO_WHEELS.replace("</robot>", '<link name="base_link"/></robot>')
    with pytest.raises(diffbot.DescriptionError, match=r"more than once: \['base_link'\]"):
        diffbot.load_params(write("dup.urdf", text))


def test_a_chosen_joint_must_be_able_to_drive_a_wheel(write: Write) -> None:
    text = robot(
        wheel("left_joint", "0 0.1 0"),
        wheel("right_joint", "0 -0.1 0"),
        wheel("slide_joint", "0 0.2 0", joint_type="prismatic"),
    )
    path = write("slide.urdf", text)
    with pytest.raises(
        diffbot.DriveWheelError, match="'slide_joint' cannot drive a wheel: it is prismatic"
    ):
        diffbot.load_params(path, left_joint="slide_joint")


def test_a_chosen_joint_under_a_swivel_is_rejected(write: Write) -> None:
    links = """<link name="base_link"/><link name="swivel"/>
  <joint name="swivel_joint" type="continuous"><parent link="base_link"/>
    <child link="swivel"/><origin xyz="-0.2 0 0"/><axis xyz="0 0 1"/></joint>"""
    text = robot(
        wheel("left_joint", "0 0.1 0"),
        wheel("right_joint", "0 -0.1 0"),
        wheel("caster", "0 0.05 0", parent="swivel"),
        links=links,
    )
    with pytest.raises(diffbot.DriveWheelError, match=r"moving joint\(s\) \['swivel_joint'\]"):
        diffbot.load_params(write("sw.urdf", text), left_joint="caster")


def test_full_turn_revolute_wheels_count_and_mimic_wheels_do_not(write: Write) -> None:
    revolute = robot(
        wheel("left_joint", "0 0.1 0", joint_type="revolute").replace(
            "</joint>", '<limit lower="-1e9" upper="1e9" effort="1" velocity="2"/></joint>', 1
        ),
        wheel("right_joint", "0 -0.1 0", joint_type="revolute").replace(
            "</joint>", '<limit lower="-1e9" upper="1e9" effort="1" velocity="2"/></joint>', 1
        ),
        wheel("rear_left", "-0.2 0.1 0").replace(
            "</joint>", '<mimic joint="left_joint"/></joint>', 1
        ),
        wheel("rear_right", "-0.2 -0.1 0").replace(
            "</joint>", '<mimic joint="right_joint"/></joint>', 1
        ),
    )
    params = diffbot.load_params(write("rev.urdf", revolute))
    assert (params.left_joint, params.right_joint) == ("left_joint", "right_joint")
    assert params.max_wheel_speed == pytest.approx(2.0)


def test_separation_of_wheels_off_one_axle_is_their_lateral_distance(write: Write) -> None:
    text = robot(wheel("left_joint", "0.1 0.1 0"), wheel("right_joint", "-0.1 -0.1 0"))
    params = diffbot.load_params(write("off.urdf", text))
    assert params.wheel_separation == pytest.approx(0.2, abs=1e-12)
    assert any("not on one lateral axle" in w for w in params.warnings)


def test_a_plain_urdf_mentioning_xacro_in_a_comment_stays_plain(write: Write) -> None:
    text = TWO_WHEELS.replace("<robot", "<!-- generated by xacro: ${HOME} -->\n<robot", 1)
    params = diffbot.load_params(write("gen.urdf", text), args={"x": "1"})
    assert params.wheel_separation == pytest.approx(0.2)
    assert any("plain URDF" in w for w in params.warnings)


@pytest.mark.parametrize("value", ["nan", "inf"])
def test_a_non_finite_velocity_limit_is_an_error(write: Write, value: str) -> None:
    text = robot(
        wheel("left_joint", "0 0.1 0").replace(
            "</joint>", f'<limit effort="1" velocity="{value}"/></joint>', 1
        ),
        wheel("right_joint", "0 -0.1 0"),
    )
    with pytest.raises(diffbot.DescriptionError, match="non-finite velocity limit"):
        diffbot.load_params(write("lim.urdf", text))


@pytest.mark.parametrize("entry", ["{}", "[]", "null", '"x"'])
def test_a_cache_entry_of_the_wrong_shape_is_recomputed(
    tmp_path: Path, write: Write, monkeypatch: pytest.MonkeyPatch, entry: str
) -> None:
    monkeypatch.setenv("DIFFBOT_CACHE_DIR", str(tmp_path / "cache"))
    path = write("c.urdf", TWO_WHEELS)
    first = diffbot.load_params(path)
    (cached,) = (tmp_path / "cache").glob("params-*.json")
    cached.write_text(entry)
    assert diffbot.load_params(path) == first


def test_a_cache_entry_with_wrong_types_is_recomputed(
    tmp_path: Path, write: Write, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("DIFFBOT_CACHE_DIR", str(tmp_path / "cache"))
    path = write("c.urdf", TWO_WHEELS)
    first = diffbot.load_params(path)
    (cached,) = (tmp_path / "cache").glob("params-*.json")
    data = json.loads(cached.read_text())
    for field, bad in (("wheel_radius", "abc"), ("warnings", "abc"), ("left_sign", 2)):
        cached.write_text(json.dumps({**data, field: bad}))
        assert diffbot.load_params(path) == first
        assert diffbot.load_params(path).warnings == ()


@pytest.mark.parametrize("switch", ["trust", "no_controllers"])
def test_load_params_switches_are_bools_not_truthy_words(switch: str) -> None:
    with pytest.raises(diffbot.ParameterError, match=f"^{switch} must be True or False"):
        diffbot.load_params(**{switch: "false"})  # type: ignore[arg-type]
