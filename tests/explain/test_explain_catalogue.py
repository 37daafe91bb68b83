"""The language catalogues: the same keys and placeholders, and no English in Spanish output."""

from __future__ import annotations

import re
import sys
from pathlib import Path

import pytest
from robots import BOT_50_RPM

from diffbot.explain import (
    ExplainError,
    catalogue,
    catalogues,
    explain_fk,
    explain_ik,
    explain_odom,
    explain_plan,
    languages,
    render,
)
from diffbot.explain.catalogue import REFERENCE_LANGUAGE, placeholders
from diffbot.planfile import parse_plan
from diffbot.trajectory import EXAMPLES, plan


def test_english_and_spanish_are_both_available() -> None:
    assert {"en", "es"} <= set(languages())


@pytest.mark.parametrize("lang", languages())
def test_every_catalogue_has_exactly_the_english_keys(lang: str) -> None:
    assert set(catalogue(lang)) == set(catalogue(REFERENCE_LANGUAGE))


@pytest.mark.parametrize("lang", languages())
def test_every_catalogue_string_has_the_english_placeholders(lang: str) -> None:
    english = catalogue(REFERENCE_LANGUAGE)
    for key, template in catalogue(lang).items():
        assert placeholders(template) == placeholders(english[key]), key


def test_placeholders_are_read_from_format_fields() -> None:
    assert placeholders("{peak} > {limit}: needs {duration}") == {"peak", "limit", "duration"}


def _all_renderings(lang: str) -> list[str]:
    over = plan(parse_plan("straight 1 1s; spin 90"), BOT_50_RPM)
    derivations = [
        explain_ik(BOT_50_RPM, 0.1, 0.0),
        explain_ik(BOT_50_RPM, 1.0, 2.0),
        explain_fk(BOT_50_RPM, 1.0, 2.0),
        explain_plan(plan(parse_plan(EXAMPLES["A"]), BOT_50_RPM)),
        explain_plan(over),
        explain_odom(BOT_50_RPM, 0.0, 0.0, 1.0, 1.5, 0.1),
    ]
    return [render(d, fmt, lang) for d in derivations for fmt in ("text", "md")]


def _english_phrases() -> set[str]:
    """Word runs (two or more letters) of the English strings that Spanish translates."""
    english, spanish = catalogue("en"), catalogue("es")
    phrases = set()
    for key, template in english.items():
        if template == spanish[key]:
            continue
        for literal in re.split(r"\{[^}]*\}", template):
            phrases.update(re.findall(r"[A-Za-z][A-Za-z ]*[A-Za-z]", literal))
    # single symbols shared by both languages ("x at the start" starts with the symbol x)
    return {phrase for phrase in phrases if len(phrase) > 2}


def test_spanish_output_contains_no_english_catalogue_string() -> None:
    phrases = _english_phrases()
    assert "within the motor limit" in phrases
    for rendered in _all_renderings("es"):
        leaked = sorted(p for p in phrases if re.search(rf"\b{re.escape(p)}\b", rendered))
        assert leaked == [], leaked


def test_spanish_output_uses_the_class_wording() -> None:
    text = "\n".join(_all_renderings("es")).lower()
    for wording in (
        "velocidad lineal",
        "velocidad angular",
        "rueda izquierda",
        "rueda derecha",
        "rpm",
        "límite del motor",
    ):
        assert wording in text


def test_an_unknown_language_is_refused_with_the_available_ones() -> None:
    with pytest.raises(ExplainError, match=r"no strings for language 'fr'; available: en, es"):
        render(explain_ik(BOT_50_RPM, 0.1, 0.0), lang="fr")


def test_a_language_code_that_is_not_a_code_is_refused() -> None:
    with pytest.raises(ExplainError, match="no strings for language"):
        catalogue("../en")


def _add_catalogue(
    monkeypatch: pytest.MonkeyPatch, folder: Path, lang: str, strings: dict[str, str]
) -> None:
    """Put a catalogue module for ``lang`` in ``folder`` and make it part of the catalogues."""
    (folder / f"{lang}.py").write_text(f"STRINGS = {strings!r}\n", encoding="utf-8")
    monkeypatch.setattr(catalogues, "__path__", [*catalogues.__path__, str(folder)])
    monkeypatch.delitem(sys.modules, f"{catalogues.__name__}.{lang}", raising=False)
    catalogue.cache_clear()


def test_a_third_language_is_one_new_catalogue_file(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    strings = {key: f"<{template}>" for key, template in catalogue("en").items()}
    _add_catalogue(monkeypatch, tmp_path, "xx", strings)
    try:
        assert "xx" in languages()
        rendered = render(explain_ik(BOT_50_RPM, 0.1, 0.0), "text", "xx")
        assert "<Angular velocity of the left wheel>" in rendered
    finally:
        catalogue.cache_clear()


def test_a_catalogue_missing_a_key_is_refused_by_name(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    strings = dict(catalogue("en"))
    del strings["label.chord"]
    _add_catalogue(monkeypatch, tmp_path, "yy", strings)
    try:
        with pytest.raises(ExplainError, match=r"'yy' strings differ .*missing \['label.chord'\]"):
            catalogue("yy")
    finally:
        catalogue.cache_clear()


def test_a_catalogue_with_other_placeholders_is_refused_by_name(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    strings = dict(catalogue("en"))
    strings["check.within"] = "{peak} is fine"
    _add_catalogue(monkeypatch, tmp_path, "zz", strings)
    try:
        with pytest.raises(ExplainError, match=r"'zz' string 'check.within' has placeholders"):
            catalogue("zz")
    finally:
        catalogue.cache_clear()
