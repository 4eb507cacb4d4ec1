"""The WebSocket's server messages as the console builds them: one TypedDict per message and per shape it carries,
one builder per message type. mypy checks every message against these; the contract they must match is the API's
(`api/schemas.py`, `core/contract.py`: the JSON Schema the dashboard's types are generated from), and
tests/unit/test_shapes.py fails when a TypedDict here and its model there name different fields.

Plain dicts at run time (a report goes out at thousands a second: no model is built on the way, orjson writes it).
"""

from __future__ import annotations

from typing import Any, Literal, NotRequired, TypedDict

ProviderEvent = Literal["appeared", "lost", "regained", "live", "configured", "unchecked"]


# ---- the shapes the messages carry ---------------------------------------------------------
class TopicHealth(TypedDict):
    ageSeconds: float
    samples: int
    alive: bool
    receivedAt: float


class LinkConfig(TypedDict):
    commsLostTimeout: float
    regainedTime: float
    policy: str
    regainedBehavior: int


class RelayHop(TypedDict):
    name: str
    dataTime: float | None
    ageSeconds: float | None
    quietSeconds: float


class ProviderSummary(TypedDict):
    id: str
    name: str | None
    link: str
    umaaVersion: str
    linkConfig: LinkConfig
    jausId: str | None
    ageSeconds: float
    topics: dict[str, TopicHealth]
    relay: NotRequired[RelayHop | None]


class ReportEnvelope(TypedDict):
    report: dict[str, Any]
    invalid: list[str]
    receivedAt: float


class ProviderDetail(ProviderSummary):
    reports: dict[str, ReportEnvelope | None]


class FixBrief(TypedDict):
    lat: float | None
    lon: float | None
    course: float | None
    sog: float | None
    latLongValid: bool | None
    invalid: list[str]
    receivedAt: float
    timeStamp: NotRequired[dict[str, Any] | None]


class FixStatusBrief(TypedDict):
    fixValid: bool | None
    originLat: float | None
    originLon: float | None
    receivedAt: float


class InsBrief(TypedDict):
    state: str | None
    status: str | None
    receivedAt: float


class VehicleBrief(TypedDict):
    id: str
    name: str | None
    link: str
    umaaVersion: str
    jausId: str | None
    relay: RelayHop | None
    fix: FixBrief | None
    fixStatus: FixStatusBrief | None
    ins: InsBrief | None


class Transition(TypedDict):
    seq: int
    status: str
    reason: str
    logMessage: str
    violation: str | None
    providerTime: float | None
    receivedAt: float


class Command(TypedDict):
    sessionId: str
    service: str
    providerId: str
    state: str | None
    operator: str | None
    createdAt: float
    status: str | None
    terminal: bool
    unanswered: bool
    cancelRequested: bool
    canceledBy: str | None
    canceledOn: str | None
    canceledAt: float | None
    cancelCause: str | None
    closedUnheard: str | None
    closedAt: float | None
    cleanedUp: bool
    console: str | None
    ackedAt: float | None
    violations: list[str]
    transitions: list[Transition]


class AlarmShelf(TypedDict):
    id: str
    reason: str
    by: str | None
    station: str | None
    at: float
    until: float


class Alarm(TypedDict):
    id: int
    kind: str
    severity: str
    providerId: str | None
    vehicle: str | None
    sessionId: str | None
    text: str
    since: float
    state: str
    clearedAt: float | None
    ackedAt: float | None
    ackedBy: str | None
    cause: str
    chattering: bool
    shelf: AlarmShelf | None
    returned: str | None


class PlannedSilence(TypedDict):
    id: str
    providerId: str
    vehicle: str
    reason: str
    by: str | None
    station: str | None
    at: float
    until: float


class Task(TypedDict):
    taskId: int
    kind: str
    vehicle: str
    imcId: int
    featureId: int | None
    sensor: str | None
    resolution: float | None
    deadline: float | None
    point: dict[str, float] | None  # {lat, lon}
    state: str
    progress: int
    quality: int | None
    synch: str | None
    operator: str | None
    station: str | None
    createdAt: float
    updatedAt: float
    stateAt: float


class RecordingStatus(TypedDict):
    state: str
    directory: str
    file: str | None
    startedAt: float | None
    messages: int
    dropped: int
    error: str | None
    writerCpuSeconds: float


class ReplayStatus(TypedDict):
    file: str
    state: str
    speed: float
    position: float
    start: float
    end: float


class DatabaseState(TypedDict):
    unavailableSince: float | None
    writesHeld: int
    writesDropped: int


class ConsoleLoad(TypedDict):
    behind: bool
    behindSince: float | None
    loopDelayMs: float
    ingestLagMs: float
    cpuCores: float
    samplesLost: int
    vehiclesNotChecked: int


class GatewayState(TypedDict):
    name: str
    enabled: bool
    endpoint: str | None
    messagesOut: int
    messagesPerSecond: float
    lastError: str | None
    lastErrorAt: float | None
    counters: dict[str, int]


# ---- the messages -------------------------------------------------------------------------
class SnapshotMessage(TypedDict):
    type: Literal["snapshot"]
    consoleId: str
    serverTime: float
    authRequired: bool
    providers: list[ProviderDetail]
    fleet: list[VehicleBrief]
    commands: list[Command]
    gateways: list[GatewayState]
    recording: RecordingStatus
    replay: ReplayStatus | None
    alarms: list[Alarm]
    silences: list[PlannedSilence]
    database: DatabaseState | None
    load: ConsoleLoad | None


class ReportMessage(TypedDict):
    type: Literal["report"]
    providerId: str
    topic: str
    report: ReportEnvelope
    partial: NotRequired[bool]  # sent only on a thinned GPSReport


class ProviderMessage(TypedDict):
    type: Literal["provider"]
    event: ProviderEvent
    provider: ProviderSummary


class CommandMessage(TypedDict):
    type: Literal["command"]
    command: Command


class TransitionMessage(TypedDict):
    type: Literal["transition"]
    sessionId: str
    transition: Transition
    command: Command


class RecordingMessage(TypedDict):
    type: Literal["recording"]
    recording: RecordingStatus


class ReplayMessage(TypedDict):
    type: Literal["replay"]
    replay: ReplayStatus


class GatewaysMessage(TypedDict):
    type: Literal["gateways"]
    gateways: list[GatewayState]


class WorldModelMessage(TypedDict):
    type: Literal["worldmodel"]
    worldModel: dict[str, Any]  # a GeoJSON FeatureCollection (comap/geo.py)


class TaskMessage(TypedDict):
    type: Literal["task"]
    task: Task


class AlarmsMessage(TypedDict):
    type: Literal["alarms"]
    alarms: list[Alarm]


class SilencesMessage(TypedDict):
    type: Literal["silences"]
    silences: list[PlannedSilence]


class DatabaseMessage(TypedDict):
    type: Literal["database"]
    database: DatabaseState


class LoadMessage(TypedDict):
    type: Literal["load"]
    load: ConsoleLoad


class PaceMessage(TypedDict):
    type: Literal["pace"]
    othersEvery: float


class ErrorMessage(TypedDict):
    type: Literal["error"]
    message: str


class PongMessage(TypedDict):
    type: Literal["pong"]
    serverTime: float


ServerMessage = (
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
    | PongMessage
)


# ---- the builders, one per message type (the snapshot's: Console.snapshot) --------------------------------------------
def report_message(provider_id: str, topic: str, report: ReportEnvelope) -> ReportMessage:
    return {"type": "report", "providerId": provider_id, "topic": topic, "report": report}


def thin_report_message(message: ReportMessage, report: ReportEnvelope) -> ReportMessage:
    """The report message carrying a thinned `report` (`partial`)."""
    return {"type": "report", "providerId": message["providerId"], "topic": message["topic"], "report": report, "partial": True}


def provider_message(event: ProviderEvent, provider: ProviderSummary) -> ProviderMessage:
    return {"type": "provider", "event": event, "provider": provider}


def command_message(command: Command) -> CommandMessage:
    return {"type": "command", "command": command}


def transition_message(transition: Transition, command: Command) -> TransitionMessage:
    return {"type": "transition", "sessionId": command["sessionId"], "transition": transition, "command": command}


def recording_message(recording: RecordingStatus) -> RecordingMessage:
    return {"type": "recording", "recording": recording}


def replay_message(replay: ReplayStatus) -> ReplayMessage:
    return {"type": "replay", "replay": replay}


def gateways_message(gateways: list[GatewayState]) -> GatewaysMessage:
    return {"type": "gateways", "gateways": gateways}


def worldmodel_message(world: dict[str, Any]) -> WorldModelMessage:
    return {"type": "worldmodel", "worldModel": world}


def task_message(task: Task) -> TaskMessage:
    return {"type": "task", "task": task}


def alarms_message(alarms: list[Alarm]) -> AlarmsMessage:
    return {"type": "alarms", "alarms": alarms}


def silences_message(silences: list[PlannedSilence]) -> SilencesMessage:
    return {"type": "silences", "silences": silences}


def database_message(database: DatabaseState) -> DatabaseMessage:
    return {"type": "database", "database": database}


def load_message(load: ConsoleLoad) -> LoadMessage:
    return {"type": "load", "load": load}


def pace_message(others_every: float) -> PaceMessage:
    return {"type": "pace", "othersEvery": others_every}


def error_message(message: str) -> ErrorMessage:
    return {"type": "error", "message": message}


def pong_message(server_time: float) -> PongMessage:
    return {"type": "pong", "serverTime": server_time}
