"""The console's tables, one SQLModel class per concept. The column names are those of the first (raw sqlite3)
schema, so a database written by an earlier release is read as it is; `migrations/` creates and changes them.

TrackPoint and SeriesPoint are also the REST response models of the track and chart routes. A shape the console keeps
in memory as it keeps it here is declared once, as a base (AlarmBase, ShelfBase, SilenceBase) from which the table row
and the console's own class derive (the template's `UserBase` pattern); the API's schemas (api/schemas.py,
core/contract.py) keep their camelCase field names, sent as the console builds them (core/messages.py).
tests/unit/test_shapes.py fails when one drifts from its base."""

from __future__ import annotations

from sqlalchemy import Index, Table
from sqlmodel import Field, SQLModel

TRACK, SERIES = "track", "series"


class Meta(SQLModel, table=True):
    """Key/value of the first schema; its 'source' row held the console's source GUID before the consoles table."""

    __tablename__ = "meta"
    key: str = Field(primary_key=True)
    value: str


class ConsoleIdentity(SQLModel, table=True):
    """A console station's name and its UMAA source GUID (NumericGUID): one per name, never shared."""

    __tablename__ = "consoles"
    name: str = Field(primary_key=True, description="--console-name (default: host name and HTTP port)")
    guid: str = Field(unique=True, description="the console's source GUID as a UUID string")
    created_at: float = Field(description="UTC seconds since the epoch when the name was first used")


class CommandIssued(SQLModel):
    """A command as issued; with CommandHandled, what the row (CommandRecord) and the API's command (core/contract.py,
    in camelCase) have in common."""

    session_id: str
    service: str
    provider_id: str
    state: str | None
    operator: str | None
    created_at: float


class CommandHandled(SQLModel):
    """What became of a command besides its statuses: unanswered, cancelled, closed, acknowledged, cleaned up."""

    unanswered: bool = Field(description="no ISSUED within the unanswered timeout")
    cancel_requested: bool
    canceled_by: str | None = Field(description="the operator who canceled it (null: no sign-in, or the console's "
                                                "shutdown)")
    canceled_on: str | None = Field(default=None, description=(
        "the console station its cancel was asked on (its --console-name); null: not canceled, or before stations were "
        "recorded with a cancel"))
    canceled_at: float | None = Field(default=None, description="when its cancel was asked, UTC seconds")
    cancel_cause: str | None = Field(default=None, description=(
        "why it was cancelled: operator, an operator asked it (canceledBy, when signed in); shutdown, the console station "
        "canceledOn cancelled it as it stopped (its Consumer Shutdown Sequence; canceledBy null). Null: not cancelled, "
        "or cancelled before the cause was recorded"))
    closed_unheard: str | None = Field(default=None, description=(
        "a canceled command the vehicle never answered (no status at all), ended by the console: heard, the vehicle was "
        "heard again for the unanswered timeout without answering it (it never heard the command); bound, the vehicle "
        "was not heard within --cancel-unheard-bound of the cancel. Such a command is terminal with a null status"))
    closed_at: float | None = Field(default=None, description="when the console ended it so (closedUnheard), UTC seconds")
    acked_at: float | None = Field(description="when the provider first acknowledged it (its CommandAckReport, published "
                                               "as it starts to process the command), UTC seconds")
    cleaned_up: bool
    console: str | None = Field(default=None, description="the console station that issued it (its --console-name); "
                                                          "null: a command of a release before station names")


class CommandRecord(CommandHandled, CommandIssued, table=True):
    """A command this console (or another station on the same database) issued, with its flags."""

    __tablename__ = "commands"
    session_id: str = Field(primary_key=True)
    command: str = Field(description="the command sample's own fields as JSON (its timeStamp)")


class TransitionBase(SQLModel):
    """One status of a command: the row (TransitionRecord) and the API's transition (core/contract.py, in camelCase)."""

    seq: int = Field(description="1-based position in the command's history")
    status: str
    reason: str
    log_message: str
    violation: str | None = Field(description="why this transition breaks ICD Figure 4, or null")
    provider_time: float | None = Field(description="the status sample's timeStamp, UTC seconds")
    received_at: float


class TransitionRecord(TransitionBase, table=True):
    """One status of a command, in the order received (seq from 1)."""

    __tablename__ = "transitions"
    session_id: str = Field(primary_key=True, foreign_key="commands.session_id")
    seq: int = Field(primary_key=True, description="1-based position in the command's history")


class AuditRecord(SQLModel, table=True):
    """One request to a command route (accepted or refused); the newest Settings.audit_max_rows are kept."""

    __tablename__ = "audit"
    __table_args__ = {"sqlite_autoincrement": True}  # ids never reused: the prune is one range delete on the key
    id: int | None = Field(None, primary_key=True)
    at: float
    outcome: str
    status: int
    method: str
    path: str
    client: str | None = None
    origin: str | None = None
    operator: str | None = None
    session_id: str | None = None
    reason: str


class LinkConfigRecord(SQLModel, table=True):
    """A vehicle's link configuration as an operator set it (JSON of core.contract.LinkConfig)."""

    __tablename__ = "link_config"
    provider_id: str = Field(primary_key=True)
    config: str


class VehicleNameRecord(SQLModel, table=True):
    """A vehicle's name as an operator set it from the dashboard (over --vehicle-names), who set it and when."""

    __tablename__ = "vehicle_names"
    provider_id: str = Field(primary_key=True)
    name: str
    set_by: str | None = None
    set_at: float


class ComapWorldRecord(SQLModel, table=True):
    """The CoMap world model the consoles of one database share: one row (id 1), the newest change of any of them."""

    __tablename__ = "comap_world"
    id: int = Field(1, primary_key=True, sa_column_kwargs={"autoincrement": False})
    features: str = Field(description="JSON list of the features: featureId, points ([lat, lon] degrees), coverage, "
                                      "properties")
    updated_at: float = Field(description="UTC seconds of the change (a write older than the row's is not applied)")
    source: str | None = Field(None, description="operator, coverage or imc:<system id>")
    highest_feature: int = Field(0, description="the highest featureId seen: a new feature is numbered above it")
    station: str | None = Field(None, description="the console station that wrote it")


class TaskPlanned(SQLModel):
    """A CoMap task as planned; with TaskProgress and TaskOwned, what the row (ComapTaskRecord) and the API's task
    (api/schemas.py, in camelCase) have in common."""

    task_id: int = Field(description="the CoMap task id (u16), unique among the unfinished tasks of the consoles on one "
                                     "database")
    kind: str
    vehicle: str = Field(description="the provider GUID")
    imc_id: int
    feature_id: int | None
    sensor: str | None
    resolution: float | None
    deadline: float | None = Field(description="UTC seconds since the epoch")


class TaskProgress(SQLModel):
    """A task's state and progress, as the vehicle's TaskStatus reports them."""

    state: str
    progress: int = Field(ge=0, le=100, description="% from the vehicle's TaskStatus")
    quality: int | None = Field(description="% from the vehicle's TaskStatus, null before any")


class TaskOwned(SQLModel):
    """Who assigned a task, where, and when it changed."""

    operator: str | None
    station: str | None = Field(description="the console station that assigned it (--console-name)")
    created_at: float
    updated_at: float = Field(description="UTC seconds of the newest progress (the vehicle's TaskStatus); the task's "
                                          "creation before any")
    state_at: float = Field(description="UTC seconds the state and synch were decided (a synch, a state the vehicle "
                                        "reported): a client merging copies of a task takes state and synch from the "
                                        "one with the later stateAt, progress and quality from the later updatedAt")


class ComapTaskRecord(TaskOwned, TaskProgress, TaskPlanned, table=True):
    """A CoMap task a console station assigned (comap/c2.py's Task), its state as the newest change says."""

    __tablename__ = "comap_tasks"
    task_id: int = Field(primary_key=True, sa_column_kwargs={"autoincrement": False})
    point: str | None = Field(default=None, description="a move's destination as JSON {lat, lon}")
    last_synch: str | None = None
    state_at: float = Field(0.0, sa_column_kwargs={"server_default": "0"},
                            description="a final state is never replaced (comap.c2.decided_over)")


class ComapTaskIds(SQLModel, table=True):
    """The next CoMap task id to try (one row, id 1, locked while a console takes an id: no two take the same)."""

    __tablename__ = "comap_task_ids"
    id: int = Field(1, primary_key=True, sa_column_kwargs={"autoincrement": False})
    next_task: int = Field(1, description="1..65534, wrapping")


class AlarmRaised(SQLModel):
    """An alarm as raised; with AlarmHandled, what the row (AlarmRecord), the console's alarm (console/alarms.py) and
    the API's (api/schemas.py, in camelCase) have in common."""

    id: int | None = Field(description="the row's id (a temporary negative one while the database is away)")
    kind: str
    severity: str
    provider_id: str | None = Field(description="the vehicle's source GUID; null for the console's own (recording)")
    vehicle: str | None = Field(description="the vehicle as it was named when raised")
    session_id: str | None = Field(description="the command the alarm is about, if any")
    text: str = Field(description="as said when raised, naming `vehicle`")
    since: float = Field(description="when it became active, UTC seconds")


class AlarmHandled(SQLModel):
    """What became of an alarm: its condition cleared, an operator acknowledged it."""

    cleared_at: float | None = Field(description="when its condition cleared, UTC seconds")
    acked_at: float | None
    acked_by: str | None = Field(description="the operator who acknowledged it (null: no sign-in on this console)")


class AlarmBase(AlarmHandled, AlarmRaised):
    """An alarm as it is kept: the row (AlarmRecord) and the console's alarm derive from it."""

    key: str = Field(description="kind, vehicle, command, detail: one alarm per key until it is back to normal")
    normal_at: float | None = Field(description="back to normal: out of the active set (the row stays)")


class AlarmRecord(AlarmBase, table=True):
    """An alarm (console/alarms.py); normal_at is set when it is back to normal (out of the active set)."""

    __tablename__ = "alarms"
    __table_args__ = (Index("alarms_open", "normal_at"), {"sqlite_autoincrement": True})
    id: int | None = Field(None, primary_key=True)
    console: str | None = Field(default=None, description="the console station whose alarm it is (null: before station names)")


class ShelfBase(SQLModel):
    """An alarm shelved by an operator: every station's alarm of `key` is out of view until `until`, or until it ends
    sooner (unshelved, or the alarm got worse). The row (AlarmShelfRecord) and the console's shelf (console/alarms.py's
    Shelf) derive from it."""

    id: str = Field(description="a UUID")
    key: str = Field(description="the alarm's key: kind, vehicle, command, detail")
    kind: str
    provider_id: str | None = None
    session_id: str | None = None
    severity: str = Field(description="the alarm's severity when shelved (a more severe alarm of its vehicle ends it)")
    text: str = Field(description="the alarm's text when shelved")
    reason: str
    shelved_by: str | None = None
    station: str | None = None
    shelved_at: float
    until: float = Field(description="UTC seconds the shelf ends by itself")
    ended_at: float | None = None
    ended_by: str | None = None
    end_reason: str | None = Field(default=None, description="expired, unshelved, reshelved, or 'worse: <the new alarm>'")


class AlarmShelfRecord(ShelfBase, table=True):
    """A shelf, shared by the consoles of one database."""

    __tablename__ = "alarm_shelves"
    __table_args__ = (Index("alarm_shelves_open", "ended_at"),)
    id: str = Field(primary_key=True, description="a UUID")


class SilenceBase(SQLModel):
    """A vehicle's planned link gap ("out of comms until"): its loss raises no alarm until `until` and the grace after
    it (Settings.silence_grace); still lost then, it is an alarm. The row (PlannedSilenceRecord) and the console's
    silence (console/alarms.py's Silence) derive from it."""

    id: str = Field(description="a UUID")
    provider_id: str
    reason: str
    set_by: str | None = None
    station: str | None = None
    set_at: float
    until: float = Field(description="UTC seconds the vehicle is expected back by")
    ended_at: float | None = None
    ended_by: str | None = None
    end_reason: str | None = Field(default=None, description="cancelled, heard (back by its time) or overdue (not heard by it)")


class PlannedSilenceRecord(SilenceBase, table=True):
    """A planned silence, shared by the consoles of one database."""

    __tablename__ = "planned_silences"
    __table_args__ = (Index("planned_silences_open", "ended_at"),)
    id: str = Field(primary_key=True, description="a UUID")


class TrackPoint(SQLModel, table=True):
    """One position of a vehicle's track, from its GPSFixReport (at most one per vehicle and UTC second)."""

    __tablename__ = TRACK
    providerId: str = Field(primary_key=True, description="the provider's source GUID as a UUID string")
    time: float = Field(primary_key=True, index=True,
                        description="UTC seconds since the epoch when the console received the GPSFixReport")
    positionTime: float | None = Field(description="the report's timeAtPosition, UTC seconds (null: not sent)")
    latitude: float = Field(description="degrees, WGS 84, north positive")
    longitude: float = Field(description="degrees, WGS 84, east positive")
    altitudeMsl: float | None = Field(description="altitude above mean sea level, metres")
    course: float | None = Field(description="true course over ground, degrees 0..360")
    sog: float | None = Field(description="speed over ground, metres per second")
    latLongValid: bool = Field(description="GPSLatLongValid: the position is from GPS (false: from the INS)")
    fixValid: bool | None = Field(description="fixValid of the vehicle's latest GPSFixStatusReport "
                                              "(null: none received yet)")


class SeriesPoint(SQLModel, table=True):
    """The dashboard's chart values of a vehicle at one time, from its GPSReport (at most one per UTC second)."""

    __tablename__ = SERIES
    providerId: str = Field(primary_key=True, description="the provider's source GUID as a UUID string")
    time: float = Field(primary_key=True, index=True,
                        description="UTC seconds since the epoch when the console received the GPSReport")
    cn0Mean: float | None = Field(description="mean antennaCarrierNoiseDensity (C/N0) of the satellites "
                                              "that report one, dB-Hz (null: none)")
    satellitesUsed: int = Field(description="satellites with usedInFix")
    satellitesInView: int = Field(description="numberSatellitesInView")


def table(model: type[SQLModel]) -> Table:
    """The Core table of a model (for statements on its columns, typed)."""
    t = model.__table__  # type: ignore[attr-defined]  # set by SQLModel on table=True classes
    assert isinstance(t, Table)
    return t
