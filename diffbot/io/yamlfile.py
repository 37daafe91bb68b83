"""The one YAML reader of diffbot: safe, and bounded in the work a small file can cause.

Every YAML file the tool reads (plan files, controllers files, runs files, a bag's
``metadata.yaml``) goes through :func:`load_yaml`. It builds plain data only (PyYAML's safe
loader), and it refuses before building anything:

* aliases (``*name``): nested anchors double at every level, so a file of a few hundred bytes
  names a tree of 2**27 items; none of these files needs them;
* lists and mappings nested deeper than :data:`MAX_NESTING` (a recursion that would otherwise
  end in Python's own limit);
* integers too long to read (Python refuses more than 4300 digits).

A refusal is one :class:`~diffbot.errors.DiffbotError` of the caller's kind naming the file and,
where there is one, the line and column.
"""

from __future__ import annotations

import functools
import re
from typing import Any, Final

from diffbot.errors import DiffbotError
from diffbot.formats.text import brief

__all__ = ["MAX_NESTING", "load_yaml"]

#: Deepest nesting of lists and mappings accepted in a YAML file.
MAX_NESTING: Final = 32

# ROS reads numbers with strtod, so ``1e-3`` is a double there; YAML 1.1 wants ``1.0e-3``.
_ROS_FLOAT = re.compile(r"^[-+]?(?:[0-9][0-9_]*(?:\.[0-9_]*)?|\.[0-9_]+)[eE][-+]?[0-9]+$")


class _RefusedError(Exception):
    """Why a file is refused, and where (``line L, column C`` or empty)."""

    def __init__(self, why: str, where: str = "") -> None:
        super().__init__(why)
        self.why = why
        self.where = where


def _where(mark: Any) -> str:
    return "" if mark is None else f"line {mark.line + 1}, column {mark.column + 1}"


def _base() -> type[Any]:
    """libyaml's safe loader where PyYAML was built with it (a file of thousands of controllers
    parses in a fraction of a second, not tens of seconds), else the pure-Python one."""
    import yaml

    return getattr(yaml, "CSafeLoader", yaml.SafeLoader)


def _check_events(text: str) -> None:
    """Refuse aliases and deep nesting from the parser's events, before anything is composed:
    the composer would follow both (and libyaml's composer cannot be bounded from Python)."""
    import yaml

    parser = _base()(text)
    try:
        depth = 0
        while parser.check_event():
            event = parser.get_event()
            if isinstance(event, yaml.AliasEvent):
                raise _RefusedError("aliases (*name)", _where(event.start_mark))
            if isinstance(event, yaml.CollectionStartEvent):
                depth += 1
                if depth > MAX_NESTING:
                    raise _RefusedError(
                        f"lists and mappings nested more than {MAX_NESTING} deep",
                        _where(event.start_mark),
                    )
            elif isinstance(event, yaml.CollectionEndEvent):
                depth -= 1
    finally:
        parser.dispose()


def _merged(earlier: Any, later: Any, replaced: list[str], path: str = "") -> Any:
    """``later`` over ``earlier``: mappings key by key, anything else replaced (each value
    replaced by a different one is appended to ``replaced`` as ``path.key, value``)."""
    if not (isinstance(earlier, dict) and isinstance(later, dict)):
        if earlier != later:
            replaced.append(f"{path} {brief(later)}")
        return later
    merged = dict(earlier)
    for key, value in later.items():
        inner = f"{path}.{key}" if path else str(key)
        merged[key] = _merged(merged[key], value, replaced, inner) if key in merged else value
    return merged


@functools.cache
def _loader(ros_floats: bool, duplicates: str) -> type[Any]:
    """A safe loader class: optionally ROS floats, and repeated keys refused (YAML forbids them;
    PyYAML keeps the last) or read as ROS reads them (mappings merged, the later value kept)."""
    import yaml
    from yaml.nodes import MappingNode

    class BoundedLoader(_base()):  # type: ignore[misc]
        repeated: list[str]

        def construct_mapping(self, node: MappingNode, deep: bool = False) -> dict[Any, Any]:
            if duplicates == "refuse":
                seen: set[Any] = set()
                for key_node, _ in node.value:
                    key = self.construct_object(key_node, deep=True)
                    try:
                        duplicate = key in seen
                    except TypeError:  # unhashable: the SafeLoader reports it
                        continue
                    if duplicate:
                        raise yaml.constructor.ConstructorError(
                            None, None, f"duplicate key {brief(key)}", key_node.start_mark
                        )
                    seen.add(key)
            elif duplicates == "ros":
                return self._ros_mapping(node)
            return super().construct_mapping(node, deep)  # type: ignore[no-any-return]

        def _ros_mapping(self, node: MappingNode) -> dict[Any, Any]:
            mapping: dict[Any, Any] = {}
            lines: dict[Any, int] = {}
            for key_node, value_node in node.value:
                key = self.construct_object(key_node, deep=True)
                value = self.construct_object(value_node, deep=True)
                try:
                    repeated = key in mapping
                except TypeError:  # unhashable: the SafeLoader reports it
                    return super().construct_mapping(node, True)  # type: ignore[no-any-return]
                line = key_node.start_mark.line + 1
                if repeated:
                    where = f"lines {lines[key]} and {line}"
                    replaced: list[str] = []
                    earlier = mapping[key]
                    value = _merged(earlier, value, replaced)
                    if isinstance(earlier, dict) and isinstance(value, dict):
                        later = f"; later values used: {', '.join(replaced)}" if replaced else ""
                        self.repeated.append(
                            f"{brief(key)} appears twice ({where}): its entries are merged, "
                            f"as ROS merges them{later}"
                        )
                    elif replaced:
                        self.repeated.append(
                            f"{brief(key)} is given twice ({where}): the later value, "
                            f"{brief(value)}, is used, as ROS uses it"
                        )
                mapping[key] = value
                lines[key] = line
            return mapping

    if ros_floats:
        BoundedLoader.add_implicit_resolver(
            "tag:yaml.org,2002:float", _ROS_FLOAT, list("-+0123456789.")
        )
    return BoundedLoader


def load_yaml(
    text: str,
    source: str,
    error: type[DiffbotError],
    kind: str,
    *,
    ros_floats: bool = False,
    unique_keys: bool = False,
    repeated: list[str] | None = None,
) -> Any:
    """The data of a YAML document, read safely and within bounds.

    Args:
        text: the YAML text (its size is the caller's to bound).
        source: where it came from, for messages.
        error: the error class to raise.
        kind: what the file is, for messages (``a plan file``).
        ros_floats: read ``1e-3`` as a float, as ROS does (YAML 1.1 reads a string).
        unique_keys: refuse a mapping that repeats a key.
        repeated: read repeated keys as ROS reads a parameters file (mappings merged, a value
            given twice taken from its later place) and append a sentence per repetition here.

    Raises:
        error: malformed YAML, an alias, nesting deeper than :data:`MAX_NESTING`, a repeated key
            (with ``unique_keys``), or a value that cannot be read (an integer of thousands of
            digits, a bad date).
    """
    import yaml

    try:
        _check_events(text)
        duplicates = "refuse" if unique_keys else "ros" if repeated is not None else "last"
        loader = _loader(ros_floats, duplicates)(text)  # a SafeLoader
        loader.repeated = [] if repeated is None else repeated
        try:
            return loader.get_single_data()
        finally:
            loader.dispose()
    except _RefusedError as err:
        if err.why.startswith("aliases"):
            why = f"aliases (*name) are not allowed in {kind}, write each entry out"
        else:
            why = err.why
        where = f" ({err.where})" if err.where else ""
        raise error(f"{source}: YAML {why}{where}") from None
    except yaml.YAMLError as err:
        mark = getattr(err, "problem_mark", None)
        problem = getattr(err, "problem", None) or str(err).splitlines()[0]
        if "maximum nesting depth" in problem:  # libyaml's own bound, past ours
            raise error(
                f"{source}: YAML lists and mappings nested more than {MAX_NESTING} deep"
            ) from None
        where = f" ({_where(mark)})" if mark is not None else ""
        raise error(f"{source}: malformed YAML: {' '.join(problem.split())}{where}") from None
    except RecursionError:
        raise error(f"{source}: YAML nested too deeply") from None
    except (ValueError, OverflowError) as err:  # digits past Python's limit, a bad date
        if "digits" in str(err):
            raise error(f"{source}: malformed YAML: a number too long to read") from None
        raise error(f"{source}: a value cannot be read: {str(err).split(':')[0]}") from None
