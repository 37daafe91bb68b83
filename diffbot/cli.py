"""The ``diffbot`` command line: a thin layer over the library.

Exit codes: 0 success, 1 a result that fails a check (a wheel over the motor limit), 2 bad input or
usage. Errors are one line on stderr starting with ``error:``; machine output goes to stdout.
"""

from __future__ import annotations

import functools
import json
import math
import re
import sys
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, NoReturn, TypeVar

import click

from diffbot.errors import DiffbotError
from diffbot.kinematics import (
    DiffDriveParams,
    WheelSpeeds,
    forward,
    inverse,
    joint_from_wheel,
    limit_fraction,
    rad_s_from_rpm,
    rpm_from_rad_s,
    saturate,
    wheel_from_joint,
    within_limit,
)

F = TypeVar("F", bound=Callable[..., Any])

#: Exit code of a result that fails a check (for example a wheel over the motor limit).
EXIT_CHECK_FAILED = 1
#: Exit code of bad input or usage.
EXIT_BAD_INPUT = 2


class InputError(click.ClickException):
    """Bad input found by a command: reported as ``error: ...`` with exit code 2."""

    exit_code = EXIT_BAD_INPUT


def fail(message: str) -> NoReturn:
    """Stop the command with a bad-input error."""
    raise InputError(message)


class _PipeClosedError(Exception):
    """The reader of stdout went away (click would turn the EPIPE into exit code 1)."""


class DiffbotGroup(click.Group):
    """The command group; turns every error into one ``error:`` line and an exit code."""

    def invoke(self, ctx: click.Context) -> Any:
        try:
            result = super().invoke(ctx)
            sys.stdout.flush()
        except BrokenPipeError:
            raise _PipeClosedError from None
        return result

    def main(
        self,
        args: Sequence[str] | None = None,
        prog_name: str | None = None,
        complete_var: str | None = None,
        standalone_mode: bool = True,
        **extra: Any,
    ) -> Any:
        try:
            code = super().main(args, prog_name, complete_var, standalone_mode=False, **extra)
        except click.exceptions.NoArgsIsHelpError as err:
            click.echo(err.ctx.get_help() if err.ctx else err.format_message())
            code = 0
        except click.UsageError as err:
            hint = ""
            if err.ctx is not None:
                hint = f" (see '{err.ctx.command_path} --help')"
            _error(f"{err.format_message()}{hint}", err.exit_code)
        except click.ClickException as err:
            _error(err.format_message(), err.exit_code)
        except DiffbotError as err:
            _error(str(err), EXIT_BAD_INPUT)
        except click.Abort:
            _error("aborted", 130)
        except (BrokenPipeError, _PipeClosedError):
            # The reader went away (``| head``). Exit as a process killed by SIGPIPE would, and
            # point stdout at /dev/null so the flush at exit cannot fail again.
            import os

            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, sys.stdout.fileno())
            sys.exit(128 + 13)
        except OSError as err:
            _error(f"{err.filename + ': ' if err.filename else ''}{err.strerror or err}", 2)
        if not standalone_mode:
            return code
        sys.exit(code if isinstance(code, int) else 0)


def _error(message: str, code: int) -> NoReturn:
    click.echo(f"error: {' '.join(str(message).split())}", err=True)
    sys.exit(code)


def warn(message: str) -> None:
    """Tell the user something on stderr, on one line."""
    click.echo(f"warning: {' '.join(message.split())}", err=True)


def emit_json(data: Any) -> None:
    """Print machine-readable output (strict JSON: no NaN)."""
    click.echo(json.dumps(data, indent=2, allow_nan=False))


# --------------------------------------------------------------------------------------------
# Parameter types


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


POSITIVE = FiniteFloat(0.0, open_min=True)
NON_NEGATIVE = FiniteFloat(0.0)
#: Highest --rate of the ros2 script (Hz): 'ros2 topic pub' is a Python loop, far from this fast.
MAX_PUBLISH_RATE = 1000.0


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
            fail(f"no such option: {token!r}")
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
            fail(f"no such option: {token!r}")
        if ":=" in token:
            name, _, value = token.partition(":=")
            if not name or not name.replace("_", "a").replace("-", "a").isalnum():
                fail(f"bad xacro argument {token!r}: expected NAME:=VALUE")
            args[name] = value
        else:
            rest.append(token)
    return rest, args


def _parse_packages(values: Sequence[str]) -> dict[str, str]:
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

    def with_path(self, path: str | None, xacro_args: Mapping[str, str]) -> RobotOptions:
        """The same options with a positional PATH and ``NAME:=VALUE`` tokens merged in."""
        if path is not None and self.robot is not None and path != self.robot:
            fail(f"two robots given: {path!r} and --robot {self.robot!r}")
        return RobotOptions(
            path if path is not None else self.robot,
            {**self.xacro_args, **xacro_args},
            self.packages,
            self.left_joint,
            self.right_joint,
            self.wheel_radius,
            self.wheel_separation,
            self.max_rpm,
        )

    def load(self, *, quiet: bool = False) -> DiffDriveParams:
        """Load the robot; print its warnings on stderr unless ``quiet``."""
        from diffbot.urdf import load_params

        if self.robot is not None:
            path = Path(self.robot)
            if not path.exists():
                fail(f"{self.robot}: no such file")
            if path.is_dir():
                fail(f"{self.robot}: is a directory, not a URDF or xacro file")
        params = load_params(
            self.robot,
            self.xacro_args,
            self.packages,
            left_joint=self.left_joint,
            right_joint=self.right_joint,
            wheel_radius=self.wheel_radius,
            wheel_separation=self.wheel_separation,
            max_wheel_speed=None if self.max_rpm is None else rad_s_from_rpm(self.max_rpm),
        )
        if not quiet:
            for message in params.warnings:
                warn(message)
        return params


def robot_options(command: F) -> F:
    """Add the shared robot options; the command receives them as ``robot: RobotOptions``."""
    options = [
        click.option(
            "--robot",
            metavar="PATH",
            help="Robot description (.urdf or .urdf.xacro). Default: the bundled diffbot.",
        ),
        click.option(
            "--package",
            "packages",
            metavar="NAME=DIR",
            multiple=True,
            help="Directory of ROS package NAME, for $(find NAME). Repeatable.",
        ),
        click.option("--left-joint", metavar="NAME", help="Left drive wheel joint (if ambiguous)."),
        click.option(
            "--right-joint", metavar="NAME", help="Right drive wheel joint (if ambiguous)."
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
    ]

    def wrapper(**kwargs: Any) -> Any:
        robot = RobotOptions(
            robot=kwargs.pop("robot"),
            xacro_args={},
            packages=_parse_packages(kwargs.pop("packages")),
            left_joint=kwargs.pop("left_joint"),
            right_joint=kwargs.pop("right_joint"),
            wheel_radius=kwargs.pop("wheel_radius"),
            wheel_separation=kwargs.pop("wheel_separation"),
            max_rpm=kwargs.pop("max_rpm"),
        )
        return command(robot=robot, **kwargs)

    functools.update_wrapper(wrapper, command)  # keeps options declared below this decorator
    decorated: Any = wrapper
    for option in reversed(options):
        decorated = option(decorated)
    return decorated  # type: ignore[no-any-return]


NUMBERS = {"ignore_unknown_options": True}  # lets negative numbers through as arguments


# --------------------------------------------------------------------------------------------
# Formatting


def fmt(value: float, digits: int = 6) -> str:
    """A number for people: ``digits`` significant digits, no ``-0``."""
    text = f"{value:.{digits}g}"
    return "0" if text in ("-0", "0") else text


def limit_text(params: DiffDriveParams) -> str:
    """The motor limit for people."""
    if params.max_wheel_speed is None:
        return "none"
    return f"{fmt(params.max_wheel_rpm or 0.0, 5)} rpm ({fmt(params.max_wheel_speed)} rad/s)"


# --------------------------------------------------------------------------------------------
# Commands


@click.group(
    cls=DiffbotGroup,
    context_settings={"help_option_names": ["-h", "--help"], "max_content_width": 100},
)
@click.version_option(package_name="diffbot-kinematics", prog_name="diffbot")
def main() -> None:
    """Kinematics, odometry and motion plans for differential-drive robots.

    Robot parameters (wheel radius, separation, joints, motor limit) come from a URDF/xacro
    description; the default is the bundled diffbot (r = 0.035 m, b = 0.135 m, 50 rpm). SI units
    inside; rpm and degrees only where labelled.

    \b
    Examples:
      diffbot params                          the bundled robot's parameters
      diffbot params my.urdf.xacro wheel_radius:=0.04
      diffbot ik 0.1 0.5                      wheel speeds for v = 0.1 m/s, w = 0.5 rad/s
      diffbot fk 2.86 2.86                    body velocity from wheel speeds (rad/s)
    """


@main.command()
@click.argument("tokens", nargs=-1, metavar="[PATH] [NAME:=VALUE]...")
@robot_options
@click.option("--json", "as_json", is_flag=True, help="Machine-readable output.")
def params(robot: RobotOptions, tokens: tuple[str, ...], as_json: bool) -> None:
    """Show the robot parameters derived from a description.

    PATH is a .urdf or .urdf.xacro file (default: the bundled diffbot); NAME:=VALUE tokens are
    xacro arguments. Drive wheels are found from the structure: continuous joints with a lateral
    axis hanging from base_link through fixed joints; left is +y (REP-103).

    \b
    Example:
      diffbot params diffbot.urdf.xacro wheel_radius:=0.04 --json
    """
    rest, xacro_args = split_xacro_args(tokens)
    if len(rest) > 1:
        fail(f"expected at most one PATH, got {rest}")
    options = robot.with_path(rest[0] if rest else None, xacro_args)
    p = options.load(quiet=True)
    if as_json:
        emit_json(
            {
                "wheel_radius": p.wheel_radius,
                "wheel_separation": p.wheel_separation,
                "left_joint": p.left_joint,
                "right_joint": p.right_joint,
                "left_sign": p.left_sign,
                "right_sign": p.right_sign,
                "max_wheel_speed": p.max_wheel_speed,
                "max_wheel_rpm": p.max_wheel_rpm,
                "source": p.source,
                "warnings": list(p.warnings),
            }
        )
        return
    rows = [
        ("robot", p.source),
        ("wheel radius", f"{fmt(p.wheel_radius)} m"),
        ("wheel separation", f"{fmt(p.wheel_separation)} m"),
        ("left wheel", f"{p.left_joint} (direction {p.left_sign:+d})"),
        ("right wheel", f"{p.right_joint} (direction {p.right_sign:+d})"),
        ("motor limit", limit_text(p)),
    ]
    for label, value in rows:
        click.echo(f"{label:<17} {value}")
    for message in p.warnings:
        warn(message)


@main.command()
@click.argument("tokens", nargs=-1, metavar="[PATH] [NAME:=VALUE]...")
@click.option("--robot", metavar="PATH", help="Robot description (same as PATH).")
@click.option("--package", "packages", metavar="NAME=DIR", multiple=True, help="Package directory.")
@click.option("-o", "--output", metavar="FILE", help="Write to this file instead of stdout.")
@click.option("--force", is_flag=True, help="Overwrite --output if it exists.")
def urdf(
    tokens: tuple[str, ...],
    robot: str | None,
    packages: tuple[str, ...],
    output: str | None,
    force: bool,
) -> None:
    """Print the expanded URDF of a description (like xacro).

    $(find NAME) is resolved from --package NAME=DIR, the bundled packages, then
    AMENT_PREFIX_PATH; no ROS install is needed.

    \b
    Example:
      diffbot urdf robot.urdf.xacro wheel_radius:=0.04 --package my_robot=./my_robot -o robot.urdf
    """
    from diffbot.urdf import BUNDLED_DESCRIPTION, expand

    rest, xacro_args = split_xacro_args(tokens)
    if len(rest) > 1:
        fail(f"expected at most one PATH, got {rest}")
    path = rest[0] if rest else robot
    if rest and robot and rest[0] != robot:
        fail(f"two robots given: {rest[0]!r} and --robot {robot!r}")
    expansion = expand(path, xacro_args, _parse_packages(packages))
    for message in expansion.warnings:
        warn(message)
    if output is None:
        click.echo(expansion.urdf, nl=False)
    else:
        source = Path(path) if path is not None else BUNDLED_DESCRIPTION
        write_text_atomic(Path(output), expansion.urdf, force=force, inputs=[source])


#: Storage files of a rosbag2 recording: given one of them, the recording is its directory.
_BAG_FILES = (".db3", ".mcap")


def _occupied(path: Path) -> Path:
    """The resolved path an input occupies: a bag given as one of its files is its directory."""
    resolved = path.resolve()
    if (
        resolved.is_file()
        and resolved.suffix.lower() in _BAG_FILES
        and (resolved.parent / "metadata.yaml").is_file()
    ):
        return resolved.parent
    return resolved


def input_clash(target: Path, inputs: Sequence[Path]) -> tuple[str, Path] | None:
    """How an output path would touch an input: ("is" | "inside" | "contains", that input).

    Paths are compared resolved, links followed; a bag given as one of its files is its whole
    directory. None when the output touches no input.
    """
    resolved = target.resolve()
    for given in inputs:
        occupied = _occupied(given)
        if resolved == occupied:
            return "is", given
        if occupied in resolved.parents:
            return "inside", given
        if resolved in occupied.parents:
            return "contains", given
    return None


def output_target(path: Path, *, force: bool, inputs: Sequence[Path] = ()) -> Path:
    """Check where an output may go; return the real path to replace (links followed).

    Raises a bad-input error when the path exists and ``force`` is not given, is not a regular
    file (a directory, a device), lies in a missing directory, or is one of the ``inputs``.
    """
    target = path.resolve() if path.is_symlink() else path
    if path.exists() or path.is_symlink():
        if not force:
            fail(f"{path} exists: use --force to overwrite it")
        if target.exists() and not target.is_file():
            fail(f"{path} is not a regular file: refusing to replace it")
    if not target.parent.is_dir():
        fail(f"{path}: directory {target.parent} does not exist")
    clash = input_clash(target, inputs)
    if clash is not None:
        relation, given = clash
        what = {"is": "is an input", "inside": "lies inside the input", "contains": "contains"}
        detail = "" if relation == "is" else f" {given}"
        fail(f"{path} {what[relation]}{detail}: refusing to overwrite it")
    return target


def write_text_atomic(
    path: Path,
    text: str,
    *,
    force: bool,
    inputs: Sequence[Path] = (),
    executable: bool = False,
) -> None:
    """Write a whole file or nothing: a temporary file beside it, then a rename.

    The file gets the permissions of the file it replaces, or the usual ones (umask applied;
    executable ones for scripts).
    """
    import os
    import stat
    import tempfile

    target = output_target(path, force=force, inputs=inputs)
    if target.exists():
        mode = stat.S_IMODE(target.stat().st_mode)
    else:
        umask = os.umask(0)
        os.umask(umask)
        mode = 0o666 & ~umask
    if executable:
        mode |= (mode & 0o444) >> 2  # x wherever r
    fd, tmp = tempfile.mkstemp(dir=target.parent, prefix=f".{target.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as out:
            out.write(text)
        os.chmod(tmp, mode)
        os.replace(tmp, target)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def _speeds_json(params: DiffDriveParams, joints: WheelSpeeds) -> dict[str, Any]:
    return {
        "left": float(joints.left),
        "right": float(joints.right),
        "left_rpm": float(rpm_from_rad_s(joints.left)),
        "right_rpm": float(rpm_from_rad_s(joints.right)),
    }


@main.command(context_settings=NUMBERS)
@click.argument("tokens", nargs=-1, metavar="LINEAR ANGULAR [NAME:=VALUE]...")
@robot_options
@click.option(
    "--saturate",
    "do_saturate",
    is_flag=True,
    help="Scale both wheels down to the motor limit, keeping the turning radius.",
)
@click.option("--json", "as_json", is_flag=True, help="Machine-readable output.")
def ik(robot: RobotOptions, tokens: tuple[str, ...], do_saturate: bool, as_json: bool) -> None:
    """Wheel speeds for a body velocity (inverse kinematics).

    LINEAR is the forward speed (m/s), ANGULAR the yaw rate (rad/s, positive counter-clockwise),
    as in a cmd_vel Twist. Prints the joint velocity commands (rad/s and rpm, with the joints'
    direction signs applied) and whether they are within the motor limit. Exit code 1 when a wheel
    is over the limit (unless --saturate).

    \b
    Examples:
      diffbot ik 0.1 0                 straight at 0.1 m/s: 2.857 rad/s per wheel
      diffbot ik 0.157 -0.314          the 0.5 m clockwise circle in 20 s
    """
    rest, xacro_args = split_xacro_args(tokens)
    if len(rest) != 2:
        fail(f"expected LINEAR and ANGULAR, got {len(rest)} value(s) {list(rest)}")
    linear = parse_number(rest[0], "LINEAR")
    angular = parse_number(rest[1], "ANGULAR")
    p = robot.with_path(None, xacro_args).load()
    wheels = inverse(p, linear, angular)
    check_finite(
        "wheel speeds", float(wheels.left), float(wheels.right), float(rpm_from_rad_s(wheels.left))
    )
    check_finite("wheel speeds", float(rpm_from_rad_s(wheels.right)))
    saturated = False
    if do_saturate and not within_limit(p, wheels):
        wheels = saturate(p, wheels)
        saturated = True
    joints = joint_from_wheel(p, wheels)
    ok = within_limit(p, wheels)
    fraction = limit_fraction(p, wheels)
    if as_json:
        data = _speeds_json(p, joints)
        data["within_limit"] = ok
        if do_saturate:
            data["saturated"] = saturated
        emit_json(data)
    else:
        click.echo(f"body         linear {fmt(linear)} m/s, angular {fmt(angular)} rad/s")
        for side, value in (("left", joints.left), ("right", joints.right)):
            joint = p.left_joint if side == "left" else p.right_joint
            rad_s = float(value)
            click.echo(
                f"{side + ' wheel':<12} {fmt(rad_s):>10} rad/s "
                f"{fmt(rpm_from_rad_s(rad_s), 5):>9} rpm   ({joint})"
            )
        if saturated:
            twist = forward(p, wheels.left, wheels.right)
            click.echo(
                f"saturated    to linear {fmt(float(twist.linear))} m/s, "
                f"angular {fmt(float(twist.angular))} rad/s (same turning radius)"
            )
        if fraction is None:
            click.echo("motor limit  none in the description")
        else:
            state = "within" if ok else "OVER"
            click.echo(f"motor limit  {limit_text(p)}: {state}, {100 * float(fraction):.1f}% used")
    if not ok:
        faster = "left" if abs(float(wheels.left)) >= abs(float(wheels.right)) else "right"
        rpm = abs(float(rpm_from_rad_s(wheels.left if faster == "left" else wheels.right)))
        click.echo(
            f"error: {faster} wheel at {fmt(rpm, 4)} rpm exceeds the motor limit of "
            f"{fmt(p.max_wheel_rpm or 0.0, 4)} rpm (try --saturate)",
            err=True,
        )
        sys.exit(EXIT_CHECK_FAILED)


@main.command(context_settings=NUMBERS)
@click.argument("tokens", nargs=-1, metavar="LEFT RIGHT [NAME:=VALUE]...")
@robot_options
@click.option("--rpm", "in_rpm", is_flag=True, help="LEFT and RIGHT are in rpm, not rad/s.")
@click.option("--json", "as_json", is_flag=True, help="Machine-readable output.")
def fk(robot: RobotOptions, tokens: tuple[str, ...], in_rpm: bool, as_json: bool) -> None:
    """Body velocity from wheel joint velocities (forward kinematics).

    LEFT and RIGHT are the joint velocities (rad/s, or rpm with --rpm) as the controllers see them,
    with the description's direction signs; `diffbot ik` prints the same quantities.

    \b
    Example:
      diffbot fk 1.637 2.848            the seed's counter-clockwise arc: 0.0785 m/s, 0.314 rad/s
    """
    rest, xacro_args = split_xacro_args(tokens)
    if len(rest) != 2:
        fail(f"expected LEFT and RIGHT, got {len(rest)} value(s) {list(rest)}")
    left = parse_number(rest[0], "LEFT")
    right = parse_number(rest[1], "RIGHT")
    if in_rpm:
        left, right = float(rad_s_from_rpm(left)), float(rad_s_from_rpm(right))
    p = robot.with_path(None, xacro_args).load()
    wheels = wheel_from_joint(p, WheelSpeeds(left, right))
    twist = forward(p, wheels.left, wheels.right)
    linear, angular = float(twist.linear), float(twist.angular)
    check_finite("body velocity", linear, angular)
    if as_json:
        emit_json({"linear": linear, "angular": angular})
        return
    click.echo(f"linear   {fmt(linear)} m/s")
    click.echo(f"angular  {fmt(angular)} rad/s ({fmt(math.degrees(angular), 5)} deg/s)")
    if angular == 0.0:
        radius = "straight line" if linear != 0.0 else "standing still"
    elif linear == 0.0:
        radius = "spin in place"
    else:
        radius = (
            f"{fmt(linear / angular)} m ({'counter-clockwise' if angular > 0 else 'clockwise'})"
        )
    click.echo(f"radius   {radius}")
    if not within_limit(p, wheels):
        warn(f"the wheel speeds exceed the motor limit of {limit_text(p)}")


# --------------------------------------------------------------------------------------------
# diffbot plan: motion plans (see diffbot.trajectory)

if TYPE_CHECKING:
    from diffbot.kinematics import Pose
    from diffbot.trajectory import Plan, PlannedSegment, Segment, Violation

#: File name endings read as plan files rather than plan text.
PLAN_SUFFIXES = (".yaml", ".yml", ".json", ".txt")
PLAN_FORMATS = ("table", "json", "csv", "twist", "wheels", "ros2")
_TOPIC_NAME = r"(~/|/)?[A-Za-z_][A-Za-z0-9_]*(/[A-Za-z_][A-Za-z0-9_]*)*"


def _yaml_float(value: float) -> str:
    """A float for a YAML 1.1 reader (``ros2 topic pub``): every digit, and always a dot.

    PyYAML reads ``1e-05`` as a string, so an exponent gets a ``.0`` mantissa.
    """
    text = repr(float(value))
    if "e" in text and "." not in text:
        mantissa, _, exponent = text.partition("e")
        text = f"{mantissa}.0e{exponent}"
    return text


def _twist_yaml(linear: float, angular: float) -> str:
    return f"{{linear: {{x: {_yaml_float(linear)}}}, angular: {{z: {_yaml_float(angular)}}}}}"


def _array_yaml(value: float) -> str:
    return f"{{data: [{_yaml_float(value)}]}}"


def _fixed(value: float, decimals: int) -> str:
    text = f"{value:.{decimals}f}"
    return text.lstrip("-") if float(text) == 0.0 else text


def _ceil_text(value: float, digits: int = 4) -> str:
    """``value`` (> 0) rounded up to ``digits`` significant digits (a duration that still fits).

    Written like ``%g``: plainly from 1e-4 to 10**digits (``5.457``, ``1235``), in scientific
    notation beyond (``5.457e+05``); trailing zeros are kept, so every result shows ``digits``.
    """
    from decimal import ROUND_CEILING, Decimal

    shortest = Decimal(repr(float(value)))  # reads back as value, so rounding it up still fits
    if not shortest.is_finite() or shortest <= 0:
        return fmt(value)
    quantum = Decimal(1).scaleb(shortest.adjusted() - digits + 1)
    rounded = shortest.quantize(quantum, rounding=ROUND_CEILING)  # at most digits + 1 digits
    exponent = rounded.adjusted()
    if -4 <= exponent < digits:
        return f"{rounded:.{max(0, digits - 1 - exponent)}f}"
    mantissa, _, power = f"{rounded:.{digits - 1}e}".partition("e")
    return f"{mantissa}e{int(power):+03d}"


def _one_line(text: str) -> str:
    return " ".join(str(text).split())


@dataclass(frozen=True)
class _PlanInput:
    segments: list[Segment]
    label: str
    path: Path | None


def _plan_input(tokens: Sequence[str], example: str | None) -> _PlanInput:
    from diffbot.trajectory import EXAMPLES, load_plan, parse_plan

    for token in tokens:
        if token.startswith("--") or (
            token.startswith("-") and len(token) > 1 and not token[1].isdigit() and token[1] != "."
        ):
            fail(f"no such option: {token}")
    if example is not None:
        if tokens:
            fail(f"give a plan (SPEC or FILE) or --example, not both (got {' '.join(tokens)!r})")
        return _PlanInput(
            parse_plan(EXAMPLES[example.upper()]), f"Trajectory {example.upper()}", None
        )
    if not tokens:
        return _PlanInput(parse_plan(EXAMPLES["A"]), "Trajectory A", None)
    if len(tokens) == 1:
        token = tokens[0]
        path = Path(token)
        named_file = bool(token.strip()) and path.exists()
        file_like = path.suffix.lower() in PLAN_SUFFIXES and not any(c.isspace() for c in token)
        if named_file or file_like:
            return _PlanInput(load_plan(path), str(path), path)
    return _PlanInput(parse_plan(join_plan_arguments(tokens)), "plan", None)


def join_plan_arguments(tokens: Sequence[str]) -> str:
    """One plan text from several arguments: each starts a new segment (``'straight 1' 'spin
    90'`` is ``straight 1; spin 90``), unless it starts with a number, which continues the
    segment before it (``straight 1 10s`` typed unquoted, ``spin -90deg``)."""
    text = ""
    for token in tokens:
        continues = re.match(r"\s*[+-]?[0-9.]", token) is not None
        text = token if not text else f"{text}{' ' if continues else '; '}{token}"
    return text


def _plan_limit_text(p: Plan) -> str:
    if p.limit is None:
        return "none"
    origin = "" if p.limit == p.params.max_wheel_speed else ", from --rpm-limit"
    return f"{fmt(rpm_from_rad_s(p.limit), 5)} rpm ({fmt(p.limit)} rad/s{origin})"


def _plan_robot_json(params: DiffDriveParams) -> dict[str, Any]:
    return {
        "wheel_radius": params.wheel_radius,
        "wheel_separation": params.wheel_separation,
        "left_joint": params.left_joint,
        "right_joint": params.right_joint,
        "left_sign": params.left_sign,
        "right_sign": params.right_sign,
        "max_wheel_speed": params.max_wheel_speed,
        "max_wheel_rpm": params.max_wheel_rpm,
        "source": params.source,
    }


def _pose_json(pose: Pose) -> dict[str, float]:
    return {"x": pose.x, "y": pose.y, "theta": pose.theta}


def _plan_json(p: Plan, label: str) -> dict[str, Any]:
    from diffbot.trajectory import describe_segment, format_plan, format_segment

    segments = []
    for s in p.segments:
        segments.append(
            {
                "segment": s.index + 1,
                "kind": s.kind,
                "spec": format_segment(s.segment),
                "description": describe_segment(s.segment),
                "duration": s.duration,
                "linear": float(s.twist.linear),
                "angular": float(s.twist.angular),
                "left": float(s.joints.left),
                "right": float(s.joints.right),
                "left_rpm": float(rpm_from_rad_s(s.joints.left)),
                "right_rpm": float(rpm_from_rad_s(s.joints.right)),
                "fraction": s.fraction,
                "start_pose": _pose_json(s.start_pose),
                "end_pose": _pose_json(s.end_pose),
                "end_heading": s.end_heading,
            }
        )
    return {
        "source": label,
        "plan": format_plan(s.segment for s in p.segments),
        "segments": segments,
        "duration": p.duration,
        "final_pose": _pose_json(p.final_pose),
        "within_limit": p.within_limit,
        "limit": p.limit,
        "limit_rpm": None if p.limit is None else float(f"{rpm_from_rad_s(p.limit):.12g}"),
        "violations": [
            {
                "segment": v.index + 1,
                "wheel": v.wheel,
                "rpm": v.rpm,
                "shortest_duration": v.shortest_duration,
            }
            for v in p.violations()
        ],
        "robot": _plan_robot_json(p.params),
    }


def _plan_table(p: Plan, label: str) -> str:
    from diffbot.trajectory import describe_segment, format_plan

    params = p.params
    header = [
        "#",
        "segment",
        "v m/s",
        "w rad/s",
        "left rad/s",
        "rpm",
        "right rad/s",
        "rpm",
        "limit %",
        "time s",
        "x m",
        "y m",
        "theta deg",
    ]
    rows = [header]
    for s in p.segments:
        left, right = float(s.joints.left), float(s.joints.right)
        rows.append(
            [
                str(s.index + 1),
                describe_segment(s.segment),
                _fixed(float(s.twist.linear), 4),
                _fixed(float(s.twist.angular), 4),
                _fixed(left, 3),
                _fixed(rpm_from_rad_s(left), 2),
                _fixed(right, 3),
                _fixed(rpm_from_rad_s(right), 2),
                "-" if s.fraction is None else f"{100 * s.fraction:.1f}",
                fmt(s.duration, 6),
                _fixed(s.end_pose.x, 4),
                _fixed(s.end_pose.y, 4),
                _fixed(math.degrees(s.end_pose.theta), 2),
            ]
        )
    widths = [max(len(row[i]) for row in rows) for i in range(len(header))]
    lines = [
        f"{label}: {format_plan(s.segment for s in p.segments)}",
        f"robot: {params.source} (wheel radius {fmt(params.wheel_radius)} m, "
        f"separation {fmt(params.wheel_separation)} m); motor limit {_plan_limit_text(p)}",
        "",
    ]
    for row in rows:
        cells = [
            cell.ljust(widths[i]) if i == 1 else cell.rjust(widths[i]) for i, cell in enumerate(row)
        ]
        lines.append("  ".join(cells).rstrip())
    final = p.final_pose
    lines.append("")
    lines.append(
        f"total {fmt(p.duration, 6)} s; final pose x {_fixed(final.x, 4)} m, "
        f"y {_fixed(final.y, 4)} m, theta {_fixed(math.degrees(final.theta), 2)} deg"
    )
    if p.limit is None:
        lines.append("motor limit: none in the description, not checked")
    else:
        peak = max(p.segments, key=lambda s: s.fraction or 0.0)
        if p.within_limit:
            lines.append(
                f"motor limit {_plan_limit_text(p)}: within, peak "
                f"{100 * (peak.fraction or 0.0):.1f}% in segment {peak.index + 1}"
            )
        else:
            over = sorted({v.index + 1 for v in p.violations()})
            lines.append(
                f"motor limit {_plan_limit_text(p)}: OVER in segment"
                f"{'s' if len(over) > 1 else ''} {', '.join(map(str, over))}"
            )
    return "\n".join(lines) + "\n"


def _plan_csv(p: Plan) -> str:
    import csv
    import io

    from diffbot.trajectory import format_segment

    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(
        [
            "segment",
            "kind",
            "spec",
            "duration",
            "linear",
            "angular",
            "left",
            "right",
            "left_rpm",
            "right_rpm",
            "fraction",
            "x",
            "y",
            "theta",
        ]
    )
    for s in p.segments:
        values = [
            s.duration,
            s.twist.linear,
            s.twist.angular,
            s.joints.left,
            s.joints.right,
            rpm_from_rad_s(s.joints.left),
            rpm_from_rad_s(s.joints.right),
        ]
        writer.writerow(
            [
                s.index + 1,
                s.kind,
                format_segment(s.segment),
                *(repr(float(v)) for v in values),
                "" if s.fraction is None else repr(s.fraction),
                repr(s.end_pose.x),
                repr(s.end_pose.y),
                repr(s.end_pose.theta),
            ]
        )
    return out.getvalue()


def _segment_note(s: PlannedSegment, count: int) -> str:
    from diffbot.trajectory import describe_segment

    return f"{s.index + 1}/{count} {describe_segment(s.segment)}, {fmt(s.duration, 6)} s"


def _plan_twist(p: Plan, label: str, topic: str) -> str:
    count = len(p.segments)
    lines = [
        f"# {_one_line(label)} on {_one_line(p.params.source)}: geometry_msgs/msg/Twist commands "
        f"for {topic}, each held for its duration (m/s, rad/s)",
        f"# publish one with: ros2 topic pub -r 10 {topic} geometry_msgs/msg/Twist "
        "'{linear: {x: ...}, angular: {z: ...}}'",
    ]
    for s in p.segments:
        twist = _twist_yaml(float(s.twist.linear), float(s.twist.angular))
        lines.append(f"{twist}  # {_segment_note(s, count)}")
    lines.append(f"{_twist_yaml(0.0, 0.0)}  # stop")
    return "\n".join(lines) + "\n"


def _plan_wheels(p: Plan, label: str, left_topic: str, right_topic: str) -> str:
    params = p.params
    count = len(p.segments)
    width = max(len(left_topic), len(right_topic))
    lines = [
        f"# {_one_line(label)} on {_one_line(params.source)}: std_msgs/msg/Float64MultiArray "
        "joint velocity commands (rad/s), each held for its duration",
        f"# left: {left_topic} ({params.left_joint}, direction {params.left_sign:+d})",
        f"# right: {right_topic} ({params.right_joint}, direction {params.right_sign:+d})",
    ]
    for s in p.segments:
        lines.append(f"# {_segment_note(s, count)}")
        lines.append(f"{left_topic.ljust(width)}  {_array_yaml(float(s.joints.left))}")
        lines.append(f"{right_topic.ljust(width)}  {_array_yaml(float(s.joints.right))}")
    lines.append("# stop")
    lines.append(f"{left_topic.ljust(width)}  {_array_yaml(0.0)}")
    lines.append(f"{right_topic.ljust(width)}  {_array_yaml(0.0)}")
    return "\n".join(lines) + "\n"


def _seconds_text(duration: float) -> str:
    """A duration (s) for ``sleep``: plain decimals (no exponent), to the nanosecond."""
    text = f"{duration:.9f}".rstrip("0").rstrip(".")
    return text or "0"


def _plan_ros2(
    p: Plan,
    label: str,
    *,
    wheels: bool,
    rate: float,
    cmd_vel: str,
    left_topic: str,
    right_topic: str,
) -> str:
    """A POSIX sh script that publishes the plan with ``ros2 topic pub``.

    Each segment runs its publishers in the background with no ``-t`` and stops them after the
    segment's duration, timed by ``sleep``: with ``-t N``, current ros2cli publishes the first
    message at once and exits (N - 1) periods later plus a 0.1 s ``--keep-alive``, older releases
    N periods later, so counting messages cannot give the duration. The ``sleep`` runs in the
    background too, so that a signal is handled at once by ``wait`` (a shell runs its traps only
    after the foreground command ends).
    """
    import shlex

    from diffbot import __version__
    from diffbot.trajectory import format_plan

    q = shlex.quote
    twist_type = "geometry_msgs/msg/Twist"
    array_type = "std_msgs/msg/Float64MultiArray"
    count = len(p.segments)
    hz = _number_text_plain(rate)
    lines = [
        "#!/bin/sh",
        f"# {_one_line(label)}: {format_plan(s.segment for s in p.segments)}",
        f"# robot: {_one_line(p.params.source)} (wheel radius {fmt(p.params.wheel_radius)} m, "
        f"separation {fmt(p.params.wheel_separation)} m); {count} segments, "
        f"{fmt(p.duration, 6)} s; generated by diffbot {__version__}",
        "#",
        f"# Each segment runs 'ros2 topic pub -r {hz}' in the background (publishing {hz} times a",
        "# second) for exactly the segment's duration, timed by 'sleep' (fractional seconds, as",
        "# GNU coreutils and busybox sleep accept), then stops it and starts the next segment's.",
        "# The controllers hold the last command in between. Each 'ros2 topic pub' takes a",
        "# moment to start (up to about a second) before its first message: as every segment's",
        "# time counts from its publisher's start, these delays shift the commands rather than",
        "# add up, but a segment shorter than that may publish nothing. Use a node for tighter",
        "# timing.",
        "# The robot is always stopped at the end, also on Ctrl-C, kill or a failed publisher: the",
        "# publishers are stopped first, then one zero command is published with --once.",
        "set -e",
        "",
        "pids=''",
        "stop() {",
        "    trap - EXIT INT TERM",
        '    if [ -n "$pids" ]; then kill $pids 2>/dev/null || true; fi',
    ]
    if wheels:
        zero = _array_yaml(0.0)
        lines += [
            f"    ros2 topic pub --once {q(left_topic)} {array_type} {q(zero)} &",
            "    left=$!",
            f"    ros2 topic pub --once {q(right_topic)} {array_type} {q(zero)} &",
            '    wait "$left"',
            '    wait "$!"',
            "}",
        ]
    else:
        lines += [
            f"    ros2 topic pub --once {q(cmd_vel)} {twist_type} {q(_twist_yaml(0.0, 0.0))}",
            "}",
        ]
    lines += [
        "# hold SECONDS: let the publishers in $pids run that long, then stop them",
        "hold() {",
        '    sleep "$1" &',
        "    sleeper=$!",
        '    pids="$pids $sleeper"',
        '    wait "$sleeper"',
        "    for pid in $pids; do",
        '        if [ "$pid" != "$sleeper" ] && ! kill "$pid" 2>/dev/null; then',
        '            echo "error: ros2 topic pub stopped before the end of its segment" >&2',
        "            exit 1",
        "        fi",
        "    done",
        "    pids=''",
        "}",
        "trap stop EXIT",
        "trap 'exit 130' INT",
        "trap 'exit 143' TERM",
        "",
    ]
    for s in p.segments:
        lines.append(f"# {_segment_note(s, count)}")
        if wheels:
            left = _array_yaml(float(s.joints.left))
            right = _array_yaml(float(s.joints.right))
            lines += [
                f"ros2 topic pub -r {hz} {q(left_topic)} {array_type} {q(left)} &",
                'pids="$!"',
                f"ros2 topic pub -r {hz} {q(right_topic)} {array_type} {q(right)} &",
                'pids="$pids $!"',
            ]
        else:
            twist = _twist_yaml(float(s.twist.linear), float(s.twist.angular))
            lines += [
                f"ros2 topic pub -r {hz} {q(cmd_vel)} {twist_type} {q(twist)} &",
                'pids="$!"',
            ]
        lines += [f"hold {_seconds_text(s.duration)}", ""]
    lines += ["stop"]
    return "\n".join(lines) + "\n"


def _number_text_plain(value: float) -> str:
    text = repr(float(value))
    return text[:-2] if text.endswith(".0") else text


def _violation_lines(p: Plan) -> list[str]:
    from diffbot.trajectory import describe_segment

    limit_rpm = fmt(rpm_from_rad_s(p.limit), 5) if p.limit is not None else "?"
    by_segment: dict[int, list[Violation]] = {}
    for v in p.violations():
        by_segment.setdefault(v.index, []).append(v)
    lines = []
    for index, found in by_segment.items():
        s = p.segments[index]
        parts = [(v.wheel, fmt(v.rpm, 4)) for v in found]
        if len(parts) == 2 and parts[0][1] == parts[1][1]:
            what = f"left and right wheels at {parts[0][1]} rpm exceed"
        elif len(parts) == 2:
            what = f"left wheel at {parts[0][1]} rpm and right wheel at {parts[1][1]} rpm exceed"
        else:
            what = f"{parts[0][0]} wheel at {parts[0][1]} rpm exceeds"
        lines.append(
            f"error: segment {index + 1} ({describe_segment(s.segment)}, {fmt(s.duration, 6)} s): "
            f"{what} the {limit_rpm} rpm limit; shortest duration that fits: "
            f"{_ceil_text(found[0].shortest_duration)} s"
        )
    return lines


def _check_topic(option: str, name: str) -> str:
    if not re.fullmatch(_TOPIC_NAME, name):
        fail(f"{option} {name!r} is not a valid ROS topic name")
    return name


def plan_input_options(command: F) -> F:
    """The options that say which plan to make, shared by ``plan`` and ``simulate``."""
    options = [
        click.option(
            "--example",
            type=click.Choice(["A", "B"], case_sensitive=False),
            metavar="A|B",
            help="One of the seed's Figure 1 paths (A is used when nothing is given).",
        ),
        click.option(
            "--speed",
            type=POSITIVE,
            default=0.1,
            show_default=True,
            metavar="M/S",
            help="Cruise path speed of straights and arcs without a duration (m/s).",
        ),
        click.option(
            "--spin-rate",
            type=POSITIVE,
            default=0.5,
            show_default=True,
            metavar="RAD/S",
            help="Turn rate of spins without a duration (rad/s; 0.5 rad/s = 28.6 deg/s).",
        ),
        click.option(
            "--fastest",
            is_flag=True,
            help="Give every segment the shortest duration that keeps its wheels within the "
            "limit (durations given in the plan are ignored).",
        ),
        click.option(
            "--rpm-limit",
            type=POSITIVE,
            metavar="RPM",
            help="Motor limit to check against (rpm), instead of the description's (or --max-rpm).",
        ),
    ]
    decorated: Any = command
    for option in reversed(options):
        decorated = option(decorated)
    return decorated  # type: ignore[no-any-return]


@main.command("plan", context_settings=NUMBERS)
@click.argument("tokens", nargs=-1, metavar="[SPEC | FILE] [NAME:=VALUE]...")
@robot_options
@plan_input_options
@click.option(
    "--format",
    "output_format",
    type=click.Choice(PLAN_FORMATS),
    default="table",
    show_default=True,
    help="table: for people; json, csv: for programs; twist, wheels: ROS message lines; "
    "ros2: a shell script that publishes the plan.",
)
@click.option("--json", "as_json", is_flag=True, help="Same as --format json.")
@click.option(
    "--wheels",
    "per_wheel",
    is_flag=True,
    help="ros2 script: publish per-wheel controller commands instead of cmd_vel Twists.",
)
@click.option(
    "--rate",
    type=FiniteFloat(0.0, open_min=True, maximum=MAX_PUBLISH_RATE),
    default=10.0,
    show_default=True,
    metavar="HZ",
    help=f"ros2 script: publishing rate (Hz, at most {MAX_PUBLISH_RATE:g}).",
)
@click.option(
    "--cmd-vel-topic",
    default="cmd_vel",
    show_default=True,
    metavar="TOPIC",
    help="Twist topic (twist and ros2 formats).",
)
@click.option(
    "--left-topic",
    default="left_wheel_velocity_controller/commands",
    show_default=True,
    metavar="TOPIC",
    help="Left wheel Float64MultiArray topic (wheels format, ros2 --wheels).",
)
@click.option(
    "--right-topic",
    default="right_wheel_velocity_controller/commands",
    show_default=True,
    metavar="TOPIC",
    help="Right wheel topic, likewise.",
)
@click.option(
    "-o",
    "--output",
    type=click.Path(dir_okay=False),
    help="Write to this file instead of stdout (whole or not at all).",
)
@click.option("--force", is_flag=True, help="Overwrite --output if it exists.")
def plan_command(
    robot: RobotOptions,
    tokens: tuple[str, ...],
    example: str | None,
    speed: float,
    spin_rate: float,
    fastest: bool,
    rpm_limit: float | None,
    output_format: str,
    as_json: bool,
    per_wheel: bool,
    rate: float,
    cmd_vel_topic: str,
    left_topic: str,
    right_topic: str,
    output: str | None,
    force: bool,
) -> None:
    """Velocity commands, wheel speeds and exact poses of a path.

    SPEC is a plan in text form, segments separated by ';' or newlines ('#' comments):

    \b
      straight LENGTH [DURATION]
      ccw RADIUS ANGLE [DURATION]     counter-clockwise (left) arc
      cw RADIUS ANGLE [DURATION]      clockwise (right) arc
      spin ANGLE [DURATION]           turn in place, positive = counter-clockwise

    Lengths are in m (or 25cm, 250mm), angles in degrees (or 1.57rad), durations in s (10s).
    Several arguments are joined: each starts a segment ('straight 1' 'spin 90' is 'straight 1;
    spin 90'), except one that starts with a number, which continues the segment before it (so
    straight 1 10s and spin -90deg need no quotes).
    FILE is a .yaml/.yml list such as [{straight: 1, duration: 10}, {arc: ccw, radius: 0.25,
    angle: 180}, {spin: 90}], the same in .json ([{"straight": 1, "duration": 10}, {"spin":
    90}]), or a .txt file in text form. Without either, the seed's Trajectory A is planned
    (--example A).

    Segments without a duration run at --speed (spins at --spin-rate). The robot starts at
    (0, 0) heading along x. Exit code 1 when a wheel exceeds the motor limit (the output is still
    printed); the message names the segment, the wheel and the shortest duration that fits.

    \b
    Examples:
      diffbot plan                                    the seed's Trajectory A
      diffbot plan "straight 1 10s; ccw 25cm 90; spin -90 2s"
      diffbot plan --example B --fastest
      diffbot plan path.yaml --format ros2 -o run.sh  a script of 'ros2 topic pub' commands
    """
    from diffbot.trajectory import plan as make_plan

    rest, xacro_args = split_xacro_args(tokens)
    if as_json and output_format not in ("table", "json"):
        fail(f"--json and --format {output_format} ask for two formats: give one")
    if as_json:
        output_format = "json"
    if per_wheel and output_format != "ros2":
        warn("--wheels only changes --format ros2 (the wheels format is always per wheel)")
    _check_topic("--cmd-vel-topic", cmd_vel_topic)
    _check_topic("--left-topic", left_topic)
    _check_topic("--right-topic", right_topic)
    source = _plan_input(rest, example)
    # Early, before any work, and in the plan's own words; write_text_atomic checks again.
    plan_file = [Path(source.path)] if source.path is not None else []
    if output is not None and input_clash(Path(output), plan_file) is not None:
        fail(f"{output} is the plan file itself: write the output elsewhere")
    params = robot.with_path(None, xacro_args).load()
    limit = None if rpm_limit is None else rad_s_from_rpm(rpm_limit)
    if fastest and limit is None and params.max_wheel_speed is None:
        fail(
            "--fastest needs a motor limit, and the robot description has none: "
            "give one with --max-rpm RPM or --rpm-limit RPM"
        )
    p = make_plan(
        source.segments, params, speed=speed, spin_rate=spin_rate, fastest=fastest, limit=limit
    )
    if output_format == "json":
        text = json.dumps(_plan_json(p, source.label), indent=2, allow_nan=False) + "\n"
    elif output_format == "csv":
        text = _plan_csv(p)
    elif output_format == "twist":
        text = _plan_twist(p, source.label, cmd_vel_topic)
    elif output_format == "wheels":
        text = _plan_wheels(p, source.label, left_topic, right_topic)
    elif output_format == "ros2":
        text = _plan_ros2(
            p,
            source.label,
            wheels=per_wheel,
            rate=rate,
            cmd_vel=cmd_vel_topic,
            left_topic=left_topic,
            right_topic=right_topic,
        )
    else:
        text = _plan_table(p, source.label)
    if output is None:
        click.echo(text, nl=False)
    else:
        inputs = [path for path in (source.path, robot.robot) if path is not None]
        write_text_atomic(
            Path(output),
            text,
            force=force,
            inputs=[Path(path) for path in inputs],
            executable=output_format == "ros2",
        )
    if not p.within_limit:
        for line in _violation_lines(p):
            click.echo(line, err=True)
        sys.exit(EXIT_CHECK_FAILED)


# --------------------------------------------------------------------------------------------
# odom: odometry from recorded wheel joint states

if TYPE_CHECKING:
    from diffbot.recording import Recording


def _check_out(out: str | None, inputs: Sequence[Path], force: bool) -> Path | None:
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


def _read_stdin_csv(params: DiffDriveParams) -> Recording:
    """The CSV on stdin, read whole (``diffbot simulate | diffbot odom -``)."""
    import io

    from diffbot.recording import read_csv

    data = sys.stdin.buffer.read()
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError:
        fail("-: stdin is not a text (UTF-8) CSV")
    return read_csv(
        io.StringIO(text, newline=""), params.left_joint, params.right_joint, source="-"
    )


def _skipped_text(skipped: Mapping[str, int]) -> str:
    return ", ".join(f"{count} {reason}" for reason, count in sorted(skipped.items()))


@main.command()
@click.argument("tokens", nargs=-1, metavar="INPUT [NAME:=VALUE]...")
@robot_options
@click.option(
    "--topic",
    metavar="TOPIC",
    default="/joint_states",
    show_default=True,
    help="The sensor_msgs/JointState topic of a bag.",
)
@click.option(
    "--out",
    metavar="PATH",
    help="Write the poses: a CSV file (time,x,y,theta,linear,angular), or a bag with --bag.",
)
@click.option(
    "--bag",
    "as_bag",
    is_flag=True,
    help="Write --out as a rosbag2 directory: nav_msgs/Odometry on /odom, TF on /tf.",
)
@click.option("--force", is_flag=True, help="Overwrite --out if it exists.")
@click.option("--json", "as_json", is_flag=True, help="Machine-readable summary.")
def odom(
    robot: RobotOptions,
    tokens: tuple[str, ...],
    topic: str,
    out: str | None,
    as_bag: bool,
    force: bool,
    as_json: bool,
) -> None:
    """Odometry from recorded wheel joint positions.

    INPUT is a CSV file (a time column `time`, `stamp`, `t` or `__time` in seconds, and one
    position column per wheel named by its joint or ending with `/<joint>/position`; `-` reads
    it from stdin), a rosbag2
    directory (sqlite3 or mcap) or one of its .db3/.mcap files holding sensor_msgs/JointState on
    --topic. A bag's samples are all stamped by their header stamps, or all by the bag's receive
    times when any header stamp is zero (the summary says which). Each step is integrated
    exactly along its arc; the first sample sets the encoder baseline. Samples
    without both wheel joints, with NaN/inf or with a stamp not after the previous one are
    skipped and reported.

    \b
    Reading bags needs the optional rosbags dependency:
      pip install 'diffbot-kinematics[bag]'

    \b
    Examples:
      diffbot odom joints.csv
      diffbot simulate "straight 1; spin 90" | diffbot odom -
      diffbot odom my_bag/ --topic /joint_states --out odom.csv
      diffbot odom run.mcap --out odom_bag --bag --json
    """
    from diffbot.odometry import Odometry
    from diffbot.recording import (
        format_odometry_csv,
        read_recording,
        run_odometry,
        write_odometry_bag,
    )

    rest, xacro_args = split_xacro_args(tokens)
    if len(rest) != 1:
        fail(
            "expected one INPUT (a CSV file, - for a CSV on stdin, a rosbag2 directory or a "
            f".db3/.mcap file), got {rest}"
        )
    source = rest[0]
    from_stdin = source == "-"
    if not source.strip():
        fail("INPUT is empty: give a CSV file, - for stdin, or a rosbag2 recording")
    if not from_stdin and not Path(source).exists():
        fail(f"{source}: no such file or directory")
    if as_bag and out is None:
        fail("--bag writes the --out directory: give --out DIR")
    robot = robot.with_path(None, xacro_args)
    inputs = [Path(path) for path in (None if from_stdin else source, robot.robot) if path]
    out_path = _check_out(out, inputs, force)
    p = robot.load()
    recording = _read_stdin_csv(p) if from_stdin else read_recording(source, p, topic)
    integrator = Odometry(p)
    run = run_odometry(recording, integrator)
    if out_path is not None:
        if as_bag:
            write_odometry_bag(out_path, run.rows, integrator, force=force)
        else:
            write_text_atomic(out_path, format_odometry_csv(run.rows), force=force)
    skipped_total = sum(run.skipped.values())
    if skipped_total:
        warn(
            f"skipped {skipped_total} of {run.samples + skipped_total} samples: "
            f"{_skipped_text(run.skipped)}"
        )
    pose = run.final_pose
    if as_json:
        emit_json(
            {
                "input": source,
                "final_pose": {"x": pose.x, "y": pose.y, "theta": pose.theta},
                "distance": run.distance,
                "samples": run.samples,
                "skipped": dict(sorted(run.skipped.items())),
                "duration": run.duration,
                "clock": recording.clock,
                "output": out,
            }
        )
        return
    kind = "CSV" if recording.kind == "csv" else f"rosbag2, topic {topic}, {recording.clock} stamps"
    rows = [
        ("input", f"{source} ({kind})"),
        ("samples", f"{run.samples} used, {skipped_total} skipped"),
        ("duration", f"{fmt(run.duration)} s"),
        ("distance", f"{fmt(run.distance)} m"),
        (
            # Rounded to the nanometre (nanoradian) so rounding noise reads as 0; --json has all.
            "final pose",
            f"x {fmt(round(pose.x, 9))} m, y {fmt(round(pose.y, 9))} m, "
            f"theta {fmt(round(pose.theta, 9))} rad "
            f"({fmt(round(math.degrees(pose.theta), 7), 5)} deg)",
        ),
    ]
    if out is not None:
        what = "rosbag2: /odom, /tf" if as_bag else "CSV"
        rows.append(("output", f"{out} ({what}, {len(run.rows)} poses)"))
    for label, value in rows:
        click.echo(f"{label:<11} {value}")


# --------------------------------------------------------------------------------------------
# simulate: the wheel joint states a plan would produce


class _RateType(FiniteFloat):
    """A sampling rate (Hz): > 0 and at most diffbot.simulation.MAX_RATE."""

    def __init__(self) -> None:
        super().__init__(0.0, open_min=True)

    def convert(
        self, value: Any, param: click.Parameter | None, ctx: click.Context | None
    ) -> float:
        from diffbot.simulation import MAX_RATE

        number = super().convert(value, param, ctx)
        if number > MAX_RATE:
            self.fail(f"{value!r} must be <= {MAX_RATE:g} Hz", param, ctx)
        return number


class _StartType(click.ParamType):  # type: ignore[type-arg,unused-ignore]
    """Seconds since 1970 as a decimal number, read exactly into integer nanoseconds."""

    name = "seconds"

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> int:
        from diffbot.recording import _ns_from_seconds

        if isinstance(value, int):
            return value
        try:
            stamp_ns = _ns_from_seconds(str(value))
        except ValueError:
            self.fail(f"{value!r} is not a number", param, ctx)
        if stamp_ns is None:
            self.fail(f"{value!r} is not a finite number", param, ctx)
        if stamp_ns < 0:
            self.fail(f"{value!r} must be >= 0", param, ctx)
        if stamp_ns >= 2**63:
            self.fail(f"{value!r} is past 2262, the end of int64 nanosecond stamps", param, ctx)
        return stamp_ns


@main.command(context_settings=NUMBERS)
@click.argument("tokens", nargs=-1, metavar="[SPEC | FILE] [NAME:=VALUE]...")
@robot_options
@plan_input_options
@click.option(
    "--rate",
    type=_RateType(),
    default=50.0,
    show_default=True,
    metavar="HZ",
    help="Sampling rate of the joint states (Hz), at most 1e6.",
)
@click.option(
    "--ticks",
    type=click.IntRange(min=1, max=2**32),  # diffbot.simulation.MAX_TICKS
    metavar="N",
    help="Encoder resolution (counts per revolution, up to 2**32): quantise the wheel angles.",
)
@click.option(
    "--noise",
    type=NON_NEGATIVE,
    default=0.0,
    metavar="STD",
    help="Standard deviation of Gaussian noise on the wheel angles (rad).",
)
@click.option(
    "--seed",
    type=click.IntRange(min=0, max=2**64 - 1),
    metavar="N",
    help="Seed of the noise (0 to 2**64-1), for reproducible runs.",
)
@click.option(
    "--start",
    "start_ns",
    type=_StartType(),
    default="0",
    show_default=True,
    metavar="S",
    help="Stamp of the first sample (s since 1970, read exactly to the nanosecond).",
)
@click.option(
    "--out",
    metavar="PATH",
    help="Write to this file (CSV) or, with --bag, this rosbag2 directory; default: CSV on stdout.",
)
@click.option(
    "--bag",
    "as_bag",
    is_flag=True,
    help="Write --out as a rosbag2 directory of sensor_msgs/JointState.",
)
@click.option(
    "--topic",
    metavar="TOPIC",
    default="/joint_states",
    show_default=True,
    help="The JointState topic of --bag.",
)
@click.option("--force", is_flag=True, help="Overwrite --out if it exists.")
@click.option("--json", "as_json", is_flag=True, help="Machine-readable summary (needs --out).")
def simulate(
    robot: RobotOptions,
    tokens: tuple[str, ...],
    example: str | None,
    speed: float,
    spin_rate: float,
    fastest: bool,
    rpm_limit: float | None,
    rate: float,
    ticks: int | None,
    noise: float,
    seed: int | None,
    start_ns: int,
    out: str | None,
    as_bag: bool,
    topic: str,
    force: bool,
    as_json: bool,
) -> None:
    """Wheel joint states that executing a plan would produce.

    The plan is given as for `diffbot plan` (SPEC text, a FILE, or --example; Trajectory A when
    nothing is given). The drive wheel joints follow its commands exactly, sampled at --rate Hz
    plus one sample at every segment boundary and at the end, so that `diffbot odom` of the
    result ends exactly at the plan's final pose. --noise adds Gaussian noise to the wheel angles,
    then --ticks quantises them as an encoder would. The caster joints (caster_rotation_joint,
    caster_wheel_joint) are reported at 0: the caster is not modelled.

    Output: CSV (time in s, then one column per joint in rad) on stdout or --out, or with --bag a
    rosbag2 directory of sensor_msgs/JointState on --topic. Exit code 1 when the plan exceeds the
    motor limit (the output is still written).

    \b
    Examples:
      diffbot simulate --out a.csv && diffbot odom a.csv
      diffbot simulate "straight 1; spin 90" --rate 20 --ticks 1024 --noise 0.001 --seed 1
      diffbot simulate --example B --out b_bag --bag --start 1700000000
    """
    from diffbot.recording import format_joint_states_csv, write_joint_states_bag
    from diffbot.simulation import MAX_SAMPLES, sample_count
    from diffbot.simulation import simulate as simulate_plan
    from diffbot.trajectory import plan as make_plan

    rest, xacro_args = split_xacro_args(tokens)
    _check_topic("--topic", topic)
    source = _plan_input(rest, example)
    if as_bag and out is None:
        fail("--bag writes the --out directory: give --out DIR")
    if as_json and out is None:
        fail("--json prints a summary, so the samples need --out")
    robot = robot.with_path(None, xacro_args)
    inputs = [path for path in (source.path, robot.robot) if path is not None]
    out_path = _check_out(out, [Path(path) for path in inputs], force)
    params = robot.load()
    limit = None if rpm_limit is None else rad_s_from_rpm(rpm_limit)
    p = make_plan(
        source.segments, params, speed=speed, spin_rate=spin_rate, fastest=fastest, limit=limit
    )
    count = sample_count(p.duration, rate, len(p.segments))
    if count > MAX_SAMPLES:
        highest = (MAX_SAMPLES - 2 - len(p.segments)) / p.duration
        how = (
            f"lower --rate to at most {highest:.4g} Hz for this plan"
            if highest >= 1.0
            else "the plan is too long even at 1 Hz: shorten it (or raise --speed)"
        )
        fail(
            f"the plan's {fmt(p.duration)} s at {fmt(rate)} Hz would take {count:.4g} samples, "
            f"more than the {MAX_SAMPLES} simulate makes: {how}"
        )
    if start_ns + round(p.duration * 1e9) >= 2**63:
        fail(
            f"--start plus the plan's {fmt(p.duration)} s ends past 2262, the end of int64 "
            "nanosecond stamps"
        )
    states = simulate_plan(p, params, rate, ticks=ticks, noise=noise, seed=seed)
    stamps = [start_ns + round(t * 1e9) for t in states.times.tolist()]
    if out_path is None:
        click.echo(format_joint_states_csv(stamps, states.names, states.positions), nl=False)
    elif as_bag:
        write_joint_states_bag(
            out_path, stamps, states.names, states.positions, force=force, topic=topic
        )
    else:
        text = format_joint_states_csv(stamps, states.names, states.positions)
        write_text_atomic(out_path, text, force=force)
    if out_path is not None:
        pose = p.final_pose
        if as_json:
            emit_json(
                {
                    "plan": source.label,
                    "duration": p.duration,
                    "samples": int(states.times.size),
                    "rate": rate,
                    "joints": list(states.names),
                    "final_pose": {"x": pose.x, "y": pose.y, "theta": pose.theta},
                    "within_limit": p.within_limit,
                    "output": out,
                }
            )
        else:
            what = f"rosbag2, {topic}" if as_bag else "CSV"
            rows = [
                (
                    "plan",
                    f"{source.label} ({len(p.segments)} segment"
                    f"{'' if len(p.segments) == 1 else 's'}, {fmt(p.duration)} s)",
                ),
                (
                    "samples",
                    f"{states.times.size} at {fmt(rate)} Hz and segment ends, "
                    f"{len(states.names)} joints",
                ),
                (
                    "final pose",
                    f"x {fmt(round(pose.x, 9))} m, y {fmt(round(pose.y, 9))} m, "
                    f"theta {fmt(round(pose.theta, 9))} rad",
                ),
                ("output", f"{out} ({what})"),
            ]
            for label, value in rows:
                click.echo(f"{label:<11} {value}")
    if not p.within_limit:
        for line in _violation_lines(p):
            click.echo(line, err=True)
        sys.exit(EXIT_CHECK_FAILED)
