"""Health of the console itself, the audit trail, and who a token belongs to."""

from __future__ import annotations

from typing import Any

from fastapi import APIRouter

from sem_console.api.audit import entry_json
from sem_console.api.deps import ConsoleDep, Limit, Offset, OperatorDep, SettingsDep
from sem_console.api.schemas import AuditEntry, Health, Metrics, Operator

health_router = APIRouter(prefix="/api", tags=["meta"])  # always open
reads = APIRouter(prefix="/api", tags=["meta"])
operator_router = APIRouter(prefix="/api", tags=["meta"])  # needs a token when the console has any


@health_router.get("/health", response_model=Health)
async def health(console: ConsoleDep, settings: SettingsDep) -> dict[str, Any]:
    return {"status": "ok", "consoleId": str(console.id), "domain": settings.domain,
            "authRequired": bool(settings.operators()), "readAuthRequired": settings.auth_reads}


@reads.get("/metrics", response_model=Metrics)
async def metrics(console: ConsoleDep) -> dict[str, Any]:
    """Counters since start: what the console took from DDS, applied, and sent to WebSocket clients."""
    return console.metrics()


@reads.get("/audit", response_model=list[AuditEntry])
async def audit_trail(console: ConsoleDep, limit: Limit = 100,
                      offset: Offset = 0) -> list[dict[str, Any]]:
    """Command requests, accepted and refused (for any reason), and wrong tokens on any route, newest first (bounded: README, Security)."""
    return [entry_json(r) for r in console.store.audit(limit, offset)]


@operator_router.get("/operator", response_model=Operator)
async def operator(name: OperatorDep) -> dict[str, Any]:
    """The operator the token belongs to: the dashboard's sign-in check."""
    return {"operator": name}
