"""What the commands share: option types, the robot options, the plan options, messages.

The library never imports click: commands convert their arguments here, call the library, and
format its results.
"""

from __future__ import annotations

import dataclasses
import difflib
import functools
import json
import math
import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, NoReturn, TypeVar

import click

from diffbot.commands.robot_path import (
    is_controllers_file,
    is_launch_file,
    is_package_folder,
    not_a_description,
)
from diffbot.commands.said_once import quieted, say_warnings
from diffbot.errors import EXIT_BAD_INPUT
from diffbot.io.outputs import input_clash
from diffbot.io.xmlhead import root_name
from diffbot.kinematics import DiffDriveParams, rad_s_from_rpm
from diffbot.numbers import MAX_NOISE, MAX_PLAN_DURATION, WHEEL_SIZE_RANGE
from diffbot.urdf import load_params

F = TypeVar("F", bound=Callable[..., Any])


class InputError(click.ClickException):
    """Bad input found by a command: reported as ``error: ...`` with exit code 2."""

    exit_code = EXIT_BAD_INPUT


def fail(message: str) -> NoReturn:
    """Stop the command with a bad-input error."""
    raise InputError(message)


def no_such_option(token: str) -> NoReturn:
    """Stop with click's own usage error for an unknown option (the one click gives when it
    parses the options itself, with the ``--help`` hint), suggesting the command's closest
    option names. For commands that let unknown options through as (negative number)
    arguments."""
    ctx = click.get_current_context(silent=True)
    names = [] if ctx is None else [name for p in ctx.command.params for name in p.opts]
    close = difflib.get_close_matches(token.partition("=")[0], [n for n in names if n[:1] == "-"])
    raise click.NoSuchOption(token, possibilities=close, ctx=ctx)


def warn(message: str) -> None:
    """Tell the user something on stderr, on one line; nothing when ``-q/--quiet`` is given."""
    if quieted():
        return
    click.echo(f"warning: {' '.join(message.split())}", err=True)


def emit_json(data: Any) -> None:
    """Print machine-readable output (strict JSON: no NaN), or a bad-input error when a result
    is not finite (inputs checked at the boundary should leave none)."""
    try:
        text = json.dumps(data, indent=2, allow_nan=False)
    except ValueError:
        fail("a result is infinite or NaN: the inputs are too large to compute with")
    click.echo(text)


class FiniteFloat(click.ParamType):  # type: ignore[type-arg,unused-ignore]
    """A finite float, optionally bounded; rejects NaN and infinities."""

    name = "number"

    def __init__(
        self, minimum: float | None = None, open_min: bool = False, maximum: float | None = None
    ) -> None:
        self.minimum = minimum
        self.open_min = open_min
        self.maximum = maximum

    def convert(
        self, value: Any, param: click.Parameter | None, ctx: click.Context | None
    ) -> float:
        if isinstance(value, float):
            number = value
        else:
            try:
                number = float(str(value).strip())
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
            self.fail(f"{value!r} must be <= {self.maximum:g}", param, ctx)
        return number


class NumberPair(click.ParamType):  # type: ignore[type-arg,unused-ignore]
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
                number = float(part.strip())
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
NON_NEGATIVE = FiniteFloat(0.0)
#: Highest --rate of the ros2 script (Hz): 'ros2 topic pub' is a Python loop, far from this fast.
MAX_PUBLISH_RATE = 1000.0
#: Lowest command --rate (Hz): one command per longest plan.
MIN_COMMAND_RATE = 1.0 / MAX_PLAN_DURATION


def check_finite(what: str, *values: float) -> None:
    """Bad input when a result overflows to inf or NaN (inputs too large to compute with)."""
    if not all(math.isfinite(v) for v in values):
        fail(f"the {what} overflow: the inputs are too large to compute with")


def parse_number(token: str, what: str) -> float:
    """A finite float from a command-line token, or a bad-input error naming it."""
    try:
        number = float(token)
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
        float(token)
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


def parse_packages(values: Sequence[str]) -> dict[str, str]:
    """``--package NAME=DIR`` values as a mapping."""
    packages: dict[str, str] = {}
    for value in values:
        name, sep, directory = value.partition("=")
        if not sep or not name or not directory:
            fail(f"--package {value!r}: expected NAME=DIR")
        if not Path(directory).is_dir():
            fail(f"--package {value!r}: {directory} is not a directory")
        packages[name] = directory
    return packages


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
        robot = path if path is not None else self.robot
        return dataclasses.replace(self, robot=robot, xacro_args={**self.xacro_args, **xacro_args})

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
            say_warnings(
                params.warnings,
                params.source,
                self.robot,
                xacro_args=self.xacro_args,
                packages=self.packages,
                controllers=self.controllers,
            )
        return params


def option_group(
    options: Sequence[Callable[[Any], Any]], name: str, build: Callable[[dict[str, Any]], object]
) -> Callable[[F], F]:
    """A decorator adding ``options`` to a command, which receives them as one object.

    ``build`` takes the options' values out of the keyword arguments (popping them) and
    returns the object, passed to the command as ``name``.
    """

    def decorate(command: F) -> F:
        def wrapper(**kwargs: Any) -> Any:
            return command(**{name: build(kwargs)}, **kwargs)

        functools.update_wrapper(wrapper, command)  # keeps options declared below this one
        decorated: Any = wrapper
        for option in reversed(options):
            decorated = option(decorated)
        return decorated  # type: ignore[no-any-return]

    return decorate


#: ``--trust``: let the description run xacro's full Python (robot options and ``urdf``).
trust_option = click.option(
    "--trust",
    is_flag=True,
    help="Trust the description: let xacro run its Python and read any file (default: a "
    "sandbox that reads only the description's folders and packages).",
)

_ROBOT_OPTIONS = [
    click.option(
        "--robot",
        metavar="PATH",
        help="Robot description: .urdf, .urdf.xacro, an SDF model (.sdf or model folder) or a "
        "bag with /robot_description; a description file or model folder may also be the first "
        "argument. Default: the bundled diffbot, unless both joints, the radius and the "
        "separation are given.",
    ),
    click.option(
        "--package",
        "packages",
        metavar="NAME=DIR",
        multiple=True,
        help="Directory of ROS package NAME, for $(find NAME), when the description's source "
        "tree does not hold it: the folder holding its package.xml, an install prefix "
        "(install/NAME, holding share/NAME) or a share folder (holding NAME). Repeatable.",
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
        type=NON_NEGATIVE,
        metavar="RPM",
        help="Override the motor limit (rpm).",
    ),
    click.option(
        "--controllers",
        metavar="FILE",
        type=click.Path(exists=True, dir_okay=False),
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
    click.option(
        "--source",
        type=click.Choice(["auto", "description", "controllers", "plugin"]),
        default="auto",
        show_default=True,
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
        with path.open("rb") as stream:
            head = stream.read(_HEAD_BYTES)
    except OSError:
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
        if other is not None and Path(other).resolve() != Path(path).resolve():
            fail(f"two robots given: {path!r} and --robot {given['robot']!r}")
        given["robot"] = path
        kwargs[ARGUMENTS] = tuple(tokens[1:])
    return RobotOptions(xacro_args={}, packages=packages, **given)


#: Add the shared robot options; the command receives them as ``robot: RobotOptions``.
robot_options = option_group(_ROBOT_OPTIONS, "robot", _robot_from)


NUMBERS = {"ignore_unknown_options": True}  # lets negative numbers through as arguments


def check_out(out: str | None, inputs: Sequence[Path], force: bool) -> Path | None:
    """The --out path, refused early when it is empty, exists (without --force), or is, holds
    or lies inside an input (compared as resolved paths, links followed)."""
    if out is None:
        return None
    if not out.strip():
        fail("--out needs a file or directory name, got ''")
    path = Path(out)
    clash = input_clash(path, inputs)
    if clash is not None:
        relation, given = clash
        if relation == "inside":
            fail(f"--out {out} lies inside the input {given}: inputs are never modified")
        what = "is the input" if relation == "is" else "contains the input"
        fail(f"--out {out} {what} {given}: inputs are never overwritten")
    if (path.exists() or path.is_symlink()) and not force:
        fail(f"{out} exists: use --force to overwrite it")
    return path


@dataclass(frozen=True)
class OutOptions:
    """Where a command writes its samples: ``--out`` (a CSV file or, with ``--bag``, a rosbag2
    directory) and ``--force``."""

    out: str | None
    as_bag: bool
    force: bool

    def path(self, inputs: Sequence[Path]) -> Path | None:
        """The --out path of one output, checked early against ``inputs`` (see
        :func:`check_out`); a file's path may not end in a slash."""
        if not self.as_bag:
            file_output(self.out)
        return check_out(self.out, inputs, self.force)

    def require_out_for_bag(self) -> None:
        """Bad input when --bag is given without --out."""
        if self.as_bag and self.out is None:
            fail("--bag writes the --out directory: give --out DIR")


#: The one output option of every command that writes, in its three spellings.
OUTPUT_NAMES = ("-o", "--output", "--out")


def file_output(value: str | None, option: str = "-o/--out") -> str | None:
    """``value`` unless it names a folder (a trailing slash) where a file is written: the path
    would otherwise lose its slash and a file appear where the user asked for a folder."""
    if value is not None and value.endswith(("/", os.sep)) and value.rstrip("/" + os.sep):
        fail(f"{option} {value}: ends with a slash (a folder), but a file is written there")
    return value


def output_option(
    help_text: str, *, metavar: str = "FILE", dest: str = "output"
) -> Callable[[F], F]:
    """The output option, ``-o``, ``--output`` or ``--out`` alike, received as ``dest``
    (a file: a path ending in a slash is refused; ``--out`` of :func:`out_options` may be a
    bag folder)."""

    def checked(ctx: click.Context, param: click.Parameter, value: str | None) -> str | None:
        return value if metavar != "FILE" else file_output(value)

    return click.option(*OUTPUT_NAMES, dest, metavar=metavar, help=help_text, callback=checked)


def out_options(out_help: str, bag_help: str) -> Callable[[F], F]:
    """Add the output option, ``--bag`` and ``--force``; the command receives
    ``out: OutOptions``."""
    options = [
        output_option(out_help, metavar="PATH", dest="out"),
        click.option("--bag", "as_bag", is_flag=True, help=bag_help),
        click.option("--force", is_flag=True, help="Overwrite --out if it exists."),
    ]

    return option_group(
        options, "out", lambda kw: OutOptions(kw.pop("out"), kw.pop("as_bag"), kw.pop("force"))
    )


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
    return click.option(
        "--topic", metavar="TOPIC", default="/joint_states", show_default=True, help=help_text
    )


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
        type=click.IntRange(min=0, max=2**64 - 1),
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
