"""Discovery tests, one per SEM topic (`discovery.<Topic>`): does the provider serve the topic, with
the UMAA 3.0.1 IDL's type name, members and keys (ICD rules), and with a QoS a consumer on the
project's QoS profile (dds/qos.py: reliable, transient-local) matches? ICD 3.0.1 sets no QoS: a
failure of the QoS checks is marked as the profile's (`Case.profile`), not the ICD's.

The provider's endpoints are those of its participants (the participants whose writers carry its
source GUID). A service counts as offered when any of its topics is; then every topic of it is
required (the service's operations table), and a service not offered at all is skipped: ICD
compliance is per service (ICD 3.2).

A UMAA 6.0 provider's topics are checked the same way against the UMAA 6.0 IDL (`umaa_6_0.V6_0`); 6.0 mandates
no QoS, so its endpoints' QoS is compared with RTI's UMAAQoSLib, and each difference is a warning
(`Case.warn`), not a failure.
"""

from __future__ import annotations

import uuid
from typing import Any, cast

from cyclonedds.builtin_types import DcpsEndpoint
from cyclonedds.core import DDSException, Policy, Qos
from cyclonedds.dynamic import get_types_for_typeid
from cyclonedds.util import duration

from sem_console.check import icd, umaa_6_0
from sem_console.check.observe import Observer
from sem_console.check.results import Case, Progress, Timer
from sem_console.dds.qos import TopicClass
from sem_console.dds.topics import AnySem, Sem

# How long a peer's type object may take to arrive (XTypes type lookup). Cyclone takes a
# dds_duration_t, in nanoseconds: a bare 3000 would be 3 us, and a remote type would go unchecked.
RESOLVE_TIMEOUT = duration(seconds=3)
PROFILE = "a choice of the project's QoS profile, docs/dds.md, not an ICD 3.0.1 rule"


def name(sem: AnySem) -> str:
    return f"discovery.{icd.short(sem)}"


def _policy(qos: Qos, policy: Any) -> Any:
    """The QoS's policy of this kind (Qos[...] gives None for a kind the QoS does not set)."""
    try:
        return qos[policy]
    except (KeyError, TypeError):
        return None


def _common_problems(qos: Qos, ref: str) -> list[str]:
    problems = []
    if _policy(qos, Policy.Ownership) == Policy.Ownership.Exclusive:
        problems.append(f"EXCLUSIVE ownership: a consumer with the default SHARED ownership does not match it ({PROFILE}; {ref})")
    partition = _policy(qos, Policy.Partition)
    if partition is not None and [p for p in partition.partitions if p]:
        problems.append(
            f"partition {', '.join(partition.partitions)}: a consumer in the default partition does not match it "
            f"({PROFILE}; {ref})"
        )
    return problems


def delivery_ref(sem: Sem) -> str:
    """Where the ICD has the provider's samples of this topic reach its consumers."""
    if sem.spec.cls is TopicClass.REPORT:
        return "ICD 4.2.1: the DDS bus delivers the provider's reports to the consumer"
    if sem.spec.cls is TopicClass.STATUS:
        return "ICD 4.1: the provider updates the consumer through its command status and ack"
    return "ICD 4.1: the provider responds to every command addressed to it"


def writer_problems(sem: Sem, qos: Qos) -> list[str]:
    """Why a consumer on the project's QoS profile would not (reliably, durably) receive this writer's samples."""
    problems = []
    what = "report" if sem.spec.cls is TopicClass.REPORT else "status"
    if not isinstance(_policy(qos, Policy.Reliability), Policy.Reliability.Reliable):
        problems.append(
            f"BEST_EFFORT reliability: a consumer on the project's QoS profile (RELIABLE) does not match it "
            f"({PROFILE}; {delivery_ref(sem)})"
        )
    durability = _policy(qos, Policy.Durability)
    if durability is None or durability == Policy.Durability.Volatile:
        ref = "ICD 4.2.1.1" if sem.spec.cls is TopicClass.REPORT else "ICD 4.1.2"
        problems.append(
            f"VOLATILE durability: a consumer on the project's QoS profile (TRANSIENT_LOCAL) does not match it, "
            f"and one that starts later never gets the {what} already published ({PROFILE}; {ref})"
        )
    problems += _common_problems(qos, delivery_ref(sem))
    rep = _policy(qos, Policy.DataRepresentation)
    if sem.spec.xcdr2_only and (rep is None or rep.use_cdrv0_representation or not rep.use_xcdrv2_representation):
        problems.append(
            "XCDR1 data representation for a type with @optional members: a consumer accepts XCDR2 only for "
            f"it (vendors lay out optional members differently in XCDR1; {PROFILE}; {delivery_ref(sem)})"
        )
    return problems


def reader_problems(sem: Sem, qos: Qos) -> list[str]:
    """Why a consumer's command writer (dds/qos.py writer_qos) would not reliably reach this reader."""
    problems = []
    if not isinstance(_policy(qos, Policy.Reliability), Policy.Reliability.Reliable):
        problems.append(
            f"BEST_EFFORT reliability: the provider can lose a command the consumer then waits on ({PROFILE}; "
            "ICD 4.1: the provider responds to every command addressed to it)"
        )
    durability = _policy(qos, Policy.Durability)
    if durability is None or durability == Policy.Durability.Volatile:
        problems.append(
            f"VOLATILE durability: commands already on the bus when the provider starts never reach it ({PROFILE}; "
            "ICD 4.1.2.1: the provider handles persisted commands)"
        )
    elif durability in (Policy.Durability.Transient, Policy.Durability.Persistent):
        problems.append(
            f"{durability} durability requested: a consumer's TRANSIENT_LOCAL command writer does not match it "
            f"({PROFILE}; {delivery_ref(sem)})"
        )
    problems += _common_problems(qos, delivery_ref(sem))
    deadline = _policy(qos, Policy.Deadline)
    if deadline is not None and 0 <= deadline.deadline < 2**63 - 1:
        problems.append(
            f"a deadline of {deadline.deadline / 1e9:g} s requested: a consumer's command writer (no deadline) "
            f"does not match it ({PROFILE}; {delivery_ref(sem)})"
        )
    rep = _policy(qos, Policy.DataRepresentation)
    if rep is not None and not sem.spec.xcdr2_only and not rep.use_cdrv0_representation:
        problems.append(
            "XCDR1 not accepted: a consumer's command writer offers XCDR1 (the type has no @optional member; "
            f"{PROFILE}; {delivery_ref(sem)})"
        )
    return problems


class TypeCheck:
    """Compares an endpoint's type with the UMAA 3.0.1 IDL; peers' type objects resolved once each."""

    def __init__(self, observer: Observer) -> None:
        self.observer = observer
        self._resolved: dict[bytes, type | str] = {}

    def _resolve(self, endpoint: DcpsEndpoint) -> type | str:
        type_id = endpoint.type_id
        if type_id is None:  # check() says so before it asks
            return "it sent no type information"
        key = type_id.serialize()
        if key not in self._resolved:
            try:
                # cyclonedds annotates the type as an instance; it is the class (its docstring: "IdlStruct subclass")
                resolved = get_types_for_typeid(self.observer.bus.participant, type_id, RESOLVE_TIMEOUT)[0]
                self._resolved[key] = cast("type", resolved)
            except (DDSException, Exception) as e:  # any failure means: not resolvable
                self._resolved[key] = f"its type object could not be resolved ({e})"
        return self._resolved[key]

    def check(self, sem: AnySem, endpoint: DcpsEndpoint, role: str, case: Case, version: icd.Version = icd.V3_0_1) -> list[str]:
        problems = []
        expected = icd.type_name(sem)
        ref, idl = version.topic_ref[sem], f"the {version.idl}"
        if endpoint.type_name != expected:
            problems.append(f"type name {endpoint.type_name}; {idl} names it {expected} ({ref})")
        if endpoint.type_id is None:
            case.caveat(f"members and keys not checked: {role} {endpoint.key} sent no type information")
            return problems
        t = self._resolve(endpoint)
        if isinstance(t, str):
            case.caveat(f"members and keys not checked: {role} {endpoint.key}: {t}")
            return problems
        ours, theirs = icd.members(sem.spec.type), list(getattr(t, "__annotations__", {}))
        missing, extra = [m for m in ours if m not in theirs], [m for m in theirs if m not in ours]
        if missing or extra:
            problems.append(
                f"members differ from {idl}:"
                + (f" missing {', '.join(missing)}" if missing else "")
                + (";" if missing and extra else "")
                + (f" extra {', '.join(extra)}" if extra else "")
                + f" ({ref})"
            )
        elif theirs != ours:
            problems.append(f"members in another order than {idl} ({', '.join(theirs)}): the order is the wire layout ({ref})")
        want, have = icd.keys(sem.spec.type), icd.keys(t)
        if want != have:
            problems.append(
                f"key members {{{', '.join(sorted(have)) or 'none'}}}; {idl} keys "
                f"{{{', '.join(sorted(want))}}} ({version.key_ref(sem)}: the members marked *)"
            )
        extensibility = getattr(t, "__idl_annotations__", {}).get("extensibility")
        case.note(
            f"{role} {endpoint.key}: type {endpoint.type_name}, keys {{{', '.join(sorted(have))}}}"
            + (f", {extensibility}" if extensibility else "")
        )
        return problems


def run(
    observer: Observer, provider: uuid.UUID, selected: Any, progress: Progress | None = None, version: icd.Version = icd.V3_0_1
) -> list[Case]:
    participants = observer.source_participants.get(provider, set())
    types = TypeCheck(observer)
    cases = []
    for service in version.services:
        offered = {
            sem: observer.endpoints(participants, sem, writers=sem.spec.cls is not TopicClass.COMMAND) for sem in service.topics
        }
        for sem in service.topics:
            if not selected(name(sem)):
                continue
            case = Case(name(sem))
            with Timer(case, progress):
                _check_topic(observer, types, sem, service, offered, case, version)
            cases.append(case)
    return cases


def _check_topic(
    observer: Observer,
    types: TypeCheck,
    sem: AnySem,
    service: icd.ServiceDef,
    offered: dict[AnySem, list[DcpsEndpoint]],
    case: Case,
    version: icd.Version = icd.V3_0_1,
) -> None:
    command = sem.spec.cls is TopicClass.COMMAND
    role = "reader" if command else "writer"
    if not any(offered.values()):
        case.skip(f"the provider does not offer the {service.name} service (no endpoint of its topics)")
        return
    endpoints = offered[sem]
    if not endpoints:
        others = ", ".join(icd.short(s) for s, e in offered.items() if e)
        case.fail(
            f"no {role} of {sem.spec.name}, though the provider offers {service.name} ({others}); "
            f"the service has every topic of {service.section}"
        )
        return
    findings = observer.peer_findings()  # what another vendor's operator must change, in their terms (dds/vendors.py)
    for e in endpoints:
        # (problem, a choice of the project's QoS profile rather than an ICD rule); another vendor's fix in its terms
        # first (its QoS and type information, to match the profile): the run's table shows a test's first failure only
        problems = [
            (f.message, True) for f in findings if f.participant == str(e.participant_key) and f.topic in (icd.short(sem), None)
        ]
        problems += [(p, False) for p in types.check(sem, e, role, case, version)]
        warned: list[str] = []
        if version.qos_reference is not None:  # no QoS mandated: a difference from the reference is a warning
            warned = version.qos_reference(sem, e.qos, command)
            for w in warned:
                case.warn(f"{role} {e.key}: {w}")
        elif isinstance(sem, Sem):
            problems += [(p, True) for p in (reader_problems(sem, e.qos) if command else writer_problems(sem, e.qos))]
        if not command and not problems and not observer.matched_by_consumer(sem, e):
            consumer = (
                "a consumer on the project's QoS profile"
                if version.qos_reference is None
                else "a reader that accepts any QoS (best-effort, volatile, XCDR1 and XCDR2)"
            )
            # what no reader of the default partition and SHARED ownership matches, whatever its type
            apart = [w.split(";")[0] for w in warned if w.startswith(("EXCLUSIVE ownership", "partition "))]
            why = (
                f"its {' and its '.join(apart)}: the checker's readers are SHARED, in the default partition"
                if apart
                else f"its type is not assignable to the {version.idl}'s: {version.topic_ref[sem]}"
            )
            problems.append((f"{consumer} did not match it ({why})", False))
        for p, profile in problems:
            case.fail(f"{role} {e.key}: {p}", profile=profile)
        if not problems and version.qos_reference is None:
            case.note(
                f"{role} {e.key}: QoS fits "
                + ("a consumer's command writer" if command else "a consumer on the project's QoS profile")
            )
        elif not problems and not case.warnings:
            case.note(f"{role} {e.key}: QoS as RTI's UMAAQoSLib::{umaa_6_0.profile(sem)}")


def offered_services(observer: Observer, provider: uuid.UUID, version: icd.Version = icd.V3_0_1) -> set[str]:
    """The services of which the provider has any endpoint (see the module docstring)."""
    participants = observer.source_participants.get(provider, set())
    return {
        s.name
        for s in version.services
        for sem in s.topics
        if observer.endpoints(participants, sem, writers=sem.spec.cls is not TopicClass.COMMAND)
    }
