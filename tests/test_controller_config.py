"""What a controller configuration says beyond its numbers: the frames its odometry is
published in, prefixed as diff_drive_controller prefixes them."""

from __future__ import annotations

import pytest

from diffbot.controller_config import ControllerConfig


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
