"""The one module that imports cyclonedds: the rest of :mod:`diffbot.live` takes its DDS names
from here, so that a missing install is one :class:`~diffbot.live.errors.LiveError` naming the
extra to install, raised on first use of any live module."""

from __future__ import annotations

from diffbot.live.errors import INSTALL_HINT, LiveError

try:
    from cyclonedds._clayer import (  # type: ignore[import-not-found]
        ddspy_take,
        ddspy_write,
    )
    from cyclonedds.builtin import BuiltinDataReader, BuiltinTopicDcpsPublication
    from cyclonedds.core import (
        DDSException,
        GuardCondition,
        InstanceState,
        ReadCondition,
        SampleState,
        ViewState,
        WaitSet,
    )
    from cyclonedds.domain import Domain, DomainParticipant
    from cyclonedds.idl import IdlStruct
    from cyclonedds.idl.annotations import final
    from cyclonedds.idl.types import (
        array,
        bounded_str,
        float64,
        int32,
        int64,
        sequence,
        uint8,
        uint32,
        uint64,
    )
    from cyclonedds.pub import DataWriter
    from cyclonedds.qos import Policy, Qos
    from cyclonedds.sub import DataReader
    from cyclonedds.topic import Topic
except ImportError as err:  # pragma: no cover - exercised in a subprocess without it
    raise LiveError(INSTALL_HINT) from err

__all__ = [
    "BuiltinDataReader",
    "BuiltinTopicDcpsPublication",
    "DDSException",
    "DataReader",
    "DataWriter",
    "Domain",
    "DomainParticipant",
    "GuardCondition",
    "IdlStruct",
    "InstanceState",
    "Policy",
    "Qos",
    "ReadCondition",
    "SampleState",
    "Topic",
    "ViewState",
    "WaitSet",
    "array",
    "bounded_str",
    "ddspy_take",
    "ddspy_write",
    "final",
    "float64",
    "int32",
    "int64",
    "sequence",
    "uint8",
    "uint32",
    "uint64",
]
