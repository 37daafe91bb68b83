"""The transport: ROS names and QoS on DDS, the domain and discovery range from the environment,
publishers and subscriptions that meet on loopback, malformed payloads counted."""

from __future__ import annotations

import math
import os
import re
import signal
import threading
import time
from typing import Any, cast

import pytest
from live_graph import PATIENCE, timer_periods, until

from diffbot.live import types
from diffbot.live.signals import caught, deferred
from diffbot.live.transport import (
    LiveError,
    Node,
    Timer,
    cyclone_config,
    dds_topic,
    discovery_range,
    domain_id,
)


def test_ros_topics_live_under_rt() -> None:
    assert dds_topic("/odom") == "rt/odom"
    assert dds_topic("cmd_vel") == "rt/cmd_vel"
    assert dds_topic("/Xtopic") == "rt/Xtopic"  # only the root's slash goes
    assert dds_topic("left_wheel_velocity_controller/commands") == (
        "rt/left_wheel_velocity_controller/commands"
    )


def test_the_domain_comes_from_ros_domain_id() -> None:
    assert domain_id({}) == 0
    assert domain_id({"ROS_DOMAIN_ID": " 42 "}) == 42
    assert domain_id({"ROS_DOMAIN_ID": "0"}) == 0
    assert domain_id({"ROS_DOMAIN_ID": "232"}) == 232
    for bad in ("233", "-1", "x", "1.5", "\u0664\u0662", "4_2", "\uff14"):
        with pytest.raises(LiveError, match="ROS_DOMAIN_ID must be a whole number from 0 to 232"):
            domain_id({"ROS_DOMAIN_ID": bad})


def test_the_discovery_range_follows_ros_conventions() -> None:
    assert discovery_range({}) == "SUBNET"
    assert discovery_range({"ROS_LOCALHOST_ONLY": "1"}) == "LOCALHOST"
    assert discovery_range({"ROS_LOCALHOST_ONLY": "0"}) == "SUBNET"
    # Iron and later: the range wins over the older variable.
    env = {"ROS_LOCALHOST_ONLY": "1", "ROS_AUTOMATIC_DISCOVERY_RANGE": "subnet"}
    assert discovery_range(env) == "SUBNET"
    assert discovery_range({"ROS_AUTOMATIC_DISCOVERY_RANGE": "OFF"}) == "OFF"
    assert discovery_range({"ROS_AUTOMATIC_DISCOVERY_RANGE": "SYSTEM_DEFAULT"}) == "SUBNET"
    with pytest.raises(LiveError, match="must be SUBNET, LOCALHOST, OFF"):
        discovery_range({"ROS_AUTOMATIC_DISCOVERY_RANGE": "LAN"})


def test_localhost_keeps_discovery_on_loopback() -> None:
    local = cyclone_config("LOCALHOST")
    assert "<NetworkInterface name='lo'/>" in local
    assert "<AllowMulticast>false</AllowMulticast>" in local
    assert "<Peer address='localhost'/>" in local
    off = cyclone_config("OFF")
    assert "<NetworkInterface name='lo'/>" in off
    assert "Peer" not in off
    assert "<Discovery></Discovery>" in off  # nothing to discover by: this process only
    subnet = cyclone_config("SUBNET")
    assert "NetworkInterface" not in subnet
    assert "AllowMulticast" not in subnet
    assert "Peer" not in subnet
    # The user's own configuration comes first, so that ours wins where both say something.
    assert cyclone_config("LOCALHOST", "file:///etc/dds.xml").startswith("file:///etc/dds.xml,")


def test_a_message_crosses_between_nodes_and_malformed_payloads_are_counted() -> None:
    got: list[types.JointState] = []
    with Node("talker") as talker, Node("listener") as listener:
        publisher = talker.create_publisher(types.JointState, "/joint_states")
        subscription = listener.create_subscription(types.JointState, "joint_states", got.append)
        assert publisher.wait_for_subscribers(PATIENCE)
        assert subscription.wait_for_publishers(PATIENCE)
        sent = types.JointState(name=["a", "b"], position=[1.0, -2.0])
        publisher.publish(sent)
        until(listener, lambda: bool(got))
        assert got == [sent]
        assert listener.publisher_types("/joint_states") == {"sensor_msgs::msg::dds_::JointState_"}
        payload = sent.serialize()
        subscription.deliver([payload[:-5], payload, b"\x00\x01"])
        assert (subscription.received, subscription.malformed) == (2, 2)
        assert got[-1] == sent


def test_timers_fire_on_a_monotonic_schedule() -> None:
    ticks: list[float] = []
    with Node("clock") as node:
        timer = node.create_timer(0.02, lambda: ticks.append(time.monotonic()))
        first = timer.due
        start = time.monotonic()
        node.spin(0.21)
    # At most once a period, however the machine keeps up (a late tick is not made up).
    assert 1 <= len(ticks) <= 11
    # Never early: the k-th tick takes a slot at start + 0.02 m, m > k.
    lateness = [t - (start + 0.02 * (k + 1)) for k, t in enumerate(ticks)]
    assert min(lateness) >= -0.001
    # The schedule stays on its grid: late ticks do not shift the later ones.
    slots = (timer.due - first) / 0.02
    assert slots == pytest.approx(round(slots), abs=1e-6)


def test_a_stalled_timer_skips_the_ticks_it_missed_and_stays_on_its_grid() -> None:
    fired: list[float] = []
    timer = Timer(0.02, lambda: fired.append(timer.due), due=1.0)
    timer.fire_if_due(0.999)  # not yet
    timer.fire_if_due(1.0)
    timer.fire_if_due(1.013)  # not yet: the next is at 1.02
    timer.fire_if_due(1.105)  # a stall past 1.02 ... 1.10: one tick, the next at 1.12
    timer.fire_if_due(1.11)
    timer.fire_if_due(1.12)
    assert fired == pytest.approx([1.02, 1.12, 1.14], abs=1e-12)


def test_a_service_answers_each_client_under_its_own_id_and_sequence() -> None:
    from live_graph import ServiceClient

    from diffbot.live import types

    def handler(request: types.SetOdometryRequest) -> types.SetOdometryResponse:
        return types.SetOdometryResponse(success=request.x > 0.0, message=f"x {request.x:g}")

    with Node("server") as server:
        server.create_service(
            types.SetOdometryRequest, types.SetOdometryResponse, "/server/echo", handler
        )
        server.start()
        first = ServiceClient(
            "/server/echo", types.SetOdometryRequest, types.SetOdometryResponse, 1
        )
        second = ServiceClient(
            "/server/echo", types.SetOdometryRequest, types.SetOdometryResponse, 2
        )
        try:
            first.wait_for_service()
            second.wait_for_service()
            a = first.call(types.SetOdometryRequest(x=1.5))
            b = second.call(types.SetOdometryRequest(x=-1.0))
            a2 = first.call(types.SetOdometryRequest(x=2.0))
        finally:
            first.close()
            second.close()
    # Each reply carries its request's client id and sequence number, and its own answer.
    assert (a.guid, a.seq, a.success, a.message) == (1, 1, True, "x 1.5")  # type: ignore[attr-defined]
    assert (b.guid, b.seq, b.success, b.message) == (2, 1, False, "x -1")  # type: ignore[attr-defined]
    assert (a2.guid, a2.seq, a2.message) == (1, 2, "x 2")  # type: ignore[attr-defined]


@pytest.mark.parametrize("service", ["/server/set_odometry", "/Xserver/set_odometry"])
def test_a_request_of_another_type_is_named_once(service: str) -> None:
    from cyclonedds.pub import DataWriter
    from cyclonedds.topic import Topic

    from diffbot.live import types
    from diffbot.live.qos import SERVICE

    with Node("server") as server, Node("client") as client:
        server.create_service(
            types.SetOdometryRequest,
            types.SetOdometryResponse,
            service,
            lambda request: types.SetOdometryResponse(success=True),
        )
        # A std_srvs/srv/Empty client of the same service name: it never matches the server.
        topic = Topic(client.participant, f"rq{service}Request", types.EmptyRequest)
        writer = DataWriter(client.participant, topic, SERVICE.qos())
        end = time.monotonic() + PATIENCE
        while not server.warnings and time.monotonic() < end:
            server.spin_once(0.05)
            server.check_types()
        del writer
    assert server.warnings == [
        f"'{service}' carries std_srvs/srv/Empty_Request; this node reads "
        "control_msgs/srv/SetOdometry_Request"
    ]


@pytest.mark.parametrize(
    ("service", "base"),
    # Only the leading slash is the root's: a name may begin and end with any letter.
    [("/server/reset", "server/reset"), ("/Xserver/resetX", "Xserver/resetX")],
)
def test_a_services_endpoints_carry_one_service_id_as_rmw_cyclonedds_pairs_them(
    service: str, base: str
) -> None:

    from cyclonedds.builtin import (
        BuiltinDataReader,
        BuiltinTopicDcpsPublication,
        BuiltinTopicDcpsSubscription,
    )
    from cyclonedds.qos import Policy

    from diffbot.live import types

    with Node("server") as server, Node("client") as client:
        server.create_service(
            types.EmptyRequest,
            types.EmptyResponse,
            service,
            lambda r: types.EmptyResponse(),
        )
        writers = BuiltinDataReader(client.participant, BuiltinTopicDcpsPublication)
        readers = BuiltinDataReader(client.participant, BuiltinTopicDcpsSubscription)

        def user_data(reader: Any, topic: str) -> list[bytes]:
            return [
                s.qos[Policy.Userdata].data
                for s in reader.read(N=4096)
                if getattr(s, "topic_name", None) == topic and Policy.Userdata in s.qos
            ]

        end = time.monotonic() + PATIENCE
        found: tuple[list[bytes], list[bytes]] = ([], [])
        while time.monotonic() < end and not all(found):
            found = (
                user_data(writers, f"rr/{base}Reply"),
                user_data(readers, f"rq/{base}Request"),
            )
            time.sleep(0.05)
        guids = (
            [s.key.bytes for s in writers.read(N=4096) if s.topic_name == f"rr/{base}Reply"],
            [s.key.bytes for s in readers.read(N=4096) if s.topic_name == f"rq/{base}Request"],
        )
    assert found[0] == found[1]
    assert len(found[0]) == 1
    # rmw_cyclonedds' form: the 16 bytes of an id in hex, dot-separated.
    assert re.fullmatch(rb"serviceid=(?:[0-9a-f]{1,2}\.){15}[0-9a-f]{1,2};", found[0][0])
    # The node lists the endpoints under their DDS GUIDs (what an announcement publishes).
    assert guids == ([server.writer_guids[-1]], [server.reader_guids[-1]])


def test_private_names_live_under_the_node() -> None:
    with Node("private_talker") as talker, Node("listener") as listener:
        chatter = talker.create_publisher(types.String, "~/chatter")
        talker.create_service(
            types.EmptyRequest, types.EmptyResponse, "~/reset", lambda r: types.EmptyResponse()
        )
        assert talker.resolve("~/chatter") == "/private_talker/chatter"
        until(listener, lambda: bool(listener.publications("/private_talker/chatter")))
        assert listener.publications("/private_talker/chatter") == ["std_msgs::msg::dds_::String_"]
        assert listener.publications("/x", "rr/private_talker/resetReply") == [
            "std_srvs::srv::dds_::Empty_Response_"
        ]
        assert listener.publications("~/chatter") == []  # the listener's own private name
        assert chatter.topic == "~/chatter"


def test_a_node_describes_what_it_reads_publishes_and_serves() -> None:
    with Node("describer") as node:
        assert node.describe() == "no topics"
        node.create_subscription(types.Twist, "cmd_vel", lambda m: None)
        node.create_subscription(types.TwistStamped, "/cmd_vel", lambda m: None)
        node.create_subscription(types.JointState, "~/joints", lambda m: None)
        node.create_publisher(types.Odometry, "odom")
        for service in ("~/reset", "/stop"):
            node.create_service(
                types.EmptyRequest, types.EmptyResponse, service, lambda r: types.EmptyResponse()
            )
        assert node.describe() == (
            "reads /cmd_vel (geometry_msgs/msg/Twist or geometry_msgs/msg/TwistStamped), "
            "/describer/joints (sensor_msgs/msg/JointState); "
            "publishes /odom (nav_msgs/msg/Odometry); serves /describer/reset, /stop"
        )


@pytest.mark.parametrize("text", ["", "a", "ab", "abc", "abcd"])
def test_serialized_payloads_of_any_length_arrive_whole(text: str) -> None:
    # A payload is padded to whole 4-byte words on the wire, as rmw does.
    got: list[str] = []
    raw: list[bytes] = []
    sent = types.String(text).serialize()
    with Node("talker") as talker, Node("listener") as listener:
        chatter = talker.create_publisher(types.String, "chatter")
        listener.create_subscription(types.String, "chatter", lambda m: got.append(m.data))
        listener.create_subscription(
            types.String, "chatter", raw.append, decode=cast(Any, lambda data: data)
        )
        assert chatter.wait_for_subscribers(PATIENCE)
        chatter.publish_serialized(sent)
        until(listener, lambda: bool(got and raw))
    assert got == [text]
    (payload,) = raw
    assert len(payload) % 4 == 0
    assert payload == sent + bytes(len(payload) - len(sent))


def test_a_type_mismatch_names_every_type_read() -> None:
    with Node("reader") as node:
        assert node.type_mismatch("/cmd_vel", "a/msg/B", ["x/msg/T", "x/msg/U"]) == (
            "'/cmd_vel' carries a/msg/B; this node reads x/msg/T or x/msg/U"
        )


def test_the_drop_count_outlives_the_reader() -> None:
    # A reader that keeps 3 waiting samples and refuses the newer ones, never spun: the rest of
    # 20 are refused. The count is never read before the node goes; it is read as it goes.
    from diffbot.live.transport import QosProfile

    keeps_three = QosProfile(reliable=False, depth=3, drop_newest=True)
    with Node("talker") as talker:
        reader = Node("reader")
        subscription = reader.create_subscription(
            types.String, "chatter", lambda m: None, keeps_three
        )
        chatter = talker.create_publisher(types.String, "chatter")
        assert chatter.wait_for_subscribers(PATIENCE)
        for k in range(20):
            chatter.publish(types.String(str(k)))

        def refused() -> int:
            status = subscription.reader.get_sample_rejected_status()  # type: ignore[no-untyped-call]
            return int(status.total_count)

        end = time.monotonic() + PATIENCE
        while refused() < 17 and time.monotonic() < end:
            time.sleep(0.01)
        # Best effort on a busy machine may lose a sample on the way: some were refused.
        seen = refused()
        assert seen > 0
        reader.destroy_node()
    assert subscription.dropped >= seen


def test_one_timer_checks_the_types_of_every_reader_each_second() -> None:
    with Node("reader") as node:
        assert node._timers == []  # no reader yet: nothing to check
        node.create_subscription(types.String, "a", lambda m: None)
        node.create_subscription(types.String, "b", lambda m: None)
        node.create_service(
            types.EmptyRequest, types.EmptyResponse, "c", lambda r: types.EmptyResponse()
        )
        assert timer_periods(node, node.check_types) == [1.0]


def test_a_started_node_spins_in_a_daemon_thread_named_for_it() -> None:
    with Node("background").start():
        (thread,) = [t for t in threading.enumerate() if t.name == "diffbot-background"]
        assert thread.daemon
        assert thread.is_alive()
    assert not thread.is_alive()  # the node's end waits for its spin to end


def test_stopping_and_destroying_twice_is_harmless_and_timers_need_a_period() -> None:
    node = Node("twice")
    # Nothing waiting: spin_once(0) returns at once, not after a wait slice.
    started = time.monotonic()
    for _ in range(10):
        node.spin_once(0.0)
    assert time.monotonic() - started < 0.3
    for period in (0.0, -1.0, math.inf, math.nan):
        with pytest.raises(LiveError, match="a timer period must be positive and finite"):
            node.create_timer(period, lambda: None)
    node.start()
    node.shutdown()
    # The background spin has ended when shutdown returns.
    assert "diffbot-twice" not in [t.name for t in threading.enumerate()]
    node.shutdown()
    node.destroy_node()
    node.destroy_node()


def test_a_signal_ends_a_spin_at_once_and_the_next_spin_waits_idle() -> None:
    with Node("sleeper") as node:
        with deferred(deliver=False):
            threading.Timer(0.1, os.kill, (os.getpid(), signal.SIGINT)).start()
            started = time.monotonic()
            node.spin(PATIENCE)
            assert time.monotonic() - started < PATIENCE / 2
            assert caught() == signal.SIGINT
        # The wake the signal set is cleared: the next spin sleeps in its wait set for the
        # whole time instead of returning at once from every wait.
        started, cpu = time.monotonic(), time.process_time()
        node.spin(0.5)
        assert time.monotonic() - started >= 0.5
        assert time.process_time() - cpu < 0.2


@pytest.fixture
def long_waits(monkeypatch: pytest.MonkeyPatch) -> None:
    """Waits in C of a minute, so that only a wake can end one early."""
    from diffbot.live import transport

    monkeypatch.setattr(transport, "_WAIT_SLICE", 60.0)


@pytest.mark.usefixtures("long_waits")
def test_a_wake_or_a_shutdown_ends_every_wait_until_cleared() -> None:
    with Node("woken") as node:
        node.wake()
        started = time.monotonic()
        for _ in range(3):
            node.spin_once(PATIENCE)
        assert time.monotonic() - started < PATIENCE / 2
    with Node("stopped") as node:
        node.shutdown()
        started = time.monotonic()
        node.spin_once(PATIENCE)
        assert time.monotonic() - started < PATIENCE / 2


def test_spin_once_waits_for_nothing_unless_told() -> None:
    with Node("eager") as node:
        started = time.monotonic()
        for _ in range(10):
            node.spin_once()
        assert time.monotonic() - started < 0.3


def test_one_spin_hands_on_every_waiting_message_however_many() -> None:
    from diffbot.live.transport import QosProfile

    got: list[str] = []
    many = QosProfile(depth=1000)
    with Node("talker") as talker, Node("listener") as listener:
        chatter = talker.create_publisher(types.String, "chatter", many)
        listener.create_subscription(types.String, "chatter", lambda m: got.append(m.data), many)
        assert chatter.wait_for_subscribers(PATIENCE)
        for k in range(600):
            chatter.publish(types.String(str(k)))
        end = time.monotonic() + PATIENCE
        while time.monotonic() < end:  # all 600 wait in the reader, none taken yet
            if len(listener._subscriptions[0].reader.read(N=1000)) == 600:
                break
            time.sleep(0.01)
        listener.spin_once(0.0)
    assert got == [str(k) for k in range(600)]


def test_a_latched_publisher_reaches_a_reader_that_comes_later() -> None:
    from diffbot.live.transport import LATCHED

    got: list[str] = []
    with Node("talker") as talker, Node("late") as late:
        kept = talker.create_publisher(types.String, "map", LATCHED)
        kept.publish(types.String("first"))
        news = talker.create_publisher(types.String, "news")
        news.publish(types.String("missed"))
        late.create_subscription(types.String, "map", lambda m: got.append(m.data), LATCHED)
        heard = late.create_subscription(types.String, "news", lambda m: got.append(m.data))
        until(late, lambda: bool(got))
        assert heard.wait_for_publishers(PATIENCE)
        late.spin(0.2)
    # The volatile publisher had no reader when it wrote: nothing of it is kept for later.
    assert got == ["first"]


def test_a_node_makes_each_topic_once_and_joins_its_own_domain() -> None:
    from live_graph import spare_domain

    with Node("topics", domain=spare_domain(3)) as node:
        assert node.participant.domain_id == spare_domain(3)
        assert node._topic(types.String, "x") is node._topic(types.String, "/x")
        assert node._topic(types.String, "x") is not node._topic(types.Twist, "x")


def test_a_node_whose_participant_is_gone_is_destroyed_quietly_and_makes_no_more() -> None:
    node = Node("gone")
    node.create_subscription(types.String, "chatter", lambda m: None)
    node.participant.__del__()
    node.destroy_node()
    late = Node("late")
    late.destroy_node()
    for make in (
        lambda: late.create_publisher(types.String, "out"),
        lambda: late.create_subscription(types.String, "out", lambda m: None),
        lambda: late.create_service(
            types.EmptyRequest, types.EmptyResponse, "out", lambda r: types.EmptyResponse()
        ),
    ):
        with pytest.raises(LiveError, match=r"^cannot make topic 'out': \[DDS_RETCODE_"):
            make()


@pytest.mark.parametrize("topic", ["~/cmd", "/reader/cmd"])
def test_a_topic_carrying_another_type_is_named_once_to_the_warn_callback(topic: str) -> None:
    told: list[str] = []
    with Node("reader") as reader, Node("talker") as talker:
        reader.warn = told.append
        reader.create_subscription(types.Twist, topic, lambda m: None)
        reader.create_subscription(types.String, "/both", lambda m: None)
        reader.create_subscription(types.Twist, "/both", lambda m: None)
        publishers = [
            talker.create_publisher(types.TwistStamped, "/reader/cmd"),
            talker.create_publisher(types.Twist, "/both"),
            talker.create_publisher(types.String, "/both"),
        ]
        end = time.monotonic() + PATIENCE
        while time.monotonic() < end and not (told and len(reader.publications("/both")) == 2):
            reader.spin_once(0.05)
            reader.check_types()
        reader.check_types()
        del publishers
    expected = [
        "'/reader/cmd' carries geometry_msgs/msg/TwistStamped; this node reads "
        "geometry_msgs/msg/Twist"
    ]
    assert told == expected
    assert reader.warnings == expected
