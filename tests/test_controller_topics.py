"""The diff-drive controller's own command topic and type, by ROS release, as
diff_drive_controller.cpp names them (~/cmd_vel, ~/cmd_vel_unstamped)."""

from __future__ import annotations

import pytest

from diffbot.controller_config import ControllerConfig
from diffbot.controller_topics import command_topic, distro_of
from diffbot.errors import ParameterError


def controller(
    use_stamped_vel: bool | None = None,
    name: str = "diffbot_base_controller",
    namespace: str = "",
) -> ControllerConfig:
    return ControllerConfig(
        name=name,
        source="controllers.yaml",
        ros_version=2,
        use_stamped_vel=use_stamped_vel,
        namespace=namespace,
    )


@pytest.mark.parametrize(
    ("distro", "use_stamped_vel", "topic", "stamped"),
    [
        # Humble: TwistStamped on ~/cmd_vel by default, Twist on ~/cmd_vel_unstamped when off.
        ("humble", None, "/diffbot_base_controller/cmd_vel", True),
        ("humble", True, "/diffbot_base_controller/cmd_vel", True),
        ("humble", False, "/diffbot_base_controller/cmd_vel_unstamped", False),
        # Jazzy and later: TwistStamped on ~/cmd_vel, whatever the old flag says.
        ("jazzy", False, "/diffbot_base_controller/cmd_vel", True),
        ("kilted", None, "/diffbot_base_controller/cmd_vel", True),
        ("rolling", True, "/diffbot_base_controller/cmd_vel", True),
        # No release known: a file that turns stamping off was written for Humble.
        (None, False, "/diffbot_base_controller/cmd_vel_unstamped", False),
        (None, None, "/diffbot_base_controller/cmd_vel", True),
    ],
)
def test_the_controllers_topic_by_release(
    distro: str | None, use_stamped_vel: bool | None, topic: str, stamped: bool
) -> None:
    found = command_topic(controller(use_stamped_vel), distro)
    assert (found.topic, found.stamped) == (topic, stamped)


def test_the_release_comes_from_the_option_then_ros_distro() -> None:
    assert distro_of("Humble", {"ROS_DISTRO": "jazzy"}) == "humble"
    assert distro_of(None, {"ROS_DISTRO": "jazzy"}) == "jazzy"
    assert distro_of(None, {"ROS_DISTRO": "noetic"}) is None
    assert distro_of(None, {}) is None
    with pytest.raises(ParameterError, match="distro"):
        distro_of("foxy", {})


def test_a_namespaced_controllers_topic_is_under_its_namespace() -> None:
    # a file whose section is /a200_0000/platform_velocity_controller: the controller's node is
    # there, and so is its ~/cmd_vel
    namespaced = controller(False, "platform_velocity_controller", "a200_0000")
    assert command_topic(namespaced, "humble").topic == (
        "/a200_0000/platform_velocity_controller/cmd_vel_unstamped"
    )
    assert command_topic(namespaced, "jazzy").topic == (
        "/a200_0000/platform_velocity_controller/cmd_vel"
    )
