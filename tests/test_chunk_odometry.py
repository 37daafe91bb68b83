"""Chunked odometry against the streaming integrator, sample by sample and bit for bit."""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from robots import MIRRORED

from diffbot.chunk_odometry import ChunkOdometry, seconds_since
from diffbot.errors import ParameterError, RecordingError
from diffbot.kinematics import Pose
from diffbot.odometry import (
    SKIP_MISSING_JOINT,
    SKIP_NOT_FINITE,
    SKIP_STAMP_NOT_AFTER,
    Odometry,
)

Sample = tuple[int, float, float, bool]

positions = st.floats(-50.0, 50.0) | st.sampled_from(
    [0.0, -0.0, float("nan"), float("inf"), -float("inf")]
)


@st.composite
def recordings(draw: st.DrawFn) -> list[Sample]:
    """Samples whose stamps mostly rise, with repeats, steps back and big jumps among them."""
    stamp = draw(st.integers(-(2**62), 2**62))
    out = []
    for _ in range(draw(st.integers(0, 40))):
        stamp += draw(
            st.sampled_from([10_000_000, 1, 0, -5_000_000])
            | st.integers(-(10**9), 10**9)
            | st.sampled_from([2**54, 2**60])
        )
        stamp = max(min(stamp, 2**63 - 1), -(2**63))
        out.append((stamp, draw(positions), draw(positions), draw(st.booleans() | st.just(True))))
    return out


def streaming(samples: Sequence[Sample]) -> tuple[Odometry, list[tuple[int, float, float, float]]]:
    """The odometry of the samples as the recording reader runs it: stamps as seconds since the
    first sample, a sample without both wheels given by name without the missing one."""
    odom = Odometry(MIRRORED, 0.5, -0.25, 3.0)
    origin = samples[0][0] if samples else 0
    rows = []
    for stamp_ns, left, right, both in samples:
        names, values = (["right", "left"], [right, left]) if both else (["left"], [left])
        if odom.update_joint_state(names, values, (stamp_ns - origin) / 10**9):
            rows.append((stamp_ns, odom.pose.x, odom.pose.y, odom.heading))
    return odom, rows


def chunked(
    samples: Sequence[Sample], cuts: Sequence[int]
) -> tuple[ChunkOdometry, list[tuple[int, float, float, float]]]:
    odom = ChunkOdometry(MIRRORED, 0.5, -0.25, 3.0)
    rows: list[tuple[int, float, float, float]] = []
    bounds = [0, *sorted({min(c, len(samples)) for c in cuts}), len(samples)]
    for a, b in itertools.pairwise(bounds):
        part = samples[a:b]
        poses = odom.feed(
            np.array([s[0] for s in part], dtype=np.int64),
            [s[1] for s in part],
            [s[2] for s in part],
            [s[3] for s in part],
        )
        rows += zip(
            poses.stamp_ns.tolist(),
            poses.x.tolist(),
            poses.y.tolist(),
            poses.heading.tolist(),
            strict=True,
        )
    return odom, rows


def bits(values: Sequence[float]) -> list[int]:
    return [int(v) for v in np.array(values, dtype=np.float64).view(np.int64)]


@settings(max_examples=120, deadline=None)
@given(recordings(), st.lists(st.integers(0, 40), max_size=5))
def test_chunked_run_equals_streaming_run_bit_for_bit_wherever_the_chunks_end(
    samples: list[Sample], cuts: list[int]
) -> None:
    want, want_rows = streaming(samples)
    got, got_rows = chunked(samples, cuts)
    assert [r[0] for r in got_rows] == [r[0] for r in want_rows]
    for k in (1, 2, 3):
        assert bits([r[k] for r in got_rows]) == bits([r[k] for r in want_rows])
    if not want_rows:
        with pytest.raises(RecordingError, match="no usable sample"):
            got.summary("rec")
        return
    summary = got.summary("rec")
    assert bits([*summary.final_pose, summary.heading]) == bits([*want.pose, want.heading])
    got_motion = [float(summary.twist.linear), float(summary.twist.angular), summary.distance]
    want_motion = [float(want.twist.linear), float(want.twist.angular), want.distance]
    assert bits(got_motion) == bits(want_motion)
    assert summary.samples == want.samples
    assert summary.skipped == want.skipped
    assert summary.duration == (want_rows[-1][0] - want_rows[0][0]) / 10**9


def test_skip_reasons_are_the_streaming_integrators_own() -> None:
    odom = Odometry(MIRRORED)
    odom.update_joint_state(["left"], [0.0], 0.0)
    odom.update_joint_state(["left", "right"], [math.nan, 0.0], 0.0)
    odom.update_joint_state(["left", "right"], [0.0, 0.0], 1.0)
    odom.update_joint_state(["left", "right"], [0.0, 0.0], 1.0)
    assert set(odom.skipped) == {SKIP_MISSING_JOINT, SKIP_NOT_FINITE, SKIP_STAMP_NOT_AFTER}


def test_a_quarter_circle_ends_at_its_closed_form_pose() -> None:
    # The right wheel alone turns: the robot pivots about the left wheel, radius b/2 for its
    # centre. Right sign -1, so the right joint turns negatively to roll forward.
    b, r = MIRRORED.wheel_separation, MIRRORED.wheel_radius
    turn = math.pi / 2  # heading change (rad)
    right = -np.linspace(0.0, turn * b / r, 101)
    odom = ChunkOdometry(MIRRORED)
    for part in np.array_split(np.arange(101), 4):
        odom.feed(part * 10_000_000, np.zeros(part.size), right[part])
    pose = odom.summary("rec").final_pose
    assert pose.x == pytest.approx(b / 2, abs=1e-12)
    assert pose.y == pytest.approx(b / 2, abs=1e-12)
    assert math.remainder(pose.theta - turn, math.tau) == pytest.approx(0.0, abs=1e-12)


def test_seconds_since_rounds_like_python_beyond_two_to_the_53() -> None:
    stamps = [2**62 + 1, -(2**63), 2**63 - 1, 12_345]
    got = seconds_since(np.array(stamps, dtype=np.int64), -(2**62) + 3)
    assert got.tolist() == [(s - (-(2**62) + 3)) / 10**9 for s in stamps]


def test_an_empty_recording_has_no_usable_sample() -> None:
    odom = ChunkOdometry(MIRRORED)
    odom.feed(np.empty(0, dtype=np.int64), [], [])
    odom.skip("unreadable value", 2)
    with pytest.raises(
        RecordingError, match=r"rec: no usable sample \(skipped: unreadable value: 2\)"
    ):
        odom.summary("rec")


def test_a_non_finite_start_pose_is_refused() -> None:
    with pytest.raises(ParameterError, match="theta must be a finite number"):
        ChunkOdometry(MIRRORED, theta=math.inf)


def test_the_start_pose_is_the_pose_at_the_baseline() -> None:
    odom = ChunkOdometry(MIRRORED, 1.0, 2.0, 3.0)
    odom.feed([5], [0.3], [0.7])
    assert odom.summary("rec").final_pose == Pose(1.0, 2.0, 3.0)
