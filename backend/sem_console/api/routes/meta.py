"""Health of the console itself."""

from __future__ import annotations

from typing import Any

from fastapi import APIRouter

from sem_console.api.deps import ConsoleDep, SettingsDep
from sem_console.api.schemas import Health

router = APIRouter(prefix="/api", tags=["meta"])


@router.get("/health", response_model=Health)
async def health(console: ConsoleDep, settings: SettingsDep) -> dict[str, Any]:
    return {"status": "ok", "consoleId": str(console.id), "domain": settings.domain, "authRequired": bool(settings.operators())}
