"""Alarms: the active set derived on the server (console/alarms.py), read (`reads`) and acknowledged (`writes`).

Acknowledge is an operator action: it takes the operator token when the console has any, is refused in
a replay, and is audited like a command (the operator's name is recorded).
"""

from __future__ import annotations

from typing import Annotated, Any

from fastapi import APIRouter, HTTPException, Path, status

from sem_console.api.deps import AuditDep, ConsoleDep, OperatorDep
from sem_console.api.responses import JSON_BODY, problem
from sem_console.api.schemas import Alarm, AlarmAckRequest

reads = APIRouter(tags=["alarms"])
AlarmId = Annotated[int, Path(description="the alarm's id (`id` in GET /api/alarms); negative for an alarm raised "
                                          "while the database could not be reached", examples=[1])]
writes = APIRouter(tags=["alarms"])


@reads.get("/api/alarms", response_model=list[Alarm])
async def list_alarms(console: ConsoleDep) -> list[dict[str, Any]]:
    """The active alarm set (every alarm not back to normal, in its ISA-18.2 state), newest first; the same as the
    WebSocket's `alarms`."""
    return console.alarms.active()


@writes.post("/api/alarms/{alarm_id}/ack", response_model=list[Alarm],
             responses={200: {"description": "the active alarm set after the acknowledgement, newest first"},
                        404: problem("no such alarm in the active set (unknown, or already back to normal)"), **JSON_BODY})
async def acknowledge_alarm(alarm_id: AlarmId, body: AlarmAckRequest, console: ConsoleDep, operator: OperatorDep,
                            audit: AuditDep) -> list[dict[str, Any]]:
    """Acknowledge an alarm (the body is `{}`). An event alarm, or a condition alarm
    whose condition has cleared, then returns to normal and leaves the set; an active condition alarm stays as
    active-acknowledged. Acknowledging an acknowledged alarm again changes nothing. Audited with the operator, like a
    command. Every client gets the new set."""
    if console.acknowledge(alarm_id, operator) is None:
        raise HTTPException(status.HTTP_404_NOT_FOUND, f"no alarm {alarm_id} in the active set")
    audit(status.HTTP_200_OK, None, operator)
    return console.alarms.active()
