"""The plan table's header says the robot's size as the commands use it."""

from __future__ import annotations

from robots import BOT

from diffbot.formats.plan_table import geometry_text, plan_table
from diffbot.planfile import parse_plan
from diffbot.ros.script import ros2_script
from diffbot.trajectory import plan


def test_equal_radii_are_one_radius() -> None:
    assert geometry_text(BOT) == "wheel radius 0.035 m, separation 0.135 m"


def test_equal_multiplied_radii_are_the_radius_the_wheels_roll_with() -> None:
    # Both multipliers 1.1: the rpm are those of 0.0385 m wheels, and so is the radius shown.
    robot = BOT.replace(left_wheel_radius=0.0385, right_wheel_radius=0.0385)
    assert geometry_text(robot) == "wheel radius 0.0385 m, separation 0.135 m"


def test_unequal_radii_are_each_side_s() -> None:
    # A controller's radius multipliers: the wheels roll on 0.0501 m and 0.0499 m, and the
    # table's rpm are computed from those, not from the nominal 0.05 m.
    robot = BOT.replace(wheel_radius=0.05, left_wheel_radius=0.0501, right_wheel_radius=0.0499)
    text = "wheel radii 0.0501 m left and 0.0499 m right, separation 0.135 m"
    assert geometry_text(robot) == text
    steps = plan(parse_plan("straight 1"), robot)
    assert f"({text})" in plan_table(steps, "plan").splitlines()[1]
    assert f"({text}); motor limit" in plan_table(steps, "plan", wide=True).splitlines()[1]
    topics = {"cmd_vel": "cmd_vel", "left_topic": "l", "right_topic": "r"}
    script = ros2_script(steps, "test", wheels=False, rate=10.0, **topics)
    assert f"({text})" in script.splitlines()[2]
