"""UMAA reports (as the console holds them: IDL-shaped JSON plus its `invalid` list) -> ASPN-23.

The messages are the published `aspn23` types, turned into LCM bytes by the published
`aspn23-lcm-conversions` and `aspn23-lcm` packages; nothing here encodes a byte itself.

Absent and invalid values: a UMAA value that is missing, null (NaN, unknown ordinal) or listed in the
report's `invalid` is never sent as a number. A message whose value is that value is left out; an
optional term of a message we do send (position height, every satnav observable UMAA does not have)
and every uncertainty UMAA does not give (covariances, variances) is NaN, LCM having no null. The
conversions turn a None into 0.0, so `guard` replaces every None with NaN before they see it.
"""

from __future__ import annotations

import dataclasses
import hashlib
import math
import uuid
from collections.abc import Callable
from typing import Any

import aspn23_lcm_conversions as conversions
import numpy as np
from aspn23.measurement_altitude import MeasurementAltitude, MeasurementAltitudeErrorModel, MeasurementAltitudeReference
from aspn23.measurement_direction_of_motion_2d import (
    MeasurementDirectionOfMotion2D,
    MeasurementDirectionOfMotion2DErrorModel,
    MeasurementDirectionOfMotion2DReference,
)
from aspn23.measurement_position import MeasurementPosition, MeasurementPositionErrorModel, MeasurementPositionReferenceFrame
from aspn23.measurement_satnav import MeasurementSatnav
from aspn23.measurement_speed import MeasurementSpeed, MeasurementSpeedErrorModel, MeasurementSpeedReference
from aspn23.measurement_velocity import MeasurementVelocity, MeasurementVelocityErrorModel, MeasurementVelocityReferenceFrame
from aspn23.type_header import TypeHeader
from aspn23.type_satnav_obs import TypeSatnavObs, TypeSatnavObsIonoCorrectionSource, TypeSatnavObsPseudorangeRateType
from aspn23.type_satnav_satellite_system import TypeSatnavSatelliteSystem
from aspn23.type_satnav_satellite_system import TypeSatnavSatelliteSystemSatelliteSystem as Sys
from aspn23.type_satnav_signal_descriptor import TypeSatnavSignalDescriptor
from aspn23.type_satnav_signal_descriptor import TypeSatnavSignalDescriptorSignalDescriptor as Signal
from aspn23.type_satnav_time import TypeSatnavTime, TypeSatnavTimeTimeReference
from aspn23.type_timestamp import TypeTimestamp

from sem_console.gateways import number
from sem_console.umaa.guid import SAT_PREFIX

NAN = math.nan
VENDOR_ID = 0x53454D43  # "SEMC": user-selected (ASPN reserves 0x23000000..0x23FFFFFF)
# One data source (vendor, device, context) per measurement stream, so sequence_id counts per stream
CONTEXT_IDS = {
    "measurement_position": 1,
    "measurement_altitude": 2,
    "measurement_velocity": 3,
    "measurement_speed": 4,
    "measurement_direction_of_motion_2d": 5,
    "measurement_satnav": 6,
}
TO_LCM: dict[str, Callable[[Any], Any]] = {name: getattr(conversions, f"{name}_to_lcm") for name in CONTEXT_IDS}

# one-value measurements: (class, its "no error model", the member holding the value)
SCALARS: dict[str, tuple[Any, Any, str]] = {
    "measurement_altitude": (MeasurementAltitude, MeasurementAltitudeErrorModel.NONE, "altitude"),
    "measurement_speed": (MeasurementSpeed, MeasurementSpeedErrorModel.NONE, "speed"),
    "measurement_direction_of_motion_2d": (MeasurementDirectionOfMotion2D, MeasurementDirectionOfMotion2DErrorModel.NONE, "obs"),
}

GPS_EPOCH = 315_964_800  # 1980-01-06 in POSIX seconds
LEAP_SECONDS = 18  # GPS - UTC since 2017, used when the GPSReport's clock gives no leapSecond
WEEK = 604_800

SYSTEMS = {
    "GPS": Sys.SYS_GPS,
    "GALILEO": Sys.SYS_GALILEO,
    "GLONASS": Sys.SYS_GLONASS,
    "BEIDOU": Sys.SYS_BEIDOU,
    "SBAS": Sys.SYS_SBAS,
    "QZSS": Sys.SYS_QZSS,
    "IRNSS": Sys.SYS_IRNSS,
}
# (system, carrier frequency band in MHz) -> RINEX 3.05 observation code. UMAA gives the carrier frequency,
# not the tracking code: each band takes the code a receiver of it most commonly tracks (README).
SIGNALS: list[tuple[Sys, float, float, Signal]] = [
    (Sys.SYS_GPS, 1575.42, 1.0, Signal.L1C),
    (Sys.SYS_GPS, 1227.60, 1.0, Signal.L2X),
    (Sys.SYS_GPS, 1176.45, 1.0, Signal.L5X),
    (Sys.SYS_GALILEO, 1575.42, 1.0, Signal.L1X),
    (Sys.SYS_GALILEO, 1176.45, 1.0, Signal.L5X),
    (Sys.SYS_GALILEO, 1207.14, 1.0, Signal.L7X),
    (Sys.SYS_GALILEO, 1278.75, 1.0, Signal.L6X),
    (Sys.SYS_GLONASS, 1602.0, 4.5, Signal.L1C),
    (Sys.SYS_GLONASS, 1246.0, 3.5, Signal.L2C),  # FDMA: G1, G2 with k
    (Sys.SYS_BEIDOU, 1561.098, 1.0, Signal.L2I),
    (Sys.SYS_BEIDOU, 1575.42, 1.0, Signal.L1X),
    (Sys.SYS_BEIDOU, 1176.45, 1.0, Signal.L5X),
    (Sys.SYS_BEIDOU, 1207.14, 1.0, Signal.L7I),
    (Sys.SYS_BEIDOU, 1268.52, 1.0, Signal.L6I),
    (Sys.SYS_SBAS, 1575.42, 1.0, Signal.L1C),
    (Sys.SYS_SBAS, 1176.45, 1.0, Signal.L5I),
    (Sys.SYS_QZSS, 1575.42, 1.0, Signal.L1C),
    (Sys.SYS_QZSS, 1227.60, 1.0, Signal.L2X),
    (Sys.SYS_QZSS, 1176.45, 1.0, Signal.L5X),
    (Sys.SYS_IRNSS, 1176.45, 1.0, Signal.L5A),
]


def vehicle_key(vehicle: uuid.UUID) -> int:
    """64 bits that stand for the vehicle on LCM (its channels, its device_id): BLAKE2b-64 of its whole GUID, stable
    across restarts. Not the GUID's first 64 bits: GUIDs given by hand or by a counter (…-000000000001, …-000000000002)
    share those, and their vehicles would be one device on one channel to a listener."""
    return int.from_bytes(hashlib.blake2b(vehicle.bytes, digest_size=8).digest(), "big")


def device_id(vehicle: uuid.UUID) -> int:
    """The vehicle's device_id: its key's first 63 bits (`vehicle_key`; a positive int64)."""
    return vehicle_key(vehicle) >> 1


def signal_of(system: Sys, frequency_hz: float) -> Signal | None:
    mhz = frequency_hz / 1e6
    return next((sig for s, f, half, sig in SIGNALS if s is system and abs(mhz - f) <= half), None)


def guard(obj: Any) -> Any:
    """Every None in an aspn23 message becomes NaN (the conversions would send 0.0), in place; returns obj."""
    if dataclasses.is_dataclass(obj):
        for f in dataclasses.fields(obj):
            v = getattr(obj, f.name)
            if v is None:
                setattr(obj, f.name, NAN)
            else:
                guard(v)
    elif isinstance(obj, list):
        for x in obj:
            guard(x)
    return obj


def encode(measurement: str, message: Any) -> bytes:
    """LCM bytes of an aspn23 message, by the published conversions and LCM types."""
    return bytes(TO_LCM[measurement](guard(message)).encode())


def _nan(*shape: int) -> Any:
    return np.full(shape, NAN)


NO_PARAMS = np.zeros(0)


class Encoder:
    """UMAA report JSON -> [(measurement, aspn23 message)], with a sequence_id per vehicle and stream."""

    def __init__(self) -> None:
        self.sequences: dict[tuple[uuid.UUID, str], int] = {}
        self.skipped: dict[str, int] = {}  # why a message or satellite was left out -> how often

    def _skip(self, why: str) -> None:
        self.skipped[why] = self.skipped.get(why, 0) + 1

    def header(self, vehicle: uuid.UUID, measurement: str) -> TypeHeader:
        seq = self.sequences.get((vehicle, measurement), -1) + 1
        seq = 0 if seq > 2**31 - 1 else seq  # int32, rolls over to 0
        self.sequences[(vehicle, measurement)] = seq
        return TypeHeader(vendor_id=VENDOR_ID, device_id=device_id(vehicle), context_id=CONTEXT_IDS[measurement], sequence_id=seq)

    def _time(self, report: dict[str, Any], invalid: list[str]) -> int | None:
        seconds, nanos = number(report, invalid, "timeStamp.seconds"), number(report, invalid, "timeStamp.nanoseconds")
        if seconds is None or nanos is None:
            self._skip("report without a valid timeStamp")
            return None
        return int(seconds) * 1_000_000_000 + int(nanos)

    def fix_report(self, vehicle: uuid.UUID, report: dict[str, Any], invalid: list[str]) -> list[tuple[str, Any]]:
        if report.get("GPSLatLongValid") is not True:
            # the ICD: "if not, INS position is used", and so are the report's other values. ASPN measurements feed a
            # fusion engine, which would count the INS's own solution twice if it came back as a GPS measurement
            self._skip("GPSFixReport: GPSLatLongValid is false (the INS's solution, not a GPS measurement)")
            return []
        t = self._time(report, invalid)
        if t is None:
            return []
        when = TypeTimestamp(elapsed_nsec=t)

        def n(path: str) -> float | None:
            return number(report, invalid, path)

        def why(path: str) -> str:  # a value left out: flagged invalid, or not in the report (UMAA 6.0's GlobalPose)
            return "invalid" if any(x.startswith((f"{path}:", f"{path}.")) for x in invalid) else "not reported"

        out: list[tuple[str, Any]] = []
        lat = n("position2DWithTime.geodeticPosition.geodeticLatitude.latitude")
        lon = n("position2DWithTime.geodeticPosition.geodeticLongitude.longitude")
        if lat is None or lon is None:
            self._skip("position: latitude or longitude invalid")
        else:  # height left out: UMAA gives MSL, ASPN's term3 is height above the ellipsoid
            out.append(
                (
                    "measurement_position",
                    MeasurementPosition(
                        header=self.header(vehicle, "measurement_position"),
                        time_of_validity=when,
                        reference_frame=MeasurementPositionReferenceFrame.GEODETIC,
                        term1=math.radians(lat),
                        term2=math.radians(lon),
                        term3=NAN,
                        covariance=_nan(2, 2),
                        error_model=MeasurementPositionErrorModel.NONE,
                        error_model_params=NO_PARAMS,
                        integrity=[],
                    ),
                )
            )
        alt = n("altitudeMSL.altitude")
        if alt is None:
            self._skip(f"altitude: {why('altitudeMSL.altitude')}")
        else:
            out.append(self._scalar(vehicle, "measurement_altitude", when, MeasurementAltitudeReference.MSL, alt))
        ned = [n(f"velocity.{c}") for c in ("northSpeed", "eastSpeed", "downSpeed")]
        if all(v is None for v in ned):
            self._skip(f"velocity: {why('velocity')}")
        else:
            out.append(
                (
                    "measurement_velocity",
                    MeasurementVelocity(
                        header=self.header(vehicle, "measurement_velocity"),
                        time_of_validity=when,
                        reference_frame=MeasurementVelocityReferenceFrame.NED,
                        x=ned[0],
                        y=ned[1],
                        z=ned[2],
                        covariance=_nan(3, 3),
                        error_model=MeasurementVelocityErrorModel.NONE,
                        error_model_params=NO_PARAMS,
                        integrity=[],
                    ),
                )
            )
        sog = n("SOG")
        if sog is None:
            self._skip(f"speed: SOG {why('SOG')}")
        else:
            out.append(self._scalar(vehicle, "measurement_speed", when, MeasurementSpeedReference.GROUND, sog))
        course = n("trueCourse")
        if course is None:
            self._skip(f"direction of motion: trueCourse {why('trueCourse')}")
        else:
            out.append(
                self._scalar(
                    vehicle, "measurement_direction_of_motion_2d", when, MeasurementDirectionOfMotion2DReference.NE, course
                )
            )
        return out

    def _scalar(self, vehicle: uuid.UUID, measurement: str, when: TypeTimestamp, reference: Any, value: float) -> tuple[str, Any]:
        """A one-value measurement (altitude, speed, direction of motion) with no variance known (NaN)."""
        cls, no_error_model, member = SCALARS[measurement]
        return measurement, cls(
            header=self.header(vehicle, measurement),
            time_of_validity=when,
            reference=reference,
            **{member: value},
            variance=NAN,
            error_model=no_error_model,
            error_model_params=NO_PARAMS,
            integrity=[],
        )

    def gps_report(self, vehicle: uuid.UUID, report: dict[str, Any], invalid: list[str]) -> list[tuple[str, Any]]:
        t = self._time(report, invalid)
        if t is None:
            return []
        leap = number(report, invalid, "clock.leapSecond")
        leap = int(leap) if leap is not None and 0 <= leap <= 100 else LEAP_SECONDS
        gps = t / 1e9 - GPS_EPOCH + leap
        clock = TypeSatnavTime(
            week_number=int(gps // WEEK), seconds_of_week=gps % WEEK, time_reference=TypeSatnavTimeTimeReference.TIME_GPS
        )
        obs: list[TypeSatnavObs] = []
        for i, sat in enumerate(report.get("satellites") or []):
            o = self._observation(sat, invalid, f"satellites[{i}]")
            if o is not None:
                obs.append(o)
        types = {(o.satellite_system.satellite_system, o.signal_descriptor.signal_descriptor) for o in obs}
        return [
            (
                "measurement_satnav",
                MeasurementSatnav(
                    header=self.header(vehicle, "measurement_satnav"),
                    time_of_validity=TypeTimestamp(elapsed_nsec=t),
                    receiver_clock_time=clock,
                    num_signal_types=len(types),
                    obs=obs,
                    integrity=[],
                ),
            )
        ]

    def _observation(self, sat: dict[str, Any], invalid: list[str], path: str) -> TypeSatnavObs | None:
        system = SYSTEMS.get(sat.get("constellationType") or "")
        if system is None or any(x.startswith(f"{path}.constellationType:") for x in invalid):
            self._skip("satellite: constellation unknown")
            return None
        sid = sat.get("satelliteId")
        raw = uuid.UUID(sid).bytes if isinstance(sid, str) else b""
        if raw[:14] != SAT_PREFIX:
            self._skip("satellite: PRN unknown (satelliteId does not follow the PRN convention)")
            return None
        freq = (
            number(sat, [], "carrierFrequency") if not any(x.startswith(f"{path}.carrierFrequency:") for x in invalid) else None
        )
        signal = signal_of(system, freq) if freq is not None else None
        if freq is None or signal is None:
            self._skip("satellite: carrier frequency absent or in no known band")
            return None
        cn0 = (
            None
            if any(x.startswith(f"{path}.antennaCarrierNoiseDensity:") for x in invalid)
            else number(sat, [], "antennaCarrierNoiseDensity")
        )
        return TypeSatnavObs(
            satellite_system=TypeSatnavSatelliteSystem(system),
            signal_descriptor=TypeSatnavSignalDescriptor(signal),
            prn=raw[15],
            frequency=freq,
            pseudorange=NAN,
            pseudorange_variance=NAN,
            pseudorange_rate_type=TypeSatnavObsPseudorangeRateType.PSR_RATE_DOPPLER,
            pseudorange_rate=NAN,
            pseudorange_rate_variance=NAN,
            carrier_phase=NAN,
            carrier_phase_variance=NAN,
            c_n0=cn0 if cn0 is not None else NAN,
            lock_count=-1,
            iono_correction_source=TypeSatnavObsIonoCorrectionSource.UNKNOWN,
            iono_correction_applied=False,
            tropo_correction_applied=False,
            signal_bias_correction_applied=False,
            integrity=[],
        )
