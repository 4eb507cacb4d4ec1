"""The console's tables, one SQLModel class per concept, a module per aggregate. The column names are those of the first
(raw sqlite3) schema, so a database written by an earlier release is read as it is; `migrations/` creates and changes them.

TrackPoint and SeriesPoint are also the REST response models of the track and chart routes. A shape the console keeps
in memory as it keeps it here is declared once, as a base (AlarmBase, ShelfBase, SilenceBase) from which the table row
and the console's own class derive (the template's `UserBase` pattern); the API's schemas (api/schemas.py,
core/contract.py) keep their camelCase field names, sent as the console builds them (core/messages.py).
tests/unit/test_shapes.py fails when one drifts from its base."""

from __future__ import annotations

from sqlalchemy import Table
from sqlmodel import SQLModel

from sem_console.storage.models.alarms import (
    AlarmBase,
    AlarmHandled,
    AlarmRaised,
    AlarmRecord,
    AlarmShelfRecord,
    PlannedSilenceRecord,
    ShelfBase,
    SilenceBase,
)
from sem_console.storage.models.comap import ComapTaskIds, ComapTaskRecord, ComapWorldRecord, TaskOwned, TaskPlanned, TaskProgress
from sem_console.storage.models.commands import CommandHandled, CommandIssued, CommandRecord, TransitionBase, TransitionRecord
from sem_console.storage.models.history import SERIES, TRACK, SeriesPoint, TrackPoint
from sem_console.storage.models.station import AuditRecord, ConsoleIdentity, LinkConfigRecord, Meta, VehicleNameRecord

__all__ = [
    "SERIES",
    "TRACK",
    "AlarmBase",
    "AlarmHandled",
    "AlarmRaised",
    "AlarmRecord",
    "AlarmShelfRecord",
    "AuditRecord",
    "ComapTaskIds",
    "ComapTaskRecord",
    "ComapWorldRecord",
    "CommandHandled",
    "CommandIssued",
    "CommandRecord",
    "ConsoleIdentity",
    "LinkConfigRecord",
    "Meta",
    "PlannedSilenceRecord",
    "SeriesPoint",
    "ShelfBase",
    "SilenceBase",
    "TaskOwned",
    "TaskPlanned",
    "TaskProgress",
    "TrackPoint",
    "TransitionBase",
    "TransitionRecord",
    "VehicleNameRecord",
    "table",
]


def table(model: type[SQLModel]) -> Table:
    """The Core table of a model (for statements on its columns, typed)."""
    t = model.__table__  # type: ignore[attr-defined]  # set by SQLModel on table=True classes
    assert isinstance(t, Table)
    return t
