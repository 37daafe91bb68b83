"""Following a plan live: the robot's pose in, a :class:`diffbot.follow.Follower`'s commands out.

:class:`FollowDriver` subscribes the pose (nav_msgs/Odometry, geometry_msgs/PoseStamped or
PoseWithCovarianceStamped), and at ``rate`` commands per second of the monotonic clock (each at
``start + k / rate``, never ``previous + period``) publishes the follower's Twist (or
TwistStamped) for the latest pose. The plan starts where the robot is: the first pose received
is the plan's origin, later poses are taken relative to it.

The robot is commanded zero:

- while the pose is stale (none received for ``pose_timeout`` s); the follower takes over again
  when poses come back;
- at the end: the follower done, or the time cap (the plan's duration plus the longer of 10 s and
  the duration itself, as :func:`diffbot.closed_loop.run` gives up; up to
  :data:`~diffbot.closed_loop.SETTLE_GRACE` s more for a follower waiting out its dwell);
- on Ctrl-C, SIGTERM or SIGHUP: a signal only wakes the loop (:mod:`diffbot.live.signals`),
  which stops between two commands.

Every pose passes :func:`diffbot.live.wire.pose_problem` before the follower sees it; refused
ones are counted and skipped.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Final, Literal

from diffbot.closed_loop import SETTLE_GRACE
from diffbot.kinematics import Pose, Twist
from diffbot.live import types
from diffbot.live.errors import LiveError
from diffbot.live.messages import now_ns, time_of, twist_command, yaw_of
from diffbot.live.names import check_distinct_topics, check_frame_id
from diffbot.live.signals import caught, deferred
from diffbot.live.transport import Node, Publisher
from diffbot.live.wire import Refusals, pose_problem
from diffbot.numbers import MAX_PLAN_DURATION, finite_in_range

if TYPE_CHECKING:
    from diffbot.follow import Follower

__all__ = ["FollowDriver", "FollowReport", "FollowSettings", "PoseKind"]

#: What the pose topic carries.
PoseKind = Literal["odometry", "pose", "pose-covariance"]
#: Longest a run goes on past the plan's end waiting to arrive (s), at least.
MIN_OVERTIME: Final = 10.0
#: The message type of each kind of pose topic.
_KINDS: Final[dict[PoseKind, type[Any]]] = {
    "odometry": types.Odometry,
    "pose": types.PoseStamped,
    "pose-covariance": types.PoseWithCovarianceStamped,
}
#: Longest single wait on the wait set (s): short enough to stay on schedule.
_WAIT_SLICE: Final = 0.05


@dataclass(frozen=True)
class FollowSettings:
    """Where the pose comes from and where the commands go.

    Attributes:
        rate: commands per second (Hz).
        pose_topic: the pose's topic.
        pose_kind: its message type: ``odometry`` (nav_msgs/Odometry), ``pose``
            (geometry_msgs/PoseStamped) or ``pose-covariance`` (PoseWithCovarianceStamped);
            None: the type its publisher sends, found while waiting for it.
        pose_timeout: seconds without a pose after which the robot is commanded zero.
        cmd_vel: the velocity command topic.
        stamped: send geometry_msgs/TwistStamped (stamped now, in ``frame_id``).
        frame_id: the frame of stamped commands.
        overtime: how long past the plan's end the run waits to arrive, at least (s; the
            plan's duration when longer).
    """

    rate: float = 20.0
    pose_topic: str = "odom"
    pose_kind: PoseKind | None = "odometry"
    pose_timeout: float = 0.5
    cmd_vel: str = "cmd_vel"
    stamped: bool = False
    frame_id: str = "base_link"
    overtime: float = MIN_OVERTIME

    def __post_init__(self) -> None:
        finite_in_range(self.rate, "rate", 1.0 / MAX_PLAN_DURATION, 1e4, unit="Hz", error=LiveError)
        finite_in_range(
            self.pose_timeout,
            "pose_timeout",
            0.0,
            MAX_PLAN_DURATION,
            open_low=True,
            unit="s",
            error=LiveError,
        )
        if self.pose_kind not in (None, *_KINDS):
            raise LiveError(
                f"pose_kind must be odometry, pose or pose-covariance, got {self.pose_kind!r}"
            )
        check_frame_id(self.frame_id, "frame_id")
        finite_in_range(
            self.overtime, "overtime", 0.0, MAX_PLAN_DURATION, unit="s", error=LiveError
        )


@dataclass(frozen=True)
class FollowReport:
    """How a followed drive went.

    Attributes:
        sent: commands published (the final zero not counted), the stale zeros among them.
        stale: commands that were zero because the pose was stale.
        arrived: the follower said done.
        completed: the run ended by itself (arrived or the time cap), not by a signal.
        duration: seconds from the first command to the end.
        position_error: the last pose's distance from the plan's end (m).
        heading_error: its heading's from the plan's end (rad, wrapped, absolute).
        refused: poses refused at the wire boundary.
    """

    sent: int
    stale: int
    arrived: bool
    completed: bool
    duration: float
    position_error: float
    heading_error: float
    refused: int


class FollowDriver(Node):
    """Follows a plan live from a pose topic.

    Example::

        with FollowDriver(Follower(params, made), FollowSettings()) as driver:
            if driver.wait_until_ready(5.0):
                report = driver.follow()

    Args:
        follower: the plan's follower.
        settings: rate, topics and the pose's staleness.
        domain: the DDS domain (``ROS_DOMAIN_ID`` when None).
        name: the node's name.
    """

    def __init__(
        self,
        follower: Follower,
        settings: FollowSettings = FollowSettings(),
        *,
        domain: int | None = None,
        name: str = "diffbot_follow",
    ) -> None:
        self.follower = follower
        self.settings = settings
        duration = follower.duration
        #: When the run gives up arriving (s after its start).
        self.cap = duration + max(settings.overtime, duration)
        #: The latest pose relative to the first (None before one came) and when it came
        #: (monotonic s).
        self.pose: Pose | None = None
        self.received_at = -math.inf
        self._origin: tuple[float, float, float] | None = None
        self.refusals = Refusals()
        pose = ("the pose topic", settings.pose_topic)
        check_distinct_topics([pose, ("the command topic", settings.cmd_vel)], name)
        super().__init__(name, domain=domain)
        self._twist: Publisher[types.Twist] | None = None
        self._stamped: Publisher[types.TwistStamped] | None = None
        if settings.stamped:
            self._stamped = self.create_publisher(types.TwistStamped, settings.cmd_vel)
        else:
            self._twist = self.create_publisher(types.Twist, settings.cmd_vel)
        #: What the pose topic carries (None until found on the graph, when not given).
        self.pose_kind: PoseKind | None = None
        if settings.pose_kind is not None:
            self._subscribe(settings.pose_kind)

    def _subscribe(self, kind: PoseKind) -> None:
        topic = self.settings.pose_topic
        if kind == "odometry":
            self.create_subscription(
                types.Odometry, topic, lambda m: self.on_pose(m.header, m.pose.pose)
            )
        elif kind == "pose":
            self.create_subscription(
                types.PoseStamped, topic, lambda m: self.on_pose(m.header, m.pose)
            )
        else:
            self.create_subscription(
                types.PoseWithCovarianceStamped,
                topic,
                lambda m: self.on_pose(m.header, m.pose.pose),
            )
        self.pose_kind = kind

    def _find_pose_kind(self) -> None:
        """Subscribe the pose topic by the type its publisher sends, once one is seen."""
        found = set(self.publications(self.settings.pose_topic))
        for kind, cls in _KINDS.items():
            if cls.__idl_typename__ in found:
                self._subscribe(kind)
                return

    def on_pose(self, header: types.Header, pose: types.Pose) -> None:
        """Take a pose (refused ones, :func:`~diffbot.live.wire.pose_problem`, are counted and
        skipped); the first one is the plan's origin."""
        p, q = pose.position, pose.orientation
        problem = pose_problem(
            header.stamp.sec, header.stamp.nanosec, (p.x, p.y, p.z), (q.x, q.y, q.z, q.w)
        )
        if not self.refusals.check(problem):
            return
        heading = yaw_of(q)
        if self._origin is None:
            self._origin = (p.x, p.y, heading)
        x0, y0, h0 = self._origin
        c, s = math.cos(h0), math.sin(h0)
        dx, dy = p.x - x0, p.y - y0
        self.pose = Pose(c * dx + s * dy, -s * dx + c * dy, math.remainder(heading - h0, math.tau))
        self.received_at = time.monotonic()

    @property
    def command_count(self) -> int:
        """Subscribers matched on the command topic."""
        publisher = self._stamped if self._stamped is not None else self._twist
        assert publisher is not None
        return publisher.subscription_count

    def wait_until_ready(self, timeout: float) -> bool:
        """Whether, within ``timeout`` seconds, a pose came and the command topic has a
        subscriber (False at once when a signal came)."""
        end = time.monotonic() + timeout
        while True:
            if self.pose_kind is None:
                self._find_pose_kind()
            if self.pose is not None and self.command_count > 0:
                return True
            if time.monotonic() >= end or caught() is not None:
                return False
            self.spin_once(min(end - time.monotonic(), _WAIT_SLICE))

    def send(self, twist: Twist) -> None:
        """Publish one command (m/s, rad/s)."""
        command = twist_command(float(twist.linear), float(twist.angular))
        if self._stamped is not None:
            header = types.Header(time_of(now_ns()), self.settings.frame_id)
            self._stamped.publish(types.TwistStamped(header, command))
        elif self._twist is not None:
            self._twist.publish(command)

    def stop(self) -> None:
        """Command zero."""
        self.send(Twist(0.0, 0.0))

    def follow(self, progress: Callable[[float, float], None] | None = None) -> FollowReport:
        """Command the robot at the rate until done, the time cap or a signal, then zero (the
        signal is handed on after the stop, unless an enclosing
        :func:`~diffbot.live.signals.deferred` block takes it). ``progress(t, error)`` after
        each command: the time (s) and the distance from the plan's reference (m; from its
        end past it)."""
        period = 1.0 / self.settings.rate
        sent = stale = 0
        arrived = False
        self._wake.set(False)
        start = time.monotonic()
        t = 0.0
        with deferred(self.wake):
            try:
                k = 0
                while caught() is None:
                    due = start + k * period
                    while caught() is None and time.monotonic() < due:
                        self.spin_once(min(due - time.monotonic(), _WAIT_SLICE))
                    self.spin_once(0.0)  # the latest pose
                    if caught() is not None:
                        break
                    now = time.monotonic()
                    t = now - start
                    pose = self.pose
                    if pose is None or now - self.received_at > self.settings.pose_timeout:
                        self.stop()
                        self.follower.stopped_at(t)
                        stale += 1
                    else:
                        if self.follower.done(t, pose):
                            arrived = True
                            break
                        self.send(self.follower.command(t, pose))
                        if progress is not None:
                            progress(t, self._error(t, pose))
                    sent += 1
                    # past the cap, a follower waiting out its dwell may still say done
                    settling = self.follower.settling and t < self.cap + SETTLE_GRACE
                    if t >= self.cap and not settling:
                        break
                    k += 1
            finally:
                self.stop()
                for publisher in (self._twist, self._stamped):
                    if publisher is not None:
                        publisher.flush(1.0)
            completed = caught() is None
        last = self.pose or Pose(0.0, 0.0, 0.0)
        goal = self.follower.goal
        return FollowReport(
            sent=sent,
            stale=stale,
            arrived=arrived,
            completed=completed,
            duration=t,
            position_error=math.hypot(last.x - goal.x, last.y - goal.y),
            heading_error=abs(math.remainder(last.theta - self.follower.goal_heading, math.tau)),
            refused=self.refusals.total,
        )

    def _error(self, t: float, pose: Pose) -> float:
        """The distance (m) from the timed reference (tracking) or the goal (pure pursuit,
        which has no schedule)."""
        if self.follower.law == "tracking":
            x, y = self.follower.reference(t)[:2]
        else:
            x, y = self.follower.goal.x, self.follower.goal.y
        return math.hypot(pose.x - x, pose.y - y)

    def status(self) -> str:
        """One line of counts for people."""
        return f"{self.refusals.total} poses refused, {self.malformed} malformed"
