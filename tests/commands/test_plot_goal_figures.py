"""The goal-plan figures of docs/goal-plans.md: what ``diffbot plot --to`` draws, pixel by pixel."""

from __future__ import annotations

import struct
from pathlib import Path

import pytest
from extras import need
from figures import axes_labelled, near, png_pixels

from diffbot.goals import plan_to
from diffbot.kinematics import DiffDriveParams
from diffbot.trajectory import pose_at

need("matplotlib")

IMAGES = Path(__file__).resolve().parents[2] / "docs" / "img"
#: The page's goal: 10 cm to the left, same heading; arcs of 10 cm.
GOAL = (0.0, 0.1, 0.0)
SHAPES = {
    "fastest": "goal_fastest.png",
    "spin-straight-spin": "goal_spin_straight_spin.png",
    "dubins": "goal_dubins.png",
    "reeds-shepp": "goal_reeds_shepp.png",
}


@pytest.mark.parametrize(("shape", "name"), SHAPES.items())
def test_the_page_shows_each_shapes_path(shape: str, name: str, params: DiffDriveParams) -> None:
    from diffbot.plotting import PATH_COLOUR, plan_figure

    image_file = IMAGES / name
    header = image_file.read_bytes()[:24]
    assert struct.unpack(">II", header[16:24]) == (800, 900)  # the size plot writes
    assert image_file.stat().st_size < 40_000
    image = png_pixels(image_file)
    p = plan_to(GOAL, params, shape=shape, min_radius=0.1)  # type: ignore[arg-type]
    layout = plan_figure(p, params)
    layout.canvas.draw()
    path = axes_labelled(layout, "path")
    # Along every segment that moves, the drawn path passes where the plan is at that time.
    start = 0.0
    checked = 0
    for planned in p.segments:
        if planned.kind != "spin":
            for fraction in (0.3, 0.5, 0.7):
                pose = pose_at(p, start + fraction * planned.duration)
                assert near(image, path, pose.x, pose.y, PATH_COLOUR, tolerance=24), (pose, shape)
                checked += 1
        start += planned.duration
    assert checked >= 3
    # Where no shape goes: right of the goal by 4 cm, level with the start and the goal's middle.
    assert not near(image, path, 0.04, 0.05, PATH_COLOUR, radius=2, tolerance=24)
