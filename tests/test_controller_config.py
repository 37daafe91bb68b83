"""What a controller configuration says beyond its numbers: the frames its odometry is
published in, prefixed as diff_drive_controller prefixes them."""

from __future__ import annotations

import math

import numpy as np
import pytest
from refusals import assert_refused

from diffbot.controller_config import AxisLimits, ControllerConfig


def controller(namespace: str = "", **values: object) -> ControllerConfig:
    return ControllerConfig(
        name="diff_cont", source="c.yaml", ros_version=2, namespace=namespace, **values
    )


# The explicit prefixes and their namespaces are those of ros2_control's
# controller_interface/test/test_controller_tf_prefix.cpp (resolve_tf_prefix), whose node
# namespaces always start with a slash.
@pytest.mark.parametrize(
    ("prefix", "namespace", "expected"),
    [
        ("robot", "ns", "robot/"),
        ("/robot1", "ns", "robot1/"),
        ("robot2//", "ns", "robot2//"),
        ("/robot3/", "ns", "robot3/"),
        ("/", "ns", ""),
        ("~", "ns", "ns/"),
        ("~/", "ns", "ns/"),
        ("~/robot", "ns", "ns/robot/"),
        # ros2_controllers' diff_drive_controller/test/test_diff_drive_controller.cpp:
        # configure_succeeds_tf_prefix_set_namespace and ..._tf_tilde_prefix_set_namespace.
        ("test_prefix", "test_namespace", "test_prefix/"),
        ("~", "test_namespace", "test_namespace/"),
        # No prefix: the namespace, as every release since Humble resolves it.
        ("", "a200_0000", "a200_0000/"),
        (None, "a200_0000", "a200_0000/"),
        (None, "outer/inner", "outer/inner/"),
        (None, "", ""),
        ("", "", ""),
        ("~/robot", "", "/robot/"),  # the root namespace "/" then "/robot", one slash removed
    ],
)
def test_the_frame_prefix_is_resolved_as_the_controller_resolves_it(
    prefix: str | None, namespace: str, expected: str
) -> None:
    config = controller(namespace, tf_frame_prefix=prefix)
    assert config.frame_prefix == expected
    assert config.odom_frame == expected + "odom"
    assert config.base_frame == expected + "base_link"


def test_the_prefix_goes_before_the_frames_the_file_names() -> None:
    config = controller("a200_0000", odom_frame_id="odom_wheels", base_frame_id="base_footprint")
    assert (config.odom_frame, config.base_frame) == (
        "a200_0000/odom_wheels",
        "a200_0000/base_footprint",
    )


def test_no_prefix_when_switched_off_or_for_ros_1() -> None:
    off = controller("a200_0000", tf_frame_prefix="robot", tf_frame_prefix_enable=False)
    assert (off.frame_prefix, off.odom_frame) == ("", "odom")
    assert controller("a200_0000", tf_frame_prefix_enable=True).frame_prefix == "a200_0000/"
    ros1 = ControllerConfig(
        name="diff_cont", source="c.yaml", ros_version=1, tf_frame_prefix="robot"
    )
    assert (ros1.frame_prefix, ros1.base_frame) == ("", "base_link")


def test_what_the_file_leaves_out_is_the_controller_s_default() -> None:
    # diff_drive_controller_parameter.yaml: zero covariance diagonals, a window of 10 steps.
    bare = controller()
    assert bare.pose_covariance == bare.twist_covariance == (0.0,) * 6
    assert bare.rolling_window == 10
    set_ = controller(
        pose_covariance_diagonal=(1, 2, 3, 4, 5, 6),
        twist_covariance_diagonal=(6, 5, 4, 3, 2, 1),
        velocity_rolling_window_size=3,
    )
    assert set_.pose_covariance == (1, 2, 3, 4, 5, 6)
    assert set_.twist_covariance == (6, 5, 4, 3, 2, 1)
    assert set_.rolling_window == 3


def test_the_odometry_topic_is_the_controller_s_private_one() -> None:
    # DEFAULT_ODOMETRY_TOPIC "~/odom" in diff_drive_controller.cpp: under the node's name.
    assert controller().odom_topic == "/diff_cont/odom"
    assert controller("a200_0000").odom_topic == "/a200_0000/diff_cont/odom"


@pytest.mark.parametrize(
    ("values", "named"),
    [
        ({"ros_version": 3}, "ros_version"),
        ({"ros_version": "2"}, "ros_version"),
        ({"ros_version": True}, "ros_version"),
        ({"wheel_radius": math.nan}, "wheel_radius"),
        ({"wheel_radius": "-0.05"}, "wheel_radius"),
        ({"wheel_radius": 10**400}, "wheel_radius"),
        ({"wheel_separation": math.inf}, "wheel_separation"),
        ({"wheel_separation": "wide"}, "wheel_separation"),
        ({"wheel_separation_multiplier": None}, "wheel_separation_multiplier"),
        ({"wheel_separation_multiplier": 0.0}, "wheel_separation_multiplier"),
        ({"left_wheel_radius_multiplier": "0"}, "left_wheel_radius_multiplier"),
        ({"right_wheel_radius_multiplier": math.nan}, "right_wheel_radius_multiplier"),
        ({"wheels_per_side": 2.5}, "wheels_per_side"),
        ({"wheels_per_side": -1}, "wheels_per_side"),
        ({"velocity_rolling_window_size": 0}, "velocity_rolling_window_size"),
        ({"velocity_rolling_window_size": 10**400}, "velocity_rolling_window_size"),
        ({"publish_rate": -50.0}, "publish_rate"),
        ({"cmd_vel_timeout": "-0.5"}, "cmd_vel_timeout"),
        ({"update_rate": "nan"}, "update_rate"),
        ({"update_rate": 0.0}, "update_rate"),
        ({"update_rate": [50.0]}, "update_rate"),
        ({"pose_covariance_diagonal": (0.0,) * 5}, "pose_covariance_diagonal"),
        ({"twist_covariance_diagonal": (0.0,) * 5 + (math.inf,)}, "twist_covariance_diagonal"),
        ({"linear": None}, "linear"),
        ({"angular": {"max_velocity": 1.0}}, "angular"),
    ],
)
def test_hostile_values_are_refused_naming_the_parameter(
    values: dict[str, object], named: str
) -> None:
    given = {"name": "diff_cont", "source": "c.yaml", "ros_version": 2} | values
    assert_refused(ControllerConfig, given, named)


@pytest.mark.parametrize(
    ("values", "named"),
    [
        ({"max_velocity": math.inf}, "max_velocity"),
        ({"min_velocity": "-inf"}, "min_velocity"),
        ({"max_acceleration": "fast"}, "max_acceleration"),
        ({"max_jerk": 10**400}, "max_jerk"),
        ({"min_jerk": True}, "min_jerk"),
        ({"max_deceleration": [-1.0]}, "max_deceleration"),
    ],
)
def test_hostile_limits_are_refused_naming_the_limit(values: dict[str, object], named: str) -> None:
    assert_refused(AxisLimits, values, named)


def test_a_nan_limit_is_no_limit() -> None:
    # The controller's own "no limit": kept as None, as the file reader keeps it.
    assert AxisLimits(max_velocity=math.nan, max_jerk="nan") == AxisLimits()  # type: ignore[arg-type]
    assert AxisLimits(max_velocity=math.nan).velocity_range is None


def test_numeric_strings_plan_and_execute_as_their_numbers() -> None:
    from robots import BOT

    from diffbot.execution import estimated_updates, execute_plan
    from diffbot.planfile import parse_plan
    from diffbot.ramps import controller_limits, ramp
    from diffbot.trajectory import plan

    as_text = ControllerConfig(
        name="diff_cont",
        source="c.yaml",
        ros_version=2,
        wheel_radius="0.033",  # type: ignore[arg-type]
        linear=AxisLimits(max_velocity="0.3", max_acceleration="0.5", max_jerk="2"),  # type: ignore[arg-type]
        update_rate="50",  # type: ignore[arg-type]
    )
    as_numbers = ControllerConfig(
        name="diff_cont",
        source="c.yaml",
        ros_version=2,
        wheel_radius=0.033,
        linear=AxisLimits(max_velocity=0.3, max_acceleration=0.5, max_jerk=2),
        update_rate=50,
    )
    assert as_text == as_numbers
    assert (type(as_text.update_rate), type(as_text.linear.max_jerk)) == (float, float)
    steps = plan(parse_plan("straight 1; spin 90"), BOT)
    ramped = [ramp(steps, controller_limits(c)) for c in (as_text, as_numbers)]
    assert ramped[0].duration == ramped[1].duration
    assert estimated_updates(ramped[0], as_text) == estimated_updates(ramped[1], as_numbers)
    executed = [execute_plan(r, c) for r, c in zip(ramped, (as_text, as_numbers), strict=True)]
    np.testing.assert_array_equal(executed[0].linear, executed[1].linear)
    assert executed[0].final_pose == executed[1].final_pose
