"""Reading numbers back out of rendered derivations, to compare them with the library's."""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

from diffbot.kinematics import norm_angle

# A number as render() writes it: an ASCII sign, digits, and a power of ten in either format.
_NUMBER = re.compile(r"(-?)([0-9]+)(?:\.([0-9]+))?(?:e([+-][0-9]+)| \\times 10\^\{(-?[0-9]+)\})?")


@dataclass(frozen=True)
class Printed:
    """A number read from the text, with half a unit in its last printed digit."""

    text: str
    value: float
    half_unit: float

    def matches(self, exact: float, *, angle: bool = False) -> bool:
        """True when ``exact`` rounds to this number at its printed precision."""
        if self.value == 0.0 and self.text.lstrip("-") == "0":
            # a pose coordinate below a picometre is shown as 0 on purpose
            return abs(exact) < 1e-12 or abs(exact) <= self.half_unit
        error = norm_angle(self.value - exact) if angle else self.value - exact
        return abs(error) <= self.half_unit * (1 + 1e-9) + 1e-15 * abs(exact)


def numbers(text: str) -> list[Printed]:
    """Every number in ``text``, in order."""
    found = []
    for match in _NUMBER.finditer(text):
        sign, whole, fraction, exp_text, exp_latex = match.groups()
        exponent = int(exp_text or exp_latex or 0)
        decimals = len(fraction or "")
        value = float(f"{sign}{whole}.{fraction or '0'}e{exponent}")
        found.append(Printed(match.group(), value, 0.5 * 10.0 ** (exponent - decimals)))
    return found


@dataclass(frozen=True)
class Equation:
    """One rendered step: the numbers substituted into its formula, and those of its result."""

    line: str
    substituted: list[Printed]
    result: list[Printed]


def equations(rendered: str, fmt: str) -> list[Equation]:
    """The step lines of a rendering, in order."""
    found = []
    for raw in rendered.splitlines():
        if fmt == "text":
            if not raw.startswith("    ") or raw.lstrip().startswith("→"):
                continue
            line = raw.strip()
        else:
            if not raw.startswith("$$"):
                continue
            line = raw.strip("$")
        parts = line.split(" = ")
        assert len(parts) in (2, 4), line
        substituted = numbers(parts[2]) if len(parts) == 4 else []
        found.append(Equation(line, substituted, numbers(parts[-1])))
    return found


def notes(rendered: str, fmt: str) -> list[list[Printed]]:
    """The numbers of each conclusion line (the motor limit checks), in order."""
    marker = "    → " if fmt == "text" else "> "
    return [numbers(line) for line in rendered.splitlines() if line.startswith(marker)]


def assert_numbers(
    printed: list[Printed], exact: list[float], line: str, *, angles: frozenset[int] = frozenset()
) -> None:
    """Each printed number is the exact value at its printed precision (wrap-aware for angles)."""
    assert len(printed) == len(exact), f"{line}: {[p.text for p in printed]} vs {exact}"
    for position, (number, value) in enumerate(zip(printed, exact, strict=True)):
        assert number.matches(value, angle=position in angles), (
            f"{line}: {number.text} vs {value!r}"
        )


def degrees(angle: float) -> float:
    """An angle (rad) in degrees."""
    return math.degrees(angle)
