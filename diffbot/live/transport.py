"""DDS the way ROS 2 speaks it: the :class:`Node`, and the front door of the parts it is made of.

A :class:`Node` has rclpy's shape: it makes publishers, subscriptions and timers, :meth:`Node.spin`
runs it until a signal (or a deadline), and it is a context manager that destroys its entities on
the way out. What makes its endpoints match a stock ROS 2 node's (rmw_cyclonedds, rmw_fastrtps)
sits in one module a concern, each name also importable from here:

- :mod:`diffbot.live.discovery`: the domain (``ROS_DOMAIN_ID``), how far discovery reaches
  (``ROS_LOCALHOST_ONLY``, ``ROS_AUTOMATIC_DISCOVERY_RANGE``) as Cyclone configuration, topic
  ``/name`` as the DDS topic ``rt/name``;
- :mod:`diffbot.live.qos`: rclpy's QoS profiles, plain CDR (XCDR1) forced in every endpoint;
- :mod:`diffbot.live.endpoints`: publishers, subscriptions (a malformed payload counted and
  dropped, never raised) and timers;
- :mod:`diffbot.live.types`: the messages, types named ``pkg::msg::dds_::Name_``;
- :mod:`diffbot.live.cyclone`: the one module that imports cyclonedds.
"""

from __future__ import annotations

import contextlib
import math
import os
import threading
import time
from collections.abc import Callable
from typing import Any, Final, TypeVar

from diffbot.live.cyclone import (
    BuiltinDataReader,
    BuiltinTopicDcpsPublication,
    DataReader,
    DataWriter,
    DDSException,
    GuardCondition,
    IdlStruct,
    InstanceState,
    ReadCondition,
    SampleState,
    Topic,
    WaitSet,
)
from diffbot.live.discovery import (
    DISCOVERY_TOPIC,
    cyclone_config,
    dds_topic,
    discovery_range,
    domain_id,
)
from diffbot.live.endpoints import Publisher, Subscription, Timer
from diffbot.live.errors import INSTALL_HINT, LiveError
from diffbot.live.names import check_node_name, check_topic, resolve_topic
from diffbot.live.participant import leave, participant
from diffbot.live.qos import LATCHED, PUBLISHER, SERVICE, SUBSCRIPTION, TF, QosProfile
from diffbot.live.signals import caught, deferred

__all__ = [
    "DISCOVERY_TOPIC",
    "INSTALL_HINT",
    "LATCHED",
    "PUBLISHER",
    "SUBSCRIPTION",
    "TF",
    "IdlStruct",
    "LiveError",
    "Node",
    "Publisher",
    "QosProfile",
    "Subscription",
    "Timer",
    "cyclone_config",
    "dds_topic",
    "discovery_range",
    "domain_id",
]

#: The longest a wait blocks in C: signals are handled between waits.
_WAIT_SLICE: Final = 0.05

M = TypeVar("M", bound=IdlStruct)
R = TypeVar("R", bound=IdlStruct)
N = TypeVar("N", bound="Node")


class Node:
    """A node on the ROS 2 graph, shaped like rclpy's.

    Args:
        name: the node's name (for people and ``ros2 node list``; DDS has no node names).
        domain: the DDS domain; ``ROS_DOMAIN_ID`` when None.

    Raises:
        LiveError: a bad node name, domain id or discovery range, or DDS cannot start; a bad
            topic name when an endpoint is made (:mod:`diffbot.live.names`).
    """

    def __init__(self, name: str, *, domain: int | None = None) -> None:
        self.name = check_node_name(name)
        self.participant = participant(domain)
        try:
            self._waitset = WaitSet(self.participant)
            self._wake = GuardCondition(self.participant)
            self._waitset.attach(self._wake)
        except BaseException:
            leave(self.participant)
            raise
        self._topics: dict[tuple[str, str], Topic[Any]] = {}
        self._subscriptions: list[Subscription[Any]] = []
        self._services: list[Subscription[Any]] = []
        #: The (topic, DDS type name) of each publisher made.
        self._published: list[tuple[str, str]] = []
        self._checking = False
        self._timers: list[Timer] = []
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self._publications: BuiltinDataReader | None = None
        self._destroyed = False
        #: The GUIDs of this node's readers and writers (16 bytes each), as announced.
        self.reader_guids: list[bytes] = []
        self.writer_guids: list[bytes] = []
        self._announce: Callable[[], None] | None = None
        #: What the node found wrong with the graph, once each (a topic carrying another type).
        self.warnings: list[str] = []
        #: Called with each new warning (the commands print it).
        self.warn: Callable[[str], None] = lambda message: None

    def resolve(self, topic: str) -> str:
        """The absolute name of ``topic`` (checked) for this node: ``~/x`` is ``/<name>/x``."""
        return resolve_topic(check_topic(topic), self.name)

    def _topic(self, msg_type: type[M], name: str, dds_name: str | None = None) -> Topic[M]:
        dds_name = dds_topic(self.resolve(name)) if dds_name is None else dds_name
        key = (dds_name, msg_type.__idl_typename__)
        topic = self._topics.get(key)
        if topic is None:
            try:
                topic = Topic(self.participant, dds_name, msg_type)
            except DDSException as err:
                raise LiveError(f"cannot make topic {name!r}: {err}") from None
            self._topics[key] = topic
        return topic

    def create_publisher(
        self, msg_type: type[M], topic: str, qos: QosProfile = PUBLISHER
    ) -> Publisher[M]:
        """A publisher of ``msg_type`` on the ROS topic ``topic``."""
        writer = DataWriter(self.participant, self._topic(msg_type, topic), qos.qos())
        self.writer_guids.append(writer.guid.bytes)
        self._published.append((topic, msg_type.__idl_typename__))
        if self._announce is not None:
            self._announce()
        return Publisher(writer, topic)

    def create_subscription(
        self,
        msg_type: type[M],
        topic: str,
        callback: Callable[[M], None],
        qos: QosProfile = SUBSCRIPTION,
        decode: Callable[[bytes], M] | None = None,
    ) -> Subscription[M]:
        """A subscription of ``msg_type`` on ``topic``; each message goes to ``callback``,
        decoded by ``decode`` (default: the type's own deserializer) from its serialized
        bytes."""
        reader: DataReader[M] = DataReader(
            self.participant, self._topic(msg_type, topic), qos.qos()
        )
        subscription = Subscription(
            reader,
            decode or msg_type.deserialize,
            callback,
            topic,
            type_name=msg_type.__idl_typename__,
        )
        return self._read(subscription, self._subscriptions)

    def create_service(
        self,
        request_type: type[M],
        response_type: type[R],
        name: str,
        handler: Callable[[M], R],
    ) -> Subscription[M]:
        """A ROS 2 service ``name`` as rmw_cyclonedds offers one: requests read from the DDS
        topic ``rq/<name>Request``, each answered by ``handler``'s response on
        ``rr/<name>Reply`` with the request's client id and sequence number copied in (both
        types lead with the ``guid`` and ``seq`` of its request header; see
        :mod:`diffbot.live.types`). Reliable, volatile, keep last 10, as rmw's services
        profile. The subscription returned counts requests (``received``, ``malformed``)."""
        base = self.resolve(name).lstrip("/")
        # rmw_cyclonedds pairs a service's reader and writer by this id in their user data
        # (a client waits for both before it calls).
        service_id = ".".join(f"{b:x}" for b in os.urandom(16))
        qos = SERVICE.qos(f"serviceid={service_id};".encode())
        reply = DataWriter(
            self.participant, self._topic(response_type, name, f"rr/{base}Reply"), qos
        )
        self.writer_guids.append(reply.guid.bytes)

        def answer(request: M) -> None:
            response = handler(request)
            response.guid = request.guid  # type: ignore[attr-defined]
            response.seq = request.seq  # type: ignore[attr-defined]
            reply.write(response)

        reader: DataReader[M] = DataReader(
            self.participant, self._topic(request_type, name, f"rq/{base}Request"), qos
        )
        service = Subscription(
            reader, request_type.deserialize, answer, name, type_name=request_type.__idl_typename__
        )
        return self._read(service, self._services)

    def _read(
        self, subscription: Subscription[M], kept: list[Subscription[Any]]
    ) -> Subscription[M]:
        """``subscription`` kept in ``kept``, its reader announced and waited on while spinning."""
        self._check_types_every_second()
        self.reader_guids.append(subscription.reader.guid.bytes)
        if self._announce is not None:
            self._announce()
        self._waitset.attach(ReadCondition(subscription.reader, SampleState.Any))
        kept.append(subscription)
        return subscription

    def _check_types_every_second(self) -> None:
        """Start the timer of :meth:`check_types` with the node's first reader."""
        if not self._checking:
            self._checking = True
            self.create_timer(1.0, self.check_types)

    def create_timer(self, period: float, callback: Callable[[], None]) -> Timer:
        """A timer calling ``callback`` every ``period`` seconds (monotonic) while spinning."""
        if not (math.isfinite(period) and period > 0.0):
            raise LiveError(f"a timer period must be positive and finite, got {period!r}")
        timer = Timer(period, callback, time.monotonic() + period)
        self._timers.append(timer)
        return timer

    def announce(self, distro: str | None = None) -> None:
        """Publish this node on ``ros_discovery_info`` as a ROS 2 node does, so that
        ``ros2 node list`` names it: its name, the root namespace and the GUIDs of its readers
        and writers, again whenever it makes another. ``distro`` (``ROS_DISTRO`` when None)
        picks the layout of the GIDs: 24 bytes up to Humble, 16 since Iron and when unset."""
        from diffbot.live import types

        info_type, node_type, gid_type = types.discovery_types(
            distro or os.environ.get("ROS_DISTRO", "")
        )
        size = len(gid_type().data)

        def gid(guid: bytes) -> Any:
            return gid_type(data=guid.ljust(size, b"\0")[:size])

        writer = DataWriter(
            self.participant,
            Topic(self.participant, DISCOVERY_TOPIC, info_type),
            LATCHED.qos(),
        )

        def publish() -> None:
            entry = node_type(
                node_namespace="/",
                node_name=self.name,
                reader_gid_seq=[gid(guid) for guid in self.reader_guids],
                writer_gid_seq=[gid(guid) for guid in self.writer_guids],
            )
            writer.write(
                info_type(gid=gid(self.participant.guid.bytes), node_entities_info_seq=[entry])
            )

        self._announce = publish
        publish()

    def check_types(self) -> None:
        """Warn once for each type another publisher sends on a topic this node reads than the
        ones it reads there (such a publisher never matches, so nothing would arrive from it)."""
        from diffbot.live.types import ros_type_name

        read: dict[str, set[str]] = {}
        for subscription in self._subscriptions:
            topic = self.resolve(subscription.topic)
            read.setdefault(topic, set()).add(subscription.type_name)
        found_types: list[tuple[str, str, set[str]]] = [
            (topic, found, ours)
            for topic, ours in read.items()
            for found in sorted(self.publisher_types(topic) - ours)
        ]
        for service in self._services:
            name = self.resolve(service.topic)
            request = f"rq/{name.lstrip('/')}Request"
            ours = {service.type_name}
            for found in sorted(set(self.publications(name, request)) - ours):
                found_types.append((name, found, ours))
        for topic, found, ours in found_types:
            message = self.type_mismatch(
                topic, ros_type_name(found), sorted(ros_type_name(t) for t in ours)
            )
            if message not in self.warnings:
                self.warnings.append(message)
                self.warn(message)

    def type_mismatch(self, topic: str, found: str, ours: list[str]) -> str:
        """The warning when ``topic`` carries ``found`` (a ROS type name) where this node reads
        ``ours``; nodes with an option that changes what they read say which."""
        return f"{topic!r} carries {found}; this node reads {' or '.join(ours)}"

    def publications(self, topic: str, dds_name: str | None = None) -> list[str]:
        """The DDS type name of each publisher on ``topic`` (or on the DDS topic ``dds_name``,
        such as a service's request topic) discovered so far, this node's own included (other
        types than ours too: how a node tells a TwistStamped topic from a Twist one, or sees a
        second publisher)."""
        if self._publications is None:
            self._publications = BuiltinDataReader(self.participant, BuiltinTopicDcpsPublication)
        dds_name = dds_topic(self.resolve(topic)) if dds_name is None else dds_name
        alive = InstanceState.Alive
        return [
            sample.type_name
            for sample in self._publications.read(N=4096)
            if sample.topic_name == dds_name and sample.sample_info.instance_state == alive
        ]

    def publisher_types(self, topic: str) -> set[str]:
        """The DDS type names of the publishers on ``topic`` discovered so far."""
        return set(self.publications(topic))

    def spin_once(self, timeout: float = 0.0) -> None:
        """Handle what is waiting: messages to the callbacks, timers that are due; wait at
        most ``timeout`` seconds (less when a timer comes due first) if nothing is."""
        now = time.monotonic()
        deadline = now + max(timeout, 0.0)
        for timer in self._timers:
            deadline = min(deadline, timer.due)
        wait = min(max(deadline - now, 0.0), _WAIT_SLICE)
        if wait > 0.0:
            self._waitset.wait(int(wait * 1e9))
        for subscription in (*self._subscriptions, *self._services):
            while subscription.take() >= 256:
                pass
        now = time.monotonic()
        for timer in self._timers:
            timer.fire_if_due(now)

    def spin(self, duration: float | None = None) -> None:
        """Run until :meth:`shutdown`, a signal or ``duration`` seconds.

        In the main thread SIGINT, SIGTERM and SIGHUP only wake the node while it spins
        (:mod:`diffbot.live.signals`): the loop ends cleanly between two steps, and the signal
        is then handed to the handler installed before (KeyboardInterrupt, or the SystemExit
        of the command line's SIGTERM and SIGHUP, raised to the caller), unless an enclosing
        :func:`~diffbot.live.signals.deferred` block takes it.
        """
        end = math.inf if duration is None else time.monotonic() + duration
        with deferred(self.wake):
            while not self._stop.is_set() and caught() is None:
                left = end - time.monotonic()
                if left <= 0.0:
                    break
                self.spin_once(min(left, _WAIT_SLICE))
            if not self._stop.is_set():
                self._wake.set(False)  # woken by a signal: the next spin waits again

    def wake(self) -> None:
        """Wake a wait in :meth:`spin_once` at once (safe from a signal handler)."""
        self._wake.set(True)

    def describe(self) -> str:
        """The topics this node reads and publishes, with their ROS types, and the services it
        serves: one line for people, as the commands print it at the start."""
        from diffbot.live.types import ros_type_name

        def listed(endpoints: list[tuple[str, str]]) -> str:
            types: dict[str, list[str]] = {}
            for topic, type_name in endpoints:
                named = types.setdefault(self.resolve(topic), [])
                if ros_type_name(type_name) not in named:
                    named.append(ros_type_name(type_name))
            return ", ".join(f"{topic} ({' or '.join(named)})" for topic, named in types.items())

        parts: list[str] = []
        if self._subscriptions:
            parts.append(f"reads {listed([(s.topic, s.type_name) for s in self._subscriptions])}")
        if self._published:
            parts.append(f"publishes {listed(self._published)}")
        if self._services:
            parts.append("serves " + ", ".join(self.resolve(s.topic) for s in self._services))
        return "; ".join(parts) or "no topics"

    def status(self) -> str:
        """One line of what the node counted, for people (nodes that count say more)."""
        return f"{len(self._subscriptions)} subscriptions"

    @property
    def malformed(self) -> int:
        """Payloads its subscriptions received that did not decode, dropped."""
        return sum(s.malformed for s in self._subscriptions)

    def start(self: N) -> N:
        """Spin in a background thread (for notebooks and tests) until :meth:`shutdown`."""
        self._thread = threading.Thread(target=self.spin, name=f"diffbot-{self.name}", daemon=True)
        self._thread.start()
        return self

    def shutdown(self) -> None:
        """Stop spinning (from any thread) and wait for a background spin to end."""
        self._stop.set()
        with contextlib.suppress(DDSException):  # the participant is already gone
            self._wake.set(True)
        if self._thread is not None and self._thread is not threading.current_thread():
            self._thread.join(timeout=5.0)
            self._thread = None

    def destroy_node(self) -> None:
        """Stop and delete the node's DDS entities (its participant and all it holds)."""
        if self._destroyed:
            return
        self.shutdown()
        self._destroyed = True
        for subscription in self._subscriptions:
            _ = subscription.dropped  # kept for the status once the reader is gone
        self._subscriptions.clear()
        self._services.clear()
        self._timers.clear()
        self._publications = None
        self._topics.clear()
        leave(self.participant)

    def __enter__(self: N) -> N:
        return self

    def __exit__(self, *exc: object) -> None:
        self.destroy_node()
