"""Plans run on a disturbed simulated robot, open loop and closed, and the distance of a path
from a plan's."""

from __future__ import annotations

import math

import numpy as np
import pytest
from peak_memory import peak_bytes
from refusals import assert_refused
from robots import BOT_50_RPM

from diffbot.calibration.truth import true_robot
from diffbot.closed_loop import SETTLE_GRACE, LoopSettings, path_distance, run, run_chunks
from diffbot.errors import ParameterError
from diffbot.follow import Follower
from diffbot.kinematics import Twist
from diffbot.planfile import parse_plan
from diffbot.simulation import Disturbances
from diffbot.trajectory import EXAMPLES, plan, pose_at

ROBOT = BOT_50_RPM.replace(left_joints=("l",), right_joints=("r",), left_joint="l", right_joint="r")
DISTURBED = Disturbances(motor_lag=0.15, latency=0.04, drop=0.05, seed=1)


def made(text: str):
    return plan(parse_plan(text), ROBOT)


def final_error(p, result) -> tuple[float, float]:
    goal = p.final_pose
    x, y, theta = result.truth[:, -1]
    return math.hypot(x - goal.x, y - goal.y), abs(math.remainder(theta - goal.theta, 2 * math.pi))


def test_an_undisturbed_open_loop_run_ends_at_the_plans_end() -> None:
    p = made(EXAMPLES["A"])
    result = run(p, ROBOT, LoopSettings(rate=50.0, control_rate=50.0))
    position, heading = final_error(p, result)
    assert position < 1e-9
    assert heading < 1e-9
    # The odometry of exact wheel angles agrees with the truth.
    assert np.allclose(result.odometry[:2], result.truth[:2], atol=1e-9)
    assert result.arrived
    peak = max(s.fraction or 0.0 for s in p.segments)
    assert result.peak_limit_fraction == pytest.approx(peak, rel=1e-9)


def test_wrong_radii_throw_the_open_loop_off_and_a_true_pose_source_corrects_it() -> None:
    p = made(EXAMPLES["B"])
    real = true_robot(ROBOT, (0.0357, 0.0343), 0.139)
    base = {"ticks": 4096, "seed": 2, "disturbances": DISTURBED, "true_params": real}
    open_loop = run(p, ROBOT, LoopSettings(**base))
    truth = LoopSettings(**base, pose_source="truth", pose_noise=(0.001, math.radians(0.2)))
    closed = run(p, ROBOT, truth, Follower(ROBOT, p))
    assert final_error(p, open_loop)[0] > 0.1
    position, heading = final_error(p, closed)
    assert position < 0.01
    assert heading < math.radians(1.0)
    assert closed.arrived
    assert closed.peak_limit_fraction <= 1.0 + 1e-9


def test_a_follower_at_the_motor_limit_reports_the_whole_limit_not_a_bit_over() -> None:
    # The follower scales its commands to the limit; the wheel speeds worked out from them
    # round to a last bit over it, which a reader of the JSON would take for over the limit.
    p = plan(parse_plan(EXAMPLES["A"]), ROBOT, fastest=True)
    settings = LoopSettings(seed=1, disturbances=DISTURBED)
    outcome = run(p, ROBOT, settings, Follower(ROBOT, p))
    assert outcome.peak_limit_fraction == 1.0


def test_closing_the_loop_on_odometry_ends_within_a_centimetre_and_a_degree() -> None:
    p = made(EXAMPLES["A"])
    settings = LoopSettings(ticks=4096, seed=1, disturbances=DISTURBED)
    for law in ("tracking", "pure-pursuit"):
        result = run(p, ROBOT, settings, Follower(ROBOT, p, law=law))
        position, heading = final_error(p, result)
        assert position < 0.01, law
        assert heading < math.radians(1.0), law
        cross = path_distance(p, result.truth[0], result.truth[1])
        assert cross.max() < 0.02, law


class DoneAtOnce:
    """Done at its first step with the robot driving: it commands zero from then on."""

    def __init__(self) -> None:
        self.calls = 0

    def command(self, t, pose):
        return Twist(0.0, 0.0)

    def done(self, t, pose):
        self.calls += 1
        return self.calls > 1


def test_a_follower_done_keeps_commanding_zero_so_a_lost_stop_is_sent_again() -> None:
    # Every other command is lost: the one stop sent when the follower was done was lost for
    # several seeds, and the robot drove on at its last command until the run ended.
    class Driving(DoneAtOnce):
        def command(self, t, pose):
            return Twist(0.1, 0.0)

    lost = 0
    for seed in range(30):
        motors = Disturbances(motor_lag=0.5, drop=0.5, seed=seed)
        result = run(
            made("straight 1"), ROBOT, LoopSettings(rate=100.0, disturbances=motors), Driving()
        )
        # Told 0.1 m/s for one 50 ms tick, it reaches 1 cm/s: a stop that arrives within a few
        # ticks leaves it 6 mm on; a lost one let it speed up for the 2.6 s the run settles.
        assert result.truth[0, -1] < 0.02, seed
        lost += result.truth[0, -1] > 0.006  # its first stop lost
    assert lost >= 3


class SlowToSettle:
    """Within its tolerances from 11.5 s, done a second later: past a 2 s plan's give-up
    time of 12 s."""

    settling = False

    def command(self, t, pose):
        return Twist(0.0, 0.0)

    def done(self, t, pose):
        self.settling = 11.5 <= t < 12.5
        return t >= 12.5


def test_a_follower_within_its_tolerances_at_the_give_up_time_is_let_say_done() -> None:
    # Pure pursuit, slower than the plan's timing, was given up on while waiting out its dwell
    # 0.3 mm from the goal ('--to 0,0,180 --shape reeds-shepp'): not arrived.
    result = run(made("straight 0.1 2s"), ROBOT, LoopSettings(), SlowToSettle())
    assert result.arrived
    assert result.duration == pytest.approx(12.5)


def test_a_follower_that_keeps_settling_is_given_up_on_after_the_grace() -> None:
    class Dithering(SlowToSettle):
        def done(self, t, pose):
            self.settling = True
            return False

    result = run(made("straight 0.1 2s"), ROBOT, LoopSettings(), Dithering())
    assert not result.arrived
    assert result.duration == pytest.approx(12.0 + SETTLE_GRACE)


def test_a_run_that_never_arrives_gives_up() -> None:
    p = made("straight 0.2 2s")

    class Stubborn:
        def command(self, t, pose):
            return Twist(0.0, 0.0)

        def done(self, t, pose):
            return False

    result = run(p, ROBOT, LoopSettings(), Stubborn())  # type: ignore[arg-type]
    assert not result.arrived
    assert result.duration == pytest.approx(2.0 + 10.0, abs=0.05)


@pytest.mark.parametrize(
    "kwargs",
    [
        {"rate": 20.0, "control_rate": 50.0},
        {"rate": math.nan},
        {"control_rate": -1.0},
        {"pose_source": "gps"},
        {"pose_noise": (-0.1, 0.0)},
    ],
)
def test_bad_settings_are_refused(kwargs) -> None:
    with pytest.raises(ParameterError):
        LoopSettings(**kwargs)


@pytest.mark.parametrize(
    ("kwargs", "named"),
    [
        ({"rate": "fast"}, "rate"),
        ({"rate": math.inf}, "rate"),
        ({"rate": 10**400}, "rate"),
        ({"control_rate": "nan"}, "control_rate"),
        ({"ticks": 2.5}, "ticks"),
        ({"ticks": -5}, "ticks"),
        ({"ticks": math.nan}, "ticks"),
        ({"ticks": "4096"}, "ticks"),
        ({"ticks": True}, "ticks"),
        ({"ticks": 10**400}, "ticks"),
        ({"noise": -1.0}, "noise"),
        ({"noise": "-0.001"}, "noise"),
        ({"noise": 1e308}, "noise"),
        ({"noise": math.nan}, "noise"),
        ({"noise": None}, "noise"),
        ({"noise": [0.001]}, "noise"),
        ({"seed": math.nan}, "seed"),
        ({"seed": -1}, "seed"),
        ({"seed": 1.5}, "seed"),
        ({"seed": "1"}, "seed"),
        ({"pose_noise": None}, "pose_noise"),
        ({"pose_noise": (0.01,)}, "pose_noise"),
        ({"pose_noise": "ab"}, "pose_noise"),
        ({"pose_noise": ("0.01", "inf")}, "pose_noise"),
        ({"pose_noise": (0.01, 10**400)}, "pose_noise"),
        ({"pose_noise": (-0.01, 0.0)}, "pose_noise"),
        ({"disturbances": None}, "disturbances"),
        ({"disturbances": {"drop": 0.1}}, "disturbances"),
        ({"true_params": "robot.urdf"}, "true_params"),
        ({"pose_source": None}, "pose_source"),
    ],
)
def test_hostile_settings_are_refused_naming_the_parameter(
    kwargs: dict[str, object], named: str
) -> None:
    assert_refused(LoopSettings, kwargs, named)


def test_numeric_strings_run_as_their_numbers() -> None:
    p = made(EXAMPLES["B"])
    base = {"ticks": 4096, "seed": 2, "disturbances": DISTURBED, "pose_source": "truth"}
    as_text = LoopSettings(
        rate="50.0", control_rate="20", noise="0.001", pose_noise=("0.01", "0.02"), **base
    )  # type: ignore[arg-type]
    as_numbers = LoopSettings(
        rate=50.0, control_rate=20, noise=0.001, pose_noise=(0.01, 0.02), **base
    )  # type: ignore[arg-type]
    assert as_text == as_numbers
    closed, numbers = (run(p, ROBOT, s, Follower(ROBOT, p)) for s in (as_text, as_numbers))
    for got, expected in ((closed.truth, numbers.truth), (closed.positions, numbers.positions)):
        np.testing.assert_array_equal(got, expected)
    assert (closed.arrived, closed.duration) == (numbers.arrived, numbers.duration)


def test_the_distance_from_a_plans_path_in_closed_form() -> None:
    # A straight from (0, 0) to (1, 0), a ccw quarter circle about (1, 0.5) to (1.5, 0.5), a spin.
    p = made("straight 1; ccw 0.5 90; spin 90")
    on_arc = (1.0 + 0.5 * math.sin(math.pi / 4), 0.5 - 0.5 * math.cos(math.pi / 4))
    points = [(0.5, 0.0), (0.5, 0.2), (-0.3, 0.0), (1.0, 0.5), on_arc, (1.0, 0.7), (1.5, 1.5)]
    # on the straight; beside it; before its start; the arc's centre; on the arc; beyond the
    # arc's quarter (nearest its end); above the end.
    expected = [0.0, 0.2, 0.3, 0.5, 0.0, math.hypot(0.5, 0.2), 1.0]
    xs, ys = (np.array(column) for column in zip(*points, strict=True))
    assert path_distance(p, xs, ys) == pytest.approx(expected, abs=1e-12)


@pytest.mark.parametrize("text", ["reverse cw 1 90", "reverse ccw 0.5 120", "straight -1"])
def test_the_distance_from_a_reversing_path(text: str) -> None:
    p = made(text)
    poses = [pose_at(p, share * p.duration) for share in (0.0, 0.25, 0.5, 1.0)]
    xs, ys = np.array([q.x for q in poses]), np.array([q.y for q in poses])
    assert path_distance(p, xs, ys) == pytest.approx([0.0] * 4, abs=1e-12)
    mid = poses[2]
    beside = path_distance(
        p,
        np.array([mid.x - 0.1 * math.sin(mid.theta)]),
        np.array([mid.y + 0.1 * math.cos(mid.theta)]),
    )
    assert beside == pytest.approx([0.1], abs=1e-12)


@pytest.mark.parametrize("follow", [False, True])
def test_a_run_in_chunks_is_the_whole_run_bit_for_bit_in_bounded_pieces(follow: bool) -> None:
    made = plan(parse_plan(EXAMPLES["A"]), BOT_50_RPM)
    settings = LoopSettings(
        rate=200.0,
        ticks=4096,
        noise=1e-4,
        seed=3,
        disturbances=Disturbances(motor_lag=0.1, latency=0.03, drop=0.1, slip=0.01, seed=3),
    )

    def controller() -> Follower | None:
        return Follower(BOT_50_RPM, made) if follow else None

    whole = run(made, BOT_50_RPM, settings, controller())
    outcome, chunks = run_chunks(made, BOT_50_RPM, settings, controller(), chunk=97)
    parts = list(chunks)
    assert all(part[0].size <= 97 for part in parts)
    assert len(parts) == math.ceil(whole.times.size / 97)
    for k, array in enumerate((whole.times, whole.positions, whole.truth, whole.odometry)):
        assert np.array_equal(np.concatenate([part[k] for part in parts], axis=-1), array)
    assert outcome.samples == whole.times.size <= outcome.most_samples
    assert (outcome.arrived, outcome.duration) == (whole.arrived, whole.duration)
    assert outcome.peak_limit_fraction == whole.peak_limit_fraction
    assert outcome.final_truth == tuple(float(v) for v in whole.truth[:, -1])
    assert outcome.names == whole.names


def test_an_open_loop_run_makes_its_commands_as_it_sends_them() -> None:
    # 400,000 commands held at once took about 100 MB before the first sample; made as they
    # are sent, the run's first chunk needs what its first commands do.
    long = made("straight 1 20000s")
    _, chunks = run_chunks(long, ROBOT, LoopSettings(rate=20.0, disturbances=DISTURBED), chunk=100)
    first, peak = peak_bytes(lambda: next(chunks))
    assert first[0].size == 100
    assert peak < 20e6


def test_an_open_loop_run_is_bounded_by_its_own_length_not_a_followers() -> None:
    # straight 0.01 at 1 MHz: two 20 Hz commands, then five lags and two periods to settle,
    # 0.7 s and 700,001 samples; the 10 s a follower is given past the plan's end would make
    # it over 10 million, and it was refused.
    settings = LoopSettings(rate=1e6, control_rate=20.0, disturbances=Disturbances(motor_lag=0.1))
    outcome, _ = run_chunks(made("straight 0.01"), ROBOT, settings)
    assert 700_001 <= outcome.most_samples <= 700_003


@pytest.mark.timeout(60)
def test_a_slipping_run_of_more_tractions_than_samples_is_refused_before_it_starts() -> None:
    # At 1e-6 Hz the one command is held for 1e6 s: one sample, but 1e7 tractions to draw
    # (one per 0.1 s of motion), which ran for a minute.
    slipping = Disturbances(slip=0.1, seed=1)
    settings = LoopSettings(rate=1e-6, control_rate=1e-6, disturbances=slipping)
    with pytest.raises(ParameterError, match=r"draw a slipping wheel's traction 3e\+07 times"):
        run_chunks(made("straight 0.3"), ROBOT, settings)
    calm = LoopSettings(rate=1e-6, control_rate=1e-6, disturbances=Disturbances(motor_lag=0.1))
    outcome, _ = run_chunks(made("straight 0.3"), ROBOT, calm)
    assert outcome.most_samples <= 6  # a few samples: the run is not refused without slip


class Stubborn:
    def command(self, t, pose):
        return Twist(0.1, 0.0)

    def done(self, t, pose):
        return False


@pytest.mark.parametrize("follow", [False, True])
@pytest.mark.parametrize(("rate", "control_rate"), [(50.0, 20.0), (50.0, 7.0), (1.0, 1e-3)])
def test_the_most_samples_a_run_may_take_bound_it_closely(
    follow: bool, rate: float, control_rate: float
) -> None:
    # At 1e-3 Hz a command is held for 1000 s, and the run settles for two periods after the
    # last: 3000 s, not the plan's 2 s and the follower's 10.
    settings = LoopSettings(
        rate=rate,
        control_rate=control_rate,
        disturbances=Disturbances(motor_lag=0.05, latency=0.03),
    )
    controller = Stubborn() if follow else None
    outcome, chunks = run_chunks(made("straight 0.2 2s"), ROBOT, settings, controller)  # type: ignore[arg-type]
    for _ in chunks:
        pass
    # A follower that gives up is told so at the first control tick past its time, or, to
    # rounding, the next; the bound also holds the grace a settling follower may take.
    late = rate / control_rate + SETTLE_GRACE * rate if follow else 0.0
    assert outcome.samples <= outcome.most_samples <= outcome.samples + 2 + late
