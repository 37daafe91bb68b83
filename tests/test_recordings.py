"""``diffbot.read_recording`` takes the recording options by the names the command line gives
them: ``counts_per_rev=`` and ``wrap=`` beside ``time_column=`` and the others."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

import diffbot
from diffbot.conditioning import Conditioning
from diffbot.errors import ParameterError

COUNTS_PER_REV = 1000.0
WRAP = 256.0


def counter_csv(folder: Path) -> Path:
    """Two wheels counted by an 8-bit counter (1000 counts per revolution): from 250 on, 16
    counts forward each step, wrapping past 255."""
    rows = ["t,L,R"]
    for step in range(6):
        count = (250 + 16 * step) % 256
        rows.append(f"{step * 0.1:.1f},{count},{count}")
    path = folder / "counts.csv"
    path.write_text("\n".join(rows) + "\n", encoding="utf-8")
    return path


def test_counts_and_wrap_are_keywords_as_on_the_command_line(tmp_path: Path) -> None:
    params = diffbot.load_params()
    path = counter_csv(tmp_path)
    columns = {"left_column": "L", "right_column": "R"}
    recording = diffbot.read_recording(
        path, params, counts_per_rev=COUNTS_PER_REV, wrap=WRAP, **columns
    )
    conditioned = diffbot.read_recording(
        path, params, conditioning=Conditioning(COUNTS_PER_REV, WRAP), **columns
    )
    assert list(recording.samples) == list(conditioned.samples)
    assert recording.conditioning is not None
    assert recording.conditioning.counts_per_rev == COUNTS_PER_REV
    assert recording.conditioning.wrap == WRAP
    assert recording.conditioning.wraps == 2  # one per wheel
    first, last = recording.samples[0].positions, recording.samples[-1].positions
    turned = 5 * 16 / COUNTS_PER_REV * 2 * math.pi
    assert [b - a for a, b in zip(first, last, strict=True)] == pytest.approx([turned, turned])


def test_counts_beside_a_conditioning_are_refused(tmp_path: Path) -> None:
    with pytest.raises(ParameterError, match="not both"):
        diffbot.read_recording(
            counter_csv(tmp_path),
            diffbot.load_params(),
            conditioning=Conditioning(COUNTS_PER_REV),
            counts_per_rev=COUNTS_PER_REV,
            left_column="L",
            right_column="R",
        )


def test_counts_per_rev_out_of_range_is_refused(tmp_path: Path) -> None:
    with pytest.raises(ParameterError):
        diffbot.read_recording(
            counter_csv(tmp_path), diffbot.load_params(), counts_per_rev=0.0, left_column="L"
        )
