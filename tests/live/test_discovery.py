"""``ros_discovery_info``: the entry that makes ``ros2 node list`` name a diffbot node. Its types
are byte for byte rosbags' CDR of rmw_dds_common's messages, with Humble's 24-byte GIDs and
Jazzy's 16-byte ones; a plain DDS reader sees a node's name and its endpoints' GUIDs."""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from live_graph import PATIENCE, live_process
from rosbags.typesys import Stores, get_typestore

from diffbot.live import types
from diffbot.live.transport import DISCOVERY_TOPIC, Node

STORES = {"humble": get_typestore(Stores.ROS2_HUMBLE), "jazzy": get_typestore(Stores.ROS2_JAZZY)}
NAME = st.text(st.characters(codec="utf-8", exclude_characters="\x00"), max_size=12)
INFO = "rmw_dds_common/msg/ParticipantEntitiesInfo"


def gids(size: int) -> st.SearchStrategy[bytes]:
    return st.binary(min_size=size, max_size=size)


def as_rosbags(info: Any, store: Any) -> Any:
    gid = store.types["rmw_dds_common/msg/Gid"]
    node = store.types["rmw_dds_common/msg/NodeEntitiesInfo"]

    def g(value: Any) -> Any:
        return gid(data=np.frombuffer(value.data, dtype=np.uint8))

    return store.types[INFO](
        gid=g(info.gid),
        node_entities_info_seq=[
            node(
                node_namespace=n.node_namespace,
                node_name=n.node_name,
                reader_gid_seq=[g(r) for r in n.reader_gid_seq],
                writer_gid_seq=[g(w) for w in n.writer_gid_seq],
            )
            for n in info.node_entities_info_seq
        ],
    )


@pytest.mark.parametrize(("distro", "size"), [("humble", 24), ("jazzy", 16)])
@settings(max_examples=40, deadline=None)
@given(data=st.data())
def test_discovery_bytes_equal_rosbags_both_ways(distro: str, size: int, data: Any) -> None:
    info_type, node_type, gid_type = types.discovery_types(distro)
    gid = st.builds(gid_type, data=gids(size))
    info = data.draw(
        st.builds(
            info_type,
            gid=gid,
            node_entities_info_seq=st.lists(
                st.builds(
                    node_type,
                    node_namespace=NAME,
                    node_name=NAME,
                    reader_gid_seq=st.lists(gid, max_size=3),
                    writer_gid_seq=st.lists(gid, max_size=3),
                ),
                max_size=2,
            ),
        )
    )
    store = STORES[distro]
    ours = info.serialize()
    assert ours == bytes(store.serialize_cdr(as_rosbags(info, store), INFO))
    back = store.deserialize_cdr(ours, INFO)
    assert bytes(back.gid.data) == bytes(info.gid.data)
    assert [n.node_name for n in back.node_entities_info_seq] == [
        n.node_name for n in info.node_entities_info_seq
    ]
    assert info_type.deserialize(ours) == info


def test_the_gid_layout_follows_the_distribution() -> None:
    # rmw_dds_common/msg/Gid.msg: uint8[24] data up to Humble, uint8[16] data since Iron.
    assert len(types.discovery_types("humble")[2]().data) == 24
    assert len(types.discovery_types("Foxy")[2]().data) == 24
    assert len(types.discovery_types("jazzy")[2]().data) == 16
    assert len(types.discovery_types("rolling")[2]().data) == 16
    assert types.ParticipantEntitiesInfo.__idl_typename__ == (
        "rmw_dds_common::msg::dds_::ParticipantEntitiesInfo_"
    )
    # By hand from the .msg: header, 16 GID bytes, one node: "/" and "n" as CDR strings,
    # no readers, no writers.
    info = types.ParticipantEntitiesInfo(
        gid=types.Gid(data=bytes(range(16))),
        node_entities_info_seq=[types.NodeEntitiesInfo(node_namespace="/", node_name="n")],
    )
    assert info.serialize() == (
        bytes.fromhex("00010000")
        + bytes(range(16))
        + (1).to_bytes(4, "little")
        + (2).to_bytes(4, "little")
        + b"/\0\0\0"
        + (2).to_bytes(4, "little")
        + b"n\0\0\0"
        + bytes(8)
    )


def discovered(
    listener: Node, distro: str, accept: Callable[[Any], bool], patience: float = PATIENCE
) -> Any:
    """The last ``ros_discovery_info`` entry (``distro``'s layout) that ``accept`` takes, read
    by a plain DDS reader of ``listener``'s participant; fails after :data:`PATIENCE`."""
    from cyclonedds.sub import DataReader
    from cyclonedds.topic import Topic

    from diffbot.live.transport import LATCHED

    info_type = types.discovery_types(distro)[0]
    topic = Topic(listener.participant, DISCOVERY_TOPIC, info_type)
    reader = DataReader(listener.participant, topic, LATCHED.qos())
    end = time.monotonic() + patience
    while time.monotonic() < end:
        seen = [s for s in reader.take(N=16) if accept(s)]
        if seen:
            return seen[-1]
        time.sleep(0.02)
    raise AssertionError("no such discovery entry in time")


def counts(entry: Any) -> list[tuple[str, str, int, int]]:
    return [
        (n.node_namespace, n.node_name, len(n.reader_gid_seq), len(n.writer_gid_seq))
        for n in entry.node_entities_info_seq
    ]


@pytest.mark.parametrize(("distro", "size"), [("humble", 24), ("jazzy", 16), ("", 16)])
def test_an_announced_node_is_seen_with_its_endpoints(
    distro: str, size: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    if distro:
        monkeypatch.setenv("ROS_DISTRO", distro)
    else:  # unset: the newest layout
        monkeypatch.delenv("ROS_DISTRO", raising=False)
    with Node("announced_probe") as node, Node("listener") as listener:
        node.create_subscription(types.JointState, "joint_states", lambda m: None)
        node.announce()
        # Endpoints made after the announcement are announced too.
        node.create_publisher(types.Odometry, "odom")
        node.create_publisher(types.TFMessage, "/tf")
        entry = discovered(listener, distro or "jazzy", lambda e: counts(e)[0][3] == 2)
        assert counts(entry) == [("/", "announced_probe", 1, 2)]
        assert bytes(entry.gid.data) == node.participant.guid.bytes.ljust(size, b"\0")
        (info,) = entry.node_entities_info_seq
        assert [bytes(g.data) for g in info.reader_gid_seq] == [
            guid.ljust(size, b"\0") for guid in node.reader_guids
        ]
        assert [bytes(g.data) for g in info.writer_gid_seq] == [
            guid.ljust(size, b"\0") for guid in node.writer_guids
        ]
        # The GIDs are the endpoints' DDS GUIDs: the listener discovers the same ones.
        assert len(set(node.writer_guids) | set(node.reader_guids)) == 3


def test_node_odom_announce_names_the_node(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("ROS_DISTRO", "humble")
    with live_process("node", "odom", "--announce"), Node("listener") as listener:
        entry = discovered(listener, "humble", lambda e: bool(e.node_entities_info_seq))
    # joint_states and the two services' requests read; odom, /tf and the two replies written.
    assert counts(entry) == [("/", "diffbot_odometry", 3, 4)]
    assert len(entry.gid.data) == 24


def test_without_announce_a_node_stays_off_the_list() -> None:
    with live_process("node", "odom"), Node("listener") as listener:
        # The node is up once it reads joint_states; a latched entry would arrive with it.
        states = listener.create_publisher(types.JointState, "joint_states")
        assert states.wait_for_subscribers(PATIENCE)
        with pytest.raises(AssertionError, match="no such discovery entry"):
            discovered(listener, "jazzy", lambda e: True, patience=2.0)
