"""Worked derivations of diffbot's numbers, step by step, in several languages.

Build a derivation (:func:`explain_ik`, :func:`explain_fk`, :func:`explain_plan`,
:func:`explain_odom`), then :func:`render` it as text or Markdown in a language::

    from diffbot.explain import explain_ik, render
    print(render(explain_ik(params, 0.1, 0.0), lang="es"))

Derivations hold numbers and catalogue keys, never words; each language's strings live in a
module of :mod:`diffbot.explain.catalogues`, so a new language is a new file there.
"""

from diffbot.explain.catalogue import catalogue, languages
from diffbot.explain.derive import explain_fk, explain_ik, explain_odom, explain_plan
from diffbot.explain.errors import ExplainError
from diffbot.explain.model import Derivation, Quantity, Section, Step, Text
from diffbot.explain.render import FORMATS, format_number, render

__all__ = [
    "FORMATS",
    "Derivation",
    "ExplainError",
    "Quantity",
    "Section",
    "Step",
    "Text",
    "catalogue",
    "explain_fk",
    "explain_ik",
    "explain_odom",
    "explain_plan",
    "format_number",
    "languages",
    "render",
]
