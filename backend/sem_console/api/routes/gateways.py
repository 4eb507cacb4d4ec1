"""Gateways: their state, a vehicle's recent ASPN messages as an LCM log (`reads`), and a vehicle's link
configuration, which the JAUS gateway reports (`writes`: operator token, JSON body, audited like commands)."""

from __future__ import annotations

import asyncio
import time
import uuid
from typing import Annotated

from fastapi import APIRouter, HTTPException, Query, Response, status

from sem_console.api.deps import AuditDep, ConsoleDep, GatewaysDep, OperatorDep
from sem_console.api.responses import JSON_BODY, Responses, problem
from sem_console.api.routes.history import SINCE_DOC, IsoTime, epoch
from sem_console.api.routes.providers import known_provider
from sem_console.api.schemas import GatewayState, LinkConfig
from sem_console.core import messages
from sem_console.gateways.aspn.gateway import write_log

reads = APIRouter(tags=["gateways"])
writes = APIRouter(tags=["gateways"])
LCM_LOG: Responses = {
    200: {
        "description": "an LCM log file (LCM's EventLog format) of the vehicle's ASPN-23 messages, oldest first; "
        "each event's timestamp is when the console published it (UTC microseconds)",
        "content": {"application/octet-stream": {"schema": {"type": "string", "format": "binary"}}},
    }
}


@reads.get("/api/gateways", response_model=list[GatewayState])
async def gateway_states(gateways: GatewaysDep) -> list[messages.GatewayState]:
    """Each gateway: on or off, where it sends, messages out (total and per second), last error, counters."""
    return gateways.states()


@reads.get(
    "/api/providers/{provider_id}/aspn-log",
    response_class=Response,
    responses={**LCM_LOG, 404: problem("unknown provider"), 409: problem("the ASPN gateway is off (--aspn-lcm)")},
)
async def aspn_log(
    provider_id: uuid.UUID,
    console: ConsoleDep,
    gateways: GatewaysDep,
    since: Annotated[IsoTime, Query(description=SINCE_DOC + ": a recording started then")] = None,
    seconds: Annotated[float | None, Query(gt=0, le=86_400, description="only the last this many seconds")] = None,
) -> Response:
    """The vehicle's ASPN-23 messages the console kept (the last --aspn-log-seconds, at most 8 MiB), as a `.lcm` log
    file for lcm-logplayer or any LCM log reader. `since` and `seconds` narrow the window."""
    known_provider(console, provider_id)
    if not gateways.aspn.enabled:
        raise HTTPException(status.HTTP_409_CONFLICT, "the ASPN gateway is off: start the console with --aspn-lcm URL")
    events = gateways.aspn.events(provider_id, epoch("since", since), seconds)
    data = await asyncio.to_thread(write_log, events)
    stamp = time.strftime("%Y%m%dT%H%M%SZ", time.gmtime())
    return Response(
        data,
        media_type="application/octet-stream",
        headers={"Content-Disposition": f'attachment; filename="aspn-{str(provider_id)[:8]}-{stamp}.lcm"'},
    )


@writes.put(
    "/api/providers/{provider_id}/link-config",
    response_model=LinkConfig,
    responses={404: problem("unknown provider"), **JSON_BODY},
)
async def set_link_config(
    provider_id: uuid.UUID, body: LinkConfig, console: ConsoleDep, operator: OperatorDep, audit: AuditDep
) -> messages.LinkConfig:
    """Set a vehicle's link thresholds (comms-lost timeout, regained time) and record its comms-lost policy and
    regained behaviour. Link health follows the new thresholds at once; the JAUS gateway reports them
    (ReportCommsLostConfiguration); the setting is kept in the console's database. Audited like a command. Returns
    the new configuration."""
    p = known_provider(console, provider_id)
    console.set_link_config(p, body)
    audit(status.HTTP_200_OK, None, operator)
    return p.config.to_json()
