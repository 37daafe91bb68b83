"""--cmd-vel defaults to the controllers file's diff-drive controller's own topic, by release
(--distro, ROS_DISTRO), in plan's message lines and ros2 script, drive and node ik."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest
from cli_results import assert_one_error_line
from click.testing import CliRunner, Result
from robots import bundled_controllers

from diffbot.cli import main
from diffbot.commands.topic_options import (
    resolve_cmd_vel,
    resolve_odom_topic,
    resolve_wheel_topics,
)
from diffbot.controller_config import ControllerConfig
from diffbot.kinematics import DiffDriveParams
from diffbot.urdf import load_params

#: A ros2_control_demos-style controllers file for the bundled robot's joints, written for Humble.
HUMBLE_CONTROLLERS = bundled_controllers("use_stamped_vel: false", update_rate=10)


@pytest.fixture
def controllers(tmp_path: Path) -> str:
    path = tmp_path / "controllers.yaml"
    path.write_text(HUMBLE_CONTROLLERS)
    return str(path)


def run(runner: CliRunner, *args: str, env: dict[str, str] | None = None) -> Result:
    return runner.invoke(main, list(args), env={"ROS_DISTRO": "", **(env or {})})


def test_twist_lines_go_to_the_controllers_unstamped_topic_on_humble(
    runner: CliRunner, controllers: str
) -> None:
    result = run(runner, "plan", "--controllers", controllers, "--format", "twist", "straight 1")
    assert result.exit_code == 0, result.output
    first = result.stdout.splitlines()[0]
    assert (
        "geometry_msgs/msg/Twist commands for /diffbot_base_controller/cmd_vel_unstamped" in first
    )


def test_jazzy_takes_twiststamped_on_cmd_vel(runner: CliRunner, controllers: str) -> None:
    for args, env in (
        (["--distro", "jazzy"], None),
        ([], {"ROS_DISTRO": "jazzy"}),
    ):
        result = run(
            runner,
            "plan",
            "--controllers",
            controllers,
            "--format",
            "ros2",
            "straight 1",
            *args,
            env=env,
        )
        assert result.exit_code == 0, result.output
        assert (
            "ros2 topic pub -r 10 /diffbot_base_controller/cmd_vel "
            "geometry_msgs/msg/TwistStamped" in result.stdout
        )
        # the file's use_stamped_vel: false is a Humble parameter: said to do nothing here
        assert result.stderr.splitlines() == [
            f"warning: {controllers}: use_stamped_vel: false means nothing on Jazzy (a Humble "
            "parameter): the controller takes TwistStamped on /diffbot_base_controller/cmd_vel"
        ]


def test_cmd_vel_given_overrides_the_controllers_topic(runner: CliRunner, controllers: str) -> None:
    result = run(
        runner,
        "plan",
        "--controllers",
        controllers,
        "--format",
        "twist",
        "--cmd-vel-topic",
        "my_cmd",
        "--distro",
        "jazzy",
        "straight 1",
    )
    assert result.exit_code == 0, result.output
    # The controller remapped to my_cmd still takes Jazzy's TwistStamped.
    assert "geometry_msgs/msg/TwistStamped commands for my_cmd" in result.stdout.splitlines()[0]


def test_without_a_controllers_file_the_topic_stays_cmd_vel(runner: CliRunner) -> None:
    result = run(runner, "plan", "--format", "twist", "straight 1", "--distro", "jazzy")
    assert result.exit_code == 0, result.output
    assert "geometry_msgs/msg/Twist commands for cmd_vel," in result.stdout.splitlines()[0]


def test_drive_waits_on_the_controllers_topic(runner: CliRunner, controllers: str) -> None:
    # Nothing subscribes: the message names the topic the commands would go to.
    result = run(
        runner,
        "drive",
        "--controllers",
        controllers,
        "straight 0.1",
        "--wait",
        "0.2",
        env={"ROS_DOMAIN_ID": "187"},
    )
    assert_one_error_line(result, "/diffbot_base_controller/cmd_vel_unstamped")


def test_resolving_the_topic_of_node_ik() -> None:
    robot = DiffDriveParams(
        wheel_radius=0.035,
        wheel_separation=0.135,
        controller=ControllerConfig(name="base", source="c.yaml", ros_version=2),
    )
    assert resolve_cmd_vel(robot, None, False, "jazzy") == ("/base/cmd_vel", True)
    # A topic given (the controller's remapped) keeps the type of the release named...
    assert resolve_cmd_vel(robot, "x", False, "jazzy") == ("x", True)
    assert robot.controller is not None
    controller = dataclasses.replace(robot.controller, use_stamped_vel=False)
    unstamped = robot.replace(controller=controller)
    assert resolve_cmd_vel(unstamped, "x", False, "humble") == ("x", False)
    assert resolve_cmd_vel(unstamped, None, False, "humble") == ("/base/cmd_vel_unstamped", False)
    # ... and without a release named, it is Twist unless asked for stamps.
    assert resolve_cmd_vel(robot, "x", False, None) == ("x", False)
    assert resolve_cmd_vel(robot, "x", True, None) == ("x", True)
    plain = DiffDriveParams(wheel_radius=0.035, wheel_separation=0.135)
    assert resolve_cmd_vel(plain, None, True, "jazzy") == ("cmd_vel", True)
    assert resolve_cmd_vel(plain, None, False, None) == ("cmd_vel", False)
    # Without a configuration there is no controller: the course's nodes take Twist.
    assert resolve_cmd_vel(plain, "/cmd_vel", False, "jazzy") == ("/cmd_vel", False)


def test_without_a_controller_the_gazebo_plugin_s_topic_is_the_default(
    runner: CliRunner, tmp_path: Path
) -> None:
    # A Gazebo classic ROS 2 plugin in namespace /demo, its cmd_vel remapped to cmd_demo.
    urdf = Path(__file__).parents[1] / "corpus/gazebo_classic_ros2_two_pairs/urdf/two_pairs.urdf"
    text = urdf.read_text("utf-8").replace(
        "<ros><namespace>/demo</namespace></ros>",
        "<ros><namespace>/demo</namespace><remapping>cmd_vel:=cmd_demo</remapping></ros>",
    )
    robot = tmp_path / "robot.urdf"
    robot.write_text(text, "utf-8")
    result = run(runner, "plan", "--robot", str(robot), "--format", "twist", "straight 0.1")
    assert result.exit_code == 0, result.output
    assert "ros2 topic pub -r 10 /demo/cmd_demo geometry_msgs/msg/Twist" in result.stdout
    # A topic given still wins, and a controllers file's controller before the plugin.
    given = run(
        runner,
        "plan",
        "--robot",
        str(robot),
        "--cmd-vel-topic",
        "x",
        "--format",
        "twist",
        "straight 0.1",
    )
    assert "ros2 topic pub -r 10 x geometry_msgs/msg/Twist" in given.stdout
    topics = {"cmd_vel": "/demo/c", "odom": "/demo/o"}
    plain = DiffDriveParams(wheel_radius=0.035, wheel_separation=0.135, plugin_topics=topics)
    assert resolve_cmd_vel(plain, None, False, None) == ("/demo/c", False)
    assert resolve_odom_topic(plain, None) == "/demo/o"
    assert resolve_odom_topic(plain, "given") == "given"
    controlled = plain.replace(
        controller=ControllerConfig(name="base", source="c.yaml", ros_version=2)
    )
    assert resolve_cmd_vel(controlled, None, False, "jazzy") == ("/base/cmd_vel", True)
    assert resolve_odom_topic(controlled, None) == "/base/odom"
    bare = DiffDriveParams(wheel_radius=0.035, wheel_separation=0.135)
    assert resolve_odom_topic(bare, None) == "odom"


def test_the_controllers_file_names_the_wheel_command_topics(tmp_path: Path) -> None:
    controllers = tmp_path / "controllers.yaml"
    controllers.write_text(
        "/ns/controller_manager:\n  ros__parameters: {update_rate: 50}\n"
        "/ns/left_side:\n  ros__parameters:\n    joints: [front_left_wheel_joint]\n"
        "/ns/right_side:\n  ros__parameters:\n    joints: [front_right_wheel_joint]\n"
    )
    params = load_params()
    found = ("ns/left_side/commands", "ns/right_side/commands")
    assert resolve_wheel_topics(params, str(controllers)) == found
    assert resolve_wheel_topics(params, str(controllers), ("l", None)) == ("l", found[1])
    assert resolve_wheel_topics(params, None) == (
        "left_wheel_velocity_controller/commands",
        "right_wheel_velocity_controller/commands",
    )
    # plan's wheel formats publish where node ik does: the file's topics, not the course's.
    controllers.write_text(
        bundled_controllers()
        + "left_side:\n  ros__parameters:\n    joints: [front_left_wheel_joint]\n"
        + "right_side:\n  ros__parameters:\n    joints: [front_right_wheel_joint]\n"
    )
    for args in (["--format", "wheels"], ["--format", "ros2", "--wheels"]):
        result = run(CliRunner(), "plan", "--controllers", str(controllers), *args, "straight 0.1")
        assert result.exit_code == 0, result.output
        assert "left_side/commands" in result.stdout
        assert "left_wheel_velocity_controller" not in result.stdout
    # A topic the file gives that no node could take is one error line naming the file.
    bad = tmp_path / "bad.yaml"
    bad.write_text(controllers.read_text().replace("\nleft_side:", "\n/n s/left_side:"))
    refused = run(
        CliRunner(), "plan", "--controllers", str(bad), "--format", "wheels", "straight 0.1"
    )
    assert_one_error_line(refused, str(bad))
    assert "--left-topic" in refused.stderr


@pytest.mark.parametrize("command", ["plan", "drive", "node ik"])
def test_an_unknown_distro_is_one_error_line(runner: CliRunner, command: str) -> None:
    assert_one_error_line(run(runner, *command.split(), "--distro", "foxy"), "--distro")


@pytest.mark.parametrize("fmt", ["twist", "ros2"])
def test_a_controller_topic_no_node_could_take_is_one_error_line(
    runner: CliRunner, tmp_path: Path, fmt: str
) -> None:
    # The controller's node in a namespace holding a space: /a b/base/cmd_vel is no topic.
    path = tmp_path / "controllers.yaml"
    path.write_text(bundled_controllers(name="/a b/base"))
    result = run(runner, "plan", "--controllers", str(path), "--format", fmt, "straight 0.1")
    assert_one_error_line(result, "controllers.yaml", "'/a b/base/cmd_vel'", "--cmd-vel-topic")
    # A format that names no topic still reads the robot; a topic given replaces the file's.
    table = run(runner, "plan", "--controllers", str(path), "straight 0.1")
    assert table.exit_code == 0, table.output
    given = run(runner, "plan", "--controllers", str(path), "--format", fmt, "--cmd-vel-topic", "c")
    assert given.exit_code == 0, given.output


def test_a_plugin_topic_no_node_could_take_is_a_bad_input_error() -> None:
    from diffbot.commands.messages import InputError

    topics = {"cmd_vel": "/demo/c-1", "odom": "/1/o"}
    plain = DiffDriveParams(wheel_radius=0.035, wheel_separation=0.135, plugin_topics=topics)
    with pytest.raises(InputError, match=r"'/demo/c-1'.*--cmd-vel$"):
        resolve_cmd_vel(plain, None, False, None)
    with pytest.raises(InputError, match=r"'/1/o'.*--odom-topic$"):
        resolve_odom_topic(plain, None)
    assert resolve_cmd_vel(plain, None, False, None, None) == ("/demo/c-1", False)
    assert resolve_odom_topic(plain, "o") == "o"
    controlled = plain.replace(
        controller=ControllerConfig(name="b-1", source="c.yaml", ros_version=2)
    )
    with pytest.raises(InputError, match=r"c\.yaml: the topic '/b-1/odom'"):
        resolve_odom_topic(controlled, None)
