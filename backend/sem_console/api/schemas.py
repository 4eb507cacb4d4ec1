"""The console's REST and WebSocket contract. The frontend's TypeScript types are generated from
the OpenAPI document and /api/ws-schema, which are built from these models."""

from __future__ import annotations

import typing
from typing import Annotated, Any, Literal, Union

from pydantic import BaseModel, ConfigDict, Field, TypeAdapter, field_validator

ReportTopic = Literal["GPSReport", "GPSFixReport", "GPSFixStatusReport", "InertialSensorReport"]
LinkState = Literal["live", "lost", "regained"]
InsStateName = Literal["OFF", "ON", "RESTARTING"]


class _Model(BaseModel):
    model_config = ConfigDict(extra="forbid")


class TopicHealth(_Model):
    ageSeconds: float = Field(description="seconds since the last sample on this topic")
    samples: int
    alive: bool = Field(description="false once the instance was disposed or lost its writers")
    receivedAt: float = Field(description="UTC seconds since the epoch of the last sample")


class LinkConfig(_Model):
    """A vehicle's link thresholds and comms-lost configuration (reported as JAUS ReportCommsLostConfiguration)."""


    commsLostTimeout: float = Field(ge=0.1, le=65535, description="seconds without any sample before the vehicle is lost")
    regainedTime: float = Field(ge=0, le=65535, description="seconds of continuous samples before a lost vehicle is regained")
    policy: Literal["STOP_MISSION", "CONTINUE_MISSION"] = Field(
        description="what the vehicle is set to do when it loses comms (recorded and reported; the console enforces nothing)")
    regainedBehavior: int = Field(ge=0, le=255, description="the vehicle's CommsRegainedBehavior code (JAUS u8), recorded and reported")

    @field_validator("commsLostTimeout", "regainedTime", "regainedBehavior", mode="before")
    @classmethod
    def _a_json_number(cls, v: Any) -> Any:
        """JSON numbers only: not true for 1, nor "5" for 5 (1.0 is the integer 1, as JSON Schema has it)."""
        if isinstance(v, (bool, str)):
            raise ValueError("Input should be a number")
        return v


class ProviderSummary(_Model):
    id: str = Field(description="the provider's source GUID as a UUID string")
    name: str | None = Field(description="the vehicle's name from the console's --vehicle-names, or null")
    link: LinkState
    linkConfig: LinkConfig
    jausId: str | None = Field(description="its JAUS component 'S.1.C' (the order it appeared in) when the JAUS gateway "
                                           "is on, else null")
    ageSeconds: float = Field(description="seconds since the last sample on any topic")
    topics: dict[str, TopicHealth]


class ReportEnvelope(_Model):
    report: dict[str, Any] = Field(description="the sample, member for member as in the IDL; its type per topic is "
                                             "ReportTypes in /api/ws-schema")
    invalid: list[str] = Field(description="'member.path: why' for each value that is not a valid reading")
    receivedAt: float


class ProviderDetail(ProviderSummary):
    reports: dict[ReportTopic, ReportEnvelope | None]


class Transition(_Model):
    seq: int = Field(description="1-based position in the command's history")
    status: str
    reason: str
    logMessage: str
    violation: str | None = Field(description="why this transition breaks ICD Figure 4, or null")
    providerTime: float | None = Field(description="the status sample's timeStamp, UTC seconds")
    receivedAt: float


class Command(_Model):
    sessionId: str
    service: Literal["GPSFix", "InertialSensor"]
    providerId: str
    state: InsStateName | None = Field(description="the commanded INS state (InertialSensor only)")
    operator: str | None
    createdAt: float
    status: str | None = Field(description="the last commandStatus, null before ISSUED")
    terminal: bool
    unanswered: bool = Field(description="no ISSUED within the unanswered timeout")
    cancelRequested: bool
    canceledBy: str | None = Field(description="the operator who canceled it (null: no sign-in, or the console's shutdown)")
    ackedAt: float | None = Field(description="when the provider first reported executing it (its CommandAckReport), UTC seconds")
    cleanedUp: bool
    violations: list[str]
    transitions: list[Transition]


class InertialSensorRequest(_Model):
    state: InsStateName


class GpsFixRequest(_Model):
    """A GPS fix takes no parameters: the body is the empty JSON object `{}`."""


class Problem(_Model):
    detail: str = Field(description="what is wrong, in one line")


class ValidationProblem(_Model):
    detail: str = Field(description="every problem, '; ' separated")
    errors: list[str] = Field(description="one 'location: message' per problem, e.g. 'body.state: Field required'")


class AuditEntry(_Model):
    id: int
    at: float = Field(description="UTC seconds since the epoch")
    outcome: Literal["accepted", "refused", "rate-limited"] = Field(
        description="rate-limited: refused, and the client's further refusals this minute are not recorded")
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


class Health(_Model):
    status: Literal["ok"]
    consoleId: str
    domain: int
    authRequired: bool = Field(description="commands need an operator token")
    readAuthRequired: bool = Field(description="reads (REST and /ws) need an operator token too (--auth-reads)")
    basemap: bool = Field(False, description="the console serves a PMTiles chart at /api/basemap.pmtiles (--basemap)")


class GatewayState(_Model):
    name: Literal["aspn", "jaus"]
    enabled: bool = Field(description="on (its option was given) or off")
    endpoint: str | None = Field(description="where it publishes or listens")
    messagesOut: int = Field(description="messages sent since start")
    messagesPerSecond: float = Field(description="messages sent per second over the last 5 s")
    lastError: str | None
    lastErrorAt: float | None = Field(description="UTC seconds since the epoch")
    counters: dict[str, int] = Field(description="received, malformed (by reason), answered, left out (by reason), dropped: queue full (ASPN), "
                                           "report time outside u32: console time sent (JAUS), errors")


class Metrics(_Model):
    uptimeSeconds: float
    samplesTaken: int = Field(description="samples taken from DDS since start (all three readers of every SEM topic)")
    samplesDecoded: int = Field(description="of those, decoded and applied: a writer's samples only from its owner, the most "
                                            "reliable of a topic's readers it matches, so each sample is decoded once")
    samplesByReader: dict[str, int] = Field(description="samplesDecoded per owner reader: reliableTransientLocal, "
                                                        "reliableVolatile, bestEffort")
    undecodableSamples: int
    incompatibleWriters: dict[str, int] = Field(description="per topic, writers whose QoS no reader of the console accepts, so "
                                                            "nothing of theirs is read (e.g. an XCDR1 GPSReport or GPSFixReport "
                                                            "writer: README, 'Other DDS vendors')")
    reportsApplied: int = Field(description="report samples applied to the state (after conflation and de-duplication)")
    wsClients: int
    wsMessagesPublished: int = Field(description="messages handed to WebSocket clients, one per client")
    wsClientsDropped: int
    providers: int
    commandsInMemory: int
    historyRowsWritten: int = Field(description="track and chart points written to the database")
    historyRowsPruned: int = Field(description="track and chart points removed for being older than the retention")
    historyWriteSecondsMax: float = Field(description="longest batched write of track and chart points (in a worker "
                                                      "thread, off the event loop), seconds")


class RecordingStatus(_Model):
    state: Literal["off", "recording", "failed"] = Field(description="failed: the recording stopped on an error "
                                                                     "(e.g. a full disk), see `error`")
    directory: str = Field(description="where the recordings are written")
    file: str | None = Field(description="the file being written (recording), or the last one written")
    startedAt: float | None = Field(description="when this recording started, UTC seconds (null unless recording)")
    messages: int = Field(description="messages written by this recording (all its files)")
    dropped: int = Field(description="samples dropped because the writer fell behind (its queue was full)")
    error: str | None = Field(description="why the recording stopped, when it failed")


class RecordingFile(_Model):
    name: str = Field(description="<UTC start time>.mcap, e.g. 20261122T101530.123Z.mcap")
    size: int = Field(description="bytes")
    start: float = Field(description="UTC seconds of the first message (of the file's name while it is written)")
    end: float | None = Field(description="UTC seconds of the last message; null while recording or when cut short")
    state: Literal["recording", "complete", "incomplete"] = Field(
        description="incomplete: it has no MCAP summary (the console stopped on an error or was killed); "
                    "MCAP readers still read its messages")


class RecordingRequest(_Model):
    action: Literal["start", "stop"]


# ---- WebSocket: server -> client ---------------------------------------------------------
class SnapshotMessage(_Model):
    type: Literal["snapshot"]
    consoleId: str
    serverTime: float
    authRequired: bool
    providers: list[ProviderDetail]
    commands: list[Command]
    gateways: list[GatewayState]
    recording: RecordingStatus


class ReportMessage(_Model):
    type: Literal["report"]
    providerId: str
    topic: ReportTopic
    report: ReportEnvelope


class ProviderMessage(_Model):
    type: Literal["provider"]
    event: Literal["appeared", "lost", "regained", "live", "configured"] = Field(
        description="live: a regained provider is back to normal; configured: its linkConfig changed")
    provider: ProviderSummary


class CommandMessage(_Model):
    type: Literal["command"]
    command: Command


class TransitionMessage(_Model):
    type: Literal["transition"]
    sessionId: str
    transition: Transition
    command: Command


class GatewaysMessage(_Model):
    """Every gateway's state, at most once a second and only when it changed."""

    type: Literal["gateways"]
    gateways: list[GatewayState]


class RecordingMessage(_Model):
    """The recording started, stopped, rolled over to a new file, or failed."""

    type: Literal["recording"]
    recording: RecordingStatus


class ErrorMessage(_Model):
    type: Literal["error"]
    message: str


class PongMessage(_Model):
    type: Literal["pong"]
    serverTime: float


ServerMessage = Annotated[
    Union[SnapshotMessage, ReportMessage, ProviderMessage, CommandMessage, TransitionMessage, RecordingMessage, GatewaysMessage,
          ErrorMessage,
          PongMessage],
    Field(discriminator="type"),
]


# ---- WebSocket: client -> server ---------------------------------------------------------
class PingMessage(_Model):
    type: Literal["ping"]


class ResyncMessage(_Model):
    """Ask for a fresh snapshot."""

    type: Literal["resync"]


ClientMessage = Annotated[Union[PingMessage, ResyncMessage], Field(discriminator="type")]

server_messages: TypeAdapter[Any] = TypeAdapter(ServerMessage)
client_messages: TypeAdapter[Any] = TypeAdapter(ClientMessage)


class _Messages(_Model):
    server: ServerMessage
    client: ClientMessage


def ws_schema() -> dict[str, Any]:
    """One JSON Schema document: both message unions, and the JSON form of each report type
    (derived from the generated IDL types) with `ReportTypes` mapping topic to type."""
    from sem_console.console.jsonschema import report_schemas

    schema = _Messages.model_json_schema(ref_template="#/$defs/{model}")
    defs = schema.setdefault("$defs", {})
    reports = report_schemas()
    clash = set(reports) & set(defs)
    assert not clash, f"report type names clash with message names: {clash}"
    defs.update(reports)
    defs["ReportTypes"] = {
        "type": "object", "title": "ReportTypes", "description": "The report JSON carried for each report topic",
        "properties": {topic: {"$ref": f"#/$defs/{topic}Type"} for topic in typing.get_args(ReportTopic)},
        "required": list(typing.get_args(ReportTopic)), "additionalProperties": False,
    }
    schema["properties"]["reportTypes"] = {"$ref": "#/$defs/ReportTypes"}
    return {
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": "SemConsoleMessages",
        "description": "Messages on /ws: `server` (snapshot first, then deltas) and `client`, each tagged by `type`; "
                       "`ReportTypes` gives the JSON of each report topic's `report.report`.",
        **{k: v for k, v in schema.items() if k != "title"},
    }
