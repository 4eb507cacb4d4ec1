"""`sem-sim --umaa 6.0`: the simulated vehicles' reports as a UMAA 6.0 vehicle writes them.

The vehicles' models (`reports.py`) make 3.0.1 samples; `Writer60` writes each as its 6.0 counterpart, on the 6.0
topics (named after their types), as a vehicle built on RTI's UMAA kit writes them, with the console's report QoS
(reliable, transient-local, keep-last-1: it matches the readers of the kit's UMAAQoSLib, whose AssignerQoS as shipped
makes every endpoint reliable and transient-local, and those of its TelemetryQoS, best-effort):

- GPSReport -> UMAA::SEM::GPSStatus::GPSReportType (every clock and satellite member present; a satellite's number
  is its PRN; the clock's time uncertainty as its time figure of merit);
- GPSFixReport -> UMAA::SA::GlobalPoseStatus::GlobalPoseReportType (position, course, a level attitude heading along
  the course, the altitude above or the depth below the surface, MEASURED with a fix, else ESTIMATED; a 6.0 vehicle
  is on the surface, `reports.Sensors`: 6.0 has no GPS fix command to surface it);
- InertialSensorReport -> UMAA::SEM::InertialSensorStatus::InertialSensorReportType (the alignment stage; an INS
  that is off or restarting reports INIT, an aligned one the completed stage of its alignment);
- GPSFixStatusReport has no 6.0 counterpart and is not written.

Its vehicles answer InertialSensorCommandType (`Alignments`, the INS side of the provider flow, `provider_flow.py`):
the INS walks the stages of the commanded alignment, a stage each `--align-seconds`/3: coarse, fine started, fine
complete (GPS_ALIGN: COARSE_GPS_ALIGNMENT, FINE_GPS_ALIGNMENT_STARTED, FINE_GPS_ALIGNMENT_COMPLETE; likewise
STATIONARY, TRANSFER and BEST); SNAP_ALIGN reports SNAP_ALIGNMENT_COMPLETE after one stage; INIT reports INIT at once
(initialised, not aligned) and stays there until an alignment is commanded. The `fail-midway` fault fails the
alignment halfway with its kind's failure (GPS_ALIGNMENT_FAILURE...; INIT: INERTIAL_SENSOR_FAILURE); a canceled
alignment stays at the stage it reached. Their statuses and acks go on the 6.0 topics with RTI UMAAQoSLib's CommandQoS
(`dds/qos.py`).

With `--gps-extensibility appendable` GlobalPoseReportType, the one of them with optional members, is written with its
appendable copy (as RTI's UMAA types are; XCDR2), for RTI consumers (docs/umaa-versions.md, "RTI Connext").
"""

from __future__ import annotations

import math
import time
import uuid
from typing import Any

from cyclonedds.pub import DataWriter

from UMAA_6_0.Common import IdentifierType
from UMAA_6_0.Common.MaritimeEnumeration.GPSConstellationEnumModule import GPSConstellationEnumType as Constellation
from UMAA_6_0.Common.MaritimeEnumeration.InertialSensorOpStatusEnumModule import InertialSensorOpStatusEnumType as OpStatus
from UMAA_6_0.Common.MaritimeEnumeration.NavigationSolutionEnumModule import NavigationSolutionEnumType as NavSolution
from UMAA_6_0.Common.MaritimeEnumeration.TFOMEnumModule import TFOMEnumType as Tfom
from UMAA_6_0.Common.Measurement import DateTime, GeoPosition2D
from UMAA_6_0.Common.Orientation import Orientation3DNEDType, PitchYNEDType, RollXNEDType, YawZNEDType
from UMAA_6_0.SA.GlobalPoseStatus import GlobalPoseReportType
from UMAA_6_0.SEM.GPSStatus import GPSClockType, GPSReportType, GPSSatelliteType
from UMAA_6_0.SEM.InertialSensorStatus import InertialSensorReportType

from sem_console.dds.bus import Bus
from sem_console.dds.topics import AnySem, Sem, Sem60, to_appendable
from sem_console.sim.models import STATIONARY_STAGES
from sem_console.sim.options import SimOptions
from sem_console.sim.prepared import PreparedWriter
from sem_console.umaa.samples import make
from sem_console.versions import UMAA_6_0

NIL = bytes(16)
# The 3.0.1 alignment stages as 6.0 names them (3.0.1 spells coarse "COURSE"); 6.0 has no OPERATIONAL
_OP_STATUS = {"COURSE_GPS_ALIGNMENT": "COARSE_GPS_ALIGNMENT", "COURSE_STATIONARY_ALIGNMENT": "COARSE_STATIONARY_ALIGNMENT"}
# What an INS reports aligned when it reached OPERATIONAL without a completed stage seen (--align-seconds 0): the
# completed stage of its own alignment, stationary (`models.Ins`)
_ALIGNED = STATIONARY_STAGES[-1].name


def tfom(uncertainty_ns: float | None) -> Tfom:
    """The time figure of merit of a time error (1 sigma) in nanoseconds: TFOM_1 up to 1 ns, then one more a decade,
    TFOM_9 over 10 ms."""
    if uncertainty_ns is None or uncertainty_ns <= 1:
        return Tfom.TFOM_1
    return Tfom[f"TFOM_{min(9, 1 + math.ceil(math.log10(uncertainty_ns) - 1e-9))}"]


def _identifier(source: Any) -> IdentifierType:
    return make(IdentifierType, id=bytes(source), parentID=NIL)


def _time(t: Any) -> DateTime:
    return DateTime(seconds=t.seconds, nanoseconds=t.nanoseconds)


def _constellation(c: Any) -> Constellation:
    return Constellation[c.name if c is not None else "UNKNOWN"]  # the same literals in both versions


def _satellite(s: Any) -> GPSSatelliteType:
    prn = bytes(s.satelliteId)[15] if s.satelliteId is not None else 0
    sat = GPSSatelliteType(
        antennaCarrierNoiseDensity=0.0,
        azimuth=0.0,
        basebandCarrierNoiseDensity=0.0,
        carrierFrequency=s.carrierFrequency or 0.0,
        constellationType=_constellation(s.constellationType),
        containsAlmanacData=bool(s.containsAlmanacData),
        elevation=0.0,
        ephemerisData=bool(s.ephemerisData),
        satelliteID=float(prn),
        usedInFix=False,
    )
    _changing(sat, s)
    return sat


def _changing(sat: GPSSatelliteType, s: Any) -> None:
    """The members of a satellite that change between a vehicle's reports, from its 3.0.1 satellite."""
    sat.antennaCarrierNoiseDensity = s.antennaCarrierNoiseDensity or 0.0
    sat.azimuth = s.azimuth or 0.0
    sat.basebandCarrierNoiseDensity = s.basebandCarrierNoiseDensity or 0.0
    sat.elevation = s.elevation or 0.0
    sat.usedInFix = bool(s.usedInFix)


def _constant(s: Any) -> tuple[Any, ...]:
    return s.carrierFrequency, s.constellationType, s.containsAlmanacData, s.ephemerisData, s.satelliteId


class Skies:
    """Each vehicle's satellites as 6.0 writes them, made once from its 3.0.1 satellite samples (`Sensors.satellites`:
    the same objects every report) with their constant members; each report sets the members that change. A satellite
    whose sample is another object, or whose constant members changed, is made again."""

    def __init__(self) -> None:
        self._of: dict[bytes, list[tuple[Any, tuple[Any, ...], GPSSatelliteType] | None]] = {}  # by vehicle: 3.0.1, 6.0

    def __call__(self, vehicle: bytes, sats: list[Any]) -> list[GPSSatelliteType]:
        known = self._of.get(vehicle)
        if known is None or len(known) != len(sats):
            known = self._of[vehicle] = [None] * len(sats)
        out = []
        for i, s in enumerate(sats):
            entry, constant = known[i], _constant(s)
            if entry is not None and entry[0] is s and entry[1] == constant:
                sat = entry[2]
                _changing(sat, s)
            else:
                sat = _satellite(s)
                known[i] = (s, constant, sat)
            out.append(sat)
        return out


def gps_report(r: Any, skies: Skies | None = None) -> GPSReportType:
    """A 3.0.1 GPSReport as 6.0's; `skies`: the vehicles' 6.0 satellites, kept from one report to the next."""
    c = r.clock
    clock = make(
        GPSClockType,
        bias=c.bias or 0,
        biasUncertainty=c.biasUncertianty or 0,
        drift=c.drift or 0,
        driftUncertainty=c.driftUncertainty or 0,
        elapsedRealtime=c.elapsedRealtime or 0,
        elapsedRealtimeUncertainty=c.elapsedRealtimeUncertainty or 0,
        fullBias=c.fullBias or 0,
        hardwareClockDiscontinuityCount=c.hardwareClockDiscontinuityCount or 0,
        leapSecond=c.leapSecond or 0,
        referenceCarrierFrequency=c.referenceCarrierFrequency or 0.0,
        referenceCodeTypeFor=c.referenceCodeTypeFor or "",
        referenceConstellationType=_constellation(c.referenceConstellationType),
        time=c.time or 0,
        timeFigureOfMerit=tfom(c.timeUncertainty),
    )
    return make(
        GPSReportType,
        clock=clock,
        numberSatellitesInView=r.numberSatellitesInView,
        satellites=skies(bytes(r.source), r.satellites) if skies is not None else [_satellite(s) for s in r.satellites],
        timeStamp=_time(r.timeStamp),
        source=_identifier(r.source),
    )


def global_pose(fix: Any) -> GlobalPoseReportType:
    position = fix.position2DWithTime.geodeticPosition
    height = fix.altitudeMSL.altitude
    return GlobalPoseReportType(
        altitude=height if height >= 0 else None,
        altitudeAGL=None,
        altitudeASF=None,
        altitudeGeodetic=None,
        attitude=Orientation3DNEDType(
            pitch=PitchYNEDType(pitch=0.0), roll=RollXNEDType(roll=0.0), yaw=YawZNEDType(yaw=fix.trueCourse)
        ),
        attitudeCovariance=None,
        course=fix.trueCourse,
        depth=-height if height < 0 else None,
        navigationSolution=NavSolution.MEASURED if fix.GPSLatLongValid else NavSolution.ESTIMATED,
        position=GeoPosition2D(
            geodeticLatitude=position.geodeticLatitude.latitude, geodeticLongitude=position.geodeticLongitude.longitude
        ),
        positionCovariance=None,
        timeStamp=_time(fix.timeStamp),
        source=_identifier(fix.source),
    )


# per commanded kind (InertialSensorCmdEnumType), the stages its INS reports in turn; the last one is the aim
STAGES: dict[str, tuple[str, ...]] = {
    **{
        f"{kind}_ALIGN": (f"COARSE_{kind}_ALIGNMENT", f"FINE_{kind}_ALIGNMENT_STARTED", f"FINE_{kind}_ALIGNMENT_COMPLETE")
        for kind in ("BEST", "GPS", "STATIONARY", "TRANSFER")
    },
    "SNAP_ALIGN": ("INIT", "SNAP_ALIGNMENT_COMPLETE"),
    "INIT": ("INIT",),
}
FAILURE = {
    **{kind: f"{kind.removesuffix('_ALIGN')}_ALIGNMENT_FAILURE" for kind in STAGES if kind != "INIT"},
    "INIT": "INERTIAL_SENSOR_FAILURE",
}


class Alignment:
    """One vehicle's commanded alignment: its kind, since when (sensor seconds), where it stopped or failed."""

    def __init__(self, kind: str, since: float, stage_seconds: float) -> None:
        self.kind, self.since, self.stage_seconds = kind, since, stage_seconds
        self.stopped: str | None = None  # the stage a canceled or updated alignment stays at, or its failure

    def status(self, t: float) -> str:
        if self.stopped is not None:
            return self.stopped
        stages = STAGES[self.kind]
        step = int((t - self.since) / self.stage_seconds) if self.stage_seconds > 0 else len(stages)
        return stages[min(max(step, 0), len(stages) - 1)]

    def done(self, t: float) -> bool:
        return self.stopped is None and self.status(t) == STAGES[self.kind][-1]


class Alignments:
    """The INS side of a 6.0 vehicle's InertialSensorCommandType (provider_flow.InsEffects), for every vehicle of the
    simulator; `Writer60` reports each vehicle's stage."""

    def __init__(self, align_seconds: float) -> None:
        self.stage_seconds = align_seconds / 3  # coarse, fine started, fine complete
        self.by_vehicle: dict[uuid.UUID, tuple[Alignment, Any]] = {}  # with the sensors whose time it runs on

    def start(self, sensors: Any, command: Any, t: float) -> None:
        self.by_vehicle[uuid.UUID(bytes=bytes(sensors.source))] = (Alignment(command.state.name, t, self.stage_seconds), sensors)

    def _of(self, sensors: Any) -> Alignment | None:
        entry = self.by_vehicle.get(uuid.UUID(bytes=bytes(sensors.source)))
        return entry[0] if entry else None

    def done(self, sensors: Any, command: Any, t: float) -> bool:
        a = self._of(sensors)
        return a is not None and a.kind == command.state.name and a.done(t)

    def fail(self, sensors: Any, command: Any, t: float) -> None:
        a = self._of(sensors)
        if a is not None:
            a.stopped = FAILURE[a.kind]

    def stop(self, sensors: Any, command: Any, t: float) -> None:
        a = self._of(sensors)
        if a is not None and a.stopped is None:
            a.stopped = a.status(t)

    def status(self, vehicle: uuid.UUID) -> str | None:
        """The stage a vehicle's commanded alignment reports now; None: none commanded."""
        entry = self.by_vehicle.get(vehicle)
        if entry is None:
            return None
        a, sensors = entry
        return a.status(sensors.t(time.monotonic()))


def ins_report(r: Any, aligned: dict[uuid.UUID, str], commanded: str | None = None) -> InertialSensorReportType:
    """A 3.0.1 InertialSensorReport as 6.0's; `aligned`: per vehicle, the stage its last alignment completed with (kept
    here), what an aligned 6.0 INS reports where 3.0.1 says OPERATIONAL; `commanded`: the stage of the alignment a
    command started (`Alignments`), which it reports unless the INS failed."""
    status = r.status.name
    vehicle = uuid.UUID(bytes=bytes(r.source))
    if commanded is not None and status != "INERTIAL_SENSOR_FAILURE":
        return InertialSensorReportType(status=OpStatus[commanded], timeStamp=_time(r.timeStamp), source=_identifier(r.source))
    if status.endswith("_ALIGNMENT_COMPLETE"):
        aligned[vehicle] = status
    elif status == "OPERATIONAL":
        status = aligned.get(vehicle, _ALIGNED)
    if r.state.name != "ON" and status != "INERTIAL_SENSOR_FAILURE":
        status = "INIT"
    return InertialSensorReportType(
        status=OpStatus[_OP_STATUS.get(status, status)], timeStamp=_time(r.timeStamp), source=_identifier(r.source)
    )


class Writer60:
    """Writes the vehicles' 3.0.1 samples as their 6.0 counterparts (the module's docstring)."""

    @staticmethod
    def speaks(opts: SimOptions, number: int) -> bool:
        """Whether vehicle `number` speaks UMAA 6.0 (--umaa 6.0, --umaa-6-0-vehicles): its samples go through here."""
        return opts.version_of(number) == UMAA_6_0

    @classmethod
    def of_fleet(cls, bus: Bus, opts: SimOptions) -> Writer60 | None:
        """The writer of the simulator's 6.0 vehicles; None when it runs none."""
        if not any(cls.speaks(opts, n) for n in opts.numbers):
            return None
        return cls(bus, opts.scaled(opts.align_seconds), opts.gps_extensibility == "appendable")

    def __init__(self, bus: Bus, align_seconds: float, appendable: bool = False) -> None:
        # appendable (--gps-extensibility appendable): the type with optional members, GlobalPoseReportType, written with
        # its appendable copy in XCDR2, as RTI's UMAA types are, for an RTI consumer (docs/umaa-versions.md)
        sems = (Sem60.GPS_REPORT, Sem60.GLOBAL_POSE_REPORT, Sem60.INS_REPORT)
        self.appendable = {s for s in sems if appendable and s.spec.appendable is not None}
        self.writers: dict[AnySem, DataWriter[Any]] = {  # batched: the simulator sends them at the end of each tick
            sem: bus.writer(sem, appendable=sem in self.appendable, batching=True) for sem in sems
        }
        # the command flow's statuses and acks: reliable, transient-local, with RTI UMAAQoSLib's CommandQoS (bus.writer)
        self.writers.update({sem: bus.writer(sem) for sem in (Sem60.INS_COMMAND_STATUS, Sem60.INS_COMMAND_ACK)})
        self.prepared = {sem: PreparedWriter(self.writers[sem]) for sem in sems}  # the reports (sim/prepared.py)
        self._aligned: dict[uuid.UUID, str] = {}  # per vehicle, the stage its alignment completed with
        self.skies = Skies()
        self.alignments = Alignments(align_seconds)

    def ins_report(self, r: Any) -> InertialSensorReportType:
        return ins_report(r, self._aligned, self.alignments.status(uuid.UUID(bytes=bytes(r.source))))

    def _as_6_0(self, sem: Sem, sample: Any) -> tuple[Sem60, Any] | None:
        if sem is Sem.GPS_REPORT:
            return Sem60.GPS_REPORT, gps_report(sample, self.skies)
        if sem is Sem.GPS_FIX_REPORT:
            return Sem60.GLOBAL_POSE_REPORT, global_pose(sample)
        if sem is Sem.INS_REPORT:
            return Sem60.INS_REPORT, self.ins_report(sample)
        return None  # GPSFixStatusReport: no 6.0 counterpart

    def write(self, sem: AnySem, sample: Any) -> None:
        """A 3.0.1 report as its 6.0 counterpart; a 6.0 sample (a command's status or ack) as it is."""
        out = self._as_6_0(sem, sample) if isinstance(sem, Sem) else (sem, sample)
        if out is not None:
            sample = to_appendable(out[1]) if out[0] in self.appendable else out[1]
            prepared = self.prepared.get(out[0])
            if prepared is not None:
                prepared.write(sample)
            else:
                self.writers[out[0]].write(sample)

    def dispose(self, sem: AnySem, sample: Any) -> None:
        out = self._as_6_0(sem, sample) if isinstance(sem, Sem) else (sem, sample)
        if out is not None:
            self.writers[out[0]].dispose(to_appendable(out[1]) if out[0] in self.appendable else out[1])
