"""Commands: issue GPSFix and InertialSensor commands, cancel them, read their history."""

from __future__ import annotations

import uuid
from typing import Any

from fastapi import APIRouter, HTTPException, status

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
def request_gps_fix(provider_id: uuid.UUID, console: ConsoleDep, operator: OperatorDep) -> dict[str, Any]:
    """Surface the vehicle for a GPS fix (GPSFixCommand). Returns the command with its sessionId."""
    known_provider(console, provider_id)
    return console.issue(Service.GPS_FIX, provider_id, None, operator).to_json()


@router.post("/api/providers/{provider_id}/inertial-sensor", response_model=Command, status_code=status.HTTP_201_CREATED,
             responses={404: {"description": "unknown provider"}, **AUTH})
def set_inertial_sensor(provider_id: uuid.UUID, body: InertialSensorRequest, console: ConsoleDep,
                        operator: OperatorDep) -> dict[str, Any]:
    """Set the inertial sensor OFF, ON or RESTARTING (InertialSensorCommand)."""
    known_provider(console, provider_id)
    return console.issue(Service.INERTIAL_SENSOR, provider_id, InsState[body.state], operator).to_json()


@router.delete("/api/commands/{session_id}", response_model=Command,
               responses={404: {"description": "unknown command"}, 409: {"description": "the command has finished"}, **AUTH})
def cancel_command(session_id: uuid.UUID, console: ConsoleDep, operator: OperatorDep) -> dict[str, Any]:
    """Cancel a running command: the console disposes it, the provider answers CANCELED."""
    if session_id not in console.commands.by_session:
        raise HTTPException(status.HTTP_404_NOT_FOUND, f"no command with sessionId {session_id}")
    try:
        return console.commands.cancel(session_id, operator).to_json()
    except CommandError as e:
        raise HTTPException(status.HTTP_409_CONFLICT, str(e)) from None


@router.get("/api/commands", response_model=list[Command])
def list_commands(console: ConsoleDep) -> list[dict[str, Any]]:
    """Every command this console issued, oldest first, with every status transition."""
    return [c.to_json() for c in sorted(console.commands.by_session.values(), key=lambda c: c.created_at)]


@router.get("/api/commands/{session_id}", response_model=Command, responses={404: {"description": "unknown command"}})
def get_command(session_id: uuid.UUID, console: ConsoleDep) -> dict[str, Any]:
    cmd = console.commands.by_session.get(session_id)
    if cmd is None:
        raise HTTPException(status.HTTP_404_NOT_FOUND, f"no command with sessionId {session_id}")
    return cmd.to_json()
