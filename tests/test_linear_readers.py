"""No reader's time grows faster than its input: each reader of files and messages, fed large
adversarial inputs (thousands of comments, deep nesting, long lines, many columns, many
repeated tokens), takes at most a constant multiple of its time per byte on a small input of
the same shape (harness: tests/linear_time.py)."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import click
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st
from linear_time import assert_linear
from robots import two_wheel_urdf

import diffbot
from diffbot.io.csv_chunks import read_csv
from diffbot.io.jointstate_cdr import decode_positions, parse_layout
from diffbot.io.waypoints import read_waypoints
from diffbot.live.cdr import decode_joint_state, encode_joint_state
from diffbot.planfile import load_plan
from diffbot.urdf.controllers import load_controllers
from diffbot.urdf.xacro import expand

FEW = settings(
    max_examples=2,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
)
#: Comment text: anything but what ends a comment or breaks the encoding.
WORDS = st.text(
    st.characters(codec="utf-8", exclude_characters="-<>&\r", exclude_categories=["Cs", "Cc"]),
    min_size=1,
    max_size=40,
)
TOKENS = st.sampled_from(["a", "1", " ", "$", "\\", '"', "%(", "<!--", "{", "[", ",", "é"])


def on_file(path: Path, reader: Callable[[Path], object]) -> Callable[[bytes], object]:
    """A reader of bytes that writes them to ``path`` and reads it with ``reader``."""

    def read(data: bytes) -> object:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(data)
        return reader(path)

    return read


@pytest.fixture(autouse=True)
def _no_cache(monkeypatch: pytest.MonkeyPatch) -> None:
    # each read derives the parameters again, as a first run does
    monkeypatch.setenv("DIFFBOT_NO_CACHE", "1")


# --- robot descriptions ---------------------------------------------------------------------


def _urdf(shape: str, word: str) -> Callable[[int], bytes]:
    def make(n: int) -> bytes:
        if shape == "comments before the root":
            declaration, rest = two_wheel_urdf().split("\n", 1)
            return f"{declaration}\n{f'<!-- {word} -->' * n}\n{rest}".encode()
        if shape == "comments between elements":
            return two_wheel_urdf(body=f"<!-- {word} -->\n" * n).encode()
        if shape == "a long attribute":
            body = f'<material name="{"x" * (40 * n)}"><color rgba="0 0 0 1"/></material>'
            return two_wheel_urdf(body=body).encode()
        body = "".join(
            f'<material name="m{i}"><color rgba="0 0 0 1"/></material>' for i in range(n)
        )
        return two_wheel_urdf(body=body).encode()

    return make


@FEW
@given(
    shape=st.sampled_from(
        ["comments before the root", "comments between elements", "a long attribute", "many"]
    ),
    word=WORDS,
)
@example(shape="comments before the root", word="generated banner")
def test_a_urdf_is_read_in_linear_time(tmp_path: Path, shape: str, word: str) -> None:
    read = on_file(tmp_path / "robot.urdf", diffbot.load_params)
    print("urdf", shape, assert_linear(read, _urdf(shape, word), 300, accepts=True))


def _links(shape: str) -> Callable[[int], bytes]:
    """``n`` more links: unattached (several roots, refused), in a chain of fixed joints below
    the base, or each fixed to the base."""

    def make(n: int) -> bytes:
        links = [f'<link name="x{i}"/>' for i in range(n)]
        if shape != "unattached":
            parents = ["base_link", *(f"x{i}" for i in range(n - 1))]
            if shape == "on the base":
                parents = ["base_link"] * n
            links += [
                f'<joint name="j{i}" type="fixed"><parent link="{parent}"/>'
                f'<child link="x{i}"/></joint>'
                for i, parent in enumerate(parents)
            ]
        return two_wheel_urdf(body="\n".join(links)).encode()

    return make


@pytest.mark.parametrize("shape", ["unattached", "a chain", "on the base"])
def test_a_urdf_of_many_links_is_read_in_linear_time(tmp_path: Path, shape: str) -> None:
    read = on_file(tmp_path / "robot.urdf", diffbot.load_params)
    accepts = shape != "unattached"
    print("urdf links", shape, assert_linear(read, _links(shape), 1000, accepts=accepts))


def _xacro(shape: str, word: str) -> Callable[[int], bytes]:
    def make(n: int) -> bytes:
        if shape == "comments":
            body = f"<!-- {word} -->\n" * n
        elif shape == "properties":
            body = "".join(f'<xacro:property name="p{i}" value="{i}"/>' for i in range(n))
        else:  # a long expression: a sum of n terms
            body = f'<xacro:property name="s" value="${{{"+".join(["1"] * n)}}}"/>'
        return two_wheel_urdf(body=body, xacro=True).encode()

    return make


@FEW
@given(shape=st.sampled_from(["comments", "properties", "a long expression"]), word=WORDS)
@example(shape="comments", word="<!-")
def test_a_xacro_description_is_expanded_in_linear_time(
    tmp_path: Path, shape: str, word: str
) -> None:
    read = on_file(tmp_path / "robot.urdf.xacro", expand)
    print("xacro", shape, assert_linear(read, _xacro(shape, word), 200, accepts=True))


def _sdf(shape: str, word: str) -> Callable[[int], bytes]:
    wheel = (
        '<link name="{0}"><pose>0 {1} 0 -1.5708 0 0</pose><collision name="c"><geometry>'
        "<cylinder><radius>0.05</radius><length>0.02</length></cylinder></geometry></collision>"
        '</link><joint name="{0}_joint" type="revolute"><parent>base</parent><child>{0}</child>'
        "<axis><xyz>0 0 1</xyz></axis></joint>"
    )
    wheels = '<link name="base"/>' + wheel.format("left", 0.1) + wheel.format("right", -0.1)

    def make(n: int) -> bytes:
        comments = f"<!-- {word} -->\n" * n
        if shape == "comments before the root":
            return f"{comments}<sdf version='1.9'><model name='m'>{wheels}</model></sdf>".encode()
        if shape == "comments in the model":
            return f"<sdf version='1.9'><model name='m'>{comments}{wheels}</model></sdf>".encode()
        # nested models, n deep
        nested = "<model name='n'>" * n + "</model>" * n
        return f"<sdf version='1.9'><model name='m'>{wheels}{nested}</model></sdf>".encode()

    return make


@FEW
@given(
    shape=st.sampled_from(["comments before the root", "comments in the model", "nesting"]),
    word=WORDS,
)
@example(shape="comments before the root", word="model")
def test_an_sdf_model_is_read_in_linear_time(tmp_path: Path, shape: str, word: str) -> None:
    read = on_file(tmp_path / "model.sdf", expand)
    print("sdf", shape, assert_linear(read, _sdf(shape, word), 200, accepts=shape != "nesting"))


# --- YAML, text and JSON files --------------------------------------------------------------

CONTROLLER = (
    "diff_drive_controller:\n  ros__parameters:\n"
    "    type: diff_drive_controller/DiffDriveController\n"
    "    left_wheel_names: [left_wheel_joint]\n    right_wheel_names: [right_wheel_joint]\n"
    "    wheel_separation: 0.2\n    wheel_radius: 0.05\n"
)


def _yaml(shape: str, word: str, document: str) -> Callable[[int], bytes]:
    def make(n: int) -> bytes:
        if shape == "comments":
            return (f"# {word}\n" * n + document).encode()
        if shape == "a long line":  # a quote in a quoted scalar is written twice
            quoted = word.replace("'", "''")
            return (document + f"other: '{quoted * n}'\n").encode()
        if shape == "many keys":
            return (document + "".join(f"k{i}: {word!r}\n" for i in range(n))).encode()
        if shape == "nesting":
            return (document + "deep: " + "[" * n + "]" * n + "\n").encode()
        return (document + f"other: '{'$(arg a) ' * n}'\n").encode()

    return make


YAML_SHAPES = st.sampled_from(["comments", "a long line", "many keys", "nesting", "tokens"])


@FEW
@given(shape=YAML_SHAPES, word=WORDS)
@example(shape="tokens", word="a")
@example(shape="a long line", word="0'")
def test_a_controllers_file_is_read_in_linear_time(tmp_path: Path, shape: str, word: str) -> None:
    read = on_file(tmp_path / "controllers.yaml", load_controllers)
    print(
        "controllers",
        shape,
        assert_linear(read, _yaml(shape, word, CONTROLLER), 400, accepts=shape != "nesting"),
    )


def _plan(kind: str, token: str) -> Callable[[int], bytes]:
    def make(n: int) -> bytes:
        if kind == "txt":
            return ("straight 1; spin 90\n" * n + f"# {token * n}\n").encode()
        if kind == "yaml":
            return ("- straight: 1\n" * n + f"# {token * n}\n").encode()
        if kind == "json":  # a string never closed, full of escaped quotes
            return ('[{"straight": 1}, "' + (token + '\\"') * n + "]").encode()
        return ("[" * n + "]" * n).encode()

    return make


@FEW
@given(kind=st.sampled_from(["txt", "yaml", "json", "nesting"]), token=TOKENS)
@example(kind="json", token="a")
def test_a_plan_file_is_read_in_linear_time(tmp_path: Path, kind: str, token: str) -> None:
    suffix = "json" if kind == "nesting" else kind
    read = on_file(tmp_path / f"plan.{suffix}", load_plan)
    print(
        "plan",
        kind,
        repr(token),
        assert_linear(read, _plan(kind, token), 500, accepts=kind in ("txt", "yaml")),
    )


def _waypoints(shape: str, token: str) -> Callable[[int], bytes]:
    def make(n: int) -> bytes:
        if shape == "rows":
            return b"x,y,heading\n" + b"1,2,30 deg\n" * n
        if shape == "a long number":
            return f"1,{'1' * (8 * n)}{token}\n".encode()
        return f"1,{' ' * (8 * n)}2{' ' * (8 * n)}m{token}\n".encode()

    return make


@FEW
@given(shape=st.sampled_from(["rows", "a long number", "long blanks"]), token=TOKENS)
@example(shape="a long number", token="x")
def test_a_waypoints_file_is_read_in_linear_time(tmp_path: Path, shape: str, token: str) -> None:
    read = on_file(tmp_path / "points.csv", read_waypoints)
    print(
        "waypoints",
        shape,
        repr(token),
        assert_linear(read, _waypoints(shape, token), 1000, accepts=shape == "rows"),
    )


def _read_runs(path: Path) -> object:
    from diffbot.commands.calibrate import _runs_file

    try:
        return _runs_file(str(path))
    except click.ClickException:
        return None


def _runs(kind: str, token: str) -> Callable[[int], bytes]:
    def make(n: int) -> bytes:
        if kind == "csv":
            return ("direction,x,y\n" + "cw,0.1,0.2\n" * n + f"ccw,{token * n},1\n").encode()
        return ("cw:\n" + "  - [0.1, 0.2]\n" * n + f"# {token * n}\n").encode()

    return make


@FEW
@given(kind=st.sampled_from(["csv", "yaml"]), token=TOKENS)
@example(kind="csv", token="1")
def test_a_runs_file_is_read_in_linear_time(tmp_path: Path, kind: str, token: str) -> None:
    read = on_file(tmp_path / f"runs.{kind}", _read_runs)
    print(
        "runs",
        kind,
        repr(token),
        assert_linear(read, _runs(kind, token), 500, accepts=kind == "yaml"),
    )


# --- recordings -----------------------------------------------------------------------------


def _csv(shape: str, token: str) -> Callable[[int], bytes]:
    def make(n: int) -> bytes:
        if shape == "rows":
            rows = "".join(f"{i},0.1,0.2\n" for i in range(n))
        elif shape == "quoted wide rows":  # the quote sends every row through csv
            wide = f"{token}," * 200
            rows = '0,0.1,0.2,"x"\n' + "".join(f"{i},0.1,0.2,{wide}x\n" for i in range(n))
        elif shape == "columns":
            names = ",".join(f"c{i}" for i in range(n))
            rows = f"{names}\n" + f"0,0.1,0.2,{','.join(['0.5'] * n)}\n" * 10
            return f"time,left,right,{rows}".encode()
        else:
            rows = f"0,0.1,{token * (8 * n)}\n1,0.2,0.3\n"
        return f"time,left,right\n{rows}".encode()

    return make


@FEW
@given(shape=st.sampled_from(["rows", "columns", "a long cell", "quoted wide rows"]), token=TOKENS)
@example(shape="columns", token="1")
@example(shape="quoted wide rows", token="12")
def test_a_csv_recording_is_read_in_linear_time(tmp_path: Path, shape: str, token: str) -> None:
    read = on_file(tmp_path / "run.csv", lambda path: read_csv(path, "left", "right"))
    print(
        "csv",
        shape,
        repr(token),
        assert_linear(read, _csv(shape, token), 1000, accepts=shape != "a long cell"),
    )


METADATA = (
    "rosbag2_bagfile_information:\n  version: 5\n  storage_identifier: sqlite3\n"
    "  duration: {nanoseconds: 0}\n  message_count: 0\n"
    "  topics_with_message_count: []\n  compression_format: ''\n  compression_mode: ''\n"
)


def _read_bag_metadata(path: Path) -> object:
    from diffbot.io.bag_chunks import TopicChunks

    TopicChunks(path.parent).close()
    return None


def _metadata(shape: str, word: str) -> Callable[[int], bytes]:
    listed = _yaml(shape, word, METADATA + "  relative_file_paths: [b.db3]\n")

    def make(n: int) -> bytes:
        if shape == "files":
            return (METADATA + "  relative_file_paths:\n" + "    - b.db3\n" * n).encode()
        return listed(n)

    return make


@FEW
@given(
    shape=st.sampled_from(["files", "comments", "a long line", "many keys", "nesting"]), word=WORDS
)
@example(shape="files", word="b")
def test_bag_metadata_is_read_in_linear_time(tmp_path: Path, shape: str, word: str) -> None:
    read = on_file(tmp_path / "bag/metadata.yaml", _read_bag_metadata)
    print("bag metadata", shape, assert_linear(read, _metadata(shape, word), 400, accepts=False))


# --- CDR payloads ---------------------------------------------------------------------------


def _joint_states(shape: str, word: str) -> Callable[[int], bytes]:
    def make(n: int) -> bytes:
        if shape == "many joints":
            names = [f"{word}{i}" for i in range(n)]
        elif shape == "repeated names":
            names = [word] * n
        else:
            names = [word * n, "left", "right"]
        return encode_joint_state(
            1, word * (n if shape == "a long frame" else 1), names, [0.5] * len(names)
        )

    return make


JOINT_SHAPES = st.sampled_from(["many joints", "repeated names", "long names", "a long frame"])
NAMES = st.text(st.characters(codec="utf-8", exclude_categories=["Cs"]), min_size=1, max_size=8)


def _decode_live(data: bytes) -> object:
    try:
        return decode_joint_state(data)
    except ValueError:
        return None


def _decode_recorded(data: bytes) -> object:
    parse_layout(data)
    return decode_positions([data] * 4, ["left", "right"])


@FEW
@given(shape=JOINT_SHAPES, word=NAMES)
@example(shape="many joints", word="wheel")
def test_a_live_joint_state_is_decoded_in_linear_time(shape: str, word: str) -> None:
    print(
        "live cdr",
        shape,
        assert_linear(_decode_live, _joint_states(shape, word), 2000, accepts=True),
    )


@FEW
@given(shape=JOINT_SHAPES, word=NAMES)
@example(shape="repeated names", word="left")
def test_a_recorded_joint_state_is_decoded_in_linear_time(shape: str, word: str) -> None:
    print(
        "recorded cdr",
        shape,
        assert_linear(_decode_recorded, _joint_states(shape, word), 2000, accepts=True),
    )
