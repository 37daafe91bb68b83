"""The promises every command keeps by one mechanism, checked over every command and subcommand,
so that a new command, option or reader that bypasses them fails here:

- every option or argument that names a file or folder is of a path type, which notes it for the
  input/output guard as click parses it;
- every output option is the output type, written through :mod:`diffbot.io.outputs`;
- every option naming a file a command writes a changed copy of is the edited type;
- no path option takes a name that stands for no file or folder of its own: an empty name, and
  for an output or an edited file ``.``, ``/`` or a name ending in ``/.``, refused as click
  parses it by the one check of :mod:`diffbot.io.outputs`;
- every numeric option is of a checked number type (finite, in range, integers of sane size);
- every file is read through :mod:`diffbot.io.textfile` (or one of the few binary readers named
  here, each with its reason).
"""

from __future__ import annotations

import ast
import shutil
from pathlib import Path

import click
import pytest
from cli_results import assert_one_error_line
from click.testing import CliRunner
from robots import two_wheel_urdf

import diffbot
from diffbot import cli
from diffbot.commands.options import ARGUMENTS, CheckedNumber
from diffbot.commands.paths import OUTPUT_NAMES, EditedPath, InputPath, OutputPath, PackageDir

EXAMPLES = Path(diffbot.__file__).parent.parent / "docs" / "examples"


def every_command() -> list[tuple[str, click.Command]]:
    """Every command a user can run, subcommands of groups included, by its full name."""
    found: list[tuple[str, click.Command]] = []

    def walk(group: click.Group, prefix: str) -> None:
        ctx = click.Context(group)
        for name in group.list_commands(ctx):
            command = group.get_command(ctx, name)
            assert command is not None, name
            if isinstance(command, click.Group):
                walk(command, f"{prefix}{name} ")
            else:
                found.append((f"{prefix}{name}", command))

    walk(cli.main, "")
    return found


COMMANDS = every_command()
BY_NAME = [pytest.param(command, id=name) for name, command in COMMANDS]

#: Metavars of values that name a file or a folder.
PATH_METAVARS = {"FILE", "DIR", "PATH", "INPUT", "ROBOT", "NAME=DIR"}
#: Metavars of numeric values.
NUMBER_METAVARS = {"N", "M", "S", "HZ", "RPM", "STD", "SECONDS", "FRACTION", "L,R", "X,Y"}
#: Values holding numbers that are text to the command line and numbers to the library, which
#: checks them with diffbot.numbers where it parses them (poses, a time offset or "auto").
PARSED_LATER = {"--to", "--from", "--time-offset"}
#: Options naming a file a command reads to write a changed copy of it (named after it).
EDITED = {"--apply-to"}


def test_every_command_is_walked() -> None:
    names = {name for name, _ in COMMANDS}
    assert {*cli.COMMANDS} - {"explain", "calibrate", "node"} <= names
    assert {"explain ik", "calibrate fit", "calibrate umbmark", "node robot"} <= names


@pytest.mark.parametrize("command", BY_NAME)
def test_every_path_is_of_a_path_type(command: click.Command) -> None:
    for param in command.params:
        metavar = (param.metavar or "").strip("[]")
        if param.name == ARGUMENTS and param.nargs == -1:
            # words that may be a plan, numbers or a path: the command takes a path through
            # diffbot.commands.paths.input_path (checked by the refusals below)
            continue
        if metavar in PATH_METAVARS or isinstance(param.type, click.Path):
            assert isinstance(param.type, (InputPath, PackageDir, OutputPath)), param.opts


@pytest.mark.parametrize("command", BY_NAME)
def test_every_output_is_of_the_output_type(command: click.Command) -> None:
    for param in command.params:
        is_output = any(name in OUTPUT_NAMES for name in param.opts)
        assert is_output == isinstance(param.type, OutputPath), param.opts
        if is_output:
            assert tuple(param.opts) == OUTPUT_NAMES


@pytest.mark.parametrize("command", BY_NAME)
def test_every_edited_file_is_of_the_edited_type(command: click.Command) -> None:
    for param in command.params:
        edited = any(name in EDITED for name in param.opts)
        assert edited == isinstance(param.type, EditedPath), param.opts


def path_params() -> list[object]:
    """(command, words before the value, what the value must name) of every path option and
    argument, found by metavar as well as by type so that one of another type is found too."""
    found: list[object] = []
    for name, command in COMMANDS:
        for param in command.params:
            metavar = (param.metavar or "").strip("[]")
            if param.name == ARGUMENTS and param.nargs == -1:
                continue  # words taken for a path through input_path (see the refusals below)
            path_type = isinstance(param.type, (click.Path, OutputPath, PackageDir))
            if not (metavar in PATH_METAVARS or path_type):
                continue
            option = [max(param.opts, key=len)] if isinstance(param, click.Option) else []
            kind = "input"
            if any(n in OUTPUT_NAMES for n in param.opts):
                kind = "output"
            elif any(n in EDITED for n in param.opts):
                kind = "edited"
            label = f"{name} {option[0] if option else param.name}"
            found.append(pytest.param(name.split(), option, kind, id=label))
    return found


#: Names that stand for no file or folder of its own.
NO_NAME = ["", " "]
FOLDERS = [".", "/", "sub/.", "sub/..", "./"]


@pytest.mark.parametrize(("words", "option", "kind"), path_params())
def test_no_path_takes_a_name_of_no_file_of_its_own(
    words: list[str],
    option: list[str],
    kind: str,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "sub").mkdir()
    refused = NO_NAME + (FOLDERS if kind != "input" else [])
    for value in refused:
        result = CliRunner().invoke(cli.main, [*words, *option, value])
        assert_one_error_line(result, *option[:1] if kind == "edited" else ())
        assert [p.name for p in tmp_path.iterdir()] == ["sub"], value
        assert list((tmp_path / "sub").iterdir()) == [], value


@pytest.mark.parametrize("command", BY_NAME)
def test_every_number_is_of_a_checked_type(command: click.Command) -> None:
    for param in command.params:
        numeric = isinstance(param.type, (click.types.FloatParamType, click.types.IntParamType))
        if numeric or (param.metavar or "") in NUMBER_METAVARS:
            assert isinstance(param.type, CheckedNumber), param.opts
        elif any(name in PARSED_LATER for name in param.opts):
            assert isinstance(param.type, click.types.StringParamType), param.opts


# --- every command that writes refuses to write over or inside its inputs ----------------------


@pytest.fixture
def inputs(tmp_path: Path) -> dict[str, str]:
    robot = tmp_path / "robot.urdf"
    robot.write_text(two_wheel_urdf(), encoding="utf-8")
    plan = tmp_path / "plan.txt"
    plan.write_text("straight 1\n", encoding="utf-8")
    joints = tmp_path / "joints.csv"
    shutil.copy(EXAMPLES / "joints.csv", joints)
    picture = tmp_path / "joints.png"  # a CSV under the name of the picture plot would write
    shutil.copy(EXAMPLES / "joints.csv", picture)
    paths = {"robot": robot, "plan": plan, "joints": joints, "picture": picture, "dir": tmp_path}
    return {name: str(path) for name, path in paths.items()}


#: Each command that writes, run with its inputs and an output over one of them.
REFUSALS = {
    "urdf": ("urdf {robot} -o {robot}", "is an input"),
    "plan": ("plan {plan} --robot {robot} -o {plan}", "plan file itself"),
    "simulate": ("simulate {robot} {plan} -o {robot}", "is the input"),
    "odom": ("odom {joints} -o {joints}", "is the input"),
    "plot": ("plot --odom {picture} -o {picture}", "is an input"),
    "calibrate umbmark": (
        "calibrate umbmark --side 1 --cw 0.1,0 --ccw -0.1,0 --apply-to {robot} -o {robot}",
        "is an input",
    ),
    "calibrate fit": ("calibrate fit {joints} --apply-to {robot} -o {joints}", "is an input"),
}


def test_every_command_that_writes_is_checked_below() -> None:
    writing = {
        name
        for name, command in COMMANDS
        if any(isinstance(p.type, OutputPath) for p in command.params)
    }
    assert writing == set(REFUSALS)


@pytest.mark.parametrize("name", sorted(REFUSALS))
def test_every_command_that_writes_refuses_to_write_over_an_input(
    name: str, inputs: dict[str, str]
) -> None:
    words, fragment = REFUSALS[name]
    args = words.format(**inputs).split()
    before = {p.name: p.read_bytes() for p in Path(inputs["dir"]).iterdir()}
    result = CliRunner().invoke(cli.main, [*args, "--force"])
    assert_one_error_line(result, fragment)
    assert {p.name: p.read_bytes() for p in Path(inputs["dir"]).iterdir()} == before


# --- every file is read through the one reader ---------------------------------------------------

#: Methods that open or read a file (``path.open()``, ``ET.parse(path)``, ...), and functions.
READING_METHODS = {"open", "read_text", "read_bytes", "loadtxt", "genfromtxt", "connect"}
READING_FUNCTIONS = {"open"}
XML_MODULES = {"ET", "ElementTree"}

#: The reads that do not go through diffbot.io.textfile, each for its reason: (module, function).
OWN_READERS = {
    # the reader helper itself
    ("diffbot/io/textfile.py", "open_text"),
    ("diffbot/io/textfile.py", "open_regular"),
    # stdout pointed at /dev/null
    ("diffbot/cli.py", "_drop_stdout"),
    # a recording's storage, through the rosbags readers
    ("diffbot/io/bag_chunks.py", "_open_reader"),
    # a descriptor from textfile.open_regular, read in binary to bound its size
    ("diffbot/urdf/sdf.py", "_parse"),
    # a descriptor from textfile.open_regular: the head of a file, to tell a description
    ("diffbot/commands/options.py", "xml_root"),
    # a descriptor from textfile.open_regular: a wheel's mesh, bounded in size, in binary
    ("diffbot/urdf/meshes.py", "mesh_radius"),
    # the parameter cache is the tool's own file, read from a small regular file only
    ("diffbot/urdf/cache.py", "_code_fingerprint"),
    ("diffbot/urdf/cache.py", "_read_entry"),
    # a descriptor from textfile.open_regular, read in binary to bound its size
    ("diffbot/urdf/controllers.py", "_read_file"),
    # binary storage of a recording, each file checked regular by io.recordings first
    ("diffbot/io/bag_chunks.py", "_open_uri"),
    ("diffbot/io/bag_chunks.py", "_decompressed"),
    # numbers from text already read (a StringIO), not from a file
    ("diffbot/io/csv_chunks.py", "_fast"),
    # the tool's own marks of the warnings shown, created empty (a write, not a read)
    ("diffbot/commands/said_once.py", "shown_before"),
    # standard input copied to a file in the run's own temporary folder (a write, not a read)
    ("diffbot/commands/plot.py", "_stdin_file"),
    # the bundled robot's derived parameters, a file of the package itself
    ("diffbot/urdf/shipped.py", "shipped_fields"),
    # compressed storage of a recording checked regular by io.recordings first, inflated within
    # a bound (a file object rosbags opened, or diffbot's own copy of a .db3.zstd)
    ("diffbot/io/bag_inflate.py", "copy_inflated"),
    ("diffbot/io/bag_inflate.py", "open"),
}


def file_reads() -> set[tuple[str, str]]:
    """(module, function) of every call that opens or reads a file in the package."""
    root = Path(diffbot.__file__).parent
    found: set[tuple[str, str]] = set()
    for path in sorted(root.rglob("*.py")):
        module = path.relative_to(root.parent).as_posix()
        if module.startswith("diffbot/live/"):
            continue  # the network, not files
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for function in ast.walk(tree):
            if not isinstance(function, (ast.FunctionDef, ast.AsyncFunctionDef)):
                continue
            for node in ast.walk(function):
                if isinstance(node, ast.Call) and _a_read(node):
                    found.add((module, function.name))
    return found


def _a_read(call: ast.Call) -> bool:
    """A call that opens or reads a file, not to write it."""
    called = call.func
    if isinstance(called, ast.Name):
        reads = called.id in READING_FUNCTIONS
    elif isinstance(called, ast.Attribute):
        owner = called.value
        xml = called.attr == "parse" and isinstance(owner, ast.Name) and owner.id in XML_MODULES
        reads = called.attr in READING_METHODS or xml
    else:
        reads = False
    return reads and not _a_write(call)


def _a_write(call: ast.Call) -> bool:
    """A call that opens a file for writing (``open(..., "w")``)."""
    modes = [a.value for a in call.args[1:2] if isinstance(a, ast.Constant)]
    modes += [
        k.value.value
        for k in call.keywords
        if k.arg == "mode" and isinstance(k.value, ast.Constant)
    ]
    return any(isinstance(m, str) and ("w" in m or "a" in m or "x" in m) for m in modes)


def test_every_file_is_read_through_the_reader_helper() -> None:
    reads = file_reads()
    assert reads - OWN_READERS == set(), "read through diffbot.io.textfile instead"
