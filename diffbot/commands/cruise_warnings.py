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
    from diffbot.ramps import RampedPlan

__all__ = ["warn_over_body", "warn_slowed_runs", "warn_unused"]


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


def warn_slowed_runs(ramped: RampedPlan) -> None:
    """Warn about segments a ramped plan drives slower than they ask: consecutive segments of
    one direction are one run, with no stop between them, cruising at the slowest one's speed,
    so a faster segment takes longer than its duration (or its speed) says."""
    for run in ramped.runs:
        planned = [ramped.steps.segments[i] for i in run.segments]
        speeds = [
            abs(float(p.twist.angular if isinstance(p.segment, Spin) else p.twist.linear))
            for p in planned
        ]
        slowest = min(speeds)
        slowed = [
            i + 1 for i, v in zip(run.segments, speeds, strict=True) if v > slowest * 1.000001
        ]
        if not slowed:
            continue
        unit = "rad/s" if isinstance(planned[0].segment, Spin) else "m/s"
        first, last = run.segments[0] + 1, run.segments[-1] + 1
        named = ", ".join(str(i) for i in slowed)
        warn(
            f"segments {first}-{last} are one run (one direction, no stop between them), at "
            f"the slowest one's {slowest:.4g} {unit}: segment{'s' if len(slowed) > 1 else ''} "
            f"{named} take{'' if len(slowed) > 1 else 's'} longer than written (--steps drives "
            "each at its own speed, without ramps)"
        )
