"""The bounded YAML reader: plain data, or one error of the caller's kind before any work that a
small file could multiply (aliases, deep nesting, endless digits)."""

from __future__ import annotations

import time

import pytest
from hypothesis import given
from hypothesis import strategies as st

from diffbot.errors import PlanError
from diffbot.io.yamlfile import MAX_NESTING, load_yaml


def bomb(levels: int) -> str:
    """Anchors that double at every level: a few hundred bytes naming 2**levels items."""
    lines = ["a0: &a0 [x, x]"]
    lines += [f"a{k}: &a{k} [*a{k - 1}, *a{k - 1}]" for k in range(1, levels + 1)]
    return "\n".join(lines) + "\n"


def load(text: str, **options: bool) -> object:
    return load_yaml(text, "f.yaml", PlanError, "a test file", **options)


def test_plain_data_is_read() -> None:
    assert load("a: [1, 2.5, x]\nb: {c: null}\n") == {"a": [1, 2.5, "x"], "b": {"c": None}}


def test_an_alias_bomb_is_refused_at_its_first_alias_quickly() -> None:
    text = bomb(27)
    assert len(text) < 600
    start = time.perf_counter()
    with pytest.raises(PlanError) as caught:
        load(text)
    assert time.perf_counter() - start < 1.0
    message = str(caught.value)
    assert message == (
        "f.yaml: YAML aliases (*name) are not allowed in a test file, write each entry out "
        "(line 2, column 10)"
    )


def test_nesting_up_to_the_limit_is_read_and_deeper_is_refused() -> None:
    deep_ok = "[" * MAX_NESTING + "]" * MAX_NESTING
    assert load(deep_ok) is not None
    too_deep = "[" * (MAX_NESTING + 1) + "]" * (MAX_NESTING + 1)
    with pytest.raises(PlanError, match=f"nested more than {MAX_NESTING} deep"):
        load(too_deep)
    with pytest.raises(PlanError, match="nested more than"):
        load("[" * 100_000)  # never reaches Python's recursion limit


@given(st.integers(min_value=MAX_NESTING + 1, max_value=400))
def test_block_mappings_nested_past_the_limit_are_refused(depth: int) -> None:
    text = "".join(f"{'  ' * k}k{k}:\n" for k in range(depth)) + "  " * depth + "v\n"
    with pytest.raises(PlanError, match="nested more than"):
        load(text)


def test_ros_floats_read_exponents_without_a_dot() -> None:
    assert load("a: 1e-3\n") == {"a": "1e-3"}  # YAML 1.1
    assert load("a: 1e-3\n", ros_floats=True) == {"a": pytest.approx(1e-3, rel=0, abs=0)}


def test_repeated_keys_are_refused_only_when_asked() -> None:
    assert load("a: 1\na: 2\n") == {"a": 2}
    with pytest.raises(PlanError, match=r"malformed YAML: duplicate key 'a' \(line 2, column 1\)"):
        load("a: 1\na: 2\n", unique_keys=True)


def test_an_integer_of_thousands_of_digits_is_an_error() -> None:
    with pytest.raises(PlanError, match=r"f\.yaml: malformed YAML: a number too long to read"):
        load("a: 1" + "0" * 5000 + "\n")


def test_malformed_yaml_names_the_line() -> None:
    with pytest.raises(PlanError, match=r"f.yaml: malformed YAML: .*\(line 3, column 1\)"):
        load("a:\n  b: [1, 2\n")


def test_repeated_keys_read_as_ros_reads_them_merge_mappings_and_say_so() -> None:
    # ROS merges a node or namespace written twice (ros2/rclcpp#2166); PyYAML keeps only the last.
    text = "ns:\n  a: 1\n  b: {c: 2}\nns:\n  b: {d: 3}\n  a: 1\n"
    repeated: list[str] = []
    data = load_yaml(text, "p.yaml", PlanError, "a file", repeated=repeated)
    assert data == {"ns": {"a": 1, "b": {"c": 2, "d": 3}}}
    assert len(repeated) == 1
    assert "'ns' appears twice (lines 1 and 4)" in repeated[0]
    assert "later values used" not in repeated[0]  # nothing was replaced by another value


def test_a_value_given_twice_takes_the_later_and_names_both_lines() -> None:
    repeated: list[str] = []
    data = load_yaml("r: 0.05\nq: 1\nr: 7\n", "p.yaml", PlanError, "a file", repeated=repeated)
    assert data == {"q": 1, "r": 7}
    assert repeated == [
        "'r' is given twice (lines 1 and 3): the later value, 7, is used, as ROS uses it"
    ]
    nested: list[str] = []
    load_yaml("n:\n  r: 1\nn:\n  r: 2\n", "p.yaml", PlanError, "a file", repeated=nested)
    assert nested[0].endswith("later values used: r 2")


def test_without_asking_the_later_key_still_wins_silently() -> None:
    assert load_yaml("n: {a: 1}\nn: {b: 2}\n", "p.yaml", PlanError, "a file") == {"n": {"b": 2}}
