"""Names checked before they reach DDS: topics, frame ids and node names.

A name goes into Cyclone's C code (a topic name: DDS aborts the process on one of 64 KiB or
more) or into every message (a frame id, as UTF-8 with a terminating NUL), so each is checked
once, here, for what ROS allows: its length, its encoding, and for topics and nodes the ROS
name rules (``rmw_validate_full_topic_name``, ``rmw_validate_node_name``). Plain string tests,
no regular expression: linear in the name's length.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Final

from diffbot.live.errors import LiveError
from diffbot.numbers import shown

__all__ = [
    "MAX_FRAME_LENGTH",
    "MAX_NODE_NAME_LENGTH",
    "MAX_TOPIC_LENGTH",
    "check_distinct_topics",
    "check_frame_id",
    "check_node_name",
    "check_topic",
    "frame_problem",
    "node_name_problem",
    "repeated_topic",
    "resolve_topic",
    "topic_problem",
]

#: Longest topic name ROS 2 accepts, its leading ``/`` included (rmw: 255 less 8 for the
#: ``rt/`` and other prefixes).
MAX_TOPIC_LENGTH: Final = 247
#: Longest node name (rmw).
MAX_NODE_NAME_LENGTH: Final = 255
#: Longest frame id taken (characters): far beyond any robot's, short enough for every tool.
MAX_FRAME_LENGTH: Final = 255


def _encoding_problem(name: str) -> str | None:
    try:
        name.encode("utf-8")
    except UnicodeEncodeError:
        return "is not valid UTF-8"
    if any(ord(c) < 0x20 or ord(c) == 0x7F for c in name):
        return "holds a control character"
    return None


def _token_problem(token: str) -> str | None:
    if not token:
        return "has an empty part (a doubled or trailing '/')"
    if not (token.isascii() and token.replace("_", "a").isalnum()):
        return "may hold only letters, digits, '_' and '/'"
    if token[0].isdigit():
        return "has a part starting with a digit"
    return None


def topic_problem(name: str) -> str | None:
    """What is wrong with ``name`` as a ROS topic name (``/a/b``, ``a/b``, ``~/a``); None
    when it is a valid one."""
    if len(name) > MAX_TOPIC_LENGTH:
        return f"is longer than {MAX_TOPIC_LENGTH} characters ({len(name)})"
    problem = _encoding_problem(name)
    if problem is not None:
        return problem
    body = name[2:] if name.startswith("~/") else name[1:] if name.startswith("/") else name
    for token in body.split("/"):
        problem = _token_problem(token)
        if problem is not None:
            return problem
    return None


def resolve_topic(name: str, node: str) -> str:
    """The absolute name of topic ``name`` of node ``node`` in the root namespace, as rcl
    expands it: ``odom`` and ``/odom`` are ``/odom``, a private ``~/odom`` is ``/<node>/odom``.

    Raises:
        LiveError: the expanded name is longer than ROS allows.
    """
    full = f"/{node}/{name[2:]}" if name.startswith("~/") else "/" + name.lstrip("/")
    if len(full) > MAX_TOPIC_LENGTH:
        raise LiveError(
            f"topic {shown(name)} is longer than {MAX_TOPIC_LENGTH} characters once expanded "
            f"for node {shown(node)} ({len(full)})"
        )
    return full


def check_distinct_topics(named: Sequence[tuple[str, str]], node: str) -> None:
    """Refuse two of a node's topics that are one once expanded for node ``node``.

    Args:
        named: (what the topic is for, its name) pairs; a left and a right wheel's command
            topics, say: given one name, their commands would be mixed on it.
        node: the node's name (for private ``~/`` names).

    Raises:
        LiveError: a bad topic name, or two that are one topic.
    """
    problem = repeated_topic([(w, resolve_topic(check_topic(n, w), node)) for w, n in named])
    if problem is not None:
        raise LiveError(problem)


def repeated_topic(named: Sequence[tuple[str, str]]) -> str | None:
    """What is wrong when two of ``named``'s (what it is for, absolute name) topics are one;
    None when they all differ."""
    seen: dict[str, str] = {}
    for what, name in named:
        if name in seen:
            return f"{seen[name]} and {what} are both {name}: each needs a topic of its own"
        seen[name] = what
    return None


def node_name_problem(name: str) -> str | None:
    """What is wrong with ``name`` as a ROS node name (one token: letters, digits, ``_``, not
    starting with a digit); None when it is a valid one."""
    if len(name) > MAX_NODE_NAME_LENGTH:
        return f"is longer than {MAX_NODE_NAME_LENGTH} characters ({len(name)})"
    return _encoding_problem(name) or _token_problem(name)


def frame_problem(name: str) -> str | None:
    """What is wrong with ``name`` as a frame id (tf2 frames: any UTF-8 text without control
    characters, not empty, at most :data:`MAX_FRAME_LENGTH` characters); None when fine."""
    if not name:
        return "is empty"
    if len(name) > MAX_FRAME_LENGTH:
        return f"is longer than {MAX_FRAME_LENGTH} characters ({len(name)})"
    return _encoding_problem(name)


def _checked(name: str, what: str, problem: str | None) -> str:
    if problem is not None:
        raise LiveError(f"{what} {shown(name)} {problem}")
    return name


def check_topic(name: str, what: str = "topic") -> str:
    """``name`` when it is a valid ROS topic name.

    Raises:
        LiveError: naming ``what`` and the problem.
    """
    return _checked(name, what, topic_problem(name))


def check_node_name(name: str, what: str = "node name") -> str:
    """``name`` when it is a valid ROS node name.

    Raises:
        LiveError: naming ``what`` and the problem.
    """
    return _checked(name, what, node_name_problem(name))


def check_frame_id(name: str, what: str = "frame id") -> str:
    """``name`` when it is a usable frame id.

    Raises:
        LiveError: naming ``what`` and the problem.
    """
    return _checked(name, what, frame_problem(name))
