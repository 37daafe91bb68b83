"""The ``diffbot`` command line: a thin layer over the library.

Exit codes: 0 success, 1 a result that fails a check (a wheel over the motor limit), 2 bad input or
usage. Errors are one line on stderr starting with ``error:``; machine output goes to stdout.
"""

from __future__ import annotations

import functools
import json
import math
import sys
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, NoReturn, TypeVar

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
    """A finite float, optionally bounded below; rejects NaN and infinities."""

    name = "number"

    def __init__(self, minimum: float | None = None, open_min: bool = False) -> None:
        self.minimum = minimum
        self.open_min = open_min

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
        return number


POSITIVE = FiniteFloat(0.0, open_min=True)
NON_NEGATIVE = FiniteFloat(0.0)
FINITE = FiniteFloat()


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
    if not token.startswith("-") or token == "-":
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
    for source in inputs:
        if source.exists() and target.exists() and source.resolve() == target.resolve():
            fail(f"{path} is an input: refusing to overwrite it")
    return target


def write_text_atomic(path: Path, text: str, *, force: bool, inputs: Sequence[Path] = ()) -> None:
    """Write a whole file or nothing: a temporary file beside it, then a rename.

    The file gets the permissions of the file it replaces, or the usual ones (umask applied).
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
