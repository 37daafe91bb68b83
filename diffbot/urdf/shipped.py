"""The bundled robot's derived parameters, shipped with the package.

Deriving needs NumPy (and a child process to keep it out of a command that needs it for
nothing else), so the bundled robot's fields are derived once, when the package is made, and
stored in ``description/derived.json``, keyed by a digest of the expanded URDF (less the folder
it is installed in) and the label it is derived under. A first command after install reads
them instead of deriving; any other URDF (the bundled description with other xacro arguments
included) is derived as usual. :func:`write_shipped` writes the file again; a test holds it
equal to a fresh derivation."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path
from typing import Any

from diffbot.urdf.cache import fields_json, from_entry
from diffbot.urdf.wheels import Derived, JointChoice

__all__ = ["BUNDLED_LABEL", "SHIPPED_PATH", "shipped_entry", "shipped_fields", "write_shipped"]

#: The label the bundled robot is derived under (it appears in warnings and errors).
BUNDLED_LABEL = "bundled diffbot"
#: Where the bundled robot's derived fields are stored.
SHIPPED_PATH = Path(__file__).resolve().parent.parent / "description" / "derived.json"


def _digest(urdf: str) -> str:
    # The expansion names the description's own files by their absolute paths: the digest is
    # taken with that folder left out, so that it holds wherever the package is installed.
    relative = urdf.replace(str(SHIPPED_PATH.parent), "<description>")
    return hashlib.sha256(relative.encode("utf-8")).hexdigest()


def shipped_entry(urdf: str, fields: Derived) -> dict[str, Any]:
    """The JSON record of ``fields`` derived from ``urdf`` under :data:`BUNDLED_LABEL`."""
    return {"urdf_sha256": _digest(urdf), "source": BUNDLED_LABEL, "fields": fields_json(fields)}


def shipped_fields(
    urdf: str, source: str, left_joint: JointChoice, right_joint: JointChoice
) -> Derived | None:
    """The shipped fields when ``urdf`` is the bundled robot's as shipped, else None."""
    if source != BUNDLED_LABEL or left_joint is not None or right_joint is not None:
        return None
    try:
        entry = json.loads(SHIPPED_PATH.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    if not isinstance(entry, dict) or entry.get("source") != BUNDLED_LABEL:
        return None
    if entry.get("urdf_sha256") != _digest(urdf):
        return None
    return from_entry(entry.get("fields"))


def write_shipped() -> None:
    """Derive the bundled robot afresh and store it at :data:`SHIPPED_PATH`."""
    from diffbot.urdf.wheels import derive_text
    from diffbot.urdf.xacro import expand

    urdf = expand(None).urdf
    entry = shipped_entry(urdf, derive_text(urdf, BUNDLED_LABEL))
    SHIPPED_PATH.write_text(json.dumps(entry, indent=1, sort_keys=True) + "\n", encoding="utf-8")
