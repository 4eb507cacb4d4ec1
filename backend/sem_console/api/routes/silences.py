"""Planned silences ("out of comms until"): a vehicle's expected link gap, read (`reads`), declared and cancelled
(`writes`: operator actions, audited, refused in a replay). Shared by the consoles of one database."""

from __future__ import annotations

import uuid
from typing import Annotated

from fastapi import APIRouter, HTTPException, Path, status

from sem_console.api.deps import AuditDep, ConsoleDep, OperatorDep
from sem_console.api.responses import JSON_BODY, problem
from sem_console.api.routes.providers import known_provider
from sem_console.api.schemas import PlannedSilence, SilenceRequest
from sem_console.console.alarms import clock_time
from sem_console.core import messages

VehicleId = Annotated[
    uuid.UUID,
    Path(description="the vehicle's source GUID (`id` in GET /api/providers)", examples=["77b2ceb8-5afe-554e-8450-93db17c48923"]),
]  # sem-sim's vehicle 1
reads = APIRouter(tags=["alarms"])
writes = APIRouter(tags=["alarms"])


@reads.get("/api/silences", response_model=list[PlannedSilence])
async def list_silences(console: ConsoleDep) -> list[messages.PlannedSilence]:
    """The planned silences in force, the soonest to end first; the same as the WebSocket's `silences`."""
    return console.planned_silences()


@writes.put(
    "/api/providers/{provider_id}/silence",
    response_model=list[PlannedSilence],
    responses={
        200: {"description": "the planned silences in force after it"},
        404: problem("unknown provider"),
        409: problem("`until` has passed"),
        **JSON_BODY,
    },
)
async def plan_silence(
    provider_id: VehicleId, body: SilenceRequest, console: ConsoleDep, operator: OperatorDep, audit: AuditDep
) -> list[messages.PlannedSilence]:
    """Declare a vehicle out of comms until `until` (diving, over the horizon, a relay down): its link loss raises no
    alarm until then and the console's grace after it (silence_grace); still not heard then, that is an alarm
    (silence-overdue). A new one replaces the vehicle's silence in force. Every client gets the silences."""
    p = known_provider(console, provider_id)
    now = console.wall_time()
    if body.until <= now:
        raise HTTPException(status.HTTP_409_CONFLICT, f"until {clock_time(body.until)} has passed: give a time to come")
    console.plan_silence(p, body.until, body.reason, operator)
    audit(status.HTTP_200_OK, f"out of comms until {clock_time(body.until)}: {body.reason}", operator)
    return console.planned_silences()


@writes.delete(
    "/api/providers/{provider_id}/silence",
    response_model=list[PlannedSilence],
    responses={
        200: {"description": "the planned silences in force after it"},
        404: problem("unknown provider, and no planned silence for it"),
    },
)
async def cancel_silence(
    provider_id: VehicleId, console: ConsoleDep, operator: OperatorDep, audit: AuditDep
) -> list[messages.PlannedSilence]:
    """End a vehicle's planned silence now: a loss is an alarm again. A vehicle without one keeps none (nothing
    changes); a vehicle never heard of, without one, is a 404."""
    if not console.cancel_silence(provider_id, operator):
        known_provider(console, provider_id)
        audit(status.HTTP_200_OK, "no planned silence", operator)
    else:
        audit(status.HTTP_200_OK, None, operator)
    return console.planned_silences()
