"""Health of the console itself."""

from __future__ import annotations

from typing import Any

from fastapi import APIRouter

from sem_console.api.deps import ConsoleDep, SettingsDep
from sem_console.api.schemas import Health, Metrics

router = APIRouter(prefix="/api", tags=["meta"])


@router.get("/health", response_model=Health)
async def health(console: ConsoleDep, settings: SettingsDep) -> dict[str, Any]:
    return {"status": "ok", "consoleId": str(console.id), "domain": settings.domain, "authRequired": bool(settings.operators())}


@router.get("/metrics", response_model=Metrics)
async def metrics(console: ConsoleDep) -> dict[str, Any]:
    """Counters since start: what the console took from DDS, applied, and sent to WebSocket clients."""
    return console.metrics()
