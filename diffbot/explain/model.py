"""The structure of a worked derivation: quantities, steps, sections.

A derivation holds numbers and catalogue keys only, never words: :func:`diffbot.explain.render`
turns it into text or Markdown in a language.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import NamedTuple, Union

__all__ = ["Derivation", "Quantity", "Section", "Step", "Text"]


class Quantity(NamedTuple):
    """A number as it is shown.

    Attributes:
        value: the value, in ``unit``.
        unit: a unit key of :data:`diffbot.explain.notation.UNITS` (``"m"``, ``"rad/s"``,
            ``"rpm"``, ...; ``""`` for a pure number).
        digits: significant digits shown.
    """

    value: float
    unit: str = ""
    digits: int = 4


#: What a catalogue string's placeholder may be filled with.
Argument = Union[Quantity, int, "Text"]


@dataclass(frozen=True)
class Text:
    """A catalogue string to be shown: its key and the values of its ``{placeholders}``."""

    key: str
    args: Mapping[str, Argument] = field(default_factory=dict)


@dataclass(frozen=True)
class Step:
    """One line of a derivation: ``symbol = formula = formula with numbers = result``.

    A step without a formula states a given value (``r = 0.035 m``).

    Attributes:
        label: what the step computes, in words.
        symbol: notation key of the left-hand side (:data:`diffbot.explain.notation.SYMBOLS`).
        result: the value, as the library computes it.
        formula: notation key of the formula (:data:`diffbot.explain.notation.FORMULAS`), or
            None for a given value.
        values: the numbers substituted into the formula, by its placeholder names.
        also: the result in another unit (rpm for wheel speeds, degrees for angles), or None.
        note: a conclusion drawn from the result (the motor limit check), or None.
    """

    label: Text
    symbol: str
    result: Quantity
    formula: str | None = None
    values: Mapping[str, Quantity] = field(default_factory=dict)
    also: Quantity | None = None
    note: Text | None = None


@dataclass(frozen=True)
class Section:
    """A titled group of steps (the given data, one segment of a plan, ...)."""

    title: Text
    steps: tuple[Step, ...]


@dataclass(frozen=True)
class Derivation:
    """A whole worked derivation: a title and its sections, in order."""

    title: Text
    sections: tuple[Section, ...]

    @property
    def steps(self) -> tuple[Step, ...]:
        """Every step of every section, in order."""
        return tuple(step for section in self.sections for step in section.steps)
