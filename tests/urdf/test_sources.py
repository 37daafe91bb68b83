"""Controller configuration and Gazebo plugins against the geometry: which value wins, where
each comes from, and where the sources disagree."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import diffbot
from diffbot.kinematics import forward, inverse
from diffbot.odometry import Odometry

WHEELS_XACRO = """<?xml version="1.0"?>
<robot xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:macro name="wheel" params="side y">
    <link name="${side}_wheel">
      <collision><origin rpy="${pi/2} 0 0"/>
        <geometry><cylinder radius="${wheel_radius}" length="0.03"/></geometry></collision>
    </link>
    <joint name="${side}_wheel_joint" type="continuous">
      <parent link="base_link"/><child link="${side}_wheel"/>
      <origin xyz="0 ${y} 0"/><axis xyz="0 1 0"/>
    </joint>
  </xacro:macro>
</robot>
"""

ROBOT_XACRO = """<?xml version="1.0"?>
<robot name="rover" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:property name="wheel_radius" value="0.05"/>
  <xacro:property name="track" value="0.36"/>
  <xacro:include filename="$(find rover_description)/urdf/wheels.xacro"/>
  <link name="base_link"/>
  <xacro:wheel side="left" y="${track/2}"/>
  <xacro:wheel side="right" y="${-track/2}"/>
  <gazebo>
    <plugin filename="gz_ros2_control-system" name="gz_ros2_control::GazeboSimROS2ControlPlugin">
      <parameters>$(find rover_description)/config/controllers.yaml</parameters>
    </plugin>
  </gazebo>
  PLUGIN
</robot>
"""

GZ_PLUGIN = """<gazebo>
    <plugin filename="gz-sim-diff-drive-system" name="gz::sim::systems::DiffDrive">
      <left_joint>left_wheel_joint</left_joint><right_joint>right_wheel_joint</right_joint>
      <wheel_separation>SEP</wheel_separation><wheel_radius>0.05</wheel_radius>
    </plugin>
  </gazebo>"""

CONTROLLERS = """/**:
  controller_manager:
    ros__parameters:
      update_rate: 50
      diff_cont:
        type: diff_drive_controller/DiffDriveController
  diff_cont:
    ros__parameters:
      left_wheel_names: ["left_wheel_joint"]
      right_wheel_names: ["right_wheel_joint"]
      wheel_separation: 0.36
      wheel_radius: 0.05
      wheel_separation_multiplier: 1.05
      left_wheel_radius_multiplier: 1.01
      right_wheel_radius_multiplier: 0.99
      linear.x.max_velocity: 0.5
"""

ROS1_CONTROLLERS = """mobile_base_controller:
  type: diff_drive_controller/DiffDriveController
  left_wheel: ['left_wheel_joint']
  right_wheel: ['right_wheel_joint']
  wheel_separation: 0.4
  wheel_radius: 0.05
"""


def workspace(tmp_path: Path, plugin: str = "", controllers: str | None = CONTROLLERS) -> Path:
    """A package laid out as in a ROS workspace: src/rover_description/{urdf,config}."""
    package = tmp_path / "src" / "rover_description"
    (package / "urdf").mkdir(parents=True)
    (package / "config").mkdir()
    (package / "urdf" / "wheels.xacro").write_text(WHEELS_XACRO, encoding="utf-8")
    robot = package / "urdf" / "rover.urdf.xacro"
    robot.write_text(ROBOT_XACRO.replace("PLUGIN", plugin), encoding="utf-8")
    if controllers is not None:
        (package / "config" / "controllers.yaml").write_text(controllers, encoding="utf-8")
    return robot


def load(robot: Path, **options: object) -> diffbot.DiffDriveParams:
    package = robot.parent.parent
    return diffbot.load_params(robot, packages={"rover_description": package}, **options)  # type: ignore[arg-type]


def test_the_controllers_file_the_plugin_names_wins_with_its_multipliers(tmp_path: Path) -> None:
    params = load(workspace(tmp_path))
    controllers = str(tmp_path / "src/rover_description/config/controllers.yaml")
    assert params.wheel_separation == pytest.approx(0.36 * 1.05, rel=1e-15)
    assert params.wheel_radius == pytest.approx(0.05, rel=1e-15)
    assert params.radii == pytest.approx((0.05 * 1.01, 0.05 * 0.99), rel=1e-15)
    assert params.sources["wheel_separation"] == f"controllers:{controllers}"
    assert params.sources["left_wheel_radius"] == f"controllers:{controllers}"
    assert params.sources["left_joints"] == f"controllers:{controllers}"
    assert params.controller is not None
    assert params.controller.linear.max_velocity == 0.5
    # The multiplier is a setting: the base separation is what agrees with the joints.
    assert params.disagreements == ()
    assert not any("disagree" in w for w in params.warnings)


def test_a_later_parameters_file_of_the_plugin_replaces_the_values_it_sets(
    tmp_path: Path,
) -> None:
    # As a simulation's ros2_control plugin names the controllers file, then its own overrides.
    robot = workspace(tmp_path)
    text = robot.read_text(encoding="utf-8")
    first = "<parameters>$(find rover_description)/config/controllers.yaml</parameters>"
    later = "<parameters>$(find rover_description)/config/sim.yaml</parameters>"
    robot.write_text(text.replace(first, first + later), encoding="utf-8")
    overrides = "diff_cont:\n  ros__parameters:\n    wheel_separation: 0.31\n"
    overrides += "    linear.x.max_velocity: 0.2\n"
    (robot.parent.parent / "config" / "sim.yaml").write_text(overrides, encoding="utf-8")
    params = load(robot)
    assert params.wheel_separation == pytest.approx(0.31 * 1.05, rel=1e-15)
    assert params.radii == pytest.approx((0.05 * 1.01, 0.05 * 0.99), rel=1e-15)
    assert params.controller is not None
    assert params.controller.linear.max_velocity == 0.2
    assert params.controller.source.endswith("controllers.yaml")


def test_overrides_win_over_the_controller(tmp_path: Path) -> None:
    params = load(workspace(tmp_path), wheel_radius=0.06, wheel_separation=0.5)
    assert (params.wheel_separation, *params.radii) == (0.5, 0.06, 0.06)
    assert params.sources["wheel_separation"] == params.sources["wheel_radius"] == "override"


def test_a_missing_parameters_file_is_a_warning_and_the_geometry_is_used(tmp_path: Path) -> None:
    params = load(workspace(tmp_path, controllers=None))
    assert params.wheel_separation == pytest.approx(0.36, rel=1e-15)
    assert params.controller is None
    assert set(params.sources.values()) == {"description"}
    assert any("does not exist here" in w for w in params.warnings)


def test_a_gazebo_plugin_that_disagrees_with_the_joints_is_reported(tmp_path: Path) -> None:
    robot = workspace(tmp_path, plugin=GZ_PLUGIN.replace("SEP", "0.40"), controllers=None)
    params = load(robot)
    (found,) = params.disagreements
    assert found.field == "wheel_separation"
    assert found.values == {"description": pytest.approx(0.36), "gazebo plugin": 0.4}
    assert found.difference == pytest.approx(0.04, abs=1e-12)
    agreeing = load(
        workspace(tmp_path / "b", plugin=GZ_PLUGIN.replace("SEP", "0.3602"), controllers=None)
    )
    assert agreeing.disagreements == ()  # 0.2 mm is within the 0.5 mm tolerance


def test_a_ros1_controllers_file_given_explicitly(tmp_path: Path) -> None:
    config = tmp_path / "ros1.yaml"
    config.write_text(ROS1_CONTROLLERS, encoding="utf-8")
    params = load(workspace(tmp_path, controllers=None), controllers=config)
    assert params.wheel_separation == pytest.approx(0.4, rel=1e-15)
    assert params.sources["wheel_separation"] == f"controllers:{config}"


def test_a_controller_whose_left_wheel_sits_on_the_right_is_a_disagreement(
    tmp_path: Path,
) -> None:
    swapped = CONTROLLERS.replace('["left_wheel_joint"]', "X").replace(
        '["right_wheel_joint"]', '["left_wheel_joint"]'
    )
    swapped = swapped.replace("X", '["right_wheel_joint"]')
    params = load(workspace(tmp_path, controllers=swapped))
    assert params.left_joints == ("left_wheel_joint",)  # the geometry decides the sides
    fields = {d.field for d in params.disagreements}
    assert {"left_joints", "right_joints"} <= fields
    assert any("controller's wheels cannot be used" in w for w in params.warnings)


def test_several_diff_drive_controllers_need_a_name(tmp_path: Path) -> None:
    two = CONTROLLERS + CONTROLLERS.replace("diff_cont", "other_cont").replace("/**:", "/**/b:")
    config = tmp_path / "two.yaml"
    config.write_text(two, encoding="utf-8")
    robot = workspace(tmp_path, controllers=None)
    with pytest.raises(
        diffbot.DescriptionError, match=r"several diff-drive controllers.*controller="
    ):
        load(robot, controllers=config)
    assert load(robot, controllers=config, controller="other_cont").controller is not None


@settings(max_examples=50, deadline=None)
@given(
    multipliers=st.tuples(*(st.floats(0.9, 1.1) for _ in range(3))),
    speeds=st.tuples(st.floats(-3, 3), st.floats(-3, 3)),
)
def test_kinematics_and_odometry_follow_the_multiplied_geometry(
    multipliers: tuple[float, float, float], speeds: tuple[float, float]
) -> None:
    separation, left, right = multipliers
    base = diffbot.DiffDriveParams(wheel_radius=0.05, wheel_separation=0.36)
    params = base.replace(
        wheel_separation=0.36 * separation,
        left_wheel_radius=0.05 * left,
        right_wheel_radius=0.05 * right,
    )
    twist = forward(params, *speeds)
    assert twist.linear == pytest.approx(0.5 * 0.05 * (left * speeds[0] + right * speeds[1]))
    wheels = inverse(params, twist.linear, twist.angular)
    assert wheels.left == pytest.approx(speeds[0], abs=1e-9)
    assert wheels.right == pytest.approx(speeds[1], abs=1e-9)
    odom = Odometry(params)
    odom.update(0.0, 0.0, 0.0)
    odom.update(speeds[0], speeds[1], 1.0)
    assert odom.twist.linear == pytest.approx(twist.linear, abs=1e-12)
    assert odom.twist.angular == pytest.approx(twist.angular, abs=1e-12)
    assert math.isclose(odom.heading, twist.angular, abs_tol=1e-12)


# --- paper cuts found on real workspaces -----------------------------------------------------


def test_a_relative_package_directory_is_taken_from_the_current_directory(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    robot = workspace(tmp_path, controllers=None)
    monkeypatch.chdir(tmp_path)
    params = diffbot.load_params(robot, packages={"rover_description": "src/rover_description"})
    assert params.wheel_separation == pytest.approx(0.36, rel=1e-15)


def test_a_missing_package_is_named_when_the_expansion_reaches_it(tmp_path: Path) -> None:
    # the workspace holds no package.xml, so no source tree tells where rover_description is
    robot = workspace(tmp_path, controllers=None)
    with pytest.raises(
        diffbot.PackageNotFoundError,
        match=r"^package 'rover_description' not found \(needed by rover\.urdf\.xacro\): give "
        r"its directory with packages: rover_description=DIR$",
    ):
        diffbot.load_params(robot)


def test_a_file_of_macros_says_so(tmp_path: Path) -> None:
    robot = workspace(tmp_path, controllers=None)
    with pytest.raises(diffbot.DescriptionError, match="defines no links: is it a file of macros"):
        diffbot.load_params(robot.parent / "wheels.xacro")


def test_a_controllers_file_gets_the_descriptions_size_check(tmp_path: Path) -> None:
    absurd = CONTROLLERS.replace("wheel_separation: 0.36", "wheel_separation: 1200.0")
    with pytest.raises(
        diffbot.DescriptionError,
        match=r"wheel separation 1260 m \(from the controller's wheel_separation in .*\) is out",
    ):
        load(workspace(tmp_path, controllers=absurd))


# --- the controllers file a description names stays in its sandbox ------------------------------


def named_elsewhere(tmp_path: Path, parameters: str) -> Path:
    """The workspace's robot naming ``parameters`` as its controllers file, and a controllers
    file outside the package at ``tmp_path/outside/controllers.yaml``."""
    robot = workspace(tmp_path)
    text = robot.read_text(encoding="utf-8")
    robot.write_text(
        text.replace("$(find rover_description)/config/controllers.yaml", parameters),
        encoding="utf-8",
    )
    (tmp_path / "outside").mkdir()
    (tmp_path / "outside" / "controllers.yaml").write_text(
        CONTROLLERS.replace("0.36", "0.5"), encoding="utf-8"
    )
    return robot


def test_a_controllers_file_outside_the_package_is_read_only_when_trusted(tmp_path: Path) -> None:
    from diffbot.errors import OutsideRootsError

    robot = named_elsewhere(tmp_path, str(tmp_path / "outside" / "controllers.yaml"))
    with pytest.raises(OutsideRootsError, match=r"outside/controllers.yaml.*trust=True"):
        load(robot)
    trusted = load(robot, trust=True)
    assert trusted.wheel_separation == pytest.approx(0.5 * 1.05, rel=1e-12)


def test_a_relative_controllers_name_starts_from_the_description_folder(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    robot = named_elsewhere(tmp_path, "../config/controllers.yaml")
    monkeypatch.chdir(tmp_path / "outside")  # a ../config/controllers.yaml here would not count
    params = load(robot)
    assert params.wheel_separation == pytest.approx(0.36 * 1.05, rel=1e-12)
    assert params.sources["wheel_separation"].endswith("config/controllers.yaml")


def test_an_expansion_lists_the_folders_it_may_read(tmp_path: Path) -> None:
    robot = workspace(tmp_path)
    package = robot.parent.parent
    expansion = diffbot.expand(robot, packages={"rover_description": package})
    assert robot.parent.resolve() in expansion.folders
    assert package.resolve() in expansion.folders
    assert tmp_path.resolve() not in expansion.folders


def test_an_expansion_says_which_included_file_wrote_each_parameters_element(
    tmp_path: Path,
) -> None:
    # The folder travels through xacro as an attribute (escaped, as a folder with "${" in its
    # name shows), and is taken out of the URDF text.
    control = tmp_path / "pkg ${odd}" / "control"
    control.mkdir(parents=True)
    (control.parent / "package.xml").write_text("<package><name>p</name></package>", "utf-8")
    (control / "plugin.xacro").write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro"><gazebo><plugin name="g" '
        'filename="libgazebo_ros2_control.so"><parameters>config/c.yaml</parameters></plugin>'
        "</gazebo></robot>",
        encoding="utf-8",
    )
    robot = tmp_path / "pkg ${odd}" / "urdf" / "robot.urdf.xacro"
    robot.parent.mkdir()
    robot.write_text(
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro"><link name="base"/>'
        '<xacro:include filename="../control/plugin.xacro"/>'
        "<gazebo><plugin name='h' filename='x.so'><parameters>top.yaml</parameters></plugin>"
        "</gazebo></robot>",
        encoding="utf-8",
    )
    expansion = diffbot.expand(robot)
    assert dict(expansion.named_from) == {
        "config/c.yaml": control.resolve(),
        "top.yaml": robot.parent.resolve(),
    }
    assert "diffbot-named-from" not in expansion.urdf
    assert "<parameters>config/c.yaml</parameters>" in expansion.urdf


# --- wheels whose collision is a mesh ----------------------------------------------------


def test_a_mesh_is_read_only_when_no_other_source_gives_the_radius(tmp_path: Path) -> None:
    # The wheels' meshes lie outside the description's folders; the controller gives the
    # radius, so they are never needed.
    robot = workspace(tmp_path)
    (robot.parent / "wheels.xacro").write_text(
        WHEELS_XACRO.replace(
            '<cylinder radius="${wheel_radius}" length="0.03"/>',
            '<mesh filename="file:///nowhere/tyre.stl"/>',
        ),
        encoding="utf-8",
    )
    params = load(robot)
    assert params.wheel_radius == pytest.approx(0.05, rel=1e-15)
    assert params.sources["wheel_radius"].startswith("controllers:")
    with pytest.raises(diffbot.DescriptionError, match="outside the description's folders"):
        load(robot, no_controllers=True)
