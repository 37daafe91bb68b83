"""xacro expressions evaluated without running arbitrary Python.

xacro evaluates ``${...}`` and ``$(eval ...)`` with Python's ``eval``, so a description downloaded
from anywhere could run any code or read any file. :func:`safe_eval` walks the syntax tree
instead and knows only literals, operators, conditionals, subscripts, the functions xacro
documents (math and a few builtins), ``xacro.load_yaml`` and the attributes of YAML data,
namespaces and plain strings, lists and dicts; anything else is refused before it runs, and so
are results too large to compute (:mod:`diffbot.urdf.expression_limits`).
"""

from __future__ import annotations

import ast
import builtins
import math
import operator
import re
from collections.abc import Callable, Mapping
from typing import Any

from diffbot.errors import RefusedExpressionError
from diffbot.urdf.expression_limits import (
    MAX_EXPRESSION,
    MAX_FORMAT_WIDTH,
    MAX_ITEMS,
    RefusalError,
    check_binary,
    check_method_call,
    check_power,
    check_size,
)

__all__ = ["TRUST_HINT", "SafeFunction", "safe_eval", "symbols"]

#: What a refusal tells the user to do when they vouch for the description.
TRUST_HINT = "trust the description ({trust}) to let xacro run it with its full Python"


class SafeFunction:
    """A function expressions may call; only these and :class:`_Method` are ever called."""

    __slots__ = ("function", "name")

    def __init__(self, name: str, function: Callable[..., Any]) -> None:
        self.name = name
        self.function = function

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        return self.function(*args, **kwargs)

    def __repr__(self) -> str:
        return f"<function {self.name}>"


class _Method:
    """A whitelisted method bound to a str, list, tuple or dict."""

    __slots__ = ("name", "owner")

    def __init__(self, owner: Any, name: str) -> None:
        self.owner = owner
        self.name = name

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        args = check_method_call(self.owner, self.name, args)
        return getattr(self.owner, self.name)(*args, **kwargs)

    def __repr__(self) -> str:
        return f"<method {type(self.owner).__name__}.{self.name}>"


_STR_METHODS = frozenset(
    (
        "capitalize",
        "center",
        "count",
        "endswith",
        "find",
        "index",
        "isalnum",
        "isalpha",
        "isdigit",
        "islower",
        "isspace",
        "isupper",
        "join",
        "ljust",
        "lower",
        "lstrip",
        "replace",
        "rfind",
        "rindex",
        "rjust",
        "rsplit",
        "rstrip",
        "split",
        "splitlines",
        "startswith",
        "strip",
        "title",
        "upper",
        "zfill",
    )
)
_SEQUENCE_METHODS = frozenset({"count", "index"})
_DICT_METHODS = frozenset({"get", "items", "keys", "values"})

_BINARY: dict[type[ast.operator], Callable[[Any, Any], Any]] = {
    ast.Add: operator.add,
    ast.Sub: operator.sub,
    ast.Mult: operator.mul,
    ast.Div: operator.truediv,
    ast.FloorDiv: operator.floordiv,
    ast.Mod: operator.mod,
    ast.Pow: operator.pow,
    ast.LShift: operator.lshift,
    ast.RShift: operator.rshift,
    ast.BitAnd: operator.and_,
    ast.BitOr: operator.or_,
    ast.BitXor: operator.xor,
}
_UNARY: dict[type[ast.unaryop], Callable[[Any], Any]] = {
    ast.UAdd: operator.pos,
    ast.USub: operator.neg,
    ast.Not: operator.not_,
    ast.Invert: operator.invert,
}
_COMPARE: dict[type[ast.cmpop], Callable[[Any, Any], Any]] = {
    ast.Eq: operator.eq,
    ast.NotEq: operator.ne,
    ast.Lt: operator.lt,
    ast.LtE: operator.le,
    ast.Gt: operator.gt,
    ast.GtE: operator.ge,
    ast.Is: operator.is_,
    ast.IsNot: operator.is_not,
    ast.In: lambda a, b: a in b,
    ast.NotIn: lambda a, b: a not in b,
}
_CONSTANT_TYPES = (bool, int, float, complex, str, type(None))
_NODE_NAMES = {
    "Lambda": "lambda",
    "ListComp": "a comprehension",
    "SetComp": "a comprehension",
    "DictComp": "a comprehension",
    "GeneratorExp": "a generator expression",
    "NamedExpr": "assignment (:=)",
    "Await": "await",
    "Yield": "yield",
    "YieldFrom": "yield",
    "Starred": "unpacking (*)",
}

#: The node types :class:`_Evaluator` knows, each by a method ``_<name in lower case>``.
_VISITED = frozenset(
    (
        "Attribute",
        "BinOp",
        "BoolOp",
        "Call",
        "Compare",
        "Constant",
        "Dict",
        "FormattedValue",
        "IfExp",
        "JoinedStr",
        "List",
        "Name",
        "Set",
        "Slice",
        "Subscript",
        "Tuple",
        "UnaryOp",
    )
)


def _methods_of(value: Any) -> frozenset[str]:
    if isinstance(value, str):
        return _STR_METHODS
    if isinstance(value, dict):
        return _DICT_METHODS
    if isinstance(value, (list, tuple)):
        return _SEQUENCE_METHODS
    return frozenset()


class _Evaluator:
    """Evaluates one parsed expression, node by node, refusing what is not whitelisted."""

    def __init__(
        self,
        names: Mapping[str, Any],
        fallback: Mapping[str, Any],
        tick: Callable[[], None] | None = None,
    ) -> None:
        import xacro

        self.names = names
        self.fallback = fallback
        self.tick = tick
        self.namespace_type: type[Any] = xacro.NameSpace
        self.yaml_dict_type: type[Any] = xacro.YamlDictWrapper

    def eval(self, node: ast.AST) -> Any:
        if self.tick is not None:
            self.tick()
        name = type(node).__name__
        if name not in _VISITED:
            raise RefusalError(_NODE_NAMES.get(name, f"the construct {name}"))
        return getattr(self, f"_{name.lower()}")(node)

    def _constant(self, node: ast.Constant) -> Any:
        if not isinstance(node.value, _CONSTANT_TYPES):
            raise RefusalError(f"the constant {node.value!r}")
        return node.value

    def _name(self, node: ast.Name) -> Any:
        name = node.id
        if name.startswith("__"):
            raise RefusalError(f"the name {name!r}")
        try:
            return self.names[name]
        except KeyError:
            pass
        try:
            return self.fallback[name]
        except KeyError:
            pass
        if name in vars(builtins):
            raise RefusalError(f"the Python builtin {name!r}")
        raise NameError(f"name '{name}' is not defined")

    def _attribute(self, node: ast.Attribute) -> Any:
        owner = self.eval(node.value)
        name = node.attr
        if name.startswith("_"):
            raise RefusalError(f"the attribute {name!r}")
        if isinstance(owner, self.namespace_type):
            try:
                return owner[name]
            except KeyError:
                if name in vars(builtins):
                    raise RefusalError(f"the Python builtin {name!r}") from None
                raise NameError(f"name '{name}' is not defined") from None
        if isinstance(owner, self.yaml_dict_type) and name in owner:
            return owner[name]
        if name in _methods_of(owner):
            return _Method(owner, name)
        if isinstance(owner, self.yaml_dict_type):
            raise AttributeError(f"The yaml dictionary has no key '{name}'")
        raise RefusalError(f"the attribute {name!r} of a value of type {type(owner).__name__}")

    def _subscript(self, node: ast.Subscript) -> Any:
        owner = self.eval(node.value)
        index = self.eval(node.slice)
        if not isinstance(owner, (str, list, tuple, dict, range)):
            raise RefusalError(f"indexing a {type(owner).__name__}")
        return owner[index]

    def _slice(self, node: ast.Slice) -> slice:
        parts = (node.lower, node.upper, node.step)
        return slice(*(None if part is None else self.eval(part) for part in parts))

    def _binop(self, node: ast.BinOp) -> Any:
        kind = type(node.op)
        function = _BINARY.get(kind)
        if function is None:
            raise RefusalError(f"the operator {kind.__name__}")
        left, right = self.eval(node.left), self.eval(node.right)
        check_binary(kind, left, right)
        return check_size(function(left, right))

    def _unaryop(self, node: ast.UnaryOp) -> Any:
        return _UNARY[type(node.op)](self.eval(node.operand))

    def _boolop(self, node: ast.BoolOp) -> Any:
        value: Any = None
        for operand in node.values:
            value = self.eval(operand)
            if bool(value) is isinstance(node.op, ast.Or):
                return value
        return value

    def _compare(self, node: ast.Compare) -> bool:
        left = self.eval(node.left)
        for op, comparator in zip(node.ops, node.comparators, strict=True):
            right = self.eval(comparator)
            if not _COMPARE[type(op)](left, right):
                return False
            left = right
        return True

    def _ifexp(self, node: ast.IfExp) -> Any:
        return self.eval(node.body) if self.eval(node.test) else self.eval(node.orelse)

    def _elements(self, nodes: list[ast.expr]) -> list[Any]:
        if any(isinstance(n, ast.Starred) for n in nodes):
            raise RefusalError("unpacking (*)")
        return check_size([self.eval(n) for n in nodes])

    def _list(self, node: ast.List) -> list[Any]:
        return self._elements(node.elts)

    def _tuple(self, node: ast.Tuple) -> tuple[Any, ...]:
        return tuple(self._elements(node.elts))

    def _set(self, node: ast.Set) -> set[Any]:
        return set(self._elements(node.elts))

    def _dict(self, node: ast.Dict) -> dict[Any, Any]:
        if any(key is None for key in node.keys):
            raise RefusalError("unpacking (**)")
        keys = self._elements([key for key in node.keys if key is not None])
        return check_size(dict(zip(keys, self._elements(node.values), strict=True)))

    def _joinedstr(self, node: ast.JoinedStr) -> str:
        return check_size("".join(str(self.eval(part)) for part in node.values))

    def _formattedvalue(self, node: ast.FormattedValue) -> str:
        value = self.eval(node.value)
        if node.conversion == ord("r"):
            value = repr(value)
        elif node.conversion == ord("s"):
            value = str(value)
        elif node.conversion == ord("a"):
            value = ascii(value)
        spec = "" if node.format_spec is None else str(self.eval(node.format_spec))
        if any(int(d) > MAX_FORMAT_WIDTH for d in re.findall(r"\d+", spec)):
            raise RefusalError(f"a format field wider than {MAX_FORMAT_WIDTH}")
        return format(value, spec)

    def _call(self, node: ast.Call) -> Any:
        function = self.eval(node.func)
        if not isinstance(function, (SafeFunction, _Method)):
            raise RefusalError(f"calling {_describe(function)}")
        if any(isinstance(a, ast.Starred) for a in node.args) or any(
            k.arg is None for k in node.keywords
        ):
            raise RefusalError("unpacking (* or **) in a call")
        args = [self.eval(a) for a in node.args]
        kwargs = {str(k.arg): self.eval(k.value) for k in node.keywords}
        return check_size(function(*args, **kwargs))


def _describe(value: Any) -> str:
    name = getattr(value, "__name__", None)
    if isinstance(name, str) and callable(value):
        return f"{name!r}"
    return f"a {type(value).__name__}"


def _refusal(expression: str, reason: str) -> RefusedExpressionError:
    shown = expression if len(expression) <= 80 else expression[:77] + "..."
    return RefusedExpressionError(
        f"expression {shown!r} refused in an untrusted description: it uses {reason}; {TRUST_HINT}"
    )


def safe_eval(
    expression: str, names: Mapping[str, Any], *, tick: Callable[[], None] | None = None
) -> Any:
    """Evaluate a xacro expression without running arbitrary Python.

    Known are literals (numbers, strings, booleans, None, lists, tuples, dicts, sets),
    arithmetic, comparison and boolean operators, conditional expressions, subscripts and slices,
    f-strings and ``%`` formatting, calls of the functions xacro documents (``pi``, ``sin``,
    ``sqrt``, ``radians``, ``min``, ``len``, ``range``, ... also under ``math.`` and
    ``python.``), ``xacro.load_yaml`` where :func:`sandboxed` provides it, the keys of YAML data
    and namespaces as attributes (``left.wheel_radius``, ``props.a.b``), and a few methods of
    strings, lists and dicts (``split``, ``get``, ...). Names starting with ``__``, attributes
    starting with ``_``, lambdas, comprehensions and any other call are refused.

    Args:
        expression: the text inside ``${...}`` or ``$(eval ...)``.
        names: the properties in scope; names not found there come from the sandbox's own table.
        tick: called before each step of the evaluation; it may raise to end it (an
            expansion's time budget).

    Returns:
        The value, typed as Python's ``eval`` would give it.

    Raises:
        RefusedExpressionError: the expression uses something outside the sandbox, or its result
            (or a step towards it) would be an integer over :data:`MAX_INT_BITS` bits or a string
            or container over :data:`MAX_ITEMS` characters or items.
        SyntaxError, NameError, TypeError, ZeroDivisionError, ...: as Python's ``eval`` would.
    """
    text = expression.strip()
    if len(text) > MAX_EXPRESSION:
        raise _refusal(text, f"more than {MAX_EXPRESSION} characters")
    try:
        tree = ast.parse(text, mode="eval")
        return _Evaluator(names, _defaultsymbols(), tick).eval(tree.body)
    except RefusalError as err:
        raise _refusal(text, str(err)) from None
    except (RecursionError, MemoryError):
        raise _refusal(text, "nesting too deep to evaluate") from None


# --- the table of names expressions may use ------------------------------------------------------

_MATH_EXCLUDED = frozenset({"comb", "factorial", "perm", "prod"})
_BUILTINS: dict[str, Any] = {
    "abs": abs,
    "all": all,
    "any": any,
    "bool": bool,
    "chr": chr,
    "dict": dict,
    "divmod": divmod,
    "enumerate": enumerate,
    "float": float,
    "frozenset": frozenset,
    "int": int,
    "len": len,
    "list": list,
    "max": max,
    "min": min,
    "ord": ord,
    "repr": repr,
    "reversed": reversed,
    "round": round,
    "set": set,
    "sorted": sorted,
    "str": str,
    "tuple": tuple,
    "zip": zip,
}
#: Builtins xacro puts at top level (the others only under ``python.``).
_TOP_LEVEL_BUILTINS = frozenset(
    {
        "list",
        "dict",
        "len",
        "str",
        "float",
        "int",
        "bool",
        "min",
        "max",
        "round",
        "sorted",
        "abs",
        "tuple",
        "range",
    }
)
_XACRO_FUNCTIONS: tuple[str, ...] = ("abs_filename", "arg", "dotify", "error", "fatal", "message")
_XACRO_FUNCTIONS += ("print_location", "tokenize", "warning")


def _range(*args: int) -> range:
    result = range(*args)
    if len(result) > MAX_ITEMS:
        raise RefusalError(f"a range of more than {MAX_ITEMS} items")
    return result


def _sum(items: Any, start: Any = 0) -> Any:
    """``sum`` in time linear in its result: lists and tuples are joined once, where Python's
    ``sum`` copies the whole result at each item (``sum([[1]] * n, [])`` takes n² steps)."""
    if not isinstance(start, (list, tuple)):
        return sum(items, start)
    joined = list(start)
    for item in items:
        if not isinstance(item, type(start)):
            kind = type(start).__name__
            raise TypeError(f'can only concatenate {kind} (not "{type(item).__name__}") to {kind}')
        joined.extend(item)
        if len(joined) > MAX_ITEMS:
            raise RefusalError(f"a sum of more than {MAX_ITEMS} items")
    return joined if isinstance(start, list) else tuple(joined)


def _round(number: Any, ndigits: Any = None) -> Any:
    # round(5, -10**9) would compute 10**(10**9) first
    if isinstance(ndigits, int) and abs(ndigits) > MAX_FORMAT_WIDTH:
        raise RefusalError(f"rounding to more than {MAX_FORMAT_WIDTH} digits")
    return round(number, ndigits)


def _pow(base: Any, exponent: Any, modulus: Any = None) -> Any:
    if modulus is None:
        check_power(base, exponent)
        return pow(base, exponent)
    return pow(base, exponent, modulus)


def _tokenize(text: Any, sep: Any = ",; ", skip_empty: bool = True) -> list[str]:
    """``xacro.tokenize`` without a regular expression made of its argument: ``text`` cut at
    every character of ``sep``, empty pieces dropped unless ``skip_empty`` is false.

    xacro builds the pattern ``[SEP]`` from the text it is given, so a crafted ``sep`` closes
    the class and backtracks exponentially; here every character of ``sep`` is one separator
    (a ``-`` too: no ranges), in time linear in ``text``.
    """
    text, sep = str(text), str(sep)
    parts = [text]
    if sep:
        parts = text.translate(dict.fromkeys(map(ord, sep), sep[0])).split(sep[0])
    return [part for part in parts if part] if skip_empty else parts


def _refused_load_yaml(filename: str) -> Any:
    raise RefusalError("xacro.load_yaml outside an expansion (no folders to read from)")


def _namespace(entries: Mapping[str, Any]) -> Any:
    import xacro

    space = xacro.NameSpace()
    dict.update(space, entries)
    return space


def symbols(load_yaml: Callable[[str], Any]) -> dict[str, Any]:
    """The sandbox's global names: safe math, builtins, and xacro's own helpers."""
    import xacro

    def safe(name: str, function: Any) -> Any:
        return SafeFunction(name, function) if callable(function) else function

    maths = {
        k: safe(k, v)
        for k, v in vars(math).items()
        if not k.startswith("_") and k not in _MATH_EXCLUDED
    }
    maths["pow"] = SafeFunction("pow", math.pow)
    python = {k: safe(k, v) for k, v in _BUILTINS.items()}
    python.update(
        range=SafeFunction("range", _range),
        pow=SafeFunction("pow", _pow),
        round=SafeFunction("round", _round),
        sum=SafeFunction("sum", _sum),
    )
    booleans = {"True": True, "False": False}
    original = xacro.create_global_symbols()["xacro"]
    helpers = {k: safe(k, original[k]) for k in _XACRO_FUNCTIONS if k in original}
    helpers["tokenize"] = SafeFunction("tokenize", _tokenize)
    helpers["load_yaml"] = SafeFunction("load_yaml", load_yaml)

    table: dict[str, Any] = dict(maths)
    table.update({k: python[k] for k in _TOP_LEVEL_BUILTINS})
    table.update(booleans)
    table["load_yaml"] = helpers["load_yaml"]
    table["math"] = _namespace(maths)
    table["python"] = _namespace({**python, **booleans})
    table["xacro"] = _namespace(helpers)
    return table


_DEFAULT_SYMBOLS: dict[str, Any] = {}


def _defaultsymbols() -> dict[str, Any]:
    if not _DEFAULT_SYMBOLS:
        _DEFAULT_SYMBOLS.update(symbols(_refused_load_yaml))
    return _DEFAULT_SYMBOLS
