"""Shared dependencies of the routes."""

from __future__ import annotations

from typing import Annotated

from fastapi import Depends, HTTPException, Request, status
from fastapi.security import HTTPAuthorizationCredentials, HTTPBearer

from sem_console.console.service import Console
from sem_console.core.config import Settings

_bearer = HTTPBearer(auto_error=False, description="an operator token, when the console has any configured")


async def get_console(request: Request) -> Console:
    return request.app.state.console  # type: ignore[no-any-return]


async def get_settings(request: Request) -> Settings:
    return request.app.state.settings  # type: ignore[no-any-return]


ConsoleDep = Annotated[Console, Depends(get_console)]
SettingsDep = Annotated[Settings, Depends(get_settings)]


async def operator_name(settings: SettingsDep,
                  credentials: Annotated[HTTPAuthorizationCredentials | None, Depends(_bearer)]) -> str | None:
    """The signed-in operator for command routes; None when the console needs no sign-in."""
    operators = settings.operators()
    if not operators:
        return None
    name = operators.get(credentials.credentials) if credentials else None
    if name is None:
        raise HTTPException(status.HTTP_401_UNAUTHORIZED, "an operator token is required: Authorization: Bearer <token>",
                            headers={"WWW-Authenticate": "Bearer"})
    return name


OperatorDep = Annotated[str | None, Depends(operator_name)]
