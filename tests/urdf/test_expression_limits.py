"""The size limits of sandboxed expressions (diffbot/urdf/expression_limits.py)."""

from __future__ import annotations

import ast

import pytest
from hypothesis import given
from hypothesis import strategies as st

from diffbot.errors import ExpansionLimitError
from diffbot.urdf.expression_limits import (
    MAX_ITEMS,
    RefusalError,
    check_binary,
    check_size,
    weight,
    yaml_weight,
)

_LEAVES = st.one_of(st.text(max_size=5), st.binary(max_size=5), st.integers(), st.none())
_VALUES = st.recursive(
    _LEAVES,
    lambda inner: st.one_of(
        st.lists(inner, max_size=6),
        st.tuples(inner, inner),
        st.dictionaries(st.text(max_size=3), inner, max_size=4),
    ),
    max_leaves=30,
)


def _items(value: object) -> int:
    """Containers and their items, nested ones counted, each at least once."""
    if isinstance(value, dict):
        return 1 + sum(_items(k) + _items(v) for k, v in value.items())
    if isinstance(value, (list, tuple)):
        return 1 + sum(_items(x) for x in value)
    return 1


@given(_VALUES)
def test_every_item_of_a_container_counts_at_least_one(value: object) -> None:
    if isinstance(value, (list, tuple, dict)):
        assert weight(value) >= _items(value)


@given(st.text(max_size=50))
def test_a_string_weighs_its_characters(text: str) -> None:
    assert weight(text) == len(text)


@pytest.mark.parametrize("empty", ["", b"", (), []])
def test_a_container_of_empty_items_weighs_its_length(empty: object) -> None:
    assert weight([empty] * 1000) >= 1001


@pytest.mark.parametrize("empty", ["", b""])
def test_repeating_a_list_of_empty_strings_is_refused_past_the_limit(empty: object) -> None:
    with pytest.raises(RefusalError, match="a repetition of more than"):
        check_binary(ast.Mult, [empty], MAX_ITEMS)
    million = [empty] * (MAX_ITEMS // 2)
    with pytest.raises(RefusalError, match="a repetition of more than"):
        check_binary(ast.Mult, million, 100)
    with pytest.raises(RefusalError, match="characters or items"):
        check_size([empty] * (MAX_ITEMS + 1))


def test_a_repetition_within_the_limit_passes() -> None:
    check_binary(ast.Mult, [""], MAX_ITEMS // 2 - 1)
    check_binary(ast.Mult, "", 10**12)  # an empty string repeated is empty


def test_yaml_data_weighs_each_alias_where_it_stands() -> None:
    leaf = ["", ""]  # one list, referred to ten times as YAML aliases are
    data = {"a": [leaf] * 10}
    # the dict, its key and value (a list of ten), and ten times the leaf list and its items
    assert yaml_weight(data, {}, MAX_ITEMS) == 1 + 1 + 1 + 10 * 3


def test_yaml_data_that_holds_itself_is_refused() -> None:
    loop: list[object] = []
    loop.append(loop)
    with pytest.raises(ExpansionLimitError, match="refers to itself"):
        yaml_weight(loop, {}, MAX_ITEMS)
