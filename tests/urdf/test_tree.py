"""The link/joint tree: whole-turn swivels, and wheels that turn on steering joints."""

from __future__ import annotations

import math
from collections.abc import Callable

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from linear_time import assert_linear

from diffbot.errors import DiffbotError, NotDifferentialError
from diffbot.urdf.tree import (
    FULL_TURN_SLACK,
    Tree,
    check_not_steered,
    joints_of,
    parse_urdf,
    steered_wheels,
)


def tree_of(body: str) -> Tree:
    text = f'<robot name="t"><link name="base_link"/>{body}</robot>'
    robot = parse_urdf(text, "t.urdf")
    return Tree(robot, joints_of(robot, "t.urdf"), "t.urdf")


def swivel(name: str, xyz: str, *, axis: str = "0 0 1", limit: str = "", rpy: str = "0 0 0") -> str:
    """A joint (revolute with ``limit``, else continuous) carrying a link named after it."""
    kind = "revolute" if limit else "continuous"
    return (
        f'<joint name="{name}" type="{kind}"><parent link="base_link"/><child link="{name}_l"/>'
        f'<origin xyz="{xyz}" rpy="{rpy}"/><axis xyz="{axis}"/>{limit}</joint>'
        f'<link name="{name}_l"/>'
    )


def wheel_under(parent: str, name: str, *, axis: str = "0 1 0") -> str:
    return (
        f'<joint name="{name}" type="continuous"><parent link="{parent}"/><child link="{name}_l"/>'
        f'<origin xyz="0 0 -0.05"/><axis xyz="{axis}"/></joint><link name="{name}_l"/>'
    )


def limits(lower: float, upper: float) -> str:
    return f'<limit lower="{lower!r}" upper="{upper!r}" effort="1" velocity="1"/>'


def test_a_wheel_on_a_limited_vertical_joint_is_steered() -> None:
    tree = tree_of(
        swivel("steer_fl", "0.3 0.2 0", limit=limits(-0.6, 0.6))
        + wheel_under("steer_fl_l", "wheel_fl")
        + swivel("plain_left", "0 0.2 0", axis="0 1 0")
    )
    assert steered_wheels(tree) == {"wheel_fl": ["steer_fl"]}
    with pytest.raises(NotDifferentialError) as raised:
        check_not_steered(tree, "t.urdf")
    message = str(raised.value)
    assert message.startswith("t.urdf: a steered robot, not a differential drive")
    assert "['wheel_fl']" in message
    assert "['steer_fl']" in message
    assert raised.value.fields["steering_joints"] == ["steer_fl"]


def test_a_free_swivel_is_a_casters_not_steering() -> None:
    tree = tree_of(
        swivel("caster_swivel", "-0.2 0 0") + wheel_under("caster_swivel_l", "caster_wheel")
    )
    assert steered_wheels(tree) == {}
    check_not_steered(tree, "t.urdf")  # no error


@pytest.mark.parametrize("half", [math.pi, 3.14159265, 3.14159, 3.1416, 3.14])
def test_a_swivel_limited_to_a_turn_as_written_is_a_casters(half: float) -> None:
    tree = tree_of(
        swivel("caster_swivel", "-0.2 0 0", limit=limits(-half, half))
        + wheel_under("caster_swivel_l", "caster_wheel")
    )
    assert tree.joints["caster_swivel"].full_turn
    assert steered_wheels(tree) == {}


def test_a_range_short_of_a_turn_by_more_than_the_slack_steers() -> None:
    half = math.pi - FULL_TURN_SLACK  # a range short of a turn by twice the slack
    tree = tree_of(
        swivel("steer", "0.3 0 0", limit=limits(-half, half)) + wheel_under("steer_l", "drive")
    )
    assert not tree.joints["steer"].full_turn
    assert steered_wheels(tree) == {"drive": ["steer"]}


def test_a_free_joint_between_makes_no_wheel_of_the_base() -> None:
    # An arm's pan joint is limited about z, but the joint below it rolls freely: the
    # continuous joint under both belongs to the arm, not to a steered wheel.
    tree = tree_of(
        swivel("pan", "0.1 0 0.3", limit=limits(-2.9, 2.9))
        + '<joint name="roll" type="continuous"><parent link="pan_l"/><child link="roll_l"/>'
        '<axis xyz="1 0 0"/></joint><link name="roll_l"/>' + wheel_under("roll_l", "wrist")
    )
    assert steered_wheels(tree) == {}


def test_suspension_about_a_lateral_axis_does_not_steer() -> None:
    tree = tree_of(
        swivel("rocker", "0 0.3 0", axis="0 1 0", limit=limits(-0.5, 0.5))
        + wheel_under("rocker_l", "wheel")
    )
    assert steered_wheels(tree) == {}


def test_a_steering_joint_is_vertical_in_the_base_frame_not_its_own() -> None:
    # Rolled a quarter turn, the joint's own y axis is the base's z: it steers.
    rolled = tree_of(
        swivel("knuckle", "0.3 0.2 0", axis="0 1 0", rpy=f"{math.pi / 2} 0 0", limit=limits(-1, 1))
        + wheel_under("knuckle_l", "wheel", axis="0 0 -1")
    )
    assert steered_wheels(rolled) == {"wheel": ["knuckle"]}
    # Its own z axis is then the base's -y: a suspension, steering nothing.
    lateral = tree_of(
        swivel("arm", "0.3 0.2 0", axis="0 0 1", rpy=f"{math.pi / 2} 0 0", limit=limits(-1, 1))
        + wheel_under("arm_l", "wheel", axis="0 0 -1")
    )
    assert steered_wheels(lateral) == {}


def test_every_steering_joint_of_a_chain_is_named_base_side_first() -> None:
    body = (
        swivel("outer", "0.3 0.2 0", limit=limits(-0.5, 0.5))
        + '<joint name="inner" type="revolute"><parent link="outer_l"/><child link="inner_l"/>'
        f'<axis xyz="0 0 1"/>{limits(-0.2, 0.2)}</joint><link name="inner_l"/>'
        + wheel_under("inner_l", "wheel")
    )
    assert steered_wheels(tree_of(body)) == {"wheel": ["outer", "inner"]}


@settings(max_examples=40, deadline=None)
@given(
    tilt=st.floats(min_value=0.0, max_value=math.pi / 2),
    span=st.floats(min_value=0.05, max_value=2 * math.pi - 2 * FULL_TURN_SLACK),
)
def test_steering_is_a_vertical_axis_within_25_degrees_and_a_range_short_of_a_turn(
    tilt: float, span: float
) -> None:
    # A joint leaning by `tilt` from the vertical (pitched about y), its wheel's axis lateral.
    body = swivel(
        "joint", "0.3 0.2 0", rpy=f"0 {tilt!r} 0", limit=limits(-span / 2, span / 2)
    ) + wheel_under("joint_l", "wheel")
    steers = steered_wheels(tree_of(body)) != {}
    assert steers == (math.cos(tilt) >= math.cos(math.radians(25.0)))


def _many_links(shape: str) -> Callable[[int], bytes]:
    """A tree of ``n`` more links: unattached (several roots), defined twice, in a chain of
    fixed joints below the base, each on the base, or in a chain with the wheels at its end."""

    def make(n: int) -> bytes:
        links = [f'<link name="x{i}"/>' for i in range(n)]
        if shape == "defined twice":
            links += links
        elif shape != "unattached":
            parents = ["base_link"] * n
            if shape != "on the base":
                parents = ["base_link", *(f"x{i}" for i in range(n - 1))]
            links += [
                f'<joint name="j{i}" type="fixed"><parent link="{parent}"/><child link="x{i}"/>'
                "</joint>"
                for i, parent in enumerate(parents)
            ]
        end = f"x{n - 1}" if shape == "wheels at the end of a chain" else "base_link"
        links += [wheel_under(end, "left"), wheel_under(end, "right")]
        return "".join(links).encode()

    return make


def _tree_and_wheels(data: bytes) -> object:
    tree = tree_of(data.decode())
    return steered_wheels(tree)


@pytest.mark.parametrize(
    "shape",
    ["unattached", "defined twice", "a chain", "on the base", "wheels at the end of a chain"],
)
def test_a_tree_of_many_links_is_checked_in_linear_time(shape: str) -> None:
    accepts = shape not in ("unattached", "defined twice")
    if not accepts:
        with pytest.raises(DiffbotError, match=r"root links|more than once"):
            _tree_and_wheels(_many_links(shape)(3))
    print(shape, assert_linear(_tree_and_wheels, _many_links(shape), 2000, accepts=accepts))


def test_a_cycle_far_from_the_root_is_named() -> None:
    chain = "".join(
        f'<link name="c{i}"/><joint name="k{i}" type="fixed"><parent link="c{(i - 1) % 50}"/>'
        f'<child link="c{i}"/></joint>'
        for i in range(50)
    )
    with pytest.raises(DiffbotError, match=r"a cycle through 'c\d+'"):
        tree_of(chain)
