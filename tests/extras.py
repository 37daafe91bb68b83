"""Packages of the ``test`` extra: a test that needs one fails without it, never skips.

``pip install -e '.[test]'`` installs OMPL, rosbags, ruckig, matplotlib, cyclonedds and dask
with the test tools; a test that skipped when one is missing would pass a checkout where the
comparison it makes never ran.
"""

from __future__ import annotations

import importlib
from types import ModuleType

import pytest


def need(name: str) -> ModuleType:
    """The module ``name``, imported; the test (or the test file) fails when it is missing."""
    try:
        return importlib.import_module(name)
    except ImportError as error:
        pytest.fail(
            f"{name} is missing: the test extra installs it (pip install -e '.[test]'): {error}",
            pytrace=False,
        )
