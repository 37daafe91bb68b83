"""A robot without hardware on a live graph: wheel commands in, joint states and its true pose out.

Each update (``rate`` per second of the monotonic clock) turns every wheel joint by its commanded
velocity times the time since the last update, and publishes:

- ``joint_states``: every moving joint of the description (the wheels at their angles, the others
  at rest), optionally quantised to encoder ticks and with Gaussian noise, stamped now;
- ``ground_truth/odom``: the exact pose, the wheels' true angles integrated along their arcs
  (:class:`diffbot.odometry.Odometry`);
- ``/tf``: the moving joints' transforms (what robot_state_publisher does with joint states).

At start it publishes, transient local, ``/robot_description`` and the fixed joints' transforms
on ``/tf_static``. Commands are the velocity controllers' Float64MultiArray (one value per joint
of a side), or ``cmd_vel`` through the same inverse kinematics as ``node ik``. When commands go
quiet for ``timeout`` seconds the wheels stop.

Given :class:`~diffbot.simulation.Disturbances`, the wheels are those of a
:class:`~diffbot.simulation.DisturbedRobot` stepped on the monotonic clock, the same model
``simulate`` runs: each command message reaches the motors ``latency`` s late, or never (a
``drop`` share), the wheels follow with the first-order ``motor_lag`` and the motor limit, and the
ground moves by the real geometry less the ``slip``; joint states report the angles the wheels
turned.
"""

from __future__ import annotations

import math
import random
import time
from dataclasses import dataclass, field
from typing import Any, cast

from diffbot.calibration.truth import true_robot
from diffbot.kinematics import DiffDriveParams, WheelSpeeds, forward, wheel_from_joint
from diffbot.live import types
from diffbot.live.cdr import (
    OdometryWriter,
    decode_twist,
    decode_twist_stamped,
    encode_joint_state,
    encode_tf,
)
from diffbot.live.messages import now_ns, transform, twist_mismatch, yaw_quaternion
from diffbot.live.names import check_distinct_topics, check_frame_id
from diffbot.live.transport import LATCHED, TF, LiveError, Node, Subscription
from diffbot.live.wire import Refusals, twist_problem, wheel_problem
from diffbot.numbers import MAX_PLAN_DURATION, finite_in_range, shown
from diffbot.odometry import DEFAULT_POSE_COVARIANCE, DEFAULT_TWIST_COVARIANCE, Odometry
from diffbot.ros.messages import covariance_matrix
from diffbot.simulation import Disturbances, DisturbedRobot
from diffbot.urdf.link_frames import MOVING, LinkTransform, description_joints, link_transform
from diffbot.wheel_commands import WheelCommander
from diffbot.wheel_topics import LEFT_TOPIC, RIGHT_TOPIC

__all__ = ["RobotNode", "RobotSettings"]


@dataclass(frozen=True)
class RobotSettings:
    """How the simulated robot listens, moves and reports.

    Attributes:
        rate: updates per second (Hz).
        cmd_vel: read velocity commands from this topic instead of per-side wheel commands.
        stamped: the velocity commands are TwistStamped.
        left_topic: the left side's Float64MultiArray command topic.
        right_topic: the right side's.
        timeout: seconds without a command after which the wheels stop (0: never).
        ticks: encoder counts per revolution of the reported angles (None: exact).
        noise: standard deviation (rad) of Gaussian noise on the reported angles.
        seed: the noise's seed.
        true_radii: the real left and right wheel radii (m) the robot moves by (None: the
            described ones); joint_states still report the angles the wheels turned.
        true_separation: the real wheel separation (m) (None: the described one).
        limit_wheels: run per-side wheel commands through the controller's limiter too, as
            the velocity commands of ``cmd_vel`` always are (when it has limits).
        disturbances: motor lag, latency, drops and slip (seeded by their own ``seed``).
    """

    rate: float = 50.0
    cmd_vel: str | None = None
    stamped: bool = False
    left_topic: str = LEFT_TOPIC
    right_topic: str = RIGHT_TOPIC
    timeout: float = 0.5
    ticks: int | None = None
    noise: float = 0.0
    seed: int | None = None
    true_radii: tuple[float, float] | None = None
    true_separation: float | None = None
    limit_wheels: bool = False
    disturbances: Disturbances = field(default_factory=Disturbances)


class RobotNode(Node):
    """A simulated differential-drive robot.

    Args:
        params: the robot (radii, separation, wheel joints, signs).
        description: its URDF text, for ``/robot_description`` and the link transforms (None:
            only the wheel joints are reported, no transforms).
        settings: rate, topics, encoder model.
        domain: the DDS domain (``ROS_DOMAIN_ID`` when None).
        name: the node's name.
    """

    def __init__(
        self,
        params: DiffDriveParams,
        description: str | None = None,
        settings: RobotSettings = RobotSettings(),
        *,
        domain: int | None = None,
        name: str = "diffbot_robot",
    ) -> None:
        finite_in_range(settings.rate, "rate", 1.0 / MAX_PLAN_DURATION, error=LiveError)
        finite_in_range(settings.timeout, "timeout", 0.0, MAX_PLAN_DURATION, error=LiveError)
        self.params = params
        self.settings = settings
        self.left_joints = params.left_joints or (params.left_joint,)
        self.right_joints = params.right_joints or (params.right_joint,)
        wheels = (*self.left_joints, *self.right_joints)
        joints = description_joints(description) if description is not None else []
        self._moving = [j for j in joints if j.type in MOVING]
        self._fixed = [link_transform(j) for j in joints if j.type not in MOVING]
        others = [j.name for j in self._moving if j.name not in wheels]
        self.names = [*wheels, *others]
        # The description's names go into every JointState and /tf message.
        for joint_name in self.names:
            check_frame_id(joint_name, "joint name")
        for joint in joints:
            check_frame_id(joint.parent, f"link of joint {shown(joint.name)}")
            check_frame_id(joint.child, f"link of joint {shown(joint.name)}")
        #: Each wheel joint's true angle (rad) and commanded velocity (rad/s).
        self.positions = dict.fromkeys(self.names, 0.0)
        self.velocities = dict.fromkeys(wheels, 0.0)
        # The pose moves by the real geometry; the wheels turn as commanded.
        real = true_robot(params, settings.true_radii, settings.true_separation)
        self.truth = Odometry(real)
        self._real = real
        #: The disturbed wheels and ground (None: the wheels turn exactly as commanded).
        self.motors = (
            DisturbedRobot(params, settings.disturbances, real)
            if settings.disturbances.any
            else None
        )
        self._start = time.monotonic()
        self._covariances = (
            covariance_matrix(DEFAULT_POSE_COVARIANCE),
            covariance_matrix(DEFAULT_TWIST_COVARIANCE),
        )
        self._ground_truth = OdometryWriter("odom", "base_link", *self._covariances)
        self._random = random.Random(settings.seed)
        self._last_command: float | None = None
        self._last_update: float | None = None
        self.commander = (
            WheelCommander(params)
            if settings.cmd_vel is not None or settings.limit_wheels
            else None
        )
        #: The wheel commands waiting for the limiter (rad/s, by joint), when it takes them.
        self.targets: dict[str, float] | None = (
            dict.fromkeys(wheels, 0.0)
            if settings.cmd_vel is None and self.commander is not None and self.commander.limited
            else None
        )
        self.updates = 0
        self.timeouts = 0
        #: Commands refused (:mod:`diffbot.live.wire`), by reason.
        self.refusals = Refusals()
        if settings.cmd_vel is None:
            sides = [("{left_topic}", settings.left_topic), ("{right_topic}", settings.right_topic)]
            check_distinct_topics(sides, name)
        super().__init__(name, domain=domain)
        self.joint_states = self.create_publisher(types.JointState, "joint_states")
        self.ground_truth = self.create_publisher(types.Odometry, "ground_truth/odom")
        self.tf = self.create_publisher(types.TFMessage, "/tf", TF)
        self.subscriptions: list[Subscription[Any]] = []
        if settings.cmd_vel is not None:
            # Commands are read straight into (linear, angular), not into message objects.
            kind, decode = (
                (types.TwistStamped, decode_twist_stamped)
                if settings.stamped
                else (types.Twist, decode_twist)
            )
            self.subscriptions.append(
                self.create_subscription(
                    kind, settings.cmd_vel, cast(Any, self.on_command), decode=cast(Any, decode)
                )
            )
        else:
            for topic, side in ((settings.left_topic, 0), (settings.right_topic, 1)):
                self.subscriptions.append(
                    self.create_subscription(
                        types.Float64MultiArray,
                        topic,
                        lambda m, side=side: self.on_wheels(side, m.data),  # type: ignore[misc]
                    )
                )
        if description is not None:
            latched = self.create_publisher(types.String, "/robot_description", LATCHED)
            latched.publish(types.String(description))
            static = self.create_publisher(types.TFMessage, "/tf_static", LATCHED)
            stamp = now_ns()
            static.publish(types.TFMessage([_message(t, stamp) for t in self._fixed]))
            self._latched = (latched, static)
        self.create_timer(1.0 / settings.rate, self.update)

    def type_mismatch(self, topic: str, found: str, ours: list[str]) -> str:
        """On a velocity command topic, name the option that reads the other kind of twist."""
        if self.settings.cmd_vel is not None:
            return twist_mismatch(topic, found)
        return super().type_mismatch(topic, found, ours)

    def on_wheels(self, side: int, values: list[float]) -> None:
        """Take one side's joint velocity commands (rad/s), one per joint of the side; refused
        ones (:func:`~diffbot.live.wire.wheel_problem`) stop the side."""
        joints = self.right_joints if side else self.left_joints
        if not self.refusals.check(wheel_problem(values, len(joints))):
            values = [0.0] * len(joints)
        held = self.velocities if self.targets is None else self.targets
        for joint, value in zip(joints, values, strict=True):
            held[joint] = self._saturated(value)
        self._last_command = time.monotonic()
        if self.targets is None:
            self._command_motors()

    def on_twist(self, twist: types.Twist) -> None:
        """Take a velocity command, turned into wheel commands as ``node ik`` does; a refused
        one (:func:`~diffbot.live.wire.twist_problem`) stops the wheels."""
        self.on_command((twist.linear.x, twist.angular.z))

    def on_command(self, command: tuple[float, float]) -> None:
        """Take a velocity command as (linear.x (m/s), angular.z (rad/s)), as :meth:`on_twist`
        does."""
        assert self.commander is not None
        linear, angular = command
        if not self.refusals.check(twist_problem(linear, angular)):
            linear = angular = 0.0
            self.commander.reset()
        out = self.commander.step(linear, angular, 1.0 / self.settings.rate)
        for joints, values in ((self.left_joints, out.left), (self.right_joints, out.right)):
            for joint, value in zip(joints, values, strict=True):
                self.velocities[joint] = value
        self._last_command = time.monotonic()
        self._command_motors()

    def _saturated(self, value: float) -> float:
        """A joint velocity (rad/s) no faster than the motor limit: the wheels never turn
        faster, whatever they are told (the disturbed motors clamp again, at their speeds)."""
        limit = self.params.max_wheel_speed
        return value if limit is None else min(max(value, -limit), limit)

    def _command_motors(self) -> None:
        """Hand the commanded joint velocities, one message's worth, to the disturbed motors
        (each side's mean, as wheel-ground speeds)."""
        motors = self.motors
        if motors is None:
            return
        motors.advance(time.monotonic() - self._start)
        wheels = wheel_from_joint(self.params, WheelSpeeds(*self._side_means(self.velocities)))
        motors.command(float(wheels.left), float(wheels.right))

    def _side_means(self, by_joint: dict[str, float]) -> tuple[float, float]:
        left = sum(by_joint[j] for j in self.left_joints) / len(self.left_joints)
        right = sum(by_joint[j] for j in self.right_joints) / len(self.right_joints)
        return left, right

    @property
    def refused(self) -> int:
        """Commands refused at the boundary."""
        return self.refusals.total

    def update(self) -> None:
        """Move the wheels by their velocities over the time since the last update; publish."""
        now = time.monotonic()
        last, self._last_update = self._last_update, now
        if last is not None and self.motors is None:
            dt = now - last
            for joint, velocity in self.velocities.items():
                self.positions[joint] += velocity * dt
        # The commands held until now; from now on the wheels stop if they have gone quiet.
        timeout = self.settings.timeout
        if self._last_command is not None and timeout > 0.0 and now - self._last_command > timeout:
            self._last_command = None
            if any(self.velocities.values()):
                self.timeouts += 1
            self.velocities = dict.fromkeys(self.velocities, 0.0)
            if self.motors is not None:
                self.motors.halt()
            if self.targets is not None:
                self.targets = dict.fromkeys(self.targets, 0.0)
                assert self.commander is not None
                self.commander.reset()
        if self.targets is not None:
            self._limit_wheels(self.targets)
        stamp = now_ns()
        if self.motors is None:
            left, right = self._side_means(self.positions)
            self.truth.update(left, right, stamp_ns=stamp)
            state = self.truth.state
            velocities = [self.velocities.get(name, 0.0) for name in self.names]
        else:
            state, velocities = self._move_motors(now)
        self.updates += 1
        reported = [self._encoder(self.positions[name]) for name in self.names]
        # Serialized here (diffbot.live.cdr), not field by field by the types' serializer.
        self.joint_states.publish_serialized(
            encode_joint_state(stamp, "", self.names, reported, velocities)
        )
        x, y, heading, linear, angular = state
        q = yaw_quaternion(heading)
        pose = (x, y, 0.0, q.x, q.y, q.z, q.w)
        self.ground_truth.publish_serialized(
            self._ground_truth.odometry(stamp, pose, linear, angular)
        )
        if self._moving:
            moved = [link_transform(j, self.positions.get(j.name, 0.0)) for j in self._moving]
            transforms = [(stamp, t.parent, t.child, (*t.translation, *t.rotation)) for t in moved]
            self.tf.publish_serialized(encode_tf(transforms))

    def _move_motors(
        self, now: float
    ) -> tuple[tuple[float, float, float, float, float], list[float]]:
        """Step the disturbed motors to ``now`` (monotonic s): the wheel joints at their angles;
        the true pose and twist (m, rad, m/s, rad/s) and every joint's velocity (rad/s)."""
        motors = self.motors
        assert motors is not None
        motors.advance(now - self._start)
        p = self.params
        turned = {}
        for joints, sign, side in (
            (self.left_joints, p.left_sign, 0),
            (self.right_joints, p.right_sign, 1),
        ):
            for joint in joints:
                self.positions[joint] = sign * motors.angles[side]
                turned[joint] = sign * motors.speeds[side]
        body = forward(self._real, motors.speeds[0], motors.speeds[1])
        x, y, heading = motors.pose
        state = (x, y, heading, float(body.linear), float(body.angular))
        return state, [turned.get(name, 0.0) for name in self.names]

    def _limit_wheels(self, targets: dict[str, float]) -> None:
        """One limiter update of the wheel commands: each side's mean joint velocity as the
        body velocity it asks for, limited, and back to every joint of the side."""
        assert self.commander is not None
        wheels = wheel_from_joint(self.params, WheelSpeeds(*self._side_means(targets)))
        body = forward(self.params, wheels.left, wheels.right)
        out = self.commander.step(float(body.linear), float(body.angular), 1.0 / self.settings.rate)
        for joints, values in ((self.left_joints, out.left), (self.right_joints, out.right)):
            for joint, value in zip(joints, values, strict=True):
                self.velocities[joint] = value
        self._command_motors()

    def _encoder(self, angle: float) -> float:
        """An angle as the encoder reports it: with noise, then quantised to ticks."""
        if self.settings.noise:
            angle += self._random.gauss(0.0, self.settings.noise)
        ticks = self.settings.ticks
        if ticks:
            step = 2.0 * math.pi / ticks
            angle = round(angle / step) * step
        return angle

    def status(self) -> str:
        """One line of counts for people."""
        received = sum(s.received for s in self.subscriptions)
        return (
            f"{self.updates} updates, {received} commands, {self.refused} refused, "
            f"{self.timeouts} timeouts, {self.malformed} malformed"
        )


def _message(link: LinkTransform, stamp: int) -> types.TransformStamped:
    x, y, z, w = link.rotation
    return transform(stamp, link.parent, link.child, link.translation, types.Quaternion(x, y, z, w))
