"""Alarms: the active set derived on the server (console/alarms.py), read (`reads`), acknowledged, shelved and
unshelved (`writes`).

Acknowledge, shelve and unshelve are operator actions: they take the operator token when the console has any, are
refused in a replay, and are audited like a command (the operator's name is recorded; a shelf's reason too).
"""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, HTTPException, Path, status

from sem_console.api.deps import AuditDep, ConsoleDep, OperatorDep, SettingsDep
from sem_console.api.responses import JSON_BODY, problem
from sem_console.api.schemas import Alarm, AlarmAckRequest, ShelveRequest, UnshelveRequest
from sem_console.core import messages

reads = APIRouter(tags=["alarms"])
AlarmId = Annotated[
    int,
    Path(
        description="the alarm's id (`id` in GET /api/alarms): its row's, taken ahead; negative for one raised "
        "while the database could not be reached and no id was taken ahead (its row's after a restart)",
        examples=[1],
    ),
]
writes = APIRouter(tags=["alarms"])


@reads.get("/api/alarms", response_model=list[Alarm])
async def list_alarms(console: ConsoleDep) -> list[messages.Alarm]:
    """The active alarm set (every alarm not back to normal, in its ISA-18.2 state), newest first; the same as the
    WebSocket's `alarms`."""
    return console.active_alarms()


@writes.post(
    "/api/alarms/{alarm_id}/ack",
    response_model=list[Alarm],
    responses={
        200: {"description": "the active alarm set after the acknowledgement, newest first"},
        404: problem("no such alarm in the active set (unknown, or already back to normal)"),
        **JSON_BODY,
    },
)
async def acknowledge_alarm(
    alarm_id: AlarmId, body: AlarmAckRequest, console: ConsoleDep, operator: OperatorDep, audit: AuditDep
) -> list[messages.Alarm]:
    """Acknowledge an alarm (the body is `{}`). An event alarm, or a condition alarm
    whose condition has cleared, then returns to normal and leaves the set; an active condition alarm stays as
    active-acknowledged. Acknowledging an acknowledged alarm again changes nothing. Audited with the operator, like a
    command. Every client gets the new set."""
    if console.acknowledge(alarm_id, operator) is None:
        raise HTTPException(status.HTTP_404_NOT_FOUND, f"no alarm {alarm_id} in the active set")
    audit(status.HTTP_200_OK, None, operator)
    return console.active_alarms()


NOT_ACTIVE = problem("no such alarm in the active set (unknown, or already back to normal)")


@writes.post(
    "/api/alarms/{alarm_id}/shelve",
    response_model=list[Alarm],
    responses={
        200: {"description": "the active alarm set after shelving, newest first"},
        404: NOT_ACTIVE,
        409: problem("`minutes` is outside the console's shelving bounds (shelve_min_minutes to shelve_max_minutes)"),
        **JSON_BODY,
    },
)
async def shelve_alarm(
    alarm_id: AlarmId, body: ShelveRequest, console: ConsoleDep, settings: SettingsDep, operator: OperatorDep, audit: AuditDep
) -> list[messages.Alarm]:
    """Shelve an alarm: out of view (no tone, not counted unacknowledged, listed as shelved) on every station of the
    database for `minutes`, within the console's bounds. It comes back when the time ends, when unshelved, or at once
    when it gets worse: a new alarm of its vehicle at least as severe. Shelving a shelved alarm shelves it again from
    now. Audited with its reason; every client gets the new set."""
    low, high = settings.shelve_min_minutes, settings.shelve_max_minutes
    if not low <= body.minutes <= high:
        raise HTTPException(
            status.HTTP_409_CONFLICT,
            f"{body.minutes:g} minutes is outside this console's shelving bounds, {low:g} to {high:g} "
            "minutes: shelve for a time within them",
        )
    if console.shelve(alarm_id, body.reason, body.minutes, operator) is None:
        raise HTTPException(status.HTTP_404_NOT_FOUND, f"no alarm {alarm_id} in the active set")
    audit(status.HTTP_200_OK, f"shelved for {body.minutes:g} min: {body.reason}", operator)
    return console.active_alarms()


@writes.post(
    "/api/alarms/{alarm_id}/unshelve",
    response_model=list[Alarm],
    responses={
        200: {"description": "the active alarm set after unshelving, newest first"},
        404: NOT_ACTIVE,
        409: problem("the alarm is not shelved"),
        **JSON_BODY,
    },
)
async def unshelve_alarm(
    alarm_id: AlarmId, body: UnshelveRequest, console: ConsoleDep, operator: OperatorDep, audit: AuditDep
) -> list[messages.Alarm]:
    """Bring a shelved alarm back into view at once, on every station (the body is `{}`)."""
    shelved = console.shelved(alarm_id)
    if shelved is None:
        raise HTTPException(status.HTTP_404_NOT_FOUND, f"no alarm {alarm_id} in the active set")
    if not shelved:
        raise HTTPException(status.HTTP_409_CONFLICT, f"alarm {alarm_id} is not shelved")
    console.unshelve(alarm_id, operator)
    audit(status.HTTP_200_OK, None, operator)
    return console.active_alarms()
