"""Names are checked before they reach DDS: a topic of 65,536 characters killed a node with
SIGSEGV, a frame id that is not UTF-8 gave a traceback; each is now one error line."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from diffbot.live import types
from diffbot.live.errors import LiveError
from diffbot.live.names import (
    MAX_FRAME_LENGTH,
    MAX_TOPIC_LENGTH,
    check_distinct_topics,
    check_frame_id,
    check_node_name,
    check_topic,
    frame_problem,
    node_name_problem,
    repeated_topic,
    resolve_topic,
    topic_problem,
)
from diffbot.live.transport import Node

#: What ``sys.argv`` holds for the byte 0xff of a command line (surrogate escape).
NOT_UTF8 = b"odom\xff".decode("utf-8", "surrogateescape")


@pytest.mark.parametrize(
    "name", ["odom", "/odom", "~/odom", "/tf", "left_wheel_velocity_controller/commands", "_a/b1"]
)
def test_ros_topic_names_pass(name: str) -> None:
    assert topic_problem(name) is None


@pytest.mark.parametrize(
    ("name", "problem"),
    [
        ("", "has an empty part (a doubled or trailing '/')"),
        ("/", "has an empty part (a doubled or trailing '/')"),
        ("a//b", "has an empty part (a doubled or trailing '/')"),
        ("a/", "has an empty part (a doubled or trailing '/')"),
        ("1odom", "has a part starting with a digit"),
        ("a/2b", "has a part starting with a digit"),
        # A private name's first part is checked as any other.
        ("~/1odom", "has a part starting with a digit"),
        ("~/ odom", "may hold only letters, digits, '_' and '/'"),
        ("/1odom", "has a part starting with a digit"),
        ("a b", "may hold only letters, digits, '_' and '/'"),
        ("odöm", "may hold only letters, digits, '_' and '/'"),
        ("a\x00b", "holds a control character"),
        (NOT_UTF8, "is not valid UTF-8"),
        ("a" * 65_536, "is longer than 247 characters (65536)"),
    ],
)
def test_bad_topic_names_are_named(name: str, problem: str) -> None:
    assert topic_problem(name) == problem


@pytest.mark.parametrize(
    ("name", "resolved"),
    [
        ("odom", "/odom"),
        ("/odom", "/odom"),
        ("a/b", "/a/b"),
        ("~/odom", "/diffbot_odometry/odom"),
        ("~/a/b", "/diffbot_odometry/a/b"),
        # Only slashes lead to the root: a name may begin with any letter.
        ("Xray/scan", "/Xray/scan"),
    ],
)
def test_a_topic_resolves_as_rcl_expands_it_in_the_root_namespace(name: str, resolved: str) -> None:
    assert resolve_topic(name, "diffbot_odometry") == resolved


def test_a_checked_topic_is_returned_or_refused_naming_what_it_is() -> None:
    assert check_topic("/odom") == "/odom"
    with pytest.raises(LiveError) as refused:
        check_topic("a b", "cmd_vel")
    assert str(refused.value) == "cmd_vel 'a b' may hold only letters, digits, '_' and '/'"


def test_the_longest_topic_is_rmws() -> None:
    assert topic_problem("/" + "a" * (MAX_TOPIC_LENGTH - 1)) is None
    assert topic_problem("/" + "a" * MAX_TOPIC_LENGTH) is not None


def test_a_private_topic_is_held_to_the_longest_once_expanded() -> None:
    node = "n" * 10
    fits = "~/" + "a" * (MAX_TOPIC_LENGTH - len(node) - 2)
    assert len(resolve_topic(fits, node)) == MAX_TOPIC_LENGTH
    assert topic_problem(fits + "a") is None  # short enough as written...
    with pytest.raises(
        LiveError, match=r"longer than 247 characters once expanded .* \(248\)"
    ) as caught:
        resolve_topic(fits + "a", node)  # ...not once /<node>/ stands for ~/
    assert str(caught.value).startswith("topic '~/aaaa")
    assert "for node 'nnnnnnnnnn' (248)" in str(caught.value)


@settings(max_examples=60)
@given(st.text(max_size=300))
def test_a_name_that_passes_is_one_dds_takes(name: str) -> None:
    if topic_problem(name) is None:
        assert 0 < len(name) <= MAX_TOPIC_LENGTH
        assert name.isascii()
        assert "//" not in name
    if frame_problem(name) is None:
        assert 0 < len(name.encode("utf-8")) <= 4 * MAX_FRAME_LENGTH
        assert "\x00" not in name


def test_frames_and_node_names() -> None:
    assert frame_problem("base_link") is None
    assert frame_problem("robot1/base_link") is None
    assert frame_problem("") == "is empty"
    assert frame_problem(NOT_UTF8) == "is not valid UTF-8"
    assert frame_problem("x" * 256) == "is longer than 255 characters (256)"
    assert frame_problem("x" * 255) is None  # the longest taken
    assert node_name_problem("n" * 255) is None
    assert node_name_problem("n" * 256) == "is longer than 255 characters (256)"
    assert frame_problem("base\x7flink") == "holds a control character"  # DEL
    assert frame_problem("base\x80link") is None  # a C1 code point is UTF-8 text
    assert node_name_problem("diffbot_odometry") is None
    assert node_name_problem("diffbot/odometry") == "may hold only letters, digits, '_' and '/'"
    with pytest.raises(LiveError) as refused:
        check_frame_id(NOT_UTF8, "frame_id")
    assert str(refused.value) == "frame_id 'odom\\udcff' is not valid UTF-8"
    with pytest.raises(LiveError) as refused:
        check_frame_id("")
    assert str(refused.value) == "frame id '' is empty"
    with pytest.raises(LiveError) as refused:
        check_node_name("9lives")
    assert str(refused.value) == "node name '9lives' has a part starting with a digit"


def test_a_node_refuses_a_bad_name_before_dds_sees_it() -> None:
    with pytest.raises(LiveError, match="node name"):
        Node("no spaces")
    with Node("namer") as node:
        with pytest.raises(LiveError, match=r"^topic 'aaaa\S*\.\.\. is longer than 247"):
            node.create_publisher(types.String, "a" * 65_536)
        with pytest.raises(LiveError, match="not valid UTF-8"):
            node.create_subscription(types.String, NOT_UTF8, lambda m: None)


def _diffbot(*args: bytes) -> subprocess.CompletedProcess[bytes]:
    return subprocess.run(
        [sys.executable, "-m", "diffbot", *args],
        capture_output=True,
        timeout=120,
        check=False,
        env=os.environ.copy(),
    )


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (
            [b"node", b"odom", b"--odom-topic", b"a" * 65_536],
            b"error: --odom-topic '" + b"a" * 36 + b"... is not a valid ROS "
            b"topic name: it is longer than 247 characters (65536)\n",
        ),
        (
            [b"node", b"ik", b"--cmd-vel", b"cmd\xffvel"],
            b"error: --cmd-vel 'cmd\\udcffvel' is not a valid ROS topic name: it is not valid "
            b"UTF-8\n",
        ),
        (
            [b"node", b"odom", b"--frame-id", b"odom\xff"],
            b"error: --frame-id 'odom\\udcff' is not a usable frame id: it is not valid UTF-8\n",
        ),
        (
            [b"node", b"odom", b"--child-frame-id", b"b" * 300],
            b"error: --child-frame-id '" + b"b" * 36 + b"... is not a usable "
            b"frame id: it is longer than 255 characters (300)\n",
        ),
        (
            [b"drive", b"straight 0.1", b"--stamped", b"--frame-id", b"base\xfflink"],
            b"error: --frame-id 'base\\udcfflink' is not a usable frame id: it is not valid "
            b"UTF-8\n",
        ),
        (
            [b"node", b"robot", b"--left-topic", b"l" * 70_000],
            b"error: --left-topic '" + b"l" * 36 + b"... is not a valid ROS "
            b"topic name: it is longer than 247 characters (70000)\n",
        ),
    ],
)
def test_a_bad_name_on_the_command_line_is_one_error_line(
    args: list[bytes], message: bytes
) -> None:
    done = _diffbot(*args, b"--duration", b"0.1") if args[0] == b"node" else _diffbot(*args)
    assert done.returncode == 2, done.stderr[-2000:]
    assert done.stderr == message


@pytest.mark.parametrize(
    ("left", "right", "node", "both"),
    [("a", "/a", "n", "/a"), ("~/a", "/n/a", "n", "/n/a"), ("/n/b", "~/b", "n", "/n/b")],
)
def test_two_topics_that_expand_to_one_are_refused_naming_both(
    left: str, right: str, node: str, both: str
) -> None:
    with pytest.raises(LiveError) as refused:
        check_distinct_topics([("the left", left), ("the right", right)], node)
    assert (
        str(refused.value)
        == f"the left and the right are both {both}: each needs a topic of its own"
    )


def test_distinct_topics_pass_and_a_bad_one_is_named_before_any_comparison() -> None:
    check_distinct_topics([("l", "a"), ("r", "~/a"), ("c", "/b/a")], "b2")
    assert repeated_topic([("l", "/a"), ("r", "/b")]) is None
    assert repeated_topic([("l", "/a"), ("r", "/b"), ("c", "/a")]) == (
        "l and c are both /a: each needs a topic of its own"
    )
    with pytest.raises(LiveError, match=r"^the right topic '1a' "):
        check_distinct_topics([("the left topic", "1a"), ("the right topic", "1a")][::-1], "n")
