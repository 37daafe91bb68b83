"""Closing the loop: a plan and a pose estimate in, a velocity command out.

:class:`Follower` drives a robot along a plan from its pose estimate (odometry, or an external
pose source), with one of two published control laws:

``tracking`` (default): trajectory tracking of the timed plan. The reference pose
``(x_r, y_r, theta_r)`` and velocity ``(v_r, w_r)`` at time ``t`` come from the plan in closed
form (the same poses :func:`diffbot.trajectory.pose_at` and :meth:`RampedPlan.pose_at` give). The
error in the robot frame is::

    e_x =  cos(theta) (x_r - x) + sin(theta) (y_r - y)
    e_y = -sin(theta) (x_r - x) + cos(theta) (y_r - y)
    e_theta = wrap(theta_r - theta)

and the command is the nonlinear law of Kanayama, Kimura, Miyazaki and Noguchi, "A stable
tracking control method for an autonomous mobile robot", IEEE ICRA 1990, pp. 384-389::

    v = v_r cos(e_theta) + k_x e_x
    w = w_r + v_r k_y e_y + k(v_r) sin(e_theta)
    k(v_r) = |v_r| k_theta + k_spin max(0, 1 - |v_r| k_theta / k_spin)²

With ``V = (e_x² + e_y²)/2 + (1 - cos e_theta)/k_y`` its derivative along the error dynamics is
``-k_x e_x² - k(v_r) sin²(e_theta)/k_y <= 0`` for every sign of ``v_r`` whenever ``k_x, k_y,
k_theta > 0`` and ``k(v_r) >= 0``: the law is stable, and asymptotically so while the
reference keeps moving (``v_r`` or ``w_r`` not tending to zero). Two departures from the paper,
both within that proof: the heading gain multiplies ``|v_r|`` instead of ``v_r``, so reversing
segments keep their sign of correction (the paper's law turns the wrong way when ``v_r < 0``),
and ``k_spin`` corrects the heading where ``v_r`` is 0 (spins in place), fading out as the
speed grows (a heading gain above ``2 v_r sqrt(k_y)`` over-damps the lateral error: at speed
``k_theta = 2/l`` with ``k_y = 1/l²`` is critical damping).
No division by ``v_r`` appears anywhere. On the reference the errors are zero and the command
is the feed-forward ``(v_r, w_r)`` exactly (while the integral below is zero).

Integral (tracking): wheels of unequal radii turn the robot on every straight, a curvature
``beta`` (1/m) times the speed (``beta = delta / b`` for radii ``delta`` apart as a share of
the radius); the law above holds that turn off at a lateral offset ``beta / k_y``. The law
adds ``v_r xi`` to ``w``, a curvature learnt from the lateral error over the distance
travelled, ``d xi/dt = k_i k_y |v_r| e_y``. Linearised about the reference, the lateral error
over the distance ``s`` then obeys ``e''' + k_theta e'' + k_y e' + k_i k_y e = 0``, stable
(Routh-Hurwitz) for ``0 <= k_i < k_theta``, with no offset left: ``xi`` tends to ``beta``.
With the default gains its roots are ``-1.42/l`` and ``(-0.29 ± 0.30j)/l`` (damping 0.69).
Anti-windup: ``|xi| <= MAX_MISMATCH / b``, and ``xi`` is held while the command is cut by the
motor limit and while ``|k_y e_y|`` exceeds that bound (an error no mismatch it may learn
explains is a transient); bounded, it is a bounded disturbance of the law above. The same
mismatch moves a turning robot, ``v - beta b²/4 w`` for ``v``: the law adds ``xi b²/4 w`` to
``v``, so a spin stays in place. The lead's prediction (below) moves the pose by what the robot
is then expected to do, ``w - xi v``.

Lead (tracking): a robot acts on a command late, ``L`` s after it is sent and through wheels
that follow a changing command a first-order lag ``tau`` behind, so the law above corrects an
error the robot has already moved on from. With ``lead`` > 0 the law is a Smith predictor: the
commands sent in the last ``lead`` s, not yet carried out, each held until the next, move the
pose by their arcs, and the law acts on that predicted pose against the reference pose and
velocity at ``t + lead``. ``v_r(t + L) + tau dv_r/dt`` (the feed-forward a lagged wheel needs)
is ``v_r(t + L + tau)`` to first order, its bounded form where the plan's speed steps; a command
held for a control period ``T`` acts on average ``T/2`` after it is sent: :func:`delay_lead` gives
``L + tau + T/2``. Past the plan's end the prediction is used until the commands sent while the
plan ran are carried out (``t < end + lead``); the arrival's millimetre corrections then act on
the pose as given, where a prediction misled by a lost command is worse than none. With
``lead = 0`` the law is the one above, exactly.

``pure-pursuit``: untimed path following, the regulated pure pursuit of Macenski, Singh,
Martin and Gines, "Regulated pure pursuit for robot path tracking", Autonomous Robots 47,
2023 (the Nav2 controller). The plan's straights and arcs are cut into legs driven in one
direction (a spin or a change of direction starts a new leg, reached by turning in place); on
a leg the robot steers along the circle through the lookahead point ``(x_l, y_l)`` (robot
frame, at the lookahead distance ``L`` along the path): curvature ``kappa = 2 y_l / (x_l² +
y_l²)``, ``w = v kappa`` (the same formula holds driving backwards with ``v < 0``). The speed
is the plan's own along the leg, regulated: times ``r / r_min`` on curves tighter than
``r_min`` (``r = 1/|kappa|``), and times ``d / d_approach`` within ``d_approach`` of the
leg's end (never below a creep speed); when the lookahead point lies more than 45 degrees off
the robot's heading it first turns in place toward it. The lookahead point is the first point
past the robot's progress along the leg at the distance ``L`` from it; the progress (the
nearest point) only moves forward along the leg, and a leg is done only once the progress is
within ``L`` of its end, so a loop is driven although it ends where it starts. A spin turns its
signed angle on the robot's heading counted in whole turns (360 degrees is a turn, 270 degrees
is not -90).

Arrival, both laws: Kanayama's law at ``v_r = 0`` corrects ``e_x`` and the heading but not a
lateral error (no command moves the robot sideways), so past the plan's end the follower
stabilises the final pose itself: from when the robot is out of ``xy_tolerance`` with a
lateral error over 0.6 of it until the distance is under 0.4 of it, it turns toward the goal
point (or away from it, to reverse onto it) and drives there (``w = k_spin beta``,
``v = ±k_x d cos beta``, moving only while the bearing error ``beta`` is under 0.3 rad);
otherwise it aligns (``v = k_x e_x``, ``w = k_spin sin e_theta``). The wide hysteresis keeps
a noisy pose source from toggling the two. It is done when past the plan's end (for pure
pursuit: every leg driven and every spin turned) and within ``xy_tolerance`` and
``yaw_tolerance`` for :data:`DWELL` s, or three lead times when longer (a robot that acts on
its commands a lead time late coasts on for about that long: ``--motor-lag 1`` still rolled
3 mm past a one-second dwell); once :meth:`Follower.done` has said so it commands zero (until
the pose leaves the tolerances).

Every command is brought within the motor limit by scaling both wheels by one factor (the
commanded curvature is kept, as :func:`diffbot.kinematics.saturate` does), then, when the
robot's controller configuration gives acceleration or jerk limits (for pure pursuit also a
ramped plan's), through the diff_drive_controller limiter model of :mod:`diffbot.limiter` (both
axes moved the same share of the way, so the curvature stays). The tracking law keeps a ramped
plan's limits through its reference: the ramps use all of them, so the feedback held to them
has no authority left and swings out of control. The arrival and pure pursuit's turns in place
and approach go no faster than the limits can stop within the error left
(:func:`diffbot.arrival.stopping_speed`).
"""

from __future__ import annotations

import bisect
import math
from collections import deque
from collections.abc import Mapping
from dataclasses import dataclass, fields, replace
from typing import TYPE_CHECKING, Final

from diffbot.arrival import Arrival
from diffbot.errors import ParameterError
from diffbot.follow_plan import axis_brakes, axis_limits, body_share, controller_limits, pieces
from diffbot.kinematics import DiffDriveParams, Pose, Twist
from diffbot.numbers import WHEEL_SIZE_RANGE, finite_in_range, positive_finite, shown

if TYPE_CHECKING:
    from diffbot.body_limits import BodyLimits
    from diffbot.ramps import RampedPlan
    from diffbot.trajectory import Plan

__all__ = [
    "DEFAULT_XY_TOLERANCE",
    "DEFAULT_YAW_TOLERANCE",
    "DWELL",
    "LAWS",
    "MAX_LEAD",
    "MAX_MISMATCH",
    "Follower",
    "Gains",
    "default_gains",
    "delay_lead",
]

#: The control laws :class:`Follower` offers.
LAWS: Final = ("tracking", "pure-pursuit")
#: How long (s) the pose must stay within the tolerances before a follower is done.
DWELL: Final = 1.0
#: The longest lead time (s) a tracking follower takes: a robot slower than this to act on its
#: commands is not one a prediction from its commands can steer.
MAX_LEAD: Final = 2.0
#: Distance from the final pose within which a follower is done (m).
DEFAULT_XY_TOLERANCE: Final = 0.005
#: Heading error within which a follower is done (rad): 0.5 degrees.
DEFAULT_YAW_TOLERANCE: Final = math.radians(0.5)
#: The largest difference between the wheels' radii, as a share of the radius, whose turn the
#: tracking law's integral learns: its curvature bias is held within ``MAX_MISMATCH / b``.
MAX_MISMATCH: Final = 0.1

_TWO_PI = 2.0 * math.pi
#: The longest time between two commands (s) the integral counts: a longer gap is a pause.
_LONGEST_STEP = 0.5


@dataclass(frozen=True)
class Gains:
    """Feedback gains, SI units.

    Attributes:
        kx: along-track gain (1/s): m/s of speed per m of error ahead.
        ky: lateral gain (1/m²): rad/s per (m/s of reference speed · m of lateral error).
        ktheta: heading gain per speed (1/m): rad/s per (m/s · rad).
        kspin: heading gain at any speed (1/s): rad/s per rad, for spins and arrival.
        min_radius: pure pursuit's curvature regulation radius (m): slower on tighter curves.
        approach: pure pursuit's slow-down distance before a leg's end (m).
        creep: the slowest pure-pursuit speed while approaching (m/s).
        ki: the tracking law's integral gain (1/m): curvature (1/m) learnt per (m of lateral
            error · m travelled) times ``ky``; 0 turns the integral off, and it must stay below
            ``ktheta`` (the stability bound).
    """

    kx: float
    ky: float
    ktheta: float
    kspin: float
    min_radius: float
    approach: float
    creep: float
    ki: float = 0.0


def _wrap(angle: float) -> float:
    return math.remainder(angle, _TWO_PI)


def _top_speeds(params: DiffDriveParams, limit: float | None) -> tuple[float, float]:
    """The robot's top straight speed (m/s) and spin rate (rad/s) within the motor limit, or
    infinities without one."""
    if limit is None:
        return math.inf, math.inf
    radius = min(params.radii)
    return limit * radius, 2.0 * limit * radius / params.wheel_separation


def default_gains(params: DiffDriveParams, limit: float | None = None) -> Gains:
    """Gains scaled to the robot: its size sets the lengths, its motor limit the rates.

    The rates: ``kspin = min(3, w_max / (pi/4))`` (1/s; a 45-degree error asks at most the top
    spin rate ``w_max``), ``kx = 2 kspin / 3``. The lengths: with ``L = 0.75 ·
    wheel_separation``, the lateral length ``l = min(L, v_max / kspin)`` (at the top speed
    ``v_max`` the lateral error is corrected no faster than the heading at rest), ``ky =
    1/l²``, ``ktheta = 2/l`` (a critically damped lateral response over about ``l`` of
    travel), ``ki = ktheta / 8``; pure pursuit's ``min_radius = 4 L``, ``approach = 1.5 L``,
    ``creep = 0.2 v_max`` (at most 0.05 m/s). The bundled robot (r = 0.035 m, b = 0.135 m,
    50 rpm; l = 0.061 m): kx 2 1/s, ky 268 1/m², ktheta 32.7 1/m, kspin 3 1/s, ki 4.09 1/m,
    min_radius 0.41 m, approach 0.15 m, creep 0.037 m/s.

    Args:
        params: the robot.
        limit: its motor limit (rad/s); ``params.max_wheel_speed`` when None.
    """
    lim = params.max_wheel_speed if limit is None else limit
    lim = None if lim is None else positive_finite(lim, "the motor limit (rad/s)")
    v_max, w_max = _top_speeds(params, lim)
    scale = 0.75 * params.wheel_separation
    kspin = min(3.0, w_max / (math.pi / 4.0))
    lateral = min(scale, v_max / kspin)
    return Gains(
        kx=2.0 * kspin / 3.0,
        ky=1.0 / (lateral * lateral),
        ktheta=2.0 / lateral,
        kspin=kspin,
        min_radius=4.0 * scale,
        approach=1.5 * scale,
        creep=min(0.05, 0.2 * v_max),
        ki=0.25 / lateral,
    )


def delay_lead(latency: float, motor_lag: float, control_rate: float) -> float:
    """The tracking law's lead (s) for a robot that acts on a command ``latency`` s after it is
    sent, through wheels of first-order time constant ``motor_lag`` (s), commanded at
    ``control_rate`` (Hz): ``latency + motor_lag + 1 / (2 control_rate)``. A first-order lag
    follows a ramp ``motor_lag`` behind; a command held for one control period acts, on
    average, half a period after it is sent. (A follower takes at most :data:`MAX_LEAD`.)

    Raises:
        ParameterError: a delay that is not finite and >= 0, a rate that is not > 0.
    """
    latency = finite_in_range(latency, "latency", 0.0, 1e6, unit="s")
    motor_lag = finite_in_range(motor_lag, "motor_lag", 0.0, 1e6, unit="s")
    rate = finite_in_range(control_rate, "control_rate", 0.0, 1e6, open_low=True, unit="Hz")
    return latency + motor_lag + 0.5 / rate


def _checked_gains(gains: Gains | Mapping[str, float] | None, base: Gains) -> Gains:
    if gains is None:
        return base
    if isinstance(gains, Gains):
        given = {item.name: getattr(gains, item.name) for item in fields(Gains)}
    elif isinstance(gains, Mapping):
        unknown = sorted(set(gains) - {item.name for item in fields(Gains)})
        if unknown:
            raise ParameterError(f"gains: unknown gain {unknown[0]!r}")
        given = dict(gains)
    else:
        raise ParameterError(f"gains must be a Gains or a mapping of names, got {shown(gains)}")
    checked: dict[str, float] = {}
    for name, value in given.items():
        low_open = name not in ("kspin", "ki")
        checked[name] = finite_in_range(value, f"gains {name}", 0.0, 1e9, open_low=low_open)
    made = replace(base, **checked)
    if made.ki >= made.ktheta:
        raise ParameterError(
            f"gains ki ({made.ki:g} 1/m) must be below ktheta ({made.ktheta:g} 1/m): a larger "
            "integral gain makes the lateral error grow"
        )
    return made


class Follower:
    """A plan follower: call :meth:`command` at the control rate with the pose estimate.

    Args:
        params: the robot (its geometry and motor limit).
        plan: the plan to follow (a step plan or a ramped one), from pose (0, 0, 0) of the odom
            frame.
        law: ``"tracking"`` (timed, Kanayama's law) or ``"pure-pursuit"`` (untimed, regulated
            pure pursuit).
        gains: the gains, or a mapping of the ones to change (see :class:`Gains`); by default
            :func:`default_gains` of the robot and the plan's motor limit.
        lookahead: pure pursuit's lookahead distance (m), by default ``1.5 · 0.75 ·
            wheel_separation`` (0.15 m for the bundled robot); the tracking law has none.
        lead: the tracking law's lead time (s), from 0 (the default: the law acts on the
            pose as given) to :data:`MAX_LEAD`: about the robot's command latency plus its
            motor lag. The law then acts on the pose predicted ``lead`` s ahead from the
            commands it sent in the last ``lead`` s, which the robot has not yet carried out,
            against the reference at ``t + lead`` (see the module's notes).
        xy_tolerance: distance from the final pose within which it is done (m), > 0.
        yaw_tolerance: heading error within which it is done (rad), > 0.
        body: body velocity limits every command keeps (m/s, rad/s; both axes scaled by one
            factor), as the plan was made within (``--max-linear``, ``--max-angular``).

    Raises:
        ParameterError: an unknown law, a gain, lookahead or tolerance that is not finite or
            out of its range.
    """

    def __init__(
        self,
        params: DiffDriveParams,
        plan: Plan | RampedPlan,
        *,
        law: str = "tracking",
        gains: Gains | Mapping[str, float] | None = None,
        lookahead: float | None = None,
        lead: float = 0.0,
        xy_tolerance: float = DEFAULT_XY_TOLERANCE,
        yaw_tolerance: float = DEFAULT_YAW_TOLERANCE,
        body: BodyLimits | None = None,
    ) -> None:
        from diffbot.trajectory import Plan

        if law not in LAWS:
            raise ParameterError(f"law must be one of {', '.join(LAWS)}, got {shown(law)}")
        self.params = params
        self.plan = plan
        self.law = law
        self.body = body
        steps = plan if isinstance(plan, Plan) else plan.steps
        self.limit = steps.limit if steps.limit is not None else params.max_wheel_speed
        self.gains = _checked_gains(gains, default_gains(params, self.limit))
        self.xy_tolerance = finite_in_range(
            xy_tolerance, "xy_tolerance", 0.0, 1e3, open_low=True, unit="m"
        )
        self.yaw_tolerance = finite_in_range(
            yaw_tolerance, "yaw_tolerance", 0.0, math.pi, open_low=True, unit="rad"
        )
        if law == "tracking":
            if lookahead is not None:
                raise ParameterError(
                    "lookahead is pure pursuit's distance; the tracking law takes a lead (s)"
                )
            self.lookahead = 0.0
        else:
            self.lookahead = (
                1.5 * 0.75 * params.wheel_separation
                if lookahead is None
                else finite_in_range(lookahead, "lookahead", WHEEL_SIZE_RANGE[0], 1e3, unit="m")
            )
        self.lead = finite_in_range(lead, "lead", 0.0, MAX_LEAD, unit="s")
        #: How long (s) the pose must stay within the tolerances before it is done.
        self.dwell = max(DWELL, 3.0 * self.lead)
        if self.lead and law != "tracking":
            raise ParameterError("lead is the tracking law's; pure pursuit takes none")
        self.duration = plan.duration
        self.goal = steps.final_pose
        self.goal_heading = steps.segments[-1].end_heading
        self._pieces = pieces(plan)
        self._starts = [piece[0] for piece in self._pieces]
        self._index = 0
        left, right = params.radii
        self._wheel = (left, right, 0.5 * params.wheel_separation)
        self._axes = (
            axis_limits(plan, params) if law == "pure-pursuit" else controller_limits(params)
        )
        linear, angular = axis_brakes(self._axes)
        #: The tracking law's integral: the curvature (1/m) added per m/s of reference speed,
        #: held within the largest bias a wheel mismatch gives.
        self.bias = 0.0
        self._bias_cap = MAX_MISMATCH / params.wheel_separation
        self._quarter = 0.25 * params.wheel_separation**2
        self._saturated = False
        self._last: tuple[float, float, float, float, float] | None = None  # t, v0, w0, v1, w1
        #: The commands sent within the last ``lead`` s and the one before: the time (s),
        #: (v, w) and the pose the commands before reach in the command frame (m, m, rad).
        self._sent: deque[tuple[float, float, float, float, float, float]] = deque()
        self._arrival = Arrival(
            self.goal.x,
            self.goal.y,
            self.goal_heading,
            self.gains,
            self.xy_tolerance,
            (linear, angular),
        )
        self._within_since: float | None = None
        self._done: bool | None = None
        self._pursuit = None
        if law == "pure-pursuit":
            from diffbot.pursuit import Pursuit

            self._pursuit = Pursuit(
                steps, self.gains, self.lookahead, self.xy_tolerance, (linear, angular)
            )

    # ----------------------------------------------------------------------------------------
    def reference(self, t: float) -> tuple[float, float, float, float, float]:
        """The timed reference at ``t`` (s): x, y (m), heading (rad, not wrapped), linear
        (m/s) and angular (rad/s) velocity; the final pose and zero velocity past the end."""
        if t >= self.duration:
            goal = self.goal
            return goal.x, goal.y, self.goal_heading, 0.0, 0.0
        starts, i = self._starts, self._index
        if t < starts[i] or (i + 1 < len(starts) and t >= starts[i + 1]):
            i = max(0, bisect.bisect_right(starts, t) - 1)
            self._index = i
        t0, x0, y0, h0, lg, ag, p, v, a, j = self._pieces[i]
        tau = t - t0 if t > t0 else 0.0
        s = p + tau * (v + tau * (0.5 * a + tau * j / 6.0))
        speed = v + tau * (a + 0.5 * j * tau)
        ds, turn = lg * s, ag * s
        half = 0.5 * turn
        chord = ds * (math.sin(half) / half) if half != 0.0 else ds
        mean = h0 + half
        return (
            x0 + chord * math.cos(mean),
            y0 + chord * math.sin(mean),
            h0 + turn,
            lg * speed,
            ag * speed,
        )

    def done(self, t: float, pose: Pose) -> bool:
        """Whether the plan is finished: past its end (for pure pursuit: its path driven) and
        within ``xy_tolerance`` and ``yaw_tolerance`` of its final pose, as every pose given
        for the last :attr:`dwell` s was (a robot still coasting leaves the tolerance within
        that time; call this at every control step)."""
        pursuit = self._pursuit
        finished = pursuit.finished if pursuit is not None else t >= self.duration
        goal = self.goal
        dx, dy = goal.x - pose[0], goal.y - pose[1]
        if not (
            finished
            and dx * dx + dy * dy <= self.xy_tolerance * self.xy_tolerance
            and abs(_wrap(self.goal_heading - pose[2])) <= self.yaw_tolerance
        ):
            self._within_since = self._done = None
            return False
        if self._within_since is None or t < self._within_since:
            self._within_since = t
        self._done = t - self._within_since >= self.dwell or None
        return bool(self._done)

    @property
    def settling(self) -> bool:
        """Whether the last pose :meth:`done` saw was within the tolerances, the follower
        waiting out its dwell: a run about to give up lets it finish (at most the dwell)."""
        return self._within_since is not None and not self._done

    def command(self, t: float, pose: Pose) -> Twist:
        """The command (linear.x m/s, angular.z rad/s) at ``t`` (s since the plan started)
        for the robot at ``pose`` (m, m, rad; odom frame): within the motor limit and the
        acceleration limits; zero once done."""
        x, y, theta = pose[0], pose[1], pose[2]
        pursuit = self._pursuit
        if pursuit is not None:
            arriving = pursuit.finished or pursuit.update(x, y, theta)
            if not arriving:
                v, w = pursuit.command(x, y, theta)
                return self._limited(t, v, w)
        else:
            lead = self.lead
            # Predicted while the plan's own commands are in flight; past them, the arrival
            # regulates at millimetres, where a prediction misled by a lost command is worse
            # than the pose as given.
            if lead and t < self.duration + lead:
                x, y, theta = self._predicted(t, x, y, theta)
            ahead = t + lead
            if ahead < self.duration:
                xr, yr, hr, vr, wr = self.reference(ahead)
                cos_t, sin_t = math.cos(theta), math.sin(theta)
                dx, dy = xr - x, yr - y
                ex = cos_t * dx + sin_t * dy
                ey = cos_t * dy - sin_t * dx
                eh = math.remainder(hr - theta, _TWO_PI)
                g = self.gains
                v = vr * math.cos(eh) + g.kx * ex
                speed = abs(vr) * g.ktheta
                fade = 1.0 - speed / g.kspin if speed < g.kspin else 0.0
                w = wr + vr * g.ky * ey + (speed + g.kspin * fade * fade) * math.sin(eh)
                if g.ki:
                    bias = self._integrated(t, abs(vr) * g.ki * g.ky * ey, g.ky * ey)
                    w += vr * bias
                    v += bias * self._quarter * w
                return self._limited(t, v, w)
        if self._done:
            return self._limited(t, 0.0, 0.0)
        v, w = self._arrival.command(x, y, theta)
        return self._limited(t, v, w)

    def _integrated(self, t: float, rate: float, offset: float) -> float:
        """The curvature bias after the step from the last command to ``t`` at ``rate``
        (1/m/s). Held (anti-windup) while the last command was cut by the motor limit, and
        while the lateral error is larger than the largest bias could hold it (``offset`` =
        ``ky e_y`` beyond the cap, 1/m): that error is a transient, not a bias."""
        last = self._last
        cap = self._bias_cap
        if last is not None and not self._saturated and -cap <= offset <= cap:
            dt = t - last[0]
            if 0.0 < dt <= _LONGEST_STEP:
                self.bias = min(max(self.bias + rate * dt, -cap), cap)
        return self.bias

    def _predicted(self, t: float, x: float, y: float, theta: float) -> tuple[float, float, float]:
        """The pose ``lead`` s after ``t``: ``(x, y, theta)`` moved by the commands sent from
        ``t - lead`` on, each held until the next (the last until ``t``), along its arc.

        Each command sent carries the pose the commands so far reach from a fixed origin (the
        command frame); the motion over the window is the change of that pose from
        ``t - lead`` to ``t``, seen from its start: two arcs and a rotation whatever the
        number of commands in the window."""
        sent = self._sent
        if not sent:
            return x, y, theta
        start = t - self.lead
        while len(sent) > 1 and sent[1][0] <= start:
            sent.popleft()
        first, last = sent[0], sent[-1]
        sx, sy, sh = (
            _advanced(first, start - first[0])
            if start > first[0]
            else (first[3], first[4], first[5])
        )
        ex, ey, eh = _advanced(last, t - last[0]) if t > last[0] else (last[3], last[4], last[5])
        dx, dy = ex - sx, ey - sy
        cos_s, sin_s = math.cos(sh), math.sin(sh)
        ahead = cos_s * dx + sin_s * dy
        left = cos_s * dy - sin_s * dx
        cos_t, sin_t = math.cos(theta), math.sin(theta)
        return x + cos_t * ahead - sin_t * left, y + sin_t * ahead + cos_t * left, theta + eh - sh

    def stopped_at(self, t: float) -> None:
        """Say that the robot was commanded zero at ``t`` (s) other than through
        :meth:`command` (a live driver's stop on a stale pose): the prediction of a follower
        with a lead counts it as sent."""
        if self.lead:
            self._record(t, 0.0, 0.0)

    def _record(self, t: float, v: float, w: float) -> None:
        """Keep the command sent at ``t`` with the command frame's pose it starts from."""
        sent = self._sent
        while sent and sent[-1][0] >= t:
            sent.pop()
        pose = _advanced(sent[-1], t - sent[-1][0]) if sent else (0.0, 0.0, 0.0)
        sent.append((t, v, w, *pose))
        start = t - self.lead
        while len(sent) > 1 and sent[1][0] <= start:
            sent.popleft()

    def _limited(self, t: float, v: float, w: float) -> Twist:
        """``(v, w)`` within the motor limit (curvature kept), then the acceleration limits."""
        lim = self.limit
        left_radius, right_radius, half = self._wheel
        self._saturated = False
        if lim is not None:
            track = half * w
            peak = max(abs((v - track) / left_radius), abs((v + track) / right_radius))
            if peak > lim:
                scale = lim / peak
                v, w = v * scale, w * scale
                self._saturated = True
        share = body_share(v, w, self.body)
        if share < 1.0:
            v, w = v * share, w * share
            self._saturated = True
        last = self._last
        if self._axes:
            from diffbot.limiter import limit

            t0, v0, w0, v1, w1 = (t, 0.0, 0.0, 0.0, 0.0) if last is None else last
            dt = t - t0
            if dt > 0.0:
                lin, ang = self._axes
                lv, lw = limit(lin, v, v0, v1, dt), limit(ang, w, w0, w1, dt)
                linear = _share(lv, v0, v)
                share = min(linear, _share(lw, w0, w))
                # A stop is not held back by the turn: braking, the speed keeps its own limit
                # (the curvature gives way, as the controller's axes are limited apart).
                braking = abs(v) < abs(v0) and v * v0 >= 0.0
                v = v0 + (linear if braking else share) * (v - v0)
                w = w0 + share * (w - w0)
            else:
                v, w = v0, w0
        if last is None or t > last[0]:
            previous = (0.0, 0.0) if last is None else (last[1], last[2])
            self._last = (t, v, w, *previous)
        if self.lead:
            self._record(t, v, w - self.bias * v)
        # The named tuple's own __new__ is a Python function: tuple.__new__ builds the same.
        return tuple.__new__(Twist, (v + 0.0, w + 0.0))


def _advanced(
    sent: tuple[float, float, float, float, float, float], dt: float
) -> tuple[float, float, float]:
    """The command frame's pose a command ``(t, v, w, x, y, theta)`` reaches after ``dt`` s."""
    _, v, w, x, y, theta = sent
    ds, turn = v * dt, w * dt
    half = 0.5 * turn
    chord = ds * (math.sin(half) / half) if half != 0.0 else ds
    mean = theta + half
    return x + chord * math.cos(mean), y + chord * math.sin(mean), theta + turn


def _share(limited: float, last: float, command: float) -> float:
    if command == last:
        return 1.0
    return min(max((limited - last) / (command - last), 0.0), 1.0)
