"""The live package from Python: importing diffbot (or diffbot.live) loads no DDS; the nodes are
there by name when used."""

from __future__ import annotations

import subprocess
import sys

import diffbot.live


def loads_cyclonedds(statement: str) -> bool:
    probe = f"import sys\n{statement}\nprint('cyclonedds' in sys.modules)"
    done = subprocess.run(
        [sys.executable, "-c", probe], capture_output=True, text=True, timeout=60, check=True
    )
    return done.stdout.strip() == "True"


def test_importing_the_packages_loads_no_dds() -> None:
    assert not loads_cyclonedds("import diffbot")
    assert not loads_cyclonedds("import diffbot.live")
    assert loads_cyclonedds("from diffbot.live import OdometryNode")


def test_every_public_name_resolves() -> None:
    for name in diffbot.live.__all__:
        assert getattr(diffbot.live, name).__name__ == name
