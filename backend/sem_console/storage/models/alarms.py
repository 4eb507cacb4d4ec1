"""The alarms, their shelves and the planned silences."""

from __future__ import annotations

from sqlalchemy import Index
from sqlmodel import Field, SQLModel


class AlarmRaised(SQLModel):
    """An alarm as raised; with AlarmHandled, what the row (AlarmRecord), the console's alarm (console/alarms.py) and
    the API's (api/schemas.py, in camelCase) have in common."""

    id: int | None = Field(
        description="the alarm's id: its row's, taken ahead; negative for one raised while the database could not be "
        "reached and no id was taken ahead (its row's after a restart)"
    )
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
