"""Several drive wheels per side: each side moves by the mean of its joints present in a
sample, in the CSV columns and in the bulk CDR decoding alike, as the streaming integrator
fed those means."""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np
import pytest
from bags import write_bag
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from robots import SKID

from diffbot.errors import RecordingError
from diffbot.odometry import SKIP_MISSING_JOINT, Odometry
from diffbot.replay import bag_odometry, csv_odometry

JOINTS = (*SKID.left_joints, *SKID.right_joints)

#: One sample: the position of each of the four joints, or None where it is missing.
Sample = tuple[float | None, float | None, float | None, float | None]

cells = st.none() | st.floats(-20.0, 20.0, allow_nan=False) | st.just(-0.0)
samples = st.lists(st.tuples(cells, cells, cells, cells), min_size=1, max_size=25)


def side_mean(values: list[float | None]) -> float | None:
    """A side's angle: its present positions added left to right, divided by their count."""
    present = [v for v in values if v is not None]
    return sum(present) / len(present) if present else None


def reference(rows: list[Sample]) -> Odometry:
    """The streaming integrator fed each sample as a JointState of its present joints (stamps
    0.01 s apart), which averages the joints of each side itself."""
    odom = Odometry(SKID)
    for k, row in enumerate(rows):
        names = [joint for joint, value in zip(JOINTS, row, strict=True) if value is not None]
        values = [value for value in row if value is not None]
        odom.update_joint_state(names, values, k / 100)
    return odom


def bits(values: list[float]) -> list[int]:
    return np.array(values, dtype=np.float64).view(np.int64).tolist()


def check(
    got_pose: list[float], odom: Odometry, skipped: dict[str, int], rows: list[Sample]
) -> None:
    assert bits(got_pose) == bits([*odom.pose, odom.distance])
    missing = sum(
        1 for row in rows if side_mean(list(row[:2])) is None or side_mean(list(row[2:])) is None
    )
    assert skipped.get(SKIP_MISSING_JOINT, 0) == missing


@settings(max_examples=60, deadline=None)
@given(samples)
def test_csv_odometry_averages_the_present_joints_of_each_side(rows: list[Sample]) -> None:
    lines = ["time," + ",".join(JOINTS)]
    for k, row in enumerate(rows):
        lines.append(f"{k / 100!r}," + ",".join("" if v is None else repr(v) for v in row))
    text = "\n".join(lines) + "\n"
    odom = reference(rows)
    if odom.samples == 0:
        with pytest.raises(RecordingError, match="no usable sample"):
            csv_odometry(io.StringIO(text, newline=""), SKID)
        return
    got = csv_odometry(io.StringIO(text, newline=""), SKID, chunk_bytes=97).summary
    check([*got.final_pose, got.distance], odom, dict(got.skipped), rows)


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(samples, st.sampled_from(["sqlite3", "mcap"]))
def test_bag_odometry_averages_the_present_joints_of_each_side(
    tmp_path_factory: pytest.TempPathFactory, rows: list[Sample], storage: str
) -> None:
    messages = []
    for k, row in enumerate(rows):
        names = [j for j, v in zip(JOINTS, row, strict=True) if v is not None]
        values = [v for v in row if v is not None]
        stamp = 10**9 + k * 10**7
        messages.append((stamp, stamp, names, values))
    path = write_bag(tmp_path_factory.mktemp("bag") / "rec", messages, storage=storage)
    odom = reference(rows)
    if odom.samples == 0:
        with pytest.raises(RecordingError, match="no usable sample"):
            bag_odometry(path, SKID)
        return
    got = bag_odometry(path, SKID, chunk_size=4).summary
    check([*got.final_pose, got.distance], odom, dict(got.skipped), rows)


def test_a_csv_needs_a_column_for_each_side(tmp_path: Path) -> None:
    path = tmp_path / "a.csv"
    path.write_text("time,front_left,rear_left\n0,1,2\n", encoding="utf-8")
    with pytest.raises(RecordingError, match="no column for the right wheel joint 'front_right'"):
        csv_odometry(path, SKID)


def test_a_wheel_missing_from_a_row_moves_its_side_by_the_others_motion() -> None:
    # Encoders from their own zeros (100 and 0 rad left, 0 and 50 right), all turning at
    # 1 rad/s straight ahead; one row lacks the second left wheel. The mean of the angles
    # present would jump by 50 rad there: a false turn, a distance 17 times too long.
    lines = ["time," + ",".join(JOINTS)]
    for k in range(31):
        t = k / 10
        row = [100.0 + t, t, t, 50.0 + t]
        cells = [repr(v) for v in row]
        if k == 15:
            cells[1] = ""
        lines.append(f"{t!r}," + ",".join(cells))
    text = "\n".join(lines) + "\n"
    got = csv_odometry(io.StringIO(text, newline=""), SKID).summary
    radius = SKID.wheel_radius
    assert got.final_pose.x == pytest.approx(3.0 * radius, abs=1e-12)
    assert got.final_pose.y == pytest.approx(0.0, abs=1e-12)
    assert got.final_pose.theta == pytest.approx(0.0, abs=1e-12)
    assert got.distance == pytest.approx(3.0 * radius, abs=1e-12)
