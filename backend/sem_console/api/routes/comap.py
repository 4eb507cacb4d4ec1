"""CoMap: the world model (GeoJSON), tasks over IMC, the vehicles' capabilities and the IMC node's counters.

`writes` (PUT /api/worldmodel, POST /api/tasks, POST /api/tasks/{id}/synch) are command routes:
operator token, Origin guard, JSON body and audit, as the UMAA commands.
"""

from __future__ import annotations

import uuid
from datetime import UTC
from typing import Any

from fastapi import APIRouter, HTTPException, Path, status

from sem_console.api.deps import AuditDep, ConsoleDep, OperatorDep
from sem_console.api.responses import BODY_TOO_LARGE, JSON_BODY, Responses, problem
from sem_console.api.schemas import ComapStatus, ComapVehicle, SynchRequest, Task, TaskRequest, WorldModel, WorldModelIn
from sem_console.comap.c2 import TaskError
from sem_console.comap.codec import MAX_PAYLOAD, encode_payload
from sem_console.comap.geo import Feature, GeoError, feature_from_geojson, world_model_message
from sem_console.core import messages

writes = APIRouter(tags=["CoMap"])
reads = APIRouter(tags=["CoMap"])
TaskId = Path(ge=0, le=0xFFFF, description="the CoMap task id", examples=[1])
COMAP_OFF = "; or CoMap is off (the console was started without --imc-port)"
UNKNOWN_TASK: Responses = {404: problem("unknown task")}


def _features(body: WorldModelIn) -> list[Feature]:
    """The features, or a 409 for what the schema allows but CoMap cannot carry."""
    out: list[Feature] = []
    problems = []
    seen: set[int] = set()
    for i, f in enumerate(body.features):
        try:
            feat = feature_from_geojson(f.model_dump(), f"features[{i}]")
        except GeoError as e:
            problems.append(str(e))
            continue
        if feat.feature_id >= 0 and feat.feature_id in seen:
            problems.append(f"features[{i}]: featureId {feat.feature_id} is given twice")
        seen.add(feat.feature_id)
        out.append(feat)
    if problems:
        raise HTTPException(status.HTTP_409_CONFLICT, "; ".join(problems[:20]))
    return out


@reads.get("/api/worldmodel", response_model=WorldModel)
async def get_world_model(console: ConsoleDep) -> dict[str, Any]:
    """The world model the consoles on this database share: a GeoJSON FeatureCollection, `properties.featureId` and
    `properties.coverage` per feature."""
    return console.world_model()


@writes.put(
    "/api/worldmodel",
    response_model=WorldModel,
    responses={
        **JSON_BODY,
        409: problem(
            "geometry CoMap cannot carry: a polygon that crosses itself or has fewer "
            "than 3 distinct vertices, a featureId given twice"
        ),
        413: {
            **BODY_TOO_LARGE,
            "description": "the world model does not fit one IMC packet (65535 bytes of "
            "payload), or the request body is over 1 MiB",
        },
    },
)
async def put_world_model(body: WorldModelIn, console: ConsoleDep, operator: OperatorDep, audit: AuditDep) -> dict[str, Any]:
    """Replace the world model and send it (IMC WorldModel) to every IMC peer. Features without a
    featureId are numbered; a closed polygon ring and an open one are the same polygon."""
    features = _features(body)
    size = len(encode_payload(world_model_message([Feature(max(f.feature_id, 0), f.points, f.coverage) for f in features])))
    if size > MAX_PAYLOAD:
        raise HTTPException(
            status.HTTP_413_REQUEST_ENTITY_TOO_LARGE, f"the world model is {size} bytes of IMC payload; at most {MAX_PAYLOAD} fit"
        )
    model = console.put_world_model(features)
    audit(status.HTTP_200_OK, f"worldmodel:{len(features)} features", operator)
    return model


@reads.get("/api/tasks", response_model=list[Task])
async def list_tasks(console: ConsoleDep) -> list[messages.Task]:
    """Every task of the consoles on this database (stored: kept across restarts), newest first, with its state,
    progress, quality and the station that assigned it."""
    return [t.to_json() for t in console.tasks()]


@reads.get("/api/tasks/{task_id}", response_model=Task, responses=UNKNOWN_TASK)
async def get_task(console: ConsoleDep, task_id: int = TaskId) -> messages.Task:
    """One task, as the list has it."""
    task = console.task(task_id)
    if task is None:
        raise HTTPException(status.HTTP_404_NOT_FOUND, f"no task {task_id}")
    return task.to_json()


@writes.post(
    "/api/tasks",
    response_model=Task,
    status_code=status.HTTP_201_CREATED,
    responses={
        201: {
            "description": "the task, sent to the vehicle as TaskAdmin ASSIGN (state ASSIGNED)",
            "links": {
                name: {"operationId": op, "parameters": {"task_id": "$response.body#/taskId"}}
                for name, op in (
                    ("GetTask", "get_task_api_tasks__task_id__get"),
                    ("SynchTask", "synch_task_api_tasks__task_id__synch_post"),
                )
            },
        },
        404: problem("the vehicle has no IMC system id in the console's vehicle table"),
        409: problem("a survey of a feature the world model does not have, or no free task id" + COMAP_OFF),
        503: problem("the database cannot be reached: task ids are taken there"),
        **JSON_BODY,
    },
)
async def assign_task(body: TaskRequest, console: ConsoleDep, operator: OperatorDep, audit: AuditDep) -> messages.Task:
    """Assign a SurveyTask (featureId, sensor, resolution, deadline) or a MoveTask (point, deadline) to a vehicle."""
    if not console.comap_linked():
        raise HTTPException(status.HTTP_409_CONFLICT, "CoMap is off: start the console with --imc-port")
    deadline = None
    if body.deadline is not None:
        d = body.deadline if body.deadline.tzinfo else body.deadline.replace(tzinfo=UTC)
        deadline = d.timestamp()
    try:
        task = await console.assign_task(
            body.kind,
            body.vehicle,
            operator,
            feature_id=body.featureId,
            sensor=body.sensor,
            resolution=body.resolution,
            deadline=deadline,
            point=body.point.model_dump() if body.point else None,
        )
    except TaskError as e:
        raise HTTPException(e.status, str(e)) from None
    audit(status.HTTP_201_CREATED, f"task:{task.task_id}", operator)
    return task.to_json()


@writes.post(
    "/api/tasks/{task_id}/synch",
    response_model=Task,
    responses={
        **UNKNOWN_TASK,
        **JSON_BODY,
        409: problem(
            "the task has finished; or this console has no CoMap link to the task's vehicle (CoMap off, or the "
            "vehicle not in its --imc-vehicles): the answer names the station that assigned it"
        ),
    },
)
async def synch_task(
    body: SynchRequest, console: ConsoleDep, operator: OperatorDep, audit: AuditDep, task_id: int = TaskId
) -> messages.Task:
    """HOLD, RESUME or INTERRUPT the task's vehicle (IMC SynchAdmin), whichever station assigned the task: this
    console sends it when it has a CoMap link to the vehicle."""
    try:
        task = console.synch(task_id, body.action)
    except TaskError as e:
        raise HTTPException(e.status, str(e)) from None
    audit(status.HTTP_200_OK, f"task:{task_id}:{body.action}", operator)
    return task.to_json()


@reads.get("/api/comap", response_model=ComapStatus)
async def comap_status(console: ConsoleDep) -> dict[str, Any]:
    """The IMC node: its id, port, peers, counters (bad datagrams per reason) and the CoMap vehicles heard or configured."""
    return console.comap_status()


@reads.get(
    "/api/providers/{provider_id}/capabilities",
    response_model=ComapVehicle,
    responses={404: problem("the provider has no IMC system id and has not been seen on the bus")},
)
async def provider_capabilities(provider_id: uuid.UUID, console: ConsoleDep) -> dict[str, Any]:
    """The vehicle's CoMap side: its IMC system id and the capabilities of its last VehicleCapabilities."""
    info = console.capabilities_of(provider_id)
    if info is None:
        if console.provider(provider_id) is None:
            raise HTTPException(status.HTTP_404_NOT_FOUND, f"no provider {provider_id} has been seen or given an IMC id")
        return {"imcId": None, "providerId": str(provider_id), "capabilities": None, "lastHeard": None}
    return info.to_json()
