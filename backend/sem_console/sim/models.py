"""What a simulated vehicle's sensors see: satellites, a track at sea, and an INS.

Pure functions of time (seconds since the vehicle started, already scaled), so they
can be tested without DDS. Angles on the wire are radians, as UMAA's Angle types.
"""

from __future__ import annotations

import math
import random
from collections.abc import Callable
from dataclasses import dataclass, field

from UMAA.Common.MaritimeEnumeration.GPSConstellationEnumType import GPSConstellationEnumType as Constellation
from UMAA.Common.MaritimeEnumeration.InertialSensorOpStatusEnumType import InertialSensorOpStatusEnumType as OpStatus
from UMAA.Common.MaritimeEnumeration.InertialSensorStateEnumType import InertialSensorStateEnumType as InsState

# (constellation, share of the sky, PRN range, carrier frequency Hz)
CONSTELLATIONS = [
    (Constellation.GPS, 0.30, range(1, 33), 1575.42e6),
    (Constellation.GALILEO, 0.25, range(1, 37), 1575.42e6),
    (Constellation.GLONASS, 0.20, range(1, 25), 1602.0e6),
    (Constellation.BEIDOU, 0.20, range(1, 64), 1561.098e6),
    (Constellation.SBAS, 0.05, range(120, 159), 1575.42e6),
]
MAX_USED = 12
SUBMERGED_DEPTH_M = -30.0
_EL_MIN, _EL_MAX, _TWO_PI = math.radians(3), math.radians(89), 2 * math.pi


@dataclass
class Satellite:
    constellation: Constellation
    prn: int
    frequency: float
    az0: float  # radians
    az_rate: float  # radians per second
    el_mid: float
    el_amp: float
    el_rate: float
    phase: float
    almanac: bool
    ephemeris: bool

    @property
    def orbit(self) -> Orbit:
        """What `sky_view` takes of it."""
        return self.az0, self.az_rate, self.el_mid, self.el_amp, self.el_rate, self.phase


def make_sky(seed: int, count: int, sky_speed: float = 20.0) -> list[Satellite]:
    """`count` satellites (20..40) spread over the five constellations."""
    rng = random.Random(seed)
    sats: list[Satellite] = []
    remaining = count
    for i, (const, share, prns, freq) in enumerate(CONSTELLATIONS):
        n = remaining if i == len(CONSTELLATIONS) - 1 else max(1, round(count * share))
        n = min(n, remaining - (len(CONSTELLATIONS) - 1 - i))  # leave one for each constellation after
        remaining -= n
        for k, prn in enumerate(sorted(rng.sample(list(prns), n))):
            freq_k = freq + (k - 7) * 562500.0 if const is Constellation.GLONASS else freq
            sats.append(
                Satellite(
                    constellation=const,
                    prn=prn,
                    frequency=freq_k,
                    az0=rng.uniform(0, 2 * math.pi),
                    # real satellites move about 0.5 deg/min; sky_speed makes them visibly move
                    az_rate=math.radians(rng.uniform(0.2, 0.6)) / 60 * sky_speed * rng.choice((-1, 1)),
                    el_mid=math.radians(rng.uniform(20, 60)),
                    el_amp=math.radians(rng.uniform(5, 25)),
                    el_rate=rng.uniform(0.5, 1.5) * 2 * math.pi / 3600 * sky_speed,
                    phase=rng.uniform(0, 2 * math.pi),
                    almanac=True,
                    ephemeris=rng.random() > 0.1,
                )
            )
    return sats


Orbit = tuple[float, float, float, float, float, float]  # a satellite's az0, az_rate, el_mid, el_amp, el_rate, phase


def sky_view(
    orbits: list[Orbit], t: float, exposure: float, gauss: Callable[[float, float], float]
) -> list[tuple[float, float, float]]:
    """Each satellite's azimuth (radians, -pi..pi as UMAA's Angle), elevation (3..89 degrees, in radians) and C/N0
    (dB-Hz) at `t` seconds, from its `Satellite.orbit` (az0, az_rate, el_mid, el_amp, el_rate, phase): the C/N0 rises with
    elevation, with a noise of gauss(0, 1) drawn per satellite in order; `exposure` 0 (the antenna under water) .. 1
    (clear). One loop over plain numbers: a thousand vehicles' skies a second."""
    sin, lo, hi, two_pi, pi = math.sin, _EL_MIN, _EL_MAX, _TWO_PI, math.pi
    dim = 4.0 * (1 - exposure)
    out = []
    for az0, az_rate, el_mid, el_amp, el_rate, phase in orbits:
        az = (az0 + az_rate * t) % two_pi
        if az > pi:
            az -= two_pi
        el = el_mid + el_amp * sin(el_rate * t + phase)
        el = lo if el < lo else hi if el > hi else el
        noise = gauss(0, 1.0)
        cn0 = (28.0 + 22.0 * sin(el) + noise) * exposure + dim * abs(noise) / 2
        out.append((az, el, cn0 if cn0 > 0.0 else 0.0))
    return out


@dataclass
class Track:
    """A vehicle cruising a wide circle; depth moves between submerged and surface."""

    lat0: float
    lon0: float
    speed: float = 1.8  # m/s over ground
    turn_rate: float = math.radians(0.5)  # rad/s of course change
    course0: float = 0.0

    def at(self, t: float) -> tuple[float, float, float]:
        """(latitude deg, longitude deg, true course rad 0..2pi) at t seconds."""
        course = (self.course0 + self.turn_rate * t) % (2 * math.pi)
        r = self.speed / self.turn_rate  # radius of the circle in metres
        north = r * (math.sin(self.course0 + self.turn_rate * t) - math.sin(self.course0))
        east = -r * (math.cos(self.course0 + self.turn_rate * t) - math.cos(self.course0))
        lat = self.lat0 + north / 111_320.0
        lon = self.lon0 + east / (111_320.0 * math.cos(math.radians(self.lat0)))
        return lat, lon, course


@dataclass
class Pilot:
    """A vehicle under way to waypoints (a CoMap task) instead of cruising its circle: it holds its
    position when it has none left, or while held."""

    lat: float
    lon: float
    course: float = 0.0  # rad, 0..2pi
    speed: float = 0.0  # m/s over ground
    waypoints: list[tuple[float, float]] = field(default_factory=list)
    travelled: float = 0.0  # m since the waypoints were given

    def go(self, waypoints: list[tuple[float, float]]) -> None:
        self.waypoints, self.travelled = list(waypoints), 0.0

    def step(self, dt: float, speed: float) -> None:
        """Move `speed * dt` metres along the waypoints (a reached one is dropped)."""
        left = speed * dt
        self.speed = 0.0
        while left > 0 and self.waypoints:
            k = math.cos(math.radians(self.lat))
            lat, lon = self.waypoints[0]
            north, east = (lat - self.lat) * 111_320.0, (lon - self.lon) * 111_320.0 * k
            d = math.hypot(north, east)
            if d > 1e-6:
                self.course = math.atan2(east, north) % (2 * math.pi)
            if d <= left:
                self.lat, self.lon = lat, lon
                self.waypoints.pop(0)
                left -= d
                self.travelled += d
            else:
                self.lat += north * left / d / 111_320.0
                self.lon += east * left / d / (111_320.0 * k)
                self.travelled += left
                left = 0.0
            self.speed = speed


# The stages of the simulated INS's own alignment, after power-on or a restart: it aligns stationary
STATIONARY_STAGES: tuple[OpStatus, ...] = (
    OpStatus.INIT,
    OpStatus.COURSE_STATIONARY_ALIGNMENT,
    OpStatus.FINE_STATIONARY_ALIGNMENT_STARTED,
    OpStatus.FINE_STATIONARY_ALIGNMENT_COMPLETE,
)


@dataclass
class Ins:
    """Inertial sensor: power state and alignment, driven by commands and time."""

    align_seconds: float
    state: InsState = InsState.ON
    since: float = 0.0  # time the current state began
    failed: bool = False
    stages: tuple[OpStatus, ...] = STATIONARY_STAGES

    def set(self, state: InsState, t: float) -> None:
        self.state, self.since = state, t

    @property
    def stage_seconds(self) -> float:
        return self.align_seconds / len(self.stages)

    def step(self, t: float) -> None:
        """RESTARTING lasts one alignment stage, then the INS is ON and aligns again."""
        if self.state is InsState.RESTARTING and t - self.since >= self.stage_seconds:
            self.set(InsState.ON, t)

    def status(self, t: float) -> OpStatus:
        # No literal means "off": an unpowered or restarting INS reports INIT.
        if self.failed:
            return OpStatus.INERTIAL_SENSOR_FAILURE
        if self.state is not InsState.ON:
            return OpStatus.INIT
        if self.stage_seconds <= 0:
            return OpStatus.OPERATIONAL
        stage = max(0, int((t - self.since) / self.stage_seconds))  # t may be a tick older than `since`
        return self.stages[stage] if stage < len(self.stages) else OpStatus.OPERATIONAL
