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
    from cyclonedds.idl import types as idl
    from cyclonedds.idl.annotations import final
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
    "ddspy_take",
    "ddspy_write",
    "final",
    "idl",
]
