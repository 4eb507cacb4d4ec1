"""Commands: issue GPSFix and InertialSensor commands, cancel them (`writes`), read their history (`reads`).

Every route is `async def`: it runs on the event loop, the one thread that owns the
console's state (a plain `def` would run in a worker thread); the database is read in a worker thread, never on the
loop (tests/system/test_loop.py).
"""

from __future__ import annotations

import uuid
from typing import Annotated

from fastapi import APIRouter, HTTPException, Query, status
from fastapi.exceptions import RequestValidationError

from sem_console.api.deps import AuditDep, ConsoleDep, Limit, Offset, OperatorDep
from sem_console.api.responses import DATABASE_READ, JSON_BODY, Responses, problem
from sem_console.api.routes.providers import known_provider
from sem_console.api.schemas import Command, GpsFixRequest, InertialSensorRequest
from sem_console.console.alarms import vehicle_label
from sem_console.console.commands import CommandError
from sem_console.console.service import Console
from sem_console.core import messages
from sem_console.dds.topics import Service
from sem_console.versions.commands import Commanding, commanding, refusal

writes = APIRouter(tags=["commands"])
reads = APIRouter(tags=["commands"])
UNKNOWN_PROVIDER: Responses = {404: problem("unknown provider")}
# a command not among the running and newest finished ones is looked up in the database
UNKNOWN_COMMAND: Responses = {404: problem("unknown command"), **DATABASE_READ}
LOST: Responses = {
    409: problem(
        "the vehicle's link is lost: the answer names it and how long it has been silent; send "
        "confirmLost true to command it anyway (a replay, read-only, refuses every command with 409)"
    )
}
# OpenAPI links: the sessionId of a created command is what the command routes take (for clients and test tools)
CREATED: Responses = {
    201: {
        "description": "the command, published on the bus",
        "links": {
            name: {"operationId": op, "parameters": {"session_id": "$response.body#/sessionId"}}
            for name, op in (
                ("GetCommand", "get_command_api_commands__session_id__get"),
                ("CancelCommand", "cancel_command_api_commands__session_id__delete"),
            )
        },
    }
}


@writes.post(
    "/api/providers/{provider_id}/gps-fix",
    response_model=Command,
    status_code=status.HTTP_201_CREATED,
    responses={**CREATED, **UNKNOWN_PROVIDER, **LOST, **JSON_BODY},
)
async def request_gps_fix(
    provider_id: uuid.UUID, body: GpsFixRequest, console: ConsoleDep, operator: OperatorDep, audit: AuditDep
) -> messages.Command:
    """Surface the vehicle for a GPS fix (GPSFixCommand); the body is `{}`. Returns the command with its sessionId.
    A UMAA 6.0 vehicle has no GPS fix service: 422."""
    c = reachable_commanding(console, provider_id, Service.GPS_FIX, None, ("path", "provider_id"), body.confirmLost)
    cmd = console.issue(c, provider_id, None, operator)
    audit(status.HTTP_201_CREATED, str(cmd.session_id), operator)
    return cmd.to_json()


@writes.post(
    "/api/providers/{provider_id}/inertial-sensor",
    response_model=Command,
    status_code=status.HTTP_201_CREATED,
    responses={**CREATED, **UNKNOWN_PROVIDER, **LOST, **JSON_BODY},
)
async def set_inertial_sensor(
    provider_id: uuid.UUID, body: InertialSensorRequest, console: ConsoleDep, operator: OperatorDep, audit: AuditDep
) -> messages.Command:
    """Command the inertial sensor with a state of the vehicle's UMAA version (its `umaaVersion`): 3.0.1, OFF, ON or
    RESTARTING (InertialSensorCommand); 6.0, BEST_ALIGN, GPS_ALIGN, INIT, SNAP_ALIGN, STATIONARY_ALIGN or
    TRANSFER_ALIGN (InertialSensorCommandType). A state of the other version: 422, naming the vehicle's version and its
    choices."""
    c = reachable_commanding(console, provider_id, Service.INERTIAL_SENSOR, body.state, ("body", "state"), body.confirmLost)
    cmd = console.issue(c, provider_id, body.state, operator)
    audit(status.HTTP_201_CREATED, str(cmd.session_id), operator)
    return cmd.to_json()


def reachable_commanding(
    console: Console, provider_id: uuid.UUID, service: Service, state: str | None, where: tuple[str, ...], confirm_lost: bool
) -> Commanding:
    """How a known vehicle's version commands `service`: a 422 (a validation problem at `where`) naming its version
    and its choices when it cannot take this command, whether or not it is lost (no confirmation asked for a command
    that would be refused); then, a vehicle whose link is lost only with the operator's explicit confirmation (409
    otherwise): the command would wait on the bus and may run whenever the vehicle comes back."""
    p = known_provider(console, provider_id)
    refused = refusal(p.umaa_version, service, state, vehicle_label(p.id, p.name))
    found = commanding(p.umaa_version, service)
    if refused is not None or found is None:
        raise RequestValidationError([{"loc": where, "msg": refused, "type": "value_error"}])
    if p.link == "lost" and not confirm_lost:
        silent = console.silent_for(p)
        raise HTTPException(
            status.HTTP_409_CONFLICT,
            f"{vehicle_label(p.id, p.name)} is lost (nothing heard for {silent:.0f} s): "
            "the command could run whenever it comes back; send confirmLost true to command it anyway",
        )
    return found


@writes.delete(
    "/api/commands/{session_id}", response_model=Command, responses={**UNKNOWN_COMMAND, 409: problem("the command has finished")}
)
async def cancel_command(session_id: uuid.UUID, console: ConsoleDep, operator: OperatorDep, audit: AuditDep) -> messages.Command:
    """Cancel a running command, an UNANSWERED one too: the console disposes it, the provider answers CANCELED. The
    command stays in the history."""
    if await console.command(session_id) is None:
        raise HTTPException(status.HTTP_404_NOT_FOUND, f"no command with sessionId {session_id}")
    await console.take_over(session_id)  # another station's running command, cancelled from here
    try:
        cmd = console.cancel(session_id, operator)
    except CommandError as e:
        raise HTTPException(status.HTTP_409_CONFLICT, str(e)) from None
    audit(status.HTTP_200_OK, str(session_id), operator)
    return cmd.to_json()


@reads.get(
    "/api/commands",
    response_model=list[Command],
    responses={
        200: {
            "description": "commands, newest first",
            "links": {
                "GetNewestCommand": {
                    "operationId": "get_command_api_commands__session_id__get",
                    "parameters": {"session_id": "$response.body#/0/sessionId"},
                }
            },
        },
        **DATABASE_READ,
    },
)
async def list_commands(
    console: ConsoleDep,
    limit: Limit = 100,
    offset: Offset = 0,
    provider_id: Annotated[uuid.UUID | None, Query(description="only commands to this provider")] = None,
) -> list[messages.Command]:
    """Commands this console issued, newest first, with every status transition (`limit` from `offset`)."""
    return await console.command_history(limit, offset, provider_id)


@reads.get("/api/commands/{session_id}", response_model=Command, responses=UNKNOWN_COMMAND)
async def get_command(session_id: uuid.UUID, console: ConsoleDep) -> messages.Command:
    """One command with every status transition: from memory, or from the database once it is no longer among the
    running and newest finished ones."""
    cmd = await console.command(session_id)
    if cmd is None:
        raise HTTPException(status.HTTP_404_NOT_FOUND, f"no command with sessionId {session_id}")
    return cmd.to_json()
