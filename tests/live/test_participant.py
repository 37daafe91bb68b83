"""A process's DDS participants: the domain id checked, the user's Cyclone configuration taken,
and what Cyclone says when it cannot start folded into the one error."""

from __future__ import annotations

import os
from collections.abc import Callable

import pytest
from live_graph import spare_domain

from diffbot.live.cyclone import DDSException
from diffbot.live.errors import LiveError
from diffbot.live.participant import _cyclone_says, participant


def test_a_domain_out_of_range_is_refused_before_dds() -> None:
    for bad in (-1, 233):
        with pytest.raises(LiveError, match=rf"^the domain id must be from 0 to 232, got {bad}$"):
            participant(bad)


@pytest.mark.parametrize(
    ("uri", "said"),
    [
        (
            "file:///nonexistent/dds.xml",
            "can't open configuration file file:///nonexistent/dds.xml",
        ),
        (
            "<CycloneDDS><Domain><General><Bogus/></General></Domain></CycloneDDS>",
            "config: //CycloneDDS/Domain/General: Bogus: unknown element",
        ),
    ],
)
def test_the_users_cyclone_configuration_is_taken_and_its_faults_are_the_error(
    uri: str, said: str, monkeypatch: pytest.MonkeyPatch, capfd: pytest.CaptureFixture[str]
) -> None:
    # A domain of its own: Cyclone keeps the first configuration of each domain.
    domain = spare_domain(4)
    monkeypatch.setenv("CYCLONEDDS_URI", uri)
    with pytest.raises(LiveError) as caught:
        participant(domain)
    assert str(caught.value).startswith(f"cannot start DDS on domain {domain}: {said}")
    assert "\n" not in str(caught.value)
    assert capfd.readouterr().err == ""  # Cyclone's lines are in the error, not on stderr


class ConfiguredError(Exception):
    """Raised instead of starting a domain: the domain id and the configuration it was given."""


@pytest.fixture
def configured(monkeypatch: pytest.MonkeyPatch) -> None:
    """No domain started yet in this process, and each start raises :class:`ConfiguredError`
    instead of starting one."""
    from diffbot.live import participant as module

    def start(ident: int, config: str) -> None:
        raise ConfiguredError(ident, config)

    monkeypatch.setattr(module, "Domain", start)
    monkeypatch.setattr(module, "_DOMAINS", {})


@pytest.mark.parametrize(
    ("environment", "reach"),
    [
        ({"ROS_LOCALHOST_ONLY": "1"}, "LOCALHOST"),
        ({"ROS_AUTOMATIC_DISCOVERY_RANGE": "OFF"}, "OFF"),
        ({"ROS_AUTOMATIC_DISCOVERY_RANGE": "SUBNET"}, "SUBNET"),
    ],
)
@pytest.mark.usefixtures("configured")
def test_a_domain_is_configured_for_the_discovery_range_after_the_users_file(
    environment: dict[str, str], reach: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    from diffbot.live.discovery import cyclone_config

    for name in ("ROS_LOCALHOST_ONLY", "ROS_AUTOMATIC_DISCOVERY_RANGE"):
        monkeypatch.delenv(name, raising=False)
    for name, value in environment.items():
        monkeypatch.setenv(name, value)
    monkeypatch.setenv("CYCLONEDDS_URI", "file:///etc/dds.xml")
    with pytest.raises(ConfiguredError) as started:
        participant(spare_domain(4))
    assert started.value.args == (spare_domain(4), cyclone_config(reach, "file:///etc/dds.xml"))


@pytest.mark.parametrize("ident", [0, 232])
@pytest.mark.usefixtures("configured")
def test_the_first_and_last_domain_ids_are_taken(ident: int) -> None:
    with pytest.raises(ConfiguredError) as started:
        participant(ident)
    assert started.value.args[0] == ident


def test_a_participant_that_cannot_join_is_one_error_naming_the_domain(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    from diffbot.live import participant as module

    def full(ident: int) -> None:
        raise DDSException(-1, "no participant index left")

    monkeypatch.setattr(module, "DomainParticipant", full)
    with pytest.raises(LiveError) as caught:
        participant(spare_domain(3))
    assert str(caught.value).startswith(f"cannot join DDS domain {spare_domain(3)}: ")
    assert "no participant index left" in str(caught.value)


def test_what_cyclone_writes_goes_on_to_stderr_unless_it_fails(
    capfd: pytest.CaptureFixture[str],
) -> None:
    with _cyclone_says() as said:
        os.write(2, b"1.5 [0] main: a warning\n")
    assert said == []
    assert capfd.readouterr().err == "1.5 [0] main: a warning\n"

    held: list[list[str]] = []

    def failing() -> None:
        with _cyclone_says() as said:
            held.append(said)
            os.write(2, b"1.5 [0] main: the reason\n1.6 [0] main: and more\n")
            raise DDSException(1, "failed")

    with pytest.raises(DDSException):
        failing()
    assert held == [["the reason", "and more"]]
    assert capfd.readouterr().err == ""


class _Entity:
    """Stands in for a Cyclone entity: records its making and its (first) deletion in ``log``."""

    def __init__(self, log: list[tuple[str, object]], kind: str, *args: object) -> None:
        self.log, self.kind, self.gone = log, kind, False
        log.append((f"make {kind}", args))

    def __del__(self) -> None:
        if not self.gone:
            self.gone = True
            self.log.append((f"delete {self.kind}", id(self)))


@pytest.fixture
def entities(monkeypatch: pytest.MonkeyPatch) -> list[tuple[str, object]]:
    """No domain started yet in this process; domains and participants are :class:`_Entity`
    stand-ins whose making and deletion go, in order, into the list returned."""
    from diffbot.live import participant as module

    log: list[tuple[str, object]] = []
    made: list[_Entity] = []  # kept, so that only an explicit deletion is logged, not the GC's

    def maker(kind: str) -> Callable[..., _Entity]:
        def make(*args: object) -> _Entity:
            made.append(_Entity(log, kind, *args))
            return made[-1]

        return make

    monkeypatch.setattr(module, "Domain", maker("domain"))
    monkeypatch.setattr(module, "DomainParticipant", maker("participant"))
    monkeypatch.setattr(module, "_DOMAINS", {})
    monkeypatch.setattr(module, "_MEMBERS", {})
    return log


def test_the_last_participant_to_leave_takes_its_domain_after_itself(
    entities: list[tuple[str, object]], monkeypatch: pytest.MonkeyPatch
) -> None:
    from diffbot.live.discovery import cyclone_config
    from diffbot.live.participant import leave

    here = spare_domain(4)
    first, second = participant(here), participant(here)
    other = participant(spare_domain(3))
    assert [kind for kind, _ in entities].count("make domain") == 2
    leave(first)
    leave(first)  # a second call does nothing
    assert entities[-1] == ("delete participant", id(first))
    leave(second)
    # The participant goes first, then its domain: deleting a domain waits for its disposals.
    assert [kind for kind, _ in entities[-3:]] == [
        "delete participant",
        "delete participant",
        "delete domain",
    ]
    assert entities[-2] == ("delete participant", id(second))
    assert not other.gone  # another domain's participant is not touched
    # The next participant configures the domain anew, from the environment as it is now.
    monkeypatch.setenv("CYCLONEDDS_URI", "file:///etc/dds.xml")
    participant(here)
    made = [args for kind, args in entities if kind == "make domain"]
    assert made[-1] == (here, cyclone_config("LOCALHOST", "file:///etc/dds.xml"))


def test_a_participant_that_cannot_join_an_empty_domain_takes_it_away(
    entities: list[tuple[str, object]], monkeypatch: pytest.MonkeyPatch
) -> None:
    from diffbot.live import participant as module

    def full(ident: int) -> None:
        raise DDSException(-1, "no participant index left")

    monkeypatch.setattr(module, "DomainParticipant", full)
    with pytest.raises(LiveError):
        participant(spare_domain(4))
    assert [kind for kind, _ in entities] == ["make domain", "delete domain"]
    assert module._DOMAINS == {}
