"""The console as a CoMap C2: the world model, the tasks it assigned and the vehicles' capabilities.

Plain Python on the event loop: `send(message, dst)` puts an IMC message on the wire, `emit(ws)`
publishes a WebSocket message, `save` stores a change (the world model, a task) in the database the consoles
of an operations centre share; `load_world`/`load_task` apply what is stored (another station's change) when
it is newer than this console's. Task ids are u16 from 1, taken in the database (Database.new_comap_task), so
no two stations send the same. A task's `state`:

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
from collections.abc import Callable, Mapping
from dataclasses import asdict, dataclass, field
from typing import Any, Protocol

from sem_console.comap.codec import BROADCAST, Header, Message, msg
from sem_console.comap.geo import Feature, GeoError, collection, coverage_name, features_from_world_model, world_model_message
from sem_console.comap.messages import Sensor, SynchOp, TaskOp, TaskStatusEnum
from sem_console.core import messages
from sem_console.core.messages import ServerMessage, task_message, worldmodel_message

log = logging.getLogger("sem-console.comap")
FINAL = {"REJECTED", "COMPLETED", "ERROR", "INTERRUPTED"}
CAPABILITY_KINDS = {"CapabilityAreaSurvey": "AREA_SURVEY", "CapabilityPointSurvey": "POINT_SURVEY", "CapabilityMove": "MOVE"}


def decided_over(state: str, at: float, other: str, other_at: float) -> bool:
    """Whether a task's `state`, decided at `at`, replaces its `other` state decided at `other_at` (on another station,
    or held through a database outage): the one decided later, except that a finished task (FINAL) is never made
    unfinished again, and of two final states the first stands (the vehicle finished it before any later word reached
    it). A HOLD sent by a station that had not yet read its vehicle's COMPLETED left the task HELD on every station,
    for good: the vehicle reports nothing more, and its id was never free again (Database.new_comap_task)."""
    if state in FINAL:
        return other not in FINAL or at < other_at
    return other not in FINAL and at > other_at


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
    station: str | None = None  # the console station that assigned it
    # when the state and synch were decided (a synch, a state the vehicle reported): apart from updated_at, which
    # progress reports move on too, so that a station's HOLD is not lost to progress stored after it (load_task,
    # Database.set_comap_task)
    state_at: float = field(default_factory=time.time)

    def to_json(self) -> messages.Task:
        return {
            "taskId": self.task_id,
            "kind": self.kind,
            "vehicle": str(self.vehicle),
            "imcId": self.imc_id,
            "featureId": self.feature_id,
            "sensor": self.sensor,
            "resolution": self.resolution,
            "deadline": self.deadline,
            "point": self.point,
            "state": self.state,
            "progress": self.progress,
            "quality": self.quality,
            "synch": self.last_synch,
            "operator": self.operator,
            "station": self.station,
            "createdAt": self.created_at,
            "updatedAt": self.updated_at,
            "stateAt": self.state_at,
        }


@dataclass
class VehicleInfo:
    imc_id: int
    provider: uuid.UUID | None
    capabilities: list[dict[str, Any]] | None = None  # None until its VehicleCapabilities arrives
    last_heard: float | None = None

    def to_json(self) -> dict[str, Any]:
        return {
            "imcId": self.imc_id,
            "providerId": str(self.provider) if self.provider else None,
            "capabilities": self.capabilities,
            "lastHeard": self.last_heard,
        }


def capability_json(m: Message) -> dict[str, Any]:
    out: dict[str, Any] = {"kind": CAPABILITY_KINDS[m.name]}
    for k, v in m.fields.items():
        key = {
            "res_bathym_factor": "resolutionBathymetryFactor",
            "cov_rate": "coverageRate",
            "cov_bathym_factor": "coverageBathymetryFactor",
        }.get(k, k)
        out[key] = _sensor_name(v) if k == "sensor" else (v if math.isfinite(v) else None)
    return out


def _sensor_name(v: int) -> str:
    try:
        return Sensor(v).name
    except ValueError:
        return f"UNKNOWN({v})"


class Saver(Protocol):
    def world(self, world: dict[str, Any]) -> None: ...
    def task(self, task: Task) -> None: ...


class _NotSaved:
    def world(self, world: dict[str, Any]) -> None:
        pass

    def task(self, task: Task) -> None:
        pass


class C2:
    def __init__(
        self,
        vehicles: dict[uuid.UUID, int],
        send: Callable[[Message, int], object],
        emit: Callable[[ServerMessage], None],
        save: Saver | None = None,
        station: str | None = None,
    ) -> None:
        self.send, self.emit, self.save, self.station = send, emit, save or _NotSaved(), station
        self.linked = False  # CoMap on: the console's IMC node is open (a synch is sent only then)
        self.vehicles: dict[int, VehicleInfo] = {i: VehicleInfo(i, g) for g, i in vehicles.items()}
        self.imc_of: dict[uuid.UUID, int] = dict(vehicles)
        self.features: list[Feature] = []
        self.world_updated_at: float | None = None
        self.world_source: str | None = None
        self.tasks: dict[int, Task] = {}
        self._highest_feature = 0  # the highest featureId seen (here and, stored, by the other consoles): new ones go above
        self.refused_world_models = 0  # WorldModels from peers that could not be used (a feature without vertices...)

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
        self.emit(worldmodel_message(self.world_model()))
        self.save.world(
            {
                "features": [asdict(f) for f in self.features],
                "updated_at": self.world_updated_at,
                "source": source,
                "highest_feature": self._highest_feature,
            }
        )

    def load_world(self, stored: Mapping[str, Any] | None) -> None:
        """The stored world model (Database.comap_world), applied when newer than this console's."""
        if stored is None:
            return
        self._saw_features([stored["highest_feature"]])
        if self.world_updated_at is not None and stored["updated_at"] <= self.world_updated_at:
            return
        self.features = [
            Feature(f["feature_id"], [(lat, lon) for lat, lon in f["points"]], f["coverage"], f["properties"])
            for f in stored["features"]
        ]
        self.world_updated_at, self.world_source = stored["updated_at"], stored["source"]
        self.emit(worldmodel_message(self.world_model()))

    def load_task(self, row: Mapping[str, Any]) -> None:
        """A stored task (Database.comap_tasks), applied where newer than this console's of that id: its state and synch
        when decided over ours (`state_at`, `decided_over`: another station's HOLD), its progress when reported after
        ours. Each by its own stamp: the vehicle's progress, stamped as each report comes, moves `updated_at` on faster
        than the notifications come, and comparing the whole change never let the other station's HOLD in (seen: B
        held, A showed IN_PROGRESS)."""
        task = Task(**{**row, "vehicle": uuid.UUID(row["vehicle"])})
        old = self.tasks.get(task.task_id)
        if old is not None and old.created_at > task.created_at:
            return  # a finished task of that id, which ours replaced
        if old is not None and old.created_at == task.created_at:
            state = decided_over(task.state, task.state_at, old.state, old.state_at)
            progress = task.updated_at > old.updated_at
            if not state and not progress:
                return
            if state:
                old.state, old.last_synch, old.state_at = task.state, task.last_synch, task.state_at
            if progress:
                old.progress, old.quality, old.updated_at = task.progress, task.quality, task.updated_at
            task = old
        self.tasks[task.task_id] = task
        self.emit(task_message(task.to_json()))

    # ---- IMC input ------------------------------------------------------------------------------
    def on_message(self, header: Header, m: Message) -> None:
        v = self.vehicles.get(header.src)
        if v is None:
            v = self.vehicles[header.src] = VehicleInfo(header.src, None)
        v.last_heard = time.time()
        if m.name == "WorldModel":
            try:
                self.features = features_from_world_model(m)
            except GeoError as e:  # the datagram was well formed (accepted), its model is not: counted apart
                self.refused_world_models += 1
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
        self._set(task, state, progressed=True)

    def _set(self, task: Task, state: str, decided: bool = False, progressed: bool = False) -> None:
        """The task's state now (a report of progress alone gives the one it has); `decided`: a synch, which decides
        the state whether or not it changed; `progressed`: a TaskStatus set its progress and quality. Only a decision
        stamps `state_at`, and only a progress report `updated_at`: a progress report keeps the stamp of the state it
        was read with, and so never stores a stale state over another station's newer one, and a synch keeps the
        stamp of the progress it was read with, and so never stores a stale progress over the assigning station's
        newer one (a HOLD stamped as progress, written after an outage, left a task COMPLETED at 0 % everywhere)."""
        now = time.time()
        if decided or state != task.state:
            task.state_at = now
        if progressed:
            task.updated_at = now
        task.state = state
        self.emit(task_message(task.to_json()))
        self.save.task(task)

    # ---- tasks ------------------------------------------------------------------------------------
    def plan(
        self,
        kind: str,
        vehicle: uuid.UUID,
        operator: str | None,
        *,
        feature_id: int | None = None,
        sensor: str = "ANY",
        resolution: float = 1.0,
        deadline: float | None = None,
        point: dict[str, float] | None = None,
    ) -> Task:
        """A task checked against the vehicle table and the world model, not sent; its id (0 here) is taken in the
        database (Database.new_comap_task), then `assign` sends it."""
        imc_id = self.imc_of.get(vehicle)
        if imc_id is None:
            raise TaskError(404, f"vehicle {vehicle} has no IMC system id in the console's vehicle table (--imc-vehicles)")
        if kind == "survey" and not any(f.feature_id == feature_id for f in self.features):
            raise TaskError(409, f"no feature {feature_id} in the world model")
        survey = kind == "survey"
        return Task(
            0,
            kind,
            vehicle,
            imc_id,
            operator,
            feature_id if survey else None,
            sensor if survey else None,
            resolution if survey else None,
            deadline if deadline is not None else time.time() + 3600,
            None if survey else point,
            station=self.station,
        )

    def assign(self, task: Task) -> Task:
        """Send a planned task, its id taken (TaskAdmin ASSIGN; a survey's world model first)."""
        if task.kind == "survey":
            assert task.sensor is not None and task.resolution is not None
            arg = msg(
                "SurveyTask",
                task_id=task.task_id,
                feature_id=task.feature_id,
                sensor=Sensor[task.sensor].value,
                resolution=task.resolution,
                deadline=task.deadline,
            )
            # the vehicle needs the feature's geometry: the world model goes first
            self.send(world_model_message(self.features), task.imc_id)
        else:
            assert task.point is not None
            arg = msg(
                "MoveTask",
                task_id=task.task_id,
                deadline=task.deadline,
                destination=msg("MapPoint", lat=math.radians(task.point["lat"]), lon=math.radians(task.point["lon"]), alt=0.0),
            )
        self.tasks[task.task_id] = task
        self.send(msg("TaskAdmin", tid=task.task_id, op=TaskOp.ASSIGN, arg=arg), task.imc_id)
        self.emit(task_message(task.to_json()))
        return task

    def synch(self, task_id: int, action: str) -> Task:
        task = self.tasks.get(task_id)
        if task is None:
            raise TaskError(404, f"no task {task_id}")
        if task.state in FINAL:
            raise TaskError(409, f"task {task_id} is {task.state}")
        if not self.linked or self.imc_of.get(task.vehicle) != task.imc_id:
            why = "CoMap is off (no --imc-port)" if not self.linked else f"IMC system {task.imc_id} is not in its --imc-vehicles"
            where = (
                f"on station {task.station!r}, which assigned it"
                if task.station not in (None, self.station)
                else "on a station with a CoMap link to it, or start this one with --imc-port and --imc-vehicles"
            )
            raise TaskError(409, f"task {task_id} cannot be synched from this console ({why}): synch it {where}")
        self.send(msg("SynchAdmin", op=SynchOp[action].value), task.imc_id)
        task.last_synch = action
        self._set(task, {"HOLD": "HELD", "RESUME": "IN_PROGRESS", "INTERRUPT": "INTERRUPTED"}[action], decided=True)
        return task

    def capabilities_of(self, provider: uuid.UUID) -> VehicleInfo | None:
        imc = self.imc_of.get(provider)
        return None if imc is None else self.vehicles.get(imc)
