"""Wheel odometry: an incremental integrator for streams and a vectorised batch integrator.

Both integrate each step *exactly* along its arc, not with Euler's rule. Over one step the wheels
turn through displacements that give a path length ``ds`` and a heading change ``dθ``; with the
wheel speeds constant over the step the robot moves along a circular arc, whose chord has length
``ds·sinc(dθ/2)`` and points along ``θ + dθ/2``. A path made of constant-velocity segments (a
plan of straights, arcs and spins) is thus reproduced exactly, whatever the sampling rate, as
long as each segment boundary falls on a sample.

Wheel positions are absolute joint angles (rad), as in sensor_msgs/JointState; the description's
direction signs are applied, so a positive wheel-ground angle always rolls the robot forward.
Nothing is lost across a skipped sample: the next good one is integrated from the last good one.
A side with several wheels (a skid steer) counts as one wheel at the mean angle of its wheels, as
diff_drive_controller averages a side's wheel feedback (:meth:`Odometry.update_joint_state`).

The streaming path (:class:`Odometry`) uses plain floats and :mod:`math` only; NumPy is imported by
:func:`integrate` alone.
"""

from __future__ import annotations

import math
import operator
import sys
from collections.abc import Mapping, Sequence
from typing import Final

from diffbot.batch_odometry import PoseSeries, initial_pose, integrate
from diffbot.errors import ParameterError
from diffbot.kinematics import DiffDriveParams, Pose, Twist, norm_angle
from diffbot.numbers import MAX_ROLLING_WINDOW, as_number, shown
from diffbot.ros.messages import (
    Header,
    OdometryMessage,
    PoseWithCovariance,
    Quaternion,
    TransformStamped,
    TwistWithCovariance,
    Vector3,
    covariance_matrix,
)
from diffbot.samples import SKIP_NOT_FINITE
from diffbot.side_angles import MessageSides
from diffbot.velocity_feedback import check_feedback
from diffbot.window_sums import WindowSums

__all__ = [
    "DEFAULT_POSE_COVARIANCE",
    "DEFAULT_TWIST_COVARIANCE",
    "SKIP_MISSING_JOINT",
    "SKIP_NOT_FINITE",
    "SKIP_STAMP_NOT_AFTER",
    "Odometry",
    "PoseSeries",
    "integrate",
]

#: Why a sample was skipped: the sample lacks every wheel joint of a side.
SKIP_MISSING_JOINT: Final = "missing joint"
#: Why a sample was skipped: its stamp is not after the previous used sample's (duplicate, late).
SKIP_STAMP_NOT_AFTER: Final = "stamp not after previous"

#: Diagonal (x, y, z, roll, pitch, yaw) of the pose covariance, as in ros2_controllers'
#: diff_drive_controller example configuration (m², rad²).
DEFAULT_POSE_COVARIANCE: Final = (0.001, 0.001, 0.001, 0.001, 0.001, 0.01)
#: Diagonal of the twist covariance, likewise ((m/s)², (rad/s)²).
DEFAULT_TWIST_COVARIANCE: Final = (0.001, 0.001, 0.001, 0.001, 0.001, 0.01)


# A node builds a message for every JointState: building the records with tuple.__new__ skips
# the Python-level __new__ of each NamedTuple and halves the cost of message().
_new = tuple.__new__
_sin = math.sin
_cos = math.cos
_remainder = math.remainder
_PI: Final = math.pi
_TWO_PI: Final = 2.0 * math.pi
#: Stamps in ns are ROS times: they fit in a signed 64-bit integer.
_INT64: Final = 2**63
#: The shortest step (s) a displacement is divided by: the smallest normal float. A step
#: shorter than it (a subnormal, such as 5e-324 s) is too small to compute with (as
#: :func:`diffbot.numbers.positive_finite` refuses it), and the velocity over it overflows to
#: infinity: it is skipped as a stamp not after the previous one. (ros2_controllers'
#: diff_drive_controller likewise skips an update whose period is too short to integrate.)
_SHORTEST_STEP: Final = sys.float_info.min


class Odometry:
    """Dead reckoning from the wheel joint positions of a differential-drive robot.

    Feed it samples of absolute wheel joint angles (rad) with increasing stamps, through
    :meth:`update` or :meth:`update_joint_state`: in seconds (``stamp``, a float) or, for ROS
    times since the epoch, in integer nanoseconds (``stamp_ns``), as a float near 1.7e9 s
    resolves only 0.24 µs and velocities over short steps suffer from it. The first usable
    sample sets the encoder baseline and does not move the robot. Every later one moves the pose
    exactly along the arc the wheels describe since the previous used sample.

    A sample is skipped, counted in :attr:`skipped` under its reason and otherwise ignored when it
    lacks every wheel joint of a side, holds a NaN or infinite value, or is not stamped after the
    previous used sample (a float stamp after it by less than the smallest normal float, about
    2.2e-308 s, counts as not after it: no velocity can be divided by such a step). Wheel
    positions are absolute, so the motion during skipped samples is still accounted for by the
    next used one.

    The velocity (:attr:`twist`) is the displacement over the time of the last
    ``velocity_rolling_window_size`` steps: with the default 1, over the last step alone; with
    more, a step whose stamp comes a moment after the previous one (a tiny gap, which would make
    the one-step estimate spike) weighs only as much as its time.

    Example::

        odom = Odometry(params)
        stamp = msg.header.stamp
        odom.update_joint_state(msg.name, msg.position, stamp_ns=stamp.sec * 10**9 + stamp.nanosec)
        odom.pose  # Pose(x, y, theta)

    Args:
        params: the robot (radius, separation, joint names, direction signs).
        x: initial x (m) in the odom frame, within ±:data:`~diffbot.numbers.MAX_COORDINATE`.
        y: initial y (m), likewise.
        theta: initial heading (rad), within ±:data:`~diffbot.numbers.MAX_RECORDED_ANGLE`.
        frame_id: the fixed frame of the pose (REP-105 ``odom``).
        child_frame_id: the robot's frame (``base_link``).
        pose_covariance: diagonal of the pose covariance (x, y, z, roll, pitch, yaw).
        twist_covariance: diagonal of the twist covariance.
        velocity_rolling_window_size: how many of the last steps the velocity estimate spans
            (diff_drive_controller's parameter of that name); 1 = the last step alone.
        feedback: ``"position"`` (samples are wheel angles) or ``"velocity"``: samples are
            wheel velocities (rad/s; a JointState's ``velocity``), each held over the step
            that ends at its sample, as diff_drive_controller's ``update_from_vel`` moves by
            velocity times the period since the last update (``position_feedback: false``).

    Raises:
        ParameterError: an initial pose that is no number, not finite or out of its range, a bad
            covariance diagonal, a window size that is not a whole number >= 1, or an unknown
            ``feedback``.
    """

    def __init__(
        self,
        params: DiffDriveParams,
        x: float = 0.0,
        y: float = 0.0,
        theta: float = 0.0,
        *,
        frame_id: str = "odom",
        child_frame_id: str = "base_link",
        pose_covariance: Sequence[float] = DEFAULT_POSE_COVARIANCE,
        twist_covariance: Sequence[float] = DEFAULT_TWIST_COVARIANCE,
        velocity_rolling_window_size: int = 1,
        feedback: str = "position",
    ) -> None:
        self.params = params
        #: What the samples are: ``position`` or ``velocity``.
        self.feedback = check_feedback(feedback)
        # Velocities are integrated into the wheel angles _left/_right before each step.
        self._velocity = feedback == "velocity"
        self.frame_id = frame_id
        self.child_frame_id = child_frame_id
        self.pose_covariance = covariance_matrix(pose_covariance, "pose_covariance")
        self.twist_covariance = covariance_matrix(twist_covariance, "twist_covariance")
        # Attributes read per message stay few (at most 30 in all): CPython keeps an instance's
        # attributes in a fast inline layout only up to that many.
        several = len(params.left_joints) > 1 or len(params.right_joints) > 1
        #: Where a message's names put each side's joints (sides of several wheels only).
        self._sides = MessageSides(params.left_joints, params.right_joints) if several else None
        #: The last steps' (ds, dθ, dt), when the velocity spans more than one step.
        window = _window_size(velocity_rolling_window_size)
        self._steps = WindowSums(window) if window > 1 else None
        left_radius, right_radius = params.radii
        self._left_scale = params.left_sign * left_radius
        self._right_scale = params.right_sign * right_radius
        self._turn = 1.0 / params.wheel_separation
        self._half_turn = 0.5 / params.wheel_separation
        self._names: list[str] | tuple[str, ...] | None = None
        self._left_index = -1
        self._right_index = -1
        self._samples = 0
        self._skipped: dict[str, int] = {}
        self._left = self._right = 0.0
        self._stamp: float | None = None
        self._stamp_ns: int | None = None
        self.reset(x, y, theta)

    def reset(
        self, x: float = 0.0, y: float = 0.0, theta: float = 0.0, *, new_baseline: bool = False
    ) -> None:
        """Put the robot at a pose, keeping the encoder baseline.

        The pose, twist (and its window) and distance start afresh; the next sample moves the
        robot from this pose by the wheel motion since the last used sample, so no step is lost
        (as diff_drive_controller's ``set_odometry``). Before the first sample, the first sample
        still sets the baseline. The sample counters keep counting.

        Args:
            x: x (m) in the odom frame.
            y: y (m).
            theta: heading (rad).
            new_baseline: forget the last sample instead: the next sample sets a new baseline
                and may carry any stamp (to replay a recording again from its start); a side
                of several wheels learns its encoders' offsets afresh.

        Raises:
            ParameterError: a value that is no number, NaN, infinite or out of its range (see
                :class:`Odometry`).
        """
        x, y, theta = initial_pose(x, y, theta, ("x", "y", "theta"))
        self._x = x
        self._y = y
        self._heading = theta
        self._linear = 0.0
        self._angular = 0.0
        self._distance = 0.0
        self._heading0 = theta
        self._left0 = self._left
        self._right0 = self._right
        if new_baseline:
            self._stamp = None
            self._stamp_ns = None
            if self._sides is not None:  # the encoders' offsets are the old baseline's too
                self._sides = MessageSides(self.params.left_joints, self.params.right_joints)
        if self._steps is not None:
            self._steps.clear()

    def update(
        self,
        left_position: float,
        right_position: float,
        stamp: float | None = None,
        *,
        stamp_ns: int | None = None,
    ) -> bool:
        """Integrate one sample of absolute wheel joint angles.

        Give the time either as ``stamp`` (s, a float) or as ``stamp_ns`` (integer ns, as in
        builtin_interfaces/Time: ``sec * 10**9 + nanosec``). A float near the epoch
        (1.7e9 s) resolves only 0.24 µs, so the steps between stamps made as
        ``sec + nanosec * 1e-9`` are off by up to that much: at 1 kHz the velocity is off by up
        to 2e-4 relative. With ``stamp_ns`` each step is the exact integer difference of two
        stamps, converted to seconds once. Both forms may be mixed; a step from a float stamp
        is taken in floats. (Stamps relative to the start of a recording, as floats, keep full
        precision too.)

        Args:
            left_position: the left wheel joint's angle (rad), as the joint reports it.
            right_position: the right wheel joint's angle (rad).
            stamp: the sample's time (s).
            stamp_ns: the sample's time (ns), instead of ``stamp``.

        Returns:
            True when the sample was used (the first one only sets the baseline), False when it
            was skipped (NaN or infinite value, or a stamp not after the previous used one).

        Raises:
            ParameterError: neither or both of ``stamp`` and ``stamp_ns`` given, a
                ``stamp_ns`` that is not an integer, or a position or ``stamp`` that is no
                number (NaN and infinities are numbers: the sample is skipped).
        """
        # Floats, the usual samples, pass as they are; anything else is read as a number once.
        left = left_position
        if type(left) is not float:
            left = as_number(left, "left_position")
        right = right_position
        if type(right) is not float:
            right = as_number(right, "right_position")
        if stamp_ns is None:
            if stamp is None:
                raise ParameterError("give the sample's time: stamp (s) or stamp_ns (ns)")
            if type(stamp) is not float:
                stamp = as_number(stamp, "stamp")
        else:
            stamp_ns = self._check_stamp_ns(stamp, stamp_ns)
            if stamp_ns is None:
                return False
            stamp = stamp_ns / 1_000_000_000
        # x - x is 0.0 for every finite x and NaN for NaN and the infinities: one test for three.
        if (left - left) + (right - right) + (stamp - stamp) != 0.0:
            self._skip(SKIP_NOT_FINITE)
            return False
        last = self._stamp
        if last is None:
            if self._velocity:  # the first velocity only starts the clock
                left, right = self._left, self._right
            self._left0 = self._left = left
            self._right0 = self._right = right
            self._heading0 = self._heading
            self._stamp = stamp
            self._stamp_ns = stamp_ns
            self._samples += 1
            return True
        if stamp_ns is not None and self._stamp_ns is not None:
            if stamp_ns <= self._stamp_ns:
                self._skip(SKIP_STAMP_NOT_AFTER)
                return False
            dt = (stamp_ns - self._stamp_ns) / 1_000_000_000  # exact, then rounded once
        else:
            # stamp - last is > 0 exactly when stamp > last (subtraction underflows gradually)
            dt = stamp - last
            if dt < _SHORTEST_STEP:
                self._skip(SKIP_STAMP_NOT_AFTER)
                return False
        if self._velocity:
            left = self._left + left * dt
            right = self._right + right * dt
        # The same formulas as integrate(), so both agree to the last bit wherever math and NumPy
        # agree on sin and cos. The heading is linear in the wheel angles, so it is computed from
        # the angles travelled since the baseline rather than summed step by step: its rounding
        # error then stays at a few ulps of those angles instead of growing with every sample.
        dl = (left - self._left) * self._left_scale
        dr = (right - self._right) * self._right_scale
        ds = (dl + dr) * 0.5
        half = (dr - dl) * self._half_turn
        # ds * sinc(half), inline: see kinematics.sinc
        chord = ds * (_sin(half) / half if half != 0.0 else 1.0)
        along = self._heading + half
        self._x += chord * _cos(along)
        self._y += chord * _sin(along)
        self._heading = (
            (right - self._right0) * self._right_scale - (left - self._left0) * self._left_scale
        ) * self._turn + self._heading0
        self._distance += abs(ds)
        if self._steps is None:
            self._linear = ds / dt
            self._angular = 2.0 * half / dt
        else:
            self._average(ds, 2.0 * half, dt)
        self._left = left
        self._right = right
        self._stamp = stamp
        self._stamp_ns = stamp_ns
        self._samples += 1
        return True

    def _average(self, ds: float, turn: float, dt: float) -> None:
        """Velocity over the window: the sums of its displacements over the sum of its times."""
        steps = self._steps
        assert steps is not None
        distance, heading, time = steps.push((ds, turn, dt))
        self._linear = distance / time
        self._angular = heading / time

    def _check_stamp_ns(self, stamp: float | None, stamp_ns: int) -> int | None:
        """``stamp_ns`` as an int, or None (the sample skipped) when it is outside int64."""
        if stamp is not None:
            raise ParameterError("give the sample's time once: stamp (s) or stamp_ns (ns)")
        try:
            value = operator.index(stamp_ns)
        except TypeError:
            raise ParameterError(
                f"stamp_ns must be an integer number of nanoseconds, got {stamp_ns!r}"
            ) from None
        if not -_INT64 <= value < _INT64:
            self._skip(SKIP_NOT_FINITE)
            return None
        return value

    def update_joint_state(
        self,
        names: Sequence[str],
        positions: Sequence[float],
        stamp: float | None = None,
        *,
        stamp_ns: int | None = None,
        velocities: Sequence[float] | None = None,
    ) -> bool:
        """Integrate one sensor_msgs/JointState message.

        The wheel joints are found by name, in any order, among any other joints. The lookup is
        cached, so a stream whose messages list the same names costs one list comparison.

        A side with several joints (``params.left_joints``, ``params.right_joints``) is the
        mean of their positions, and moves by the motion of those the message holds when it
        lacks some (:mod:`diffbot.side_angles`: each joint less its encoder's offset, added one
        by one in the order of ``params.left_joints``, the sum divided by their count, in
        float64; velocities are averaged as they are). A joint holds a position when its name is
        in ``names`` (its first occurrence) and ``positions`` reaches its index. The sample is
        skipped as ``missing joint`` only when no joint of a side holds one; a NaN or infinite
        position of any present joint skips it as ``not finite``. With one joint per side the
        side is that joint's position, unchanged.

        Args:
            names: the message's ``name`` field.
            positions: its ``position`` field (rad), parallel to ``names``.
            stamp: its header stamp (s); near the epoch a float loses precision (see
                :meth:`update`), so prefer ``stamp_ns``.
            stamp_ns: its header stamp in integer ns (``sec * 10**9 + nanosec``), instead of
                ``stamp``.
            velocities: its ``velocity`` field (rad/s): read instead of ``positions`` when
                the feedback is velocity (and needed then).

        Returns:
            True when the sample was used, False when it was skipped (every joint of a side
            missing or without a position, a NaN or infinite value, a stamp not after the
            previous one).

        Raises:
            ParameterError: neither or both of ``stamp`` and ``stamp_ns`` given, a
                ``stamp_ns`` that is not an integer, or no ``velocities`` with velocity feedback.
        """
        if self._velocity:
            if velocities is None:
                raise ParameterError("feedback='velocity' reads the message's velocities=")
            positions = velocities
        # Sides of several wheels leave this cache empty and take the branch on a miss: the
        # two-wheel path, a node's per-message call, pays for no test of its own.
        cached = self._names
        if names is not cached:
            if type(names) is not list and type(names) is not tuple:
                names = list(names)
            if names != cached:
                if self._sides is not None:
                    return self._update_sides(self._sides, names, positions, stamp, stamp_ns)
                try:
                    left_index = names.index(self.params.left_joint)
                    right_index = names.index(self.params.right_joint)
                except ValueError:
                    self._skip(SKIP_MISSING_JOINT)
                    return False
                # A list may be changed in place after this call: keep a copy to compare with.
                self._names = names if type(names) is tuple else list(names)
                self._left_index = left_index
                self._right_index = right_index
        try:
            left = positions[self._left_index]
            right = positions[self._right_index]
        except IndexError:
            self._skip(SKIP_MISSING_JOINT)
            return False
        if stamp_ns is None:
            return self.update(left, right, stamp)
        return self.update(left, right, stamp, stamp_ns=stamp_ns)

    def _update_sides(
        self,
        sides: MessageSides,
        names: Sequence[str],
        positions: Sequence[float],
        stamp: float | None,
        stamp_ns: int | None,
    ) -> bool:
        """update_joint_state for sides of several wheels (:class:`MessageSides`)."""
        found = sides.values(names, positions, angles=not self._velocity)
        if found is None:
            self._skip(SKIP_MISSING_JOINT)
            return False
        left, right = found
        if stamp_ns is None:
            return self.update(left, right, stamp)
        return self.update(left, right, stamp, stamp_ns=stamp_ns)

    @property
    def velocity_rolling_window_size(self) -> int:
        """How many of the last steps the velocity estimate spans."""
        return 1 if self._steps is None else self._steps.size

    def _skip(self, reason: str) -> None:
        self._skipped[reason] = self._skipped.get(reason, 0) + 1

    @property
    def pose(self) -> Pose:
        """The pose in the odom frame: x, y (m) and theta (rad) in (-pi, pi]."""
        return Pose(self._x, self._y, norm_angle(self._heading))

    @property
    def heading(self) -> float:
        """The unwrapped heading (rad): counts whole turns, unlike ``pose.theta``."""
        return self._heading

    @property
    def twist(self) -> Twist:
        """Body velocity over the last step: linear (m/s) and angular (rad/s); zero before one."""
        return Twist(self._linear, self._angular)

    @property
    def distance(self) -> float:
        """Path length travelled (m): the sum of |ds| over all steps, so reversing adds to it."""
        return self._distance

    @property
    def stamp(self) -> float | None:
        """Stamp (s) of the last used sample, or None before the first."""
        return self._stamp

    @property
    def stamp_ns(self) -> int | None:
        """Stamp (ns) of the last used sample when it was given as ``stamp_ns``, else None."""
        return self._stamp_ns

    @property
    def samples(self) -> int:
        """How many samples were used, the baseline included."""
        return self._samples

    @property
    def state(self) -> tuple[float, float, float, float, float]:
        """x, y (m), the unwrapped heading (rad), linear (m/s) and angular (rad/s) velocity.

        The whole pose and twist in one read, for loops over millions of samples.
        """
        return (self._x, self._y, self._heading, self._linear, self._angular)

    @property
    def skipped(self) -> Mapping[str, int]:
        """How many samples were skipped, by reason (see the ``SKIP_*`` constants)."""
        return dict(self._skipped)

    def _orientation(self) -> Quaternion:
        # remainder() maps the heading exactly to [-pi, pi]; -pi is reported as pi (norm_angle).
        heading = _remainder(self._heading, _TWO_PI)
        half = 0.5 * heading if heading != -_PI else 0.5 * _PI
        return _new(Quaternion, (0.0, 0.0, _sin(half), _cos(half)))

    def transform(self) -> TransformStamped:
        """The odom -> base_link transform (as published on /tf), stamped with the last sample."""
        stamp = self._stamp
        return _new(
            TransformStamped,
            (
                _new(Header, (stamp if stamp is not None else 0.0, self.frame_id)),
                self.child_frame_id,
                _new(Vector3, (self._x, self._y, 0.0)),
                self._orientation(),
            ),
        )

    def message(self) -> OdometryMessage:
        """A nav_msgs/Odometry record of the pose and twist, stamped with the last used sample.

        The records are immutable, so the covariance matrices are shared between messages.
        """
        # Built inline (no helper calls): a node calls this for every JointState it receives.
        heading = _remainder(self._heading, _TWO_PI)
        half = 0.5 * heading if heading != -_PI else 0.5 * _PI
        stamp = self._stamp
        return _new(
            OdometryMessage,
            (
                _new(Header, (stamp if stamp is not None else 0.0, self.frame_id)),
                self.child_frame_id,
                _new(
                    PoseWithCovariance,
                    (
                        _new(Vector3, (self._x, self._y, 0.0)),
                        _new(Quaternion, (0.0, 0.0, _sin(half), _cos(half))),
                        self.pose_covariance,
                    ),
                ),
                _new(
                    TwistWithCovariance,
                    (
                        _new(Vector3, (self._linear, 0.0, 0.0)),
                        _new(Vector3, (0.0, 0.0, self._angular)),
                        self.twist_covariance,
                    ),
                ),
            ),
        )


def _window_size(value: int) -> int:
    """``value`` as a window size (a whole number >= 1), or ParameterError."""
    try:
        size = operator.index(value)
    except TypeError:
        size = 0
    if isinstance(value, bool) or not 1 <= size <= MAX_ROLLING_WINDOW:
        raise ParameterError(
            "velocity_rolling_window_size must be a whole number from 1 to "
            f"{MAX_ROLLING_WINDOW:,}, got {shown(value)}"
        )
    return size
