"""The options a recording is read by, held once: the CSV layout and the wheel values they
give, and where the poses and the progress go."""

from __future__ import annotations

import math

import numpy as np
import pytest
from robots import BOT
from sinks import Collect

import diffbot
from diffbot.chunk_odometry import ChunkOdometry
from diffbot.conditioning import Conditioning
from diffbot.io.csv_layout import CsvLayout
from diffbot.reading import Reading
from diffbot.samples import wheel_limit

S = 1_000_000_000


def test_an_unknown_feedback_is_refused_when_the_options_are_made() -> None:
    with pytest.raises(diffbot.ParameterError, match="feedback= 'effort'"):
        Reading(feedback="effort")


def test_a_csv_is_read_for_the_field_and_in_the_units_asked() -> None:
    counts = Conditioning(counts_per_rev=4096)
    given = CsvLayout(time_column="stamp", left_columns=("l",), delimiter=";")
    layout = Reading(conditioning=counts, layout=given, feedback="velocity").csv_layout()
    assert layout == CsvLayout("stamp", ("l",), None, ";", None, "velocity", 4096)
    assert Reading().csv_layout() == CsvLayout()
    assert Reading(conditioning=counts).wheel_limit() == wheel_limit("position", 4096)
    assert Reading(feedback="velocity").wheel_limit() == wheel_limit("velocity")


def test_velocities_become_the_angles_the_positions_would_be() -> None:
    # 100 counts a revolution: 100 counts/s held for each second, or positions 100 apart.
    counts = Conditioning(counts_per_rev=100, wrap=0)
    stamps = np.array([0, S, 2 * S], dtype=np.int64)
    present = np.ones((3, 2), dtype=np.bool_)
    by_position = Reading(conditioning=counts).wheel_angles(BOT, ["l", "r"], 1)
    by_velocity = Reading(conditioning=counts, feedback="velocity").wheel_angles(BOT, ["l", "r"], 1)
    positions = np.array([[0.0, 0.0], [100.0, -100.0], [200.0, -200.0]])
    velocities = np.array([[100.0, -100.0]] * 3)
    want = [[0.0, 0.0], [2 * math.pi, -2 * math.pi], [4 * math.pi, -4 * math.pi]]
    np.testing.assert_allclose(by_position.feed(stamps, positions, present), want, atol=1e-12)
    np.testing.assert_allclose(by_velocity.feed(stamps, velocities, present), want, atol=1e-12)
    assert by_velocity.report().counts_per_rev == 100


def test_the_poses_and_the_progress_go_where_they_are_asked() -> None:
    sink, used = Collect(), []
    reading = Reading(sink=sink, progress=used.append)
    odom = ChunkOdometry(BOT)
    stamps = np.array([0, S], dtype=np.int64)
    reading.deliver(odom.feed(stamps, np.array([0.0, 1.0]), np.array([0.0, 1.0])), 7)
    assert [row[0] for row in sink.rows] == [0, S]
    assert used == [7]
    reading.restart()
    assert (sink.rows, sink.restarts) == ([], 1)
    Reading().deliver(odom.feed(stamps + 2 * S, np.array([2.0, 3.0]), np.array([2.0, 3.0])), 7)
    Reading().restart()  # nowhere to go: nothing to do


def test_an_input_read_again_reports_each_part_once() -> None:
    from diffbot.reading import ReadAgain

    told: list[int] = []
    progress = ReadAgain(told.append)
    for used in (3, 4, 2):
        progress(used)
    progress.again()  # read from the start again: nothing new until past the 9 reported
    for used in (5, 3, 4, 6):
        progress(used)
    assert told == [3, 4, 2, 3, 6]
    assert sum(told) == 18
