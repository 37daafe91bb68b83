"""``diffbot explain``: the worked derivation of a number, step by step, as the class shows it."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import click

from diffbot.commands.groups import SuggestingGroup
from diffbot.commands.options import (
    NUMBERS,
    RobotOptions,
    check_finite,
    fail,
    option_group,
    parse_number,
    robot_options,
    split_xacro_args,
    warn,
)
from diffbot.commands.plan_options import PlanOptions, plan_arguments
from diffbot.commands.shown_defaults import choice_option
from diffbot.explain import FORMATS, Derivation, languages, render
from diffbot.explain import explain_fk as derive_fk
from diffbot.explain import explain_ik as derive_ik
from diffbot.explain import explain_odom as derive_odom
from diffbot.explain import explain_plan as derive_plan
from diffbot.trajectory import Plan

__all__ = ["explain"]


@dataclass(frozen=True)
class Rendering:
    """How a derivation is shown: ``--lang`` and ``--format``."""

    lang: str
    fmt: str

    def show(self, derivation: Derivation) -> None:
        """Print the derivation; bad input when one of its numbers overflows."""
        check_finite("results", *(step.result.value for step in derivation.steps))
        click.echo(render(derivation, self.fmt, self.lang), nl=False)


#: Add ``--lang`` and ``--format``; the command receives them as ``rendering: Rendering``.
rendering_options = option_group(
    [
        choice_option(
            "--lang",
            choices=languages(),
            default="en",
            help="Language of the words (the maths is the same in all).",
        ),
        choice_option(
            "--format",
            "output_format",
            choices=FORMATS,
            default="text",
            help="text: for a terminal; md: Markdown with LaTeX maths, for notes.",
        ),
    ],
    "rendering",
    lambda kw: Rendering(kw.pop("lang"), kw.pop("output_format")),
)


def _numbers(
    robot: RobotOptions, tokens: Sequence[str], names: Sequence[str]
) -> tuple[list[float], RobotOptions]:
    """The numbers named ``names`` among the tokens, and the robot options with the tokens'
    ``NAME:=VALUE`` xacro arguments."""
    rest, xacro_args = split_xacro_args(tokens)
    if len(rest) != len(names):
        fail(f"expected {' '.join(names)}, got {len(rest)} value(s) {list(rest)}")
    values = [parse_number(token, name) for token, name in zip(rest, names, strict=True)]
    return values, robot.with_path(None, xacro_args)


@click.group(cls=SuggestingGroup)
def explain() -> None:
    """Worked derivations of ik, fk, plan and odom, step by step.

    Each step is a formula, then the formula with the robot's numbers, then the result with
    its unit. The numbers are those the other commands compute; the words are in English or
    Spanish (--lang es), as text or as Markdown with LaTeX maths for notes (--format md).

    \b
    Examples:
      diffbot explain ik 0.1 0 --lang es      wheel speeds for 0.1 m/s straight ahead
      diffbot explain fk 2.857 2.857
      diffbot explain plan --example A --format md > trajectory_a.md
      diffbot explain odom 0 0 1 1.5 0.1      one odometry step of 0.1 s
    """


def _numbers_command(
    name: str,
    names: tuple[str, ...],
    derive: Callable[..., Derivation],
    help_text: str,
    examples: Sequence[str],
) -> click.Command:
    """A subcommand that derives from a few numbers given as arguments, in this order."""
    lines = "\n".join(f"  {example}" for example in examples)
    help_text = f"{help_text}\n\n\b\nExamples:\n{lines}"

    @explain.command(name, context_settings=NUMBERS, help=help_text)
    @click.argument("tokens", nargs=-1, metavar=f"{' '.join(names)} [NAME:=VALUE]...")
    @robot_options
    @rendering_options
    def command(robot: RobotOptions, rendering: Rendering, tokens: tuple[str, ...]) -> None:
        values, robot = _numbers(robot, tokens, names)
        rendering.show(derive(robot.load(), *values, joints=True))

    return command


ik = _numbers_command(
    "ik",
    ("LINEAR", "ANGULAR"),
    derive_ik,
    "Wheel speeds for a body velocity: LINEAR (m/s) and ANGULAR (rad/s, positive "
    "counter-clockwise), and the check against the motor limit.",
    [
        "diffbot explain ik 0.1 0 --lang es",
        "diffbot explain ik docs/examples/tutorial_bot/tutorial_bot.urdf 0.2 1 --format md",
    ],
)
fk = _numbers_command(
    "fk",
    ("LEFT", "RIGHT"),
    derive_fk,
    "Body velocity for two joint velocities: LEFT and RIGHT (rad/s) as 'diffbot fk' takes "
    "them, with the description's direction signs (a mirrored axis turns backwards to roll "
    "forward).",
    ["diffbot explain fk 2.857 2.857", "diffbot explain fk -1 2.5 --format md"],
)
odom = _numbers_command(
    "odom",
    ("L0", "R0", "L1", "R1", "DT"),
    derive_odom,
    "One odometry step from the origin: the joint angles before (L0, R0) and after (L1, R1) "
    "the step (rad, as a recording holds them: a mirrored axis turns backwards to roll "
    "forward), and DT its duration (s), as 'diffbot odom' reads two such samples.",
    ["diffbot explain odom 0 0 1 1.5 0.1", "diffbot explain odom 0 0 -2 2 0.5 --lang es"],
)


@explain.command("plan", context_settings=NUMBERS)
@plan_arguments
@rendering_options
def plan(
    robot: RobotOptions,
    plan_options: PlanOptions,
    rendering: Rendering,
    tokens: tuple[str, ...],
) -> None:
    """A plan segment by segment: v, ω, each wheel's speed, the rpm check and the end pose.

    SPEC, FILE and the plan options are those of 'diffbot plan' (see 'diffbot plan --help');
    without a plan, Trajectory A is explained.

    \b
    Examples:
      diffbot explain plan --example A --format md > trajectory_a.md
      diffbot explain plan "straight 1; spin 90" --fastest
    """
    made = plan_options.build(plan_options.request(robot, tokens)).made
    if not isinstance(made, Plan):
        # The step plan holds the cruise speeds, the motor limit check and the poses.
        warn("a ramped plan is derived at its cruise speeds: the ramps are not derived")
        made = made.steps
    rendering.show(derive_plan(made))
