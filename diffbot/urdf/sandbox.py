"""Expand xacro descriptions bounded, and untrusted ones in a sandbox.

Unless the description is trusted, expressions are evaluated by
:func:`diffbot.urdf.expressions.safe_eval`, and files (includes, ``xacro.load_yaml``) are read
only inside the description's folder tree and the folders of the packages ``$(find PKG)``
resolved; ``$(env)``, ``$(optenv)``, ``$(arg)``, ``$(find)`` and ``$(dirname)`` work as usual.

Trusted or not, the expansion is bounded: in total text produced (``max_bytes``), elements
processed (``max_elements``), macro or include nesting (``max_depth``) and CPU time
(``max_seconds``), so a macro that doubles itself fails within a fraction of a second instead
of running for hours, and so does a costly expression evaluated over and over. Every file the
expansion reads is recorded (:class:`Reads`), so outputs can be kept off all of them.

xacro keeps its state in module globals, so :func:`sandboxed` patches them while holding
:data:`XACRO_LOCK`, and expansions are serialised.
"""

from __future__ import annotations

import contextlib
import os
import re
import threading
import time
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from types import SimpleNamespace
from typing import Any

from diffbot.errors import DescriptionError, ExpansionLimitError, OutsideRootsError, XacroError
from diffbot.formats.text import one_line
from diffbot.io.pathnames import resolved
from diffbot.io.textfile import check_regular
from diffbot.numbers import flag
from diffbot.urdf.expression_limits import weight, yaml_weight
from diffbot.urdf.expressions import SafeFunction, safe_eval, symbols
from diffbot.urdf.include_glob import include_files

__all__ = [
    "MAX_BYTES",
    "MAX_DEPTH",
    "MAX_ELEMENTS",
    "MAX_SECONDS",
    "XACRO_LOCK",
    "Reads",
    "description_roots",
    "inside_folders",
    "process",
    "sandboxed",
]

#: Most text (characters) one expansion may produce, counted over every evaluated text.
MAX_BYTES = 50_000_000
#: Deepest nesting of macro calls, and of included files.
MAX_DEPTH = 64
#: Most elements one expansion may process (each macro body and inserted block counts again).
#: xacro takes about 50 us per element, so this bounds an expansion to about half a second; the
#: bundled robot processes 136.
MAX_ELEMENTS = 10_000

#: Most CPU time one expansion may take (s), checked at each element and, untrusted, at each
#: step of an expression: the largest real descriptions expand in about a second; sizes alone
#: do not bound time (a million-item sort is allowed, and may be asked for ten thousand times).
MAX_SECONDS = 10.0

#: Held while xacro's module globals are patched; reentrant so callers can hold it around us.
XACRO_LOCK = threading.RLock()

# --- files ---------------------------------------------------------------------------------------


def description_roots(path: str | os.PathLike[str]) -> tuple[Path, ...]:
    """The folders an untrusted description may read: its own, and its ROS package's.

    A description usually sits in ``urdf/`` of a package and reads ``../config/*.yaml``, so the
    nearest folder at most two levels up holding a ``package.xml`` counts too.

    A description that is a link (as ``colcon build --symlink-install`` installs one) has both:
    those of the folder it is named in, and those of the file it links to.

    Args:
        path: the description file, or its folder (an SDF model folder).

    Returns:
        The folders, symbolic links resolved.
    """
    roots: list[Path] = []
    for named in (Path(os.path.abspath(path)), resolved(path, DescriptionError)):
        folder = named if named.is_dir() else named.parent
        folder = resolved(folder, DescriptionError)
        found = [folder]
        for parent in list(folder.parents)[:2]:
            if (parent / "package.xml").is_file() and parent != Path(parent.anchor):
                found.append(parent)
                break
        roots += [f for f in found if f not in roots]
    return tuple(roots)


def inside_folders(path: str | os.PathLike[str], folders: Iterable[Path]) -> bool:
    """Whether ``path``, symbolic links resolved, is one of ``folders`` (resolved) or lies
    inside one."""
    real = resolved(path, DescriptionError)
    real_folders = [resolved(f, DescriptionError) for f in folders]
    return any(real == f or f in real.parents for f in real_folders)


def check_inside(
    path: str | os.PathLike[str], folders: Sequence[Path], what: str, reader: str
) -> None:
    """Refuse ``path`` unless it lies inside one of ``folders`` (links resolved).

    Args:
        path: the file about to be read.
        folders: the description's folders.
        what: the refused action, for the message ("reading", "the include").
        reader: what would read it, for the message ("xacro").

    Raises:
        OutsideRootsError: ``path`` is outside every folder.
    """
    if inside_folders(path, folders):
        return
    shown = ", ".join(str(f) for f in folders)
    raise OutsideRootsError(
        f"{os.fspath(path)}: {what} refused in an untrusted description: it is outside the "
        f"description's folders ({shown}); trust the description ({{trust}}) to let {reader} "
        "read any file"
    )


class _Roots:
    """The folders files may be read from; ``$(find PKG)`` adds the folders it resolves."""

    def __init__(self, roots: Iterable[str | os.PathLike[str]]) -> None:
        self.folders: list[Path] = []
        for root in roots:
            self.add(root)

    def add(self, root: str | os.PathLike[str]) -> None:
        folder = resolved(root, DescriptionError)
        if folder not in self.folders:
            self.folders.append(folder)

    def check(self, filename: str, what: str) -> None:
        check_inside(filename, self.folders, what, "xacro")


# --- xacro patched ------------------------------------------------------------------------------


def _replace_node(node: Any, by: Any, content_only: bool = False) -> None:
    """xacro's ``replace_node`` in one splice of the parent's children.

    minidom's ``insertBefore`` looks the reference node up in the parent's children on every
    call, so xacro's node-by-node insertion costs time quadratic in the number of siblings: a
    few thousand macro calls in one element took a minute. Splicing once keeps it linear per call.
    """
    parent = node.parentNode
    sources = [] if by is None else by if isinstance(by, list) else [by]
    moved: list[Any] = []
    for source in sources:
        if content_only:
            moved.extend(source.childNodes)
            source.childNodes[:] = []
        else:
            if source.parentNode is not None:
                source.parentNode.removeChild(source)
            moved.append(source)
    siblings = parent.childNodes
    at = siblings.index(node)
    siblings[at : at + 1] = moved
    node.parentNode = node.previousSibling = node.nextSibling = None
    first = max(at - 1, 0)
    last = min(at + len(moved) + 1, len(siblings))
    for index in range(first, last):
        child = siblings[index]
        child.parentNode = parent
        child.previousSibling = siblings[index - 1] if index > 0 else None
        child.nextSibling = siblings[index + 1] if index + 1 < len(siblings) else None


@dataclass
class _Budget:
    """What one expansion has used so far, against its limits."""

    source: str
    max_bytes: int
    max_depth: int
    max_elements: int
    max_seconds: float
    bytes: int = 0
    elements: int = 0
    # The CPU time of this thread: what other threads and processes do does not count.
    deadline: float = field(init=False)

    def __post_init__(self) -> None:
        self.deadline = time.thread_time() + self.max_seconds

    def spend_time(self) -> None:
        if time.thread_time() > self.deadline:
            raise ExpansionLimitError(
                f"{self.source}: expansion refused: it takes more than {self.max_seconds:g} s "
                "of CPU time (max_seconds); a costly expression may be evaluated over and over"
            )

    def spend_bytes(self, count: int) -> None:
        self.bytes += count
        if self.bytes > self.max_bytes:
            raise ExpansionLimitError(
                f"{self.source}: expansion refused: it produces more than {self.max_bytes} "
                "characters of text (max_bytes)"
            )

    def spend_element(self) -> None:
        self.spend_time()
        self.elements += 1
        if self.elements > self.max_elements:
            raise ExpansionLimitError(
                f"{self.source}: expansion refused: it processes more than {self.max_elements} "
                "elements (max_elements); a macro may be calling itself over and over"
            )

    def check_depth(self, depth: int, what: str) -> None:
        if depth > self.max_depth:
            raise ExpansionLimitError(
                f"{self.source}: expansion refused: {what} nested more than {self.max_depth} "
                "deep (max_depth)"
            )


class _EvalNames(Mapping[str, Any]):
    """The names of ``$(eval ...)``: its functions, then the xacro arguments, typed."""

    def __init__(self, functions: Mapping[str, Any], args: Mapping[str, str]) -> None:
        self.functions = functions
        self.args = args

    def __getitem__(self, key: str) -> Any:
        if key in self.functions:
            return self.functions[key]
        import xacro.substitution_args as subst

        return subst.convert_value(self.args[key], "auto")

    def __iter__(self) -> Iterator[str]:
        return iter({**self.functions, **self.args})

    def __len__(self) -> int:
        return len({**self.functions, **self.args})


@contextlib.contextmanager
def sandboxed(
    path: str | os.PathLike[str],
    *,
    roots: Iterable[str | os.PathLike[str]] = (),
    find: Callable[[str], str] | None = None,
    trust: bool = False,
    max_bytes: int = MAX_BYTES,
    max_depth: int = MAX_DEPTH,
    max_elements: int = MAX_ELEMENTS,
    max_seconds: float = MAX_SECONDS,
    folders: list[Path] | None = None,
    shown: Callable[[str], str] = str,
) -> Iterator[list[Path]]:
    """Patch xacro so that the expansion of ``path`` run inside is sandboxed and bounded.

    Holds :data:`XACRO_LOCK` throughout; xacro is restored on exit. Run ``xacro.process_file``
    (or ``xacro.process_doc``) inside, once.

    Args:
        path: the description to expand; its folders (:func:`description_roots`) may be read.
        roots: further folders that may be read (package folders known beforehand).
        find: resolves ``$(find PKG)`` to a folder, which may then be read too; None keeps the
            resolver xacro has when entering.
        trust: run xacro as it is (full Python, any file); the size limits still hold.
        max_bytes: most characters of text evaluated in the whole expansion.
        max_depth: deepest nesting of macro calls and of included files.
        max_elements: most elements processed (macro bodies and blocks count each time).
        max_seconds: most CPU time of the expansion (s), checked between elements and, when
            untrusted, between the steps of an expression.
        folders: a list that receives, on exit, the folders the description may read (its own,
            its package's, ``roots`` and the packages ``$(find PKG)`` resolved), so that files
            its text names (a controllers file) can be held to the same sandbox.
        shown: how a path is written in a message (as the user gave it).

    Yields:
        The files the expansion reads (included files and YAML data, not ``path`` itself), filled
        in as it runs; expand inside the ``with`` block.
    """
    import xacro
    import xacro.substitution_args as subst

    trust = flag(trust, "trust")
    with XACRO_LOCK:
        allowed = _Roots([*description_roots(path), *roots])
        budget = _Budget(os.fspath(path), max_bytes, max_depth, max_elements, max_seconds)
        read: list[Path] = []
        resolve = find if find is not None else subst._eval_find
        located: dict[str, str] = {}

        def tracking_find(package: str) -> str:
            folder = resolve(package)
            allowed.add(folder)
            located[package] = folder
            return folder

        def load_yaml(filename: str) -> Any:
            # Absolute before it is checked: xacro.load_yaml joins a relative name to the
            # including file's folder again, and would read another file than the one checked.
            name = os.path.abspath(xacro.abs_filename_spec(filename))
            allowed.check(name, "xacro.load_yaml")
            if not os.path.lexists(name) and xacro.filestack:
                _missing_include(name, xacro.filestack[-1], located, shown, "loads")
            check_regular(name, DescriptionError, "a YAML file")
            read.append(Path(name))
            with contextlib.suppress(OSError):
                budget.spend_bytes(os.path.getsize(name))
            data = xacro.load_yaml(name)
            budget.spend_bytes(yaml_weight(data, {}, max_bytes))
            return data

        table = symbols(load_yaml)

        def evaluate(text: str, names: Any) -> Any:
            budget.spend_time()
            if trust:
                return xacro.safe_eval(text, names)
            return safe_eval(text, names, tick=budget.spend_time)

        def eval_text(text: str, names: Any) -> Any:
            lexer = xacro.QuickLexer(xacro.LEXER)
            lexer.lex(text)
            pieces: list[Any] = []
            while lexer.peek():
                kind, token = lexer.next()
                if kind == lexer.EXPR:
                    expression = token[2:-1]
                    try:
                        piece = evaluate(eval_text(expression, names), names)
                    except Exception as err:  # xacro reports any failure with the expression
                        raise xacro.XacroException(
                            exc=err, suffix=f"{os.linesep}when evaluating expression '{expression}'"
                        ) from err
                elif kind == lexer.EXTENSION:
                    piece = xacro.eval_extension(f"$({eval_text(token[2:-1], names)})")
                elif kind == lexer.DOLLAR_DOLLAR_BRACE:
                    piece = token[1:]
                else:
                    piece = token
                budget.spend_bytes(weight(piece, max_bytes))
                pieces.append(piece)
            return pieces[0] if len(pieces) == 1 else "".join(map(str, pieces))

        def eval_all(node: Any, macros: Any, names: Any) -> None:
            budget.spend_element()
            saved["eval_all"](node, macros, names)

        def handle_macro_call(node: Any, macros: Any, names: Any) -> bool:
            budget.check_depth(len(xacro.macrostack or ()) + 1, "macro calls")
            return bool(saved["handle_macro_call"](node, macros, names))

        def parse(source: Any, filename: str | None = None) -> Any:
            if source is None and filename is not None:
                budget.check_depth(len(xacro.filestack or ()), "included files")
                included = os.path.join(xacro.root_dir, filename)
                if not trust:
                    allowed.check(included, "reading")
                if not os.path.lexists(included) and len(xacro.filestack or ()) > 1:
                    _missing_include(included, xacro.filestack[-2], located, shown)
                check_regular(included, DescriptionError, "a xacro file")
                read.append(Path(included))
                document = saved["parse"](source, filename)
                _mark_origin(document, resolved(included, DescriptionError).parent)
                return document
            return saved["parse"](source, filename)

        def list_includes(pattern: str) -> list[str]:
            def check(folder: str) -> None:
                allowed.check(os.path.join(xacro.root_dir, folder), "listing")

            return include_files(pattern, check)

        def subst_eval(text: str, context: dict[str, Any]) -> str:
            args = context.setdefault("arg", {})
            functions: dict[str, Any] = {
                k: v for k, v in table.items() if k not in ("python", "xacro", "load_yaml")
            }
            functions.update(
                arg=SafeFunction("arg", lambda n: subst.convert_value(args[n], "auto")),
                dirname=SafeFunction("dirname", lambda: subst._eval_dirname(context["filename"])),
                env=SafeFunction("env", subst._eval_env),
                optenv=SafeFunction("optenv", subst._eval_optenv),
                find=SafeFunction("find", tracking_find),
                true=True,
                false=False,
            )
            return str(safe_eval(text, _EvalNames(functions, args), tick=budget.spend_time))

        def eval_extension(text: str) -> Any:
            # $(dirname) is the folder of the file being read, as ROS's xacro passes it
            # (the PyPI release passes no file, and cannot substitute it)
            context = xacro.substitution_args_context
            context["filename"] = xacro.filestack[-1] if xacro.filestack else None
            return saved["eval_extension"](text)

        # What xacro is given in place of its own, by name; what it had is put back on exit.
        patches: dict[str, Any] = {
            "eval_text": eval_text,
            "eval_all": eval_all,
            "handle_macro_call": handle_macro_call,
            "parse": parse,
            "replace_node": _replace_node,
            "eval_extension": eval_extension,
            "all_includes": [],
        }
        if not trust:
            patches.update(
                glob=SimpleNamespace(glob=list_includes),
                safe_eval=safe_eval,
                _global_symbols=table,
            )
        saved: dict[str, Any] = {name: getattr(xacro, name) for name in patches}
        saved.update(
            subst_eval=subst._eval,
            eval_find=subst._eval_find,
            dict_find=subst._eval_dict.get("find"),
        )
        try:
            for name, patched in patches.items():
                setattr(xacro, name, patched)
            subst._eval_find = tracking_find
            subst._eval_dict["find"] = tracking_find
            if not trust:
                subst._eval = subst_eval
            yield read
        finally:
            if folders is not None:
                folders.extend(allowed.folders)
            for name in patches:
                setattr(xacro, name, saved[name])
            subst._eval = saved["subst_eval"]
            subst._eval_find = saved["eval_find"]
            if saved["dict_find"] is not None:
                subst._eval_dict["find"] = saved["dict_find"]


def _missing_include(
    included: str,
    including: str,
    located: Mapping[str, str],
    shown: Callable[[str], str],
    verb: str = "includes",
) -> None:
    """Raise the error of an included (or loaded) file that does not exist below a package
    ``$(find PKG)`` gave: it names the including file, the ``$(find)`` and the option that would
    fix it."""
    target = Path(os.path.abspath(included))
    for package, folder in located.items():
        base = Path(os.path.abspath(folder))
        if base in target.parents:
            rest = target.relative_to(base).as_posix()
            raise DescriptionError(
                f"{shown(including)} {verb} $(find {package})/{rest}, but {shown(included)} "
                f"does not exist (package {package} is at {shown(folder)}): if {package} "
                f"is elsewhere, give the folder holding its package.xml with {{packages}} "
                f"{package}=DIR",
                path=included,
                package=package,
            )


def _diffbot_cause(err: BaseException) -> BaseException | None:
    """The first diffbot error in a chain of xacro's wrapped exceptions."""
    seen: set[int] = set()
    current: BaseException | None = err
    while current is not None and id(current) not in seen:
        if isinstance(current, DescriptionError):
            return current
        seen.add(id(current))
        current = getattr(current, "exc", None) or current.__cause__
    return None


def _xacro_message(err: BaseException, filestack: list[Any] | None) -> str:
    location = ""
    files = [str(f) for f in filestack or () if f]
    if files:
        location = f" (in {files[-1]})"
    return one_line(f"xacro: {err}{location}")


#: The attribute that carries, through the expansion, the folder of the included file that
#: wrote a ``<parameters>`` element; taken out before the URDF text is made.
NAMED_FROM = "diffbot-named-from"


def _mark_origin(document: Any, folder: Path) -> None:
    """Tag the ``<parameters>`` elements of an included file with its folder (written so that
    xacro, which evaluates attributes, gives it back as it is)."""
    escaped = re.sub(r"(?<!\$)\$+(?=[{(])", lambda match: "$" + match.group(0), str(folder))
    for element in document.getElementsByTagName("parameters"):
        element.setAttribute(NAMED_FROM, escaped)


def _take_origins(document: Any) -> dict[str, Path]:
    """The folders of the included files that wrote ``<parameters>`` elements, by their
    (expanded, stripped) text; the tags are removed."""
    origins: dict[str, Path] = {}
    for element in document.getElementsByTagName("parameters"):
        if element.hasAttribute(NAMED_FROM):
            folder = element.getAttribute(NAMED_FROM)
            element.removeAttribute(NAMED_FROM)
            text = "".join(
                node.data for node in element.childNodes if node.nodeType == node.TEXT_NODE
            )
            origins.setdefault(text.strip(), Path(folder))
    return origins


@dataclass
class Reads:
    """What an expansion read, for the files its text names and the outputs kept off them.

    Attributes:
        files: the files read: the description, included files, YAML data.
        folders: the folders the description may read (:func:`sandboxed`'s ``folders``).
        named_from: for each ``<parameters>`` text an included file wrote, that file's folder
            (where a relative name in it starts from).
    """

    files: list[Path] = field(default_factory=list)
    folders: list[Path] = field(default_factory=list)
    named_from: dict[str, Path] = field(default_factory=dict)


def process(
    path: str | os.PathLike[str],
    mappings: Mapping[str, str] | None = None,
    *,
    reads: Reads | None = None,
    **options: Any,
) -> str:
    """Expand a xacro description in the sandbox.

    Args:
        path: the .xacro file.
        mappings: xacro arguments (``NAME:=VALUE``).
        reads: a record that receives what the expansion read, even when it fails.
        **options: the other keywords of :func:`sandboxed` (``roots``, ``find``, ``trust``,
            ``max_bytes``, ``max_depth``, ``max_elements``, ``max_seconds``, ``shown``).

    Returns:
        The expanded URDF text.

    Raises:
        RefusedExpressionError: an expression uses something outside the sandbox.
        OutsideRootsError: the description reads a file outside its folders.
        ExpansionLimitError: the expansion goes over a limit.
        PackageNotFoundError: ``find`` does not know a package.
        DescriptionError: a file is malformed XML or not a regular file.
        XacroError: xacro failed for another reason (message prefixed ``xacro:``).
    """
    import xml.parsers.expat

    import xacro

    mappings = {} if mappings is None else mappings
    try:
        folders = None if reads is None else reads.folders
        with sandboxed(path, folders=folders, **options) as read:
            try:
                document = xacro.process_file(os.fspath(path), mappings=mappings)
                origins = _take_origins(document)
                if reads is not None:
                    reads.named_from.update(origins)
                return str(document.toprettyxml(indent="  "))
            finally:
                if reads is not None:
                    # xacro lists what it includes and loads; trusted, it loads YAML unwatched
                    listed = [Path(os.path.abspath(name)) for name in xacro.all_includes]
                    reads.files.extend(dict.fromkeys([*read, *listed]))
    except RecursionError:
        raise ExpansionLimitError(
            f"{os.fspath(path)}: expansion refused: nesting too deep for Python (max_depth)"
        ) from None
    except xml.parsers.expat.ExpatError as err:
        where = xacro.filestack[-1] if xacro.filestack else os.fspath(path)
        raise DescriptionError(f"{where}: malformed XML: {err}") from None
    except Exception as err:  # xacro lets Python errors of bad expressions escape
        cause = _diffbot_cause(err)
        if cause is not None:
            raise cause from None
        raise XacroError(_xacro_message(err, xacro.filestack)) from None
