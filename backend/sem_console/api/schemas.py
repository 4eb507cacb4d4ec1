"""The console's REST and WebSocket contract. The frontend's TypeScript types are generated from
the OpenAPI document and /api/ws-schema, which are built from these models."""

from __future__ import annotations

import re
import typing
import uuid
from datetime import datetime
from typing import Annotated, Any, Literal

from pydantic import AfterValidator, BaseModel, BeforeValidator, ConfigDict, Field, TypeAdapter
from sqlmodel import SQLModel

# the models the API shares with the lower rooms are written once, in core/contract.py; this module is the API's whole
# contract, so it names them again (`X as X`: re-exported)
from sem_console.core.config import MAX_NAME, MAX_SHELF_MINUTES, NOT_PRINTABLE, PRINTABLE
from sem_console.core.contract import CAMEL
from sem_console.core.contract import Command as Command
from sem_console.core.contract import CommandMessage as CommandMessage
from sem_console.core.contract import InsCommandName as InsCommandName
from sem_console.core.contract import InsStateName as InsStateName
from sem_console.core.contract import LinkConfig as LinkConfig
from sem_console.core.contract import LinkState as LinkState
from sem_console.core.contract import ProviderMessage as ProviderMessage
from sem_console.core.contract import ProviderSummary as ProviderSummary
from sem_console.core.contract import RelayHop as RelayHop
from sem_console.core.contract import ReportTopic as ReportTopic
from sem_console.core.contract import StrictModel as _Model
from sem_console.core.contract import TopicHealth as TopicHealth
from sem_console.core.contract import Transition as Transition
from sem_console.core.contract import TransitionMessage as TransitionMessage
from sem_console.core.versions import UmaaVersion
from sem_console.storage.models import AlarmHandled, AlarmRaised, TaskOwned, TaskPlanned, TaskProgress


class ReportEnvelope(_Model):
    report: dict[str, Any] = Field(
        description="the sample, member for member as in the IDL; its type per topic is ReportTypes in /api/ws-schema"
    )
    invalid: list[str] = Field(description="'member.path: why' for each value that is not a valid reading")
    receivedAt: float


class ProviderDetail(ProviderSummary):
    reports: dict[ReportTopic, ReportEnvelope | None]


class FixBrief(_Model):
    """Of a vehicle's newest GPSFixReport, what the map draws of a vehicle not selected."""

    lat: float | None = Field(description="position2DWithTime's latitude, degrees")
    lon: float | None = Field(description="position2DWithTime's longitude, degrees")
    course: float | None = Field(description="trueCourse, radians")
    sog: float | None = Field(description="SOG, m/s")
    latLongValid: bool | None = Field(description="GPSLatLongValid")
    invalid: list[str] = Field(description="the report's invalid values, as its envelope has them")
    receivedAt: float = Field(description="when the console received it, as its envelope has it")
    timeStamp: dict[str, Any] | None = Field(
        None, description="its timeStamp, for a vehicle seen through a relay (the age of its data); absent otherwise"
    )


class FixStatusBrief(_Model):
    """Of a vehicle's newest GPSFixStatusReport, what the page draws of a vehicle not selected."""

    fixValid: bool | None
    originLat: float | None = Field(description="originPosition's latitude, degrees")
    originLon: float | None = Field(description="originPosition's longitude, degrees")
    receivedAt: float


class InsBrief(_Model):
    """Of a vehicle's newest InertialSensorReport, what the page draws of a vehicle not selected."""

    state: str | None
    status: str | None
    receivedAt: float


class VehicleBrief(_Model):
    """A vehicle as a client that named another draws it (its list row, fleet-bar chip and map dot): a tenth of a
    ProviderDetail's bytes. GET /api/providers/{id} has the rest."""

    id: str
    name: str | None
    link: LinkState
    umaaVersion: UmaaVersion
    jausId: str | None
    relay: RelayHop | None
    fix: FixBrief | None = Field(description="null: no GPSFixReport yet")
    fixStatus: FixStatusBrief | None = Field(description="null: no GPSFixStatusReport yet")
    ins: InsBrief | None = Field(description="null: no InertialSensorReport yet")


CONFIRM_LOST = (
    "the operator has seen that the vehicle's link is lost and commands it anyway; without it a command to a "
    "lost vehicle is refused with 409"
)


def _trimmed(v: Any) -> Any:
    """Trimmed; empty is None (back to the configured name)."""
    return (v.strip() or None) if isinstance(v, str) else v


_VISIBLE = r"\x00-\x1f\x7f-\x9f\u200b-\u200f\u2028-\u202e\u2060-\u206f\ufeff"  # PRINTABLE's excluded characters
# printable (PRINTABLE), with at least one character that is not a space: what an operator writes as a reason
WORDS = rf"^[^{_VISIBLE}]*[^\s{_VISIBLE}][^{_VISIBLE}]*$"


def _words(v: str) -> str:
    if not re.match(WORDS, v):
        raise ValueError("write the reason in printable words (not only spaces, no control characters)")
    return v.strip()


Reason = Annotated[str, Field(min_length=1, max_length=200, json_schema_extra={"pattern": WORDS}), AfterValidator(_words)]


def _printable(v: str) -> str:
    if not re.match(PRINTABLE, v):
        raise ValueError(NOT_PRINTABLE)
    return v


class VehicleName(_Model):
    name: Annotated[
        Annotated[str, Field(max_length=MAX_NAME, json_schema_extra={"pattern": PRINTABLE}), AfterValidator(_printable)] | None,
        BeforeValidator(_trimmed),
    ] = Field(description="1 to 40 printable characters (trimmed); empty or null: back to the --vehicle-names name (or none)")


class VehicleNameShown(_Model):
    name: str | None = Field(description="the vehicle's name now: the one set, else its --vehicle-names name, or null")


class InertialSensorRequest(_Model):
    state: Literal[InsStateName, InsCommandName] = Field(
        description=(
            "a state of the vehicle's UMAA version (its umaaVersion): 3.0.1, OFF, ON or RESTARTING; 6.0, BEST_ALIGN, "
            "GPS_ALIGN, INIT, SNAP_ALIGN, STATIONARY_ALIGN or TRANSFER_ALIGN; one of the other version is refused (422)"
        )
    )
    confirmLost: bool = Field(False, strict=True, description=CONFIRM_LOST)


class GpsFixRequest(_Model):
    """A GPS fix takes no parameters but the lost-vehicle confirmation: the body is `{}` (or `{"confirmLost": true}`)."""

    confirmLost: bool = Field(False, strict=True, description=CONFIRM_LOST)


class Problem(_Model):
    detail: str = Field(description="what is wrong, in one line")


class ValidationProblem(_Model):
    detail: str = Field(description="every problem, '; ' separated")
    errors: list[str] = Field(description="one 'location: message' per problem, e.g. 'body.state: Field required'")


class AuditEntry(_Model):
    id: int
    at: float = Field(description="UTC seconds since the epoch")
    outcome: Literal["accepted", "refused", "rate-limited"] = Field(
        description="rate-limited: refused, and the client's further refusals this minute are not recorded"
    )
    status: int = Field(description="the HTTP status answered")
    method: str
    path: str
    client: str | None = Field(description="the client's address")
    origin: str | None = Field(description="the request's Origin header")
    operator: str | None
    sessionId: str | None = Field(description="the command created or canceled (accepted requests)")
    reason: str


class Operator(_Model):
    operator: str | None = Field(description="the name the token belongs to; null when the console has no operator tokens")


class ConsoleLoad(_Model):
    """Whether this console is the one behind (console/load.py): while it is, a vehicle's silence is not judged (its
    link "unchecked": not checked, console behind), and if that withheld a vehicle's check it raises one
    console-overloaded alarm of its own, not a link-lost per vehicle. The delays: the worst of the last second."""

    behind: bool = Field(
        description="the console's event loop ran late or handled samples late (over 0.5 s) within the last comms-lost "
        "timeout: vehicles' silences are its own, not judged"
    )
    behindSince: float | None = Field(description="UTC seconds since when it is behind; null while it keeps up")
    loopDelayMs: float = Field(description="how late its event loop ran its 5 Hz tick, the worst of the last second")
    ingestLagMs: float = Field(
        description="how long a sample waited between its take from DDS and its handling, the worst of the last second"
    )
    cpuCores: float = Field(description="the console process's CPU over the last second, in cores")
    samplesLost: int = Field(description="samples Cyclone DDS reported lost to the console's readers since it started")
    vehiclesNotChecked: int = Field(description="vehicles whose silence was not judged while it was behind")


class DdsSecurity(_Model):
    secured: bool = Field(description="the console joined the DDS bus under DDS Security (false: an open bus)")
    identity: str | None = Field(None, description="the identity it joined under: its certificate's common name")
    subject: str | None = Field(None, description="the certificate's subject (RFC 4514)")
    source: str | None = Field(None, description="where its documents are: --dds-security DIR or CYCLONEDDS_URI")
    notAfter: float | None = Field(None, description="the certificate's end, UTC seconds since the epoch")


class Health(_Model):
    status: Literal["ok"]
    consoleId: str
    domain: int
    authRequired: bool = Field(description="commands need an operator token")
    readAuthRequired: bool = Field(description="reads (REST and /ws) need an operator token too (--auth-reads)")
    ddsNetwork: str | None = Field(
        None,
        description="where the console looks for vehicles, in one line: the interface and "
        "discovery (unicast peers or multicast), or CYCLONEDDS_URI; null in a replay",
    )
    ddsSecurity: DdsSecurity | None = Field(
        None, description="whether the console's DDS bus is secured and under which identity; null in a replay"
    )
    basemap: bool = Field(False, description="the console serves a PMTiles chart at /api/basemap.pmtiles (--basemap)")
    replay: bool = Field(
        description="the console serves a recording (sem-console --replay), not DDS: read-only, "
        "with playback controls (/api/replay)"
    )
    consoleName: str = Field("", description="this console station's --console-name")
    databaseUnavailableSince: float | None = Field(
        None,
        description=(
            "UTC seconds since when the console's PostgreSQL database cannot be reached (shared history unavailable): "
            "monitoring goes on, commands, transitions, audit and acknowledgements are held here and written when it is "
            "back; null while it can be reached"
        ),
    )
    databaseWritesHeld: int = Field(0, description="writes held for the database (at most 50000; past it the oldest go)")
    databaseWritesDropped: int = Field(
        0,
        description="held writes dropped since the console started, the oldest first, "
        "because more than 50000 were held: lost from the shared history",
    )
    load: ConsoleLoad | None = Field(None, description="whether the console is the one behind (null in a replay)")


class GatewayState(_Model):
    name: Literal["aspn", "jaus", "foxglove"]
    enabled: bool = Field(description="on (its option was given) or off")
    endpoint: str | None = Field(description="where it publishes or listens")
    messagesOut: int = Field(description="messages sent since start")
    messagesPerSecond: float = Field(description="messages sent per second over the last 5 s")
    lastError: str | None
    lastErrorAt: float | None = Field(description="UTC seconds since the epoch")
    counters: dict[str, int] = Field(
        description="received, malformed (by reason), answered, left out (by reason), dropped: "
        "queue full (ASPN), "
        "report time outside u32: console time sent (JAUS), left out: no subscriber, left out: no valid position "
        "(Foxglove), errors"
    )


class PeerFinding(_Model):
    """What another vendor's participant must change for the console to read it (docs/dds.md, "Other DDS vendors")."""

    participant: str = Field(description="the participant's GUID")
    name: str = Field(description="its name as it announces it (RTI: the participant's name in its XML), else its GUID")
    vendor: Literal["RTI"] = Field(description="the vendor, from the GUID's vendor id (RTI Connext: 01.01)")
    kind: Literal["typeInformation", "representation", "unmatched", "unmatchedReader"] = Field(
        description="typeInformation: it sends XTypes type information the console cannot use, so none of its SEM topics "
        "match; representation: a GPSReport or GPSFixReport writer offers XCDR1; unmatched: another SEM "
        "writer of it that no reader of the console matches; unmatchedReader: a command reader of it that "
        "the console's command writer does not match (its commands would go nowhere)"
    )
    topic: str | None = Field(description="the SEM topic (short name, e.g. GPSReport); null for the whole participant")
    fix: str = Field(description="what to change, in the vendor's terms")
    message: str = Field(description="the whole finding in one line, as logged: who, what, the fix and the docs")


class Metrics(_Model):
    uptimeSeconds: float
    samplesLost: int = Field(0, description=ConsoleLoad.model_fields["samplesLost"].description)
    samplesTaken: int = Field(description="samples taken from DDS since start (all three readers of every SEM topic)")
    samplesDecoded: int = Field(
        description="of those, decoded and applied: a writer's samples only from its owner, the most "
        "reliable of a topic's readers it matches, so each sample is decoded once"
    )
    samplesByReader: dict[str, int] = Field(
        description="samplesDecoded per owner reader: reliableTransientLocal, reliableVolatile, bestEffort"
    )
    undecodableSamples: int
    incompatibleWriters: dict[str, int] = Field(
        description="per topic, writers whose QoS no reader of the console accepts, so "
        "nothing of theirs is read (e.g. an XCDR1 GPSReport or GPSFixReport "
        "writer: README, 'Other DDS vendors')"
    )
    peerFindings: list[PeerFinding] = Field(
        description="other vendors' participants (today RTI Connext) that the console "
        "sees in discovery but cannot read, each with the exact fix"
    )
    reportsApplied: int = Field(description="report samples applied to the state (after conflation and de-duplication)")
    reportWindowWaits: int = Field(
        description="report takes that waited for the conflation window (report_interval): input "
        "dense enough to batch; sparse input is taken as it arrives"
    )
    wsClients: int
    wsMessagesPublished: int = Field(description="messages handed to WebSocket clients, one per client")
    wsClientsDropped: int
    providers: int
    commandsInMemory: int
    historyRowsWritten: int = Field(description="track and chart points written to the database")
    historyRowsPruned: int = Field(description="track and chart points removed for being older than the retention")
    historyRowsRolledUp: int = Field(
        description="track and chart points removed by the rollup (older than --track-rollup-after-hours: the first "
        "of each vehicle's --track-rollup-seconds, and each change of its GPSLatLongValid or fixValid, is kept)"
    )
    historyWriteSecondsMax: float = Field(
        description="longest batched write of track and chart points (in a worker thread, off the event loop), seconds"
    )


class RecordingStatus(_Model):
    state: Literal["off", "recording", "failed"] = Field(
        description="failed: the recording stopped on an error (e.g. a full disk), see `error`"
    )
    directory: str = Field(description="where the recordings are written")
    file: str | None = Field(description="the file being written (recording), or the last one written")
    startedAt: float | None = Field(description="when this recording started, UTC seconds (null unless recording)")
    messages: int = Field(description="messages written by this recording (all its files)")
    dropped: int = Field(description="samples dropped because the writer fell behind (its queue was full)")
    error: str | None = Field(description="why the recording stopped, when it failed")
    writerCpuSeconds: float = Field(0.0, description="CPU seconds the recording's writer thread has used (bench/recording.py)")


class RecordingFile(_Model):
    name: str = Field(description="<UTC start time>.mcap, e.g. 20261122T101530.123Z.mcap")
    size: int = Field(description="bytes")
    start: float = Field(description="UTC seconds of the first message (of the file's name while it is written)")
    end: float | None = Field(description="UTC seconds of the last message; null while recording or when cut short")
    state: Literal["recording", "complete", "incomplete"] = Field(
        description="incomplete: it has no MCAP summary (the console stopped on an error or was killed); "
        "MCAP readers still read its messages"
    )


class RecordingRequest(_Model):
    action: Literal["start", "stop"]


class ReplayStatus(_Model):
    file: str = Field(description="the recording being replayed")
    state: Literal["playing", "paused"] = Field(description="paused at the end once it has played to the end")
    speed: float = Field(description="recording seconds per wall-clock second, 0.25 to 20")
    position: float = Field(description="the instant shown, UTC seconds (start..end); the console's clock")
    start: float = Field(description="the recording's first message, UTC seconds")
    end: float = Field(description="the recording's last message, UTC seconds")


class ReplayPlay(_Model):
    """Play from the position (from the start when at the end)."""

    action: Literal["play"]


class ReplayPause(_Model):
    action: Literal["pause"]


class ReplaySeek(_Model):
    """Show the state at `position`: rebuilt from the recording, sent to every client as a fresh snapshot."""

    action: Literal["seek"]
    position: float = Field(
        strict=True, allow_inf_nan=False, description="UTC seconds; outside the recording it is taken as its start or end"
    )


class ReplaySpeed(_Model):
    action: Literal["speed"]
    speed: float = Field(strict=True, ge=0.25, le=20, description="recording seconds per wall-clock second")


ReplayRequest = Annotated[ReplayPlay | ReplayPause | ReplaySeek | ReplaySpeed, Field(discriminator="action")]


# ---- CoMap: world model (GeoJSON), tasks, vehicles --------------------------------------------
CoverageName = Literal["COMPLETED", "PARTIAL", "NONE"]
SensorName = Literal["ANY", "SIDESCAN", "MULTIBEAM", "CAMERA", "MAGNETOMETER"]
TaskState = Literal["ASSIGNED", "ACCEPTED", "REJECTED", "IN_PROGRESS", "HELD", "COMPLETED", "ERROR", "INTERRUPTED"]
ISO_8601 = re.compile(r"\d{4}-\d{2}-\d{2}([Tt ].*)?")


def iso_only(v: Any) -> Any:
    """ISO 8601 only: pydantic would also take a number as seconds since the epoch."""
    if isinstance(v, str) and not ISO_8601.fullmatch(v.strip()):
        raise ValueError("expected an ISO 8601 date and time, e.g. 2026-11-22T08:00:00Z")
    return v


def _iso_string(v: Any) -> Any:
    if v is not None and not isinstance(v, str):
        raise ValueError("expected an ISO 8601 date and time as a string, e.g. 2026-11-22T08:00:00Z")
    return iso_only(v)


def _no_bool(v: Any) -> Any:
    if isinstance(v, bool):
        raise ValueError("must be a number, not a boolean")
    return v


NoBool = BeforeValidator(_no_bool)
Finite = Annotated[float, Field(allow_inf_nan=False), NoBool]
Lon = Annotated[float, Field(ge=-180, le=180, allow_inf_nan=False), NoBool]
Lat = Annotated[float, Field(ge=-90, le=90, allow_inf_nan=False), NoBool]
Position = Annotated[
    tuple[Lon, Lat] | tuple[Lon, Lat, Finite], Field(description="[longitude, latitude(, altitude m)], degrees (GeoJSON)")
]
FeatureId = Annotated[int, Field(ge=0, le=0xFFFE), NoBool]


class FeatureProperties(BaseModel):
    model_config = ConfigDict(extra="allow")
    featureId: FeatureId | None = Field(
        None, description="the CoMap feature id (u16); the console numbers a feature without one when it takes the model"
    )
    coverage: CoverageName | None = Field(None, description="the feature's CoverageState, or null when none is known")


class PointGeometry(_Model):
    type: Literal["Point"]
    coordinates: Position


class LineStringGeometry(_Model):
    type: Literal["LineString"]
    coordinates: Annotated[list[Position], Field(min_length=2, max_length=2, description="a CoMap line has 2 vertices")]


class PolygonGeometry(_Model):
    type: Literal["Polygon"]
    coordinates: Annotated[
        list[Annotated[list[Position], Field(min_length=3, max_length=4096)]],
        Field(min_length=1, max_length=1, description="one ring, no holes; closed or not"),
    ]


class GeoJsonFeature(_Model):
    type: Literal["Feature"]
    id: Annotated[int, NoBool] | str | None = Field(None, description="GeoJSON feature id (the console gives featureId)")
    geometry: Annotated[PointGeometry | LineStringGeometry | PolygonGeometry, Field(discriminator="type")]
    properties: FeatureProperties


class WorldModelIn(_Model):
    """A GeoJSON FeatureCollection: CoMap's 1 vertex point, 2 line, 3+ polygon."""

    type: Literal["FeatureCollection"]
    features: Annotated[list[GeoJsonFeature], Field(max_length=1000)]


class WorldModel(_Model):
    type: Literal["FeatureCollection"]
    features: list[GeoJsonFeature]
    updatedAt: float | None = Field(description="UTC seconds of the last change, null before any")
    source: str | None = Field(
        description="'operator' (a PUT), 'imc:<system id>' (a WorldModel received) or 'coverage' (a CoverageState merged)"
    )


class LatLon(_Model):
    lat: Lat = Field(description="degrees")
    lon: Lon = Field(description="degrees")


class _TaskRequest(_Model):
    vehicle: uuid.UUID = Field(
        description="the UMAA provider GUID; it needs an IMC system id (--imc-vehicles)",
        examples=["77b2ceb8-5afe-554e-8450-93db17c48923"],
    )  # sem-sim's vehicle 1
    sensor: SensorName = Field("ANY", description="survey: the sensor to survey with")
    resolution: Annotated[float, Field(gt=0, le=1e6, allow_inf_nan=False), NoBool] = Field(1.0, description="survey: px/m²")
    deadline: Annotated[datetime | None, BeforeValidator(_iso_string)] = Field(
        None, description="ISO 8601 (UTC when no offset is given); default: an hour from now"
    )


class SurveyTaskRequest(_TaskRequest):
    """A SurveyTask of a world model feature."""

    kind: Literal["survey"]
    featureId: FeatureId = Field(description="the world model feature to survey", examples=[1])
    point: LatLon | None = Field(None, description="not used by a survey")


class MoveTaskRequest(_TaskRequest):
    """A MoveTask to a point."""

    kind: Literal["move"]
    point: LatLon = Field(description="the destination")
    featureId: FeatureId | None = Field(None, description="not used by a move")


TaskRequest = Annotated[SurveyTaskRequest | MoveTaskRequest, Field(discriminator="kind")]


class _TaskPoint(SQLModel):
    point: LatLon | None


class _TaskSynch(SQLModel):
    synch: Literal["HOLD", "RESUME", "INTERRUPT"] | None = Field(description="the last SynchAdmin sent for this task")


class Task(TaskOwned, _TaskSynch, TaskProgress, _TaskPoint, TaskPlanned):
    model_config = CAMEL
    kind: Literal["survey", "move"]
    sensor: SensorName | None
    state: TaskState


class SynchRequest(_Model):
    action: Literal["HOLD", "RESUME", "INTERRUPT"]


class Capability(_Model):
    kind: Literal["AREA_SURVEY", "POINT_SURVEY", "MOVE"]
    sensor: str | None = None
    resolution: float | None = Field(None, description="px/m²")
    resolutionBathymetryFactor: float | None = None
    coverageRate: float | None = Field(None, description="m²/s")
    coverageBathymetryFactor: float | None = None
    duration: float | None = Field(None, description="s")
    speed: float | None = Field(None, description="m/s")


class ComapVehicle(_Model):
    imcId: int | None = Field(description="its IMC system id, null for a provider not in --imc-vehicles")
    providerId: str | None = Field(description="the provider GUID from --imc-vehicles, null for a system not in the table")
    capabilities: list[Capability] | None = Field(description="from its last VehicleCapabilities, null before any")
    lastHeard: float | None = Field(description="UTC seconds of its last IMC message")


class ComapStatus(_Model):
    enabled: bool = Field(description="false unless the console was started with --imc-port")
    imcId: int
    port: int | None
    peers: list[str]
    counters: dict[str, int] = Field(
        description="datagrams received, accepted, sent; dropped ones per reason: truncated, "
        "bad_sync, bad_size, bad_crc, unknown_id, bad_message; notForUs; refusedWorldModels: "
        "WorldModels accepted as datagrams whose model was not used (a feature without "
        "vertices, a vertex out of range; the log names it)"
    )
    vehicles: list[ComapVehicle]


# ---- Alarms (ISA-18.2 states, derived on the server from the console's state) ------------------------
AlarmKind = Literal[
    "link-lost",
    "ins-failure",
    "fix-lost",
    "no-fix-after-command",
    "command-unanswered",
    "command-failed",
    "command-interrupted",
    "flow-violation",
    "executed-late",
    "recording-failed",
    "silence-overdue",
    "relay-silent",
    "console-overloaded",
]
AlarmState = Literal["active-unacknowledged", "active-acknowledged", "cleared-unacknowledged"]


class AlarmShelf(_Model):
    """An alarm shelved by an operator: out of view (no tone, not counted unacknowledged) until `until`, on every
    station of the database; it comes back at once when it gets worse (a new alarm of its vehicle at least as severe)."""

    id: str
    reason: str
    by: str | None = Field(description="the operator who shelved it (null: no sign-in on that console)")
    station: str | None = Field(description="the console station it was shelved on")
    at: float = Field(description="when it was shelved, UTC seconds")
    until: float = Field(description="when it comes back by itself, UTC seconds")


class _AlarmState(SQLModel):
    state: AlarmState


class Alarm(AlarmHandled, _AlarmState, AlarmRaised):
    """One alarm of the active set. A condition alarm (link-lost, ins-failure, fix-lost, no-fix-after-command,
    command-unanswered) is active while its condition holds, then cleared-unacknowledged until acknowledged. An event
    alarm (command-failed, command-interrupted, flow-violation, executed-late, recording-failed) is latched: what
    happened does not undo itself (the order was not carried out, the vehicle ran it late), so it stays
    active-unacknowledged until acknowledged, never "cleared". An acknowledged alarm whose condition has cleared, and
    an acknowledged event, return to normal and leave the set (the row stays in the database with its times)."""

    model_config = CAMEL
    id: int
    kind: AlarmKind
    severity: Literal["alarm", "warning"] = Field(description="alarm: act now; warning: look when you can")
    vehicle: str | None = Field(
        description="the vehicle as the operator knows it now: its name (set from the dashboard "
        "or configured), else its short id; a rename sends the set again"
    )
    text: str = Field(
        description="one line in the operator's words, naming the vehicle as `vehicle` does (the "
        "console's database keeps the text as it was when raised)"
    )
    cause: str = Field(description="its kind in words ('Link lost'): many alarms at once are grouped by it")
    chattering: bool = Field(
        description="it cleared and came back `chatter_count` times within `chatter_minutes`: "
        "it is not sounded again until acknowledged"
    )
    shelf: AlarmShelf | None = Field(description="its shelf, while shelved (null: in view)")
    returned: str | None = Field(
        description="why it is back in view after a shelf (its time ended, unshelved, worse), until acknowledged"
    )


class AlarmAckRequest(_Model):
    """Acknowledge takes no parameters: the body is `{}` (JSON, like every command request)."""


LAST_TIME = 32_503_680_000  # UTC seconds of the year 3000: a time beyond is no planned return


class ShelveRequest(_Model):
    reason: Reason = Field(description="why it is shelved, for the other stations and the record (1 to 200 characters)")
    minutes: float = Field(
        gt=0,
        le=MAX_SHELF_MINUTES,
        examples=[60],
        description=(
            "how long, minutes: within the console's bounds (shelve_min_minutes to shelve_max_minutes, by default 15 to 480)"
        ),
    )


class UnshelveRequest(_Model):
    """Unshelve takes no parameters: the body is `{}`."""


class PlannedSilence(_Model):
    """A vehicle's planned link gap ("out of comms until"): its loss raises no alarm until `until` and the console's
    grace (silence_grace) after it; still not heard then, that is a silence-overdue alarm."""

    id: str
    providerId: str
    vehicle: str = Field(description="the vehicle as the operator knows it now")
    reason: str
    by: str | None
    station: str | None
    at: float = Field(description="when it was declared, UTC seconds")
    until: float = Field(description="when the vehicle is expected back, UTC seconds")


class SilenceRequest(_Model):
    until: float = Field(
        ge=0, le=LAST_TIME, description="when the vehicle is expected back, UTC seconds: in the future", examples=[4_102_444_800]
    )
    reason: Reason = Field(description="why (diving, over the horizon, a relay down), 1 to 200 characters")


# ---- WebSocket: server -> client ---------------------------------------------------------
class DatabaseState(_Model):
    """Whether the console's database can be reached (as GET /api/health has it)."""

    unavailableSince: float | None = Field(description=Health.model_fields["databaseUnavailableSince"].description)
    writesHeld: int = Field(description=Health.model_fields["databaseWritesHeld"].description)
    writesDropped: int = Field(description=Health.model_fields["databaseWritesDropped"].description)


class SnapshotMessage(_Model):
    type: Literal["snapshot"]
    consoleId: str
    serverTime: float
    authRequired: bool
    providers: list[ProviderDetail] = Field(
        description=(
            "every vehicle with its latest reports, its GPSReport's satellites left out (an empty list): only the selected "
            "vehicle's are drawn, and GET /api/providers/{id} has them; to a client that named its vehicle on connect "
            "(/ws?vehicle=), that vehicle alone (if known)"
        )
    )
    fleet: list[VehicleBrief] = Field(
        default_factory=list,
        description=(
            "to a client that named its vehicle on connect (/ws?vehicle=): every other vehicle, as the brief its overviews "
            "draw; empty otherwise"
        ),
    )
    commands: list[Command]
    gateways: list[GatewayState]
    recording: RecordingStatus
    replay: ReplayStatus | None = Field(description="the replay's playback (sem-console --replay); null for a live console")
    alarms: list[Alarm] = Field(description="the active alarm set (every alarm not returned to normal), newest first")
    silences: list[PlannedSilence] = Field(description="the planned silences in force, the soonest to end first")
    database: DatabaseState | None = Field(None, description="the database's reach (null in a replay: its own file)")
    load: ConsoleLoad | None = Field(None, description="whether the console is the one behind (null in a replay)")


class ReportMessage(_Model):
    type: Literal["report"]
    providerId: str
    topic: ReportTopic
    report: ReportEnvelope
    partial: bool = Field(
        False,
        description=(
            "a GPSReport without its satellites (an empty list): sent to a client that selected another vehicle or none "
            "(`select`), but once every 5 s or longer with a large fleet (a replay: of the recording's time); the `select` "
            "of this vehicle brings its latest whole"
        ),
    )


class GatewaysMessage(_Model):
    """Every gateway's state, at most once a second and only when it changed."""

    type: Literal["gateways"]
    gateways: list[GatewayState]


class RecordingMessage(_Model):
    """The recording started, stopped, rolled over to a new file, or failed."""

    type: Literal["recording"]
    recording: RecordingStatus


class ReplayMessage(_Model):
    """A replay's playback changed (play, pause, speed, seek) or moved on (every 0.5 s while playing)."""

    type: Literal["replay"]
    replay: ReplayStatus


class WorldModelMessage(_Model):
    """The world model changed (a PUT, a WorldModel over IMC, a CoverageState)."""

    type: Literal["worldmodel"]
    worldModel: WorldModel


class TaskMessage(_Model):
    """A CoMap task was assigned or changed."""

    type: Literal["task"]
    task: Task


class AlarmsMessage(_Model):
    """The active alarm set changed (raised, acknowledged, cleared, returned to normal): the whole set, newest first."""

    type: Literal["alarms"]
    alarms: list[Alarm]


class DatabaseMessage(_Model):
    """The database became unreachable or reachable again, or what is held for it changed (at most once a second
    while only the count of held writes moves)."""

    type: Literal["database"]
    database: DatabaseState


class LoadMessage(_Model):
    """The console fell behind or caught up (console-overloaded): its load then."""

    type: Literal["load"]
    load: ConsoleLoad


class SilencesMessage(_Model):
    """A planned silence was declared, cancelled or ended: every one in force, the soonest to end first."""

    type: Literal["silences"]
    silences: list[PlannedSilence]


class PaceMessage(_Model):
    """To a client that named the vehicle it draws (`select`, /ws?vehicle=): how often, at most, each other vehicle's
    report of a topic comes to it (the console shares a budget of reports a second among the vehicles it does not
    draw), sent with its first `select` and again when the fleet's size moves it. A vehicle not drawn is silent only
    when nothing of it came for longer than this beside the usual bound."""

    type: Literal["pace"]
    othersEvery: float = Field(gt=0, description="seconds: each other vehicle's report of a topic comes at most this often")


class ErrorMessage(_Model):
    type: Literal["error"]
    message: str


class PongMessage(_Model):
    type: Literal["pong"]
    serverTime: float


ServerMessage = Annotated[
    SnapshotMessage
    | ReportMessage
    | ProviderMessage
    | CommandMessage
    | TransitionMessage
    | RecordingMessage
    | ReplayMessage
    | GatewaysMessage
    | WorldModelMessage
    | TaskMessage
    | AlarmsMessage
    | SilencesMessage
    | DatabaseMessage
    | LoadMessage
    | PaceMessage
    | ErrorMessage
    | PongMessage,
    Field(discriminator="type"),
]


# ---- WebSocket: client -> server ---------------------------------------------------------
class PingMessage(_Model):
    type: Literal["ping"]


class ResyncMessage(_Model):
    """Ask for a fresh snapshot."""

    type: Literal["resync"]


class AckMessage(_Model):
    """On `/ws?ack=1`: the client has taken the first `frames` frames of this socket (counted from its first, the
    snapshot); the console sends reports only while a window of bytes is unacknowledged (`ws_window_bytes`)."""

    type: Literal["ack"]
    frames: int = Field(ge=0)


class SelectMessage(_Model):
    """The vehicle the client draws in full (null: none): its reports go out ahead of the others' and its latest
    GPSReport comes whole at once; every other vehicle's GPSReport then comes `partial` but once every 5 s (longer with
    a large fleet: a budget of whole ones a second), and each other vehicle's reports at most once a topic every pace
    (0.25 s, longer with a large fleet: a budget of reports a second; told in a `pace` message), the newest. A client
    that never sends one gets every report whole, as it comes."""

    type: Literal["select"]
    providerId: uuid.UUID | None


ClientMessage = Annotated[PingMessage | ResyncMessage | AckMessage | SelectMessage, Field(discriminator="type")]

server_messages: TypeAdapter[Any] = TypeAdapter(ServerMessage)
client_messages: TypeAdapter[Any] = TypeAdapter(ClientMessage)


class _Messages(_Model):
    server: ServerMessage
    client: ClientMessage


def ws_schema() -> dict[str, Any]:
    """One JSON Schema document: both message unions, and the JSON form of each report type
    (derived from the generated IDL types) with `ReportTypes` mapping topic to type."""
    from sem_console.codec.jsonschema import report_schemas

    schema = _Messages.model_json_schema(ref_template="#/$defs/{model}")
    defs = schema.setdefault("$defs", {})
    reports = report_schemas()
    clash = set(reports) & set(defs)
    assert not clash, f"report type names clash with message names: {clash}"
    defs.update(reports)
    defs["ReportTypes"] = {
        "type": "object",
        "title": "ReportTypes",
        "description": "The report JSON carried for each report topic",
        "properties": {topic: {"$ref": f"#/$defs/{topic}Type"} for topic in typing.get_args(ReportTopic)},
        "required": list(typing.get_args(ReportTopic)),
        "additionalProperties": False,
    }
    schema["properties"]["reportTypes"] = {"$ref": "#/$defs/ReportTypes"}
    return {
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": "SemConsoleMessages",
        "description": "Messages on /ws: `server` (snapshot first, then deltas) and `client`, each tagged by `type`; "
        "a client of /ws?batch=1 gets the `report` messages that waited for its sender as one frame (up to 500), "
        "a JSON array of them in order (a lone one as itself). "
        "`ReportTypes` gives the JSON of each report topic's `report.report`.",
        **{k: v for k, v in schema.items() if k != "title"},
    }
