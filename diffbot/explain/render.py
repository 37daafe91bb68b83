"""Derivations as plain text (for a terminal) or Markdown with LaTeX maths (for notes).

Text (with U+2212 as the subtraction sign)::

    Velocidad angular de la rueda izquierda
      ω_L = (v - ω·b/2) / r = (0.1 - 0·0.135/2) / 0.035 = 2.857 rad/s (27.3 rpm)

Markdown writes each step as a display formula, ``$$\\omega_L = \\frac{v - \\omega \\cdot
b/2}{r} = ...$$``. Numbers keep their significant digits (trailing zeros dropped) and switch to
powers of ten outside [1e-6, 1e9); negative numbers substituted into a formula are parenthesised.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from string import Template
from typing import Literal

from diffbot.explain.catalogue import catalogue
from diffbot.explain.errors import ExplainError
from diffbot.explain.model import Argument, Derivation, Quantity, Step, Text
from diffbot.explain.notation import FORMULAS, SYMBOLS, UNITS, Notation

__all__ = ["FORMATS", "format_number", "render"]

Format = Literal["text", "md"]
#: The output formats :func:`render` knows.
FORMATS: tuple[Format, ...] = ("text", "md")


def format_number(value: float, digits: int, *, latex: bool = False) -> str:
    """A number rounded to ``digits`` significant digits (or to a whole number, when that has
    more), trailing zeros dropped.

    Positional between 1e-6 and 1e9 (``0.0785``, ``27.3``); otherwise ``1.5e-07`` (text) or
    ``1.5 \\times 10^{-7}`` (LaTeX), so that no number is written with hundreds of zeros.
    """
    if math.isnan(value):
        return r"\mathrm{NaN}" if latex else "nan"
    if math.isinf(value):
        sign = "-" if value < 0 else ""
        return sign + (r"\infty" if latex else "inf")
    if value == 0.0:
        return "0"
    mantissa, exponent_text = f"{value:.{digits - 1}e}".split("e")
    exponent = int(exponent_text)
    if -6 <= exponent < 9:
        # Whole numbers keep all their digits: 1220 for 1222.3 would read as exact.
        decimals = max(0, digits - 1 - exponent)
        return _strip(f"{value:.{decimals}f}")
    mantissa = _strip(mantissa)
    if latex:
        return rf"{mantissa} \times 10^{{{exponent}}}"
    return f"{mantissa}e{exponent:+03d}"


def _strip(number: str) -> str:
    if "." in number:
        number = number.rstrip("0").rstrip(".")
    return "0" if number in ("-0", "") else number


class _Writer:
    """Renders the parts of a derivation in one language and format."""

    def __init__(self, fmt: Format, lang: str) -> None:
        self.latex = fmt == "md"
        self.strings = catalogue(lang)

    def pick(self, notation: Notation) -> str:
        return notation.latex if self.latex else notation.text

    def number(self, quantity: Quantity) -> str:
        return format_number(quantity.value, quantity.digits, latex=self.latex)

    def quantity(self, quantity: Quantity) -> str:
        """A number with its unit, in the current format (LaTeX maths in Markdown)."""
        unit = self.pick(UNITS[quantity.unit])
        number = self.number(quantity)
        if not unit:
            return number
        if quantity.unit == "deg":
            return number + unit
        return rf"{number}\ {unit}" if self.latex else f"{number} {unit}"

    def words(self, text: Text) -> str:
        """A catalogue string with its placeholders filled (quantities in plain text)."""
        return self.strings[text.key].format_map(
            {name: self.argument(value) for name, value in text.args.items()}
        )

    def argument(self, value: Argument) -> str:
        if isinstance(value, Text):
            return self.words(value)
        if isinstance(value, Quantity):
            if self.latex:
                return f"${self.quantity(value)}$"
            return self.quantity(value)
        return str(value)

    def substituted(self, template: Template, values: Mapping[str, Quantity]) -> str:
        numbers: dict[str, str] = {}
        for name, quantity in values.items():
            number = self.number(quantity)
            numbers[name] = f"({number})" if quantity.value < 0.0 else number
        return template.substitute(numbers)

    def equation(self, step: Step) -> str:
        """``symbol = formula = numbers = result (also)``."""
        parts = [self.pick(SYMBOLS[step.symbol])]
        if step.formula is not None:
            template = Template(self.pick(FORMULAS[step.formula]))
            parts.append(
                template.substitute({name: self.pick(SYMBOLS[name]) for name in step.values})
            )
            parts.append(self.substituted(template, step.values))
        result = self.quantity(step.result)
        if step.also is not None:
            also = self.quantity(step.also)
            result = rf"{result}\ ({also})" if self.latex else f"{result} ({also})"
        parts.append(result)
        return " = ".join(parts)


def _text(derivation: Derivation, writer: _Writer) -> list[str]:
    lines = [writer.words(derivation.title)]
    for section in derivation.sections:
        lines.extend(["", writer.words(section.title)])
        for step in section.steps:
            lines.append(f"  {writer.words(step.label)}")
            lines.append(f"    {writer.equation(step)}")
            if step.note is not None:
                lines.append(f"    → {writer.words(step.note)}")
    return lines


def _markdown(derivation: Derivation, writer: _Writer) -> list[str]:
    lines = [f"## {writer.words(derivation.title)}"]
    for section in derivation.sections:
        lines.extend(["", f"### {writer.words(section.title)}"])
        for step in section.steps:
            lines.extend(["", f"**{writer.words(step.label)}**", ""])
            lines.append(f"$${writer.equation(step)}$$")
            if step.note is not None:
                lines.extend(["", f"> {writer.words(step.note)}"])
    return lines


def render(derivation: Derivation, fmt: str = "text", lang: str = "en") -> str:
    """A derivation as text or Markdown in a language.

    Args:
        derivation: from :func:`~diffbot.explain.explain_ik` and its siblings.
        fmt: ``"text"`` (Unicode maths, for a terminal) or ``"md"`` (Markdown with ``$$``
            LaTeX display maths).
        lang: a language code with a catalogue (``"en"``, ``"es"``; see
            :func:`~diffbot.explain.languages`).

    Returns:
        The rendering, lines separated by ``\\n``, ending with one.

    Raises:
        ExplainError: an unknown format or language.
    """
    if fmt == "text":
        lines = _text(derivation, _Writer("text", lang))
    elif fmt == "md":
        lines = _markdown(derivation, _Writer("md", lang))
    else:
        raise ExplainError(f"unknown format {fmt!r}: expected one of {', '.join(FORMATS)}")
    return "\n".join(lines) + "\n"
