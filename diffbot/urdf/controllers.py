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
import os
import re
from collections.abc import Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from diffbot.controller_config import AxisLimits, ControllerConfig
from diffbot.io.textfile import check_regular, open_regular
from diffbot.io.yamlfile import load_yaml
from diffbot.numbers import shown
from diffbot.urdf.controller_values import ControllerConfigError, config_of

__all__ = [
    "DIFF_DRIVE_TYPES",
    "MAX_FILE_BYTES",
    "AxisLimits",
    "ControllerConfig",
    "ControllerConfigError",
    "choose_controller",
    "load_command_controllers",
    "load_controller_files",
    "load_controllers",
    "load_other_drive_controllers",
    "node_base_name",
    "other_drive_controllers",
    "read_controller_files",
    "read_controllers",
    "substitute_args",
]

#: The plugin names under which the diff-drive controller is declared.
DIFF_DRIVE_TYPES = frozenset(
    {"diff_drive_controller/DiffDriveController", "diff_drive_controller::DiffDriveController"}
)

#: Controller files larger than this (bytes) are refused: real ones are a few kB.
MAX_FILE_BYTES = 4 * 1024 * 1024

_ROS2_KEY = "ros__parameters"
_WILDCARDS = frozenset({"*", "**"})


# --- YAML -------------------------------------------------------------------------------------


def _parse_yaml(text: str, source: str, repeated: list[str] | None = None) -> Any:
    if len(text) > MAX_FILE_BYTES:
        raise ControllerConfigError(
            f"{source}: controllers file is larger than {MAX_FILE_BYTES} bytes"
        )
    return load_yaml(
        text,
        source,
        ControllerConfigError,
        "a controllers file",
        ros_floats=True,
        repeated=[] if repeated is None else repeated,  # read as ROS reads them, said or not
    )


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
    source: str

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
            yield _Node(here, _flatten(params), source)
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
    for name, value in _ros2_types(_ros2_nodes(tree, source)):
        if (
            value not in DIFF_DRIVE_TYPES
            and _OTHER_DRIVE.search(value.rsplit("/", 1)[-1].rsplit(":", 1)[-1])
            and (name, value) not in found
        ):
            found.append((name, value))
    return found


def _ros2_types(nodes: Iterable[_Node]) -> Iterator[tuple[str, str]]:
    """Every ROS 2 controller's name and ``type``, as its own section (``type:``) or a
    controller manager's (``NAME.type:``) declares it."""
    for node in nodes:
        for key, value in node.params.items():
            if isinstance(value, str) and (key == "type" or key.endswith(".type")):
                yield node.name if key == "type" else node_base_name((key[: -len(".type")],)), value


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
    return read_controller_files([(text, source)], args)


def read_controller_files(
    files: Sequence[tuple[str, str]], args: Mapping[str, str] | None = None
) -> list[ControllerConfig]:
    """Every diff-drive controller that several parameter files configure together, as a node
    given them in this order takes them: a later file's value of a parameter replaces an
    earlier one's (a simulation file that changes a controller's separation, say).

    Args:
        files: each file's YAML text and where it came from (a path).
        args: values of ``$(arg NAME)`` substitutions.

    Returns:
        As :func:`read_controllers`; each controller's ``source`` is the first file that
        configures it.

    Raises:
        ControllerConfigError: as :func:`read_controllers`, naming the file.
    """
    used: list[str] = []
    unresolved: list[str] = []
    repeated: list[str] = []
    nodes: list[_Node] = []
    ros1: list[tuple[str, dict[str, Any], str]] = []
    for text, source in files:
        used += _ARG.findall(text)
        text, missing = substitute_args(text, args)
        unresolved += missing
        said: list[str] = []
        tree = _parse_yaml(text, source, said)
        repeated += [f"{source}: {sentence}" for sentence in said]
        if tree is None:
            continue
        if not isinstance(tree, Mapping):
            raise ControllerConfigError(
                f"{source}: a controllers file must be a mapping of node names, "
                f"got {type(tree).__name__}"
            )
        nodes += _ros2_nodes(tree, source)
        ros1 += [(name, params, source) for name, params in _ros1_controllers(tree)]
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
    namespaces: dict[str, str] = {}
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
            # its own sections, then the controller manager's that declares it
            owners = [*(sections or ()), node]
            namespaces[declared_name] = _namespace_of(owners)
            warnings = (
                () if sections else (f"no {declared_name}: {_ROS2_KEY} section configures it",)
            )
            configs.append(
                config_of(
                    declared_name,
                    owners[0].source,
                    2,
                    params_of(declared_name),
                    manager_rate,
                    warnings=warnings,
                )
            )
        if _is_diff_drive(node.params.get("type")) and name not in seen and name not in _WILDCARDS:
            seen.add(name)
            namespaces[name] = _namespace_of([*by_name[name], *managers])
            configs.append(config_of(name, by_name[name][0].source, 2, params_of(name), rate))
    for name, params, source in ros1:
        configs.append(config_of(name, source, 1, params, None))
    unset = [
        f"$(arg {name}) has no value: give it as {name}:=VALUE, as the launch file would"
        for name in dict.fromkeys(unresolved)
    ] + repeated
    return [
        dataclasses.replace(
            c,
            warnings=(*c.warnings, *unset),
            arguments=tuple(dict.fromkeys(used)),
            namespace=namespaces.get(c.name, "") if c.ros_version == 2 else "",
        )
        for c in (_follow_chain(c, nodes) for c in configs)
    ]


def _namespace_of(sections: Sequence[_Node]) -> str:
    """The namespace the first of ``sections`` (the controller's own, then its controller
    manager's) puts its node in: ``a200_0000`` for ``/a200_0000/diff_cont:`` or for namespace
    keys above it; empty at the root, or when every section leaves it to a wildcard."""
    for section in sections:
        parts = [part for key in section.path for part in str(key).split("/") if part]
        if not any(part in _WILDCARDS for part in parts[:-1]):
            return "/".join(parts[:-1])
    return ""


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


def load_controller_files(
    paths: Sequence[str | os.PathLike[str]], args: Mapping[str, str] | None = None
) -> list[ControllerConfig]:
    """:func:`read_controller_files` of files, in order.

    Raises:
        ControllerConfigError: as :func:`load_controllers`, naming the file.
    """
    return read_controller_files([(_read_file(p), os.fspath(p)) for p in paths], args)


def load_other_drive_controllers(path: str | os.PathLike[str]) -> list[tuple[str, str]]:
    """:func:`other_drive_controllers` of a file."""
    return other_drive_controllers(_read_file(path), os.fspath(path))


#: The controllers that take joint velocities on ``~/commands`` (std_msgs/Float64MultiArray).
_WHEEL_COMMAND_TYPES = (
    "forward_command_controller/ForwardCommandController",
    "velocity_controllers/JointGroupVelocityController",
)


def load_command_controllers(path: str | os.PathLike[str]) -> dict[str, tuple[str, ...]]:
    """The controllers of a controllers YAML that take velocities for a group of joints on
    their ``commands`` topic (``joints``: a forward_command_controller of the ``velocity``
    interface, a JointGroupVelocityController; one of no declared type counts), by name, with
    their joints.

    A controller in a namespace is named with it (``a200_0000/left_wheel_controller``), the
    namespace of its own section or else of its controller manager's, so that its ``commands``
    topic is the one it subscribes.

    Raises:
        ControllerConfigError: as :func:`load_controllers`.
    """
    source = os.fspath(path)
    tree = _parse_yaml(_read_file(source), source)
    if not isinstance(tree, Mapping):
        return {}
    nodes = list(_ros2_nodes(tree, source))
    managers = [node for node in nodes if node.name == "controller_manager"]
    kinds = dict(_ros2_types(nodes))
    found: dict[str, tuple[str, ...]] = {}
    for node in nodes:
        joints = node.params.get("joints")
        kind = kinds.get(node.name, _WHEEL_COMMAND_TYPES[0])
        interface = node.params.get("interface_name", "velocity")
        if kind not in _WHEEL_COMMAND_TYPES or interface != "velocity":
            continue  # it takes no velocities on commands (a trajectory, positions)
        if isinstance(joints, list) and joints and all(isinstance(j, str) for j in joints):
            namespace = _namespace_of([node, *managers])
            found["/".join(part for part in (namespace, node.name) if part)] = tuple(joints)
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
