"""The project's own DDS topic of the relays (docs/relay.md#the-console-knows-the-hop): a `sem-relay` of the operations
side writes, once a second, one sample per relay of the vehicles' side it hears: that relay's name, the vehicles it
carries, the age of the last data that came over the link from it, and how long each vehicle's data may be quiet by
the link's rate caps (a console adds it to the vehicle's comms-lost timeout). A console reads it to mark the vehicles seen
through a relay and to raise one alarm for a relay gone silent. Not a UMAA topic: no vehicle writes or reads it."""

# no `from __future__ import annotations`: cyclonedds reads the IDL struct's annotations as types

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from cyclonedds.core import Policy, Qos
from cyclonedds.domain import DomainParticipant
from cyclonedds.idl import IdlStruct
from cyclonedds.idl.annotations import key
from cyclonedds.idl.types import int64, sequence
from cyclonedds.pub import DataWriter
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic

TOPIC = "SEMConsole_RelayLink"
PERIOD = 1.0  # s between a relay's samples
NEVER = -1  # ageMs of a relay that carried no data yet


@dataclass
class RelayLink(IdlStruct, typename="SEMConsole::RelayLink"):
    relay: str  # the vehicles' side relay's --name
    if TYPE_CHECKING:
        vehicles: list[str]
    else:
        vehicles: sequence[str]  # the vehicles it carries: their source GUIDs as UUID strings
    ageMs: int64  # ms since the last data over the link from it, as the operations side's relay wrote the sample
    if TYPE_CHECKING:
        quietMs: list[int] = field(default_factory=list)
    else:
        # of each vehicle (in `vehicles`' order): ms its data may be quiet by the link's caps (none said: 0)
        quietMs: sequence[int64] = field(default_factory=list)
    key("relay")


# the latest sample of each relay, to a console that starts later too
_QOS = Qos(
    Policy.Reliability.Reliable(1_000_000_000),
    Policy.Durability.TransientLocal,
    Policy.History.KeepLast(1),
)


def writer(participant: DomainParticipant) -> DataWriter[Any]:
    return DataWriter(participant, Topic(participant, TOPIC, RelayLink), _QOS)


def reader(participant: DomainParticipant, listener: Any = None) -> DataReader[Any]:
    return DataReader(participant, Topic(participant, TOPIC, RelayLink), _QOS, listener=listener)
