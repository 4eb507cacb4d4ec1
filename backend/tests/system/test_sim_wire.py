"""What `sem-sim` writes, read back with cyclonedds over loopback and checked member by member against what its
vehicles mean (sim/models.py and sim/reports.py, restated here): each satellite where its orbit puts it at the
report's time with its own constants, the position on the vehicle's circle at the time of its course, the clock's and
the fix's constants, time stamps of now, the INS's stages, the fault of a failed INS, a surfacing on a GPS fix command,
and both UMAA versions in one fleet. It fails when the simulator's fast paths (prepared samples and bytes) corrupt a
member."""

from __future__ import annotations

import math
import time
from typing import Any

import pytest

from UMAA.Common.MaritimeEnumeration.GPSFixEnumType import GPSFixEnumType as Fix
from UMAA.Common.MaritimeEnumeration.GPSNavigationSolutionEnumType import GPSNavigationSolutionEnumType as Nav
from UMAA.Common.MaritimeEnumeration.InertialSensorOpStatusEnumType import InertialSensorOpStatusEnumType as Op
from UMAA.Common.MaritimeEnumeration.InertialSensorStateEnumType import InertialSensorStateEnumType as InsState

from sem_console.dds.bus import Bus, all_samples
from sem_console.dds.cyclone_private import InvalidSample
from sem_console.dds.topics import Sem, Sem60, Service
from sem_console.sim.models import MAX_USED, SUBMERGED_DEPTH_M, Ins, Satellite
from sem_console.sim.options import SimOptions, vehicle_guid
from sem_console.sim.reports import Sensors
from sem_console.sim.umaa_6_0 import tfom
from sem_console.umaa.guid import satellite_guid
from support.consumer import Consumer

# the simulator's options (conftest's FAST, then these): vehicle 2's INS failed, vehicle 3 speaks UMAA 6.0
ARGS = ["--vehicles", "3", "--fault", "ins-failure:2", "--umaa-6-0-vehicles", "3"]
OPTS = SimOptions(
    vehicles=3, faults={2: {"ins-failure"}}, umaa_6_0_vehicles={3}, time_scale=0.05, fix_rate=10, ins_rate=10, gps_rate=4
)
V1, V2, V3 = (vehicle_guid(n) for n in (1, 2, 3))
ANGLE = 1e-9  # rad: a satellite's or a course's error at a report's own time (sub-nanosecond)
DEG = 1e-9  # degrees of latitude or longitude: 0.1 mm
LATE = 0.5  # s: at most from a report's time to its time stamp (a loaded machine delays a process)


def _model(number: int) -> Sensors:
    """The vehicle as the simulator builds it (its seed, sky, track and INS follow from its number)."""
    return Sensors(OPTS, number, vehicle_guid(number), OPTS.faults_for(number))


def _stamp(t: Any) -> float:
    return float(t.seconds + t.nanoseconds / 1e9)


def _sky_at(s: Satellite, t: float) -> tuple[float, float]:
    """A satellite's azimuth (-pi..pi) and elevation (3..89 degrees) t seconds after its vehicle started."""
    az = (s.az0 + s.az_rate * t) % (2 * math.pi)
    az = az - 2 * math.pi if az > math.pi else az
    el = s.el_mid + s.el_amp * math.sin(s.el_rate * t + s.phase)
    return az, min(max(el, math.radians(3)), math.radians(89))


def _angle_near(a: float, b: float) -> bool:
    return abs((a - b + math.pi) % (2 * math.pi) - math.pi) < ANGLE


class Clock:
    """A vehicle's time since its start, which its reports are made for: a course gives it (the course turns at a known
    rate from a known start, within the first turn of the circle, 12 minutes), and a GPSReport's clock its
    nanoseconds (modulo 2^31); its start on the wall clock is the earliest a time stamp allows (a stamp is taken after
    the time the report is made for)."""

    def __init__(self, model: Sensors, fixes: list[tuple[float, float]]) -> None:
        self.track = model.track
        self.start = min(stamp - self.of_course(course) for course, stamp in fixes)

    def of_course(self, course: float) -> float:
        return ((course - self.track.course0) % (2 * math.pi)) / self.track.turn_rate

    def of_clock(self, elapsed_ns: int, stamp: float) -> float:
        """The time a GPSReport was made for, from its clock's elapsed nanoseconds (modulo 2^31) and its stamp."""
        wraps = round((self.t(stamp) * 1e9 - elapsed_ns) / 2**31)
        return (wraps * 2**31 + elapsed_ns) / 1e9

    def t(self, stamp: float) -> float:
        return stamp - self.start

    def stamped(self, t: float, stamp: float) -> None:
        """The report made for t was stamped then: not before it (but for the drift of the wall clock against the
        monotonic one its times are taken from, and the precision of a stamp), and soon after."""
        assert -1e-3 <= self.t(stamp) - t < LATE, (t, self.t(stamp))


def _check_position(model: Sensors, clock: Clock, stamp: float, lat: float, lon: float, course: float) -> float:
    """The position on the vehicle's circle at the time its course gives; that time."""
    t = clock.of_course(course)
    lat_m, lon_m, course_m = model.track.at(t)
    assert abs(lat - lat_m) < DEG and abs(lon - lon_m) < DEG, (lat, lon, lat_m, lon_m)
    assert _angle_near(course, course_m)
    clock.stamped(t, stamp)
    return t


def _check_sky(model: Sensors, t: float, sats: list[Any], exposure: float | None, six: bool) -> None:
    """Every satellite in the sky's order with its own constants, where its orbit puts it at t, its C/N0 (rounded to a
    tenth, the baseband's 1.5 dB lower) as its elevation and the antenna's exposure make it (a noise of one dB: under
    water twice its size, at the surface 28 + 22 sin(elevation) plus it; `exposure` None: surfacing, somewhere between),
    and at the surface the strongest (at most 12, from 30 dB-Hz) used in the fix."""
    assert len(sats) == len(model.sky) == OPTS.satellites
    for s, sky in zip(sats, model.sky, strict=True):
        if six:
            assert s.satelliteID == float(sky.prn) and s.constellationType.name == sky.constellation.name
        else:
            assert list(s.satelliteId) == satellite_guid(sky.constellation, sky.prn) and s.constellationType is sky.constellation
        assert s.carrierFrequency == sky.frequency and s.containsAlmanacData is sky.almanac and s.ephemerisData is sky.ephemeris
        az, el = _sky_at(sky, t)
        assert _angle_near(s.azimuth, az) and abs(s.elevation - el) < ANGLE
        cn0, baseband = s.antennaCarrierNoiseDensity, s.basebandCarrierNoiseDensity
        assert cn0 == round(cn0, 1) and baseband == round(baseband, 1) and abs(baseband - max(cn0 - 1.5, 0.0)) < 0.01
        clear = 28.0 + 22.0 * math.sin(s.elevation)
        if exposure == 0.0:
            assert 0.0 <= cn0 < 13.0, cn0
        elif exposure == 1.0:
            assert abs(cn0 - clear) < 6.5, (cn0, clear)
        else:
            assert 0.0 <= cn0 < max(13.0, clear + 6.5), (cn0, clear)
    used = [s.antennaCarrierNoiseDensity for s in sats if s.usedInFix]
    unused = [s.antennaCarrierNoiseDensity for s in sats if not s.usedInFix]
    if exposure == 0.0:
        assert used == []
    if exposure != 1.0:
        return
    assert 0 < len(used) <= MAX_USED and min(used) >= 30.0
    if len(used) < MAX_USED:
        assert all(c < 30.05 for c in unused)
    assert min(used) >= max(unused) - 0.1  # the strongest, within the rounding of the C/N0 written


def _check_clock(model: Sensors, clock: Any, six: bool) -> None:
    assert -50 <= clock.bias <= 50 and -5 <= clock.drift <= 5
    assert (clock.biasUncertainty if six else clock.biasUncertianty) == 15 and clock.driftUncertainty == 2
    assert 0 <= clock.elapsedRealtime < 2**31 and clock.time == clock.elapsedRealtime
    assert clock.elapsedRealtimeUncertainty == 1000 and clock.fullBias == -1_234_567_890
    assert clock.hardwareClockDiscontinuityCount == 0 and clock.leapSecond == 18
    assert clock.referenceCarrierFrequency == 1575.42e6 and clock.referenceCodeTypeFor == "C/A"
    assert clock.referenceConstellationType.name == model.sky[0].constellation.name
    if six:
        assert clock.timeFigureOfMerit is tfom(20.0)
    else:
        assert clock.timeUncertainty == 20.0


def _current(stamps: list[float], began: float) -> None:
    """Time stamps of now, in the order written, at the report's rate."""
    assert stamps == sorted(stamps) and began - 1 <= stamps[0] and stamps[-1] <= time.time() + 0.1


def _at_rate(stamps: list[float], rate: float) -> None:
    """Reports no more often than the report's rate, on average over those read (a reader that keeps the latest, in a
    loaded test process, misses some, which only lowers it; a late tick shortens one interval and lengthens the one
    before: that none is missing is test_sim_flush.py's)."""
    assert len(stamps) >= 5
    assert (len(stamps) - 1) / (stamps[-1] - stamps[0]) <= 1.3 * rate, (len(stamps), stamps[-1] - stamps[0], rate)


def _take(readers: dict[Any, Any], into: dict[Any, dict[bytes, list[Any]]], late: dict[Any, list[float]]) -> None:
    """The readers' samples by topic and vehicle, and by topic how long after its stamp each arrived."""
    for sem, r in readers.items():
        for s in r.take(N=1000, condition=all_samples(r)):
            if not isinstance(s, InvalidSample):
                into.setdefault(sem, {}).setdefault(bytes(getattr(s.source, "id", s.source)), []).append(s)
                late.setdefault(sem, []).append(time.time() - _stamp(s.timeStamp))


@pytest.mark.timeout(120)
def test_every_member_of_every_report_is_what_the_vehicle_means(sim, consumer: Consumer, new_bus: Any, domain: int) -> None:
    bus: Bus = new_bus(domain)
    six_readers = {sem: bus.reader(sem) for sem in (Sem60.GPS_REPORT, Sem60.GLOBAL_POSE_REPORT, Sem60.INS_REPORT)}
    readers = {**six_readers, **{sem: bus.reader(sem) for sem in Sem if sem.spec.cls.value == "report"}}
    six: dict[Any, dict[bytes, list[Any]]] = {}
    late: dict[Any, list[float]] = {}
    began = time.time()
    sim(*ARGS)

    def has(n: int) -> bool:
        _take(readers, six, late)
        three = [sem for sem in Sem if sem.spec.cls.value == "report"]
        return all(len(consumer.reports[sem].get(v, [])) >= n for sem in three for v in (V1, V2)) and all(
            len(six.get(sem, {}).get(V3.bytes, [])) >= n for sem in six_readers
        )

    consumer.wait(lambda: has(12), 30, "a dozen reports of every topic from every vehicle")
    # vehicle 1 surfaces on a GPS fix command: a valid fix, satellites used, then its reports until the fix is stable
    consumer.command(Service.GPS_FIX, V1)
    consumer.wait(lambda: consumer.latest(Sem.GPS_FIX_REPORT, V1).GPSFixCommandStatus is Fix.STABLE, 15, "a stable fix")
    consumer.wait(lambda: has(24), 15, "a dozen more reports")
    assert set(late) == set(readers)  # every topic read (each tick's reports leave at its end: test_sim_flush.py)

    for v, number in ((V1, 1), (V2, 2)):
        model = _model(number)
        fixes = consumer.reports[Sem.GPS_FIX_REPORT][v]
        clock = Clock(model, [(f.trueCourse, _stamp(f.timeStamp)) for f in fixes])
        for sem in (Sem.GPS_FIX_REPORT, Sem.GPS_FIX_STATUS_REPORT, Sem.GPS_REPORT, Sem.INS_REPORT):
            reports = consumer.reports[sem][v]
            assert all(bytes(r.source) == v.bytes for r in reports)
            _current([_stamp(r.timeStamp) for r in reports], began)
        _at_rate([_stamp(r.timeStamp) for r in fixes], OPTS.fix_rate)
        _at_rate([_stamp(r.timeStamp) for r in consumer.reports[Sem.GPS_REPORT][v]], OPTS.gps_rate)
        _at_rate([_stamp(r.timeStamp) for r in consumer.reports[Sem.INS_REPORT][v]], OPTS.ins_rate)
        surfaced_at, submerged_until = math.inf, -math.inf  # the first stamp at the surface, the last under water
        fix_times: dict[float, float] = {}  # each fix report's time: its stamp
        for f in fixes:
            stamp = _stamp(f.timeStamp)
            pos = f.position2DWithTime
            lat, lon = pos.geodeticPosition.geodeticLatitude.latitude, pos.geodeticPosition.geodeticLongitude.longitude
            t = _check_position(model, clock, stamp, lat, lon, f.trueCourse)
            fix_times[t] = stamp
            clock.stamped(t, pos.timeAtPosition)
            assert pos.timeAtPosition <= stamp
            assert model.track.speed == f.SOG and f.magneticVariation == math.radians(-10.8)
            assert f.velocity.northSpeed == f.SOG * math.cos(f.trueCourse) and f.velocity.eastSpeed == f.SOG * math.sin(
                f.trueCourse
            )
            depth = f.altitudeMSL.altitude
            assert SUBMERGED_DEPTH_M <= depth <= 0.0 and f.GPSLatLongValid is (depth >= 0.0)
            rising = -SUBMERGED_DEPTH_M / OPTS.scaled(OPTS.surface_seconds)
            assert f.velocity.downSpeed in ((0.0, -rising) if depth == SUBMERGED_DEPTH_M else (-rising,) if depth < 0 else (0.0,))
            if depth >= 0.0:
                surfaced_at = min(surfaced_at, stamp)
            if depth == SUBMERGED_DEPTH_M:
                submerged_until = stamp
            if v == V2:
                assert depth == SUBMERGED_DEPTH_M and f.GPSFixCommandStatus is Fix.INITIATING
        assert (surfaced_at < math.inf) is (v == V1)
        for s in consumer.reports[Sem.GPS_FIX_STATUS_REPORT][v]:
            origin = s.originPosition
            assert origin.geodeticPosition.geodeticLatitude.latitude == model.track.lat0
            assert (
                origin.geodeticPosition.geodeticLongitude.longitude == model.track.lon0
                and origin.heightAboveEllipsoid.altitude == -36.5
            )
            valid = _stamp(s.timeStamp) >= surfaced_at
            assert s.fixValid is valid and s.timeOut is (not valid) and s.lowBkupBattery is False and s.pCode is False
            assert s.navSolution is (Nav.GPS_3D if valid else Nav.GPS_DEAD_RECK)
            assert 0 <= s.countDown <= math.ceil(OPTS.scaled(OPTS.surface_seconds)) and (valid or s.carrierToNoise == [])
            assert s.carrierToNoise == sorted(s.carrierToNoise, reverse=True) and len(s.carrierToNoise) <= 11
        statuses = [(_stamp(s.timeStamp), s) for s in consumer.reports[Sem.GPS_FIX_STATUS_REPORT][v]]
        for g in consumer.reports[Sem.GPS_REPORT][v]:
            stamp = _stamp(g.timeStamp)
            assert g.numberSatellitesInView == len(g.satellites)
            t = clock.of_clock(g.clock.elapsedRealtime, stamp)
            clock.stamped(t, stamp)
            exposure = 0.0 if stamp <= submerged_until else 1.0 if stamp >= surfaced_at else None
            _check_sky(model, t, g.satellites, exposure, six=False)
            _check_clock(model, g.clock, six=False)
            # a fix report of the same tick (the same time, to the nanosecond of the clock): its status, stamped right
            # after it, carries the C/N0 of this report's satellites used in the fix, strongest first
            tick = next((stamp for ft, stamp in fix_times.items() if abs(ft - t) < 2e-9), None)
            status = [s for at, s in statuses if tick is not None and 0.0 <= at - tick < 0.002]
            if len(status) == 1 and status[0].fixValid:
                used = sorted((s.antennaCarrierNoiseDensity for s in g.satellites if s.usedInFix), reverse=True)[:11]
                assert status[0].carrierToNoise == used
        ins = consumer.reports[Sem.INS_REPORT][v]
        assert all(r.state is InsState.ON for r in ins)
        if v == V2:  # the ins-failure fault
            assert all(r.status is Op.INERTIAL_SENSOR_FAILURE for r in ins)
        else:
            model_ins = Ins(OPTS.scaled(OPTS.align_seconds))
            for r in ins:  # at a time up to LATE before its stamp
                t = clock.t(_stamp(r.timeStamp))
                assert r.status in {model_ins.status(t - LATE * k / 10) for k in range(11)}, (t, r.status)
            assert ins[-1].status is Op.OPERATIONAL

    # vehicle 3 speaks UMAA 6.0: on the surface from its start, its position measured
    model = _model(3)
    poses = six[Sem60.GLOBAL_POSE_REPORT][V3.bytes]
    clock = Clock(model, [(p.course, _stamp(p.timeStamp)) for p in poses])
    rates = {Sem60.GPS_REPORT: OPTS.gps_rate, Sem60.GLOBAL_POSE_REPORT: OPTS.fix_rate, Sem60.INS_REPORT: OPTS.ins_rate}
    for sem60, rate in rates.items():
        reports = six[sem60][V3.bytes]
        assert all(bytes(r.source.parentID) == bytes(16) for r in reports)
        _current([_stamp(r.timeStamp) for r in reports], began)
        _at_rate([_stamp(r.timeStamp) for r in reports], rate)
    for p in poses:
        _check_position(model, clock, _stamp(p.timeStamp), p.position.geodeticLatitude, p.position.geodeticLongitude, p.course)
        assert p.attitude.yaw.yaw == p.course and p.attitude.pitch.pitch == 0.0 and p.attitude.roll.roll == 0.0
        assert p.altitude == 0.0 and p.depth is None and p.navigationSolution.name == "MEASURED"
        assert p.altitudeAGL is None and p.altitudeASF is None and p.altitudeGeodetic is None
        assert p.attitudeCovariance is None and p.positionCovariance is None
    for g in six[Sem60.GPS_REPORT][V3.bytes]:
        assert g.numberSatellitesInView == len(g.satellites)
        t = clock.of_clock(g.clock.elapsedRealtime, _stamp(g.timeStamp))
        clock.stamped(t, _stamp(g.timeStamp))
        _check_sky(model, t, g.satellites, 1.0, six=True)
        _check_clock(model, g.clock, six=True)
    stages = [r.status.name for r in six[Sem60.INS_REPORT][V3.bytes]]
    order = ["INIT", "COARSE_STATIONARY_ALIGNMENT", "FINE_STATIONARY_ALIGNMENT_STARTED", "FINE_STATIONARY_ALIGNMENT_COMPLETE"]
    assert [order.index(s) for s in stages] == sorted(order.index(s) for s in stages) and stages[-1] == order[-1]
