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


def test_the_environment_and_the_errors_are_read_without_dds() -> None:
    # Where discovery reaches and which domain: pure, no participant needed.
    assert not loads_cyclonedds("import diffbot.live.discovery")
    assert not loads_cyclonedds("from diffbot.live import LiveError")
    assert loads_cyclonedds("import diffbot.live.qos")


def test_the_transport_names_every_part_as_its_home_does() -> None:
    from diffbot.live import cyclone, discovery, endpoints, errors, qos, transport

    homes = (cyclone, discovery, endpoints, errors, qos)
    for name in transport.__all__:
        found = [home for home in homes if name in home.__all__]
        if name == "Node":
            assert found == []
            continue
        (home,) = found
        assert getattr(transport, name) is getattr(home, name), name
