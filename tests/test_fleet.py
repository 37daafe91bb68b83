"""diffbot.fleet on its own: its messages name library parameters, never command-line flags."""

from __future__ import annotations

import pytest

from diffbot.cli import FLAGS
from diffbot.errors import RecordingError
from diffbot.fleet import dask_address


@pytest.mark.parametrize(
    ("address", "reason"),
    [
        ("ftp://host:1", "unknown scheme"),
        ("inproc://", "an inproc address names HOST/PID/N"),
        ("tcp://:8786", "the host is missing or malformed"),
        ("tcp://host:99999", "the port must be a number from 1 to 65535"),
    ],
)
def test_a_malformed_address_is_named_by_its_library_parameter(address: str, reason: str) -> None:
    with pytest.raises(RecordingError, match=reason) as caught:
        dask_address(address)
    assert str(caught.value).startswith("dask_address= ")
    assert "--dask" not in str(caught.value)
    assert caught.value.render(FLAGS.__getitem__).startswith("--dask ")


@pytest.mark.parametrize(
    ("address", "expected"),
    [
        ("host", "tcp://host:8786"),
        ("tls://10.0.0.2:9000", "tls://10.0.0.2:9000"),
        ("tcp://[::1]:8786", "tcp://[::1]:8786"),
    ],
)
def test_a_good_address_is_completed_as_dask_does(address: str, expected: str) -> None:
    assert dask_address(address) == expected
