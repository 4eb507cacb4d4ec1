"""Simulated vehicles: UMAA Service Providers for GPSFixControl, GPSFixStatus, GPSStatus,
InertialSensorControl and InertialSensorStatus (ICD 4.1 and 5.1).

One process, one participant, one writer per topic; each vehicle writes its own
instances (keyed by its source GUID). A single thread runs `Simulator.tick`, so no
state is shared between threads.
"""

from __future__ import annotations

import contextlib
import json
import logging
import math
import os
import random
import time
import uuid
from collections import OrderedDict
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

from cyclonedds.internal import InvalidSample
from cyclonedds.core import InstanceState

from UMAA.Common.MaritimeEnumeration.CommandStatusEnumType import CommandStatusEnumType as Status
from UMAA.Common.MaritimeEnumeration.CommandStatusReasonEnumType import CommandStatusReasonEnumType as Reason
from UMAA.Common.MaritimeEnumeration.GPSFixEnumType import GPSFixEnumType as FixState
from UMAA.Common.MaritimeEnumeration.GPSNavigationSolutionEnumType import GPSNavigationSolutionEnumType as NavSolution
from UMAA.Common.MaritimeEnumeration.InertialSensorStateEnumType import InertialSensorStateEnumType as InsState
from UMAA.Common.Measurement import (
    Altitude_HAE, Altitude_MSL, GeodeticLatitude, GeodeticLongitude, Position2D, Position2DTime,
    Position3D_WGS84, Velocity3D_PlatformNED,
)
from UMAA.SEM.GPSFixStatus import GPSFixReportType, GPSFixStatusReportType
from UMAA.SEM.GPSStatus import GPSClockType, GPSReportType, GPSSatelliteType
from UMAA.SEM.InertialSensorStatus import InertialSensorReportType

from sem_console.dds.bus import Bus, all_samples, wait_for_acks
from sem_console.dds.qos import TopicClass
from sem_console.dds.topics import Sem, Service
from sem_console.sim.models import MAX_USED, SUBMERGED_DEPTH_M, Ins, Track, make_sky
from sem_console.umaa.flow import TERMINAL
from sem_console.umaa.guid import from_guid, satellite_guid, stable_guid, to_guid
from sem_console.umaa.samples import make, now_datetime

log = logging.getLogger("sem-sim")

MAX_TOMBSTONES = 10_000
FAULTS = ("reject", "fail-midway", "no-answer", "slow", "skip-commanded", "ins-failure")


@dataclass
class SimOptions:
    vehicles: int = 1
    time_scale: float = 1.0  # every duration below is multiplied by this
    step_seconds: float = 0.5  # ISSUED -> COMMANDED -> EXECUTING
    surface_seconds: float = 8.0  # dive depth to surface, then a fix
    align_seconds: float = 12.0  # INS power-on to OPERATIONAL
    fix_rate: float = 5.0  # Hz, GPSFixReport and GPSFixStatusReport
    gps_rate: float = 1.0  # Hz, GPSReport
    ins_rate: float = 2.0  # Hz, InertialSensorReport
    satellites: int = 32
    sky_speed: float = 20.0
    on_startup: str = "fail"  # persisted commands found at startup: "fail" or "resume"
    orphan_grace: float = 10.0  # s a command may have no writer before it counts as canceled
    command_timeout: float = 300.0  # s an executing command may take before it fails with TIMEOUT
    state_file: Path | None = None  # where the provider journals command states (default: per domain, see Journal)
    health_file: Path | None = None  # touched every second while the simulator runs (for container healthchecks)
    slow_factor: float = 10.0
    faults: dict[int, set[str]] = field(default_factory=dict)  # vehicle index (1-based, 0 = all) -> faults
    start_lat: float = 36.80
    start_lon: float = -75.70

    def faults_for(self, index: int) -> set[str]:
        return self.faults.get(0, set()) | self.faults.get(index, set())

    def scaled(self, seconds: float) -> float:
        return seconds * self.time_scale


def vehicle_guid(index: int) -> uuid.UUID:
    """Stable source GUID of simulated vehicle `index` (1-based), the same on every run."""
    return stable_guid(f"sim-vehicle-{index}")


@dataclass
class Execution:
    """One command as the provider runs it."""

    service: Service
    command: Any
    received: float
    status: Status | None = None
    next_at: float = 0.0  # when the next flow step is due
    orphan_since: float | None = None
    reached: bool = False  # the commanded state was reached and reported
    ended: bool = False  # status and ack disposed

    @property
    def session(self) -> uuid.UUID:
        return from_guid(self.command.sessionID)


class Vehicle:
    def __init__(self, sim: Simulator, index: int) -> None:
        self.sim, self.index = sim, index
        self.opts = sim.opts
        self.guid = vehicle_guid(index)
        self.source = to_guid(self.guid)
        self.faults = self.opts.faults_for(index)
        seed = int.from_bytes(self.guid.bytes[:8], "big")
        self.rng = random.Random(seed)
        self.sky = make_sky(seed, self.opts.satellites, self.opts.sky_speed)
        self.track = Track(self.opts.start_lat + 0.02 * (index - 1), self.opts.start_lon + 0.02 * (index - 1),
                           course0=self.rng.uniform(0, 2 * math.pi))
        self.t0 = time.monotonic()
        self.ins = Ins(self.opts.scaled(self.opts.align_seconds), failed="ins-failure" in self.faults)
        self.depth = SUBMERGED_DEPTH_M
        self.surfacing = False
        self.fix_state = FixState.INITIATING
        self.executions: dict[tuple[Service, uuid.UUID], Execution] = {}
        self.ended: OrderedDict[tuple[Service, uuid.UUID], None] = OrderedDict()  # tombstones of ended commands
        self.next_report = {Sem.GPS_FIX_REPORT: 0.0, Sem.GPS_REPORT: 0.0, Sem.INS_REPORT: 0.0}

    # ---- sensor state -------------------------------------------------------------
    def t(self, now: float) -> float:
        return now - self.t0

    @property
    def exposure(self) -> float:
        """0 with the antenna under water, 1 at the surface."""
        return max(0.0, min(1.0, 1.0 - self.depth / SUBMERGED_DEPTH_M))

    @property
    def fix_valid(self) -> bool:
        return self.depth >= 0.0

    def step_models(self, now: float, dt: float) -> None:
        self.ins.step(self.t(now))
        if self.surfacing and self.depth < 0.0:
            rate = -SUBMERGED_DEPTH_M / max(self.opts.scaled(self.opts.surface_seconds), 1e-3)
            self.depth = min(0.0, self.depth + rate * dt)

    # ---- reports -------------------------------------------------------------------
    def satellites(self, now: float) -> list[GPSSatelliteType]:
        t = self.t(now)
        rows = []
        for s in self.sky:
            az, el = s.az_el(t)
            cn0 = s.cn0(el, self.exposure, self.rng.gauss(0, 1.0))
            rows.append((s, az, el, cn0))
        used = set()
        if self.fix_valid:
            strongest = sorted(rows, key=lambda r: -r[3])
            used = {id(r[0]) for r in strongest[:MAX_USED] if r[3] >= 30.0}
        return [make(
            GPSSatelliteType,
            antennaCarrierNoiseDensity=round(cn0, 1), azimuth=az, basebandCarrierNoiseDensity=round(max(cn0 - 1.5, 0.0), 1),
            carrierFrequency=s.frequency, constellationType=s.constellation, containsAlmanacData=s.almanac,
            elevation=el, ephemerisData=s.ephemeris, satelliteId=satellite_guid(s.constellation, s.prn),
            usedInFix=id(s) in used,
        ) for s, az, el, cn0 in rows]

    def gps_report(self, now: float, sats: list[GPSSatelliteType]) -> GPSReportType:
        elapsed_ns = int(self.t(now) * 1e9)
        clock = make(
            GPSClockType, bias=self.rng.randint(-50, 50), biasUncertianty=15, drift=self.rng.randint(-5, 5),
            driftUncertainty=2, elapsedRealtime=elapsed_ns % 2**31, elapsedRealtimeUncertainty=1000,
            fullBias=-1_234_567_890, hardwareClockDiscontinuityCount=0, leapSecond=18,
            referenceCarrierFrequency=1575.42e6, referenceCodeTypeFor="C/A",
            referenceConstellationType=self.sky[0].constellation, time=elapsed_ns % 2**31, timeUncertainty=20.0,
        )
        # every listed satellite is above the horizon (in view); whether it is tracked shows in its C/N0
        return GPSReportType(clock=clock, numberSatellitesInView=len(sats), satellites=sats,
                             source=self.source, timeStamp=now_datetime())

    def fix_reports(self, now: float, sats: list[GPSSatelliteType]) -> tuple[GPSFixReportType, GPSFixStatusReportType]:
        lat, lon, course = self.track.at(self.t(now))
        sog = self.track.speed
        rising = -SUBMERGED_DEPTH_M / max(self.opts.scaled(self.opts.surface_seconds), 1e-3) if self.surfacing and self.depth < 0 else 0.0
        fix = GPSFixReportType(
            altitudeMSL=Altitude_MSL(altitude=self.depth),
            GPSFixCommandStatus=self.fix_state,
            GPSLatLongValid=self.fix_valid,
            magneticVariation=math.radians(-10.8),
            position2DWithTime=Position2DTime(
                geodeticPosition=Position2D(GeodeticLatitude(lat), GeodeticLongitude(lon)), timeAtPosition=time.time()),
            SOG=sog, trueCourse=course,
            velocity=Velocity3D_PlatformNED(downSpeed=-rising, eastSpeed=sog * math.sin(course), northSpeed=sog * math.cos(course)),
            source=self.source, timeStamp=now_datetime(),
        )
        used_cn0 = sorted((s.antennaCarrierNoiseDensity or 0.0 for s in sats if s.usedInFix), reverse=True)[:11]
        status = GPSFixStatusReportType(
            carrierToNoise=used_cn0,
            countDown=max(0, math.ceil(-self.depth / -SUBMERGED_DEPTH_M * self.opts.scaled(self.opts.surface_seconds))) if self.surfacing else 0,
            fixValid=self.fix_valid, lowBkupBattery=False,
            navSolution=NavSolution.GPS_3D if self.fix_valid else NavSolution.GPS_DEAD_RECK,
            originPosition=Position3D_WGS84(
                Position2D(GeodeticLatitude(self.track.lat0), GeodeticLongitude(self.track.lon0)), Altitude_HAE(-36.5)),
            pCode=False, timeOut=not self.fix_valid, source=self.source, timeStamp=now_datetime(),
        )
        return fix, status

    def ins_report(self, now: float) -> InertialSensorReportType:
        return InertialSensorReportType(state=self.ins.state, status=self.ins.status(self.t(now)),
                                        source=self.source, timeStamp=now_datetime())

    def _reschedule(self, sem: Sem, rate: float, now: float) -> None:
        """Next due time from the previous one, so the tick does not stretch every period;
        after a stall (or a report forced early) the schedule starts again from now."""
        nxt = self.next_report[sem] + 1.0 / rate
        self.next_report[sem] = nxt if nxt > now else now + 1.0 / rate

    def publish_reports(self, now: float) -> None:
        due = {k: now >= v for k, v in self.next_report.items()}
        if due[Sem.GPS_FIX_REPORT] or due[Sem.GPS_REPORT]:
            sats = self.satellites(now)
            if due[Sem.GPS_REPORT]:
                self.sim.write(Sem.GPS_REPORT, self.gps_report(now, sats))
                self._reschedule(Sem.GPS_REPORT, self.opts.gps_rate, now)
            if due[Sem.GPS_FIX_REPORT]:
                fix, status = self.fix_reports(now, sats)
                self.sim.write(Sem.GPS_FIX_REPORT, fix)
                self.sim.write(Sem.GPS_FIX_STATUS_REPORT, status)
                self._reschedule(Sem.GPS_FIX_REPORT, self.opts.fix_rate, now)
        if due[Sem.INS_REPORT]:
            self.sim.write(Sem.INS_REPORT, self.ins_report(now))
            self._reschedule(Sem.INS_REPORT, self.opts.ins_rate, now)

    def dispose_reports(self) -> None:
        key = self.source
        self.sim.dispose(Sem.GPS_FIX_REPORT, make(GPSFixReportType, source=key, **_zero_fix()))
        self.sim.dispose(Sem.GPS_FIX_STATUS_REPORT, make(GPSFixStatusReportType, source=key, **_zero_fix_status()))
        self.sim.dispose(Sem.GPS_REPORT, make(GPSReportType, source=key, clock=make(GPSClockType), numberSatellitesInView=0,
                                              satellites=[], timeStamp=now_datetime()))
        self.sim.dispose(Sem.INS_REPORT, make(InertialSensorReportType, source=key, state=InsState.OFF,
                                              status=self.ins.status(0), timeStamp=now_datetime()))

    # ---- commands (ICD 4.1) ---------------------------------------------------------
    def step_delay(self) -> float:
        d = self.opts.scaled(self.opts.step_seconds)
        return d * self.opts.slow_factor if "slow" in self.faults else d

    def on_command(self, service: Service, cmd: Any, now: float, startup: bool, last_status: Status | None) -> None:
        key = (service, from_guid(cmd.sessionID))
        ex = self.executions.get(key)
        if ex is not None:
            ex.orphan_since = None  # a writer is back for this command: it is not orphaned
            return  # commands are immutable: a repeat of a known command changes nothing
        if key in self.ended:
            return  # canceled or cleaned up before: a republished sample must not start it again
        ex = Execution(service, cmd, received=now)
        self.executions[key] = ex
        if "no-answer" in self.faults:
            return
        if startup and last_status is not None:
            self.recover(ex, last_status, now)
        else:
            self.accept(ex, now)

    def recover(self, ex: Execution, last: Status, now: float) -> None:
        """Provider Startup Sequence for a command this provider had already answered (ICD 4.1.2.1)."""
        ex.status = last
        if last in TERMINAL:
            return  # finished: wait for the consumer's cleanup
        self.sim.write(ex.service.ack, self.ack_sample(ex))  # the ack died with the previous process
        if self.opts.on_startup == "resume":
            log.info("vehicle %d resumes %s %s from %s", self.index, ex.service.value, ex.session, last.name)
            ex.next_at = now
            if last is Status.EXECUTING:
                self.start_effect(ex, now)
        else:
            self.publish_status(ex, Status.FAILED, Reason.SERVICE_FAILED, "provider restarted and does not resume commands")

    def accept(self, ex: Execution, now: float) -> None:
        """Command Start Sequence: ISSUED; then, for a valid command it will run, the ack."""
        self.publish_status(ex, Status.ISSUED, Reason.SUCCEEDED, "command received")
        error = self.validate(ex)
        if error:
            self.publish_status(ex, Status.FAILED, Reason.VALIDATION_FAILED, error)
            return
        if "reject" in self.faults:
            self.publish_status(ex, Status.FAILED, Reason.RESOURCE_REJECTED, "resource rejected the command (injected fault)")
            return
        for other in self.executions.values():  # a newer command of a service supersedes the running one
            if other is not ex and other.service is ex.service and other.status not in TERMINAL and other.status is not None:
                self.publish_status(other, Status.FAILED, Reason.INTERRUPTED, f"superseded by command {ex.session}")
        self.sim.write(ex.service.ack, self.ack_sample(ex))
        ex.next_at = now + self.step_delay()

    def validate(self, ex: Execution) -> str | None:
        ts = ex.command.timeStamp
        if not 0 <= ts.nanoseconds <= 999_999_999 or ts.seconds < 0:
            return f"timeStamp out of range ({ts.seconds} s, {ts.nanoseconds} ns)"
        if ex.service is Service.INERTIAL_SENSOR and not isinstance(ex.command.state, InsState):
            return f"unknown inertial sensor state {ex.command.state!r}"
        return None

    def ack_sample(self, ex: Execution) -> Any:
        if ex.service is Service.GPS_FIX:
            return ex.service.ack.spec.type(source=self.source, sessionID=ex.command.sessionID)
        return ex.service.ack.spec.type(state=ex.command.state, source=self.source, sessionID=ex.command.sessionID)

    def status_sample(self, ex: Execution, status: Status, reason: Reason, message: str) -> Any:
        return ex.service.status.spec.type(source=self.source, commandStatus=status, commandStatusReason=reason,
                                           logMessage=message[:4095], sessionID=ex.command.sessionID, timeStamp=now_datetime())

    def publish_status(self, ex: Execution, status: Status, reason: Reason, message: str) -> None:
        ex.status = status
        self.sim.journal.set(self.guid, ex.service, ex.session, status)
        self.sim.write(ex.service.status, self.status_sample(ex, status, reason, message))
        log.info("vehicle %d %s %s -> %s/%s %s", self.index, ex.service.value, ex.session, status.name, reason.name, message)

    def start_effect(self, ex: Execution, now: float) -> None:
        if ex.service is Service.GPS_FIX:
            self.surfacing = True
            self.fix_state = FixState.INITIATING
        else:
            target = ex.command.state
            if target is InsState.ON and self.ins.state is InsState.ON:
                return  # already on: nothing to do but report it
            self.ins.set(target, self.t(now))

    def effect_done(self, ex: Execution, now: float) -> bool:
        if ex.service is Service.GPS_FIX:
            if self.fix_state is FixState.INITIATING and self.depth > SUBMERGED_DEPTH_M / 2:
                self.fix_state = FixState.PERFORMING
            if self.fix_valid:
                self.fix_state = FixState.STABLE
            return self.fix_valid
        target = ex.command.state
        if target is InsState.OFF:
            return self.ins.state is InsState.OFF
        status = self.ins.status(self.t(now))
        return self.ins.state is InsState.ON and status.name == "OPERATIONAL"

    def advance(self, ex: Execution, now: float) -> None:
        if ex.status in TERMINAL or ex.status is None or now < ex.next_at or "no-answer" in self.faults:
            return
        if ex.status is Status.ISSUED:
            if "skip-commanded" in self.faults:  # break Figure 4 on purpose
                self.publish_status(ex, Status.EXECUTING, Reason.SUCCEEDED, "executing (COMMANDED skipped: injected fault)")
                self.start_effect(ex, now)
            else:
                self.publish_status(ex, Status.COMMANDED, Reason.SUCCEEDED, "validated and commanded")
            ex.next_at = now + self.step_delay()
        elif ex.status is Status.COMMANDED:
            self.publish_status(ex, Status.EXECUTING, Reason.SUCCEEDED, "executing")
            self.start_effect(ex, now)
            ex.next_at = now + self.step_delay()
        elif ex.status is Status.EXECUTING:
            half = self.opts.scaled(self.opts.surface_seconds if ex.service is Service.GPS_FIX else self.opts.align_seconds) / 2
            if now - ex.received >= self.opts.scaled(self.opts.command_timeout):
                self.surfacing = False
                self.publish_status(ex, Status.FAILED, Reason.TIMEOUT, "the command did not finish in time")
            elif ex.service is Service.INERTIAL_SENSOR and self.ins.failed and ex.command.state is not InsState.OFF:
                self.publish_status(ex, Status.FAILED, Reason.RESOURCE_FAILED, "inertial sensor failure")
            elif "fail-midway" in self.faults and now - ex.received >= half:
                self.surfacing = False
                self.publish_status(ex, Status.FAILED, Reason.RESOURCE_FAILED, "resource failed during execution (injected fault)")
            elif self.effect_done(ex, now) and ("slow" not in self.faults or now >= ex.next_at):
                if not ex.reached:  # report the reached state first; COMPLETED follows on the next tick
                    ex.reached = True
                    self.next_report[Sem.GPS_FIX_REPORT if ex.service is Service.GPS_FIX else Sem.INS_REPORT] = 0.0
                else:
                    self.publish_status(ex, Status.COMPLETED, Reason.SUCCEEDED, "completed")

    def end(self, ex: Execution, now: float) -> None:
        """The consumer disposed the command (or it lost every writer): cancel or clean up."""
        if ex.ended:
            return
        if ex.status is not None and ex.status not in TERMINAL and "no-answer" not in self.faults:
            if ex.service is Service.GPS_FIX:
                self.surfacing = False  # stays where it is
            self.publish_status(ex, Status.CANCELED, Reason.CANCELED, "canceled by the consumer")
        if ex.status is not None:
            self.sim.dispose(ex.service.status, self.status_sample(ex, ex.status, Reason.SUCCEEDED, ""))
            self.sim.dispose(ex.service.ack, self.ack_sample(ex))
        ex.ended = True
        key = (ex.service, ex.session)
        del self.executions[key]
        self.ended[key] = None
        while len(self.ended) > MAX_TOMBSTONES:
            self.ended.popitem(last=False)
        self.sim.journal.drop(self.guid, ex.service, ex.session)

    def shutdown(self) -> None:
        """Provider Shutdown Sequence: fail what is incomplete, then dispose the reports."""
        for ex in list(self.executions.values()):
            if ex.status is not None and ex.status not in TERMINAL:
                self.publish_status(ex, Status.FAILED, Reason.SERVICE_FAILED, "provider shutting down")
        self.dispose_reports()


def _zero_fix() -> dict[str, Any]:
    pos = Position2D(GeodeticLatitude(0.0), GeodeticLongitude(0.0))
    return dict(altitudeMSL=Altitude_MSL(0.0), GPSFixCommandStatus=FixState.INITIATING, GPSLatLongValid=False,
                magneticVariation=0.0, position2DWithTime=Position2DTime(pos, None), SOG=0.0, trueCourse=0.0,
                velocity=Velocity3D_PlatformNED(0.0, 0.0, 0.0), timeStamp=now_datetime())


def _zero_fix_status() -> dict[str, Any]:
    pos = Position3D_WGS84(Position2D(GeodeticLatitude(0.0), GeodeticLongitude(0.0)), Altitude_HAE(0.0))
    return dict(carrierToNoise=[], countDown=0, fixValid=False, lowBkupBattery=False, navSolution=NavSolution.NO_NAV,
                originPosition=pos, pCode=False, timeOut=False, timeStamp=now_datetime())


class Journal:
    """The last status of each command a provider answered, in a small JSON file.

    Status and ack samples live in the provider's own transient-local writers, so they
    die with the process; this file is what lets a restarted provider tell a command it
    never saw (start it) from one it was running (resume or fail it) or had finished
    (leave it for the consumer's cleanup). Entries go when a command is cleaned up.
    """

    def __init__(self, path: Path) -> None:
        self.path = path
        try:
            self.entries: dict[str, str] = json.loads(path.read_text())
        except (OSError, ValueError):
            self.entries = {}

    @staticmethod
    def _key(vehicle: uuid.UUID, service: Service, session: uuid.UUID) -> str:
        return f"{vehicle}/{service.value}/{session}"

    def get(self, vehicle: uuid.UUID, service: Service, session: uuid.UUID) -> Status | None:
        name = self.entries.get(self._key(vehicle, service, session))
        return Status[name] if name in Status.__members__ else None

    def set(self, vehicle: uuid.UUID, service: Service, session: uuid.UUID, status: Status) -> None:
        self.entries[self._key(vehicle, service, session)] = status.name
        self._save()

    def drop(self, vehicle: uuid.UUID, service: Service, session: uuid.UUID) -> None:
        if self.entries.pop(self._key(vehicle, service, session), None) is not None:
            self._save()

    def _save(self) -> None:
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            tmp = self.path.with_suffix(".tmp")
            tmp.write_text(json.dumps(self.entries))
            tmp.replace(self.path)
        except OSError as e:  # a read-only disk must not stop the vehicle
            log.warning("cannot write %s: %s", self.path, e)


def default_state_file(domain: int) -> Path:
    base = Path(os.environ.get("XDG_STATE_HOME") or Path.home() / ".local" / "state")
    return base / "sem-sim" / f"domain-{domain}.json"


class Simulator:
    """Runs the vehicles of one `sem-sim` process on one DDS participant."""

    TICK = 0.02  # s

    def __init__(self, bus: Bus, opts: SimOptions) -> None:
        self.bus, self.opts = bus, opts
        self.journal = Journal(opts.state_file or default_state_file(bus.domain_id))
        # Provider Startup Sequence: publishers of status and ack (and reports) first ...
        self.writers = {sem: bus.writer(sem) for sem in Sem if sem.spec.cls is not TopicClass.COMMAND}
        self.vehicles = {v.guid: v for v in (Vehicle(self, i) for i in range(1, opts.vehicles + 1))}
        # ... then subscribe to commands; at startup the status readers tell where a persisted command stood.
        self.command_readers = {s: bus.reader(s.command) for s in Service}
        self.status_readers = {s: bus.reader(s.status) for s in Service}
        self.conditions = {s: all_samples(r) for s, r in self.command_readers.items()}
        self._bus_status: dict[tuple[uuid.UUID, uuid.UUID], Status] = {}
        self._health_at = 0.0
        self.last = time.monotonic()
        self.started = False

    def write(self, sem: Sem, sample: Any) -> None:
        self.writers[sem].write(sample)

    def dispose(self, sem: Sem, sample: Any) -> None:
        self.writers[sem].dispose(sample)

    def startup(self, window: float = 1.0) -> None:
        """Handle commands already on the bus addressed to our vehicles (ICD 4.1.2.1).

        For `window` seconds, commands that arrive are checked against the journal (and
        any status still on the bus) before they are treated as new.
        """
        deadline = time.monotonic() + window
        while time.monotonic() < deadline:
            self._take_bus_statuses()
            self.poll_commands(startup=True)
            self.step_vehicles()
            time.sleep(self.TICK)
        self.status_readers.clear()  # only needed for startup; they would keep our own statuses
        self.started = True

    def _take_bus_statuses(self) -> None:
        for reader in self.status_readers.values():
            for s in reader.take(N=4096):
                if not isinstance(s, InvalidSample) and from_guid(s.source) in self.vehicles:
                    self._bus_status[(from_guid(s.source), from_guid(s.sessionID))] = s.commandStatus

    def last_status(self, vehicle: Vehicle, service: Service, session: uuid.UUID) -> Status | None:
        return self.journal.get(vehicle.guid, service, session) or self._bus_status.get((vehicle.guid, session))

    def poll_commands(self, startup: bool = False) -> None:
        now = time.monotonic()
        for service, reader in self.command_readers.items():
            while True:
                try:
                    samples = reader.take(N=256, condition=self.conditions[service])
                except Exception as e:  # a sample Python cannot decode must not stop the vehicles
                    log.warning("undecodable %s command: %s", service.value, e)
                    break
                for s in samples:
                    self.handle(service, s, now, startup)
                if len(samples) < 256:
                    break

    def handle(self, service: Service, s: Any, now: float, startup: bool) -> None:
        state = s.sample_info.instance_state
        cmd = s.key_sample if isinstance(s, InvalidSample) else s
        try:
            dest, session = from_guid(cmd.destination), from_guid(cmd.sessionID)
        except (TypeError, ValueError):
            return
        vehicle = self.vehicles.get(dest)
        if vehicle is None:
            return  # addressed to another provider
        if not isinstance(s, InvalidSample):
            last = self.last_status(vehicle, service, session) if startup else None
            vehicle.on_command(service, s, now, startup, last)
        # A dispose that follows an unread sample shows only in that sample's instance state.
        ex = vehicle.executions.get((service, session))
        if ex is None:
            return
        if state == InstanceState.NotAliveDisposed:
            vehicle.end(ex, now)
        elif state == InstanceState.NotAliveNoWriters and ex.orphan_since is None:
            ex.orphan_since = now

    def tick(self) -> None:
        self.poll_commands()
        self.step_vehicles()

    def step_vehicles(self) -> None:
        now = time.monotonic()
        dt, self.last = now - self.last, now
        if self.opts.health_file and now - self._health_at >= 1.0:
            self._health_at = now
            with contextlib.suppress(OSError):
                self.opts.health_file.touch()
        for v in self.vehicles.values():
            v.step_models(now, dt)
            for ex in list(v.executions.values()):
                if ex.orphan_since is not None and now - ex.orphan_since >= self.opts.orphan_grace:
                    v.end(ex, now)
                else:
                    v.advance(ex, now)
            v.publish_reports(now)

    def run(self, stop: Callable[[], bool]) -> None:
        if not self.started:
            self.startup()
        while not stop():
            self.tick()
            time.sleep(self.TICK)

    def shutdown(self, ack_timeout: float = 2.0) -> None:
        for v in self.vehicles.values():
            v.shutdown()
        wait_for_acks(self.writers.values(), ack_timeout)
