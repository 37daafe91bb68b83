"""The files a wildcard ``<xacro:include filename="...">`` names, found as :func:`glob.glob`
finds them but without listing a folder the caller refuses: in an untrusted description, none
outside its own folders, so that neither the names there nor their number are learnt."""

from __future__ import annotations

import fnmatch
import os
from collections.abc import Callable

__all__ = ["include_files"]

_WILDCARDS = frozenset("*?[")


def _has_wildcard(name: str) -> bool:
    return not _WILDCARDS.isdisjoint(name)


def include_files(pattern: str, check: Callable[[str], None]) -> list[str]:
    """The paths matching ``pattern``, sorted, as :func:`glob.glob` matches them (``*``, ``?``
    and ``[...]`` within one name; a name that begins with a dot only where the pattern's does).

    Args:
        pattern: the include's file name, wildcards and all.
        check: called with each folder before it is listed, and with the folder of each match
            (its path as the pattern spells it); it raises to refuse one.
    """
    parts = pattern.split(os.sep)
    first = next((k for k, part in enumerate(parts) if _has_wildcard(part)), len(parts))
    head = os.sep.join(parts[:first]) or (os.sep if pattern.startswith(os.sep) else "")
    # Each path found, and whether it is a name a listing gave (no name of the pattern's after).
    found = [(head, False)]
    for part in parts[first:]:
        if not _has_wildcard(part):
            found = [
                (os.path.join(path, part), False)
                for path, was_listed in found
                if not was_listed or os.path.isdir(path)  # a listed name goes on if a folder
            ]
            continue
        listed: list[tuple[str, bool]] = []
        for folder, was_listed in found:
            where = folder or os.curdir
            # A listed name that is no folder is passed over, as glob does; a folder the pattern
            # spells is checked first, so that whether it exists is not learnt when refused.
            if was_listed and not os.path.isdir(where):
                continue
            check(where)
            if not os.path.isdir(where):
                continue
            for name in sorted(os.listdir(where)):
                if name.startswith(".") and not part.startswith("."):
                    continue
                if fnmatch.fnmatchcase(name, part):
                    listed.append((os.path.join(folder, name), True))
        found = listed
    matches: list[str] = []
    for path, _ in found:
        check(os.path.dirname(path) or os.curdir)
        if os.path.lexists(path):
            matches.append(path)
    return sorted(matches)
