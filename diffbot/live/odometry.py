"""The odometry node: sensor_msgs/JointState in, nav_msgs/Odometry and odom -> base_link out.

What diff_drive_controller publishes from its wheel feedback, computed by
:class:`diffbot.odometry.Odometry` (exact along each step's arc): each joint state moves the pose
by its wheels' motion since the last used one, stamped with the joint state's own header stamp.
The motion is read from the wheels' positions or, with velocity feedback (the controller's
``position_feedback: false``), from their velocities held over the time since the last one.
A sample with mismatched ``name``/``position`` lengths, a NaN or an angle out of range, a stamp
ahead of this machine's clock (:mod:`diffbot.live.wire`), without a wheel joint or going back in
time is skipped and counted (:attr:`OdometryNode.counts`), never read as zero.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any, cast

from diffbot.controller_config import ControllerConfig
from diffbot.kinematics import DiffDriveParams
from diffbot.live import types
from diffbot.live.cdr import JointStateReader, OdometryWriter
from diffbot.live.names import check_frame_id
from diffbot.live.transport import SUBSCRIPTION, TF, LiveError, Node
from diffbot.live.wire import Refusals, joint_state_problem, planar_pose_problem
from diffbot.numbers import MAX_COORDINATE, MAX_PLAN_DURATION, MAX_RECORDED_ANGLE, finite_in_range
from diffbot.odometry import DEFAULT_POSE_COVARIANCE, DEFAULT_TWIST_COVARIANCE, Odometry
from diffbot.ros.messages import covariance_matrix
from diffbot.velocity_feedback import FEEDBACKS

__all__ = [
    "JOINT_STATES",
    "SKIP_DROPPED",
    "SKIP_MISMATCHED",
    "SKIP_NO_VELOCITY",
    "OdometryNode",
    "OdometrySettings",
]

#: Why a joint state was skipped: its name and position (velocity) arrays differ in length.
SKIP_MISMATCHED = "mismatched lengths"
#: Why a joint state was skipped with velocity feedback: it holds no velocities at all.
SKIP_NO_VELOCITY = "no velocities"
#: The reason of joint states dropped unread, the node behind a flood (or lost on the way).
SKIP_DROPPED = "dropped while behind"
#: The joint-state subscription: best effort, a queue deep enough for bursts at kHz rates;
#: what comes while it is full is dropped and counted (memory stays bounded).
JOINT_STATES = replace(SUBSCRIPTION, depth=100, drop_newest=True)

#: The feedback a controller's ``position_feedback`` gives (None: not said).
_FEEDBACK_OF: dict[bool | None, str] = {False: "velocity", True: "position"}


@dataclass(frozen=True)
class OdometrySettings:
    """What the node publishes, where, and how often.

    Attributes:
        joint_states: the JointState topic it reads.
        odom_topic: the Odometry topic it writes.
        publish_tf: whether it also broadcasts odom -> base_link on /tf.
        frame_id: the odometry frame (REP-105 ``odom``).
        child_frame_id: the robot's frame.
        publish_rate: at most this many odometry messages per second of joint-state stamps
            (Hz); None: one per joint state used.
        pose_covariance: diagonal of the pose covariance (m², rad²).
        twist_covariance: diagonal of the twist covariance ((m/s)², (rad/s)²).
        window: velocity rolling window (steps).
        services: the name the odometry services are under (``/<services>/set_odometry``,
            ``/<services>/reset_odometry``): the controller's name when a controllers file
            names one, else the node's (None).
        feedback: ``"position"`` (the joint states' wheel positions) or ``"velocity"`` (their
            wheel velocities, as diff_drive_controller with ``position_feedback: false``).
    """

    joint_states: str = "joint_states"
    odom_topic: str = "odom"
    publish_tf: bool = True
    frame_id: str = "odom"
    child_frame_id: str = "base_link"
    publish_rate: float | None = None
    pose_covariance: tuple[float, ...] = DEFAULT_POSE_COVARIANCE
    twist_covariance: tuple[float, ...] = DEFAULT_TWIST_COVARIANCE
    window: int = 1
    services: str | None = None
    feedback: str = "position"

    def with_controller(
        self, controller: ControllerConfig | None, **given: Any
    ) -> OdometrySettings:
        """These settings with the controller configuration's, then the ``given`` ones (options
        the user typed: they win).

        The controller's are those its file sets and, where it leaves them out, the
        controller's own defaults (its ``~/odom`` topic under its node's name, its prefixed
        ``odom`` and ``base_link`` frames, zero covariances, a window of 10 steps); only
        ``publish_rate``, whose default differs between releases, stays one message per joint
        state when the file does not set it."""
        values: dict[str, Any] = {}
        if controller is not None:
            found = {
                "odom_topic": controller.odom_topic,
                "frame_id": controller.odom_frame,
                "child_frame_id": controller.base_frame,
                "publish_rate": controller.publish_rate,
                "publish_tf": controller.enable_odom_tf,
                "pose_covariance": controller.pose_covariance,
                "twist_covariance": controller.twist_covariance,
                "window": controller.rolling_window,
                "services": controller.node_name,
                "feedback": _FEEDBACK_OF.get(controller.position_feedback),
            }
            values = {k: v for k, v in found.items() if v is not None}
        values.update({k: v for k, v in given.items() if v is not None})
        return replace(self, **values)


class OdometryNode(Node):
    """Odometry from joint states on a live graph.

    Example::

        with OdometryNode(load_params()) as node:
            node.spin(10.0)
            print(node.odometry.pose, node.counts)

    Args:
        params: the robot (radii, separation, wheel joints, direction signs).
        settings: topics, frames, rate, covariances, window.
        domain: the DDS domain (``ROS_DOMAIN_ID`` when None).
        name: the node's name.
    """

    def __init__(
        self,
        params: DiffDriveParams,
        settings: OdometrySettings = OdometrySettings(),
        *,
        domain: int | None = None,
        name: str = "diffbot_odometry",
    ) -> None:
        if settings.publish_rate is not None:
            finite_in_range(
                settings.publish_rate, "publish_rate", 1.0 / MAX_PLAN_DURATION, error=LiveError
            )
        check_frame_id(settings.frame_id, "frame_id")
        check_frame_id(settings.child_frame_id, "child_frame_id")
        if settings.feedback not in FEEDBACKS:
            raise LiveError(f"feedback must be 'position' or 'velocity', got {settings.feedback!r}")
        self.settings = settings
        self._velocity = settings.feedback == "velocity"
        self.odometry = Odometry(
            params,
            feedback=settings.feedback,
            frame_id=settings.frame_id,
            child_frame_id=settings.child_frame_id,
            pose_covariance=settings.pose_covariance,
            twist_covariance=settings.twist_covariance,
            velocity_rolling_window_size=settings.window,
        )
        self._writer = OdometryWriter(
            settings.frame_id,
            settings.child_frame_id,
            covariance_matrix(settings.pose_covariance),
            covariance_matrix(settings.twist_covariance),
        )
        self._period_ns = 0 if settings.publish_rate is None else round(1e9 / settings.publish_rate)
        self._last_published: int | None = None
        self.mismatched = 0
        #: Joint states refused at the boundary (:mod:`diffbot.live.wire`), by reason.
        self.refusals = Refusals()
        #: Odometry messages published.
        self.published = 0
        super().__init__(name, domain=domain)
        self.odom_publisher = self.create_publisher(types.Odometry, settings.odom_topic)
        self.tf_publisher = (
            self.create_publisher(types.TFMessage, "/tf", TF) if settings.publish_tf else None
        )
        self._subscribe(params)
        base = "/" + (settings.services or self.name).strip("/")
        #: The services' names: diff_drive_controller's ``~/set_odometry``, and a reset.
        self.set_service = f"{base}/set_odometry"
        self.reset_service = f"{base}/reset_odometry"
        self.create_service(
            types.SetOdometryRequest, types.SetOdometryResponse, self.set_service, self.on_set
        )
        self.create_service(
            types.EmptyRequest, types.EmptyResponse, self.reset_service, self.on_reset
        )
        #: Service calls answered, by service name.
        self.calls: dict[str, int] = {}

    def _subscribe(self, params: DiffDriveParams) -> None:
        """Subscribe what moves the odometry: the joint states."""
        # Payloads are read into plain tuples (:class:`JointStateReader`), not messages: no
        # message object is made per sample.
        self.subscription = self.create_subscription(
            types.JointState,
            self.settings.joint_states,
            cast(Any, self._on_sample),
            JOINT_STATES,
            cast(Any, JointStateReader(self.settings.feedback).read),
        )

    def on_set(self, request: types.SetOdometryRequest) -> types.SetOdometryResponse:
        """control_msgs/srv/SetOdometry: put the odometry at (x, y, yaw), keeping the wheels'
        baseline as diff_drive_controller's ``set_odometry`` does (z, roll and pitch, which a
        planar odometry has not, are ignored as there). A value that is not finite, or beyond
        the range of poses and angles the node takes (:mod:`diffbot.live.wire`), is refused."""
        self.calls[self.set_service] = self.calls.get(self.set_service, 0) + 1
        problem = planar_pose_problem(request.x, request.y, request.yaw)
        if problem is not None:
            return types.SetOdometryResponse(
                success=False,
                message=f"x, y and yaw must be finite numbers within {MAX_COORDINATE:g} m and "
                f"{MAX_RECORDED_ANGLE:g} rad ({problem})",
            )
        self.odometry.reset(request.x, request.y, request.yaw)
        return types.SetOdometryResponse(success=True, message="Odometry set request accepted")

    def on_reset(self, request: types.EmptyRequest) -> types.EmptyResponse:
        """std_srvs/srv/Empty: put the odometry back at the origin (the wheels' baseline
        kept)."""
        self.calls[self.reset_service] = self.calls.get(self.reset_service, 0) + 1
        self.odometry.reset()
        return types.EmptyResponse()

    def on_joint_state(self, message: types.JointState) -> None:
        """Integrate one joint state and publish the odometry it gives (at most at the rate)."""
        when = message.header.stamp
        values = message.velocity if self._velocity else message.position
        self._use(when.sec, when.nanosec, message.name, values)

    def _on_sample(self, sample: tuple[int, int, Sequence[str], Sequence[float]]) -> None:
        self._use(*sample)

    def _use(self, sec: int, nanosec: int, names: Sequence[str], values: Sequence[float]) -> None:
        # values: the wheel positions (rad), or with velocity feedback the velocities (rad/s).
        velocity = self._velocity
        if len(values) != len(names):
            if velocity and not values:
                self.refusals.check(SKIP_NO_VELOCITY)
            else:
                self.mismatched += 1
            return
        if not self.refusals.check(joint_state_problem(sec, nanosec, values, velocity=velocity)):
            return
        stamp = sec * 1_000_000_000 + nanosec
        if velocity:
            used = self.odometry.update_joint_state(names, (), stamp_ns=stamp, velocities=values)
        else:
            used = self.odometry.update_joint_state(names, values, stamp_ns=stamp)
        if not used:
            return
        last = self._last_published
        period = self._period_ns
        if last is not None and stamp - last < period:
            return
        # The publish time advances by the period, as the controller's does, so that stamps a
        # little early or late keep the rate; after a gap of more than a period it starts afresh.
        if last is not None and stamp - last < 2 * period:
            self._last_published = last + period
        else:
            self._last_published = stamp
        self.publish(stamp)

    def publish(self, stamp: int) -> None:
        """Publish the current odometry (and transform) stamped ``stamp`` (ns)."""
        x, y, heading, linear, angular = self.odometry.state
        # The heading wrapped first so that w >= 0, as messages.yaw_quaternion does.
        half = 0.5 * math.remainder(heading, 2.0 * math.pi)
        pose = (x, y, 0.0, 0.0, 0.0, math.sin(half), math.cos(half))
        self.odom_publisher.publish_serialized(self._writer.odometry(stamp, pose, linear, angular))
        self.published += 1
        if self.tf_publisher is not None:
            self.tf_publisher.publish_serialized(self._writer.tf(stamp, pose))

    @property
    def counts(self) -> dict[str, int]:
        """Joint states received, used, published, and skipped by reason (malformed payloads,
        mismatched lengths and :class:`~diffbot.odometry.Odometry`'s reasons)."""
        skipped = dict(self.refusals.counts)
        for reason, n in self.odometry.skipped.items():
            skipped[reason] = skipped.get(reason, 0) + n
        if self.mismatched:
            skipped[SKIP_MISMATCHED] = self.mismatched
        if self.subscription.malformed:
            skipped["malformed"] = self.subscription.malformed
        dropped = self.subscription.dropped
        if dropped:
            skipped[SKIP_DROPPED] = dropped
        return {
            "received": self.subscription.received + self.subscription.malformed,
            "used": self.odometry.samples,
            "published": self.published,
            **skipped,
        }

    def describe(self) -> str:
        """:meth:`Node.describe`, then the frames of the odometry (``odom -> base_link``, the
        controller's prefixed ones with a controllers file): what a tf tree must hold."""
        frames = f"{self.settings.frame_id} -> {self.settings.child_frame_id}"
        return f"{super().describe()}; frames {frames}"

    def status(self) -> str:
        """One line of counts for people: ``1200 joint states, 1198 used, 1198 published;
        skipped: 2 not finite``."""
        counts = self.counts
        line = self._tally(counts)
        if counts:
            line += "; skipped: " + ", ".join(f"{n} {reason}" for reason, n in counts.items())
        return line

    def _tally(self, counts: dict[str, int]) -> str:
        """The status line's head, taking its counts out of ``counts`` (the skips remain)."""
        return (
            f"{counts.pop('received')} joint states, {counts.pop('used')} used, "
            f"{counts.pop('published')} published"
        )
