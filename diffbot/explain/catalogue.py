"""The strings of the derivations, one catalogue per language.

Each language is a module of :mod:`diffbot.explain.catalogues` named by its code and defining
``STRINGS``, a dict from keys to :meth:`str.format` templates. English is the reference: every
other catalogue must hold exactly its keys, with the same placeholders.
"""

from __future__ import annotations

import functools
import importlib
import pkgutil
import re
import string
from collections.abc import Mapping
from types import MappingProxyType

from diffbot.explain import catalogues
from diffbot.explain.errors import ExplainError

__all__ = ["REFERENCE_LANGUAGE", "catalogue", "languages", "placeholders"]

#: The language whose keys every catalogue must hold.
REFERENCE_LANGUAGE = "en"

_CODE = re.compile(r"[a-z]{2,3}(?:_[A-Z]{2})?")


def languages() -> tuple[str, ...]:
    """The codes of the languages there are catalogues for, sorted."""
    return tuple(
        sorted(
            info.name
            for info in pkgutil.iter_modules(catalogues.__path__)
            if _CODE.fullmatch(info.name)
        )
    )


def placeholders(template: str) -> frozenset[str]:
    """The names of the ``{placeholders}`` of a catalogue string."""
    return frozenset(
        name for _, name, _, _ in string.Formatter().parse(template) if name is not None
    )


@functools.cache
def catalogue(lang: str) -> Mapping[str, str]:
    """The strings of a language, checked against the reference language.

    Args:
        lang: a language code such as ``"en"`` or ``"es"``.

    Returns:
        A read-only mapping from keys to templates.

    Raises:
        ExplainError: no catalogue for the language, or one whose keys or placeholders differ
            from the reference language's.
    """
    available = languages()
    if lang not in available:
        raise ExplainError(f"no strings for language {lang!r}; available: {', '.join(available)}")
    strings: Mapping[str, str] = importlib.import_module(f"{catalogues.__name__}.{lang}").STRINGS
    if lang != REFERENCE_LANGUAGE:
        reference = catalogue(REFERENCE_LANGUAGE)
        missing = sorted(set(reference) - set(strings))
        extra = sorted(set(strings) - set(reference))
        if missing or extra:
            raise ExplainError(
                f"the {lang!r} strings differ from the {REFERENCE_LANGUAGE!r} ones: "
                f"missing {missing}, unknown {extra}"
            )
        for key, template in reference.items():
            found, expected = placeholders(strings[key]), placeholders(template)
            if found != expected:
                raise ExplainError(
                    f"the {lang!r} string {key!r} has placeholders {sorted(found)}, "
                    f"expected {sorted(expected)}"
                )
    return MappingProxyType(dict(strings))
