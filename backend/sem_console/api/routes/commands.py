"""Commands: issue GPSFix and InertialSensor commands, cancel them, read their history.

Every route is `async def`: it runs on the event loop, the one thread that owns the
console's state (a plain `def` would run in a worker thread).
"""

from __future__ import annotations

import uuid
from typing import Annotated, Any

from fastapi import APIRouter, HTTPException, Query, status

from UMAA.Common.MaritimeEnumeration.InertialSensorStateEnumType import InertialSensorStateEnumType as InsState

from sem_console.api.deps import ConsoleDep, OperatorDep
from sem_console.api.routes.providers import known_provider
from sem_console.api.schemas import Command, InertialSensorRequest
from sem_console.console.commands import CommandError
from sem_console.dds.topics import Service

router = APIRouter(tags=["commands"])
AUTH = {401: {"description": "an operator token is configured and none (or a wrong one) was given"}}


@router.post("/api/providers/{provider_id}/gps-fix", response_model=Command, status_code=status.HTTP_201_CREATED,
             responses={404: {"description": "unknown provider"}, **AUTH})
async def request_gps_fix(provider_id: uuid.UUID, console: ConsoleDep, operator: OperatorDep) -> dict[str, Any]:
    """Surface the vehicle for a GPS fix (GPSFixCommand). Returns the command with its sessionId."""
    known_provider(console, provider_id)
    return console.issue(Service.GPS_FIX, provider_id, None, operator).to_json()


@router.post("/api/providers/{provider_id}/inertial-sensor", response_model=Command, status_code=status.HTTP_201_CREATED,
             responses={404: {"description": "unknown provider"}, **AUTH})
async def set_inertial_sensor(provider_id: uuid.UUID, body: InertialSensorRequest, console: ConsoleDep,
                        operator: OperatorDep) -> dict[str, Any]:
    """Set the inertial sensor OFF, ON or RESTARTING (InertialSensorCommand)."""
    known_provider(console, provider_id)
    return console.issue(Service.INERTIAL_SENSOR, provider_id, InsState[body.state], operator).to_json()


@router.delete("/api/commands/{session_id}", response_model=Command,
               responses={404: {"description": "unknown command"}, 409: {"description": "the command has finished"}, **AUTH})
async def cancel_command(session_id: uuid.UUID, console: ConsoleDep, operator: OperatorDep) -> dict[str, Any]:
    """Cancel a running command: the console disposes it, the provider answers CANCELED."""
    if console.commands.get(session_id) is None:
        raise HTTPException(status.HTTP_404_NOT_FOUND, f"no command with sessionId {session_id}")
    try:
        return console.commands.cancel(session_id, operator).to_json()
    except CommandError as e:
        raise HTTPException(status.HTTP_409_CONFLICT, str(e)) from None


@router.get("/api/commands", response_model=list[Command])
async def list_commands(console: ConsoleDep, limit: Annotated[int, Query(ge=1, le=1000)] = 100,
                        offset: Annotated[int, Query(ge=0)] = 0) -> list[dict[str, Any]]:
    """Commands this console issued, newest first, with every status transition (`limit` from `offset`)."""
    return console.commands.history(limit, offset)


@router.get("/api/commands/{session_id}", response_model=Command, responses={404: {"description": "unknown command"}})
async def get_command(session_id: uuid.UUID, console: ConsoleDep) -> dict[str, Any]:
    cmd = console.commands.get(session_id)
    if cmd is None:
        raise HTTPException(status.HTTP_404_NOT_FOUND, f"no command with sessionId {session_id}")
    return cmd.to_json()
