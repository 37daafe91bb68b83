"""Warnings about the cruise options of a plan: given where they change nothing, or over the
body velocity limits (the segments they time are then slowed, which the plan would not say)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from diffbot.commands.options import warn
from diffbot.trajectory import Arc, Segment, Spin, Straight

if TYPE_CHECKING:
    from diffbot.body_limits import BodyLimits
    from diffbot.commands.plan_options import PlanOptions

__all__ = ["warn_over_body", "warn_unused"]


def warn_unused(options: PlanOptions, segments: Sequence[Segment]) -> set[str]:
    """Warn about a cruise option given for a plan whose segments all carry durations (or,
    with --fastest, that replaces them): it would change nothing, silently. Returns the
    options warned about."""
    unused: set[str] = set()
    for option, kinds in (("--speed", (Straight, Arc)), ("--spin-rate", (Spin,))):
        if option not in options.given:
            continue
        unused.add(option)
        if options.fastest:
            warn(f"{option} changes nothing with --fastest (every segment runs at the limit)")
            continue
        used = [s for s in segments if isinstance(s, kinds)]
        if all(s.duration is not None for s in used):
            what = "straight or arc" if option == "--speed" else "spin"
            warn(
                f"{option} changes nothing: every {what} of the plan has its own duration"
                if used
                else f"{option} changes nothing: the plan has no {what}"
            )
        else:
            unused.discard(option)
    return unused


def warn_over_body(options: PlanOptions, body: BodyLimits, unused: set[str]) -> None:
    """Warn about a cruise speed given over the body velocity limits (and not among the
    ``unused`` options): the segments it times are slowed to the limit, which the plan
    would not say otherwise."""
    pairs = (
        ("--speed", options.speed, body.linear, "--max-linear", options.max_linear, "m/s"),
        (
            "--spin-rate",
            options.spin_rate,
            body.angular,
            "--max-angular",
            options.max_angular,
            "rad/s",
        ),
    )
    for option, value, bounds, limit_option, given, unit in pairs:
        if option not in options.given or option in unused or bounds is None:
            continue
        if value <= bounds[1]:
            continue
        axis = "linear.x" if option == "--speed" else "angular.z"
        where = limit_option if given is not None else f"the controllers file's {axis}"
        warn(
            f"{option} {value:g} {unit} is over the body velocity limit of {bounds[1]:g} "
            f"{unit} ({where}): the segments it times run at {bounds[1]:g} {unit}"
        )
