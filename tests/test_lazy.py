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


def test_a_submodule_is_imported_as_the_package_attribute_it_is() -> None:
    """``diffbot.urdf`` after ``import diffbot``, as when the package imported it eagerly."""
    import json.decoder

    getattr_, _ = lazy_names("json", {}, {})
    assert getattr_("decoder") is json.decoder
    for name in ("no_such_module", "__wrapped__", "a-b"):
        with pytest.raises(AttributeError, match=name):
            getattr_(name)


def test_the_whole_package_names_its_submodules_after_a_bare_import() -> None:
    import subprocess

    probe = "import diffbot; print(diffbot.urdf.__name__, diffbot.kinematics.__name__)"
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True)
    assert done.stdout.split() == ["diffbot.urdf", "diffbot.kinematics"], done.stderr


def test_the_module_is_imported_only_when_a_name_of_it_is_asked_for(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    home = types.ModuleType("diffbot_lazy_probe")
    home.value = 42  # type: ignore[attr-defined]
    getattr_, _ = lazy_names("pkg", {"value": "diffbot_lazy_probe"}, {})
    assert "diffbot_lazy_probe" not in sys.modules
    monkeypatch.setitem(sys.modules, "diffbot_lazy_probe", home)
    assert getattr_("value") == 42
