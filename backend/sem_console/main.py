"""The FastAPI application: REST, WebSocket and (when built) the dashboard, on one origin."""

from __future__ import annotations

import logging
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from pathlib import Path

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse
from fastapi.staticfiles import StaticFiles

from sem_console import __version__
from sem_console.api.routes import commands, meta, providers, ws
from sem_console.console.service import Console
from sem_console.core.config import Settings

log = logging.getLogger("sem-console")
DEFAULT_FRONTEND = Path(__file__).resolve().parents[2] / "frontend" / "dist"


def create_app(settings: Settings | None = None) -> FastAPI:
    settings = settings or Settings()

    @asynccontextmanager
    async def lifespan(app: FastAPI) -> AsyncIterator[None]:
        console = Console(settings)  # owns the DDS participant
        app.state.console = console
        await console.start()
        log.info("console %s on DDS domain %d", console.id, settings.domain)
        try:
            yield
        finally:
            await console.stop()

    app = FastAPI(title="SEM Console", version=__version__, lifespan=lifespan,
                  description="UMAA SEM (GPS and inertial sensor) operator console over DDS. "
                              "WebSocket messages on /ws are described by /api/ws-schema.")
    app.state.settings = settings

    @app.exception_handler(RequestValidationError)
    async def validation_error(_request: Request, exc: RequestValidationError) -> JSONResponse:
        """422 with one readable line per problem, e.g. "body.state: Input should be 'OFF', 'ON' or 'RESTARTING'"."""
        problems = [f"{'.'.join(str(x) for x in e['loc'])}: {e['msg']}" for e in exc.errors()]
        return JSONResponse(status_code=422, content={"detail": "; ".join(problems), "errors": problems})

    for r in (providers.router, commands.router, meta.router, ws.router):
        app.include_router(r)
    frontend = settings.frontend_dir or DEFAULT_FRONTEND
    if (frontend / "index.html").exists():
        app.mount("/", StaticFiles(directory=frontend, html=True), name="dashboard")
    return app
