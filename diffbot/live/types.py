"""The ROS 2 message types diffbot speaks on a live graph, as DDS structs, declared once.

Each class is the DDS type a ROS 2 middleware registers for the message: named
``pkg::msg::dds_::Name_`` (rmw_cyclonedds' and Fast DDS' mangling of ``pkg/msg/Name``), ``final``
and keyless, its fields in the order and widths of the ``.msg`` file. On the wire they are plain
CDR (XCDR1), little endian, behind the 4-byte encapsulation header, byte for byte what a ROS 2
node sends; :mod:`diffbot.live.transport` forces that representation in QoS.

Units are those of the messages: m, m/s, rad, rad/s; stamps in whole seconds and nanoseconds.

The struct machinery comes from :mod:`diffbot.live.cyclone`, the one module that imports
cyclonedds (and says how to install it when it is missing).
"""

# No ``from __future__ import annotations``: cyclonedds reads the field types from the class
# annotations when it builds a type's serializer.

from dataclasses import dataclass, field
from typing import Any

from diffbot.live.cyclone import IdlStruct, final, idl

__all__ = [
    "ROS_TYPES",
    "EmptyRequest",
    "EmptyResponse",
    "Float64MultiArray",
    "Gid",
    "Header",
    "HumbleGid",
    "HumbleNodeEntitiesInfo",
    "HumbleParticipantEntitiesInfo",
    "JointState",
    "MultiArrayDimension",
    "MultiArrayLayout",
    "NodeEntitiesInfo",
    "Odometry",
    "ParticipantEntitiesInfo",
    "Point",
    "Pose",
    "PoseStamped",
    "PoseWithCovariance",
    "PoseWithCovarianceStamped",
    "Quaternion",
    "SetOdometryRequest",
    "SetOdometryResponse",
    "String",
    "TFMessage",
    "Time",
    "Transform",
    "TransformStamped",
    "Twist",
    "TwistStamped",
    "TwistWithCovariance",
    "Vector3",
    "dds_type_name",
    "discovery_types",
    "ros_type_name",
]


def dds_type_name(ros_name: str) -> str:
    """The DDS name of a ROS type: ``pkg/msg/Name`` -> ``pkg::msg::dds_::Name_``."""
    package, kind, name = ros_name.split("/")
    return f"{package}::{kind}::dds_::{name}_"


def ros_type_name(dds_name: str) -> str:
    """The ROS name of a DDS type name (the inverse of :func:`dds_type_name`); a name that is
    not a ROS type's comes back unchanged."""
    parts = dds_name.split("::")
    if len(parts) != 4 or parts[2] != "dds_" or not parts[3].endswith("_"):
        return dds_name
    return f"{parts[0]}/{parts[1]}/{parts[3][:-1]}"


@final
@dataclass
class Time(IdlStruct, typename="builtin_interfaces::msg::dds_::Time_"):
    """builtin_interfaces/Time: seconds and nanoseconds (0..999999999) since the epoch."""

    sec: idl.int32 = 0
    nanosec: idl.uint32 = 0


@final
@dataclass
class Header(IdlStruct, typename="std_msgs::msg::dds_::Header_"):
    """std_msgs/Header: the stamp and the frame the data is in."""

    stamp: Time = field(default_factory=Time)
    frame_id: str = ""


@final
@dataclass
class Vector3(IdlStruct, typename="geometry_msgs::msg::dds_::Vector3_"):
    """geometry_msgs/Vector3."""

    x: idl.float64 = 0.0
    y: idl.float64 = 0.0
    z: idl.float64 = 0.0


@final
@dataclass
class Point(IdlStruct, typename="geometry_msgs::msg::dds_::Point_"):
    """geometry_msgs/Point (m)."""

    x: idl.float64 = 0.0
    y: idl.float64 = 0.0
    z: idl.float64 = 0.0


@final
@dataclass
class Quaternion(IdlStruct, typename="geometry_msgs::msg::dds_::Quaternion_"):
    """geometry_msgs/Quaternion: the identity unless given."""

    x: idl.float64 = 0.0
    y: idl.float64 = 0.0
    z: idl.float64 = 0.0
    w: idl.float64 = 1.0


@final
@dataclass
class Pose(IdlStruct, typename="geometry_msgs::msg::dds_::Pose_"):
    """geometry_msgs/Pose."""

    position: Point = field(default_factory=Point)
    orientation: Quaternion = field(default_factory=Quaternion)


@final
@dataclass
class Twist(IdlStruct, typename="geometry_msgs::msg::dds_::Twist_"):
    """geometry_msgs/Twist: linear (m/s) and angular (rad/s) velocity."""

    linear: Vector3 = field(default_factory=Vector3)
    angular: Vector3 = field(default_factory=Vector3)


@final
@dataclass
class TwistStamped(IdlStruct, typename="geometry_msgs::msg::dds_::TwistStamped_"):
    """geometry_msgs/TwistStamped."""

    header: Header = field(default_factory=Header)
    twist: Twist = field(default_factory=Twist)


@final
@dataclass
class Transform(IdlStruct, typename="geometry_msgs::msg::dds_::Transform_"):
    """geometry_msgs/Transform: translation (m) and rotation."""

    translation: Vector3 = field(default_factory=Vector3)
    rotation: Quaternion = field(default_factory=Quaternion)


@final
@dataclass
class TransformStamped(IdlStruct, typename="geometry_msgs::msg::dds_::TransformStamped_"):
    """geometry_msgs/TransformStamped: the child frame in ``header.frame_id``."""

    header: Header = field(default_factory=Header)
    child_frame_id: str = ""
    transform: Transform = field(default_factory=Transform)


@final
@dataclass
class PoseWithCovariance(IdlStruct, typename="geometry_msgs::msg::dds_::PoseWithCovariance_"):
    """geometry_msgs/PoseWithCovariance: a 6x6 row-major covariance."""

    pose: Pose = field(default_factory=Pose)
    covariance: idl.array[idl.float64, 36] = field(default_factory=lambda: [0.0] * 36)


@final
@dataclass
class PoseStamped(IdlStruct, typename="geometry_msgs::msg::dds_::PoseStamped_"):
    """geometry_msgs/PoseStamped: a pose in ``header.frame_id`` (what motion capture sends)."""

    header: Header = field(default_factory=Header)
    pose: Pose = field(default_factory=Pose)


@final
@dataclass
class PoseWithCovarianceStamped(
    IdlStruct, typename="geometry_msgs::msg::dds_::PoseWithCovarianceStamped_"
):
    """geometry_msgs/PoseWithCovarianceStamped: what localization (AMCL, robot_localization)
    publishes."""

    header: Header = field(default_factory=Header)
    pose: PoseWithCovariance = field(default_factory=PoseWithCovariance)


@final
@dataclass
class TwistWithCovariance(IdlStruct, typename="geometry_msgs::msg::dds_::TwistWithCovariance_"):
    """geometry_msgs/TwistWithCovariance."""

    twist: Twist = field(default_factory=Twist)
    covariance: idl.array[idl.float64, 36] = field(default_factory=lambda: [0.0] * 36)


@final
@dataclass
class Odometry(IdlStruct, typename="nav_msgs::msg::dds_::Odometry_"):
    """nav_msgs/Odometry: the pose in ``header.frame_id``, the twist in ``child_frame_id``."""

    header: Header = field(default_factory=Header)
    child_frame_id: str = ""
    pose: PoseWithCovariance = field(default_factory=PoseWithCovariance)
    twist: TwistWithCovariance = field(default_factory=TwistWithCovariance)


@final
@dataclass
class JointState(IdlStruct, typename="sensor_msgs::msg::dds_::JointState_"):
    """sensor_msgs/JointState: positions (rad), velocities (rad/s), efforts (N m) by name."""

    header: Header = field(default_factory=Header)
    name: idl.sequence[str] = field(default_factory=list)
    position: idl.sequence[idl.float64] = field(default_factory=list)
    velocity: idl.sequence[idl.float64] = field(default_factory=list)
    effort: idl.sequence[idl.float64] = field(default_factory=list)


@final
@dataclass
class MultiArrayDimension(IdlStruct, typename="std_msgs::msg::dds_::MultiArrayDimension_"):
    """std_msgs/MultiArrayDimension."""

    label: str = ""
    size: idl.uint32 = 0
    stride: idl.uint32 = 0


@final
@dataclass
class MultiArrayLayout(IdlStruct, typename="std_msgs::msg::dds_::MultiArrayLayout_"):
    """std_msgs/MultiArrayLayout."""

    dim: idl.sequence[MultiArrayDimension] = field(default_factory=list)
    data_offset: idl.uint32 = 0


@final
@dataclass
class Float64MultiArray(IdlStruct, typename="std_msgs::msg::dds_::Float64MultiArray_"):
    """std_msgs/Float64MultiArray: what a forward_command_controller's ``commands`` takes."""

    layout: MultiArrayLayout = field(default_factory=MultiArrayLayout)
    data: idl.sequence[idl.float64] = field(default_factory=list)


@final
@dataclass
class String(IdlStruct, typename="std_msgs::msg::dds_::String_"):
    """std_msgs/String."""

    data: str = ""


@final
@dataclass
class TFMessage(IdlStruct, typename="tf2_msgs::msg::dds_::TFMessage_"):
    """tf2_msgs/TFMessage: what /tf and /tf_static carry."""

    transforms: idl.sequence[TransformStamped] = field(default_factory=list)


def _entities_info(
    gid_bytes: int, release: str, prefix: str = ""
) -> tuple[type[Any], type[Any], type[Any]]:
    """rmw_dds_common's Gid, NodeEntitiesInfo and ParticipantEntitiesInfo with GIDs of
    ``gid_bytes`` bytes, as the ROS releases ``release`` declare them, their Python names
    behind ``prefix``: one declaration for both widths, whose DDS types share their names."""

    @final
    @dataclass
    class Gid(IdlStruct, typename="rmw_dds_common::msg::dds_::Gid_"):
        data: idl.array[idl.uint8, gid_bytes] = bytes(gid_bytes)  # type: ignore[misc]

    @final
    @dataclass
    class NodeEntitiesInfo(IdlStruct, typename="rmw_dds_common::msg::dds_::NodeEntitiesInfo_"):
        node_namespace: idl.bounded_str[256] = "/"
        node_name: idl.bounded_str[256] = ""
        reader_gid_seq: idl.sequence[Gid] = field(default_factory=list)
        writer_gid_seq: idl.sequence[Gid] = field(default_factory=list)

    @final
    @dataclass
    class ParticipantEntitiesInfo(
        IdlStruct, typename="rmw_dds_common::msg::dds_::ParticipantEntitiesInfo_"
    ):
        gid: Gid = field(default_factory=Gid)
        node_entities_info_seq: idl.sequence[NodeEntitiesInfo] = field(default_factory=list)

    Gid.__doc__ = (
        f"rmw_dds_common/Gid as {release} declare it: {gid_bytes} bytes, an endpoint's 16-byte"
        " DDS GUID" + (", then zeros." if gid_bytes > 16 else ".")
    )
    NodeEntitiesInfo.__doc__ = (
        "rmw_dds_common/NodeEntitiesInfo: a node's name and the GIDs of its readers and writers"
        f" ({release})."
    )
    ParticipantEntitiesInfo.__doc__ = (
        "rmw_dds_common/ParticipantEntitiesInfo: what ``ros_discovery_info`` carries, the nodes"
        f" of one DDS participant ({release})."
    )
    made = (Gid, NodeEntitiesInfo, ParticipantEntitiesInfo)
    for kind in made:
        kind.__name__ = kind.__qualname__ = prefix + kind.__name__
    return made


Gid, NodeEntitiesInfo, ParticipantEntitiesInfo = _entities_info(16, "Iron and later")
HumbleGid, HumbleNodeEntitiesInfo, HumbleParticipantEntitiesInfo = _entities_info(
    24, "Humble and earlier", "Humble"
)


#: The ROS distributions whose rmw_dds_common/Gid holds 24 bytes (16 since Iron).
GID_24_DISTROS = frozenset(
    {"ardent", "bouncy", "crystal", "dashing", "eloquent", "foxy", "galactic", "humble"}
)


def discovery_types(
    distro: str,
) -> tuple[type[Any], type[Any], type[Any]]:
    """The ParticipantEntitiesInfo, NodeEntitiesInfo and Gid types of ROS distribution
    ``distro`` (a name as ``ROS_DISTRO`` holds it): Humble's 24-byte GIDs up to Humble, else
    16-byte ones."""
    if distro.strip().lower() in GID_24_DISTROS:
        return HumbleParticipantEntitiesInfo, HumbleNodeEntitiesInfo, HumbleGid
    return ParticipantEntitiesInfo, NodeEntitiesInfo, Gid


# --------------------------------------------------------------------------------------------
# Services. rmw_cyclonedds sends a request and its reply as one sample each, on the DDS topics
# ``rq/<service>Request`` and ``rr/<service>Reply``, the message behind a 16-byte header
# (``cdds_request_header_t`` in its serdata.hpp): the client's 64-bit id (``guid``, the last
# half of its writer's GUID) and the request's sequence number (``seq``). In plain CDR the two
# leading fields of a struct are those same 16 bytes, so each type below is the header's two
# fields, then the ``.srv`` file's. A server copies both into its reply; a client keeps the
# replies carrying its own id.


@final
@dataclass
class SetOdometryRequest(IdlStruct, typename="control_msgs::srv::dds_::SetOdometry_Request_"):
    """control_msgs/srv/SetOdometry's request: the pose to put the odometry at (m, rad)."""

    guid: idl.uint64 = 0
    seq: idl.int64 = 0
    x: idl.float64 = 0.0
    y: idl.float64 = 0.0
    z: idl.float64 = 0.0
    roll: idl.float64 = 0.0
    pitch: idl.float64 = 0.0
    yaw: idl.float64 = 0.0


@final
@dataclass
class SetOdometryResponse(IdlStruct, typename="control_msgs::srv::dds_::SetOdometry_Response_"):
    """control_msgs/srv/SetOdometry's response: whether the pose was taken, and why not."""

    guid: idl.uint64 = 0
    seq: idl.int64 = 0
    success: bool = False
    message: str = ""


@final
@dataclass
class EmptyRequest(IdlStruct, typename="std_srvs::srv::dds_::Empty_Request_"):
    """std_srvs/srv/Empty's request (an empty struct gets one placeholder byte in ROS 2)."""

    guid: idl.uint64 = 0
    seq: idl.int64 = 0
    structure_needs_at_least_one_member: idl.uint8 = 0


@final
@dataclass
class EmptyResponse(IdlStruct, typename="std_srvs::srv::dds_::Empty_Response_"):
    """std_srvs/srv/Empty's response."""

    guid: idl.uint64 = 0
    seq: idl.int64 = 0
    structure_needs_at_least_one_member: idl.uint8 = 0


#: Every message type of the nodes' topics, by its ROS name (the discovery types, whose
#: layout depends on the distribution, are in :func:`discovery_types`).
ROS_TYPES: dict[str, type[IdlStruct]] = {
    ros_type_name(cls.__idl_typename__): cls
    for cls in (
        Time,
        Header,
        Vector3,
        Point,
        Quaternion,
        Pose,
        Twist,
        TwistStamped,
        Transform,
        TransformStamped,
        PoseWithCovariance,
        PoseStamped,
        PoseWithCovarianceStamped,
        TwistWithCovariance,
        Odometry,
        JointState,
        MultiArrayDimension,
        MultiArrayLayout,
        Float64MultiArray,
        String,
        TFMessage,
    )
}
