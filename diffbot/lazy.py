"""Public names of a package loaded on first use (a module ``__getattr__``, PEP 562), so that
importing the package costs only what it always needs."""

from __future__ import annotations

import importlib

# Imported before anything else by the command line's entry point: no module for types only.
TYPE_CHECKING = False
if TYPE_CHECKING:
    from collections.abc import Callable, Mapping
    from typing import Any

__all__ = ["lazy_names"]


def lazy_names(
    package: str, homes: Mapping[str, str], namespace: dict[str, Any]
) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """The ``__getattr__`` and ``__dir__`` of ``package`` whose names in ``homes`` (name ->
    module) load on first use; each loaded name is kept in ``namespace`` (the package's
    ``globals()``), so later lookups skip the function."""

    def getattr_(name: str) -> Any:
        home = homes.get(name)
        if home is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(home), name)
        namespace[name] = value
        return value

    def dir_() -> list[str]:
        return sorted({*namespace, *homes})

    return getattr_, dir_
