"""Every regular expression of the package matches in time linear in its text: none has
repeats that can take the same characters in more than one way (a ReDoS).

Two checks: regexploit (nested and adjacent repeats over one character class, cubic and
worse, such as ``(a+)+`` or ``a*\\w*[a-z]*!``) and, for what it cannot see, a repeat whose body
holds a repeat that can run on into the next round of the body (``(<!--.*?-->\\s*)*``,
exponential in the number of comments). Two overlapping repeats side by side (quadratic) are
left to the readers' time tests (tests/test_linear_readers.py).
"""

from __future__ import annotations

import ast
import re
import warnings
from collections.abc import Iterator
from pathlib import Path

import pytest

with warnings.catch_warnings():
    warnings.simplefilter("ignore", DeprecationWarning)  # regexploit reads sre_parse
    from regexploit.ast.sre import SreOpParser
    from regexploit.languages.python_node_visitor import RE_FUNC_TO_FLAGS_POS, RegexFlagVisitor
    from regexploit.redos import find

try:
    from re import _constants as sre_constants
    from re import _parser as sre_parse
except ImportError:  # Python 3.10
    import sre_constants  # type: ignore[no-redef]
    import sre_parse  # type: ignore[no-redef]

PACKAGE = Path(__file__).resolve().parent.parent / "diffbot"


def _source(expression: str) -> str:
    return ast.unparse(ast.parse(expression, mode="eval").body)


#: Patterns built at run time, with what they are built from spelled out: a new one fails the
#: test until it is added here.
BUILT = {
    (
        "calibration/apply.py",
        _source(r'''rb"(\s" + definition.attribute.encode() + rb"\s*=\s*)([\"'])[^\"']*\2"'''),
    ): [rb"(\sdefault\s*=\s*)([\"'])[^\"']*\2", rb"(\svalue\s*=\s*)([\"'])[^\"']*\2"],
}

#: What the old test of an SDF root element matched with re.S; it hung on plain URDFs.
OLD_SDF_TEST = r"\s*(<\?xml[^>]*\?>\s*)?(<!--.*?-->\s*)*<sdf[\s>]"


def _constants(tree: ast.Module) -> dict[str, str | bytes]:
    found: dict[str, str | bytes] = {}
    for node in tree.body:
        if isinstance(node, ast.Assign | ast.AnnAssign) and isinstance(node.value, ast.Constant):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            for target in targets:
                if isinstance(target, ast.Name) and isinstance(node.value.value, str | bytes):
                    found[target.id] = node.value.value
    return found


def _flags(call: ast.Call, position: int) -> int:
    if len(call.args) > position:
        return int(RegexFlagVisitor.get_flags(call.args[position]))
    for keyword in call.keywords:
        if keyword.arg == "flags":
            return int(RegexFlagVisitor.get_flags(keyword.value))
    return 0


def package_patterns() -> Iterator[tuple[str, str | bytes, int]]:
    """Every pattern given to a function of ``re`` in the package: (where, pattern, flags)."""
    for path in sorted(PACKAGE.rglob("*.py")):
        name = str(path.relative_to(PACKAGE))
        tree = ast.parse(path.read_text(encoding="utf-8"))
        constants = _constants(tree)
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and node.module in ("re", "regex", "sre_compile"):
                raise AssertionError(f"{name}:{node.lineno}: import re itself, not from it")
            if isinstance(node, ast.Import) and any(
                a.name in ("re", "regex") and a.asname for a in node.names
            ):
                raise AssertionError(f"{name}:{node.lineno}: import re under its own name")
            if not (
                isinstance(node, ast.Call)
                and isinstance(node.func, ast.Attribute)
                and isinstance(node.func.value, ast.Name)
                and node.func.value.id == "re"
                and node.func.attr in RE_FUNC_TO_FLAGS_POS
            ):
                continue
            where = f"{name}:{node.lineno}"
            flags = _flags(node, RE_FUNC_TO_FLAGS_POS[node.func.attr])
            argument = node.args[0]
            if isinstance(argument, ast.Constant) and isinstance(argument.value, str | bytes):
                yield where, argument.value, flags
            elif isinstance(argument, ast.Name) and argument.id in constants:
                yield where, constants[argument.id], flags
            elif (name, ast.unparse(argument)) in BUILT:
                for pattern in BUILT[name, ast.unparse(argument)]:
                    yield where, pattern, flags
            else:
                raise AssertionError(f"{where}: pattern {ast.unparse(argument)} is not checked")


def regexploit_findings(pattern: str | bytes, flags: int) -> list[str]:
    """regexploit's findings on one pattern; a pattern it cannot read is an error, not a pass."""
    text = pattern.decode("latin-1") if isinstance(pattern, bytes) else pattern
    parsed = SreOpParser().parse_sre(text, flags)
    return [f"{r} (e.g. {r.example()})" for r in find(parsed)]


# --- repeats that run on into the next round of their own body ----------------------------

_ALPHABET = [chr(c) for c in range(128)] + ["\u00a0", "\u00e9", "\u2028", "\u4e00"]
_CATEGORIES = {
    "DIGIT": str.isdigit,
    "SPACE": str.isspace,
    "WORD": lambda c: c.isalnum() or c == "_",
}


def _category(name: str, char: str) -> bool:
    kind = str(name).removeprefix("CATEGORY_").removeprefix("UNI_").removeprefix("LOC_")
    negate = kind.startswith("NOT_")
    test = _CATEGORIES.get(kind.removeprefix("NOT_"))
    return test is not None and test(char) != negate


def _in_set(items: list[tuple[object, object]], char: str, ignore_case: bool) -> bool:
    chars = {char, char.lower(), char.upper()} if ignore_case else {char}
    hit, negate = False, False
    for op, value in items:
        name = str(op)
        if name == "NEGATE":
            negate = True
        elif name == "LITERAL":
            hit |= chr(value) in chars  # type: ignore[call-overload]
        elif name == "RANGE":
            low, high = value  # type: ignore[misc]
            hit |= any(low <= ord(c) <= high for c in chars)
        elif name == "CATEGORY":
            hit |= _category(str(value), char)
    return hit != negate


def _chars(item: tuple[object, object], flags: int) -> set[str]:
    """Characters (of a sample alphabet) that ``item`` may consume anywhere."""
    op, value = item
    name = str(op)
    case = bool(flags & re.IGNORECASE)
    if name == "LITERAL":
        return {c for c in _ALPHABET if _in_set([(op, value)], c, case)}
    if name == "NOT_LITERAL":
        return {c for c in _ALPHABET if not _in_set([(sre_constants.LITERAL, value)], c, case)}
    if name == "ANY":
        return {c for c in _ALPHABET if c != "\n" or flags & re.DOTALL}
    if name == "IN":
        return {c for c in _ALPHABET if _in_set(list(value), c, case)}  # type: ignore[call-overload]
    found: set[str] = set()
    for sub in _children(item):
        for child in sub:
            found |= _chars(child, flags)
    return found


def _children(item: tuple[object, object]) -> list[list[tuple[object, object]]]:
    op, value = item
    name = str(op)
    if name in ("MAX_REPEAT", "MIN_REPEAT", "POSSESSIVE_REPEAT"):
        return [list(value[2])]  # type: ignore[index]
    if name == "SUBPATTERN":
        return [list(value[-1])]  # type: ignore[index]
    if name == "BRANCH":
        return [list(branch) for branch in value[1]]  # type: ignore[index]
    if name in ("ATOMIC_GROUP", "ASSERT", "ASSERT_NOT"):
        return [list(value if name == "ATOMIC_GROUP" else value[1])]  # type: ignore[index]
    return []


def _first(sequence: list[tuple[object, object]], flags: int) -> set[str]:
    """Characters a match of ``sequence`` may start with."""
    found: set[str] = set()
    for item in sequence:
        name = str(item[0])
        if name in ("AT", "ASSERT", "ASSERT_NOT", "GROUPREF"):
            continue
        if name in ("MAX_REPEAT", "MIN_REPEAT", "POSSESSIVE_REPEAT"):
            found |= _first(_children(item)[0], flags)
            if item[1][0] == 0:  # type: ignore[index]
                continue
            return found
        if name in ("SUBPATTERN", "BRANCH", "ATOMIC_GROUP"):
            for sub in _children(item):
                found |= _first(sub, flags)
            return found
        return found | _chars(item, flags)
    return found


def _unbounded(item: tuple[object, object]) -> bool:
    return str(item[0]) in ("MAX_REPEAT", "MIN_REPEAT") and item[1][1] == sre_constants.MAXREPEAT  # type: ignore[index]


def _may_be_empty(item: tuple[object, object]) -> bool:
    """Whether ``item`` may match no character (an anchor, a lookaround, an optional repeat)."""
    name = str(item[0])
    if name in ("AT", "ASSERT", "ASSERT_NOT"):
        return True
    return name in ("MAX_REPEAT", "MIN_REPEAT", "POSSESSIVE_REPEAT") and item[1][0] == 0  # type: ignore[index]


def _runs_on(sequence: list[tuple[object, object]], flags: int) -> Iterator[str]:
    for item in sequence:
        if _unbounded(item):
            body = _children(item)[0]
            while len(body) == 1 and str(body[0][0]) == "SUBPATTERN":
                body = _children(body[0])[0]
            start = _first(body, flags)
            for index, inner in enumerate(body):
                if not _unbounded(inner):
                    continue
                swallows = _chars(inner, flags)
                rest = body[index + 1 :]
                # the inner repeat can take the rest of this round and the start of the next
                if start & swallows and all(
                    _chars(part, flags) & swallows for part in rest if not _may_be_empty(part)
                ):
                    yield f"{inner[0]} inside a repeat can run into its next round"
        for sub in _children(item):
            yield from _runs_on(sub, flags)


def run_on_findings(pattern: str | bytes, flags: int) -> list[str]:
    text = pattern.decode("latin-1") if isinstance(pattern, bytes) else pattern
    return list(_runs_on(list(sre_parse.parse(text, flags)), flags))


# --- the checks ----------------------------------------------------------------------------


def test_the_checks_find_what_they_are_for() -> None:
    # a check that finds nothing anywhere would pass any package
    assert regexploit_findings(r"(a+)+b", 0)
    assert regexploit_findings(r"[a-z]*\w*[a-z0-9]*!", 0)
    assert run_on_findings(OLD_SDF_TEST, re.S)
    assert run_on_findings(r"(<!--.*?-->\s*)*<sdf", 0)
    # and neither refuses repeats kept apart by a character the inner repeat cannot take
    assert not run_on_findings(r"(~/|/)?[A-Za-z_][A-Za-z0-9_]*(/[A-Za-z_][A-Za-z0-9_]*)*", 0)
    assert not run_on_findings(rb"<[^\"'>]*(?:(?:\"[^\"]*\"|'[^']*')[^\"'>]*)*>", 0)


def test_every_pattern_of_the_package_is_found() -> None:
    found = {pattern for _, pattern, _ in package_patterns()}
    assert len(found) >= 25
    assert r"[A-Za-z0-9](?:[A-Za-z0-9.\-]*[A-Za-z0-9])?|\[[0-9A-Fa-f:.]+\]" in found


@pytest.mark.parametrize(("where", "pattern", "flags"), list(package_patterns()))
def test_no_pattern_backtracks_more_than_linearly(
    where: str, pattern: str | bytes, flags: int
) -> None:
    findings = regexploit_findings(pattern, flags) + run_on_findings(pattern, flags)
    assert not findings, f"{where}: {pattern!r}: {'; '.join(findings)}"
