"""The live message types are byte for byte the CDR of ROS 2's own: each type's serialization
equals rosbags' CDR serializer (Humble and Jazzy type stores), both ways, for messages
hypothesis makes up.

Both serializers write the 4-byte encapsulation header (``00 01 00 00``: plain CDR, little
endian) before the body, so whole byte strings compare."""

from __future__ import annotations

import dataclasses
import struct
import typing
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from rosbags.typesys import Stores, get_typestore

from diffbot.live import types
from diffbot.live.types import ROS_TYPES, dds_type_name, ros_type_name

STORES = {"humble": get_typestore(Stores.ROS2_HUMBLE), "jazzy": get_typestore(Stores.ROS2_JAZZY)}
#: ROS strings are UTF-8 without NUL.
TEXT = st.text(st.characters(codec="utf-8", exclude_characters="\x00"), max_size=12)
FLOAT = st.floats(allow_nan=False, width=64)
RANGES = {"int32": (-(2**31), 2**31 - 1), "uint32": (0, 2**32 - 1)}


def strategy(annotation: Any) -> st.SearchStrategy[Any]:
    """Values of a field's type, read from its cyclonedds annotation."""
    if annotation is str:
        return TEXT
    if isinstance(annotation, type) and dataclasses.is_dataclass(annotation):
        hints = typing.get_type_hints(annotation, include_extras=True)
        return st.builds(
            annotation, **{f.name: strategy(hints[f.name]) for f in dataclasses.fields(annotation)}
        )
    kind = typing.get_args(annotation)[1]
    if kind == "float64":
        return FLOAT
    if kind in RANGES:
        return st.integers(*RANGES[kind])
    element = strategy(kind.subtype)
    if type(kind).__name__ == "array":
        return st.lists(element, min_size=kind.length, max_size=kind.length)
    return st.lists(element, max_size=4)


def plain(value: Any) -> Any:
    """A message of either library as nested dicts and lists of Python values."""
    if isinstance(value, np.ndarray):
        return [plain(v) for v in value.tolist()]
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {
            f.name: plain(getattr(value, f.name))
            for f in dataclasses.fields(value)
            if f.name != "__msgtype__"
        }
    return value


def to_rosbags(value: Any, store: Any, ros_name: str) -> Any:
    """Our message as the typestore's message class."""
    cls = store.types[ros_name]
    hints = typing.get_type_hints(type(value), include_extras=True)
    fields: dict[str, Any] = {}
    for f in dataclasses.fields(value):
        item = getattr(value, f.name)
        annotation = hints[f.name]
        if dataclasses.is_dataclass(item):
            fields[f.name] = to_rosbags(item, store, ros_type_name(type(item).__idl_typename__))
        elif isinstance(item, list):
            kind = typing.get_args(annotation)[1]
            if getattr(kind, "subtype", None) is str:
                fields[f.name] = list(item)
            elif dataclasses.is_dataclass(kind.subtype):
                name = ros_type_name(kind.subtype.__idl_typename__)
                fields[f.name] = [to_rosbags(v, store, name) for v in item]
            else:
                fields[f.name] = np.array(item, dtype=np.float64)
        else:
            fields[f.name] = item
    return cls(**fields)


@pytest.mark.parametrize("store_name", sorted(STORES))
@pytest.mark.parametrize("ros_name", sorted(ROS_TYPES))
@settings(max_examples=40, deadline=None)
@given(data=st.data())
def test_bytes_equal_rosbags_both_ways(ros_name: str, store_name: str, data: st.DataObject) -> None:
    store = STORES[store_name]
    cls = ROS_TYPES[ros_name]
    message = data.draw(strategy(cls))
    ours = message.serialize()
    theirs = bytes(store.serialize_cdr(to_rosbags(message, store, ros_name), ros_name))
    assert ours == theirs
    # Ours -> rosbags reads the same message; rosbags' bytes -> ours reads it too.
    assert plain(store.deserialize_cdr(ours, ros_name)) == plain(message)
    assert plain(cls.deserialize(theirs)) == plain(message)


def test_the_header_says_plain_cdr_little_endian() -> None:
    # OMG DDS-XTypes 1.3, 7.6.3.1.2: CDR_LE is 0x0001; options follow as two zero bytes.
    assert types.String("ab").serialize() == bytes.fromhex("0001000003000000616200")


def test_the_types_carry_ros_dds_names() -> None:
    assert types.Odometry.__idl_typename__ == "nav_msgs::msg::dds_::Odometry_"
    assert dds_type_name("tf2_msgs/msg/TFMessage") == "tf2_msgs::msg::dds_::TFMessage_"
    assert ros_type_name("geometry_msgs::msg::dds_::TwistStamped_") == (
        "geometry_msgs/msg/TwistStamped"
    )
    assert ros_type_name("Chatter") == "Chatter"
    # Only the four-part form with dds_ and a trailing _ is a ROS type's; others stay as given.
    for other in ("a::msg::dds_::B", "a::msg::idl::B_", "a::dds_::B_", "a::b::msg::dds_::C_"):
        assert ros_type_name(other) == other
    assert len(ROS_TYPES) == 21
    for ros_name, cls in ROS_TYPES.items():
        assert cls.__idl_typename__ == dds_type_name(ros_name)
        cls().serialize()  # builds the type's serializer, which finds its keys
        assert cls.__idl_annotations__.get("extensibility", "final") == "final"
        assert cls.__idl__.keyless


def test_a_truncated_payload_is_refused() -> None:
    payload = types.JointState(name=["a"], position=[1.0]).serialize()
    for cut in (3, 9, 20):
        with pytest.raises(struct.error, match="requires a buffer"):
            types.JointState.deserialize(payload[:-cut])


def test_a_service_request_leads_with_rmw_cyclonedds_request_header() -> None:
    import struct

    from diffbot.live import types

    request = types.SetOdometryRequest(
        guid=0x0102030405060708, seq=7, x=5.0, y=-2.0, yaw=1.57079632679
    )
    # CDR little endian: the encapsulation header, then cdds_request_header_t (uint64 client
    # id, int64 sequence number), then the request's six float64 fields.
    header = b"\x00\x01\x00\x00" + struct.pack("<Qq", 0x0102030405060708, 7)
    assert request.serialize() == header + struct.pack(
        "<6d", 5.0, -2.0, 0.0, 0.0, 0.0, 1.57079632679
    )
    response = types.SetOdometryResponse(guid=1, seq=2, success=True, message="ok")
    body = response.serialize()[4:]
    # bool, padding to the string's 4-byte length, the string with its terminating NUL.
    assert body == struct.pack("<Qq", 1, 2) + b"\x01\x00\x00\x00" + struct.pack("<I", 3) + b"ok\x00"
    assert types.EmptyRequest(guid=3, seq=4).serialize()[4:] == struct.pack("<QqB", 3, 4, 0)
    assert (
        types.SetOdometryRequest.__idl_typename__ == "control_msgs::srv::dds_::SetOdometry_Request_"
    )
    assert types.EmptyResponse.__idl_typename__ == "std_srvs::srv::dds_::Empty_Response_"
