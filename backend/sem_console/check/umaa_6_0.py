"""What `sem-check` knows of UMAA 6.0 (the SEM ICD 6.0 of 6 June 2024 and the SA ICD 6.0 for GlobalPoseStatus), as
data: the services, their topics (named after their full type names) with the section and table of each, the rules
for the values of the three reports, the QoS reference (RTI's UMAAQoSLib, since 6.0 mandates no QoS), the decoding
of the samples a checker reads, and the InertialSensor tests it runs. Its commands are built, and their statuses
read, by the console's own 6.0 commanding (`versions/commands.py`, `versions/umaa_6_0.py`).

The command flow of 6.0 is 3.0.1's (the Figure 14 state machine is 3.0.1's Figure 4 under another number, and the
literals keep their names though their ordinals are alphabetical now), plus UPDATED (ICD 6.0 4.1.4.2): a command of
the same source and sessionID with a newer timeStamp restarts the flow at ISSUED/UPDATED. What 6.0 adds to the
checks: the reasons Figure 15 allows for each transition to FAILED (`failed_reason`).
"""

from __future__ import annotations

import math
import re
import uuid
from typing import Any

from cyclonedds.core import InstanceState, Policy, Qos

from UMAA.Common.MaritimeEnumeration.CommandStatusEnumType import CommandStatusEnumType as Status
from UMAA.Common.MaritimeEnumeration.CommandStatusReasonEnumType import CommandStatusReasonEnumType as Reason
from UMAA_6_0.Common.MaritimeEnumeration.InertialSensorCmdEnumModule import InertialSensorCmdEnumType as InsCmd

from sem_console.check.icd import ServiceDef, Version
from sem_console.check.values import in_range, satellite_counts
from sem_console.codec import fastcdr
from sem_console.codec.decode import Item, ReportItem, StatusItem, guid
from sem_console.dds.qos import TopicClass
from sem_console.dds.topics import AnySem, Sem60, Service
from sem_console.versions import UMAA_6_0, umaa_6_0

SERVICES = (
    ServiceDef("GPSStatus", "ICD 6.0 5.1.1, Table 8", (Sem60.GPS_REPORT,)),
    ServiceDef(
        "InertialSensorControl", "ICD 6.0 5.1.2, Table 10", (Sem60.INS_COMMAND, Sem60.INS_COMMAND_STATUS, Sem60.INS_COMMAND_ACK)
    ),
    ServiceDef("InertialSensorStatus", "ICD 6.0 5.1.3, Table 14", (Sem60.INS_REPORT,)),
    ServiceDef("GlobalPoseStatus", "SA ICD 6.0 6.1.6, Table 18", (Sem60.GLOBAL_POSE_REPORT,)),
)
TOPIC_REF: dict[AnySem, str] = {
    Sem60.GPS_REPORT: "ICD 6.0 5.1.1.1, Table 9",
    Sem60.INS_COMMAND_ACK: "ICD 6.0 5.1.2.1, Table 11",
    Sem60.INS_COMMAND_STATUS: "ICD 6.0 5.1.2.2, Table 12",
    Sem60.INS_COMMAND: "ICD 6.0 5.1.2.3, Table 13",
    Sem60.INS_REPORT: "ICD 6.0 5.1.3.1, Table 15",
    Sem60.GLOBAL_POSE_REPORT: "SA ICD 6.0 6.1.6.1, Table 19",
}
FLOW_REFS = {
    "flow": "ICD 6.0 4.1, Figure 14",
    "figure": "Figure 14",
    "every": "ICD 6.0 4.1.4",
    "start": "ICD 6.0 4.1.4 step 3",
    "ack": "ICD 6.0 4.1.4.1 step 1",
    "commanded": "ICD 6.0 4.1.4.1 step 2",
    "executing": "ICD 6.0 4.1.4.1 step 3",
    "complete": "ICD 6.0 4.1.4.3",
    "failed": "ICD 6.0 4.1.4.4",
    "cancel": "ICD 6.0 4.1.4.5",
    "cancel figure": "Figure 26",
    "cleanup": "ICD 6.0 4.1.5, Figure 27",
    "subscribe": "ICD 6.0 4.1.2.1",
    "destination": "ICD 6.0 4.1",
    "ins ack": "ICD 6.0 5.1.2.1, Table 11: the source command",
    "ins report": "ICD 6.0 5.1.2.3 and 5.1.3.1",
    "update": "ICD 6.0 4.1.4.2",
    "reasons": "ICD 6.0 4.1, Figure 15",
}
# The InertialSensor tests, in the order they run: INIT first (it also stops a running alignment), each alignment,
# GPS_ALIGN again (`same`: the alignment it has just completed), TRANSFER_ALIGN (so that the cancel's and the update's
# GPS_ALIGN do not ask for the alignment it is in), and the update last: its GPS_ALIGN, the standard alignment, leaves
# the sensor aligned by GPS.
TESTS: tuple[InsCmd | str, ...] = (
    InsCmd.INIT,
    InsCmd.BEST_ALIGN,
    InsCmd.STATIONARY_ALIGN,
    InsCmd.SNAP_ALIGN,
    InsCmd.GPS_ALIGN,
    "same",
    InsCmd.TRANSFER_ALIGN,
    "cancel",
    "update",
)
LAST = InsCmd.GPS_ALIGN  # the command of the same, cancel and update tests
# Alignments a provider may reject (a vehicle at sea cannot align stationary, a snap or transfer alignment needs a
# feed the command does not carry): FAILED with its reason is an answer (ICD 6.0 4.1.4.4)
REJECTABLE = frozenset({InsCmd.BEST_ALIGN, InsCmd.STATIONARY_ALIGN, InsCmd.SNAP_ALIGN, InsCmd.TRANSFER_ALIGN})
# the InertialSensorOpStatusEnumType literals of each alignment kind (ICD 6.0 5.3.4, Table 28)
_KIND = {
    InsCmd.BEST_ALIGN: "BEST_ALIGNMENT",
    InsCmd.GPS_ALIGN: "GPS_ALIGNMENT",
    InsCmd.SNAP_ALIGN: "SNAP_ALIGNMENT",
    InsCmd.STATIONARY_ALIGN: "STATIONARY_ALIGNMENT",
    InsCmd.TRANSFER_ALIGN: "TRANSFER_ALIGNMENT",
}


def key_ref(sem: AnySem) -> str:
    if sem.spec.cls is TopicClass.COMMAND:
        return "ICD 6.0 5.2.2, Table 17 (UMAACommand)"
    if sem.spec.cls is TopicClass.STATUS:
        return "ICD 6.0 5.2.4, Table 19 (UMAACommandStatusBase)"
    return "ICD 6.0 5.2.3, Table 18 (UMAAStatus)"


# ---- the QoS reference: RTI's UMAAQoSLib (qos/umaa_qos_lib.xml of RTI's UMAA kit) -----------------------------------
QOS_REFERENCE = "RTI's UMAAQoSLib, the reference sem-check compares with: UMAA 6.0 mandates no QoS"
LIVELINESS = {True: 10.0, False: 5.0}  # CommandQoS's lease: a reader's 10 s, a writer's 5 s


def profile(sem: AnySem) -> str:
    """The UMAAQoSLib profile RTI's AssignerQoS gives the topic."""
    return "TelemetryQoS" if sem.spec.cls is TopicClass.REPORT else "CommandQoS"


def _policy(qos: Qos, policy: Any) -> Any:
    try:
        return qos[policy]
    except (KeyError, TypeError):
        return None


def qos_differences(sem: AnySem, qos: Qos, reader: bool) -> list[str]:
    """How an endpoint's QoS differs from UMAAQoSLib's profile for its topic (AssignerQoS: *ReportType TelemetryQoS,
    best-effort; *CommandType, *CommandStatusType and *CommandAckReportType CommandQoS, reliable, keep-all, with a
    liveliness lease of 5 s for a writer and 10 s for a reader; both volatile)."""
    name = profile(sem)
    said = f"UMAAQoSLib::{name} has"
    out = []
    reliable = isinstance(_policy(qos, Policy.Reliability), Policy.Reliability.Reliable)
    if name == "TelemetryQoS" and reliable:
        out.append(f"RELIABLE reliability; {said} BEST_EFFORT")
    if name == "CommandQoS" and not reliable:
        out.append(f"BEST_EFFORT reliability; {said} RELIABLE")
    durability = _policy(qos, Policy.Durability)
    if durability is not None and durability != Policy.Durability.Volatile:
        kind = {
            Policy.Durability.TransientLocal: "TRANSIENT_LOCAL",
            Policy.Durability.Transient: "TRANSIENT",
            Policy.Durability.Persistent: "PERSISTENT",
        }.get(durability, str(durability))
        out.append(f"{kind} durability; {said} VOLATILE")
    if _policy(qos, Policy.Ownership) == Policy.Ownership.Exclusive:
        out.append(f"EXCLUSIVE ownership; {said} SHARED")
    partition = _policy(qos, Policy.Partition)
    if partition is not None and [p for p in partition.partitions if p]:
        out.append(f"partition {', '.join(partition.partitions)}; {said} the default partition")
    if name == "CommandQoS":
        lease = _policy(qos, Policy.Liveliness)
        seconds = getattr(lease, "lease_duration", None)
        want = LIVELINESS[reader]
        if not isinstance(seconds, int) or abs(seconds / 1e9 - want) > 1e-6:
            have = "infinite" if not isinstance(seconds, int) or seconds >= 2**63 - 1 else f"{seconds / 1e9:g} s"
            out.append(f"a liveliness lease of {have}; {said} {want:g} s for a {'reader' if reader else 'writer'}")
    return [f"{d} ({QOS_REFERENCE})" for d in out]


# ---- decoding what the checker reads -------------------------------------------------------------------------------
def parent_in(body: dict[str, Any] | None) -> uuid.UUID | None:
    """The parent a 6.0 report's source says its provider has (its IDL JSON's `source.parentID`); None: not a GUID."""
    parent = ((body or {}).get("source") or {}).get("parentID")
    try:
        return uuid.UUID(parent) if isinstance(parent, str) else None
    except ValueError:
        return None


def decode(sem: Sem60, data: bytes, valid: bool, instance_state: int, received: float) -> Item | None:
    """A 6.0 sample as the checker judges it: a report as the 6.0 IDL's JSON (not the console's model), a status or ack
    as its sample. None when it cannot be decoded."""
    t = sem.spec.type
    try:
        if not valid:
            invalid: list[str] = []
            sample, body = t.deserialize_key(data), None
            source = guid(getattr(sample, "source", None))
        elif sem.spec.cls is TopicClass.REPORT:
            body, invalid = fastcdr.decoder(t).json(data)
            text = umaa_6_0.source_of(body)
            source = fastcdr.guid_uuid(text) if isinstance(text, str) else None
            sample = None
        else:
            sample, body = fastcdr.decoder(t).sample(data), None
            source = guid(getattr(sample, "source", None))
    except Exception:  # any failure means: not decodable
        return None
    if source is None:
        return None
    alive = instance_state == InstanceState.Alive
    if sem.spec.cls is TopicClass.REPORT:
        return ReportItem(sem.spec.name, source, body, invalid, alive and valid, received, version=UMAA_6_0)
    session = guid(getattr(sample, "sessionID", None))
    if session is None:
        return None
    kind = "status" if sem is Sem60.INS_COMMAND_STATUS else "ack"
    return StatusItem(Service.INERTIAL_SENSOR, kind, source, session, sample if valid else None, alive)


# Figure 15: the reasons of FAILED from each state; the first status FAILED/SERVICE_FAILED (4.1.2.1)
FAILED_REASONS: dict[Status | None, frozenset[Reason]] = {
    None: frozenset({Reason.SERVICE_FAILED}),
    Status.ISSUED: frozenset(
        {Reason.VALIDATION_FAILED, Reason.RESOURCE_FAILED, Reason.INTERRUPTED, Reason.TIMEOUT, Reason.SERVICE_FAILED}
    ),
    Status.COMMANDED: frozenset({Reason.RESOURCE_REJECTED, Reason.INTERRUPTED, Reason.TIMEOUT, Reason.SERVICE_FAILED}),
    Status.EXECUTING: frozenset(
        {Reason.OBJECTIVE_FAILED, Reason.RESOURCE_FAILED, Reason.INTERRUPTED, Reason.TIMEOUT, Reason.SERVICE_FAILED}
    ),
}


def failed_reason(before: Status | None, status: Status | int, reason: Reason | int) -> str | None:
    """What Figure 15 finds wrong with a FAILED's reason after the state before; None: nothing."""
    allowed = FAILED_REASONS.get(before)
    if status is not Status.FAILED or allowed is None or not isinstance(reason, Reason) or reason in allowed:
        return None
    state = before.name if before is not None else "(no status)"
    return (
        f"reason {reason.name} is not valid for {state} -> FAILED ({FLOW_REFS['reasons']}: "
        f"{', '.join(sorted(r.name for r in allowed))})"
    )


# ---- what the checker reads of its InertialSensor commands' effect -----------------------------------------------
def kind(status: str) -> InsCmd | None:
    """The command of which an InertialSensorOpStatusEnumType literal is a stage (INIT for INIT); None for a failure
    or a literal of no kind."""
    if status == "INIT":
        return InsCmd.INIT
    if status.endswith("FAILURE"):
        return None
    return next((c for c, k in _KIND.items() if k in status), None)


def shows(state: InsCmd, body: dict[str, Any]) -> bool:
    """Whether an InertialSensorReportType shows the commanded state: INIT for INIT, a stage of the commanded kind of
    alignment for an alignment (ICD 6.0 5.3.3, Table 27; 5.3.4, Table 28), not its failure."""
    return kind(str(body.get("status") or "")) is state


# ---- the values of the reports -------------------------------------------------------------------------------------
SEM_TYPES = "ICD 6.0 5.4, Table 31"
_SENT = re.compile(r"satellites: (\d+) elements")
SA_TYPES = "SA ICD 6.0 6.4, Table 67"


def _identifier(body: dict[str, Any]) -> list[str | None]:
    """The source's parentID: the nil UUID or an RFC 4122 GUID (ICD 6.0 5.2.9, Table 24)."""
    parent = (body.get("source") or {}).get("parentID")
    if parent is None or parent == str(uuid.UUID(int=0)):
        return []
    g = uuid.UUID(str(parent))
    if g.variant != uuid.RFC_4122:
        return [f"source.parentID: {g} is neither the nil UUID nor an RFC 4122 GUID (ICD 6.0 5.2.9, Table 24)"]
    return []


def gps_values(b: dict[str, Any], r: Any, _limits: Any) -> list[str | None]:
    sats = b.get("satellites") or []
    out: list[str | None] = [*_identifier(b)]
    # the decoder keeps the first 300 satellites (the type's bound) and says how many came
    count = max([len(sats)] + [int(m[1]) for p in r.invalid if (m := _SENT.match(p))])
    if count > 300:
        out.append(f"satellites: {count} elements, more than 300 ({TOPIC_REF[Sem60.GPS_REPORT]}: max size = 300)")
    out.append(satellite_counts(b, TOPIC_REF[Sem60.GPS_REPORT]))
    for i, s in enumerate(sats):
        if not s:
            continue
        p = f"satellites[{i}]"
        out.append(in_range(s.get("azimuth"), -math.pi, math.pi, f"{p}.azimuth", f"{SEM_TYPES}: Angle is -pi..pi"))
        out.append(in_range(s.get("elevation"), -math.pi, math.pi, f"{p}.elevation", f"{SEM_TYPES}: Angle is -pi..pi"))
        out.append(in_range(s.get("carrierFrequency"), 0, 1e10, f"{p}.carrierFrequency", f"{SEM_TYPES}: RadioFrequencyHertz"))
        number = s.get("satelliteID")
        if isinstance(number, (int, float)) and (number < 0 or not float(number).is_integer()):
            out.append(f"{p}.satelliteID: {number} is not a non-negative integer ({SEM_TYPES}: NaturalNumberCount)")
    clock = b.get("clock") or {}
    out.append(
        in_range(
            clock.get("referenceCarrierFrequency"),
            0,
            1e10,
            "clock.referenceCarrierFrequency",
            f"{SEM_TYPES}: RadioFrequencyHertz",
        )
    )
    return out


def pose_values(b: dict[str, Any], _r: Any, _limits: Any) -> list[str | None]:
    ref = TOPIC_REF[Sem60.GLOBAL_POSE_REPORT]
    position = b.get("position") or {}
    attitude = b.get("attitude") or {}
    two_pi = 6.28318530718
    out: list[str | None] = [
        *_identifier(b),
        in_range(position.get("geodeticLatitude"), -90, 90, "position.geodeticLatitude", f"{SA_TYPES}: GeodeticLatitude"),
        in_range(position.get("geodeticLongitude"), -180, 180, "position.geodeticLongitude", f"{SA_TYPES}: GeodeticLongitude"),
        in_range(b.get("course"), -two_pi, two_pi, "course", f"{SA_TYPES}: CourseTrueNorth"),
        in_range(
            (attitude.get("pitch") or {}).get("pitch"),
            -math.pi / 2,
            math.pi / 2,
            "attitude.pitch.pitch",
            f"{SA_TYPES}: PitchHalfAngle",
        ),
        in_range((attitude.get("roll") or {}).get("roll"), -two_pi, two_pi, "attitude.roll.roll", f"{SA_TYPES}: RollAngle"),
        in_range(
            (attitude.get("yaw") or {}).get("yaw"),
            -two_pi,
            two_pi,
            "attitude.yaw.yaw",
            "the 6.0 IDL's YawAngle, Measurements.idl",
        ),
        # the optional members, when present (SA ICD 6.0 Table 19: †)
        in_range(b.get("altitude"), 0, math.inf, "altitude", f"{SA_TYPES}: MSLAltitude"),
        in_range(b.get("altitudeAGL"), 0, math.inf, "altitudeAGL", f"{SA_TYPES}: DistanceAGL"),
        in_range(b.get("altitudeASF"), 0, 401_056_000, "altitudeASF", f"{SA_TYPES}: DistanceASF"),
        in_range(b.get("altitudeGeodetic"), -10_000, 700_000, "altitudeGeodetic", f"{SA_TYPES}: GeodeticAltitude"),
        in_range(b.get("depth"), 0, 10_000, "depth", f"{SA_TYPES}: DistanceBSL"),
    ]
    for member, kind in (("attitudeCovariance", "CovarOrientationNED"), ("positionCovariance", "CovarPosNED")):
        for k, v in (b.get(member) or {}).items():
            out.append(in_range(v, -10_000, 10_000, f"{member}.{k}", f"{SA_TYPES}: {kind}"))
    if b.get("altitude") is not None and b.get("depth") is not None and b["altitude"] > 0 and b["depth"] > 0:
        out.append(f"altitude {b['altitude']} m above and depth {b['depth']} m below the sea at once ({ref})")
    return out


def ins_values(b: dict[str, Any], _r: Any, _limits: Any) -> list[str | None]:
    return [*_identifier(b)]


def decoder_finding(problem: str) -> str | None:
    """A decoder's finding with the 6.0 section that states the rule; None for satellites past the bound of 300 (the
    decoder keeps 300), which gps_values reports with its section."""
    if "unknown" in problem and "ordinal" in problem:
        return f"{problem} (ICD 6.0 5.3; SA ICD 6.0 6.3)"
    if "elements, more than" in problem:
        return None
    return f"{problem} ({SEM_TYPES}; {SA_TYPES})"


# The timing test's references (reports.TIMING_REFS): 6.0's DateTime has signed seconds (DateTimeSeconds, Table 31)
TIMING_REFS = {
    "stamp": "ICD 6.0 5.2.1, Table 16",
    "datetime": "ICD 6.0 5.2.6, Table 21; Table 31",
    "utc": "ICD 6.0 5.2.6",
    "publish": "ICD 6.0 4.2: a Service Provider replies to every request; 4.2.1",
    "update": "ICD 6.0 4.2.1: the service is always providing the current data to the bus",
    "seconds": "",
}

V6_0 = Version(
    "6.0",
    "UMAA 6.0 IDL",
    SERVICES,
    TOPIC_REF,
    key_ref,
    (Sem60.GPS_REPORT, Sem60.GLOBAL_POSE_REPORT, Sem60.INS_REPORT),
    FLOW_REFS,
    "ICD 6.0 5.3",
    SEM_TYPES,
    qos_reference=qos_differences,
    value_checks={Sem60.GPS_REPORT: gps_values, Sem60.GLOBAL_POSE_REPORT: pose_values, Sem60.INS_REPORT: ins_values},
    decoder_finding=decoder_finding,
    timing=TIMING_REFS,
)
