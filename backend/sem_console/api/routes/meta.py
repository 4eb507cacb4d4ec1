"""Health of the console itself, the audit trail, and who a token belongs to."""

from __future__ import annotations

from typing import Any

from fastapi import APIRouter, HTTPException
from fastapi.responses import FileResponse

from sem_console.api.audit import entry_json
from sem_console.api.deps import ConsoleDep, Limit, Offset, OperatorDep, SettingsDep
from sem_console.api.responses import DATABASE_READ
from sem_console.api.schemas import AuditEntry, Health, Metrics, Operator, Problem
from sem_console.dds.bus import domain_security
from sem_console.dds.config import describe
from sem_console.dds.security import BusSecurity

health_router = APIRouter(prefix="/api", tags=["meta"])  # always open
reads = APIRouter(prefix="/api", tags=["meta"])
operator_router = APIRouter(prefix="/api", tags=["meta"])  # needs a token when the console has any


@health_router.get("/health", response_model=Health)
async def health(console: ConsoleDep, settings: SettingsDep) -> dict[str, Any]:
    """The console itself: its id and station name, its DDS domain and network, whether that bus is secured (DDS
    Security, and under which identity), whether commands and reads need a token, whether it has a chart or replays a
    recording, and its database's state. Always open, even with --auth-reads."""
    reach = console.database_reach()
    return {
        "status": "ok",
        "consoleId": str(console.id),
        "domain": settings.domain,
        "authRequired": bool(settings.operators()),
        "readAuthRequired": settings.auth_reads,
        "basemap": settings.basemap is not None,
        "replay": settings.replay is not None,
        "consoleName": console.station,
        "databaseUnavailableSince": reach["unavailableSince"],
        "databaseWritesHeld": reach["writesHeld"],
        "databaseWritesDropped": reach["writesDropped"],
        "load": console.load_state(),
        "ddsNetwork": None if settings.replay is not None else describe(settings.dds_interface, settings.dds_peers),
        "ddsSecurity": None if settings.replay is not None else security_json(domain_security(settings.domain)),
    }


def security_json(security: BusSecurity | None) -> dict[str, Any]:
    if security is None:
        return {"secured": False}
    return {
        "secured": True,
        "identity": security.identity,
        "subject": security.subject or None,
        "source": security.source,
        "notAfter": security.not_after.timestamp() if security.not_after else None,
    }


@reads.get("/metrics", response_model=Metrics)
async def metrics(console: ConsoleDep) -> dict[str, Any]:
    """Counters since start: what the console took from DDS, applied, and sent to WebSocket clients."""
    return console.metrics()


PMTILES = "application/vnd.pmtiles"
_BYTES = {"schema": {"type": "string", "format": "binary"}}


@reads.get(
    "/basemap.pmtiles",
    response_class=FileResponse,
    responses={
        200: {"description": "the whole PMTiles file", "content": {PMTILES: _BYTES}},
        206: {
            "description": "the byte range asked for with `Range: bytes=a-b` (how the dashboard's pmtiles reader reads it)",
            "content": {PMTILES: _BYTES},
        },
        404: {"description": "the console has no basemap (no --basemap)", "model": Problem},
        416: {"description": "the range is outside the file", "content": {"text/plain": {"schema": {"type": "string"}}}},
    },
)
async def basemap(settings: SettingsDep) -> FileResponse:
    """The offline chart given with --basemap, for the map; HTTP range requests (`Range: bytes=a-b`, answered 206
    with `Accept-Ranges: bytes`) are how it is read."""
    if settings.basemap is None:
        raise HTTPException(404, "no basemap: start the console with --basemap FILE.pmtiles")
    return FileResponse(settings.basemap, media_type=PMTILES)


@reads.get("/audit", response_model=list[AuditEntry], responses=DATABASE_READ)
async def audit_trail(console: ConsoleDep, limit: Limit = 100, offset: Offset = 0) -> list[dict[str, Any]]:
    """Command requests, accepted and refused (for any reason), and wrong tokens on any route, newest first. Refusals
    are bounded per client address and minute (--audit-refusals-per-minute), the trail by --audit-max-rows."""
    return [entry_json(r) for r in await console.audit_trail(limit, offset)]


@operator_router.get("/operator", response_model=Operator)
async def operator(name: OperatorDep) -> dict[str, Any]:
    """The operator the token belongs to: the dashboard's sign-in check. On a console without operator tokens
    `{"operator": null}`, whatever is sent."""
    return {"operator": name}
