"""What the commands share: number types, the robot options, descriptions among arguments.

The library never imports click: commands convert their arguments here, call the library, and
format its results. Path types and output options are :mod:`diffbot.commands.paths`'; errors
and messages :mod:`diffbot.commands.messages`'.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import click

from diffbot.commands.messages import InputError as InputError
from diffbot.commands.messages import emit_json as emit_json
from diffbot.commands.messages import fail as fail
from diffbot.commands.messages import no_such_option as no_such_option
from diffbot.commands.messages import warn as warn
from diffbot.commands.option_groups import F as F
from diffbot.commands.option_groups import option_group as option_group
from diffbot.commands.paths import OUTPUT_NAMES as OUTPUT_NAMES
from diffbot.commands.paths import InputPath, PackageDir, input_path
from diffbot.commands.paths import OutOptions as OutOptions
from diffbot.commands.paths import check_out as check_out
from diffbot.commands.paths import named_output as named_output
from diffbot.commands.paths import out_options as out_options
from diffbot.commands.paths import output_option as output_option
from diffbot.commands.robot_path import (
    is_controllers_file,
    is_launch_file,
    is_package_folder,
    not_a_description,
)
from diffbot.commands.said_once import say_warnings
from diffbot.commands.shown_defaults import choice_option, name_option
from diffbot.errors import DescriptionError
from diffbot.io.pathnames import resolved
from diffbot.io.textfile import open_regular
from diffbot.io.xmlhead import root_name
from diffbot.kinematics import DiffDriveParams, rad_s_from_rpm, rpm_from_rad_s
from diffbot.numbers import (
    MAX_COUNT,
    MAX_NOISE,
    MAX_PLAN_DURATION,
    MAX_TIMER_RATE,
    MOTOR_LIMIT_RANGE,
    WHEEL_SIZE_RANGE,
    written_form,
    written_number,
)
from diffbot.urdf import load_params
from diffbot.urdf.sources import SOURCE_MODES


class CheckedNumber(click.ParamType):  # type: ignore[type-arg,unused-ignore]
    """Base of the types of every numeric option and argument: each refuses, as click converts
    it, NaN, infinities, and values outside its range (integers of sane size)."""


class FiniteFloat(CheckedNumber):
    """A finite float, optionally bounded; rejects NaN and infinities."""

    name = "number"

    def __init__(
        self,
        minimum: float | None = None,
        open_min: bool = False,
        maximum: float | None = None,
        unit: str = "",
    ) -> None:
        self.minimum = minimum
        self.open_min = open_min
        self.maximum = maximum
        self.unit = f" {unit}" if unit else ""

    def convert(
        self, value: Any, param: click.Parameter | None, ctx: click.Context | None
    ) -> float:
        if isinstance(value, float):
            number = value
        else:
            try:
                number = written_number(str(value).strip())
            except ValueError:
                self.fail(f"{value!r} is not a number", param, ctx)
        if not math.isfinite(number):
            self.fail(f"{value!r} is not a finite number", param, ctx)
        if self.minimum is not None:
            if self.open_min and number <= self.minimum:
                self.fail(f"{value!r} must be > {self.minimum:g}", param, ctx)
            if not self.open_min and number < self.minimum:
                self.fail(f"{value!r} must be >= {self.minimum:g}", param, ctx)
        if self.maximum is not None and number > self.maximum:
            self.fail(f"{value!r} must be <= {self.maximum:g}{self.unit}", param, ctx)
        return number


#: The fastest motor limit an option takes, as --help writes it (rpm, rounded down).
_MOST_RPM = f"{math.floor(rpm_from_rad_s(MOTOR_LIMIT_RANGE[1]) * 100) / 100:.2f}"


class MotorLimit(FiniteFloat):
    """A motor limit in rpm, within :data:`diffbot.numbers.MOTOR_LIMIT_RANGE` once in rad/s:
    above 0, no faster than a wheel turns, and not so small that it divides wrong."""

    name = "rpm"

    def __init__(self) -> None:
        super().__init__(0.0, open_min=True)

    def convert(
        self, value: Any, param: click.Parameter | None, ctx: click.Context | None
    ) -> float:
        number = super().convert(value, param, ctx)
        low, high = MOTOR_LIMIT_RANGE
        if rad_s_from_rpm(number) > high:
            self.fail(
                f"{value!r} is faster than any wheel turns: a motor limit is at most "
                f"{_MOST_RPM} rpm ({high:g} rad/s)",
                param,
                ctx,
            )
        if rad_s_from_rpm(number) < low:
            self.fail(f"{value!r} is too small to compute with", param, ctx)
        return number


class NumberPair(CheckedNumber):
    """Two finite numbers, comma-separated (``X,Y``), optionally both positive."""

    def __init__(
        self,
        name: str,
        unit: str,
        *,
        positive: bool = False,
        bounds: tuple[float, float] | None = None,
    ) -> None:
        self.name = name
        self.unit = unit
        self.positive = positive
        self.bounds = bounds

    def convert(
        self, value: Any, param: click.Parameter | None, ctx: click.Context | None
    ) -> tuple[float, float]:
        if isinstance(value, tuple):
            return value
        parts = str(value).split(",")
        kind = "positive numbers" if self.positive else "numbers"
        if len(parts) != 2:
            self.fail(
                f"{value!r} is not {self.name}: two {kind} ({self.unit}), comma-separated",
                param,
                ctx,
            )
        numbers = []
        for part in parts:
            try:
                number = written_number(part.strip())
            except ValueError:
                self.fail(f"{value!r}: {part.strip()!r} is not a number", param, ctx)
            if not math.isfinite(number):
                self.fail(f"{value!r}: {part.strip()!r} is not a finite number", param, ctx)
            numbers.append(number)
        first, second = numbers
        if self.positive and not (first > 0.0 and second > 0.0):
            self.fail(f"{value!r}: both must be > 0", param, ctx)
        if self.bounds is not None:
            low, high = self.bounds
            if not (low <= first <= high and low <= second <= high):
                self.fail(
                    f"{value!r}: both must be from {low:g} to {high:g} {self.unit}", param, ctx
                )
        return first, second


class Count(click.IntRange, CheckedNumber):  # type: ignore[type-arg,unused-ignore,misc]
    """A whole number from ``minimum`` to ``maximum`` (both given: no count is unbounded)."""

    def __init__(self, minimum: int, maximum: int = MAX_COUNT) -> None:
        super().__init__(min=minimum, max=maximum)

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> Any:
        if isinstance(value, str) and not written_form(value.strip()):
            self.fail(f"{value!r} is not a valid integer.", param, ctx)
        return super().convert(value, param, ctx)


class Names(click.Choice):  # type: ignore[type-arg,unused-ignore]
    """One of a few names, in any case; a wrong one is told the names as the help spells them
    (click's own message would give them in lower case)."""

    def __init__(self, names: Sequence[str]) -> None:
        super().__init__(list(names), case_sensitive=False)

    def get_invalid_choice_message(self, value: Any, ctx: click.Context | None) -> str:
        return f"{value!r} is not one of {', '.join(map(str, self.choices))}."


POSITIVE = FiniteFloat(0.0, open_min=True)
#: A wheel radius or separation of a real robot (m).
WHEEL_SIZE = FiniteFloat(WHEEL_SIZE_RANGE[0], maximum=WHEEL_SIZE_RANGE[1])
#: Highest --rate of the ros2 script and of a live node (Hz): 'ros2 topic pub' is a Python loop,
#: far from this fast, and so is a node.
MAX_PUBLISH_RATE = MAX_TIMER_RATE
#: Lowest command --rate (Hz): one command per longest plan.
MIN_COMMAND_RATE = 1.0 / MAX_PLAN_DURATION


def check_finite(what: str, *values: float) -> None:
    """Bad input when a result overflows to inf or NaN (inputs too large to compute with)."""
    if not all(math.isfinite(v) for v in values):
        fail(f"the {what} overflow: the inputs are too large to compute with")


def parse_number(token: str, what: str) -> float:
    """A finite float from a command-line token, or a bad-input error naming it."""
    try:
        number = written_number(token)
    except ValueError:
        if token.startswith("-"):
            no_such_option(token)
        fail(f"{what}: {token!r} is not a number")
    if not math.isfinite(number):
        fail(f"{what}: {token!r} is not a finite number")
    return number


def _looks_like_option(token: str) -> bool:
    """``-x`` or ``--xyz``; not ``-``, nor a negative value such as ``-90``, ``-.5`` or
    ``-90deg`` (a sign and a digit or a dot: commands give those their own messages)."""
    if not token.startswith("-") or token == "-" or token[1] in "0123456789.":
        return False
    try:
        written_number(token)
    except ValueError:
        return True
    return False


def split_xacro_args(tokens: Sequence[str]) -> tuple[list[str], dict[str, str]]:
    """Separate ``NAME:=VALUE`` xacro arguments from the other positional tokens.

    Commands that take negative numbers let unknown options through as tokens; a token that
    looks like an option but is no number is reported here as the unknown option it is.
    """
    rest: list[str] = []
    args: dict[str, str] = {}
    for token in tokens:
        if _looks_like_option(token) and ":=" not in token:
            no_such_option(token)
        if ":=" in token:
            name, _, value = token.partition(":=")
            if not name or not name.replace("_", "a").replace("-", "a").isalnum():
                fail(f"bad xacro argument {token!r}: expected NAME:=VALUE")
            args[name] = value
        else:
            rest.append(token)
    return rest, args


def parse_packages(values: Sequence[tuple[str, str]]) -> dict[str, str]:
    """``--package NAME=DIR`` values (of :class:`~diffbot.commands.paths.PackageDir`) as a
    mapping."""
    return dict(values)


# --------------------------------------------------------------------------------------------
# Robot options, shared by every command that needs a robot


@dataclass(frozen=True)
class RobotOptions:
    """What the shared robot options say; :meth:`load` turns them into parameters."""

    robot: str | None
    xacro_args: Mapping[str, str]
    packages: Mapping[str, str]
    left_joint: str | None
    right_joint: str | None
    wheel_radius: float | None
    wheel_separation: float | None
    max_rpm: float | None
    controllers: str | None = None
    controller: str | None = None
    trust: bool = False
    source: str = "auto"
    no_controllers: bool = False

    def with_path(self, path: str | None, xacro_args: Mapping[str, str]) -> RobotOptions:
        """The same options with a positional PATH and ``NAME:=VALUE`` tokens merged in."""
        if path is not None and self.robot is not None and path != self.robot:
            fail(f"two robots given: {path!r} and --robot {self.robot!r}")
        robot = input_path(path) if path is not None else self.robot
        return dataclasses.replace(self, robot=robot, xacro_args={**self.xacro_args, **xacro_args})

    def with_tokens(self, tokens: Sequence[str], what: str = "PATH") -> RobotOptions:
        """The same options with the description and the ``NAME:=VALUE`` xacro arguments
        among a command's positional ``tokens`` merged in (at most one description, ``what``
        in the message)."""
        rest, xacro_args = split_xacro_args(tokens)
        if len(rest) > 1:
            fail(f"expected at most one {what}, got {rest}")
        return self.with_path(rest[0] if rest else None, xacro_args)

    def load(self, *, quiet: bool = False) -> DiffDriveParams:
        """Load the robot; print its warnings on stderr unless ``quiet`` (once in full for a
        description, then as one line: :func:`~diffbot.commands.said_once.say_warnings`)."""
        if self.robot is not None:
            path = Path(self.robot)
            if not path.exists():
                fail(f"{self.robot}: no such file")
            problem = not_a_description(self.robot)
            if problem is not None:
                fail(problem)
        params = load_params(
            self.robot,
            self.xacro_args,
            self.packages,
            left_joint=self.left_joint,
            right_joint=self.right_joint,
            wheel_radius=self.wheel_radius,
            wheel_separation=self.wheel_separation,
            max_wheel_speed=None if self.max_rpm is None else rad_s_from_rpm(self.max_rpm),
            controllers=self.controllers,
            controller=self.controller,
            trust=self.trust,
            source=self.source,
            no_controllers=self.no_controllers,
        )
        if not quiet:
            say_warnings(params.warnings, params.source, self.robot, self.params_command())
        return params

    def params_command(self) -> list[str]:
        """The words of the ``diffbot params`` command that loads this description as given:
        its path, xacro arguments, packages and controllers file."""
        words = ["diffbot", "params", *([self.robot] if self.robot else [])]
        words += [f"{name}:={value}" for name, value in self.xacro_args.items()]
        words += [f"--package={name}={folder}" for name, folder in self.packages.items()]
        return words + ([f"--controllers={self.controllers}"] if self.controllers else [])


#: ``--trust``: let the description run xacro's full Python (robot options and ``urdf``).
trust_option = click.option(
    "--trust",
    is_flag=True,
    help="Trust the description: let xacro run its Python and read any file (default: a "
    "sandbox that reads only the description's folders and packages).",
)


def robot_path_option(help_text: str) -> Callable[[F], F]:
    """``--robot PATH``: the robot description, an input of the run."""
    return click.option("--robot", type=InputPath(), metavar="PATH", help=help_text)


def package_option(help_text: str) -> Callable[[F], F]:
    """``--package NAME=DIR`` (repeatable), received as ``packages``."""
    return click.option(
        "--package",
        "packages",
        type=PackageDir(),
        metavar="NAME=DIR",
        multiple=True,
        help=help_text,
    )


_ROBOT_OPTIONS = [
    robot_path_option(
        "Robot description: .urdf, .urdf.xacro, an SDF model (.sdf or model folder) or a "
        "bag with /robot_description; a description file or model folder may also be the first "
        "argument. Default: the bundled diffbot, unless both joints, the radius and the "
        "separation are given."
    ),
    package_option(
        "Directory of ROS package NAME, for $(find NAME), when the description's source "
        "tree does not hold it: the folder holding its package.xml, an install prefix "
        "(install/NAME, holding share/NAME) or a share folder (holding NAME). Repeatable."
    ),
    click.option(
        "--left-joint",
        metavar="NAME[,NAME]",
        help="Left drive wheel joint(s), comma-separated (if ambiguous).",
    ),
    click.option(
        "--right-joint",
        metavar="NAME[,NAME]",
        help="Right drive wheel joint(s), comma-separated (if ambiguous).",
    ),
    click.option(
        "--wheel-radius", type=POSITIVE, metavar="M", help="Override the wheel radius (m)."
    ),
    click.option(
        "--wheel-separation",
        type=POSITIVE,
        metavar="M",
        help="Override the wheel separation (m).",
    ),
    click.option(
        "--max-rpm",
        type=MotorLimit(),
        metavar="RPM",
        help=f"Override the motor limit (rpm): above 0, at most {_MOST_RPM} rpm "
        f"({MOTOR_LIMIT_RANGE[1]:g} rad/s). A description's joint velocity limit above that is "
        "taken for a placeholder, no limit.",
    ),
    click.option(
        "--controllers",
        metavar="FILE",
        type=InputPath(exists=True, dir_okay=False),
        help="The robot's ros2_control controllers YAML: its diff_drive_controller's separation, "
        "radii (multipliers applied), wheels and limits win over the description. Default: the "
        "file the description's ros2_control Gazebo plugin names, if it exists.",
    ),
    click.option(
        "--controller",
        metavar="NAME",
        help="Which diff-drive controller of the file, when it holds several.",
    ),
    click.option(
        "--no-controllers",
        is_flag=True,
        help="Read no controllers file, not even the one the description names.",
    ),
    choice_option(
        "--source",
        choices=SOURCE_MODES,
        default="auto",
        help="Where the radius, separation and wheels come from: auto takes the controllers "
        "file, else the simulator's diff-drive plugin, else the geometry; the others are still "
        "cross-checked.",
    ),
    trust_option,
]


#: File name endings of robot descriptions (``.urdf.xacro`` ends with ``.xacro``).
DESCRIPTION_SUFFIXES = (".urdf", ".xacro", ".sdf")
#: XML root elements of robot descriptions.
DESCRIPTION_ROOTS = ("robot", "sdf")
#: How much of a file is read to find its XML root element (bytes).
_HEAD_BYTES = 65536


def xml_root(path: Path) -> str | None:
    """The name of the root element of an XML file (without namespace prefix), read from its
    head only; None when the file is not XML or cannot be read."""
    try:
        with open(open_regular(path, DescriptionError, "a description"), "rb") as stream:
            head = stream.read(_HEAD_BYTES)
    except (OSError, DescriptionError):
        return None
    # XML names here are ASCII; any other byte only has to be neither a name nor a blank
    return root_name(head.removeprefix(b"\xef\xbb\xbf").decode("ascii", "replace"))


def is_description(token: str) -> bool:
    """Whether a command-line argument names a robot description rather than plan text, a plan
    file, a recording or a number: a name ending ``.urdf``, ``.xacro`` or ``.sdf``, an existing
    file whose XML root element is ``<robot>`` or ``<sdf>``, or an SDF model folder (it holds a
    ``model.config``); a ROS package folder, a launch file or a controllers YAML too, to be told
    what to give."""
    if not token.strip() or ":=" in token:
        return False
    path = Path(token)
    if path.name.lower().endswith(DESCRIPTION_SUFFIXES) or is_launch_file(path):
        return True
    if not exists(path):
        return False
    if path.is_dir():  # an SDF model folder; a bag folder is a recording, not a robot
        return (path / "model.config").is_file() or is_package_folder(path)
    return path.is_file() and (xml_root(path) in DESCRIPTION_ROOTS or is_controllers_file(path))


def exists(path: Path) -> bool:
    """Whether a path names something, False for a name the system cannot look up (too long,
    a NUL byte): plan text may be given where a file name could be."""
    try:
        return path.exists()
    except (OSError, ValueError):
        return False


#: The name of the positional arguments of commands that take a robot: a description given as
#: the first of them is taken out and used as ``--robot``.
ARGUMENTS = "tokens"


def _robot_from(kwargs: dict[str, Any]) -> RobotOptions:
    # Every option is named after its field, but for the two built from other values.
    packages = parse_packages(kwargs.pop("packages"))
    if kwargs.get("controllers") is not None and kwargs.get("no_controllers"):
        fail("--controllers and --no-controllers: choose one")
    names = [f.name for f in dataclasses.fields(RobotOptions)]
    given = {name: kwargs.pop(name) for name in names if name not in ("xacro_args", "packages")}
    tokens = kwargs.get(ARGUMENTS)
    if tokens and is_description(tokens[0]):
        path = tokens[0]
        other = given["robot"]
        if other is not None and resolved(other) != resolved(path):
            fail(f"two robots given: {path!r} and --robot {given['robot']!r}")
        given["robot"] = input_path(path)
        kwargs[ARGUMENTS] = tuple(tokens[1:])
    return RobotOptions(xacro_args={}, packages=packages, **given)


#: Add the shared robot options; the command receives them as ``robot: RobotOptions``.
robot_options = option_group(_ROBOT_OPTIONS, "robot", _robot_from)


NUMBERS = {"ignore_unknown_options": True}  # lets negative numbers through as arguments


def topic_option(help_text: str, *, reading: bool = False) -> Callable[[F], F]:
    """``--topic``, the JointState topic of a bag: ``/joint_states`` by default, or, when
    ``reading`` a bag, ``/joint_states`` or else the bag's only JointState topic (None)."""
    if reading:
        return click.option(
            "--topic",
            metavar="TOPIC",
            default=None,
            help=f"{help_text} Default: /joint_states, or else the bag's only JointState topic.",
        )
    return name_option("--topic", "/joint_states", help_text)


def true_geometry_options(radii_help: str, separation_help: str) -> Callable[[F], F]:
    """``--true-wheel-radius L,R`` (``true_radii``) and ``--true-separation M``: the robot's
    real geometry (m), where it differs from the description."""

    def decorate(command: F) -> F:
        command = click.option(
            "--true-separation", type=WHEEL_SIZE, metavar="M", help=separation_help
        )(command)
        return click.option(
            "--true-wheel-radius",
            "true_radii",
            type=NumberPair("L,R", "m", positive=True, bounds=WHEEL_SIZE_RANGE),
            metavar="L,R",
            help=radii_help,
        )(command)

    return decorate


def encoder_noise_options(command: F) -> F:
    """``--noise STD`` (rad, at most a revolution) and ``--seed N``: the simulated encoders'
    Gaussian noise, for ``simulate`` and ``node robot`` alike."""
    command = click.option(
        "--seed",
        type=Count(0, 2**64 - 1),
        metavar="N",
        help="Seed of the noise (0 to 2**64-1), for reproducible runs.",
    )(command)
    return click.option(
        "--noise",
        type=FiniteFloat(0.0, maximum=MAX_NOISE),
        default=0.0,
        metavar="STD",
        help="Standard deviation of Gaussian noise on the wheel angles (rad), at most 2 pi.",
    )(command)


def quiet_option(command: F) -> F:
    """``--quiet``: no progress bar (it shows only when stderr is a terminal anyway)."""
    return click.option(
        "--quiet",
        "-q",
        is_flag=True,
        help="No progress bar (shown on a terminal) nor warnings on stderr.",
    )(command)
