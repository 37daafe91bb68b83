"""Diff-drive settings from controllers YAML and Gazebo plugins: every form, every error.

The known values marked "ros2_controllers" are ported from ros-controls/ros2_controllers,
``diff_drive_controller/test/test_odometry.cpp`` and ``test_diff_drive_controller.cpp``, test named
in each case; they are checked here through the configuration this module reads and diffbot's own
kinematics and odometry.
"""

from __future__ import annotations

import dataclasses
import math
import os
from pathlib import Path
from xml.etree import ElementTree

import pytest
from hypothesis import given
from hypothesis import strategies as st

from diffbot.errors import DescriptionError
from diffbot.kinematics import DiffDriveParams, inverse, norm_angle
from diffbot.odometry import Odometry
from diffbot.urdf.controllers import (
    MAX_FILE_BYTES,
    AxisLimits,
    ControllerConfig,
    ControllerConfigError,
    choose_controller,
    load_command_controllers,
    load_controllers,
    load_other_drive_controllers,
    other_drive_controllers,
    read_controller_files,
    read_controllers,
    substitute_args,
)
from diffbot.urdf.gazebo import (
    GazeboPluginError,
    gazebo_drives,
    ros2_control_parameter_files,
)

TOL = 1e-12

ROS2_NESTED = """
controller_manager:
  ros__parameters:
    update_rate: 50
    joint_state_broadcaster:
      type: joint_state_broadcaster/JointStateBroadcaster
    diff_cont:
      type: diff_drive_controller/DiffDriveController

diff_cont:
  ros__parameters:
    left_wheel_names: [front_left_wheel_joint, rear_left_wheel_joint]
    right_wheel_names: [front_right_wheel_joint, rear_right_wheel_joint]
    wheel_separation: 0.30
    wheel_radius: 0.05
    wheels_per_side: 2
    wheel_separation_multiplier: 1.1
    left_wheel_radius_multiplier: 0.98
    right_wheel_radius_multiplier: 1.02
    odom_frame_id: odom
    base_frame_id: base_footprint
    pose_covariance_diagonal: [0.001, 0.001, 0.0, 0.0, 0.0, 0.01]
    twist_covariance_diagonal: [0.002, 0.002, 0.0, 0.0, 0.0, 0.02]
    publish_rate: 40.0
    open_loop: false
    enable_odom_tf: true
    use_stamped_vel: false
    preserve_turning_radius: true
    cmd_vel_timeout: 0.25
    velocity_rolling_window_size: 4
    some_future_parameter: {anything: [1, 2]}
    linear:
      x:
        max_velocity: 0.8
        min_velocity: -0.4
        max_acceleration: 1.5
        max_deceleration: -3.0
        max_jerk: .nan
    angular:
      z:
        max_velocity: 2.0
        max_acceleration: 4.0
"""


def one(text: str, source: str = "controllers.yaml") -> ControllerConfig:
    """The single diff-drive controller of a YAML text."""
    configs = read_controllers(text, source)
    assert len(configs) == 1, configs
    return configs[0]


def section(body: str, name: str = "diff_cont", manager: str = "controller_manager") -> str:
    """A ROS 2 file declaring one diff-drive controller ``name`` with the given parameters."""
    indented = "\n".join("    " + line for line in body.strip().splitlines())
    return (
        f"{manager}:\n  ros__parameters:\n    update_rate: 100\n"
        f"    {name}:\n      type: diff_drive_controller/DiffDriveController\n"
        f"{name}:\n  ros__parameters:\n{indented}\n"
    )


def test_a_later_file_replaces_what_it_sets_and_keeps_the_rest() -> None:
    # One node given both files, in order: the simulation's file changes one value, its own
    # duplicate key within a file is said, and the controller is the first file's.
    later = (
        "diff_cont:\n  ros__parameters:\n    wheel_separation: 0.4\n    wheel_separation: 0.42\n"
    )
    (config,) = read_controller_files([(ROS2_NESTED, "a.yaml"), (later, "b.yaml")])
    assert config.source == "a.yaml"
    assert config.wheel_separation == 0.42
    assert config.wheel_radius == 0.05
    assert config.wheels_per_side == 2
    assert config.linear.max_velocity == 0.8
    assert any(w.startswith("b.yaml: ") for w in config.warnings)
    (alone,) = read_controller_files([(ROS2_NESTED, "a.yaml")])
    assert alone.wheel_separation == 0.30
    assert read_controller_files([(later, "b.yaml")]) == []  # no file declares its type


def params_of(config: ControllerConfig, radius: float | None = None) -> DiffDriveParams:
    """The robot a controller computes with (one radius: ``radius`` or the left one)."""
    left_radius = config.left_radius if radius is None else radius
    separation = config.effective_separation
    assert left_radius is not None
    assert separation is not None
    return DiffDriveParams(wheel_radius=left_radius, wheel_separation=separation)


# --- ROS 2 forms ------------------------------------------------------------------------------


def test_ros2_nested_file_gives_every_setting() -> None:
    config = one(ROS2_NESTED)
    assert config == ControllerConfig(
        name="diff_cont",
        source="controllers.yaml",
        ros_version=2,
        left_wheel_names=("front_left_wheel_joint", "rear_left_wheel_joint"),
        right_wheel_names=("front_right_wheel_joint", "rear_right_wheel_joint"),
        wheel_separation=0.30,
        wheel_radius=0.05,
        wheels_per_side=2,
        wheel_separation_multiplier=1.1,
        left_wheel_radius_multiplier=0.98,
        right_wheel_radius_multiplier=1.02,
        linear=AxisLimits(
            max_velocity=0.8,
            min_velocity=-0.4,
            max_acceleration=1.5,
            max_deceleration=-3.0,
        ),
        angular=AxisLimits(max_velocity=2.0, max_acceleration=4.0),
        preserve_turning_radius=True,
        open_loop=False,
        use_stamped_vel=False,
        odom_frame_id="odom",
        base_frame_id="base_footprint",
        pose_covariance_diagonal=(0.001, 0.001, 0.0, 0.0, 0.0, 0.01),
        twist_covariance_diagonal=(0.002, 0.002, 0.0, 0.0, 0.0, 0.02),
        publish_rate=40.0,
        enable_odom_tf=True,
        velocity_rolling_window_size=4,
        cmd_vel_timeout=0.25,
        update_rate=50.0,
    )
    assert config.warnings == ()


def test_multipliers_give_the_effective_separation_and_radii() -> None:
    config = one(ROS2_NESTED)
    assert config.effective_separation == pytest.approx(0.33, abs=TOL)
    assert config.left_radius == pytest.approx(0.049, abs=TOL)
    assert config.right_radius == pytest.approx(0.051, abs=TOL)


def test_absent_settings_are_none_and_multipliers_default_to_one() -> None:
    config = one(section("left_wheel_names: [l]\nright_wheel_names: [r]"))
    assert (config.wheel_separation, config.wheel_radius) == (None, None)
    assert (config.effective_separation, config.left_radius, config.right_radius) == (
        None,
        None,
        None,
    )
    assert config.wheel_separation_multiplier == 1.0
    assert config.left_wheel_radius_multiplier == config.right_wheel_radius_multiplier == 1.0
    assert config.linear == config.angular == AxisLimits()
    assert config.open_loop is None
    assert config.update_rate == 100.0


def test_dotted_keys_read_as_nested_ones() -> None:
    nested = one(ROS2_NESTED)
    dotted = one(
        section(
            """
left_wheel_names: [front_left_wheel_joint, rear_left_wheel_joint]
right_wheel_names: [front_right_wheel_joint, rear_right_wheel_joint]
linear.x.max_velocity: 0.8
linear.x.min_velocity: -0.4
linear:
  x.max_acceleration: 1.5
  x: {max_deceleration: -3.0}
angular.z: {max_velocity: 2.0}
angular.z.max_acceleration: 4.0
"""
        )
    )
    assert dotted.linear == nested.linear
    assert dotted.angular == nested.angular


@given(
    st.lists(
        st.sampled_from(["max_velocity", "max_acceleration", "max_jerk"]), unique=True, min_size=1
    ),
    st.floats(min_value=0.0, max_value=100.0, allow_nan=False),
)
def test_dotted_and_nested_limits_agree_for_any_values(keys: list[str], value: float) -> None:
    dotted = "\n".join(f"linear.x.{key}: {value!r}" for key in keys)
    nested = "linear:\n  x:\n" + "\n".join(f"    {key}: {value!r}" for key in keys)
    a = one(section(dotted)).linear
    b = one(section(nested)).linear
    assert a == b
    assert all(getattr(a, key) == value for key in keys)


def test_wildcard_node_names_and_wildcard_parameters_apply() -> None:
    config = one(
        """
/**:
  ros__parameters:
    use_sim_time: true
    wheel_radius: 0.04
/**/controller_manager:
  ros__parameters:
    update_rate: 20
    base_controller: {type: diff_drive_controller/DiffDriveController}
/**/base_controller:
  ros__parameters:
    left_wheel_names: [l]
    right_wheel_names: [r]
    wheel_separation: 0.2
"""
    )
    assert config.name == "base_controller"
    assert (config.wheel_radius, config.wheel_separation, config.update_rate) == (0.04, 0.2, 20.0)


def test_namespaced_manager_and_controller_are_matched_by_their_last_component() -> None:
    config = one(
        section(
            "left_wheel_names: [l]\nright_wheel_names: [r]\nwheel_separation: 0.25",
            name="/robot1/diff_cont",
            manager="robot1/controller_manager",
        ).replace("    /robot1/diff_cont:\n", "    diff_cont:\n")
    )
    assert (config.name, config.wheel_separation, config.update_rate) == ("diff_cont", 0.25, 100.0)


def test_namespaces_as_nested_keys_are_followed() -> None:
    config = one(
        """
robot1:
  controller_manager:
    ros__parameters:
      update_rate: 60
      diff_cont: {type: diff_drive_controller/DiffDriveController}
  diff_cont:
    ros__parameters: {left_wheel_names: [l], right_wheel_names: [r], wheel_radius: 0.07}
"""
    )
    assert (config.name, config.wheel_radius, config.update_rate) == ("diff_cont", 0.07, 60.0)


WHEELS = "  ros__parameters: {left_wheel_names: [l], right_wheel_names: [r]}\n"


@pytest.mark.parametrize(
    ("text", "namespace"),
    [
        # the controller's own section names its node's namespace
        (section("wheel_radius: 0.07", name="/robot1/diff_cont"), "robot1"),
        # namespace keys above both sections
        (
            "robot1:\n  controller_manager:\n    ros__parameters:\n"
            "      diff_cont: {type: diff_drive_controller/DiffDriveController}\n"
            "  diff_cont:\n    ros__parameters: {left_wheel_names: [l], right_wheel_names: [r]}\n",
            "robot1",
        ),
        # a wildcard leaves it to the controller manager's section
        (
            "/a/b/controller_manager:\n  ros__parameters:\n"
            "    diff_cont: {type: diff_drive_controller/DiffDriveController}\n"
            "/**/diff_cont:\n" + WHEELS,
            "a/b",
        ),
        # the type in the controller's own namespaced section
        (
            "/ns/diff_cont:\n  ros__parameters:\n"
            "    type: diff_drive_controller/DiffDriveController\n"
            "    left_wheel_names: [l]\n    right_wheel_names: [r]\n",
            "ns",
        ),
        # wildcards everywhere, or no namespace at all: the root
        (
            "/**/controller_manager:\n  ros__parameters:\n"
            "    diff_cont: {type: diff_drive_controller/DiffDriveController}\n"
            "/**/diff_cont:\n" + WHEELS,
            "",
        ),
        (section("wheel_radius: 0.07"), ""),
    ],
)
def test_the_controllers_node_namespace_is_the_one_its_file_names(
    text: str, namespace: str
) -> None:
    config = one(text)
    assert (config.name, config.namespace) == ("diff_cont", namespace)
    assert config.node_name == "/" + "/".join(p for p in (namespace, "diff_cont") if p)


def test_the_frame_prefix_is_read_with_the_namespace_it_stands_for() -> None:
    def config(lines: str) -> ControllerConfig:
        wheels = "left_wheel_names: [l]\nright_wheel_names: [r]\n"
        return one(section(wheels + lines, "/a200_0000/diff_cont"))

    # An empty tf_frame_prefix is the controller's default, not a malformed value.
    empty = config("tf_frame_prefix: ''")
    assert (empty.tf_frame_prefix, empty.odom_frame) == ("", "a200_0000/odom")
    tilde = config("tf_frame_prefix: '~/robot'\nbase_frame_id: base")
    assert tilde.base_frame == "a200_0000/robot/base"
    off = config("tf_frame_prefix_enable: false")
    assert (off.tf_frame_prefix_enable, off.base_frame) == (False, "base_link")


def test_type_in_the_controllers_own_section_is_found() -> None:
    config = one(
        """
controller_manager:
  ros__parameters: {update_rate: 30}
diff_cont:
  ros__parameters:
    type: diff_drive_controller/DiffDriveController
    left_wheel_names: [l]
    right_wheel_names: [r]
    wheel_separation: 0.5
"""
    )
    assert (config.name, config.wheel_separation, config.update_rate) == ("diff_cont", 0.5, 30.0)


def test_declared_controller_without_a_section_is_kept_with_a_warning() -> None:
    config = one(
        "controller_manager:\n  ros__parameters:\n"
        "    diff_cont: {type: diff_drive_controller/DiffDriveController}\n"
    )
    assert config.left_wheel_names == ()
    assert config.warnings == ("no diff_cont: ros__parameters section configures it",)


def test_other_controller_types_and_empty_files_give_no_controller() -> None:
    text = (
        "controller_manager:\n  ros__parameters:\n"
        "    jsb: {type: joint_state_broadcaster/JointStateBroadcaster}\n"
        "jsb:\n  ros__parameters: {type: joint_state_broadcaster/JointStateBroadcaster}\n"
    )
    assert read_controllers(text, "a.yaml") == []
    assert read_controllers("", "empty.yaml") == []
    assert read_controllers("# nothing\n", "comment.yaml") == []


# --- choosing among several -------------------------------------------------------------------

TWO_CONTROLLERS = """
controller_manager:
  ros__parameters:
    front_drive: {type: diff_drive_controller/DiffDriveController}
    rear_drive: {type: diff_drive_controller/DiffDriveController}
front_drive:
  ros__parameters: {left_wheel_names: [fl], right_wheel_names: [fr], wheel_separation: 0.4}
rear_drive:
  ros__parameters: {left_wheel_names: [rl], right_wheel_names: [rr], wheel_separation: 0.5}
"""


def test_two_controllers_are_both_found_in_declaration_order() -> None:
    configs = read_controllers(TWO_CONTROLLERS, "two.yaml")
    assert [(c.name, c.wheel_separation) for c in configs] == [
        ("front_drive", 0.4),
        ("rear_drive", 0.5),
    ]


def test_choosing_among_two_by_name_gives_that_one() -> None:
    configs = read_controllers(TWO_CONTROLLERS, "two.yaml")
    assert choose_controller(configs, "rear_drive").left_wheel_names == ("rl",)


def test_choosing_among_two_without_a_name_lists_the_names() -> None:
    configs = read_controllers(TWO_CONTROLLERS, "two.yaml")
    with pytest.raises(
        ControllerConfigError, match=r"several .* in two\.yaml: 'front_drive', 'rear_drive'"
    ):
        choose_controller(configs)


def test_choosing_an_unknown_name_lists_the_names() -> None:
    configs = read_controllers(TWO_CONTROLLERS, "two.yaml")
    with pytest.raises(
        ControllerConfigError, match=r"no diff-drive controller 'middle'.*'front_drive', 'rear"
    ):
        choose_controller(configs, "middle")


def test_choosing_from_none_is_an_error() -> None:
    with pytest.raises(ControllerConfigError, match="no diff_drive_controller/DiffDriveController"):
        choose_controller([])


def test_the_only_controller_is_chosen_without_a_name() -> None:
    config = one(ROS2_NESTED)
    assert choose_controller([config]) is config


# --- ROS 1 ------------------------------------------------------------------------------------

ROS1 = """
robot:
  mobile_base_controller:
    type: "diff_drive_controller/DiffDriveController"
    left_wheel: ['front_left_wheel', 'rear_left_wheel']
    right_wheel: ['front_right_wheel', 'rear_right_wheel']
    publish_rate: 50.0
    wheel_separation: 0.555
    wheel_radius: 0.165
    wheel_separation_multiplier: 1.5
    wheel_radius_multiplier: 0.9
    cmd_vel_timeout: 0.25
    enable_odom_tf: false
    linear:
      x:
        has_velocity_limits: true
        max_velocity: 1.0
        min_velocity: -0.5
        has_acceleration_limits: true
        max_acceleration: 3.0
        min_acceleration: -2.0
        max_jerk: 5.0
    angular:
      z:
        has_velocity_limits: false
        max_velocity: 2.0
        has_acceleration_limits: true
        max_acceleration: 6.0
"""


def test_ros1_controller_under_a_namespace_with_wheel_lists() -> None:
    config = one(ROS1, "control.yaml")
    assert (config.name, config.ros_version, config.update_rate) == (
        "mobile_base_controller",
        1,
        None,
    )
    assert config.left_wheel_names == ("front_left_wheel", "rear_left_wheel")
    assert config.right_wheel_names == ("front_right_wheel", "rear_right_wheel")
    assert (config.publish_rate, config.cmd_vel_timeout, config.enable_odom_tf) == (
        50.0,
        0.25,
        False,
    )


def test_ros1_single_radius_multiplier_applies_to_both_sides() -> None:
    config = one(ROS1)
    assert config.effective_separation == pytest.approx(0.8325, abs=TOL)
    assert config.left_radius == pytest.approx(0.1485, abs=TOL)
    assert config.right_radius == pytest.approx(0.1485, abs=TOL)


def test_ros1_limit_flags_switch_groups_and_default_to_off() -> None:
    config = one(ROS1)
    assert config.linear == AxisLimits(
        max_velocity=1.0, min_velocity=-0.5, max_acceleration=3.0, min_acceleration=-2.0
    )  # max_jerk is dropped: has_jerk_limits defaults to false in ROS 1
    assert config.angular == AxisLimits(max_acceleration=6.0)


def test_ros1_wheel_names_may_be_single_strings() -> None:
    config = one(
        "base:\n  type: diff_drive_controller/DiffDriveController\n"
        "  left_wheel: wheel_left_joint\n  right_wheel: wheel_right_joint\n"
    )
    assert (config.left_wheel_names, config.right_wheel_names) == (
        ("wheel_left_joint",),
        ("wheel_right_joint",),
    )


# --- limits -----------------------------------------------------------------------------------


def test_nan_limits_are_no_limits() -> None:
    config = one(
        section(
            "linear.x.max_velocity: .NAN\nlinear.x.max_acceleration: .nan\n"
            "angular.z.max_velocity: .NaN\nangular.z.max_jerk: 3.0"
        )
    )
    assert config.linear == AxisLimits()
    assert config.angular == AxisLimits(max_jerk=3.0)
    assert config.linear.velocity_range is None
    assert config.angular.jerk_range == (-3.0, 3.0)


def test_ros2_limit_flags_set_false_disable_their_group() -> None:
    config = one(
        section(
            "linear.x.has_velocity_limits: false\nlinear.x.max_velocity: 1.0\n"
            "linear.x.has_acceleration_limits: true\nlinear.x.max_acceleration: 2.0"
        )
    )
    assert config.linear == AxisLimits(max_acceleration=2.0)
    assert config.warnings == ()


def test_ros2_file_with_flags_warns_about_a_group_without_its_flag() -> None:
    config = one(
        section(
            "linear.x.has_velocity_limits: true\nlinear.x.max_velocity: 1.0\n"
            "angular.z.max_velocity: 2.0"
        )
    )
    assert config.angular.max_velocity == 2.0
    assert len(config.warnings) == 1
    assert (
        "angular.z.max_velocity is set without angular.z.has_velocity_limits"
        in (config.warnings[0])
    )


def test_a_flag_set_true_without_its_maximum_is_an_error() -> None:
    with pytest.raises(
        ControllerConfigError,
        match=r"'diff_cont': linear\.x\.has_jerk_limits is true but linear\.x\.max_jerk is not set",
    ):
        read_controllers(section("linear.x.has_jerk_limits: true"), "c.yaml")


def test_velocity_range_defaults_the_minimum_to_minus_the_maximum() -> None:
    assert AxisLimits(max_velocity=0.5).velocity_range == (-0.5, 0.5)
    assert AxisLimits(max_velocity=0.5, min_velocity=-0.1).velocity_range == (-0.1, 0.5)
    assert AxisLimits(min_velocity=-0.1).velocity_range is None


def test_speed_limiter_acceleration_bounds_by_direction() -> None:
    """ros2_controllers test_diff_drive_controller.cpp, test_speed_limiter: its four limits."""
    config = one(
        section(
            "linear.x.max_acceleration: 2.0\nlinear.x.max_deceleration: -4.0\n"
            "linear.x.max_acceleration_reverse: -8.0\nlinear.x.max_deceleration_reverse: 10.0"
        )
    )
    limits = config.linear
    assert limits.acceleration_range(0.0) == (-8.0, 2.0)
    assert limits.acceleration_range(0.5) == (-4.0, 2.0)
    assert limits.acceleration_range(-0.5) == (-8.0, 10.0)
    # The times the test waits for each step of 1 m/s: 1/2, 1/4, 1/8 and 1/10 s.
    forward = limits.acceleration_range(0.0)
    braking = limits.acceleration_range(1.0)
    reverse = limits.acceleration_range(0.0)
    braking_reverse = limits.acceleration_range(-1.0)
    assert forward is not None
    assert braking is not None
    assert reverse is not None
    assert braking_reverse is not None
    assert 1.0 / forward[1] == pytest.approx(0.5, abs=TOL)
    assert -1.0 / braking[0] == pytest.approx(0.25, abs=TOL)
    assert -1.0 / reverse[0] == pytest.approx(0.125, abs=TOL)
    assert 1.0 / braking_reverse[1] == pytest.approx(0.1, abs=TOL)


def test_acceleration_bounds_mirror_the_maximum_when_alone() -> None:
    limits = AxisLimits(max_acceleration=2.0)
    assert [limits.acceleration_range(v) for v in (-1.0, 0.0, 1.0)] == [(-2.0, 2.0)] * 3
    assert AxisLimits(max_deceleration=-1.0).acceleration_range(1.0) is None


def test_older_min_acceleration_bounds_braking_and_reverse_speeding_up() -> None:
    limits = AxisLimits(max_acceleration=3.0, min_acceleration=-2.0)
    assert limits.acceleration_range(1.0) == (-2.0, 3.0)
    assert limits.acceleration_range(-1.0) == (-2.0, 3.0)


@given(
    st.floats(min_value=0.0, max_value=10.0),
    st.floats(min_value=0.0, max_value=10.0),
    st.floats(min_value=-5.0, max_value=5.0),
)
def test_acceleration_bounds_always_contain_zero(up: float, down: float, previous: float) -> None:
    bounds = AxisLimits(max_acceleration=up, max_deceleration=-down).acceleration_range(previous)
    assert bounds is not None
    assert bounds[0] <= 0.0 <= bounds[1]


# --- errors -----------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("body", "message"),
    [
        ("wheel_radius: '0.05'", r"wheel_radius must be a positive finite number, got '0\.05'"),
        ("wheel_radius: -0.05", r"wheel_radius must be a positive finite number, got -0\.05"),
        ("wheel_separation: .nan", r"wheel_separation must be a positive finite number, got nan"),
        ("wheel_separation: true", r"wheel_separation must be a positive finite number, got True"),
        ("wheel_separation_multiplier: 0", r"wheel_separation_multiplier must be a positive"),
        ("linear.x.max_velocity: -1.0", r"linear\.x\.max_velocity must be a number >= 0 or \.nan"),
        ("angular.z.max_deceleration: 2.0", r"angular\.z\.max_deceleration must be a number <= 0"),
        # An infinite limit would reach the velocity ranges and the JSON outputs: .nan says none.
        (
            "linear.x.max_velocity: .inf",
            r"linear\.x\.max_velocity must be a finite number >= 0, or \.nan for no limit, got inf",
        ),
        (
            "angular.z.min_velocity: -.inf",
            r"angular\.z\.min_velocity must be a finite number <= 0, or \.nan for no limit, "
            r"got -inf",
        ),
        ("linear.x.max_acceleration: 1e400", r"max_acceleration must be a finite number >= 0, or"),
        ("linear.x.max_jerk: fast", r"linear\.x\.max_jerk must be a number, got 'fast'"),
        ("open_loop: 'yes'", r"open_loop must be true or false, got 'yes'"),
        (
            "velocity_rolling_window_size: 0",
            r"velocity_rolling_window_size must be an integer from 1 to 1000000",
        ),
        ("wheels_per_side: 1001", r"wheels_per_side must be an integer from 0 to 1000, got 1001"),
        (  # a float cannot hold it: the message says how long it is rather than printing it
            f"wheel_separation: {'1' * 400}",
            r"wheel_separation must be a positive finite number, got an integer of about 400",
        ),
        (f"linear.x.max_jerk: {'9' * 400}", r"max_jerk must be a number, got an integer of about"),
        (
            f"pose_covariance_diagonal: [0, 0, 0, 0, 0, {'1' * 400}]",
            r"pose_covariance_diagonal must be a finite number, got an integer of about 400",
        ),
        ("cmd_vel_timeout: -0.5", r"cmd_vel_timeout must be a finite number >= 0"),
        ("pose_covariance_diagonal: [0.1, 0.1]", r"pose_covariance_diagonal must be a list of 6"),
        ("odom_frame_id: 7", r"odom_frame_id must be a non-empty string, got 7"),
        ("tf_frame_prefix: 7", r"tf_frame_prefix must be a string, got 7"),
        ("tf_frame_prefix_enable: 1", r"tf_frame_prefix_enable must be true or false, got 1"),
        (
            "left_wheel_names: l\nright_wheel_names: [r]",
            r"left_wheel_names must be a list of joint",
        ),
        ("left_wheel_names: [l]", r"right_wheel_names is missing while left_wheel_names is set"),
        ("left_wheel_names: [a, b]\nright_wheel_names: [c]", r"2 left and 1 right wheel names"),
    ],
)
def test_malformed_values_name_the_file_controller_and_key(body: str, message: str) -> None:
    with pytest.raises(ControllerConfigError, match=r"^robot\.yaml: controller 'diff_cont': "):
        read_controllers(section(body), "robot.yaml")
    with pytest.raises(ControllerConfigError, match=message):
        read_controllers(section(body), "robot.yaml")


def test_bad_update_rate_names_the_controller_manager() -> None:
    text = section("wheel_radius: 0.1").replace("update_rate: 100", "update_rate: fast")
    with pytest.raises(ControllerConfigError, match=r"'controller_manager': update_rate must be"):
        read_controllers(text, "robot.yaml")


def test_yaml_aliases_are_refused() -> None:
    bomb = 'a: &a ["lol", "lol"]\nb: &b [*a, *a]\nc: &c [*b, *b]\n'
    with pytest.raises(ControllerConfigError, match=r"bomb\.yaml: YAML aliases .*\(line 2"):
        read_controllers(bomb, "bomb.yaml")


def test_malformed_yaml_points_at_the_line() -> None:
    with pytest.raises(ControllerConfigError, match=r"bad\.yaml: malformed YAML: .*\(line 3,"):
        read_controllers("a:\n  b: [1, 2\n", "bad.yaml")


def test_a_file_that_is_not_a_mapping_is_refused() -> None:
    with pytest.raises(ControllerConfigError, match=r"must be a mapping of node names, got list"):
        read_controllers("- 1\n- 2\n", "list.yaml")


def test_ros__parameters_that_is_not_a_mapping_is_refused() -> None:
    with pytest.raises(ControllerConfigError, match=r"x\.yaml: diff_cont: ros__parameters must"):
        read_controllers("diff_cont:\n  ros__parameters: [1]\n", "x.yaml")


def test_oversized_text_is_refused_before_parsing() -> None:
    with pytest.raises(ControllerConfigError, match=r"larger than \d+ bytes"):
        read_controllers("#" * (MAX_FILE_BYTES + 1), "big.yaml")


def test_controller_errors_are_description_errors() -> None:
    assert issubclass(ControllerConfigError, DescriptionError)
    assert issubclass(GazeboPluginError, DescriptionError)


# --- files ------------------------------------------------------------------------------------


def test_loading_a_file_names_it_as_the_source(tmp_path: Path) -> None:
    path = tmp_path / "controllers.yaml"
    path.write_text(ROS2_NESTED, encoding="utf-8")
    (config,) = load_controllers(path)
    assert config.source == str(path)
    assert config == one(ROS2_NESTED, str(path))


def test_loading_a_missing_file_is_an_error(tmp_path: Path) -> None:
    with pytest.raises(ControllerConfigError, match=r"missing\.yaml: cannot read controllers"):
        load_controllers(tmp_path / "missing.yaml")


def test_loading_an_oversized_file_is_an_error(tmp_path: Path) -> None:
    path = tmp_path / "huge.yaml"
    path.write_bytes(b"#" * (MAX_FILE_BYTES + 1))
    with pytest.raises(ControllerConfigError, match=r"huge\.yaml: controllers file is larger"):
        load_controllers(path)


def test_loading_a_binary_file_is_an_error(tmp_path: Path) -> None:
    path = tmp_path / "binary.yaml"
    path.write_bytes(b"\xff\xfe\x00")
    with pytest.raises(ControllerConfigError, match=r"binary\.yaml: .* not UTF-8"):
        load_controllers(path)


# --- kinematics with the controller's values --------------------------------------------------


def test_initialisation_values_command_one_rad_s_per_wheel() -> None:
    """ros2_controllers test_diff_drive_controller.cpp, correct_initialization_using_parameters."""
    config = one(section("wheel_separation: 0.4\nwheel_radius: 1.0"))
    speeds = inverse(params_of(config), 1.0, 0.0)
    assert speeds.left == pytest.approx(1.0, abs=TOL)
    assert speeds.right == pytest.approx(1.0, abs=TOL)


def test_speed_limiter_step_targets_ten_rad_s() -> None:
    """ros2_controllers test_diff_drive_controller.cpp, test_speed_limiter: 1 m/s at r = 0.1 m."""
    config = one(section("wheel_separation: 1.0\nwheel_radius: 0.1"))
    for linear, expected in ((1.0, 10.0), (-1.0, -10.0)):
        speeds = inverse(params_of(config), linear, 0.0)
        assert speeds.left == pytest.approx(expected, abs=TOL)
        assert speeds.right == pytest.approx(expected, abs=TOL)


def test_open_loop_command_clamped_by_the_velocity_limits() -> None:
    """ros2_controllers test_diff_drive_controller.cpp, test_open_loop_odometry_with_clamped_input.

    With linear and angular max_velocity 0.5, a command of 5.0 runs at 0.5: 0.05 m and 0.05 rad
    after 0.1 s.
    """
    config = one(
        section(
            "wheel_separation: 1.0\nwheel_radius: 0.1\nopen_loop: true\n"
            "linear.x.max_velocity: 0.5\nangular.z.max_velocity: 0.5"
        )
    )
    assert config.open_loop is True
    linear_range = config.linear.velocity_range
    angular_range = config.angular.velocity_range
    assert linear_range == angular_range == (-0.5, 0.5)
    params = params_of(config)
    dt = 0.1
    for commanded, (x, theta) in (((5.0, 0.0), (0.05, 0.0)), ((0.0, 5.0), (0.0, 0.05))):
        linear = min(max(commanded[0], -0.5), 0.5)
        angular = min(max(commanded[1], -0.5), 0.5)
        speeds = inverse(params, linear, angular)
        odom = Odometry(params)
        odom.update(0.0, 0.0, 0.0)
        odom.update(float(speeds.left) * dt, float(speeds.right) * dt, dt)
        assert odom.pose.x == pytest.approx(x, abs=TOL)
        assert norm_angle(odom.pose.theta - theta) == pytest.approx(0.0, abs=TOL)


@given(
    st.floats(min_value=0.5, max_value=2.0),
    st.floats(min_value=0.5, max_value=2.0),
    st.floats(min_value=-2.0, max_value=2.0),
    st.floats(min_value=-3.0, max_value=3.0),
)
def test_multiplied_radius_and_separation_scale_the_wheel_speeds(
    radius_multiplier: float, separation_multiplier: float, linear: float, angular: float
) -> None:
    """Wheel speeds with multipliers m_r, m_b: ((v -+ w m_b b/2) / (m_r r))."""
    base = one(section("wheel_separation: 0.4\nwheel_radius: 0.05"))
    scaled = one(
        section(
            "wheel_separation: 0.4\nwheel_radius: 0.05\n"
            f"wheel_separation_multiplier: {separation_multiplier!r}\n"
            f"left_wheel_radius_multiplier: {radius_multiplier!r}\n"
            f"right_wheel_radius_multiplier: {radius_multiplier!r}"
        )
    )
    speeds = inverse(params_of(scaled), linear, angular)
    half_track = 0.5 * 0.4 * separation_multiplier * angular
    assert scaled.left_radius == scaled.right_radius
    assert speeds.left == pytest.approx((linear - half_track) / (0.05 * radius_multiplier))
    assert speeds.right == pytest.approx((linear + half_track) / (0.05 * radius_multiplier))
    unscaled = inverse(params_of(base), linear, 0.0)
    straight = inverse(params_of(scaled), linear, 0.0)
    assert float(straight.left) * radius_multiplier == pytest.approx(float(unscaled.left))


def test_side_multipliers_give_each_wheel_its_own_radius() -> None:
    """A left wheel 2 % smaller turns 1/0.98 times as fast for the same ground speed."""
    config = one(ROS2_NESTED)
    left = inverse(params_of(config, config.left_radius), 0.5, 0.0).left
    right = inverse(params_of(config, config.right_radius), 0.5, 0.0).right
    assert float(left) == pytest.approx(0.5 / 0.049, abs=1e-9)
    assert float(right) == pytest.approx(0.5 / 0.051, abs=1e-9)


# --- odometry with the controller's values (ros2_controllers test_odometry.cpp) ---------------

UNIT_ROBOT = section("wheel_separation: 1.0\nwheel_radius: 1.0\nvelocity_rolling_window_size: 10")


def odometry_after(left: float, right: float, dt: float = 1.0) -> Odometry:
    """Odometry of the OdometryTest fixture (b = 1 m, r = 1 m) after one step of wheel angles."""
    config = one(UNIT_ROBOT)
    assert config.velocity_rolling_window_size == 10
    odom = Odometry(params_of(config))
    odom.update(0.0, 0.0, 0.0)
    odom.update(left, right, dt)
    return odom


def test_odometry_linear_motion() -> None:
    """ros2_controllers test_odometry.cpp, TestLinearMotion."""
    odom = odometry_after(1.0, 1.0)
    assert odom.pose.x == pytest.approx(1.0, abs=TOL)
    assert odom.pose.y == pytest.approx(0.0, abs=TOL)
    assert norm_angle(odom.pose.theta) == pytest.approx(0.0, abs=TOL)
    assert odom.twist.linear == pytest.approx(1.0, abs=TOL)
    assert odom.twist.angular == pytest.approx(0.0, abs=TOL)


def test_odometry_pure_rotation() -> None:
    """ros2_controllers test_odometry.cpp, TestPureRotation."""
    odom = odometry_after(-1.0, 1.0)
    assert odom.pose.x == pytest.approx(0.0, abs=TOL)
    assert odom.pose.y == pytest.approx(0.0, abs=TOL)
    assert norm_angle(odom.pose.theta - 2.0) == pytest.approx(0.0, abs=TOL)
    assert odom.twist.linear == pytest.approx(0.0, abs=TOL)
    assert odom.twist.angular == pytest.approx(2.0, abs=TOL)


def test_odometry_curved_motion_follows_the_exact_arc() -> None:
    """ros2_controllers test_odometry.cpp, TestCurvedMotion_ExactArc (tolerance 1e-5 there)."""
    odom = odometry_after(1.0, 2.0)
    assert odom.pose.x == pytest.approx(1.5 * math.sin(1.0), abs=1e-12)
    assert odom.pose.y == pytest.approx(-1.5 * (math.cos(1.0) - 1.0), abs=1e-12)
    assert norm_angle(odom.pose.theta - 1.0) == pytest.approx(0.0, abs=TOL)


def test_odometry_of_an_open_loop_twist() -> None:
    """ros2_controllers test_odometry.cpp, TestOpenLoopUpdate: v = 2, w = 0.5 for 1 s."""
    config = one(UNIT_ROBOT)
    speeds = inverse(params_of(config), 2.0, 0.5)
    odom = odometry_after(float(speeds.left), float(speeds.right))
    assert odom.pose.x == pytest.approx(4.0 * math.sin(0.5), abs=1e-12)
    assert odom.pose.y == pytest.approx(-4.0 * (math.cos(0.5) - 1.0), abs=1e-12)
    assert norm_angle(odom.pose.theta - 0.5) == pytest.approx(0.0, abs=TOL)
    assert odom.twist.linear == pytest.approx(2.0, abs=TOL)
    assert odom.twist.angular == pytest.approx(0.5, abs=TOL)


def test_odometry_reset_clears_the_pose() -> None:
    """ros2_controllers test_odometry.cpp, TestReset."""
    odom = odometry_after(1.0, 1.0)
    assert odom.pose.x != 0.0
    odom.reset(0.0, 0.0, 0.0)
    assert tuple(odom.pose) == (0.0, 0.0, 0.0)


# --- Gazebo plugins ---------------------------------------------------------------------------


def robot(*plugins: str) -> ElementTree.Element:
    """A URDF root holding the given plugins, each in its own <gazebo> element."""
    body = "".join(f"<gazebo>{plugin}</gazebo>" for plugin in plugins)
    return ElementTree.fromstring(f'<robot name="r"><link name="base_link"/>{body}</robot>')


CLASSIC_ROS1 = """
<plugin name="differential_drive_controller" filename="libgazebo_ros_diff_drive.so">
  <leftJoint>left_wheel_joint</leftJoint>
  <rightJoint>right_wheel_joint</rightJoint>
  <wheelSeparation>0.16</wheelSeparation>
  <wheelDiameter>0.066</wheelDiameter>
  <commandTopic>cmd_vel</commandTopic>
</plugin>
"""

CLASSIC_ROS2_TWO_PAIRS = """
<plugin name="diff_drive" filename="libgazebo_ros_diff_drive.so">
  <num_wheel_pairs>2</num_wheel_pairs>
  <left_joint>front_left_joint</left_joint>
  <right_joint>front_right_joint</right_joint>
  <left_joint>rear_left_joint</left_joint>
  <right_joint>rear_right_joint</right_joint>
  <wheel_separation>0.30</wheel_separation>
  <wheel_separation>0.32</wheel_separation>
  <wheel_diameter>0.10</wheel_diameter>
  <wheel_diameter>0.10</wheel_diameter>
</plugin>
"""

GZ_SIM_TWO_PAIRS = """
<plugin filename="gz-sim-diff-drive-system" name="gz::sim::systems::DiffDrive">
  <left_joint>front_left_joint</left_joint>
  <left_joint>rear_left_joint</left_joint>
  <right_joint>front_right_joint</right_joint>
  <right_joint>rear_right_joint</right_joint>
  <wheel_separation>0.45</wheel_separation>
  <wheel_radius>0.08</wheel_radius>
  <topic>cmd_vel</topic>
</plugin>
"""

IGNITION = """
<plugin filename="libignition-gazebo-diff-drive-system.so"
        name="ignition::gazebo::systems::DiffDrive">
  <left_joint>l</left_joint>
  <right_joint>r</right_joint>
  <wheel_separation>0.2</wheel_separation>
  <wheel_radius>0.03</wheel_radius>
</plugin>
"""


def test_gazebo_classic_ros1_plugin_halves_the_diameter() -> None:
    (drive,) = gazebo_drives(robot(CLASSIC_ROS1))
    assert (drive.kind, drive.plugin) == ("gazebo_ros_diff_drive", "libgazebo_ros_diff_drive.so")
    assert (drive.left_joints, drive.right_joints) == (
        ("left_wheel_joint",),
        ("right_wheel_joint",),
    )
    assert drive.wheel_separation == pytest.approx(0.16, abs=TOL)
    assert drive.wheel_radius == pytest.approx(0.033, abs=TOL)


def test_gazebo_classic_ros2_plugin_with_two_wheel_pairs() -> None:
    (drive,) = gazebo_drives(robot(CLASSIC_ROS2_TWO_PAIRS))
    assert drive.left_joints == ("front_left_joint", "rear_left_joint")
    assert drive.right_joints == ("front_right_joint", "rear_right_joint")
    assert drive.wheel_separations == pytest.approx((0.30, 0.32), abs=TOL)
    assert drive.wheel_radii == pytest.approx((0.05, 0.05), abs=TOL)
    assert drive.wheel_separation == pytest.approx(0.30, abs=TOL)


def test_gz_sim_plugin_with_two_wheel_pairs() -> None:
    (drive,) = gazebo_drives(robot(GZ_SIM_TWO_PAIRS))
    assert (drive.kind, drive.plugin) == ("gz_sim_diff_drive", "gz-sim-diff-drive-system")
    assert drive.left_joints == ("front_left_joint", "rear_left_joint")
    assert drive.right_joints == ("front_right_joint", "rear_right_joint")
    assert (drive.wheel_separation, drive.wheel_radius) == (0.45, 0.08)


def test_ignition_plugin_is_a_gz_sim_drive_and_order_is_kept() -> None:
    drives = gazebo_drives(robot(IGNITION, CLASSIC_ROS1))
    assert [d.kind for d in drives] == ["gz_sim_diff_drive", "gazebo_ros_diff_drive"]
    assert (drives[0].wheel_separation, drives[0].wheel_radius) == (0.2, 0.03)


def test_plugin_without_geometry_leaves_it_none() -> None:
    (drive,) = gazebo_drives(
        robot('<plugin filename="gz-sim-diff-drive-system"><left_joint>l</left_joint></plugin>')
    )
    assert (drive.wheel_separation, drive.wheel_radius, drive.right_joints) == (None, None, ())


def test_other_plugins_are_not_drives() -> None:
    root = robot(
        '<plugin filename="gz-sim-joint-state-publisher-system" name="x"/>',
        '<plugin filename="libgazebo_ros_camera.so">'
        "<wheel_separation>1</wheel_separation></plugin>",
    )
    assert gazebo_drives(root) == []


def test_malformed_plugin_length_is_an_error() -> None:
    root = robot(CLASSIC_ROS1.replace("0.066", "six cm"))
    with pytest.raises(GazeboPluginError, match=r"<wheelDiameter> must be a positive length.*six"):
        gazebo_drives(root)


def test_plugin_separation_that_disagrees_with_the_controller_is_visible() -> None:
    config = one(section("left_wheel_names: [l]\nright_wheel_names: [r]\nwheel_separation: 0.2"))
    (drive,) = gazebo_drives(
        robot(IGNITION.replace("<wheel_separation>0.2", "<wheel_separation>0.21"))
    )
    assert config.effective_separation is not None
    assert drive.wheel_separation is not None
    assert abs(drive.wheel_separation - config.effective_separation) == pytest.approx(
        0.01, abs=1e-12
    )
    assert drive.left_joints == config.left_wheel_names
    assert drive.wheel_radius == 0.03
    assert config.wheel_radius is None


def test_ros2_control_plugins_give_their_parameter_files() -> None:
    root = robot(
        '<plugin filename="gz_ros2_control-system" '
        'name="gz_ros2_control::GazeboSimROS2ControlPlugin">'
        "<parameters>/opt/robot/config/controllers.yaml</parameters></plugin>",
        '<plugin filename="libgazebo_ros2_control.so" name="gazebo_ros2_control">'
        "<robot_param>robot_description</robot_param>"
        "<parameters> /ws/share/bot/config/classic.yaml </parameters></plugin>",
        '<plugin filename="libign_ros2_control-system.so" '
        'name="ign_ros2_control::IgnitionROS2ControlPlugin">'
        "<parameters>/ws/ign.yaml</parameters></plugin>",
        IGNITION,
    )
    assert ros2_control_parameter_files(root) == [
        "/opt/robot/config/controllers.yaml",
        "/ws/share/bot/config/classic.yaml",
        "/ws/ign.yaml",
    ]


def test_hardware_plugin_text_is_not_a_parameter_file() -> None:
    root = ElementTree.fromstring(
        '<robot name="r"><ros2_control name="s" type="system"><hardware>'
        "<plugin>gz_ros2_control/GazeboSimSystem</plugin></hardware></ros2_control></robot>"
    )
    assert ros2_control_parameter_files(root) == []
    assert gazebo_drives(root) == []


def test_exponent_without_a_dot_is_a_number_as_in_ros() -> None:
    config = one(section("wheel_radius: 5e-2\nlinear.x.max_acceleration: 1E1"))
    assert config.wheel_radius == pytest.approx(0.05, abs=TOL)
    assert config.linear.max_acceleration == pytest.approx(10.0, abs=TOL)


def test_quoted_numbers_stay_strings_and_are_refused() -> None:
    with pytest.raises(ControllerConfigError, match=r"wheel_radius must be a positive finite"):
        read_controllers(section("wheel_radius: '5e-2'"), "q.yaml")


def test_deeply_nested_yaml_is_an_error_not_a_crash() -> None:
    with pytest.raises(ControllerConfigError, match=r"deep\.yaml: YAML .* nested more than 32"):
        read_controllers("[" * 5_000, "deep.yaml")


def test_ros1_controller_with_one_side_names_the_missing_key() -> None:
    text = "base:\n  type: diff_drive_controller/DiffDriveController\n  right_wheel: [r]\n"
    with pytest.raises(ControllerConfigError, match=r"'base': left_wheel is missing while right_"):
        read_controllers(text, "ros1.yaml")


@pytest.mark.parametrize("rate", ["1.0e-300", "1.0e+300", "'fast'", "[50]", "1" * 400])
def test_an_update_rate_outside_any_controller_manager_is_refused(rate: str) -> None:
    text = section("wheel_separation: 0.3").replace("update_rate: 100", f"update_rate: {rate}")
    with pytest.raises(ControllerConfigError, match=r"'controller_manager': update_rate must be"):
        read_controllers(text, "robot.yaml")


def test_a_yaml_integer_of_5000_digits_is_a_malformed_file() -> None:
    text = section(f"wheel_separation: {'1' * 5000}")
    with pytest.raises(ControllerConfigError, match=r"^robot\.yaml: .*a number too long to read"):
        read_controllers(text, "robot.yaml")


def test_a_type_given_as_a_list_is_no_controller_type() -> None:
    text = section("type: [diff_drive_controller/DiffDriveController]").replace(
        "type: diff_drive_controller/DiffDriveController", "type: [a, b]"
    )
    assert read_controllers(text, "robot.yaml") == []


def test_a_controller_written_twice_is_merged_as_ros_merges_it_and_said() -> None:
    # A file that configures one controller in two places: ROS merges them (ros2/rclcpp#2166),
    # the later value of a key winning; PyYAML alone would drop the first place's wheels.
    text = (
        "controller_manager:\n  ros__parameters:\n    update_rate: 50\n"
        "    diff_cont:\n      type: diff_drive_controller/DiffDriveController\n"
        "diff_cont:\n  ros__parameters:\n    left_wheel_names: [l]\n"
        "    right_wheel_names: [r]\n    wheel_separation: 0.30\n    wheel_radius: 0.05\n"
        "diff_cont:\n  ros__parameters:\n    wheel_radius: 0.07\n"
    )
    (config,) = read_controllers(text, "c.yaml")
    assert config.left_wheel_names == ("l",)
    assert math.isclose(config.wheel_separation or 0.0, 0.30, rel_tol=0, abs_tol=1e-15)
    assert math.isclose(config.wheel_radius or 0.0, 0.07, rel_tol=0, abs_tol=1e-15)
    said = [w for w in config.warnings if "appears twice" in w]
    assert len(said) == 1
    assert "lines 6 and 12" in said[0]
    assert "wheel_radius 0.07" in said[0]


def test_position_feedback_is_read_and_absent_means_the_default() -> None:
    wheels = "left_wheel_names: [l]\nright_wheel_names: [r]"
    assert one(section(wheels + "\nposition_feedback: false")).position_feedback is False
    assert one(section(wheels + "\nposition_feedback: true")).position_feedback is True
    assert one(section(wheels)).position_feedback is None


#: A PID controller chained before each wheel, every node under a namespace of two levels,
#: and the wheels named by the chained controllers' full paths.
CHAINED_DEEP = """/robot/base:
  controller_manager:
    ros__parameters:
      update_rate: 100
      pid_left: {type: pid_controller/PidController}
      pid_right: {type: pid_controller/PidController}
      diff_cont: {type: diff_drive_controller/DiffDriveController}
  pid_left:
    ros__parameters:
      dof_names: [left_wheel_joint]
  pid_right:
    ros__parameters:
      dof_names: [right_wheel_joint]
  diff_cont:
    ros__parameters:
      left_wheel_names: ["/robot/base/pid_left/left_wheel_joint"]
      right_wheel_names: ["robot/base/pid_right/right_wheel_joint"]
      wheel_separation: 0.30
      wheel_radius: 0.05
"""


def test_a_chained_reference_of_several_levels_is_followed_to_its_joint() -> None:
    (config,) = read_controllers(CHAINED_DEEP, "c.yaml")
    assert config.left_wheel_names == ("left_wheel_joint",)
    assert config.right_wheel_names == ("right_wheel_joint",)
    assert config.warnings == (
        "wheel '/robot/base/pid_left/left_wheel_joint' is the reference of the chained "
        "controller '/robot/base/pid_left': followed to joint 'left_wheel_joint'",
        "wheel 'robot/base/pid_right/right_wheel_joint' is the reference of the chained "
        "controller 'robot/base/pid_right': followed to joint 'right_wheel_joint'",
    )


def test_a_reference_of_several_levels_to_another_joint_is_kept() -> None:
    text = CHAINED_DEEP.replace("dof_names: [left_wheel_joint]", "dof_names: [elbow]")
    (config,) = read_controllers(text, "c.yaml")
    # The left one names a joint its controller does not drive: kept as written.
    assert config.left_wheel_names == ("/robot/base/pid_left/left_wheel_joint",)
    assert config.right_wheel_names == ("right_wheel_joint",)
    assert len(config.warnings) == 1


def test_a_slashed_name_without_a_chained_controller_is_taken_as_a_joint() -> None:
    text = CHAINED_DEEP.replace("pid_left/left_wheel_joint", "arm/left_wheel_joint")
    (config,) = read_controllers(text, "c.yaml")
    # No controller "arm": the last component is the joint.
    assert config.left_wheel_names == ("left_wheel_joint",)
    assert "controller '/robot/base/arm'" in config.warnings[0]


# --- the other controllers of a file ------------------------------------------------------------


def test_args_are_substituted_and_the_unresolved_named_once() -> None:
    text = "r: $(arg radius)\nb: $( arg  sep )\nc: $(arg missing) $(arg missing) $(arg other)"
    done, unresolved = substitute_args(text, {"radius": "0.05", "sep": "0.3"})
    assert done == "r: 0.05\nb: $( arg  sep )\nc: $(arg missing) $(arg missing) $(arg other)"
    assert unresolved == ["missing", "other"]
    done, unresolved = substitute_args("r: $(arg radius )", None)
    assert (done, unresolved) == ("r: $(arg radius )", ["radius"])
    assert substitute_args("r: $(arg r-1)", {"r-1": 2})[0] == "r: 2"  # type: ignore[dict-item]


OTHER_DRIVES = """controller_manager:
  ros__parameters:
    mecanum: {type: mecanum_drive_controller/MecanumDriveController}
    diff: {type: diff_drive_controller/DiffDriveController}
    arm: {type: joint_trajectory_controller/JointTrajectoryController}
    /ns/steer.type: ackermann_steering_controller/AckermannSteeringController
    plugin: {type: "pkg::TricycleController"}
mecanum:
  ros__parameters: {}
rover:
  base:
    type: omni_wheel_controller/OmniWheelController
  diff1:
    type: diff_drive_controller/DiffDriveController
  arm1:
    type: position_controllers/JointGroupPositionController
  empty: {}
"""


def test_base_drives_that_are_not_differential_are_named_with_their_types(tmp_path: Path) -> None:
    found = other_drive_controllers(OTHER_DRIVES, "c.yaml")
    assert found == [
        ("base", "omni_wheel_controller/OmniWheelController"),
        ("mecanum", "mecanum_drive_controller/MecanumDriveController"),
        ("steer", "ackermann_steering_controller/AckermannSteeringController"),
        ("plugin", "pkg::TricycleController"),
    ]
    assert other_drive_controllers("[]", "c.yaml") == []
    assert other_drive_controllers(ROS2_NESTED, "c.yaml") == []
    path = tmp_path / "c.yaml"
    path.write_text(OTHER_DRIVES, encoding="utf-8")
    assert load_other_drive_controllers(path) == found


def test_command_controllers_are_found_with_their_joints(tmp_path: Path) -> None:
    path = tmp_path / "c.yaml"
    path.write_text(
        """controller_manager:
  ros__parameters:
    left: {type: forward_command_controller/ForwardCommandController}
/ns/left:
  ros__parameters:
    joints: [wheel_a, wheel_b]
right:
  ros__parameters:
    joints: [wheel_c]
empty:
  ros__parameters:
    joints: []
mixed:
  ros__parameters:
    joints: [wheel_d, 3]
single:
  ros__parameters:
    joints: wheel_e
""",
        encoding="utf-8",
    )
    assert load_command_controllers(path) == {
        "ns/left": ("wheel_a", "wheel_b"),  # its section's namespace, as a diff-drive's
        "right": ("wheel_c",),
    }
    path.write_text("- a\n- b\n", encoding="utf-8")
    assert load_command_controllers(path) == {}


def command_controllers(tmp_path: Path, text: str) -> dict[str, tuple[str, ...]]:
    path = tmp_path / "controllers.yaml"
    path.write_text(text, encoding="utf-8")
    return load_command_controllers(path)


def test_command_controllers_in_a_namespace_are_named_with_it(tmp_path: Path) -> None:
    found = command_controllers(
        tmp_path,
        """
/a200_0000/controller_manager:
  ros__parameters: {update_rate: 50}
/a200_0000/left_wheel_controller:
  ros__parameters: {joints: [wheel_a]}
robot_b:
  right_wheel_controller:
    ros__parameters: {joints: [wheel_b]}
/**/other_controller:
  ros__parameters: {joints: [wheel_c]}
plain_controller:
  ros__parameters: {joints: [wheel_d]}
""",
    )
    # A section left to a wildcard is in its controller manager's namespace.
    assert found == {
        "a200_0000/left_wheel_controller": ("wheel_a",),
        "robot_b/right_wheel_controller": ("wheel_b",),
        "a200_0000/other_controller": ("wheel_c",),
        "plain_controller": ("wheel_d",),
    }


def test_only_controllers_taking_velocities_on_commands_are_command_controllers(
    tmp_path: Path,
) -> None:
    found = command_controllers(
        tmp_path,
        """
controller_manager:
  ros__parameters:
    trajectory: {type: joint_trajectory_controller/JointTrajectoryController}
    positions: {type: position_controllers/JointGroupPositionController}
    velocities: {type: velocity_controllers/JointGroupVelocityController}
    forward: {type: forward_command_controller/ForwardCommandController}
    forward_effort: {type: forward_command_controller/ForwardCommandController}
trajectory:
  ros__parameters: {joints: [wheel_a]}
positions:
  ros__parameters: {joints: [wheel_b]}
velocities:
  ros__parameters: {joints: [wheel_c]}
forward:
  ros__parameters: {joints: [wheel_d], interface_name: velocity}
forward_effort:
  ros__parameters: {joints: [wheel_e], interface_name: effort}
undeclared:
  ros__parameters: {joints: [wheel_f]}
""",
    )
    # A trajectory controller subscribes ~/joint_trajectory; position and effort commands
    # are no wheel velocities. A section of no declared type is taken at its word.
    assert found == {
        "velocities": ("wheel_c",),
        "forward": ("wheel_d",),
        "undeclared": ("wheel_f",),
    }


def test_file_errors_are_one_message_each(tmp_path: Path) -> None:
    missing = tmp_path / "missing.yaml"
    with pytest.raises(ControllerConfigError) as caught:
        load_controllers(missing)
    assert (
        str(caught.value) == f"{missing}: cannot read controllers file: No such file or directory"
    )
    folder = tmp_path / "folder.yaml"
    folder.mkdir()
    with pytest.raises(ControllerConfigError, match=r"folder\.yaml: .*controllers file"):
        load_controllers(folder)
    fifo = tmp_path / "fifo.yaml"
    os.mkfifo(fifo)
    with pytest.raises(ControllerConfigError, match=r"fifo\.yaml: .*controllers file"):
        load_command_controllers(fifo)  # refused without blocking on the pipe
    exact = tmp_path / "exact.yaml"
    exact.write_bytes(b"#" * MAX_FILE_BYTES)  # at the bound: read
    assert load_controllers(exact) == []
    huge = tmp_path / "huge.yaml"
    huge.write_bytes(b"#" * (MAX_FILE_BYTES + 1))
    with pytest.raises(ControllerConfigError) as caught:
        load_other_drive_controllers(huge)
    assert str(caught.value) == (f"{huge}: controllers file is larger than {MAX_FILE_BYTES} bytes")
    bad = tmp_path / "bad.yaml"
    bad.write_text("a: [1\n", encoding="utf-8")
    with pytest.raises(ControllerConfigError, match=r"bad\.yaml"):
        load_command_controllers(bad)
    latin = tmp_path / "latin.yaml"
    latin.write_bytes("r: 'é'".encode("latin-1"))
    with pytest.raises(ControllerConfigError) as caught:
        load_controllers(latin)
    assert str(caught.value) == f"{latin}: controllers file is not UTF-8 text"


def test_loading_a_file_substitutes_its_args(tmp_path: Path) -> None:
    path = tmp_path / "c.yaml"
    path.write_text(
        ROS2_NESTED.replace("wheel_radius: 0.05", "wheel_radius: $(arg radius)"), encoding="utf-8"
    )
    (config,) = load_controllers(path, {"radius": "0.07"})
    assert config.wheel_radius == 0.07


def test_choosing_names_the_files_and_the_controllers() -> None:
    configs = read_controllers(TWO_CONTROLLERS, "two.yaml")
    with pytest.raises(ControllerConfigError) as caught:
        choose_controller(configs)
    assert str(caught.value) == (
        "several diff-drive controllers in two.yaml: 'front_drive', 'rear_drive'; "
        "choose one by name (controller=)"
    )
    with pytest.raises(ControllerConfigError) as caught:
        choose_controller(configs, "middle")
    assert str(caught.value) == (
        "no diff-drive controller 'middle' in two.yaml; there are: 'front_drive', 'rear_drive'"
    )
    with pytest.raises(ControllerConfigError) as caught:
        choose_controller([])
    assert str(caught.value) == "no diff_drive_controller/DiffDriveController found"
    without_source = [dataclasses.replace(c, source="") for c in configs[:1]]
    with pytest.raises(ControllerConfigError) as caught:
        choose_controller(without_source, "middle")
    assert str(caught.value) == "no diff-drive controller 'middle' in ; there are: 'front_drive'"


def test_ros1_types_under_namespaces_after_plain_values() -> None:
    text = """robot:
  rate: 50
  drive:
    type: mecanum_drive_controller/MecanumDriveController
  arm:
    ns:
      base:
        type: steering_controllers/SteeringController
"""
    assert other_drive_controllers(text, "c.yaml") == [
        ("drive", "mecanum_drive_controller/MecanumDriveController"),
        ("base", "steering_controllers/SteeringController"),
    ]


def test_a_chained_reference_to_a_group_command_controller_is_followed() -> None:
    # The chained controller names its joints under "joints", as a command controller does.
    text = CHAINED_DEEP.replace("dof_names: [left_wheel_joint]", "joints: [left_wheel_joint]")
    (config,) = read_controllers(text, "c.yaml")
    assert config.left_wheel_names == ("left_wheel_joint",)
    elbow = CHAINED_DEEP.replace("dof_names: [left_wheel_joint]", "joints: [elbow]")
    (config,) = read_controllers(elbow, "c.yaml")
    assert config.left_wheel_names == ("/robot/base/pid_left/left_wheel_joint",)


def test_a_drive_is_named_once_and_only_by_its_class_name() -> None:
    text = """controller_manager:
  ros__parameters:
    mecanum.type: mecanum_drive_controller/MecanumDriveController
    arm.type: drive_tools/JointTrajectoryController
    grip.type: "drive_tools::GripperController"
    count.type: 3
mecanum:
  ros__parameters:
    type: mecanum_drive_controller/MecanumDriveController
/ns/swerve:
  ros__parameters:
    type: swerve_drive_controller/SwerveDriveController
legacy:
  type: drive_tools/JointStateController
"""
    # Declared in the manager and in its own section: once; a package named for driving does
    # not make its other controllers drives; a type that is not text is no type.
    assert other_drive_controllers(text, "c.yaml") == [
        ("mecanum", "mecanum_drive_controller/MecanumDriveController"),
        ("swerve", "swerve_drive_controller/SwerveDriveController"),
    ]
