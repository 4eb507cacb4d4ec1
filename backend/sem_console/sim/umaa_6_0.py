"""`sem-sim --umaa 6.0`: the simulated vehicles' reports as a UMAA 6.0 vehicle writes them.

The vehicles' models (`reports.py`) make 3.0.1 samples; `Writer60` writes each as its 6.0 counterpart, on the 6.0
topics (named after their types) with the report QoS of RTI's UMAAQoSLib (TelemetryQoS: best-effort, keep-last-1),
as a vehicle built on RTI's UMAA kit writes them:

- GPSReport -> UMAA::SEM::GPSStatus::GPSReportType (every clock and satellite member present; a satellite's number
  is its PRN; the clock's time uncertainty as its time figure of merit);
- GPSFixReport -> UMAA::SA::GlobalPoseStatus::GlobalPoseReportType (position, course, a level attitude heading along
  the course, the altitude above or the depth below the surface, MEASURED with a fix, else ESTIMATED; a 6.0 vehicle
  is on the surface, `reports.Sensors`: 6.0 has no GPS fix command to surface it);
- InertialSensorReport -> UMAA::SEM::InertialSensorStatus::InertialSensorReportType (the alignment stage; an INS
  that is off or restarting reports INIT, an aligned one the completed stage of its alignment);
- GPSFixStatusReport has no 6.0 counterpart and is not written.
"""

from __future__ import annotations

import math
import uuid
from typing import Any

from cyclonedds.core import Policy, Qos
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
from sem_console.dds.qos import representation
from sem_console.dds.topics import Sem, Sem60
from sem_console.umaa.samples import make

NIL = bytes(16)
# RTI UMAAQoSLib's TelemetryQoS writer (qos/umaa_qos_lib.xml in RTI's UMAA kit): best-effort, volatile, keep-last-1
TELEMETRY = Qos(Policy.Reliability.BestEffort, Policy.Durability.Volatile, Policy.History.KeepLast(1))
# The 3.0.1 alignment stages as 6.0 names them (3.0.1 spells coarse "COURSE"); 6.0 has no OPERATIONAL
_OP_STATUS = {"COURSE_GPS_ALIGNMENT": "COARSE_GPS_ALIGNMENT", "COURSE_STATIONARY_ALIGNMENT": "COARSE_STATIONARY_ALIGNMENT"}


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
    return GPSSatelliteType(
        antennaCarrierNoiseDensity=s.antennaCarrierNoiseDensity or 0.0, azimuth=s.azimuth or 0.0,
        basebandCarrierNoiseDensity=s.basebandCarrierNoiseDensity or 0.0, carrierFrequency=s.carrierFrequency or 0.0,
        constellationType=_constellation(s.constellationType),
        containsAlmanacData=bool(s.containsAlmanacData), elevation=s.elevation or 0.0, ephemerisData=bool(s.ephemerisData),
        satelliteID=float(prn), usedInFix=bool(s.usedInFix))


def gps_report(r: Any) -> GPSReportType:
    c = r.clock
    clock = make(GPSClockType,
        bias=c.bias or 0, biasUncertainty=c.biasUncertianty or 0, drift=c.drift or 0, driftUncertainty=c.driftUncertainty or 0,
        elapsedRealtime=c.elapsedRealtime or 0, elapsedRealtimeUncertainty=c.elapsedRealtimeUncertainty or 0,
        fullBias=c.fullBias or 0, hardwareClockDiscontinuityCount=c.hardwareClockDiscontinuityCount or 0,
        leapSecond=c.leapSecond or 0, referenceCarrierFrequency=c.referenceCarrierFrequency or 0.0,
        referenceCodeTypeFor=c.referenceCodeTypeFor or "",
        referenceConstellationType=_constellation(c.referenceConstellationType),
        time=c.time or 0, timeFigureOfMerit=tfom(c.timeUncertainty))
    return make(GPSReportType, clock=clock, numberSatellitesInView=r.numberSatellitesInView,
                satellites=[_satellite(s) for s in r.satellites], timeStamp=_time(r.timeStamp), source=_identifier(r.source))


def global_pose(fix: Any) -> GlobalPoseReportType:
    position = fix.position2DWithTime.geodeticPosition
    height = fix.altitudeMSL.altitude
    return GlobalPoseReportType(
        altitude=height if height >= 0 else None, altitudeAGL=None, altitudeASF=None, altitudeGeodetic=None,
        attitude=Orientation3DNEDType(pitch=PitchYNEDType(pitch=0.0), roll=RollXNEDType(roll=0.0),
                                      yaw=YawZNEDType(yaw=fix.trueCourse)),
        attitudeCovariance=None, course=fix.trueCourse, depth=-height if height < 0 else None,
        navigationSolution=NavSolution.MEASURED if fix.GPSLatLongValid else NavSolution.ESTIMATED,
        position=GeoPosition2D(geodeticLatitude=position.geodeticLatitude.latitude,
                               geodeticLongitude=position.geodeticLongitude.longitude),
        positionCovariance=None, timeStamp=_time(fix.timeStamp), source=_identifier(fix.source))


def ins_report(r: Any, aligned: dict[uuid.UUID, str]) -> InertialSensorReportType:
    """A 3.0.1 InertialSensorReport as 6.0's; `aligned`: per vehicle, the stage its last alignment completed with (kept
    here), what an aligned 6.0 INS reports where 3.0.1 says OPERATIONAL."""
    status = r.status.name
    vehicle = uuid.UUID(bytes=bytes(r.source))
    if status.endswith("_ALIGNMENT_COMPLETE"):
        aligned[vehicle] = status
    elif status == "OPERATIONAL":
        status = aligned.get(vehicle, "FINE_GPS_ALIGNMENT_COMPLETE")
    if r.state.name != "ON" and status != "INERTIAL_SENSOR_FAILURE":
        status = "INIT"
    return InertialSensorReportType(status=OpStatus[_OP_STATUS.get(status, status)], timeStamp=_time(r.timeStamp),
                                    source=_identifier(r.source))


class Writer60:
    """Writes the vehicles' 3.0.1 samples as their 6.0 counterparts (the module's docstring)."""

    def __init__(self, bus: Bus) -> None:
        self.writers = {sem: DataWriter(bus.participant, bus.topic(sem),
                                        qos=TELEMETRY + representation(sem.spec.xcdr2_only, writer=True))
                        for sem in (Sem60.GPS_REPORT, Sem60.GLOBAL_POSE_REPORT, Sem60.INS_REPORT)}
        self._aligned: dict[uuid.UUID, str] = {}  # per vehicle, the stage its alignment completed with

    def ins_report(self, r: Any) -> InertialSensorReportType:
        return ins_report(r, self._aligned)

    def _as_6_0(self, sem: Sem, sample: Any) -> tuple[Sem60, Any] | None:
        if sem is Sem.GPS_REPORT:
            return Sem60.GPS_REPORT, gps_report(sample)
        if sem is Sem.GPS_FIX_REPORT:
            return Sem60.GLOBAL_POSE_REPORT, global_pose(sample)
        if sem is Sem.INS_REPORT:
            return Sem60.INS_REPORT, self.ins_report(sample)
        return None  # GPSFixStatusReport: no 6.0 counterpart

    def write(self, sem: Sem, sample: Any) -> None:
        out = self._as_6_0(sem, sample)
        if out is not None:
            self.writers[out[0]].write(out[1])

    def dispose(self, sem: Sem, sample: Any) -> None:
        out = self._as_6_0(sem, sample)
        if out is not None:
            self.writers[out[0]].dispose(out[1])
