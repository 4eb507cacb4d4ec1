"""Providers: every source GUID seen on a SEM topic, with its latest reports and link health."""

from __future__ import annotations

import uuid
from typing import Any

from fastapi import APIRouter, HTTPException, status

from sem_console.api.deps import ConsoleDep
from sem_console.api.responses import problem
from sem_console.api.schemas import ProviderDetail, ProviderSummary
from sem_console.console.providers import Provider
from sem_console.console.service import Console

router = APIRouter(prefix="/api/providers", tags=["providers"])
# OpenAPI links: a provider's id is what the per-vehicle routes take (for clients and test tools)
PROVIDER_LINKS = {name: {"operationId": op, "parameters": {"provider_id": "$response.body#/id"}} for name, op in (
    ("AspnLog", "aspn_log_api_providers__provider_id__aspn_log_get"),
    ("SetLinkConfig", "set_link_config_api_providers__provider_id__link_config_put"))}


def known_provider(console: Console, provider_id: uuid.UUID) -> Provider:
    p = console.provider(provider_id)
    if p is None:
        raise HTTPException(status.HTTP_404_NOT_FOUND, f"no provider {provider_id} has been seen on the bus")
    return p


@router.get("", response_model=list[ProviderSummary])
async def list_providers(console: ConsoleDep) -> list[dict[str, Any]]:
    now = console.clock.monotonic()
    return [p.summary(now) for p in console.providers.by_id.values()]


@router.get("/{provider_id}", response_model=ProviderDetail, responses={
    200: {"description": "the provider with its latest reports", "links": PROVIDER_LINKS}, 404: problem("unknown provider")})
async def get_provider(provider_id: uuid.UUID, console: ConsoleDep) -> dict[str, Any]:
    return console.provider_detail(known_provider(console, provider_id), console.clock.monotonic())
