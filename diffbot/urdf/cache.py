"""A disk cache of derived parameters, keyed by the expanded URDF and the derivation's code.

Deriving reads the URDF with diffbot's own reader (:mod:`diffbot.urdf.urdf_model`) and NumPy, a
few tens of milliseconds after NumPy's import; the result is still cached on disk keyed by the
expanded URDF text, so a second run on the same description only pays for the xacro expansion
and loads no NumPy at all. ``DIFFBOT_CACHE_DIR`` moves the cache; ``DIFFBOT_NO_CACHE=1`` turns it
off.

When an entry is missing and this process has not loaded NumPy, the parameters are derived in a
short-lived child process, so that a command that needs no NumPy otherwise (``params``,
``check``) stays free of it. Any failure of the child (an error in the description above all)
derives again in this process, so errors are raised here as they always were. The child is
isolated (:mod:`diffbot.processes`): the current folder, often the description's own
repository, is never on its path.

An entry holds only JSON data, written atomically (a temporary file renamed into place). It is
validated on read: its key, a digest of its fields and each field's type and domain must be
right, or the entry is ignored and the parameters derived again; so a hand-edited or truncated
entry, or a FIFO or device where an entry should be, never reaches a command.
"""

from __future__ import annotations

import contextlib
import dataclasses
import hashlib
import json
import math
import os
import stat
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

from diffbot.processes import python_command
from diffbot.urdf import tree, urdf_model, wheels
from diffbot.urdf.wheels import Derived, JointChoice, derive_text

__all__ = ["cache_dir", "cached_fields", "fields_json", "from_entry"]

_CACHE_VERSION = "2"
#: JSON types of each annotation used by :class:`Derived` (tuples are stored as lists).
_JSON_TYPES: dict[str, tuple[type, ...]] = {
    "float": (float, int),
    "float | None": (float, int, type(None)),
    "int": (int,),
    "str": (str,),
    "tuple[str, ...]": (list,),
}
#: The types a cache entry's fields must have, read off :class:`Derived` itself.
_FIELD_TYPES = {f.name: _JSON_TYPES[str(f.type)] for f in dataclasses.fields(Derived)}
#: Largest cache entry read (bytes): a derived record is a few hundred.
_MAX_ENTRY = 1 << 20


def _cache_dir() -> Path | None:
    if os.environ.get("DIFFBOT_NO_CACHE", "") not in ("", "0"):
        return None
    if os.environ.get("DIFFBOT_CACHE_DIR"):
        return Path(os.environ["DIFFBOT_CACHE_DIR"])
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "diffbot"


def cache_dir() -> Path | None:
    """The cache's folder (``DIFFBOT_CACHE_DIR``, else ``diffbot`` in the user's cache folder),
    or None when ``DIFFBOT_NO_CACHE`` turns the cache off."""
    return _cache_dir()


def _quiet_oserror() -> contextlib.suppress:
    # A cache that cannot be read or written only makes the run slower.
    return contextlib.suppress(OSError, ValueError, TypeError, KeyError, RecursionError)


def from_entry(data: Any) -> Derived | None:
    """The record a cache entry holds, or None when it is not exactly a well-typed one."""
    if not isinstance(data, dict) or set(data) != set(_FIELD_TYPES):
        return None
    for name, types in _FIELD_TYPES.items():
        value = data[name]
        if not isinstance(value, types) or isinstance(value, bool):
            return None
        if isinstance(value, float) and not math.isfinite(value):
            return None
    if not all(isinstance(w, str) for w in data["warnings"]):
        return None
    if not all(data[s] in (1, -1) for s in ("left_sign", "right_sign")):
        return None
    if data["wheel_separation"] <= 0 or not all(
        data[name] is None or data[name] > 0 for name in ("wheel_radius", "max_wheel_speed")
    ):
        return None
    return Derived(**{**data, "warnings": tuple(data["warnings"])})


def _digest(key: str, fields: Any) -> str:
    return hashlib.sha256(json.dumps([key, fields], sort_keys=True).encode("utf-8")).hexdigest()


def _unwrap(entry: Any, key: str) -> Any:
    """The fields an entry holds, or None unless it is this key's and its digest matches."""
    if not isinstance(entry, dict) or set(entry) != {"key", "digest", "fields"}:
        return None
    if entry["key"] != key or entry["digest"] != _digest(key, entry["fields"]):
        return None
    return entry["fields"]


def _code_fingerprint() -> str:
    # Entries are keyed by the derivation's own code, so a change to it is never hidden behind
    # results the old code cached.
    digest = hashlib.sha256(_CACHE_VERSION.encode())
    for module in (urdf_model, tree, wheels):
        with contextlib.suppress(OSError, TypeError):
            digest.update(Path(str(module.__file__)).read_bytes())
    return digest.hexdigest()


def _read_entry(path: Path) -> Any:
    """A cache entry's JSON, read only from a small regular file (never a FIFO or device)."""
    fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    with os.fdopen(fd, "rb") as stream:
        info = os.fstat(stream.fileno())
        if not stat.S_ISREG(info.st_mode) or info.st_size > _MAX_ENTRY:
            return None
        return json.loads(stream.read(_MAX_ENTRY).decode("utf-8"))


#: Longest a child process may take to derive the parameters (s) before this process does.
_CHILD_TIMEOUT = 120.0


def _derived_apart(
    urdf: str, source: str, left_joint: JointChoice, right_joint: JointChoice
) -> Derived | None:
    """:func:`derive_text` run in a child process; None when it fails in any way."""
    request = json.dumps([urdf, source, _key(left_joint), _key(right_joint)])
    with contextlib.suppress(OSError, ValueError, subprocess.SubprocessError):
        done = subprocess.run(
            python_command("from diffbot.urdf.cache import _child; _child()"),
            input=request.encode("utf-8"),
            capture_output=True,
            timeout=_CHILD_TIMEOUT,
            check=False,
        )
        if done.returncode == 0:
            return from_entry(json.loads(done.stdout.decode("utf-8")))
    return None


def _child() -> None:
    """The child's side of :func:`_derived_apart`: a request on stdin, the fields on stdout."""
    urdf, source, left, right = json.loads(sys.stdin.buffer.read().decode("utf-8"))
    try:
        fields = derive_text(urdf, source, _joints(left), _joints(right))
    except Exception:  # the parent derives again and raises the error itself
        sys.exit(1)
    json.dump(fields_json(fields), sys.stdout)


def _joints(value: Any) -> JointChoice:
    return value if value is None or isinstance(value, str) else tuple(value)


def fields_json(fields: Derived) -> dict[str, Any]:
    """The JSON form of derived fields (tuples as lists), as an entry stores them."""
    return {**dataclasses.asdict(fields), "warnings": list(fields.warnings)}


def _key(joints: JointChoice) -> object:
    return joints if joints is None or isinstance(joints, str) else list(joints)


def cached_fields(
    urdf: str,
    source: str,
    left_joint: JointChoice,
    right_joint: JointChoice,
) -> Derived:
    """What :func:`derive_text` gives for this URDF, from the disk cache when it holds it."""
    key = hashlib.sha256(
        json.dumps([_code_fingerprint(), urdf, _key(left_joint), _key(right_joint)]).encode("utf-8")
    ).hexdigest()
    directory = _cache_dir()
    path = directory / f"params-{key}.json" if directory else None
    if path is not None:
        with _quiet_oserror():
            cached = from_entry(_unwrap(_read_entry(path), key))
            if cached is not None:
                return cached
    # Apart only while this process is still free of NumPy: once it is loaded, deriving here
    # takes milliseconds and a child would only add its start.
    apart = (
        _derived_apart(urdf, source, left_joint, right_joint)
        if path is not None and "numpy" not in sys.modules
        else None
    )
    fields = apart or derive_text(urdf, source, left_joint, right_joint)
    if path is not None:
        with _quiet_oserror():
            path.parent.mkdir(parents=True, exist_ok=True)
            fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=".params-", suffix=".tmp")
            try:
                with os.fdopen(fd, "w", encoding="utf-8") as out:
                    data = fields_json(fields)
                    json.dump({"key": key, "digest": _digest(key, data), "fields": data}, out)
                os.replace(tmp, path)
            finally:
                Path(tmp).unlink(missing_ok=True)
    return fields
