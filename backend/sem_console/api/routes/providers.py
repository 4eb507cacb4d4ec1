"""Providers: every source GUID seen on a SEM topic, with its latest reports and link health."""

from __future__ import annotations

import uuid
from typing import Any

from fastapi import APIRouter, HTTPException, status

from sem_console.api.deps import AuditDep, ConsoleDep, OperatorDep
from sem_console.api.responses import JSON_BODY, problem
from sem_console.api.schemas import ProviderDetail, ProviderSummary, VehicleName, VehicleNameShown
from sem_console.console.providers import Provider
from sem_console.console.service import Console
from sem_console.core import messages

router = APIRouter(prefix="/api/providers", tags=["providers"])
writes = APIRouter(prefix="/api/providers", tags=["providers"])  # operator token, JSON body, audited
# OpenAPI links: a provider's id is what the per-vehicle routes take (for clients and test tools)
PROVIDER_LINKS = {
    name: {"operationId": op, "parameters": {"provider_id": "$response.body#/id"}}
    for name, op in (
        ("AspnLog", "aspn_log_api_providers__provider_id__aspn_log_get"),
        ("SetLinkConfig", "set_link_config_api_providers__provider_id__link_config_put"),
        ("SetName", "set_name_api_providers__provider_id__name_put"),
    )
}


def known_provider(console: Console, provider_id: uuid.UUID) -> Provider:
    p = console.provider(provider_id)
    if p is None:
        raise HTTPException(status.HTTP_404_NOT_FOUND, f"no provider {provider_id} has been seen on the bus")
    return p


@router.get("", response_model=list[ProviderSummary])
async def list_providers(console: ConsoleDep) -> list[messages.ProviderSummary]:
    """Every provider seen on the bus: its id, name, link state and link configuration, JAUS id, and the age of its
    last sample per topic."""
    return console.provider_summaries()


@router.get(
    "/{provider_id}",
    response_model=ProviderDetail,
    responses={
        200: {"description": "the provider with its latest reports", "links": PROVIDER_LINKS},
        404: problem("unknown provider"),
    },
)
async def get_provider(provider_id: uuid.UUID, console: ConsoleDep) -> messages.ProviderDetail:
    """One provider as the list has it, plus its latest GPSReport (with every satellite), GPSFixReport,
    GPSFixStatusReport and InertialSensorReport (null before any)."""
    return console.detail(known_provider(console, provider_id))


@writes.put("/{provider_id}/name", response_model=VehicleNameShown, responses={404: problem("unknown provider"), **JSON_BODY})
async def set_name(
    provider_id: uuid.UUID, body: VehicleName, console: ConsoleDep, operator: OperatorDep, audit: AuditDep
) -> dict[str, Any]:
    """Name a vehicle: the name is kept in the console's database, shared with the other consoles on it, and
    shown wherever the vehicle is named (over --vehicle-names; its alarms' text, raised before or after). A name is 1 to 40
    printable characters (no control, invisible or bidirectional format characters), trimmed; an empty or null name goes
    back to the --vehicle-names name, or none. Audited like a command. Returns the name as now shown, and every client
    gets a `provider` message (`configured`)."""
    p = known_provider(console, provider_id)
    console.set_vehicle_name(p, body.name, operator)
    # the audit says which name was set (as comap's writes say what they wrote); the row of vehicle_names keeps
    # the last only
    audit(status.HTTP_200_OK, f"name:{body.name}" if body.name else "name:(configured)", operator)
    return {"name": p.name}
