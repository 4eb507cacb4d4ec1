"""One simulated vehicle's sensors and the reports they make: GPSReport, GPSFixReport,
GPSFixStatusReport and InertialSensorReport, each on its own schedule."""

from __future__ import annotations

import math
import random
import time
import uuid
from collections.abc import Callable
from typing import Any

from UMAA.Common.MaritimeEnumeration.GPSFixEnumType import GPSFixEnumType as FixState
from UMAA.Common.MaritimeEnumeration.GPSNavigationSolutionEnumType import GPSNavigationSolutionEnumType as NavSolution
from UMAA.Common.MaritimeEnumeration.InertialSensorStateEnumType import InertialSensorStateEnumType as InsState
from UMAA.Common.Measurement import (
    Altitude_HAE,
    Altitude_MSL,
    GeodeticLatitude,
    GeodeticLongitude,
    Position2D,
    Position2DTime,
    Position3D_WGS84,
    Velocity3D_PlatformNED,
)
from UMAA.SEM.GPSFixStatus import GPSFixReportType, GPSFixStatusReportType
from UMAA.SEM.GPSStatus import GPSClockType, GPSReportType, GPSSatelliteType
from UMAA.SEM.InertialSensorStatus import InertialSensorReportType

from sem_console.dds.topics import AnySem, Sem, Service
from sem_console.sim.models import MAX_USED, SUBMERGED_DEPTH_M, Ins, Pilot, Track, make_sky, sky_view
from sem_console.sim.options import SimOptions
from sem_console.umaa.guid import satellite_guid, to_guid
from sem_console.umaa.samples import make, now_datetime
from sem_console.versions.commands import commanding

Out = Callable[[AnySem, Any], None]  # a writer's write or dispose


class Sensors:
    def __init__(self, opts: SimOptions, number: int, guid: uuid.UUID, faults: set[str]) -> None:
        self.opts = opts
        self.source = to_guid(guid)
        seed = int.from_bytes(guid.bytes[:8], "big")
        self.rng = random.Random(seed)
        self.sky = make_sky(seed, opts.satellites, opts.sky_speed)
        self.orbits = [s.orbit for s in self.sky]
        ids: list[Any] = [bytes(satellite_guid(s.constellation, s.prn)) for s in self.sky]  # NumericGUIDs, packed as they are
        self.sky_samples = [  # every member given: the constructor itself (`make` fills absent ones)
            GPSSatelliteType(
                antennaCarrierNoiseDensity=0.0,
                azimuth=0.0,
                basebandCarrierNoiseDensity=0.0,
                carrierFrequency=s.frequency,
                constellationType=s.constellation,
                containsAlmanacData=s.almanac,
                elevation=0.0,
                ephemerisData=s.ephemeris,
                satelliteId=guid,
                usedInFix=False,
            )
            for s, guid in zip(self.sky, ids, strict=True)
        ]
        self.track = Track(
            opts.start_lat + 0.02 * (number - 1), opts.start_lon + 0.02 * (number - 1), course0=self.rng.uniform(0, 2 * math.pi)
        )
        self.t0 = time.monotonic()
        self.ins = Ins(opts.scaled(opts.align_seconds), failed="ins-failure" in faults)
        # a vehicle starts submerged and surfaces on a GPSFix command; one whose version has no GPS fix service (UMAA
        # 6.0) is on the surface, its position measured (under water it would be ESTIMATED, sim/umaa_6_0.py)
        self.depth = SUBMERGED_DEPTH_M if commanding(opts.version_of(number), Service.GPS_FIX) else 0.0
        self.surfacing = False
        self.fix_state = FixState.INITIATING
        self.pilot: Pilot | None = None  # set by the vehicle's CoMap side (comap_vehicle.py)
        self.next_report = {Sem.GPS_FIX_REPORT: 0.0, Sem.GPS_REPORT: 0.0, Sem.INS_REPORT: 0.0}
        self.next_due = 0.0  # the earliest of next_report: a vehicle with nothing due and nothing moving is not stepped
        self.stepped = self.t0

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

    @property
    def moving(self) -> bool:
        """Whether it changes between its reports (surfacing, its INS restarting): stepped every tick."""
        return self.surfacing or self.ins.state is InsState.RESTARTING

    def step(self, now: float) -> None:
        dt, self.stepped = now - self.stepped, now
        self.ins.step(self.t(now))
        if self.surfacing and self.depth < 0.0:
            rate = -SUBMERGED_DEPTH_M / max(self.opts.scaled(self.opts.surface_seconds), 1e-3)
            self.depth = min(0.0, self.depth + rate * dt)

    # ---- reports -------------------------------------------------------------------
    def satellites(self, now: float) -> list[GPSSatelliteType]:
        """The sky at `now`: the vehicle's own satellite samples, the same objects on every call (each made once, with
        the members that never change), their position, C/N0 and use in the fix set now; a report is written before
        the next call."""
        view = sky_view(self.orbits, self.t(now), self.exposure, self.rng.gauss)
        used = [False] * len(view)
        if self.fix_valid:  # the strongest, from 30 dB-Hz
            for i in sorted(range(len(view)), key=lambda i: view[i][2], reverse=True)[:MAX_USED]:
                used[i] = view[i][2] >= 30.0
        for sat, (az, el, cn0), in_fix in zip(self.sky_samples, view, used, strict=True):
            sat.azimuth, sat.elevation, sat.usedInFix = az, el, in_fix
            sat.antennaCarrierNoiseDensity = round(cn0, 1)
            sat.basebandCarrierNoiseDensity = round(max(cn0 - 1.5, 0.0), 1)
        return self.sky_samples

    def gps_report(self, now: float, sats: list[GPSSatelliteType]) -> GPSReportType:
        elapsed_ns = int(self.t(now) * 1e9)
        clock = make(
            GPSClockType,
            bias=self.rng.randint(-50, 50),
            biasUncertianty=15,
            drift=self.rng.randint(-5, 5),
            driftUncertainty=2,
            elapsedRealtime=elapsed_ns % 2**31,
            elapsedRealtimeUncertainty=1000,
            fullBias=-1_234_567_890,
            hardwareClockDiscontinuityCount=0,
            leapSecond=18,
            referenceCarrierFrequency=1575.42e6,
            referenceCodeTypeFor="C/A",
            referenceConstellationType=self.sky[0].constellation,
            time=elapsed_ns % 2**31,
            timeUncertainty=20.0,
        )
        # every listed satellite is above the horizon (in view); whether it is tracked shows in its C/N0
        return make(
            GPSReportType,
            clock=clock,
            numberSatellitesInView=len(sats),
            satellites=sats,
            source=self.source,
            timeStamp=now_datetime(),
        )

    def fix_reports(self, now: float, sats: list[GPSSatelliteType]) -> tuple[GPSFixReportType, GPSFixStatusReportType]:
        lat, lon, course = self.track.at(self.t(now))
        sog = self.track.speed
        if self.pilot is not None:  # under way for a CoMap task (or holding where one ended)
            lat, lon, course, sog = self.pilot.lat, self.pilot.lon, self.pilot.course, self.pilot.speed
        rising = (
            -SUBMERGED_DEPTH_M / max(self.opts.scaled(self.opts.surface_seconds), 1e-3)
            if self.surfacing and self.depth < 0
            else 0.0
        )
        fix = make(
            GPSFixReportType,
            altitudeMSL=Altitude_MSL(altitude=self.depth),
            GPSFixCommandStatus=self.fix_state,
            GPSLatLongValid=self.fix_valid,
            magneticVariation=math.radians(-10.8),
            position2DWithTime=Position2DTime(
                geodeticPosition=Position2D(GeodeticLatitude(lat), GeodeticLongitude(lon)), timeAtPosition=time.time()
            ),
            SOG=sog,
            trueCourse=course,
            velocity=Velocity3D_PlatformNED(
                downSpeed=-rising, eastSpeed=sog * math.sin(course), northSpeed=sog * math.cos(course)
            ),
            source=self.source,
            timeStamp=now_datetime(),
        )
        used_cn0 = sorted((s.antennaCarrierNoiseDensity or 0.0 for s in sats if s.usedInFix), reverse=True)[:11]
        status = make(
            GPSFixStatusReportType,
            carrierToNoise=used_cn0,
            countDown=max(0, math.ceil(-self.depth / -SUBMERGED_DEPTH_M * self.opts.scaled(self.opts.surface_seconds)))
            if self.surfacing
            else 0,
            fixValid=self.fix_valid,
            lowBkupBattery=False,
            navSolution=NavSolution.GPS_3D if self.fix_valid else NavSolution.GPS_DEAD_RECK,
            originPosition=Position3D_WGS84(
                Position2D(GeodeticLatitude(self.track.lat0), GeodeticLongitude(self.track.lon0)), Altitude_HAE(-36.5)
            ),
            pCode=False,
            timeOut=not self.fix_valid,
            source=self.source,
            timeStamp=now_datetime(),
        )
        return fix, status

    def ins_report(self, now: float) -> InertialSensorReportType:
        return make(
            InertialSensorReportType,
            state=self.ins.state,
            status=self.ins.status(self.t(now)),
            source=self.source,
            timeStamp=now_datetime(),
        )

    def _reschedule(self, sem: Sem, rate: float, now: float) -> None:
        """Next due time from the previous one, so the tick does not stretch every period;
        after a stall (or a report forced early) the schedule starts again from now."""
        nxt = self.next_report[sem] + 1.0 / rate
        self.next_report[sem] = nxt if nxt > now else now + 1.0 / rate
        self.next_due = min(self.next_report.values())

    def report_now(self, sem: Sem) -> None:
        self.next_report[sem] = self.next_due = 0.0

    def publish(self, now: float, write: Out) -> None:
        due = {k: now >= v for k, v in self.next_report.items()}
        if due[Sem.GPS_FIX_REPORT] or due[Sem.GPS_REPORT]:
            sats = self.satellites(now)
            if due[Sem.GPS_REPORT]:
                write(Sem.GPS_REPORT, self.gps_report(now, sats))
                self._reschedule(Sem.GPS_REPORT, self.opts.gps_rate, now)
            if due[Sem.GPS_FIX_REPORT]:
                fix, status = self.fix_reports(now, sats)
                write(Sem.GPS_FIX_REPORT, fix)
                write(Sem.GPS_FIX_STATUS_REPORT, status)
                self._reschedule(Sem.GPS_FIX_REPORT, self.opts.fix_rate, now)
        if due[Sem.INS_REPORT]:
            write(Sem.INS_REPORT, self.ins_report(now))
            self._reschedule(Sem.INS_REPORT, self.opts.ins_rate, now)

    def dispose(self, dispose: Out) -> None:
        key = self.source
        dispose(Sem.GPS_FIX_REPORT, make(GPSFixReportType, source=key, **_zero_fix()))
        dispose(Sem.GPS_FIX_STATUS_REPORT, make(GPSFixStatusReportType, source=key, **_zero_fix_status()))
        dispose(
            Sem.GPS_REPORT,
            make(
                GPSReportType,
                source=key,
                clock=make(GPSClockType),
                numberSatellitesInView=0,
                satellites=[],
                timeStamp=now_datetime(),
            ),
        )
        dispose(
            Sem.INS_REPORT,
            make(InertialSensorReportType, source=key, state=InsState.OFF, status=self.ins.status(0), timeStamp=now_datetime()),
        )


def _zero_fix() -> dict[str, Any]:
    pos = Position2D(GeodeticLatitude(0.0), GeodeticLongitude(0.0))
    return dict(
        altitudeMSL=Altitude_MSL(0.0),
        GPSFixCommandStatus=FixState.INITIATING,
        GPSLatLongValid=False,
        magneticVariation=0.0,
        position2DWithTime=Position2DTime(pos, None),
        SOG=0.0,
        trueCourse=0.0,
        velocity=Velocity3D_PlatformNED(0.0, 0.0, 0.0),
        timeStamp=now_datetime(),
    )


def _zero_fix_status() -> dict[str, Any]:
    pos = Position3D_WGS84(Position2D(GeodeticLatitude(0.0), GeodeticLongitude(0.0)), Altitude_HAE(0.0))
    return dict(
        carrierToNoise=[],
        countDown=0,
        fixValid=False,
        lowBkupBattery=False,
        navSolution=NavSolution.NO_NAV,
        originPosition=pos,
        pCode=False,
        timeOut=False,
        timeStamp=now_datetime(),
    )
