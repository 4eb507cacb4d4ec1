"""Other vendors' participants in discovery, and what their operator must change for the console to read them.

RTI Connext (docs/dds.md, "Connext 7.x, and the recipe for RTI vehicles") fails against Cyclone in three ways the
console can see in discovery, none of which shows as a lost or rejected sample:
- it sends XTypes type information (Connext 7 on its defaults): Cyclone 11.0.1 cannot add RTI 7's type objects and
  then matches none of its SEM topics;
- a GPSReport or GPSFixReport writer offers XCDR1 (RTI's default): the console accepts XCDR2 only for types with
  @optional members (dds/qos.py);
- any other SEM writer the console's readers do not match (a QoS, a partition, an extensibility), and a command reader
  the console's command writers do not match (its commands would go nowhere).
The vendor is the first two bytes of the participant's GUID prefix (DDSI-RTPS 9.3.1.5; RTI 01.01, Cyclone 01.10).
What cannot be seen: NDDS_XTYPES_COMPLIANCE_MASK, so the GPSReport advice names it whatever the writer does.
"""

from __future__ import annotations

import dataclasses
import uuid
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import Any, Literal

from cyclonedds.builtin import (
    BuiltinDataReader,
    BuiltinTopicDcpsParticipant,
    BuiltinTopicDcpsPublication,
    BuiltinTopicDcpsSubscription,
)
from cyclonedds.builtin_types import DcpsEndpoint
from cyclonedds.core import InstanceState, Policy, Qos
from cyclonedds.domain import DomainParticipant

from sem_console.dds.topics import AnySem, Sem, Sem60

RTI = b"\x01\x01"  # RTI Connext's vendor id
DOCS = "docs/dds.md#rti-connext-7"
# the drop-in QoS profiles for an RTI participant, by the UMAA version of its SEM topics (their table)
DROP_IN: dict[type[AnySem], str] = {Sem: "docs/rti/sem-console-interop.xml", Sem60: "docs/rti/umaa-6.0-interop.xml"}
MASK = "NDDS_XTYPES_COMPLIANCE_MASK=0x1a9"
# A writer is judged unmatched only this long after it was discovered: Cyclone matches it with the console's
# readers as it discovers it, but the builtin topic may show it a moment before.
SETTLE = 2.0

Kind = Literal["typeInformation", "representation", "unmatched", "unmatchedReader"]


@dataclass(frozen=True)
class Finding:
    """One thing a peer's operator must change, in their terms."""

    participant: str  # the participant's GUID
    name: str  # its entity name (RTI: the participant's name in its XML), else its GUID
    vendor: str
    kind: Kind
    topic: str | None  # the SEM topic's short name, None for the participant as a whole
    fix: str  # what to change, in the vendor's terms

    @property
    def message(self) -> str:
        what = {
            "typeInformation": "sends type information this console cannot use (none of its SEM topics match)",
            "representation": f"offers {self.topic} in XCDR1",
            "unmatched": f"has a writer of {self.topic} that the console does not match",
            "unmatchedReader": f"has a reader of {self.topic} that the console's commands do not reach",
        }[self.kind]
        return f"{self.vendor} participant {self.name} {what}: {self.fix} ({DOCS})"

    def to_json(self) -> dict[str, str | None]:
        return {**dataclasses.asdict(self), "message": self.message}


def vendor_of(guid: uuid.UUID) -> bytes:
    return guid.bytes[:2]


def _representations(qos: Qos) -> tuple[bool, bool]:
    """(XCDR1, XCDR2) offered by a writer or accepted by a reader; an endpoint that says nothing uses XCDR1 only
    (DDS-XTypes 7.6.3.1.1)."""
    try:
        rep = qos[Policy.DataRepresentation]
    except (KeyError, TypeError):
        rep = None
    if rep is None:
        return True, False
    return bool(rep.use_cdrv0_representation), bool(rep.use_xcdrv2_representation)


def _partitions(qos: Qos) -> list[str]:
    """The named partitions of an endpoint (none: the default partition, where the console's readers are)."""
    try:
        partition = qos[Policy.Partition]
    except (KeyError, TypeError):
        partition = None
    return [p for p in partition.partitions if p] if partition is not None else []


def _name(qos: Qos, guid: uuid.UUID) -> str:
    try:
        entity = qos[Policy.EntityName]
    except (KeyError, TypeError):
        entity = None
    return entity.name if entity is not None and entity.name else str(guid)


def short(sem: AnySem) -> str:
    return sem.spec.name.rsplit("::", 1)[-1]


class PeerWatch:
    """What the builtin topics say of other vendors' endpoints of the given SEM topics (those its owner reads or writes,
    of either UMAA version), kept up to date by `poll`."""

    def __init__(self, participant: DomainParticipant, topics: Iterable[AnySem] = Sem) -> None:
        self.topics = {s.spec.name: s for s in topics}
        self._participants = BuiltinDataReader(participant, BuiltinTopicDcpsParticipant)
        self._pubs = BuiltinDataReader(participant, BuiltinTopicDcpsPublication)
        self._subs = BuiltinDataReader(participant, BuiltinTopicDcpsSubscription)
        self.names: dict[uuid.UUID, str] = {}  # other vendors' participants: GUID -> name
        self.writers: dict[uuid.UUID, tuple[DcpsEndpoint, int, float]] = {}  # key -> (endpoint, handle, seen at)
        self.readers: dict[uuid.UUID, tuple[DcpsEndpoint, int, float]] = {}  # as writers

    def poll(self, now: float) -> None:
        """Take what discovery learnt since the last poll (non-blocking)."""
        for p in _take_all(self._participants):
            if p.sample_info.instance_state == InstanceState.Alive and vendor_of(p.key) == RTI:
                self.names[p.key] = _name(p.qos, p.key)
            else:
                self.names.pop(p.key, None)
        for e in _take_all(self._pubs):
            if e.sample_info.instance_state == InstanceState.Alive and e.topic_name in self.topics and vendor_of(e.key) == RTI:
                old = self.writers.get(e.key)
                self.writers[e.key] = (e, e.sample_info.instance_handle, old[2] if old else now)
            else:
                self.writers.pop(e.key, None)
        for e in _take_all(self._subs):
            if e.sample_info.instance_state == InstanceState.Alive and e.topic_name in self.topics and vendor_of(e.key) == RTI:
                old = self.readers.get(e.key)
                self.readers[e.key] = (e, e.sample_info.instance_handle, old[2] if old else now)
            else:
                self.readers.pop(e.key, None)

    def findings(
        self, matched: Callable[[AnySem], set[int]], now: float, reached: Callable[[AnySem], set[int] | None] = lambda _: None
    ) -> list[Finding]:
        """What each RTI participant with SEM endpoints must change. `matched(sem)`: the publication handles the
        console's readers of that topic matched; `reached(sem)`: the subscription handles its writer of that topic
        matched (None: it writes none)."""
        out: list[Finding] = []
        endpoints: dict[uuid.UUID, list[DcpsEndpoint]] = {}
        for e, _, _ in self.writers.values():
            endpoints.setdefault(e.participant_key, []).append(e)
        for r, _, _ in self.readers.values():
            endpoints.setdefault(r.participant_key, []).append(r)
        for guid, ends in sorted(endpoints.items(), key=lambda kv: str(kv[0])):
            name = self.names.get(guid, str(guid))

            def finding(kind: Kind, topic: str | None, fix: str, guid: uuid.UUID = guid, name: str = name) -> Finding:
                return Finding(str(guid), name, "RTI", kind, topic, fix)

            writers = [self.writers[e.key] for e in ends if e.key in self.writers]
            unmatched = [(e, seen) for e, handle, seen in writers if handle not in matched(self.topics[e.topic_name])]
            typed = any(e.type_id is not None for e in ends)
            if typed and len(unmatched) == len(writers):
                # a writer is matched as it is discovered, but the builtin topic may show it a moment before: said (and
                # logged, once for good) only once its writers stayed unmatched SETTLE s
                if all(now - seen >= SETTLE for _, seen in unmatched):
                    drop_in = DROP_IN[type(self.topics[ends[0].topic_name])]
                    out.append(
                        finding(
                            "typeInformation",
                            None,
                            "set <resource_limits><type_object_max_serialized_length> "
                            f"to 0 in its participant QoS (the drop-in profile {drop_in} does)",
                        )
                    )
                continue  # nothing of it matches until then: the rest would only repeat it
            for e, seen in sorted(unmatched, key=lambda u: u[0].topic_name):
                sem = self.topics[e.topic_name]
                xcdr1, xcdr2 = _representations(e.qos)
                if sem.spec.xcdr2_only and not xcdr2:
                    mask = (
                        f" and {MASK} in its environment (Connext 7; Connext 6 cannot write it readably)"
                        if sem is Sem.GPS_REPORT
                        else ""
                    )
                    out.append(finding("representation", short(sem), f"set XCDR2 on that writer{mask}"))
                elif now - seen >= SETTLE:
                    partitions = _partitions(e.qos)  # the one thing that fails silently, no incompatible QoS on either side
                    fix = (
                        f"publish it in the default partition, as the console reads (it is in partition {', '.join(partitions)})"
                        if partitions
                        else f"compare its QoS with the drop-in profile {DROP_IN[type(sem)]} ({'XCDR1' if xcdr1 else ''}"
                        f"{'+' if xcdr1 and xcdr2 else ''}{'XCDR2' if xcdr2 else ''} offered)"
                    )
                    out.append(finding("unmatched", short(sem), fix))
            readers = [self.readers[e.key] for e in ends if e.key in self.readers]
            for e, handle, seen in sorted(readers, key=lambda r: r[0].topic_name):
                sem = self.topics[e.topic_name]
                handles = reached(sem)
                if handles is None or handle in handles or now - seen < SETTLE:
                    continue
                partitions = _partitions(e.qos)
                xcdr1, _ = _representations(e.qos)
                fix = (
                    f"subscribe to it in the default partition, where the console publishes (it is in partition "
                    f"{', '.join(partitions)})"
                    if partitions
                    else "accept XCDR_DATA_REPRESENTATION on that reader, which the console writes"
                    if not xcdr1
                    else f"compare its QoS with the drop-in profile {DROP_IN[type(sem)]}"
                )
                out.append(finding("unmatchedReader", short(sem), fix))
        return out


def _take_all(reader: BuiltinDataReader) -> list[Any]:
    """Every sample waiting (DcpsParticipant or DcpsEndpoint, each with its sample_info)."""
    out: list[Any] = []
    while True:
        got = reader.take(N=256)
        out.extend(got)
        if len(got) < 256:
            return out
