"""Gazebo plugins read from a description: Gazebo classic's own DiffDrivePlugin, which measures
its separation and radius, the plugins of drives that are not differential, and the plugins of
nested SDF models, whose joints are their model's."""

from __future__ import annotations

import math
from xml.etree import ElementTree

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from diffbot.urdf.gazebo import gazebo_drives, other_drive_plugins, scoped_plugin

OWN_PLUGIN = (
    '<gazebo><plugin filename="libDiffDrivePlugin.so" name="diff_drive">'
    "<left_joint>left_hinge</left_joint><right_joint>right_hinge</right_joint>"
    "<torque>5</torque></plugin></gazebo>"
)


def wheel(name: str, parent: str, xyz: str, rpy: str = "0 0 0", shape: str = "") -> str:
    shape = shape or '<cylinder radius="0.1" length="0.04"/>'
    return (
        f'<joint name="{name}_hinge" type="continuous"><parent link="{parent}"/>'
        f'<child link="{name}_wheel"/><origin xyz="{xyz}" rpy="{rpy}"/><axis xyz="0 0 1"/>'
        f'</joint><link name="{name}_wheel"><collision><geometry>{shape}</geometry>'
        "</collision></link>"
    )


def root(body: str, plugins: str = OWN_PLUGIN) -> ElementTree.Element:
    return ElementTree.fromstring(f'<robot name="r"><link name="chassis"/>{body}{plugins}</robot>')


def test_the_own_plugin_measures_the_anchors_distance_and_the_left_wheels_radius() -> None:
    # Anchors at (0, 0.22, 0.1) and (0.05, -0.2, 0.1): 0.05 m apart along x, 0.42 m along y.
    body = wheel("left", "chassis", "0 0.22 0.1") + wheel(
        "right", "chassis", "0.05 -0.2 0.1", shape='<cylinder radius="0.3" length="0.04"/>'
    )
    (drive,) = gazebo_drives(root(body))
    assert drive.kind == "gazebo_diff_drive"
    assert (drive.left_joints, drive.right_joints) == (("left_hinge",), ("right_hinge",))
    assert drive.wheel_separation == pytest.approx(math.hypot(0.05, 0.42), abs=1e-12)
    assert drive.wheel_radius == pytest.approx(0.1, abs=1e-12)  # the left wheel's, not 0.3


def test_the_anchors_are_taken_through_the_whole_chain_of_joints() -> None:
    # The wheels hang from a mount yawed a quarter turn: its x is the chassis' y.
    mount = (
        '<joint name="mount_joint" type="fixed"><parent link="chassis"/><child link="mount"/>'
        f'<origin xyz="0.1 0 0.05" rpy="0 0 {math.pi / 2!r}"/></joint><link name="mount"/>'
    )
    body = mount + wheel("left", "mount", "0.25 0 0") + wheel("right", "mount", "-0.25 0 0")
    (drive,) = gazebo_drives(root(body))
    assert drive.wheel_separation == pytest.approx(0.5, abs=1e-12)


def test_a_sphere_is_a_radius_and_a_missing_joint_leaves_the_lengths_out() -> None:
    body = wheel("left", "chassis", "0 0.2 0", shape='<sphere radius="0.07"/>')
    body += wheel("right", "chassis", "0 -0.2 0")
    (drive,) = gazebo_drives(root(body))
    assert drive.wheel_radius == pytest.approx(0.07, abs=1e-12)
    (missing,) = gazebo_drives(root(wheel("left", "chassis", "0 0.2 0")))
    assert missing.wheel_separations == ()
    assert missing.wheel_radius == pytest.approx(0.1, abs=1e-12)


def test_a_cycle_of_joints_measures_nothing() -> None:
    body = (
        '<joint name="left_hinge" type="continuous"><parent link="a"/><child link="b"/></joint>'
        '<joint name="back" type="fixed"><parent link="b"/><child link="a"/></joint>'
        + wheel("right", "chassis", "0 -0.2 0")
    )
    (drive,) = gazebo_drives(root(body))
    assert drive.wheel_separations == ()


@settings(max_examples=50, deadline=None)
@given(
    left=st.tuples(*[st.floats(min_value=-2.0, max_value=2.0)] * 3),
    right=st.tuples(*[st.floats(min_value=-2.0, max_value=2.0)] * 3),
    yaw=st.floats(min_value=-math.pi, max_value=math.pi),
)
def test_the_separation_is_the_euclidean_distance_whatever_the_frames(
    left: tuple[float, float, float], right: tuple[float, float, float], yaw: float
) -> None:
    body = wheel("left", "chassis", " ".join(map(repr, left)), rpy=f"0 0 {yaw!r}")
    body += wheel("right", "chassis", " ".join(map(repr, right)), rpy=f"{yaw!r} 0 0")
    (drive,) = gazebo_drives(root(body))
    distance = math.dist(left, right)
    if distance == 0.0:
        assert drive.wheel_separations == ()
    else:
        assert drive.wheel_separation == pytest.approx(distance, abs=1e-12)


def test_steering_and_mecanum_plugins_are_named() -> None:
    plugins = (
        '<gazebo><plugin filename="gz-sim-ackermann-steering-system" '
        'name="gz::sim::systems::AckermannSteering"/></gazebo>'
        '<gazebo><plugin filename="libgazebo_ros_ackermann_drive.so" name="car"/></gazebo>'
        '<gazebo><plugin filename="gz-sim-mecanum-drive-system" '
        'name="gz::sim::systems::MecanumDrive"/></gazebo>'
        '<gazebo><plugin filename="libgazebo_ros_skid_steer_drive.so" name="skid"/></gazebo>'
        '<gazebo><plugin filename="gz-sim-diff-drive-system" '
        'name="gz::sim::systems::DiffDrive"/></gazebo>'
    )
    assert other_drive_plugins(root("", plugins)) == [
        "gz::sim::systems::AckermannSteering",
        "libgazebo_ros_ackermann_drive.so",
        "gz::sim::systems::MecanumDrive",
    ]


def test_a_nested_models_plugin_names_its_joints_in_the_whole_model() -> None:
    plugin = ElementTree.fromstring(
        '<plugin filename="gz-sim-diff-drive-system" name="gz::sim::systems::DiffDrive">'
        "<left_joint> fl </left_joint><left_joint>rl</left_joint><right_joint>fr</right_joint>"
        "<right_joint/><wheel_separation>0.5</wheel_separation><topic>left_joint</topic>"
        "</plugin>"
    )
    scoped = scoped_plugin(plugin, "robot::base::")
    assert [(c.tag, c.text) for c in scoped] == [
        ("left_joint", "robot::base::fl"),
        ("left_joint", "robot::base::rl"),
        ("right_joint", "robot::base::fr"),
        ("right_joint", None),
        ("wheel_separation", "0.5"),
        ("topic", "left_joint"),
    ]
    assert plugin.findtext("left_joint") == " fl "  # the parsed file is left as it was
    assert scoped_plugin(plugin, "") is plugin
    classic = ElementTree.fromstring(
        '<plugin filename="libgazebo_ros_skid_steer_drive.so"><leftFrontJoint>a</leftFrontJoint>'
        "<rightRearJoint>b</rightRearJoint><leftJoint>c</leftJoint></plugin>"
    )
    assert [c.text for c in scoped_plugin(classic, "m::")] == ["m::a", "m::b", "m::c"]


def plugin_topic(filename: str, inner: str, name: str = "cmd_vel") -> str | None:
    plugin = f'<gazebo><plugin filename="{filename}" name="drive">{inner}</plugin></gazebo>'
    (drive,) = gazebo_drives(root("", plugin))
    return drive.topics.get(name)


@pytest.mark.parametrize(
    ("inner", "topic"),
    [
        ("", "/cmd_vel"),
        # gazebo_ros_pkgs' ROS 2 world gazebo_ros_diff_drive_demo.world: a namespace, a remap.
        (
            "<ros><namespace>/demo</namespace><remapping>cmd_vel:=cmd_demo</remapping>"
            "<remapping>odom:=odom_demo</remapping></ros>",
            "/demo/cmd_demo",
        ),
        ("<ros><namespace>robot1/</namespace></ros>", "/robot1/cmd_vel"),
        ("<ros><remapping>cmd_vel:=/abs/twist</remapping></ros>", "/abs/twist"),
        (
            "<ros><namespace>/demo</namespace><remapping>/demo/cmd_vel:=x</remapping></ros>",
            "/demo/x",
        ),
        # A rule matches when it names the same topic, as rcl expands both.
        (
            "<ros><namespace>/demo</namespace><remapping>/cmd_vel:=x</remapping></ros>",
            "/demo/cmd_vel",
        ),
        (
            "<ros><namespace>/demo</namespace><remapping>~/cmd_vel:=x</remapping></ros>",
            "/demo/cmd_vel",
        ),
        (
            "<ros><namespace>/demo</namespace><remapping>cmd_vel:=~/twist</remapping></ros>",
            "/demo/drive/twist",
        ),
        ("<ros><remapping>cmd_vel:=a</remapping><remapping>cmd_vel:=b</remapping></ros>", "/a"),
        ("<ros><remapping>other:=x</remapping><remapping>odom:=y</remapping></ros>", "/cmd_vel"),
        # Dashing and Eloquent wrote remappings and the namespace as arguments.
        ("<ros><argument>__ns:=/old</argument><argument>cmd_vel:=cmd</argument></ros>", "/old/cmd"),
        # ROS 1: commandTopic in robotNamespace.
        ("<robotNamespace>/</robotNamespace><commandTopic>cmd_vel</commandTopic>", "/cmd_vel"),
        (
            "<robotNamespace>bot</robotNamespace><commandTopic>base/twist</commandTopic>",
            "/bot/base/twist",
        ),
        (
            "<commandTopic>/mobile_base/commands/velocity</commandTopic>",
            "/mobile_base/commands/velocity",
        ),
    ],
)
def test_a_ros_plugin_s_command_topic_takes_its_namespace_and_remapping(
    inner: str, topic: str
) -> None:
    assert plugin_topic("libgazebo_ros_diff_drive.so", inner) == topic
    assert plugin_topic("libgazebo_ros_skid_steer_drive.so", inner) == topic


def test_plugins_outside_ros_have_no_command_topic() -> None:
    # gz-sim's topic is a Gazebo transport one, reached from ROS only through a bridge.
    assert plugin_topic("gz-sim-diff-drive-system", "<topic>/model/r/cmd_vel</topic>") is None
    assert plugin_topic("libDiffDrivePlugin.so", "") is None


@pytest.mark.parametrize(
    ("inner", "topic"),
    [
        ("", "/odom"),
        (
            "<ros><namespace>/demo</namespace><remapping>cmd_vel:=cmd_demo</remapping>"
            "<remapping>odom:=odom_demo</remapping></ros>",
            "/demo/odom_demo",
        ),
        (
            "<robotNamespace>bot</robotNamespace><odometryTopic>wheel_odom</odometryTopic>",
            "/bot/wheel_odom",
        ),
    ],
)
def test_a_ros_plugin_s_odometry_topic_takes_its_namespace_and_remapping(
    inner: str, topic: str
) -> None:
    assert plugin_topic("libgazebo_ros_diff_drive.so", inner, "odom") == topic
