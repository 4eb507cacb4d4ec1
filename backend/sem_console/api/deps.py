"""Shared dependencies of the routes."""

from __future__ import annotations

from collections.abc import Callable
from typing import Annotated

from fastapi import Depends, HTTPException, Query, Request, Response
from fastapi.security import HTTPAuthorizationCredentials, HTTPBearer

from sem_console.api import audit
from sem_console.api.auth import DEVICE_COOKIE, AuthError, Operators
from sem_console.console.service import Console
from sem_console.core.config import Settings
from sem_console.gateways.run import Gateways

_bearer = HTTPBearer(auto_error=False, description="an operator token")
BearerDep = Annotated[HTTPAuthorizationCredentials | None, Depends(_bearer)]


async def get_console(request: Request) -> Console:
    console: Console = request.app.state.console  # set by main.create_app
    return console


async def get_settings(request: Request) -> Settings:
    settings: Settings = request.app.state.settings  # set by main.create_app
    return settings


ConsoleDep = Annotated[Console, Depends(get_console)]
SettingsDep = Annotated[Settings, Depends(get_settings)]


class TokenRefused(HTTPException):
    """401/429 of the token check; `audit`: a wrong token or the slow-down, recorded on any route (see api/audit.py)."""

    def __init__(self, e: AuthError) -> None:
        headers = {"WWW-Authenticate": "Bearer"} if e.status == 401 else {"Retry-After": str(e.retry_after)}
        super().__init__(e.status, e.detail, headers=headers)
        self.audit = e.audit


def _authenticate(request: Request, response: Response, credentials: HTTPAuthorizationCredentials | None) -> str:
    """The operator's name; a client without a valid device cookie gets one (see api/auth.py)."""
    operators: Operators = request.app.state.operators
    device = operators.device(request.cookies.get(DEVICE_COOKIE))
    try:
        name = operators.authenticate(
            audit.client_of(request.scope) or "?", credentials.credentials if credentials else None, device=device
        )
    except AuthError as e:
        raise TokenRefused(e) from None  # logged and recorded by the app's exception handler
    if device is None:
        response.set_cookie(
            DEVICE_COOKIE, operators.new_device(), httponly=True, samesite="strict", secure=request.url.scheme == "https"
        )
    return name


async def require_operator(request: Request, response: Response, credentials: BearerDep) -> None:
    """Router dependency of the command routes when the console has operator tokens."""
    request.state.operator = _authenticate(request, response, credentials)


def token_operator(request: Request) -> str | None:
    """Who sent a request, for its audit row: the operator its token check found, else (refused before that check ran:
    a body too large or not JSON, read first) the operator of the valid bearer token it carries, if any."""
    checked: str | None = getattr(request.state, "operator", None)
    if checked is not None:
        return checked
    scheme, _, token = request.headers.get("authorization", "").partition(" ")
    operators: Operators = request.app.state.operators
    return operators.lookup(token.strip()) if scheme.lower() == "bearer" and token.strip() else None


async def require_reader(request: Request, response: Response, credentials: BearerDep) -> None:
    """Router dependency of the read routes with --auth-reads."""
    _authenticate(request, response, credentials)


async def refuse_in_replay(request: Request) -> None:
    """Router dependency of the command routes of a replay (sem-console --replay: commands, recording, link
    configuration, CoMap writes): it is read-only. The 409 is audited like every refused command request."""
    settings: Settings = request.app.state.settings
    if settings.replay is not None:
        raise HTTPException(
            409, f"read-only: this console replays the recording {settings.replay.name}; it sends no command and records nothing"
        )


async def current_operator(request: Request) -> str | None:
    """The signed-in operator (set by require_operator); None when the console needs no sign-in."""
    return getattr(request.state, "operator", None)


OperatorDep = Annotated[str | None, Depends(current_operator)]


async def get_auditor(request: Request) -> Callable[[int, str | None, str | None], None]:
    """Records an accepted command request: (HTTP status, sessionId or None, operator); refused ones are
    recorded by the app's exception handlers."""
    return lambda status, session, operator: audit.auditor(request.scope).accepted(request.scope, status, operator, session)


AuditDep = Annotated[Callable[[int, str | None, str | None], None], Depends(get_auditor)]


async def get_gateways(request: Request) -> Gateways:
    gateways: Gateways = request.app.state.gateways  # set by main.create_app
    return gateways


GatewaysDep = Annotated[Gateways, Depends(get_gateways)]


# Paging of the history routes (an offset beyond SQLite's 64-bit integers is a 422, not a crash)
Limit = Annotated[int, Query(ge=1, le=1000, description="at most this many, newest first")]
Offset = Annotated[int, Query(ge=0, le=2**62, description="skip this many")]
