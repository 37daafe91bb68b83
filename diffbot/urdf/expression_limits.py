"""Size limits of sandboxed expressions: results too large to compute are refused beforehand.

An expression such as ``9**9**9**9`` or ``'x' * 10**12`` would take hours or all memory; each
operation that can grow its result is checked against these limits before it is computed.
"""

from __future__ import annotations

import ast
import math
import re
from collections.abc import Iterable
from typing import Any, TypeVar

from diffbot.errors import ExpansionLimitError

__all__ = [
    "MAX_EXPRESSION",
    "MAX_FORMAT_WIDTH",
    "MAX_INT_BITS",
    "MAX_ITEMS",
    "PADDING_METHODS",
    "RefusalError",
    "check_binary",
    "check_format",
    "check_method_call",
    "check_power",
    "check_size",
    "weight",
    "yaml_weight",
]

#: Largest integer (bits) an expression may produce; 4096 bits is about 10**1233.
MAX_INT_BITS = 4096
#: Longest string (characters) or container (items, nested items counted) an expression may make.
MAX_ITEMS = 1_000_000
#: Longest expression text (characters).
MAX_EXPRESSION = 10_000
#: Widest field in a ``%`` or f-string format.
MAX_FORMAT_WIDTH = 1000

PADDING_METHODS = frozenset({"center", "ljust", "rjust", "zfill"})
#: What follows the ``%`` (and mapping key) of a format field: flags, width, precision.
_FORMAT_FIELD = re.compile(r"[#0 +-]*(\*|\d+)?(?:\.(\*|\d+))?")
_T = TypeVar("_T")


class RefusalError(Exception):
    """Raised deep in the evaluator; turned into a message naming the whole expression."""


def weight(value: Any, limit: int = MAX_ITEMS) -> int:
    """Characters or items ``value`` stands for, nested items counted, stopping past ``limit``.

    An item of a container counts at least one, an empty string too: a list of a million empty
    strings is a million items to build and to repeat."""
    if isinstance(value, (str, bytes)):
        return len(value)
    if isinstance(value, int):
        return value.bit_length() // 3 + 1
    if isinstance(value, dict):
        items: Iterable[Any] = (x for pair in value.items() for x in pair)
    elif isinstance(value, (list, tuple, set, frozenset)):
        items = value
    else:
        return 1
    total = 1
    for item in items:
        total += max(1, weight(item, limit - total))
        if total > limit:
            break
    return total


def yaml_weight(data: Any, memo: dict[int, int], limit: int) -> int:
    """Items in YAML data with aliases expanded (each at least one), not expanding them."""
    key = id(data)
    if key in memo:
        if memo[key] < 0:
            raise ExpansionLimitError("YAML data refers to itself (a recursive alias)")
        return memo[key]
    if isinstance(data, dict):
        children: list[Any] = [*data.keys(), *data.values()]
    elif isinstance(data, list):
        children = list(data)
    else:
        return weight(data, limit)
    memo[key] = -1
    total = 1
    for child in children:
        total += max(1, yaml_weight(child, memo, limit))
        if total > limit:
            break
    memo[key] = total
    return total


def check_size(value: _T) -> _T:
    if isinstance(value, int) and value.bit_length() > MAX_INT_BITS:
        raise RefusalError(f"an integer of more than {MAX_INT_BITS} bits")
    if isinstance(value, (str, list, tuple, dict, set, frozenset)) and weight(value) > MAX_ITEMS:
        raise RefusalError(f"a result of more than {MAX_ITEMS} characters or items")
    return value


def check_power(base: Any, exponent: Any) -> None:
    if (
        isinstance(base, int)
        and isinstance(exponent, int)
        and exponent > 0
        and abs(base) > 1
        and exponent * math.log2(abs(base)) >= MAX_INT_BITS
    ):
        raise RefusalError(f"a power of more than {MAX_INT_BITS} bits")


def check_repeat(sequence: Any, count: Any) -> None:
    if isinstance(count, int) and count > 0 and weight(sequence) * count > MAX_ITEMS:
        raise RefusalError(f"a repetition of more than {MAX_ITEMS} characters or items")


def _key_end(template: str, start: int) -> int:
    """End of the mapping key opening at ``start`` (a ``(``): its parentheses nest, as Python
    reads them; the end of the text when it is never closed (Python then refuses the format)."""
    depth, position = 0, start
    while position < len(template):
        depth += {"(": 1, ")": -1}.get(template[position], 0)
        position += 1
        if depth == 0:
            break
    return position


def check_format(template: str) -> None:
    position = template.find("%")
    while position >= 0:
        start = position + 1
        if template.startswith("(", start):
            start = _key_end(template, start)
        field = _FORMAT_FIELD.match(template, start)
        assert field is not None  # every part of the pattern may be empty
        for number in field.groups():
            if number == "*" or (number and int(number) > MAX_FORMAT_WIDTH):
                raise RefusalError(f"a format field wider than {MAX_FORMAT_WIDTH}")
        position = template.find("%", field.end())


def check_binary(kind: type[ast.operator], left: Any, right: Any) -> None:
    """Refuse, before computing it, a result that would be too large to compute."""
    sequences = (str, list, tuple)
    if kind is ast.Pow:
        check_power(left, right)
    elif kind is ast.Mult:
        if isinstance(left, sequences):
            check_repeat(left, right)
        elif isinstance(right, sequences):
            check_repeat(right, left)
        elif (
            isinstance(left, int)
            and isinstance(right, int)
            and left.bit_length() + right.bit_length() > MAX_INT_BITS + 1
        ):
            raise RefusalError(f"a product of more than {MAX_INT_BITS} bits")
    elif kind is ast.LShift:
        if isinstance(left, int) and isinstance(right, int) and right > MAX_INT_BITS:
            raise RefusalError(f"a shift of more than {MAX_INT_BITS} bits")
    elif kind is ast.Add:
        if isinstance(left, sequences) and weight(left) + weight(right) > MAX_ITEMS:
            raise RefusalError(f"a concatenation of more than {MAX_ITEMS} characters or items")
    elif kind is ast.Mod and isinstance(left, str):
        check_format(left)


def check_method_call(owner: Any, name: str, args: tuple[Any, ...]) -> tuple[Any, ...]:
    """Refuse a call whose result would be too large; the arguments to call with."""
    if name == "replace" and len(args) >= 2:
        old, new = str(args[0]), str(args[1])
        places = owner.count(old) if old else len(owner) + 1
        if len(owner) + places * max(len(new) - len(old), 0) > MAX_ITEMS:
            raise RefusalError(f"a replacement of more than {MAX_ITEMS} characters")
    elif name == "join" and args:
        parts = tuple(args[0])  # an iterator is read once, here, and joined from the copy
        if sum(weight(p) for p in parts) + len(owner) * len(parts) > MAX_ITEMS:
            raise RefusalError(f"a join of more than {MAX_ITEMS} characters")
        return (parts, *args[1:])
    elif name in PADDING_METHODS and args and isinstance(args[0], int) and args[0] > MAX_ITEMS:
        raise RefusalError(f"a padding of more than {MAX_ITEMS} characters")
    return args
