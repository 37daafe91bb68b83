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


@functools.cache
def _loader(ros_floats: bool, unique_keys: bool) -> type[Any]:
    """A safe loader class: optionally ROS floats and no duplicate keys (YAML forbids them;
    PyYAML keeps the last)."""
    import yaml
    from yaml.nodes import MappingNode

    class BoundedLoader(_base()):  # type: ignore[misc]
        def construct_mapping(self, node: MappingNode, deep: bool = False) -> dict[Any, Any]:
            if unique_keys:
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
            return super().construct_mapping(node, deep)  # type: ignore[no-any-return]

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
) -> Any:
    """The data of a YAML document, read safely and within bounds.

    Args:
        text: the YAML text (its size is the caller's to bound).
        source: where it came from, for messages.
        error: the error class to raise.
        kind: what the file is, for messages (``a plan file``).
        ros_floats: read ``1e-3`` as a float, as ROS does (YAML 1.1 reads a string).
        unique_keys: refuse a mapping that repeats a key.

    Raises:
        error: malformed YAML, an alias, nesting deeper than :data:`MAX_NESTING`, a repeated key
            (with ``unique_keys``), or a value that cannot be read (an integer of thousands of
            digits, a bad date).
    """
    import yaml

    try:
        _check_events(text)
        return yaml.load(text, Loader=_loader(ros_floats, unique_keys))  # a SafeLoader
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
