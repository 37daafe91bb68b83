"""Robots that are not differential drives: the steering, mecanum or omnidirectional drive a
description names, in a controllers file or a simulator plugin, and the refusal that names it.

A robot whose wheels steer (:func:`diffbot.urdf.tree.check_not_steered`) is refused with the
controller its description drives it with; a description driven only by another drive's
controller or plugin, with no diff-drive one, is refused too: taken for a skid steer, its
odometry would be wrong.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path
from xml.etree import ElementTree

from diffbot.controller_config import ControllerConfig
from diffbot.errors import DiffbotError, NotDifferentialError
from diffbot.urdf.controllers import load_other_drive_controllers
from diffbot.urdf.gazebo import GazeboDrive, other_drive_plugins
from diffbot.urdf.wheels import Derived, JointChoice

__all__ = ["STEERING_CONTROLLERS", "note_other_drives", "refusing_other_drives"]


def note_other_drives(
    paths: Sequence[Path], warnings: list[str], found: list[tuple[str, str]] | None
) -> None:
    """Warn of each file that holds only other drives' controllers, naming them; ``found``
    (when given) receives them as ``(name, "<type> in <file>")``."""
    for path in paths:
        others = load_other_drive_controllers(path)
        if found is not None:
            found += [(name, f"{kind} in {path}") for name, kind in others]
        if others:
            listed = ", ".join(f"{name!r} ({kind})" for name, kind in others)
            warnings.append(
                f"{path} configures no diff-drive controller, only {listed}: not a differential "
                "drive's settings, so they are not used"
            )


#: What a steered robot needs when its description names no controller.
STEERING_CONTROLLERS = (
    "it needs a steering controller (ros2_controllers' ackermann_steering_controller, "
    "bicycle_steering_controller or tricycle_steering_controller), not diff_drive_controller"
)


def refusing_other_drives(
    derive: Callable[[JointChoice, JointChoice], Derived],
    root: ElementTree.Element,
    source: str,
    config: ControllerConfig | None,
    drives: Sequence[GazeboDrive],
    other_drives: Sequence[tuple[str, str]],
) -> Callable[[JointChoice, JointChoice], Derived]:
    """``derive``, whose refusal of a steered robot names the controller the description
    gives it; and a refusal of a robot driven only by other drives' controllers or plugins.

    Raises:
        NotDifferentialError: see :func:`reconcile`.
    """
    named = [f"the plugin {label}" for label in other_drive_plugins(root)]
    named += [f"the controller {name!r} ({kind})" for name, kind in other_drives]

    def checked(left: JointChoice, right: JointChoice) -> Derived:
        try:
            return derive(left, right)
        except NotDifferentialError as err:
            runs = f"the description drives it with {', '.join(named)}" if named else None
            raise NotDifferentialError(
                f"{err.template}; {runs or STEERING_CONTROLLERS}", **err.fields
            ) from None

    if config is None and not drives and named:
        try:
            checked(None, None)  # a steered geometry is said first, with its steering joints
        except NotDifferentialError:
            raise
        except DiffbotError:
            pass
        hint = (
            "; to read its wheels as a differential drive all the same, read no controllers "
            "file ({no_controllers})"
            if other_drives
            else ""
        )
        raise NotDifferentialError(
            f"{source}: not a differential drive: the description drives it with "
            f"{', '.join(named)}, and with no diff-drive controller or plugin{hint}",
            path=source,
        )
    return checked
