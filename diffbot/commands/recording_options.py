"""The options of the commands that read recordings (``odom``, ``calibrate fit``, ``plot
--odom``): how the recorded positions are to be read, and the messages about what was done to
them."""

from __future__ import annotations

import sys
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import click

from diffbot.commands.options import F, FiniteFloat, RobotOptions, fail, option_group, warn
from diffbot.errors import EXIT_CHECK_FAILED
from diffbot.formats.text import fmt

if TYPE_CHECKING:
    from diffbot.conditioning import Conditioning, ConditioningReport
    from diffbot.io.csv_chunks import CsvLayout
    from diffbot.kinematics import DiffDriveParams
    from diffbot.samples import Recording

__all__ = [
    "RecordingOptions",
    "conditioning_lines",
    "exit_if_implausible",
    "has_implausible_steps",
    "recording_options",
    "robot_label",
    "skipped_text",
    "warn_conditioning",
    "warn_notes",
]


#: The CSV options, named as the library's readers name them.
_CSV_OPTIONS = ("time_column", "left_column", "right_column", "delimiter", "time_unit")


@dataclass(frozen=True)
class RecordingOptions:
    """How to read the positions of a recording.

    Attributes:
        counts_per_rev: encoder counts per revolution (None: radians).
        wrap: a counter's modulus (None: detected; 0: none).
        time_column: a CSV's time column.
        left_column: a CSV's left wheel column(s), comma-separated.
        right_column: a CSV's right wheel column(s).
        delimiter: a CSV's delimiter.
        time_unit: a CSV's time unit.
        feedback: ``position`` or ``velocity`` (None: see :meth:`feedback_for`).
    """

    counts_per_rev: float | None = None
    wrap: float | None = None
    time_column: str | None = None
    left_column: str | None = None
    right_column: str | None = None
    delimiter: str | None = None
    time_unit: str | None = None
    feedback: str | None = None

    def feedback_for(self, params: DiffDriveParams) -> str:
        """``--feedback``, else the controller's ``position_feedback``, else ``position``; a
        ``--wrap`` with velocities is refused (a counter wraps its positions, not its rates)."""
        feedback = self.feedback
        if feedback is None:
            controller = params.controller
            velocity = controller is not None and controller.position_feedback is False
            feedback = "velocity" if velocity else "position"
        if feedback == "velocity" and self.wrap is not None:
            fail(
                "--wrap is the modulus of a counter's positions: wheel velocities (--feedback "
                "velocity) do not wrap"
            )
        return feedback

    def csv(self) -> dict[str, str | None]:
        """The CSV options as :func:`~diffbot.recordings.read_recording` takes them (the
        fields of the same names)."""
        return {name: getattr(self, name) for name in _CSV_OPTIONS}

    def read(self, source: str, params: DiffDriveParams, topic: str | None) -> Recording:
        """A recording read whole with these options, what was judged or found said on
        stderr."""
        from diffbot.recordings import read_recording

        recording = read_recording(
            source,
            params,
            topic,
            feedback=self.feedback_for(params),
            conditioning=self.conditioning(),
            time_column=self.time_column,
            left_column=self.left_column,
            right_column=self.right_column,
            delimiter=self.delimiter,
            time_unit=self.time_unit,
        )
        warn_notes(recording.notes, source)
        skipped = sum(recording.skipped.values())
        if skipped:
            warn(
                f"{source}: skipped {skipped} of {len(recording.samples) + skipped} samples: "
                f"{skipped_text(recording.skipped)}"
            )
        if recording.conditioning is not None:
            warn_conditioning(recording.conditioning, source)
        return recording

    def check_robot(self, robot: RobotOptions, params: DiffDriveParams) -> None:
        """Refuse wheel columns that name none of the robot's joints when no robot is given (any
        one of them: one wheel of another robot is enough to put its path out).

        Columns chosen by option are read with the robot's geometry whatever they are called:
        with the bundled robot taken by default, another robot's wheels would give a path of
        the wrong size and turns of the wrong angle, and nothing would say so.
        """
        if robot_label(robot) != "bundled" or None not in (
            robot.wheel_radius,
            robot.wheel_separation,
        ):
            return
        named = [
            name.strip()
            for option in (self.left_column, self.right_column)
            if option
            for name in option.split(",")
        ]
        from diffbot.io.csv_layout import names_joint

        joints = (*params.left_joints, *params.right_joints)
        foreign = [
            name
            for name in named
            if not any(
                names_joint(name, joint, field)
                for joint in joints
                for field in ("position", "velocity")
            )
        ]
        if not foreign:
            return
        fail(
            f"the wheel column{'s' if len(foreign) > 1 else ''} "
            f"{', '.join(repr(n) for n in foreign)} name{'' if len(foreign) > 1 else 's'} none "
            f"of the bundled robot's wheel joints ({', '.join(joints)}): give the robot that "
            "recorded them (--robot PATH), or its --wheel-radius and --wheel-separation"
        )

    def layout(self) -> CsvLayout:
        """The CSV options as a :class:`~diffbot.io.csv_chunks.CsvLayout`."""
        from diffbot.io.recordings import csv_layout

        return csv_layout(**self.csv())

    def conditioning(self) -> Conditioning:
        """The library's :class:`~diffbot.conditioning.Conditioning`."""
        from diffbot.conditioning import Conditioning

        return Conditioning(self.counts_per_rev, self.wrap)


#: What odometry integrates, for the commands that read wheel feedback (recorded or live).
feedback_option = click.option(
    "--feedback",
    type=click.Choice(["position", "velocity"]),
    help="Integrate the wheel joints' positions or their velocities (as "
    "diff_drive_controller does with position_feedback: false). Default: the controllers "
    "file's position_feedback when one is given or found, else position.",
)

_OPTIONS = [
    click.option(
        "--counts-per-rev",
        type=FiniteFloat(0.0, open_min=True),
        metavar="N",
        help="The positions are encoder counts, N per wheel revolution (default: radians).",
    ),
    click.option(
        "--wrap",
        type=FiniteFloat(0.0),
        metavar="N",
        help="The positions come from a counter that wraps at N (65536 for 16 bits; a step "
        "beyond ±N/2 is a wrap). Default: detected by itself, and said so; 0: no wrap.",
    ),
    click.option(
        "--time-column",
        metavar="NAME",
        help="A CSV's time column (default: the one named time, stamp, t or __time).",
    ),
    click.option(
        "--left-column",
        metavar="NAME[,NAME]",
        help="A CSV's left wheel column(s), positions or with --feedback velocity velocities "
        "(default: named by the joints).",
    ),
    click.option(
        "--right-column",
        metavar="NAME[,NAME]",
        help="A CSV's right wheel column(s), positions or with --feedback velocity velocities "
        "(default: named by the joints).",
    ),
    click.option(
        "--delimiter",
        metavar="C",
        help="A CSV's delimiter (default: a comma, or the ; tab or | that splits the header).",
    ),
    click.option(
        "--time-unit",
        type=click.Choice(["s", "ms", "us", "ns"]),
        help="A CSV's time unit (default: seconds, or as the first stamp's size says, and "
        "said so).",
    ),
    feedback_option,
]

_FIELDS = (
    "counts_per_rev",
    "wrap",
    "time_column",
    "left_column",
    "right_column",
    "delimiter",
    "time_unit",
    "feedback",
)


def _from(kwargs: dict[str, Any]) -> RecordingOptions:
    return RecordingOptions(**{name: kwargs.pop(name) for name in _FIELDS})


def recording_options(command: F) -> F:
    """Add the recording options; the command receives ``recording: RecordingOptions``."""
    decorate: Callable[[F], F] = option_group(_OPTIONS, "recording", _from)
    return decorate(command)


def _number(value: float) -> str:
    return str(int(value)) if value == int(value) else repr(value)


def conditioning_lines(report: ConditioningReport) -> list[tuple[str, str]]:
    """The summary rows saying how the positions were read (none for plain radians)."""
    parts = []
    if report.counts_per_rev is not None:
        parts.append(f"encoder counts, {_number(report.counts_per_rev)} per revolution")
    if report.wrap is not None:
        how = "detected" if report.wrap_detected else "--wrap"
        parts.append(
            f"wrapping at {_number(report.wrap)} ({how}), {report.wraps} "
            f"wrap{'s' if report.wraps != 1 else ''} undone"
        )
    return [("positions", "; ".join(parts))] if parts else []


def skipped_text(skipped: Mapping[str, int]) -> str:
    """How many samples were skipped for each reason, in words."""
    return ", ".join(f"{count} {reason}" for reason, count in sorted(skipped.items()))


def warn_notes(notes: tuple[str, ...], source: str) -> None:
    """What the reader judged by itself, on stderr (the options that choose it instead)."""
    for note in notes:
        if "stamps" in note:
            warn(f"{source}: {note}; --time-unit to choose")
        elif "separated" in note:
            warn(f"{source}: {note}; --delimiter to choose")
        else:
            warn(f"{source}: {note}")


def warn_conditioning(report: ConditioningReport, source: str, *, commands: bool = False) -> None:
    """Warnings on stderr for a detected wrap and for implausible steps (of the wheels that
    ``commands``, velocity commands integrated open loop, would turn, when True)."""
    if report.wrap_detected and report.wrap is not None:
        warn(
            f"{source}: the wheel positions wrap around at {_number(report.wrap)} (a counter, "
            f"detected by itself): {report.wraps} wraps undone; give --wrap "
            f"{_number(report.wrap)} to say so, or --wrap 0 if they do not wrap"
        )
    first = report.first_implausible
    if first is not None:
        limit = max(report.speed_limit)
        # Commands have no encoder to blame: they ask for more than the wheels can turn.
        cause = "commands the wheels cannot follow" if commands else _cause(report)
        warn(
            f"{source}: {report.implausible_steps} implausible "
            f"step{'s' if report.implausible_steps != 1 else ''} (a wheel faster than "
            f"{fmt(limit, 4)} rad/s: {report.limit_source}); the first ends at "
            f"sample {first.sample}, t {fmt(first.seconds, 6)} s ({first.joint} at "
            f"{fmt(first.speed, 4)} rad/s): the pose is not to be trusted ({cause})"
        )


def has_implausible_steps(report: ConditioningReport) -> bool:
    """Whether a recording's pose is not to be trusted: a step of it was implausible (the
    warning of :func:`warn_conditioning` says which)."""
    return report.implausible_steps > 0


def exit_if_implausible(reports: Iterable[ConditioningReport]) -> None:
    """Exit 1 once a command's output is given when any recording read had an implausible
    step: the pose it gave is not to be trusted. Of several recordings, a last warning says how
    many (as ``odom`` of several inputs says it)."""
    read = list(reports)
    implausible = sum(has_implausible_steps(report) for report in read)
    if not implausible:
        return
    if len(read) > 1:
        warn(f"{implausible} of {len(read)} recordings have implausible steps")
    sys.exit(EXIT_CHECK_FAILED)


def _cause(report: ConditioningReport) -> str:
    """What may make steps implausible, short of the options already given."""
    if report.counts_per_rev is None:
        return "encoder counts? --counts-per-rev, --wrap"
    if report.wrap is None:
        return "a counter that wraps? --wrap; or --counts-per-rev too small"
    return "a jump in the counts, or --counts-per-rev too small"


def robot_label(robot: RobotOptions) -> str:
    """Which robot a result used, as ``--json``'s ``robot`` says it: the description's path,
    ``"bundled"``, or ``"options"`` when the joint and geometry options alone define it."""
    if robot.robot is not None:
        return robot.robot
    given = (robot.left_joint, robot.right_joint, robot.wheel_radius, robot.wheel_separation)
    return "bundled" if None in given else "options"
