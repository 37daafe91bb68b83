"""DDS the way ROS 2 speaks it, in one module: the only one that imports cyclonedds.

What makes diffbot's endpoints match a stock ROS 2 node's (rmw_cyclonedds, rmw_fastrtps):

- topic ``/name`` is the DDS topic ``rt/name`` (:func:`dds_topic`); types are named
  ``pkg::msg::dds_::Name_`` (:mod:`diffbot.live.types`);
- plain CDR (XCDR1) forced in every endpoint's QoS (a Cyclone endpoint of a ``final`` type would
  otherwise also offer XCDR2);
- QoS profiles as rclpy names them: :data:`PUBLISHER` (reliable, volatile, keep last 10),
  :data:`TF` (depth 100), :data:`LATCHED` (transient local: ``/tf_static``,
  ``/robot_description``), :data:`SUBSCRIPTION` (best effort, which matches reliable and
  best-effort publishers alike);
- ``ROS_DOMAIN_ID`` picks the domain (0..232); ``ROS_LOCALHOST_ONLY=1`` or
  ``ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST`` keep discovery and traffic on the loopback
  interface (unicast to the local peers, no multicast), ``OFF`` keeps it in the process, as
  rmw_cyclonedds does (:func:`cyclone_config`).

A :class:`Node` has rclpy's shape: it makes publishers, subscriptions and timers, :meth:`Node.spin`
runs it until a signal (or a deadline), and it is a context manager that destroys its entities on
the way out. Received payloads are decoded one by one: a malformed one is counted in
:attr:`Subscription.malformed` and dropped, never raised.
"""

from __future__ import annotations

import contextlib
import math
import os
import threading
import time
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any, Final, Generic, TypeVar

from diffbot.errors import DiffbotError

#: What the live commands say when cyclonedds is not installed.
INSTALL_HINT: Final = (
    "the live commands need cyclonedds (DDS for Python): pip install 'diffbot-kinematics[live]'"
)


class LiveError(DiffbotError):
    """A live node cannot start: no cyclonedds, a bad domain id or topic, no peer in time."""


try:
    from cyclonedds._clayer import (  # type: ignore[import-not-found]
        ddspy_take,
        ddspy_write,
    )
    from cyclonedds.builtin import BuiltinDataReader, BuiltinTopicDcpsPublication
    from cyclonedds.core import (
        DDSException,
        GuardCondition,
        InstanceState,
        ReadCondition,
        SampleState,
        ViewState,
        WaitSet,
    )
    from cyclonedds.domain import Domain, DomainParticipant
    from cyclonedds.idl import IdlStruct
    from cyclonedds.idl.annotations import final
    from cyclonedds.idl.types import (
        array,
        bounded_str,
        float64,
        int32,
        sequence,
        uint8,
        uint32,
    )
    from cyclonedds.pub import DataWriter
    from cyclonedds.qos import Policy, Qos
    from cyclonedds.sub import DataReader
    from cyclonedds.topic import Topic
except ImportError as err:  # pragma: no cover - exercised in a subprocess without it
    raise LiveError(INSTALL_HINT) from err

__all__ = [
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
    "array",
    "bounded_str",
    "cyclone_config",
    "dds_topic",
    "discovery_range",
    "domain_id",
    "final",
    "float64",
    "int32",
    "sequence",
    "uint8",
    "uint32",
]

#: The DDS topic (no ``rt/`` prefix) where ROS 2 participants list their nodes.
DISCOVERY_TOPIC: Final = "ros_discovery_info"
#: The highest domain id ROS 2 allows (the RTPS port formula overflows above it).
MAX_DOMAIN_ID: Final = 232
#: The longest a wait blocks in C: signals are handled between waits.
_WAIT_SLICE: Final = 0.05

M = TypeVar("M", bound=IdlStruct)
N = TypeVar("N", bound="Node")


@dataclass(frozen=True)
class QosProfile:
    """A QoS profile as rclpy spells it: reliability, durability and history depth."""

    reliable: bool = True
    transient_local: bool = False
    depth: int = 10
    #: Keep every sample up to ``depth`` waiting ones and refuse the newer ones, counted (a
    #: reader's :attr:`Subscription.dropped`), instead of silently overwriting the oldest.
    drop_newest: bool = False

    def qos(self) -> Qos:
        """The cyclonedds QoS, with plain CDR (XCDR1) forced as ROS 2 expects."""
        reliability = (
            Policy.Reliability.Reliable(max_blocking_time=100_000_000)
            if self.reliable
            else Policy.Reliability.BestEffort
        )
        durability = (
            Policy.Durability.TransientLocal if self.transient_local else Policy.Durability.Volatile
        )
        representation = Policy.DataRepresentation(use_cdrv0_representation=True)
        if self.drop_newest:
            return Qos(
                reliability,
                durability,
                Policy.History.KeepAll,
                Policy.ResourceLimits(
                    max_samples=self.depth, max_instances=-1, max_samples_per_instance=self.depth
                ),
                representation,
            )
        return Qos(
            reliability, durability, Policy.History.KeepLast(depth=self.depth), representation
        )


#: rclpy's default publisher profile: reliable, volatile, keep last 10.
PUBLISHER: Final = QosProfile()
#: /tf as tf2_ros' TransformBroadcaster publishes it: depth 100.
TF: Final = QosProfile(depth=100)
#: /tf_static and /robot_description: late joiners still get the last message.
LATCHED: Final = QosProfile(transient_local=True, depth=1)
#: Subscriptions: best effort matches reliable and best-effort (sensor data) publishers.
SUBSCRIPTION: Final = QosProfile(reliable=False)


def domain_id(environ: Mapping[str, str] | None = None) -> int:
    """The domain of ``ROS_DOMAIN_ID`` (0 when unset or empty).

    Raises:
        LiveError: not a whole number in 0..232.
    """
    env = os.environ if environ is None else environ
    text = env.get("ROS_DOMAIN_ID", "").strip()
    if not text:
        return 0
    try:
        value = int(text)
    except ValueError:
        value = -1
    if not 0 <= value <= MAX_DOMAIN_ID:
        raise LiveError(
            f"ROS_DOMAIN_ID must be a whole number from 0 to {MAX_DOMAIN_ID}, got {text!r}"
        )
    return value


def discovery_range(environ: Mapping[str, str] | None = None) -> str:
    """How far discovery reaches: ``SUBNET`` (Cyclone's default), ``LOCALHOST`` or ``OFF``.

    ``ROS_AUTOMATIC_DISCOVERY_RANGE`` (Iron and later) decides when set; else
    ``ROS_LOCALHOST_ONLY=1`` (Humble) means ``LOCALHOST``.

    Raises:
        LiveError: an unknown range.
    """
    env = os.environ if environ is None else environ
    text = env.get("ROS_AUTOMATIC_DISCOVERY_RANGE", "").strip().upper()
    if text in ("", "SYSTEM_DEFAULT"):
        return "LOCALHOST" if env.get("ROS_LOCALHOST_ONLY", "").strip() == "1" else "SUBNET"
    if text not in ("SUBNET", "LOCALHOST", "OFF"):
        raise LiveError(
            "ROS_AUTOMATIC_DISCOVERY_RANGE must be SUBNET, LOCALHOST, OFF or SYSTEM_DEFAULT, "
            f"got {text!r}"
        )
    return text


def cyclone_config(reach: str, user_config: str = "") -> str:
    """The Cyclone DDS configuration of a discovery range, after the user's own
    (``CYCLONEDDS_URI``), so that ours wins where both set something.

    ``LOCALHOST``: the loopback interface only, no multicast, the local participants found by
    unicast (``Peers``: localhost, participant indices assigned automatically). ``OFF``: the same
    without peers, so only this process's participants meet. ``SUBNET``: the user's
    configuration alone (empty: Cyclone's defaults, multicast discovery on the default interface).
    """
    if reach == "SUBNET":
        return user_config
    peers = (
        "<Peers><Peer address='localhost'/></Peers>"
        "<ParticipantIndex>auto</ParticipantIndex>"
        "<MaxAutoParticipantIndex>64</MaxAutoParticipantIndex>"
        if reach == "LOCALHOST"
        else ""
    )
    ours = (
        "<CycloneDDS><Domain Id='any'><General>"
        "<Interfaces><NetworkInterface name='lo'/></Interfaces>"
        "<AllowMulticast>false</AllowMulticast></General>"
        f"<Discovery>{peers}</Discovery></Domain></CycloneDDS>"
    )
    return f"{user_config},{ours}" if user_config else ours


def dds_topic(name: str) -> str:
    """The DDS topic of a ROS topic in the root namespace: ``/odom`` and ``odom`` ->
    ``rt/odom``."""
    return "rt/" + name.lstrip("/")


#: The domains this process created, by id: Cyclone takes one configuration per domain.
_DOMAINS: dict[int, Any] = {}
_DOMAINS_LOCK = threading.Lock()


def _participant(domain: int | None) -> DomainParticipant:
    """A participant on ``domain`` (``ROS_DOMAIN_ID`` when None), the domain configured from
    the environment on first use."""
    env = os.environ
    ident = domain_id() if domain is None else domain
    if not 0 <= ident <= MAX_DOMAIN_ID:
        raise LiveError(f"the domain id must be from 0 to {MAX_DOMAIN_ID}, got {ident}")
    with _DOMAINS_LOCK:
        if ident not in _DOMAINS:
            config = cyclone_config(discovery_range(), env.get("CYCLONEDDS_URI", ""))
            try:
                _DOMAINS[ident] = Domain(ident, config) if config else None
            except DDSException as err:
                raise LiveError(f"cannot start DDS on domain {ident}: {err}") from None
    try:
        return DomainParticipant(ident)
    except DDSException as err:
        raise LiveError(f"cannot join DDS domain {ident}: {err}") from None


class Publisher(Generic[M]):
    """A ROS publisher: :meth:`publish` writes one message."""

    def __init__(self, writer: DataWriter[M], topic: str) -> None:
        self._writer = writer
        #: The ROS topic name.
        self.topic = topic

    def publish(self, message: M) -> None:
        """Send ``message`` to every matched subscription."""
        self._writer.write(message)

    def publish_serialized(self, data: bytes) -> None:
        """Send a message already serialized (encapsulation header and CDR body), as
        :mod:`diffbot.live.cdr` writes the ones a node sends per sample."""
        padding = -len(data) % 4  # as cyclonedds pads its own payloads
        ret = ddspy_write(self._writer._ref, data + b"\0" * padding if padding else data)
        if ret < 0:
            raise LiveError(f"writing {self.topic} failed (DDS error {ret})")

    @property
    def subscription_count(self) -> int:
        """How many subscriptions match this publisher now."""
        return int(self._writer.get_publication_matched_status().current_count)  # type: ignore[no-untyped-call]

    def wait_for_subscribers(self, timeout: float, count: int = 1) -> bool:
        """Wait until ``count`` subscriptions have matched, at most ``timeout`` seconds."""
        return _wait_for(lambda: self.subscription_count >= count, timeout)

    def flush(self, timeout: float) -> bool:
        """Wait until reliable subscriptions acknowledged everything sent, at most ``timeout``
        seconds (before the node goes away, so its last message is not lost)."""
        try:
            return bool(self._writer.wait_for_acks(int(timeout * 1e9)))
        except DDSException:
            return False


@dataclass
class Subscription(Generic[M]):
    """A ROS subscription: ``callback(message)`` for each message a spin takes.

    Attributes:
        topic: the ROS topic name.
        received: messages decoded and handed to the callback.
        malformed: payloads that could not be decoded (truncated, bad lengths), dropped.
    """

    reader: DataReader[M]
    decode: Callable[[bytes], M]
    callback: Callable[[M], None]
    topic: str
    received: int = 0
    malformed: int = 0
    #: The DDS type name this subscription reads.
    type_name: str = ""
    #: :attr:`dropped` when last read.
    last_dropped: int = 0

    @property
    def publisher_count(self) -> int:
        """How many publishers match this subscription now."""
        return int(self.reader.get_subscription_matched_status().current_count)  # type: ignore[no-untyped-call]

    @property
    def dropped(self) -> int:
        """Messages that arrived while the reader's queue was full (a ``drop_newest`` profile)
        or that the network lost, as DDS counts them: never handed to the callback."""
        reader = self.reader
        try:
            rejected = reader.get_sample_rejected_status().total_count  # type: ignore[no-untyped-call]
            lost = reader.get_sample_lost_status().total_count  # type: ignore[no-untyped-call]
        except DDSException:  # the node is gone: the count when it went
            return self.last_dropped
        self.last_dropped = int(rejected) + int(lost)
        return self.last_dropped

    def wait_for_publishers(self, timeout: float, count: int = 1) -> bool:
        """Wait until ``count`` publishers have matched, at most ``timeout`` seconds."""
        return _wait_for(lambda: self.publisher_count >= count, timeout)

    def deliver(self, payloads: Iterable[bytes]) -> None:
        """Decode serialized messages (with their encapsulation header) and hand each to the
        callback; a payload that does not decode is counted in :attr:`malformed`."""
        decode = self.decode
        callback = self.callback
        for data in payloads:
            try:
                message = decode(data)
            except Exception:  # any decoding failure (struct.error, ...) is a malformed payload
                self.malformed += 1
                continue
            self.received += 1
            callback(message)

    def take(self, limit: int = 256) -> int:
        """Decode up to ``limit`` waiting messages and hand each to the callback; the count."""
        mask = SampleState.Any | ViewState.Any | InstanceState.Any
        taken = ddspy_take(self.reader._ref, mask, limit)
        if isinstance(taken, int):
            raise LiveError(f"reading {self.topic} failed (DDS error {taken})")
        self.deliver(data for data, info in taken if info.valid_data)
        return len(taken)


@dataclass
class Timer:
    """Calls ``callback()`` every ``period`` seconds of the monotonic clock while spinning."""

    period: float
    callback: Callable[[], None]
    due: float = field(default=0.0)

    def fire_if_due(self, now: float) -> None:
        if now >= self.due:
            # The next tick stays on the schedule; after a stall it skips missed ticks.
            self.due += self.period * max(1, math.floor((now - self.due) / self.period) + 1)
            self.callback()


class Node:
    """A node on the ROS 2 graph, shaped like rclpy's.

    Args:
        name: the node's name (for people; DDS has no node names).
        domain: the DDS domain; ``ROS_DOMAIN_ID`` when None.

    Raises:
        LiveError: a bad domain id or discovery range, or DDS cannot start.
    """

    def __init__(self, name: str, *, domain: int | None = None) -> None:
        self.name = name
        self.participant = _participant(domain)
        self._waitset = WaitSet(self.participant)
        self._wake = GuardCondition(self.participant)
        self._waitset.attach(self._wake)
        self._topics: dict[tuple[str, str], Topic[Any]] = {}
        self._subscriptions: list[Subscription[Any]] = []
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

    def _topic(self, msg_type: type[M], name: str) -> Topic[M]:
        dds_name = dds_topic(name)
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
        if not self._subscriptions:
            self.create_timer(1.0, self.check_types)
        self.reader_guids.append(reader.guid.bytes)
        if self._announce is not None:
            self._announce()
        self._waitset.attach(ReadCondition(reader, SampleState.Any))
        self._subscriptions.append(subscription)
        return subscription

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
        and writers, again whenever it makes another. ``distro`` (``ROS_DISTRO`` when None,
        else jazzy) picks the layout of the GIDs (24 bytes up to Humble, 16 since Iron)."""
        from diffbot.live import types

        info_type, node_type, gid_type = types.discovery_types(
            distro or os.environ.get("ROS_DISTRO", "") or "jazzy"
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
            topic = "/" + subscription.topic.lstrip("/")
            read.setdefault(topic, set()).add(subscription.type_name)
        for topic, ours in read.items():
            for found in sorted(self.publisher_types(topic) - ours):
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

    def publications(self, topic: str) -> list[str]:
        """The DDS type name of each publisher on ``topic`` discovered so far, this node's own
        included (other types than ours too: how a node tells a TwistStamped topic from a Twist
        one, or sees a second publisher)."""
        if self._publications is None:
            self._publications = BuiltinDataReader(self.participant, BuiltinTopicDcpsPublication)
        dds_name = dds_topic(topic)
        alive = InstanceState.Alive
        return [
            sample.type_name
            for sample in self._publications.read(N=4096)
            if getattr(sample, "topic_name", None) == dds_name
            and sample.sample_info.instance_state == alive
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
        for subscription in self._subscriptions:
            while subscription.take() >= 256:
                pass
        now = time.monotonic()
        for timer in self._timers:
            timer.fire_if_due(now)

    def spin(self, duration: float | None = None) -> None:
        """Run until :meth:`shutdown`, a signal (KeyboardInterrupt, SystemExit from SIGTERM or
        SIGHUP, raised to the caller) or ``duration`` seconds."""
        end = math.inf if duration is None else time.monotonic() + duration
        while not self._stop.is_set():
            left = end - time.monotonic()
            if left <= 0.0:
                return
            self.spin_once(min(left, _WAIT_SLICE))

    def start(self: N) -> N:
        """Spin in a background thread (for notebooks and tests) until :meth:`shutdown`."""
        self._thread = threading.Thread(target=self.spin, name=f"diffbot-{self.name}", daemon=True)
        self._thread.start()
        return self

    def shutdown(self) -> None:
        """Stop spinning (from any thread) and wait for a background spin to end."""
        self._stop.set()
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
        self._timers.clear()
        self._publications = None
        self._topics.clear()
        with contextlib.suppress(DDSException):  # already gone
            self.participant.__del__()

    def __enter__(self: N) -> N:
        return self

    def __exit__(self, *exc: object) -> None:
        self.destroy_node()


def _wait_for(condition: Callable[[], bool], timeout: float) -> bool:
    """Poll ``condition`` until it holds or ``timeout`` seconds pass; whether it held."""
    end = time.monotonic() + timeout
    while True:
        if condition():
            return True
        if time.monotonic() >= end:
            return False
        time.sleep(0.005)
