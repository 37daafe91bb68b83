"""Commands about the robot itself: ``params``, ``urdf``, ``ik`` and ``fk``."""

from __future__ import annotations

import math
import sys
from pathlib import Path
from typing import Any

import click

from diffbot import kinematics
from diffbot.body_limits import BodyLimits, body_limits, clamp, over
from diffbot.commands.limit_options import body_limit_option
from diffbot.commands.options import (
    NUMBERS,
    RobotOptions,
    check_finite,
    emit_json,
    fail,
    output_option,
    package_option,
    parse_number,
    parse_packages,
    robot_options,
    robot_path_option,
    split_xacro_args,
    trust_option,
    warn,
)
from diffbot.commands.paths import input_path
from diffbot.commands.said_once import quieted, shown_before
from diffbot.errors import EXIT_CHECK_FAILED
from diffbot.formats.plan_table import limit_text
from diffbot.formats.robot import params_json, params_lines
from diffbot.formats.text import fixed, fmt
from diffbot.io.outputs import write_text_atomic
from diffbot.kinematics import DiffDriveParams, Twist, WheelSpeeds
from diffbot.numbers import reads_as_number
from diffbot.urdf import expand

__all__ = ["fk", "ik", "params", "urdf"]


@click.command()
@click.argument("tokens", nargs=-1, metavar="[PATH] [NAME:=VALUE]...")
@robot_options
@click.option("--json", "as_json", is_flag=True, help="Machine-readable output.")
def params(robot: RobotOptions, tokens: tuple[str, ...], as_json: bool) -> None:
    """Show the robot parameters derived from a description.

    PATH is a .urdf or .urdf.xacro file, an SDF model (.sdf or model folder) or a bag holding
    /robot_description (default: the bundled diffbot); NAME:=VALUE tokens are xacro arguments.
    Drive wheels are found from the structure: continuous joints with a lateral axis hanging
    from base_link through fixed (or suspension) joints; left is +y (REP-103). A skid steer's
    wheels, split evenly between the sides, are all used.

    The robot's diff_drive_controller configuration (--controllers, or the file its ros2_control
    Gazebo plugin names) wins over the geometry: its separation times its multiplier, its radius
    times each side's multiplier, its wheel names; without one, the simulator's diff-drive plugin
    does (--source chooses). Each value says where it came from when that is not the
    description; sources that disagree are warnings (see `diffbot check`).

    \b
    Examples:
      diffbot params docs/examples/tutorial_bot/tutorial_bot.urdf --json
      diffbot params docs/examples/rover/urdf/rover.urdf.xacro wheel_radius:=0.04 \\
          --package rover_description=docs/examples/rover
    """
    p = robot.with_tokens(tokens).load(quiet=True)
    if as_json:
        emit_json(params_json(p))
        return
    for line in params_lines(p):
        click.echo(line)
    for message in p.warnings:
        warn(message)
    if p.warnings and not quieted():
        shown_before(p.source, p.warnings)  # shown in full: later commands count them


@click.command()
@click.argument("tokens", nargs=-1, metavar="[PATH] [NAME:=VALUE]...")
@robot_path_option("Robot description (same as PATH).")
@package_option("Package directory.")
@output_option("Write to this file instead of stdout.")
@click.option("--force", is_flag=True, help="Overwrite --output if it exists.")
@trust_option
def urdf(
    tokens: tuple[str, ...],
    robot: str | None,
    packages: tuple[tuple[str, str], ...],
    output: str | None,
    force: bool,
    trust: bool,
) -> None:
    """Print the expanded URDF of a description (like xacro).

    $(find NAME) is resolved from --package NAME=DIR, the packages of the description's source
    tree (folders holding a package.xml), the bundled packages, then AMENT_PREFIX_PATH and
    ROS_PACKAGE_PATH; no ROS install is needed.

    \b
    Example:
      diffbot urdf docs/examples/rover/urdf/rover.urdf.xacro wheel_radius:=0.04 \\
          --package rover_description=docs/examples/rover -o rover.urdf
    """

    rest, xacro_args = split_xacro_args(tokens)
    if len(rest) > 1:
        fail(f"expected at most one PATH, got {rest}")
    path = input_path(rest[0]) if rest else robot
    if rest and robot and rest[0] != robot:
        fail(f"two robots given: {rest[0]!r} and --robot {robot!r}")
    expansion = expand(path, xacro_args, parse_packages(packages), trust=trust)
    for message in expansion.warnings:
        warn(message)
    if output is None:
        click.echo(expansion.urdf, nl=False)
    else:
        # never over any file the description was read from, not only the top one
        write_text_atomic(Path(output), expansion.urdf, force=force, inputs=expansion.files)


def _robot_and_numbers(
    robot: RobotOptions, tokens: tuple[str, ...], names: tuple[str, str]
) -> tuple[tuple[float, float], RobotOptions]:
    """The two numbers named ``names`` among the tokens, and the robot options with the
    ``NAME:=VALUE`` tokens and a robot PATH written before the numbers, as every command that
    takes a robot takes it first."""
    rest, xacro_args = split_xacro_args(tokens)
    path = None
    if len(rest) == 3 and not reads_as_number(rest[0]):
        path, rest = rest[0], rest[1:]
    if len(rest) != 2:
        fail(f"expected {names[0]} and {names[1]}, got {len(rest)} value(s) {list(rest)}")
    numbers = parse_number(rest[0], names[0]), parse_number(rest[1], names[1])
    return numbers, robot.with_path(path, xacro_args)


def _speeds_json(params: DiffDriveParams, joints: WheelSpeeds) -> dict[str, Any]:
    return {
        "left": float(joints.left),
        "right": float(joints.right),
        "left_rpm": float(kinematics.rpm_from_rad_s(joints.left)),
        "right_rpm": float(kinematics.rpm_from_rad_s(joints.right)),
    }


@click.command(context_settings=NUMBERS)
@click.argument("tokens", nargs=-1, metavar="LINEAR ANGULAR [NAME:=VALUE]...")
@robot_options
@click.option(
    "--saturate",
    "do_saturate",
    is_flag=True,
    help="Clamp linear and angular velocity apart into the body limits, as "
    "diff_drive_controller does, then scale both wheels down to the motor limit, keeping the "
    "turning radius.",
)
@body_limit_option(0)
@body_limit_option(1)
@click.option("--json", "as_json", is_flag=True, help="Machine-readable output.")
def ik(
    robot: RobotOptions,
    tokens: tuple[str, ...],
    do_saturate: bool,
    max_linear: float | None,
    max_angular: float | None,
    as_json: bool,
) -> None:
    """Wheel speeds for a body velocity (inverse kinematics).

    LINEAR is the forward speed (m/s), ANGULAR the yaw rate (rad/s, positive counter-clockwise),
    as in a cmd_vel Twist. Prints the joint velocity commands (rad/s and rpm, with the joints'
    direction signs applied) and whether they are within the motor limit and the body limits
    (--max-linear, --max-angular, else the controllers file's linear.x and angular.z
    max_velocity). Exit code 1 when a wheel or the body velocity is over a limit (unless
    --saturate). The robot is --robot PATH, or PATH before LINEAR.

    \b
    Examples:
      diffbot ik 0.1 0                 straight at 0.1 m/s: 2.857 rad/s per wheel
      diffbot ik 0.157 -0.314          the 0.5 m clockwise circle in 20 s
    """
    (linear, angular), robot = _robot_and_numbers(robot, tokens, ("LINEAR", "ANGULAR"))
    p = robot.load()
    body = body_limits(p, max_linear, max_angular)
    asked = Twist(linear, angular)
    beyond = over(asked, body)
    clamped = do_saturate and bool(beyond)
    if clamped:
        asked = clamp(asked, body)
    wheels = kinematics.inverse(p, float(asked.linear), float(asked.angular))
    check_finite(
        "wheel speeds",
        float(wheels.left),
        float(wheels.right),
        float(kinematics.rpm_from_rad_s(wheels.left)),
    )
    check_finite("wheel speeds", float(kinematics.rpm_from_rad_s(wheels.right)))
    motor_scaled = do_saturate and not kinematics.within_limit(p, wheels)
    if motor_scaled:
        wheels = kinematics.saturate(p, wheels)
    saturated = clamped or motor_scaled
    body_ok = not over(kinematics.forward(p, wheels.left, wheels.right), body)
    joints = kinematics.joint_from_wheel(p, wheels)
    ok = kinematics.within_limit(p, wheels)
    fraction = kinematics.limit_fraction(p, wheels)
    if as_json:
        data = _speeds_json(p, joints)
        data["within_limit"] = ok
        if not body.unlimited:
            data["body_limits"] = {"linear": body.linear, "angular": body.angular}
            data["within_body_limits"] = body_ok
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
                f"{fmt(kinematics.rpm_from_rad_s(rad_s), 5):>9} rpm   ({joint})"
            )
        if saturated:
            twist = kinematics.forward(p, wheels.left, wheels.right)
            click.echo(
                f"saturated    to linear {fmt(float(twist.linear))} m/s, "
                f"angular {fmt(float(twist.angular))} rad/s "
                + _saturation_text(clamped, motor_scaled)
            )
        if fraction is None:
            click.echo("motor limit  none in the description")
        else:
            state = "within" if ok else "OVER"
            click.echo(
                f"motor limit  {limit_text(p)}: {state}, {fixed(100 * float(fraction), 1)}% used"
            )
        if not body.unlimited:
            click.echo(f"body limits  {_body_text(body)}: {'within' if body_ok else 'OVER'}")
    if not ok:
        _over_limit(p, wheels, " (try --saturate)")
    if beyond and not do_saturate:
        click.echo(
            f"error: the {' and '.join(beyond)} velocity exceeds the body limits "
            f"({_body_text(body)}) (try --saturate)",
            err=True,
        )
        sys.exit(EXIT_CHECK_FAILED)


def _saturation_text(clamped: bool, motor_scaled: bool) -> str:
    """What --saturate did, for people."""
    if not clamped:
        return "(same turning radius)"
    text = "(linear and angular clamped apart into the body limits, as diff_drive_controller does"
    return text + (", then both wheels scaled to the motor limit)" if motor_scaled else ")")


def _body_text(body: BodyLimits) -> str:
    """The body velocity limits for people: ranges in m/s and rad/s."""
    parts = []
    if body.linear is not None:
        parts.append(f"linear [{fmt(body.linear[0])}, {fmt(body.linear[1])}] m/s")
    if body.angular is not None:
        parts.append(f"angular [{fmt(body.angular[0])}, {fmt(body.angular[1])}] rad/s")
    return ", ".join(parts)


def _over_limit(p: DiffDriveParams, wheels: WheelSpeeds, hint: str = "") -> None:
    """Exit 1, naming the faster wheel, when the wheels exceed the motor limit."""
    faster = "left" if abs(float(wheels.left)) >= abs(float(wheels.right)) else "right"
    rpm = abs(float(kinematics.rpm_from_rad_s(wheels.left if faster == "left" else wheels.right)))
    click.echo(
        f"error: {faster} wheel at {fmt(rpm, 4)} rpm exceeds the motor limit of "
        f"{fmt(p.max_wheel_rpm or 0.0, 4)} rpm{hint}",
        err=True,
    )
    sys.exit(EXIT_CHECK_FAILED)


@click.command(context_settings=NUMBERS)
@click.argument("tokens", nargs=-1, metavar="LEFT RIGHT [NAME:=VALUE]...")
@robot_options
@click.option("--rpm", "in_rpm", is_flag=True, help="LEFT and RIGHT are in rpm, not rad/s.")
@click.option("--json", "as_json", is_flag=True, help="Machine-readable output.")
def fk(robot: RobotOptions, tokens: tuple[str, ...], in_rpm: bool, as_json: bool) -> None:
    """Body velocity from wheel joint velocities (forward kinematics).

    LEFT and RIGHT are the joint velocities (rad/s, or rpm with --rpm) as the controllers see them,
    with the description's direction signs; `diffbot ik` prints the same quantities. Exit code 1
    when a wheel is over the motor limit (the velocity is still printed).

    \b
    Examples:
      diffbot fk 1.637 2.848            Trajectory A's first arc: 0.0785 m/s, 0.314 rad/s
      diffbot fk 20 20 --rpm            the same in rpm
    """
    (left, right), robot = _robot_and_numbers(robot, tokens, ("LEFT", "RIGHT"))
    if in_rpm:
        left, right = (
            float(kinematics.rad_s_from_rpm(left)),
            float(kinematics.rad_s_from_rpm(right)),
        )
    p = robot.load()
    wheels = kinematics.wheel_from_joint(p, WheelSpeeds(left, right))
    twist = kinematics.forward(p, wheels.left, wheels.right)
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
        # From the wheels scaled to a peak of 1: the radius does not depend on their scale, and
        # speeds near the smallest floats would lose digits in the quotient of two tiny ones.
        left, right = float(wheels.left), float(wheels.right)
        peak = max(abs(left), abs(right))
        unit = kinematics.forward(p, left / peak, right / peak)
        turn = float(unit.linear) / float(unit.angular)
        radius = f"{fmt(turn)} m ({'counter-clockwise' if angular > 0 else 'clockwise'})"
    click.echo(f"radius   {radius}")
    if not kinematics.within_limit(p, wheels):
        _over_limit(p, wheels)
