"""diffbot.lazy: a package's names load on first use, once, and unknown names are refused."""

from __future__ import annotations

import sys
import types
from typing import Any

import pytest

from diffbot.lazy import lazy_names


def test_a_name_loads_its_module_on_first_use_and_is_kept() -> None:
    namespace: dict[str, Any] = {}
    getattr_, dir_ = lazy_names("pkg", {"dumps": "json", "sqrt": "math"}, namespace)
    assert dir_() == ["dumps", "sqrt"]
    import json

    assert getattr_("dumps") is json.dumps
    assert namespace == {"dumps": json.dumps}
    assert dir_() == ["dumps", "sqrt"]


def test_an_unknown_name_is_an_attribute_error_naming_the_package() -> None:
    getattr_, _ = lazy_names("pkg.sub", {"dumps": "json"}, {})
    with pytest.raises(AttributeError, match=r"module 'pkg.sub' has no attribute 'loads'"):
        getattr_("loads")


def test_the_module_is_imported_only_when_a_name_of_it_is_asked_for(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    home = types.ModuleType("diffbot_lazy_probe")
    home.value = 42  # type: ignore[attr-defined]
    getattr_, _ = lazy_names("pkg", {"value": "diffbot_lazy_probe"}, {})
    assert "diffbot_lazy_probe" not in sys.modules
    monkeypatch.setitem(sys.modules, "diffbot_lazy_probe", home)
    assert getattr_("value") == 42
