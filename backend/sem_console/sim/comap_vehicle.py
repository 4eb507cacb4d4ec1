"""The simulator as CoMap vehicles: each simulated vehicle is an IMC system (`--imc-id` for the
first, then one up per vehicle) on the simulator's UDP port.

A vehicle publishes its VehicleCapabilities (an area survey with each of its sensors, a point
survey, a move) every few seconds and keeps the last WorldModel it received. TaskAdmin ASSIGN:

- a SurveyTask of a feature it knows, with a sensor it has (or ANY): ACCEPT, then it drives its
  simulated GPS position (the UMAA GPSFixReport) over the feature, lawnmower lanes
  `survey_spacing` metres apart, reporting TaskStatus progress (distance done of the path) and
  CoverageState PARTIAL once on the feature, COMPLETED at the end;
- a MoveTask: ACCEPT, then it drives to the point;
- otherwise REJECT (unknown feature, a sensor it lacks, a task while another is running).

SynchAdmin HOLD stops it where it is, RESUME continues, INTERRUPT ends the task. A task past its
deadline ends with TaskStatus ERROR. Speeds follow `--time-scale` as every duration does.
"""

from __future__ import annotations

import itertools
import logging
import math
import time
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from sem_console.comap.codec import BROADCAST, Header, Message, msg
from sem_console.comap.geo import Feature, GeoError, distance_m, features_from_world_model, lawnmower
from sem_console.comap.messages import Coverage, Sensor, SynchOp, TaskOp, TaskStatusEnum
from sem_console.comap.transport import Endpoint, SocketNode
from sem_console.sim.models import Pilot

if TYPE_CHECKING:
    from sem_console.sim.options import SimOptions
    from sem_console.sim.reports import Sensors

log = logging.getLogger("sem-sim.comap")
CAPABILITIES_EVERY = 2.0  # s (real time)
STATUS_EVERY = 0.25  # s (real time) between TaskStatus reports of a running task


@dataclass
class RunningTask:
    task_id: int
    kind: str
    c2: int  # IMC id of the system that assigned it
    deadline: float
    path_m: float
    feature_id: int | None = None
    quality: int = 100
    held: bool = False
    covered: int | None = None  # the CoverageState last sent
    sent_at: float = 0.0


class ComapVehicle:
    def __init__(self, imc_id: int, sensors: Sensors, opts: SimOptions) -> None:
        self.imc_id, self.sensors, self.opts = imc_id, sensors, opts
        self.task: RunningTask | None = None
        self.sensor_kinds = [Sensor[s] for s in opts.imc_sensors]

    def capabilities(self) -> Message:
        caps = [
            msg(
                "CapabilityAreaSurvey",
                sensor=s.value,
                resolution=self.opts.imc_resolution,
                res_bathym_factor=1.0,
                cov_rate=self.opts.survey_speed * self.opts.survey_spacing,
                cov_bathym_factor=1.0,
            )
            for s in self.sensor_kinds
        ]
        caps += [
            msg("CapabilityPointSurvey", sensor=s.value, resolution=self.opts.imc_resolution, duration=10.0)
            for s in self.sensor_kinds
        ]
        return msg("VehicleCapabilities", capabilities=[*caps, msg("CapabilityMove", speed=self.opts.survey_speed)])

    @property
    def pilot(self) -> Pilot:
        if self.sensors.pilot is None:  # takes over from the circle where the vehicle is now
            lat, lon, course = self.sensors.track.at(self.sensors.t(time.monotonic()))
            self.sensors.pilot = Pilot(lat, lon, course)
        return self.sensors.pilot

    def assign(self, tid: int, arg: Message | None, c2: int, features: dict[int, Feature]) -> tuple[bool, str]:
        if self.task is not None and self.task.task_id != tid:
            return False, f"busy with task {self.task.task_id}"
        if arg is None:
            return False, "no task"
        if arg.name == "SurveyTask":
            feature = features.get(arg["feature_id"])
            if feature is None:
                return False, f"no feature {arg['feature_id']}"
            if arg["sensor"] != Sensor.ANY and arg["sensor"] not in self.sensor_kinds:
                return False, f"no sensor {arg['sensor']}"
            waypoints = lawnmower(feature.points, self.opts.survey_spacing)
            kind, deadline, fid = "survey", arg["deadline"], feature.feature_id
            want = arg["resolution"]
            quality = 100 if not (want > 0) else int(max(0, min(100, 100 * self.opts.imc_resolution / want)))
        elif arg.name == "MoveTask":
            d = arg["destination"]
            waypoints = [(math.degrees(d["lat"]), math.degrees(d["lon"]))]
            if not all(math.isfinite(x) for p in waypoints for x in p):
                return False, "destination is not a position"
            kind, deadline, fid, quality = "move", arg["deadline"], None, 100
        else:
            return False, f"cannot run a {arg.name}"
        p = self.pilot
        path = sum(distance_m(a, b) for a, b in itertools.pairwise([(p.lat, p.lon), *waypoints]))
        p.go(waypoints)
        self.task = RunningTask(tid, kind, c2, deadline, max(path, 1e-6), fid, quality)
        return True, "accepted"

    def synch(self, op: int) -> None:
        if self.task is None:
            return
        if op == SynchOp.HOLD:
            self.task.held = True
        elif op == SynchOp.RESUME:
            self.task.held = False
        elif op == SynchOp.INTERRUPT:
            self.pilot.go([])
            self.task = None

    def step(self, dt: float, send: Any) -> None:
        task = self.task
        if task is None:
            if self.sensors.pilot is not None:
                self.sensors.pilot.step(dt, 0.0)
            return
        speed = 0.0 if task.held else self.opts.survey_speed / self.opts.time_scale
        self.pilot.step(dt, speed)
        done = not self.pilot.waypoints
        progress = 100 if done else int(min(99, 100 * self.pilot.travelled / task.path_m))
        if task.kind == "survey":
            cov = Coverage.COMPLETED if done else Coverage.PARTIAL if self.pilot.travelled > 0 and progress > 0 else None
            if cov is not None and cov != task.covered:
                task.covered = cov
                send(msg("CoverageState", feature_id=task.feature_id, state=cov.value), task.c2)
        now = time.monotonic()
        late = time.time() > task.deadline and not done
        if done or late or now - task.sent_at >= STATUS_EVERY:
            task.sent_at = now
            status = TaskStatusEnum.COMPLETED if done else TaskStatusEnum.ERROR if late else TaskStatusEnum.IN_PROGRESS
            send(msg("TaskStatus", task_id=task.task_id, status=status.value, progress=progress, quality=task.quality), task.c2)
        if done or late:
            if late:
                self.pilot.go([])
            self.task = None


class ComapVehicles:
    """The CoMap side of one simulator process: one UDP socket, one IMC system per vehicle."""

    def __init__(self, opts: SimOptions, sensors: list[Sensors]) -> None:
        self.opts = opts
        self.node = SocketNode(Endpoint(opts.imc_id, opts.imc_peers), opts.imc_host, opts.imc_port or 0)
        self.vehicles = {opts.imc_id + i: ComapVehicle(opts.imc_id + i, s, opts) for i, s in enumerate(sensors)}
        self.features: dict[int, Feature] = {}
        self.last = time.monotonic()
        self.caps_at = 0.0
        log.info("CoMap: IMC systems %s on UDP %s:%d", ", ".join(map(str, self.vehicles)), opts.imc_host, opts.imc_port)

    def step(self) -> None:
        now = time.monotonic()
        dt, self.last = now - self.last, now
        for header, m, _addr in self.node.poll(lambda dst: dst in self.vehicles):
            try:
                self.on_message(header, m)
            except (GeoError, ValueError, KeyError) as e:
                log.warning("could not apply an IMC %s from %d: %s", m.name, header.src, e)
        if now - self.caps_at >= CAPABILITIES_EVERY:
            self.caps_at = now
            for v in self.vehicles.values():
                self.node.send(v.capabilities(), v.imc_id)
        for v in self.vehicles.values():
            v.step(dt, lambda m, dst, v=v: self.node.send(m, v.imc_id, dst))

    def targets(self, header: Header) -> list[ComapVehicle]:
        return list(self.vehicles.values()) if header.dst == BROADCAST else [self.vehicles[header.dst]]

    def on_message(self, header: Header, m: Message) -> None:
        if m.name == "WorldModel":
            self.features = {f.feature_id: f for f in features_from_world_model(m)}
        elif m.name == "SynchAdmin":
            for v in self.targets(header):
                v.synch(m["op"])
        elif m.name == "TaskAdmin" and m["op"] == TaskOp.ASSIGN:
            for v in self.targets(header):
                ok, why = v.assign(m["tid"], m["arg"], header.src, self.features)
                log.info("vehicle %d: task %d %s", v.imc_id, m["tid"], why)
                self.node.send(
                    msg("TaskAdmin", tid=m["tid"], op=(TaskOp.ACCEPT if ok else TaskOp.REJECT).value, arg=None),
                    v.imc_id,
                    header.src,
                )
        elif m.name == "TaskAdmin" and m["op"] == TaskOp.UNASSIGN:
            for v in self.targets(header):
                if v.task is not None and v.task.task_id == m["tid"]:
                    v.synch(SynchOp.INTERRUPT)
        elif m.name == "TaskAdmin" and m["op"] == TaskOp.STATUS_REQUEST:
            for v in self.targets(header):
                if v.task is not None and v.task.task_id == m["tid"]:
                    v.task.sent_at = 0.0  # the next step reports

    def close(self) -> None:
        self.node.close()
