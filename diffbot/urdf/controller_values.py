"""A diff-drive controller's parameters, as a controllers file holds them flat, turned into a
:class:`~diffbot.controller_config.ControllerConfig`: each value typed and within its range, or
one error naming the file, the controller and the key."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any, Literal

from diffbot.controller_config import (
    MAX_UPDATE_RATE,
    MAX_WHEELS_PER_SIDE,
    AxisLimits,
    ControllerConfig,
    default_of,
    first_of,
)
from diffbot.errors import DescriptionError
from diffbot.numbers import (
    MAX_PLAN_DURATION,
    MAX_ROLLING_WINDOW,
    as_number,
    finite_in_range,
    shown,
)

__all__ = [
    "MAX_ROLLING_WINDOW",
    "MAX_UPDATE_RATE",
    "MAX_WHEELS_PER_SIDE",
    "ControllerConfigError",
    "config_of",
]


class ControllerConfigError(DescriptionError):
    """A controllers YAML cannot be read, or a diff-drive controller in it is malformed."""


class _Reader:
    """Typed access to one controller's flat parameters, with errors naming file and key."""

    def __init__(self, name: str, source: str, params: Mapping[str, Any]) -> None:
        self.name = name
        self.source = source
        self.params = params

    def where(self, key: str) -> str:
        """The file, controller and key, for messages."""
        return f"{self.source}: controller {self.name!r}: {key}"

    def fail(self, key: str, expected: str, value: Any) -> ControllerConfigError:
        return ControllerConfigError(f"{self.where(key)} must be {expected}, got {shown(value)}")

    def number(self, key: str, expected: str = "a number") -> float | None:
        """A float; None when absent. NaN is returned as NaN (the caller decides)."""
        if key not in self.params:
            return None
        value = self.params[key]
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise self.fail(key, expected, value)
        return as_number(value, self.where(key), ControllerConfigError, expected)

    def positive(self, key: str) -> float | None:
        expected = "a positive finite number"
        value = self.number(key, expected)
        if value is not None and not (math.isfinite(value) and value > 0.0):
            raise self.fail(key, expected, value)
        return value

    def nonzero(self, key: str) -> float | None:
        expected = "a finite number other than 0 (negative: the wheels turn the other way)"
        value = self.number(key, expected)
        if value is not None and not (math.isfinite(value) and value != 0.0):
            raise self.fail(key, expected, value)
        return value

    def non_negative(self, key: str) -> float | None:
        expected = "a finite number >= 0"
        value = self.number(key, expected)
        if value is not None and not (math.isfinite(value) and value >= 0.0):
            raise self.fail(key, expected, value)
        return value

    def integer(self, key: str, minimum: int, maximum: int) -> int | None:
        if key not in self.params:
            return None
        value = self.params[key]
        if isinstance(value, bool) or not isinstance(value, int) or not minimum <= value <= maximum:
            raise self.fail(key, f"an integer from {minimum} to {maximum}", value)
        return value

    def flag(self, key: str) -> bool | None:
        if key not in self.params:
            return None
        value = self.params[key]
        if not isinstance(value, bool):
            raise self.fail(key, "true or false", value)
        return value

    def text(self, key: str, *, empty: bool = False) -> str | None:
        """A string; an empty one only with ``empty``."""
        if key not in self.params:
            return None
        value = self.params[key]
        if not isinstance(value, str) or not (value or empty):
            raise self.fail(key, "a string" if empty else "a non-empty string", value)
        return value

    def names(self, *keys: str) -> tuple[str, ...] | None:
        """Joint names from the first key present: a list of strings (or one string for ROS 1)."""
        for key in keys:
            if key not in self.params:
                continue
            value = self.params[key]
            if isinstance(value, str) and value and key in {"left_wheel", "right_wheel"}:
                return (value,)
            if not isinstance(value, list) or not all(isinstance(v, str) and v for v in value):
                raise self.fail(key, "a list of joint names", value)
            return tuple(value)
        return None

    def diagonal(self, key: str) -> tuple[float, ...] | None:
        if key not in self.params:
            return None
        value = self.params[key]
        expected = "a list of 6 finite numbers"
        if (
            not isinstance(value, list)
            or len(value) != 6
            or not all(isinstance(v, int | float) and not isinstance(v, bool) for v in value)
        ):
            raise self.fail(key, expected, value)
        return tuple(
            finite_in_range(v, self.where(key), error=ControllerConfigError) for v in value
        )

    def limit(self, key: str, sign: int) -> float | None:
        """A limit: None when absent or NaN; ``sign`` +1 for limits >= 0, -1 for <= 0.

        An infinite limit is refused rather than kept: it would reach the velocity ranges and
        outputs (which hold finite numbers only); .nan is the controller's "no limit".
        """
        value = self.number(key)
        if value is None or math.isnan(value):
            return None
        if math.isinf(value):
            side = ">= 0" if sign > 0 else "<= 0"
            raise self.fail(key, f"a finite number {side}, or .nan for no limit", value)
        if value * sign < 0.0:
            raise self.fail(
                key, "a number >= 0 or .nan" if sign > 0 else "a number <= 0 or .nan", value
            )
        return value


#: Limit keys under ``linear.x.`` / ``angular.z.``, with the sign the controller requires.
_LIMIT_SIGNS = {
    "max_velocity": 1,
    "min_velocity": -1,
    "max_acceleration": 1,
    "min_acceleration": -1,
    "max_deceleration": -1,
    "max_acceleration_reverse": -1,
    "max_deceleration_reverse": 1,
    "max_jerk": 1,
    "min_jerk": -1,
}
#: Which ``has_*_limits`` flag switches which limits.
_LIMIT_GROUPS = {
    "has_velocity_limits": ("max_velocity", "min_velocity"),
    "has_acceleration_limits": (
        "max_acceleration",
        "min_acceleration",
        "max_deceleration",
        "max_acceleration_reverse",
        "max_deceleration_reverse",
    ),
    "has_jerk_limits": ("max_jerk", "min_jerk"),
}


def _axis(reader: _Reader, prefix: str, ros_version: int, warnings: list[str]) -> AxisLimits:
    values = {key: reader.limit(f"{prefix}.{key}", sign) for key, sign in _LIMIT_SIGNS.items()}
    # Only files that use the flags at all were written for the releases that had them.
    flagged = any(".has_" in key and key.endswith("_limits") for key in reader.params)
    for flag_key, members in _LIMIT_GROUPS.items():
        flag = reader.flag(f"{prefix}.{flag_key}")
        given = [key for key in members if values[key] is not None]
        if flag is False or (flag is None and ros_version == 1):
            for key in members:
                values[key] = None
        elif flag is None and given and flagged:
            warnings.append(
                f"{prefix}.{given[0]} is set without {prefix}.{flag_key}: read as a limit, as "
                f"current releases do; Humble ignores it"
            )
        elif flag is True and values[members[0]] is None:
            raise ControllerConfigError(
                f"{reader.source}: controller {reader.name!r}: {prefix}.{flag_key} is true "
                f"but {prefix}.{members[0]} is not set"
            )
    return AxisLimits(**values)


def config_of(
    name: str,
    source: str,
    ros_version: Literal[1, 2],
    params: Mapping[str, Any],
    update_rate: Any,
    warnings: Sequence[str] = (),
) -> ControllerConfig:
    """The diff-drive controller ``name`` of ``source`` from its flat parameters.

    Args:
        name: the controller's name, for messages.
        source: the file, for messages.
        ros_version: 1 or 2: which defaults the limit flags take.
        params: the controller's parameters, flat (``linear.x.max_velocity``).
        update_rate: the controller manager's ``update_rate`` (Hz) as found, or None.
        warnings: notes already found about the controller.

    Raises:
        ControllerConfigError: a value of the wrong type or outside its range.
    """
    reader = _Reader(name, source, params)
    notes = list(warnings)
    left = reader.names("left_wheel_names", "left_wheel")
    right = reader.names("right_wheel_names", "right_wheel")
    if (left is None) != (right is None):
        keys = (
            ("left_wheel", "right_wheel")
            if ros_version == 1
            else ("left_wheel_names", "right_wheel_names")
        )
        given, missing = keys if right is None else keys[::-1]
        raise ControllerConfigError(
            f"{source}: controller {name!r}: {missing} is missing while {given} is set"
        )
    if left is not None and right is not None and len(left) != len(right):
        raise ControllerConfigError(
            f"{source}: controller {name!r}: {len(left)} left and {len(right)} right wheel names; "
            f"both sides need as many"
        )
    # A negative radius multiplier turns that side's wheels the other way (the controller divides
    # by the radius): read as a direction flip. ROS 1's common multiplier wins over the sides'.
    common_multiplier = reader.nonzero("wheel_radius_multiplier")  # ROS 1
    left_multiplier = reader.nonzero("left_wheel_radius_multiplier")
    right_multiplier = reader.nonzero("right_wheel_radius_multiplier")
    if ros_version == 1 and common_multiplier is not None:
        left_multiplier = right_multiplier = common_multiplier
    rate: float | None = None
    if update_rate is not None:
        manager = _Reader("controller_manager", source, {"update_rate": update_rate})
        if isinstance(update_rate, bool) or not isinstance(update_rate, int | float):
            raise manager.fail("update_rate", "a number (Hz)", update_rate)
        rate = finite_in_range(
            update_rate,
            manager.where("update_rate"),
            1.0 / MAX_PLAN_DURATION,
            MAX_UPDATE_RATE,
            error=ControllerConfigError,
            unit="Hz",
        )
    separation_multiplier = default_of(reader.positive("wheel_separation_multiplier"), 1.0)
    return ControllerConfig(
        name=name,
        source=source,
        ros_version=ros_version,
        left_wheel_names=left or (),
        right_wheel_names=right or (),
        wheel_separation=reader.positive("wheel_separation"),
        wheel_radius=reader.positive("wheel_radius"),
        wheels_per_side=reader.integer("wheels_per_side", 0, MAX_WHEELS_PER_SIDE),
        wheel_separation_multiplier=separation_multiplier,
        left_wheel_radius_multiplier=default_of(first_of(left_multiplier, common_multiplier), 1.0),
        right_wheel_radius_multiplier=default_of(
            first_of(right_multiplier, common_multiplier), 1.0
        ),
        linear=_axis(reader, "linear.x", ros_version, notes),
        angular=_axis(reader, "angular.z", ros_version, notes),
        preserve_turning_radius=reader.flag("preserve_turning_radius"),
        open_loop=reader.flag("open_loop"),
        position_feedback=reader.flag("position_feedback"),
        use_stamped_vel=reader.flag("use_stamped_vel"),
        odom_frame_id=reader.text("odom_frame_id"),
        base_frame_id=reader.text("base_frame_id"),
        tf_frame_prefix=reader.text("tf_frame_prefix", empty=True),
        tf_frame_prefix_enable=reader.flag("tf_frame_prefix_enable"),
        pose_covariance_diagonal=reader.diagonal("pose_covariance_diagonal"),
        twist_covariance_diagonal=reader.diagonal("twist_covariance_diagonal"),
        publish_rate=reader.positive("publish_rate"),
        enable_odom_tf=reader.flag("enable_odom_tf"),
        velocity_rolling_window_size=reader.integer(
            "velocity_rolling_window_size", 1, MAX_ROLLING_WINDOW
        ),
        cmd_vel_timeout=reader.non_negative("cmd_vel_timeout"),
        update_rate=rate,
        warnings=tuple(notes),
    )
