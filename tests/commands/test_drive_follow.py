"""The followed drive's words: the progress line on a terminal shows the tracking error, and a
run that cannot start says what never came."""

from __future__ import annotations

import io
import sys
from types import SimpleNamespace

import pytest
from click.testing import CliRunner

from diffbot.cli import main
from diffbot.commands.drive_follow import LiveFollow, _not_ready, _progress

REQUEST = LiveFollow(
    law="tracking",
    rate=20.0,
    pose_topic="odom",
    from_odometry=True,
    pose_timeout=0.5,
    cmd_vel="cmd_vel",
    stamped=False,
    frame_id="base_link",
    wait=1.0,
)


class Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_the_progress_line_shows_the_tracking_error(monkeypatch: pytest.MonkeyPatch) -> None:
    terminal = Terminal()
    monkeypatch.setattr(sys, "stderr", terminal)
    with _progress(12.0, quiet=False) as show:
        assert show is not None
        show(1.5, 0.0123)
        show(1.55, 0.5)  # within a tenth of a second of the last: not shown
    assert terminal.getvalue() == "\r   1.50 s of at most 12.0 s, tracking error     12.3 mm\n"


def test_no_progress_line_when_quiet_or_not_a_terminal(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(sys, "stderr", Terminal())
    with _progress(12.0, quiet=True) as show:
        assert show is None
    monkeypatch.setattr(sys, "stderr", io.StringIO())
    with _progress(12.0, quiet=False) as show:
        assert show is None


def test_a_run_that_cannot_start_says_what_never_came() -> None:
    no_pose = SimpleNamespace(pose=None, refusals=SimpleNamespace(total=3))
    assert _not_ready(no_pose, REQUEST) == (  # type: ignore[arg-type]
        "no pose (nav_msgs/Odometry) on 'odom' (3 refused) after 1 s: nothing was commanded"
    )
    no_robot = SimpleNamespace(pose=object(), refusals=SimpleNamespace(total=0))
    assert _not_ready(no_robot, REQUEST) == "no subscriber on cmd_vel after 1 s"  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--follow", "--lead", "-0.1"], "--lead"),
        (["--follow", "--lead", "nan"], "--lead"),
        (["--follow", "--lead", "1e9"], "--lead"),
        (["--lead", "0.2"], "--follow"),
        (["--follow", "pure-pursuit", "--lead", "0.2"], "--lead"),
    ],
)
def test_a_bad_lead_is_one_error_line_before_anything_is_driven(
    args: list[str], message: str
) -> None:
    result = CliRunner().invoke(main, ["drive", "straight 0.2", *args, "--wait", "0.1"])
    assert result.exit_code == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1
    assert lines[0].startswith("error: ")
    assert message in lines[0]


def test_the_lead_reaches_the_follower(monkeypatch: pytest.MonkeyPatch) -> None:
    from diffbot import follow
    from diffbot.commands.drive_follow import drive_follow
    from diffbot.planfile import parse_plan
    from diffbot.trajectory import plan
    from diffbot.urdf import load_params

    made: list[follow.Follower] = []

    class MadeError(Exception):
        pass

    class Recorded(follow.Follower):
        def __init__(self, *args: object, **kwargs: object) -> None:
            super().__init__(*args, **kwargs)  # type: ignore[arg-type]
            made.append(self)
            raise MadeError

    monkeypatch.setattr(follow, "Follower", Recorded)
    params = load_params()
    request = LiveFollow(**{**REQUEST.__dict__, "lead": 0.25})
    made_plan = plan(parse_plan("straight 0.2"), params)
    with pytest.raises(MadeError):
        drive_follow(request, made_plan, params, "plan", announce=False, quiet=True)
    assert [f.lead for f in made] == [0.25]
