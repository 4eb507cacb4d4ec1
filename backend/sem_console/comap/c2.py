"""The console as a CoMap C2: the world model, the tasks it assigned and the vehicles' capabilities.

Plain Python on the event loop: `send(message, dst)` puts an IMC message on the wire, `emit(ws)`
publishes a WebSocket message. Task ids are the C2's (u16, from 1). A task's `state`:

    ASSIGNED (TaskAdmin ASSIGN sent) -> ACCEPTED | REJECTED (the vehicle's TaskAdmin ACCEPT/REJECT)
    -> IN_PROGRESS (TaskStatus IN_PROGRESS) -> COMPLETED | ERROR (TaskStatus)
    HOLD -> HELD, RESUME -> IN_PROGRESS (SynchAdmin to the task's vehicle); INTERRUPT -> INTERRUPTED.

REJECTED, COMPLETED, ERROR and INTERRUPTED are final; a TaskStatus that arrives after is recorded
(progress, quality) but does not move the state.
"""

from __future__ import annotations

import logging
import math
import time
import uuid
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from sem_console.comap.codec import BROADCAST, Header, Message, msg
from sem_console.comap.geo import Feature, GeoError, collection, coverage_name, features_from_world_model, world_model_message
from sem_console.comap.messages import Sensor, SynchOp, TaskOp, TaskStatusEnum

log = logging.getLogger("sem-console.comap")
FINAL = {"REJECTED", "COMPLETED", "ERROR", "INTERRUPTED"}
CAPABILITY_KINDS = {"CapabilityAreaSurvey": "AREA_SURVEY", "CapabilityPointSurvey": "POINT_SURVEY", "CapabilityMove": "MOVE"}


class TaskError(ValueError):
    """status: the HTTP status the route answers with."""

    def __init__(self, status: int, detail: str) -> None:
        super().__init__(detail)
        self.status = status


@dataclass
class Task:
    task_id: int
    kind: str  # survey | move
    vehicle: uuid.UUID
    imc_id: int
    operator: str | None
    feature_id: int | None = None
    sensor: str | None = None
    resolution: float | None = None
    deadline: float | None = None
    point: dict[str, float] | None = None
    state: str = "ASSIGNED"
    progress: int = 0
    quality: int | None = None
    created_at: float = field(default_factory=time.time)
    updated_at: float = field(default_factory=time.time)
    last_synch: str | None = None

    def to_json(self) -> dict[str, Any]:
        return {"taskId": self.task_id, "kind": self.kind, "vehicle": str(self.vehicle), "imcId": self.imc_id,
                "featureId": self.feature_id, "sensor": self.sensor, "resolution": self.resolution,
                "deadline": self.deadline, "point": self.point, "state": self.state, "progress": self.progress,
                "quality": self.quality, "synch": self.last_synch, "operator": self.operator,
                "createdAt": self.created_at, "updatedAt": self.updated_at}


@dataclass
class VehicleInfo:
    imc_id: int
    provider: uuid.UUID | None
    capabilities: list[dict[str, Any]] | None = None  # None until its VehicleCapabilities arrives
    last_heard: float | None = None

    def to_json(self) -> dict[str, Any]:
        return {"imcId": self.imc_id, "providerId": str(self.provider) if self.provider else None,
                "capabilities": self.capabilities, "lastHeard": self.last_heard}


def capability_json(m: Message) -> dict[str, Any]:
    out: dict[str, Any] = {"kind": CAPABILITY_KINDS[m.name]}
    for k, v in m.fields.items():
        key = {"res_bathym_factor": "resolutionBathymetryFactor", "cov_rate": "coverageRate",
               "cov_bathym_factor": "coverageBathymetryFactor"}.get(k, k)
        out[key] = _sensor_name(v) if k == "sensor" else (v if math.isfinite(v) else None)
    return out


def _sensor_name(v: int) -> str:
    try:
        return Sensor(v).name
    except ValueError:
        return f"UNKNOWN({v})"


class C2:
    def __init__(self, vehicles: dict[uuid.UUID, int], send: Callable[[Message, int], object],
                 emit: Callable[[dict[str, Any]], None]) -> None:
        self.send, self.emit = send, emit
        self.vehicles: dict[int, VehicleInfo] = {i: VehicleInfo(i, g) for g, i in vehicles.items()}
        self.imc_of: dict[uuid.UUID, int] = dict(vehicles)
        self.features: list[Feature] = []
        self.world_updated_at: float | None = None
        self.world_source: str | None = None
        self.tasks: dict[int, Task] = {}
        self._next_task = 1
        self._highest_feature = 0  # the highest featureId this console has seen: new features are numbered above it

    # ---- world model ------------------------------------------------------------------------
    def world_model(self) -> dict[str, Any]:
        return {**collection(self.features), "updatedAt": self.world_updated_at, "source": self.world_source}

    def put_world_model(self, features: list[Feature]) -> dict[str, Any]:
        """Replace the model (ids given by the operator kept, the others numbered) and send it to every peer.
        A feature without an id gets one above every id seen so far (in this model, the models before it and
        the tasks), so it never takes the id of a deleted feature whose survey may still report coverage; only
        when those run out (ids go to 65534) is a lower id not in this model used."""
        used = {f.feature_id for f in features if f.feature_id >= 0}
        self._saw_features(used)
        fresh = iter(range(self._highest_feature + 1, 0xFFFF))  # 0..65534
        reuse = (i for i in range(1, 0xFFFF) if i not in used)
        for f in features:
            if f.feature_id < 0:
                f.feature_id = next(fresh, None) or next(reuse)
                used.add(f.feature_id)
                self._saw_features([f.feature_id])
        self.features = features
        self._world_changed("operator")
        self.send(world_model_message(self.features), BROADCAST)
        return self.world_model()

    def _saw_features(self, ids: Any) -> None:
        self._highest_feature = max([self._highest_feature, *ids])

    def _world_changed(self, source: str) -> None:
        self.world_updated_at, self.world_source = time.time(), source
        self.emit({"type": "worldmodel", "worldModel": self.world_model()})

    # ---- IMC input ------------------------------------------------------------------------------
    def on_message(self, header: Header, m: Message) -> None:
        v = self.vehicles.get(header.src)
        if v is None:
            v = self.vehicles[header.src] = VehicleInfo(header.src, None)
        v.last_heard = time.time()
        if m.name == "WorldModel":
            try:
                self.features = features_from_world_model(m)
            except GeoError as e:
                log.warning("ignored a WorldModel from IMC system %d: %s", header.src, e)
                return
            self._saw_features(f.feature_id for f in self.features)
            self._world_changed(f"imc:{header.src}")
        elif m.name == "CoverageState":
            self._coverage(m["feature_id"], m["state"])
        elif m.name == "VehicleCapabilities":
            v.capabilities = [capability_json(c) for c in m["capabilities"]]
        elif m.name == "TaskAdmin":
            self._task_admin(header.src, m)
        elif m.name == "TaskStatus":
            self._task_status(header.src, m)

    def _coverage(self, feature_id: int, state: int) -> None:
        name = coverage_name(state)
        for f in self.features:
            if f.feature_id == feature_id and name is not None and f.coverage != name:
                f.coverage = name
                self._world_changed("coverage")

    def _task_admin(self, src: int, m: Message) -> None:
        task = self.tasks.get(m["tid"])
        if task is None or task.imc_id != src:
            return
        op = m["op"]
        if op == TaskOp.ACCEPT and task.state == "ASSIGNED":
            self._set(task, "ACCEPTED")
        elif op == TaskOp.REJECT and task.state not in FINAL:
            self._set(task, "REJECTED")
        elif op == TaskOp.STATUS and m["arg"] is not None and m["arg"].name == "TaskStatus":
            self._task_status(src, m["arg"])

    def _task_status(self, src: int, m: Message) -> None:
        task = self.tasks.get(m["task_id"])
        if task is None or task.imc_id != src:
            return
        task.progress = max(0, min(100, m["progress"]))
        task.quality = max(0, min(100, m["quality"]))
        state = task.state
        if task.state not in FINAL:
            status = m["status"]
            if status == TaskStatusEnum.COMPLETED:
                state = "COMPLETED"
            elif status == TaskStatusEnum.ERROR:
                state = "ERROR"
            elif status == TaskStatusEnum.IN_PROGRESS and task.state in ("ASSIGNED", "ACCEPTED"):
                state = "IN_PROGRESS"
        self._set(task, state)

    def _set(self, task: Task, state: str) -> None:
        task.state, task.updated_at = state, time.time()
        self.emit({"type": "task", "task": task.to_json()})

    # ---- tasks ------------------------------------------------------------------------------------
    def assign(self, kind: str, vehicle: uuid.UUID, operator: str | None, *, feature_id: int | None = None,
               sensor: str = "ANY", resolution: float = 1.0, deadline: float | None = None,
               point: dict[str, float] | None = None) -> Task:
        imc_id = self.imc_of.get(vehicle)
        if imc_id is None:
            raise TaskError(404, f"vehicle {vehicle} has no IMC system id in the console's vehicle table (--imc-vehicles)")
        deadline = deadline if deadline is not None else time.time() + 3600
        task_id = self._new_task_id()
        if kind == "survey":
            feature = next((f for f in self.features if f.feature_id == feature_id), None)
            if feature is None:
                raise TaskError(409, f"no feature {feature_id} in the world model")
            arg = msg("SurveyTask", task_id=task_id, feature_id=feature_id, sensor=Sensor[sensor].value,
                      resolution=resolution, deadline=deadline)
            # the vehicle needs the feature's geometry: the world model goes first
            self.send(world_model_message(self.features), imc_id)
        else:
            assert point is not None
            arg = msg("MoveTask", task_id=task_id, deadline=deadline,
                      destination=msg("MapPoint", lat=math.radians(point["lat"]), lon=math.radians(point["lon"]), alt=0.0))
        task = Task(task_id, kind, vehicle, imc_id, operator, feature_id if kind == "survey" else None,
                    sensor if kind == "survey" else None, resolution if kind == "survey" else None, deadline, point)
        self.tasks[task_id] = task
        self.send(msg("TaskAdmin", tid=task_id, op=TaskOp.ASSIGN, arg=arg), imc_id)
        self.emit({"type": "task", "task": task.to_json()})
        return task

    def _new_task_id(self) -> int:
        for _ in range(0xFFFE):
            tid, self._next_task = self._next_task, self._next_task % 0xFFFE + 1
            old = self.tasks.get(tid)
            if old is None or old.state in FINAL:
                self.tasks.pop(tid, None)
                return tid
        raise TaskError(409, "every task id is taken by an unfinished task")

    def synch(self, task_id: int, action: str) -> Task:
        task = self.tasks.get(task_id)
        if task is None:
            raise TaskError(404, f"no task {task_id}")
        if task.state in FINAL:
            raise TaskError(409, f"task {task_id} is {task.state}")
        self.send(msg("SynchAdmin", op=SynchOp[action].value), task.imc_id)
        task.last_synch = action
        self._set(task, {"HOLD": "HELD", "RESUME": "IN_PROGRESS", "INTERRUPT": "INTERRUPTED"}[action])
        return task

    def capabilities_of(self, provider: uuid.UUID) -> VehicleInfo | None:
        imc = self.imc_of.get(provider)
        return None if imc is None else self.vehicles.get(imc)
