"""A plan run on a disturbed simulated robot, open loop or closed by a follower, and how far it
strayed.

:func:`run_chunks` steps a :class:`diffbot.simulation.DisturbedRobot`: at the control rate a
controller (a :class:`diffbot.follow.Follower`, or anything with its ``command`` and ``done``)
gets the pose estimate (the robot's wheel odometry, or its true pose with noise) and commands
the wheels; without a controller the plan's own commands at the control rate are sent open
loop. The joint states are sampled at the simulation rate with their encoder resolution and
noise, beside the true pose, a chunk at a time (:func:`run` gives them all at once).
:func:`path_distance` measures the true path against the plan's.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Final, Literal, Protocol, get_args

from diffbot.errors import ParameterError
from diffbot.kinematics import DiffDriveParams, Pose, Twist
from diffbot.numbers import (
    encoder_noise,
    encoder_ticks,
    finite_in_range,
    noise_seed,
    shown,
    sized,
    store_checked,
    store_number,
)
from diffbot.simulation import (
    CHUNK_SAMPLES,
    MAX_RATE,
    MAX_SAMPLES,
    SLIP_PERIOD,
    Disturbances,
    DisturbedRobot,
)

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray

    from diffbot.ramps import RampedPlan
    from diffbot.trajectory import Plan

__all__ = [
    "POSE_SOURCES",
    "Controller",
    "LoopChunk",
    "LoopOutcome",
    "LoopResult",
    "LoopSettings",
    "PoseSource",
    "longest_run",
    "path_distance",
    "run",
    "run_chunks",
    "run_size",
]

#: Where the follower's pose comes from: the robot's wheel odometry, or its true pose (with
#: noise), as motion capture or localization gives it.
PoseSource = Literal["odom", "truth"]
#: The pose sources, as :data:`PoseSource` spells them.
POSE_SOURCES: Final[tuple[PoseSource, ...]] = get_args(PoseSource)
#: Longest a run goes on past the plan's end waiting to arrive (s), at least.
MIN_OVERTIME: Final = 10.0
#: Longest a run goes on past its give-up time for a controller within its tolerances to say
#: done (s): a follower's dwell, at most three of its longest lead (2 s).
SETTLE_GRACE: Final = 6.0


def _settling(controller: object, late: float) -> bool:
    """Whether a run ``late`` s past its give-up time waits for ``controller`` (a follower
    within its tolerances, waiting out its dwell), for at most :data:`SETTLE_GRACE` s."""
    return late < SETTLE_GRACE and bool(getattr(controller, "settling", False))


class Controller(Protocol):
    """What closes the loop: a :class:`diffbot.follow.Follower`, or another law."""

    def command(self, t: float, pose: Pose) -> Twist:
        """The command (m/s, rad/s) at ``t`` (s) for the robot at ``pose``."""

    def done(self, t: float, pose: Pose) -> bool:
        """Whether it has arrived."""


@dataclass(frozen=True)
class LoopSettings:
    """How the simulated run goes.

    Attributes:
        rate: joint state sampling rate (Hz); the odometry and the pose source update at it.
        control_rate: commands per second (Hz), at most ``rate``.
        ticks: encoder resolution (counts per revolution, an integer from 1 to 2**32), or None.
        noise: encoder noise (rad, standard deviation, at most 2 pi).
        seed: seed of the encoder and pose noise (an integer >= 0), or None.
        disturbances: the robot's disturbances.
        true_params: the real robot (other radii and separation), or None.
        pose_source: ``"odom"`` (wheel odometry) or ``"truth"`` (the true pose with noise).
        pose_noise: standard deviations of the true pose's noise (m, rad).
    """

    rate: float = 50.0
    control_rate: float = 20.0
    ticks: int | None = None
    noise: float = 0.0
    seed: int | None = None
    disturbances: Disturbances = field(default_factory=Disturbances)
    true_params: DiffDriveParams | None = None
    pose_source: PoseSource = "odom"
    pose_noise: tuple[float, float] = (0.0, 0.0)

    def __post_init__(self) -> None:
        store_number(self, "rate", 0.0, MAX_RATE, open_low=True, unit="Hz")
        store_number(self, "control_rate", 0.0, MAX_RATE, open_low=True, unit="Hz")
        rate, control = self.rate, self.control_rate
        if control > rate:
            raise ParameterError(
                f"control_rate ({control:g} Hz) must not exceed the simulation rate "
                f"({rate:g} Hz): the controller sees one pose a sample"
            )
        store_checked(self, "ticks", encoder_ticks, optional=True)
        store_checked(self, "noise", encoder_noise)
        store_checked(self, "seed", noise_seed, optional=True)
        store_checked(self, "disturbances", _disturbances)
        store_checked(self, "true_params", _true_params, optional=True)
        if self.pose_source not in POSE_SOURCES:
            sources = ", ".join(POSE_SOURCES)
            raise ParameterError(
                f"pose_source must be one of {sources}, got {shown(self.pose_source)}"
            )
        store_checked(self, "pose_noise", _pose_noise)


def _disturbances(value: object) -> Disturbances:
    if not isinstance(value, Disturbances):
        raise ParameterError(f"disturbances must be a Disturbances, got {shown(value)}")
    return value


def _true_params(value: object) -> DiffDriveParams:
    if not isinstance(value, DiffDriveParams):
        raise ParameterError(f"true_params must be a DiffDriveParams or None, got {shown(value)}")
    return value


def _pose_noise(value: object) -> tuple[float, float]:
    """The true pose's noise as :class:`LoopSettings` takes it: (metres, radians)."""
    pair = sized(value, 2)
    if pair is None:
        raise ParameterError(
            f"pose_noise must be a pair (m, rad) of standard deviations, got {shown(value)}"
        )
    metres, radians = pair
    return (
        finite_in_range(metres, "pose_noise", 0.0, 1e3, unit="m"),
        finite_in_range(radians, "pose_noise", 0.0, math.pi, unit="rad"),
    )


@dataclass(frozen=True)
class LoopResult:
    """A run: samples and what they say.

    Attributes:
        times: sample times (s), shape (n,).
        positions: the joint angles as the encoders report them (rad, signs applied): left
            wheels, right wheels, then the passive joints at 0; shape (joints, n).
        names: the joint names.
        truth: the true pose x, y (m), theta (rad, wrapped) at each sample, shape (3, n).
        odometry: the wheel odometry's pose at each sample, shape (3, n).
        peak_limit_fraction: the largest commanded wheel speed over the motor limit (or None
            without one).
        arrived: whether the controller said done (open loop: whether the plan ran out).
        duration: the time until arrival, or the run's end without it (s).
    """

    times: NDArray[np.float64]
    positions: NDArray[np.float64]
    names: tuple[str, ...]
    truth: NDArray[np.float64]
    odometry: NDArray[np.float64]
    peak_limit_fraction: float | None
    arrived: bool
    duration: float


def _open_loop(made: Plan | RampedPlan, rate: float) -> Iterator[tuple[float, Twist]]:
    """The plan's commands at ``rate`` Hz with their times, made a chunk at a time as they are
    taken: a long plan has millions."""
    from diffbot.ramps import sampled

    for stream in sampled(made).command_chunks(rate):
        times, linear, angular = stream.times.tolist(), stream.linear, stream.angular
        for t, v, w in zip(times, linear.tolist(), angular.tolist(), strict=True):
            yield t, Twist(v, w)


@dataclass
class LoopOutcome:
    """What a run of :func:`run_chunks` came to, filled in as its chunks are taken.

    Attributes:
        names: the joint names of the chunks' positions.
        most_samples: the most samples the run can take (the run gives up by then).
        samples: the samples made so far.
        peak_limit_fraction: the largest commanded wheel speed over the motor limit so far (or
            None without one), to 12 significant digits: a command scaled to the limit is 1.0,
            not the last bit over it that the wheel speeds' rounding gives.
        arrived: whether the controller said done (open loop: whether the plan ran out).
        duration: the time until arrival, or the run's last sample without it (s).
        final_truth: the last sample's true pose x, y (m), theta (rad).
    """

    names: tuple[str, ...]
    most_samples: int
    samples: int = 0
    peak_limit_fraction: float | None = None
    arrived: bool = False
    duration: float = 0.0
    final_truth: tuple[float, float, float] = (0.0, 0.0, 0.0)


#: One chunk of a run: times (s), shape (n,); joint positions (rad), shape (joints, n); true
#: poses and odometry poses (x, y, theta), shape (3, n) each.
LoopChunk = tuple[
    "NDArray[np.float64]", "NDArray[np.float64]", "NDArray[np.float64]", "NDArray[np.float64]"
]


def run(
    made: Plan | RampedPlan,
    params: DiffDriveParams,
    settings: LoopSettings,
    controller: Controller | None = None,
) -> LoopResult:
    """Run ``made`` on the disturbed robot, closed by ``controller`` or open loop: all of
    :func:`run_chunks` at once.

    Raises:
        ParameterError: a run of more than :data:`diffbot.simulation.MAX_SAMPLES` samples.
    """
    import numpy as np

    outcome, chunks = run_chunks(made, params, settings, controller)
    parts = list(chunks)
    times, positions, truth, odometry = (
        np.concatenate([part[k] for part in parts], axis=-1) for k in range(4)
    )
    return LoopResult(
        times=times,
        positions=positions,
        names=outcome.names,
        truth=truth,
        odometry=odometry,
        peak_limit_fraction=outcome.peak_limit_fraction,
        arrived=outcome.arrived,
        duration=outcome.duration,
    )


def run_chunks(
    made: Plan | RampedPlan,
    params: DiffDriveParams,
    settings: LoopSettings,
    controller: Controller | None = None,
    *,
    chunk: int = CHUNK_SAMPLES,
) -> tuple[LoopOutcome, Iterator[LoopChunk]]:
    """Run ``made`` on the disturbed robot, closed by ``controller`` or open loop, ``chunk``
    samples at a time, so that memory does not grow with the run.

    A closed loop runs until the controller is done, then until the wheels stop; it gives up
    ``max(10 s, half the plan's duration)`` past the plan's end (then ``arrived`` is False).
    An open loop runs its commands, then until the wheels stop.

    Returns:
        The outcome, complete once the chunks are all taken, and the chunks.

    Raises:
        ParameterError: a run of more than :data:`diffbot.simulation.MAX_SAMPLES` samples
            (at once, before any chunk).
    """
    give_up = _give_up(made)
    seconds, most, highest = run_size(made, settings, closed=controller is not None)
    if most > MAX_SAMPLES:
        raise ParameterError(
            f"the run of up to {seconds:g} s at {settings.rate:g} Hz would take {most:.4g} "
            f"samples, more than {MAX_SAMPLES}: lower the rate to at most {highest:.4g} Hz"
        )
    draws = seconds / SLIP_PERIOD if settings.disturbances.slip else 0.0
    if draws > MAX_SAMPLES:
        # a slipping robot steps at least once per traction drawn, however rarely it is sampled
        raise ParameterError(
            f"the run of up to {seconds:g} s would draw a slipping wheel's traction "
            f"{draws:.4g} times (every {SLIP_PERIOD:g} s), more than {MAX_SAMPLES}: a faster "
            "control_rate or a shorter plan"
        )
    names = (*params.left_joints, *params.right_joints, *params.passive_joints)
    outcome = LoopOutcome(names, math.ceil(most))
    return outcome, _chunks(made, params, settings, controller, outcome, give_up, chunk)


def run_size(
    made: Plan | RampedPlan, settings: LoopSettings, *, closed: bool
) -> tuple[float, float, float]:
    """How long a run may last (s, :func:`longest_run`), the most samples it may take (one a
    sample period, and those at its ends), and the highest sampling rate (Hz) at which that
    stays within :data:`~diffbot.simulation.MAX_SAMPLES`."""
    seconds = longest_run(made, settings, closed=closed)
    return seconds, seconds * settings.rate + 2.0, (MAX_SAMPLES - 2.0) / seconds


def longest_run(made: Plan | RampedPlan, settings: LoopSettings, *, closed: bool) -> float:
    """The latest time (s) a run's last sample may fall, at most one sample period early.

    Open loop: its commands, one a control period, then the settling :func:`run_chunks`
    waits for (five motor lags, the latency and two control periods). Closed: the plan and the
    longest the follower is given to arrive, to the control tick at which it is told to stop
    (the next, should that fall on the tick to rounding), then the same settling.
    """
    from diffbot.ramps import sampled

    period = 1.0 / settings.control_rate
    settle = _settle(settings)
    if closed:
        give_up = _give_up(made) + SETTLE_GRACE
        return (math.floor(give_up * settings.control_rate) + 1) * period + settle
    return sampled(made).commands_end(settings.control_rate) + settle


def _give_up(made: Plan | RampedPlan) -> float:
    """When a run gives up waiting for its controller to arrive (s): the plan's duration and
    the longer of :data:`MIN_OVERTIME` and the duration again."""
    return made.duration + max(MIN_OVERTIME, made.duration)


def _settle(settings: LoopSettings) -> float:
    """How long a run goes on once its commands end (s), for the robot to come to rest: five
    motor lags, the latency and two control periods."""
    d = settings.disturbances
    return 5.0 * d.motor_lag + d.latency + 2.0 / settings.control_rate


def _table(rows: list[tuple[float, ...]], params: DiffDriveParams) -> LoopChunk:
    import numpy as np

    table = np.array(rows, dtype=np.float64).T
    times = table[0]
    positions = np.repeat(table[1:3], (len(params.left_joints), len(params.right_joints)), axis=0)
    extra = len(params.passive_joints)
    positions = np.vstack((positions, np.zeros((extra, times.size))))
    truth = table[3:6].copy()
    truth[2] = np.remainder(truth[2] + math.pi, 2.0 * math.pi) - math.pi
    return times, positions, truth, table[6:9]


def _chunks(
    made: Plan | RampedPlan,
    params: DiffDriveParams,
    s: LoopSettings,
    controller: Controller | None,
    outcome: LoopOutcome,
    give_up: float,
    chunk: int,
) -> Iterator[LoopChunk]:
    import random

    from diffbot.kinematics import inverse
    from diffbot.odometry import Odometry

    robot = DisturbedRobot(params, s.disturbances, s.true_params)
    odometry = Odometry(params)
    noise_random = random.Random(s.seed)
    sample_period = 1.0 / s.rate
    period = 1.0 / s.control_rate
    commands: Iterator[tuple[float, Twist]] = (
        iter(()) if controller is not None else _open_loop(made, s.control_rate)
    )
    upcoming = next(commands, None)
    limit = params.max_wheel_speed
    tick_step = 0.0 if s.ticks is None else 2.0 * math.pi / s.ticks
    left_sign, right_sign = params.left_sign, params.right_sign
    rows: list[tuple[float, ...]] = []
    peak = 0.0
    estimate = Pose(0.0, 0.0, 0.0)
    arrived, finish, stop = False, None, None
    sample, tick = 0, 0
    t = 0.0
    while True:
        t_sample, t_control = sample * sample_period, tick * period
        t = min(t_sample, t_control)
        robot.advance(t)
        if t_sample <= t:
            left, right = robot.angles
            readings = [left_sign * left, right_sign * right]
            if s.noise:
                readings = [a + noise_random.gauss(0.0, s.noise) for a in readings]
            if tick_step:
                readings = [round(a / tick_step) * tick_step for a in readings]
            odometry.update(readings[0], readings[1], t)
            odom = odometry.pose
            x, y, heading = robot.pose
            if s.pose_source == "odom":
                estimate = odom
            else:
                metres, radians = s.pose_noise
                estimate = Pose(
                    x + noise_random.gauss(0.0, metres) if metres else x,
                    y + noise_random.gauss(0.0, metres) if metres else y,
                    heading + noise_random.gauss(0.0, radians) if radians else heading,
                )
            rows.append((t, *readings, x, y, heading, *odom))
            sample += 1
            if stop is not None and t >= stop:
                break
            if len(rows) >= chunk:
                outcome.samples = sample
                outcome.peak_limit_fraction = _fraction(peak) if limit else None
                yield _table(rows, params)
                rows = []
        if t_control <= t:
            tick += 1
            if controller is not None:
                if finish is None and controller.done(t, estimate):
                    arrived, finish = True, t
                twist = controller.command(t, estimate) if finish is None else Twist(0.0, 0.0)
                if finish is None and t >= give_up and not _settling(controller, t - give_up):
                    finish, twist = t, Twist(0.0, 0.0)
            else:
                twist = Twist(0.0, 0.0)
                while upcoming is not None and upcoming[0] <= t + 1e-9:
                    twist = upcoming[1]
                    upcoming = next(commands, None)
                if upcoming is None and finish is None and twist == Twist(0.0, 0.0):
                    finish = t
                    arrived = True
            wheels = inverse(params, float(twist.linear), float(twist.angular))
            if limit:
                peak = max(peak, abs(float(wheels.left)) / limit, abs(float(wheels.right)) / limit)
            # A follower done commands zero at every tick, as a controller does, so a lost stop
            # is sent again; an open loop's commands end with the plan's final zero.
            if finish is None or t == finish or controller is not None:
                robot.command(float(wheels.left), float(wheels.right))
            if finish is not None and stop is None:
                stop = t + _settle(s)
    last = _table(rows, params)
    outcome.samples = sample
    outcome.peak_limit_fraction = _fraction(peak) if limit else None
    outcome.arrived = arrived
    outcome.duration = float(finish if finish is not None else t)
    truth = last[2]
    outcome.final_truth = (float(truth[0, -1]), float(truth[1, -1]), float(truth[2, -1]))
    yield last


def path_distance(
    plan: Plan, xs: NDArray[np.float64], ys: NDArray[np.float64]
) -> NDArray[np.float64]:
    """The distance (m) from each point ``(xs, ys)`` to the plan's path, in closed form per
    segment (a line piece, an arc, or the point of a spin)."""
    import numpy as np

    from diffbot.trajectory import geometry

    best = np.full(np.shape(xs), np.inf)
    heading = 0.0
    for planned in plan.segments:
        ds, turn = geometry(planned.segment)
        start, end = planned.start_pose, planned.end_pose
        to_end = np.hypot(xs - end.x, ys - end.y)
        if ds == 0.0:
            distance = to_end
        elif turn == 0.0:
            ux, uy = math.cos(heading), math.sin(heading)
            along = np.clip((xs - start.x) * ux + (ys - start.y) * uy, min(0.0, ds), max(0.0, ds))
            distance = np.hypot(xs - start.x - along * ux, ys - start.y - along * uy)
        else:
            radius = ds / turn  # signed: the centre lies this far to the left of the heading
            cx, cy = start.x - radius * math.sin(heading), start.y + radius * math.cos(heading)
            phi0 = math.atan2(start.y - cy, start.x - cx)
            angle = np.remainder(np.arctan2(ys - cy, xs - cx) - phi0, 2.0 * math.pi)
            if turn < 0.0:
                angle = np.remainder(-angle, 2.0 * math.pi)
            on_arc = (angle <= abs(turn)) | (abs(turn) >= 2.0 * math.pi)
            to_circle = np.abs(np.hypot(xs - cx, ys - cy) - abs(radius))
            to_start = np.hypot(xs - start.x, ys - start.y)
            distance = np.where(on_arc, to_circle, np.minimum(to_start, to_end))
        best = np.minimum(best, distance)
        heading = planned.end_heading
    return best


def _fraction(peak: float) -> float:
    """A share of the motor limit without the last-bit noise of the wheel speeds' rounding."""
    return float(f"{peak:.12g}")
