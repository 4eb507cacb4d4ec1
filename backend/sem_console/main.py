"""The FastAPI application: REST, WebSocket and (when built) the dashboard, on one origin."""

from __future__ import annotations

import asyncio
import logging
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from fastapi import Depends, FastAPI, Request
from fastapi.exception_handlers import http_exception_handler
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse, Response
from fastapi.staticfiles import StaticFiles
from sqlalchemy.exc import InterfaceError, OperationalError
from starlette.exceptions import HTTPException
from starlette.routing import Match, Mount

from sem_console import __version__
from sem_console.api.audit import Auditor
from sem_console.api.auth import Operators
from sem_console.api.deps import refuse_in_replay, require_operator, require_reader, token_operator
from sem_console.api.guard import Guard, require_json
from sem_console.api.responses import EVERY_ROUTE, NEEDS_TOKEN, READ_ONLY, Responses
from sem_console.api.routes import alarms, comap, commands, history, meta, providers, recordings, replay, silences, ws
from sem_console.api.routes import gateways as gateway_routes
from sem_console.console.service import Console
from sem_console.core.config import Settings
from sem_console.gateways.run import Gateways
from sem_console.recording.reader import time_range
from sem_console.storage.database import Database, Unavailable

log = logging.getLogger("sem-console")
METHODS = ("GET", "HEAD", "POST", "PUT", "PATCH", "DELETE")
DEFAULT_FRONTEND = Path(__file__).resolve().parents[2] / "frontend" / "dist"
# The largest request body taken (413 beyond, before it is read: a declared Content-Length at once, a chunked body as it
# arrives): the largest a route takes is a world model of one IMC packet (64 KiB of IMC, a few hundred KiB of GeoJSON).
# Without it a body of any size is read and parsed on the event loop before the token is checked: 300 MB from anyone
# reaching the port holds the loop about 7 s and takes 1.6 GB.
MAX_BODY_BYTES = 1 << 20


@dataclass(frozen=True)
class Included:
    """What every route of a router gets: its dependencies and its documented error responses."""

    dependencies: list[Any] = field(default_factory=list)
    responses: Responses = field(default_factory=dict)


def problem_line(e: Any) -> str:
    """One problem of a request as a line: `body.confirmLost: Input should be a valid boolean`; a body that is
    no JSON at all, `the body is not valid JSON (at character 10)` (counted from 1)."""
    loc = e["loc"]
    if e["type"] == "json_invalid":
        at = loc[1] if len(loc) > 1 and isinstance(loc[1], int) else None
        return "the body is not valid JSON" + (f" (at character {at + 1})" if at is not None else "")
    return f"{'.'.join(str(x) for x in loc)}: {e['msg']}"


def create_app(settings: Settings | None = None, store: Database | None = None) -> FastAPI:
    """`store`: the console's database when the caller opened it (sem-console: to refuse a bad one in one line)."""
    settings = settings or Settings()

    @asynccontextmanager
    async def lifespan(app: FastAPI) -> AsyncIterator[None]:
        console = Console(settings, store)  # its Source (console/sources.py) owns the DDS participant (none for a recording)
        app.state.console = console
        playback = None  # Foxglove's playback control of the replay: its span, and the replay once the console runs it
        if settings.replay is not None and settings.foxglove_port:
            span = await asyncio.to_thread(time_range, settings.replay)
            playback = (span or (0, 0), console.playback)
        # subscribed before the first sample arrives
        gateways = Gateways(settings, console.feed, console.clock.wall, console.c2.world_model, playback)
        app.state.gateways = gateways
        console.gateway_states = gateways.states
        await gateways.start(console.hub.publish)
        await console.start()
        if settings.replay is not None:
            log.info("console %s replaying %s (read-only)", console.id, settings.replay)
        else:
            log.info("console %s on DDS domain %d", console.id, settings.domain)
        try:
            yield
        finally:
            await console.stop()
            await gateways.stop()

    app = FastAPI(
        title="SEM Console",
        version=__version__,
        lifespan=lifespan,
        max_body_size=MAX_BODY_BYTES,
        description="UMAA SEM (GPS and inertial sensor) operator console over DDS. "
        "WebSocket messages on /ws are described by /api/ws-schema.",
    )
    app.state.settings = settings
    app.state.operators = operators = Operators(settings.operators(), settings.throttle_first_wait)
    app.state.auditor = auditor = Auditor(
        commands.writes.routes
        + recordings.writes.routes
        + gateway_routes.writes.routes
        + comap.writes.routes
        + alarms.writes.routes
        + providers.writes.routes
        + silences.writes.routes,
        settings.audit_refusals_per_minute,
    )

    @app.exception_handler(RequestValidationError)
    async def validation_error(request: Request, exc: RequestValidationError) -> JSONResponse:
        """422 with one readable line per problem, e.g. "body.confirmLost: Input should be a valid boolean"."""
        problems = [problem_line(e) for e in exc.errors()]
        if auditor.is_command(request.scope):  # an operator's refused command is what the audit is for
            auditor.refused(request.scope, 422, "; ".join(problems), operator=token_operator(request))
        return JSONResponse(status_code=422, content={"detail": "; ".join(problems), "errors": problems})

    @app.exception_handler(HTTPException)
    async def http_error(request: Request, exc: HTTPException) -> Response:
        """Refused command requests (401, 404, 409, 415, 429 ...) and 401/429 anywhere: logged and recorded (api/audit.py)."""
        if exc.status_code in (401, 429) or auditor.is_command(request.scope):
            auditor.refused(
                request.scope,
                exc.status_code,
                str(exc.detail),
                audit=getattr(exc, "audit", False),
                operator=token_operator(request),
            )
        return await http_exception_handler(request, exc)

    @app.exception_handler(Unavailable)
    async def database_unavailable(request: Request, exc: Unavailable) -> JSONResponse:
        """A read of the shared database during an outage: 503 in one line (the console goes on monitoring)."""
        return JSONResponse({"detail": str(exc)}, status_code=503, headers={"Retry-After": "2"})

    @app.exception_handler(OperationalError)
    @app.exception_handler(InterfaceError)
    async def database_unreachable(request: Request, exc: Exception) -> JSONResponse:
        """A read in a worker thread (the track and chart history) that could not reach the database: the same."""
        return await database_unavailable(request, request.app.state.console.store.unreachable(exc))

    @app.exception_handler(405)
    async def method_not_allowed(request: Request, _exc: HTTPException) -> JSONResponse:
        """405 whose Allow lists every method of the path (Starlette names only the first route's)."""
        allow = [
            m
            for m in METHODS
            if any(not isinstance(r, Mount) and r.matches({**request.scope, "method": m})[0] is Match.FULL for r in app.routes)
        ]
        return JSONResponse({"detail": "Method Not Allowed"}, status_code=405, headers={"Allow": ", ".join(allow)})

    # Reads need a token only with --auth-reads, commands only when there are tokens: the published
    # OpenAPI document then says exactly which routes need one.
    reads = Included([Depends(require_reader)], NEEDS_TOKEN) if settings.auth_reads else Included()
    writes = Included([Depends(require_operator)], NEEDS_TOKEN) if operators else Included()
    commands_writes = Included([*writes.dependencies, Depends(require_json)], writes.responses)
    if settings.replay is not None:  # read-only: commands, recording, link config, names, CoMap writes are refused (409)
        commands_writes = Included(
            [*commands_writes.dependencies, Depends(refuse_in_replay)], {**commands_writes.responses, **READ_ONLY}
        )
    replay_controls = Included([*reads.dependencies, Depends(require_json)], reads.responses)
    for r, extra in (
        (providers.router, reads),
        (history.router, reads),
        (commands.reads, reads),
        (meta.reads, reads),
        (recordings.reads, reads),
        (gateway_routes.reads, reads),
        (comap.reads, reads),
        (replay.reads, reads),
        (replay.controls, replay_controls),
        (commands.writes, commands_writes),
        (recordings.writes, commands_writes),
        (gateway_routes.writes, commands_writes),
        (comap.writes, commands_writes),
        (alarms.reads, reads),
        (alarms.writes, commands_writes),
        (silences.reads, reads),
        (silences.writes, commands_writes),
        (providers.writes, commands_writes),
        (meta.operator_router, writes),
        (meta.health_router, Included()),
        (ws.router, Included()),
    ):
        app.include_router(r, dependencies=extra.dependencies, responses={**EVERY_ROUTE, **extra.responses})
    app.add_middleware(Guard, settings=settings)
    frontend = settings.frontend_dir or DEFAULT_FRONTEND
    if (frontend / "index.html").exists():
        app.mount("/", StaticFiles(directory=frontend, html=True), name="dashboard")
    return app
