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
    ``globals()``), so later lookups skip the function. Any other name that is a submodule of
    ``package`` is imported as such (``package.sub`` after ``import package``)."""

    def getattr_(name: str) -> Any:
        home = homes.get(name)
        if home is None:
            # A submodule, as ``import package`` gave when it imported it eagerly.
            if name.isidentifier() and not name.startswith("__"):
                from importlib.util import find_spec

                try:
                    found = find_spec(f"{package}.{name}") is not None
                except ModuleNotFoundError:  # the package itself is not importable
                    found = False
                if found:
                    return importlib.import_module(f"{package}.{name}")
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(home), name)
        namespace[name] = value
        return value

    def dir_() -> list[str]:
        return sorted({*namespace, *homes})

    return getattr_, dir_
