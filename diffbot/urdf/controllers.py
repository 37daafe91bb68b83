"""Diff-drive settings from ros2_control controller files and Gazebo drive plugins.

A robot's geometry is often written in more places than its URDF: the ``diff_drive_controller``
section of a controllers YAML (``wheel_separation``, ``wheel_radius``, their multipliers, the
command limits) and the diff-drive plugin of a Gazebo simulation. This module reads those sources
as plain data, so that they can be compared with the description and with each other.

Controllers YAML, in every form found in the wild:

* ROS 2, the controller declared by the controller manager and configured in its own section::

      controller_manager:
        ros__parameters:
          update_rate: 50
          diff_cont: {type: diff_drive_controller/DiffDriveController}
      diff_cont:
        ros__parameters: {wheel_separation: 0.3, linear.x.max_velocity: 0.5}

* ROS 2, the type given in the controller's own section (``diff_cont: ros__parameters: type:``);
* node names with namespaces or wildcards (``/**:``, ``/**/controller_manager:``,
  ``ns/controller_manager:``, ``/ns/diff_cont:``, or namespaces as nested keys), matched by their
  last component; parameters of a wildcard node (``/**``) apply to every node;
* parameters nested (``linear: {x: {max_velocity: 1.0}}``), dotted (``linear.x.max_velocity``)
  or both;
* ROS 1 (``mobile_base_controller: {type: diff_drive_controller/DiffDriveController,
  left_wheel: ..., right_wheel: ...}``), possibly under namespace keys.

Command limits follow the controller's speed limiter: a limit left out or set to ``.nan`` is no
limit; ``min_*`` left out defaults to ``-max_*``. Older releases switched each group of limits on
and off with ``has_velocity_limits``, ``has_acceleration_limits`` and ``has_jerk_limits``; a flag
set to false disables its group here too. ROS 1 and ROS 2 Humble default those flags to false,
later releases to true before dropping them. So for ROS 1 a group without its flag is off; ROS 2
files are read as current releases read them (limits on), with a warning when a file that uses the
flags leaves one out, as Humble would then ignore that group.
"""

from __future__ import annotations

import dataclasses
import math
import os
import re
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Literal

from diffbot.controller_config import AxisLimits, ControllerConfig, default_of, first_of
from diffbot.errors import DescriptionError
from diffbot.io.textfile import check_regular, open_regular
from diffbot.io.yamlfile import load_yaml
from diffbot.numbers import MAX_PLAN_DURATION, as_number, finite_in_range, shown

__all__ = [
    "DIFF_DRIVE_TYPES",
    "MAX_FILE_BYTES",
    "AxisLimits",
    "ControllerConfig",
    "ControllerConfigError",
    "choose_controller",
    "load_command_controllers",
    "load_controllers",
    "load_other_drive_controllers",
    "node_base_name",
    "other_drive_controllers",
    "read_controllers",
    "substitute_args",
]

#: The plugin names under which the diff-drive controller is declared.
DIFF_DRIVE_TYPES = frozenset(
    {"diff_drive_controller/DiffDriveController", "diff_drive_controller::DiffDriveController"}
)

#: Controller files larger than this (bytes) are refused: real ones are a few kB.
MAX_FILE_BYTES = 4 * 1024 * 1024

#: Fastest controller manager loop accepted (Hz): real ones run at tens to a few thousand.
MAX_UPDATE_RATE = 1e6
#: Largest wheels_per_side and velocity_rolling_window_size accepted.
MAX_WHEELS_PER_SIDE = 1000
MAX_ROLLING_WINDOW = 1_000_000

_ROS2_KEY = "ros__parameters"
_WILDCARDS = frozenset({"*", "**"})


class ControllerConfigError(DescriptionError):
    """A controllers YAML cannot be read, or a diff-drive controller in it is malformed."""


# --- YAML -------------------------------------------------------------------------------------


def _parse_yaml(text: str, source: str) -> Any:
    if len(text) > MAX_FILE_BYTES:
        raise ControllerConfigError(
            f"{source}: controllers file is larger than {MAX_FILE_BYTES} bytes"
        )
    return load_yaml(text, source, ControllerConfigError, "a controllers file", ros_floats=True)


def _flatten(params: Mapping[Any, Any], prefix: str = "") -> dict[str, Any]:
    """Nested parameter mappings as dotted keys (``linear: {x: ..}`` -> ``linear.x``)."""
    flat: dict[str, Any] = {}
    for key, value in params.items():
        name = f"{prefix}{key}"
        if isinstance(value, Mapping):
            flat.update(_flatten(value, name + "."))
        else:
            flat[name] = value
    return flat


def _is_diff_drive(value: Any) -> bool:
    """Whether a ``type:`` value names the diff-drive controller (any YAML value may be there)."""
    return isinstance(value, str) and value in DIFF_DRIVE_TYPES


def node_base_name(path: Sequence[str]) -> str:
    """The last non-empty component of a node path (``/ns/diff_cont`` -> ``diff_cont``)."""
    parts = [part for key in path for part in str(key).split("/") if part]
    return parts[-1] if parts else ""


@dataclass(frozen=True)
class _Node:
    path: tuple[str, ...]
    params: dict[str, Any]

    @property
    def name(self) -> str:
        return node_base_name(self.path)


def _ros2_nodes(
    tree: Mapping[Any, Any], source: str, path: tuple[str, ...] = ()
) -> Iterator[_Node]:
    """Every ``<node>: ros__parameters: {...}`` section, however deep its namespace keys."""
    for key, value in tree.items():
        if not isinstance(value, Mapping):
            continue
        here = (*path, str(key))
        if _ROS2_KEY in value:
            params = value[_ROS2_KEY]
            if params is None:
                params = {}
            if not isinstance(params, Mapping):
                raise ControllerConfigError(
                    f"{source}: {'/'.join(here)}: {_ROS2_KEY} must be a mapping, "
                    f"got {shown(params)}"
                )
            yield _Node(here, _flatten(params))
        else:
            yield from _ros2_nodes(value, source, here)


def _ros1_controllers(
    tree: Mapping[Any, Any], path: tuple[str, ...] = ()
) -> Iterator[tuple[str, dict[str, Any]]]:
    """Every ROS 1 controller mapping with the diff-drive type, under any namespace keys."""
    for key, value in tree.items():
        if not isinstance(value, Mapping) or _ROS2_KEY in value:
            continue
        if _is_diff_drive(value.get("type")):
            yield node_base_name((*path, str(key))), _flatten(value)
        else:
            yield from _ros1_controllers(value, (*path, str(key)))


_ARG = re.compile(r"\$\(arg\s+([A-Za-z0-9_\-]+)\s*\)")
#: Controller types that drive a base but not as a differential drive (named in a warning).
_OTHER_DRIVE = re.compile(r"(mecanum|omni|ackermann|tricycle|bicycle|steering|swerve|drive)", re.I)


def substitute_args(text: str, args: Mapping[str, str] | None) -> tuple[str, list[str]]:
    """``$(arg NAME)`` replaced by the value of ``NAME:=VALUE``, as roslaunch does for a
    ``rosparam`` file loaded with ``subst_value``; returns the text and the names left unresolved.
    """
    given = args or {}
    unresolved: list[str] = []

    def value(match: re.Match[str]) -> str:
        name = match.group(1)
        if name in given:
            return str(given[name])
        if name not in unresolved:
            unresolved.append(name)
        return match.group(0)

    return _ARG.sub(value, text), unresolved


def other_drive_controllers(text: str, source: str) -> list[tuple[str, str]]:
    """The controllers of a file that drive a base but are no diff-drive controller, as
    ``(name, type)`` (a mecanum, omni, Ackermann, tricycle or steering controller)."""
    tree = _parse_yaml(text, source)
    if not isinstance(tree, Mapping):
        return []
    found: list[tuple[str, str]] = []
    for name, value in _ros1_types(tree):
        if value not in DIFF_DRIVE_TYPES and _OTHER_DRIVE.search(value.rsplit("/", 1)[-1]):
            found.append((name, value))
    for node in _ros2_nodes(tree, source):
        for key, value in node.params.items():
            if key == "type" or key.endswith(".type"):
                name = node.name if key == "type" else node_base_name((key[: -len(".type")],))
                if (
                    isinstance(value, str)
                    and value not in DIFF_DRIVE_TYPES
                    and _OTHER_DRIVE.search(value.rsplit("/", 1)[-1].rsplit(":", 1)[-1])
                    and (name, value) not in found
                ):
                    found.append((name, value))
    return found


def _ros1_types(tree: Mapping[Any, Any], path: tuple[str, ...] = ()) -> Iterator[tuple[str, str]]:
    """Every ROS 1 controller mapping's name and ``type``, under any namespace keys."""
    for key, value in tree.items():
        if not isinstance(value, Mapping) or _ROS2_KEY in value:
            continue
        if isinstance(value.get("type"), str):
            yield node_base_name((*path, str(key))), value["type"]
        else:
            yield from _ros1_types(value, (*path, str(key)))


def _follow_chain(config: ControllerConfig, nodes: Sequence[_Node]) -> ControllerConfig:
    """Wheel names that are another controller's reference (``pid_left/left_wheel_joint``, a
    chained controller) followed to the joint behind it."""
    notes: list[str] = []

    def joint_of(name: str) -> str:
        if "/" not in name:
            return name
        prefix, _, joint = name.rpartition("/")
        ahead = [n for n in nodes if n.name == prefix.rsplit("/", 1)[-1]]
        dofs = [v for n in ahead for k in ("dof_names", "joints") for v in n.params.get(k) or ()]
        if ahead and joint not in dofs:
            return name
        notes.append(
            f"wheel {name!r} is the reference of the chained controller {prefix!r}: "
            f"followed to joint {joint!r}"
        )
        return joint

    left = tuple(joint_of(n) for n in config.left_wheel_names)
    right = tuple(joint_of(n) for n in config.right_wheel_names)
    if not notes:
        return config
    return dataclasses.replace(
        config,
        left_wheel_names=left,
        right_wheel_names=right,
        warnings=(*config.warnings, *notes),
    )


def read_controllers(
    text: str, source: str, args: Mapping[str, str] | None = None
) -> list[ControllerConfig]:
    """Every diff-drive controller configured in a controllers YAML.

    Args:
        text: the YAML text.
        source: where it came from (a path), for messages and :attr:`ControllerConfig.source`.
        args: values of ``$(arg NAME)`` substitutions (a ROS 1 launch file's arguments).

    Returns:
        The diff-drive controllers in the order the file declares them; empty when there is none.

    Raises:
        ControllerConfigError: malformed or oversized YAML, YAML aliases, or a diff-drive controller
            with a value of the wrong type or out of its domain (the message names the file, the
            controller and the key).
    """
    used = tuple(dict.fromkeys(_ARG.findall(text)))
    text, unresolved = substitute_args(text, args)
    tree = _parse_yaml(text, source)
    if tree is None:
        return []
    if not isinstance(tree, Mapping):
        raise ControllerConfigError(
            f"{source}: a controllers file must be a mapping of node names, "
            f"got {type(tree).__name__}"
        )
    nodes = list(_ros2_nodes(tree, source))
    # Every lookup by name goes through this index: a file of thousands of controllers would
    # otherwise cost time quadratic in its size.
    by_name: dict[str, list[_Node]] = {}
    for node in nodes:
        by_name.setdefault(node.name, []).append(node)
    wildcard: dict[str, Any] = {}
    for node in nodes:
        if node.name in _WILDCARDS or not node.name:
            wildcard.update(node.params)

    def params_of(name: str) -> dict[str, Any]:
        merged = dict(wildcard)
        for node in by_name.get(name, ()):
            merged.update(node.params)
        return merged

    managers = by_name.get("controller_manager", ())
    rate = managers[0].params.get("update_rate") if managers else None
    configs: list[ControllerConfig] = []
    seen: set[str] = set()
    for node in nodes:
        name = node.name
        manager_rate = node.params.get("update_rate")
        declared = [
            node_base_name((key[: -len(".type")],))
            for key, value in node.params.items()
            if key.endswith(".type") and _is_diff_drive(value)
        ]
        for declared_name in declared:
            if declared_name in seen:
                continue
            seen.add(declared_name)
            sections = by_name.get(declared_name)
            warnings = (
                () if sections else (f"no {declared_name}: {_ROS2_KEY} section configures it",)
            )
            configs.append(
                _config(
                    declared_name,
                    source,
                    2,
                    params_of(declared_name),
                    manager_rate,
                    warnings=warnings,
                )
            )
        if _is_diff_drive(node.params.get("type")) and name not in seen and name not in _WILDCARDS:
            seen.add(name)
            configs.append(_config(name, source, 2, params_of(name), rate))
    for name, params in _ros1_controllers(tree):
        configs.append(_config(name, source, 1, params, None))
    unset = [
        f"$(arg {name}) has no value: give it as {name}:=VALUE, as the launch file would"
        for name in unresolved
    ]
    return [
        dataclasses.replace(c, warnings=(*c.warnings, *unset), arguments=used)
        for c in (_follow_chain(c, nodes) for c in configs)
    ]


def _read_file(path: str | os.PathLike[str]) -> str:
    """A controllers file's text, bounded in size, never from a FIFO or device."""
    source = os.fspath(path)
    if os.path.exists(source):  # never a FIFO or device
        check_regular(source, ControllerConfigError, "a controllers file")
    try:
        with open(
            open_regular(source, ControllerConfigError, "a controllers file"), "rb"
        ) as stream:
            data = stream.read(MAX_FILE_BYTES + 1)
    except OSError as err:
        reason = err.strerror or str(err)
        raise ControllerConfigError(f"{source}: cannot read controllers file: {reason}") from err
    if len(data) > MAX_FILE_BYTES:
        raise ControllerConfigError(
            f"{source}: controllers file is larger than {MAX_FILE_BYTES} bytes"
        )
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as err:
        raise ControllerConfigError(f"{source}: controllers file is not UTF-8 text") from err


def load_controllers(
    path: str | os.PathLike[str], args: Mapping[str, str] | None = None
) -> list[ControllerConfig]:
    """Every diff-drive controller configured in a controllers YAML file.

    Args:
        path: the file.
        args: values of ``$(arg NAME)`` substitutions.

    Returns:
        As :func:`read_controllers`, with the path as source.

    Raises:
        ControllerConfigError: the file cannot be read, is larger than :data:`MAX_FILE_BYTES`, or
            is malformed (see :func:`read_controllers`).
    """
    return read_controllers(_read_file(path), os.fspath(path), args)


def load_other_drive_controllers(path: str | os.PathLike[str]) -> list[tuple[str, str]]:
    """:func:`other_drive_controllers` of a file."""
    return other_drive_controllers(_read_file(path), os.fspath(path))


def load_command_controllers(path: str | os.PathLike[str]) -> dict[str, tuple[str, ...]]:
    """The controllers of a controllers YAML that command a group of joints (``joints``: a
    forward_command_controller, JointGroupVelocityController...), by name, with their joints.

    Raises:
        ControllerConfigError: as :func:`load_controllers`.
    """
    source = os.fspath(path)
    tree = _parse_yaml(_read_file(source), source)
    if not isinstance(tree, Mapping):
        return {}
    found: dict[str, tuple[str, ...]] = {}
    for node in _ros2_nodes(tree, source):
        joints = node.params.get("joints")
        if isinstance(joints, list) and joints and all(isinstance(j, str) for j in joints):
            found[node.name] = tuple(joints)
    return found


def choose_controller(
    configs: Sequence[ControllerConfig], name: str | None = None
) -> ControllerConfig:
    """The diff-drive controller to use.

    Args:
        configs: the controllers found (:func:`read_controllers`).
        name: the controller's name; may be left out when there is exactly one.

    Returns:
        The controller of that name, or the only one.

    Raises:
        ControllerConfigError: there is none, there are several and no name, or none has the name
            (the message lists the names there are).
    """
    sources = sorted({c.source for c in configs})
    where = f" in {', '.join(sources)}" if sources else ""
    names = ", ".join(repr(c.name) for c in configs)
    if not configs:
        raise ControllerConfigError("no diff_drive_controller/DiffDriveController found")
    if name is None:
        if len(configs) > 1:
            raise ControllerConfigError(
                f"several diff-drive controllers{where}: {names}; "
                "choose one by name ({controller})"
            )
        return configs[0]
    for config in configs:
        if config.name == name:
            return config
    raise ControllerConfigError(f"no diff-drive controller {name!r}{where}; there are: {names}")


# --- values -----------------------------------------------------------------------------------


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

    def text(self, key: str) -> str | None:
        if key not in self.params:
            return None
        value = self.params[key]
        if not isinstance(value, str) or not value:
            raise self.fail(key, "a non-empty string", value)
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
        """A limit: None when absent or NaN; ``sign`` +1 for limits >= 0, -1 for <= 0."""
        value = self.number(key)
        if value is None or math.isnan(value):
            return None
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


def _config(
    name: str,
    source: str,
    ros_version: Literal[1, 2],
    params: Mapping[str, Any],
    update_rate: Any,
    warnings: Sequence[str] = (),
) -> ControllerConfig:
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
        use_stamped_vel=reader.flag("use_stamped_vel"),
        odom_frame_id=reader.text("odom_frame_id"),
        base_frame_id=reader.text("base_frame_id"),
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
