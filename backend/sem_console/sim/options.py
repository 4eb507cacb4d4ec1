"""What a `sem-sim` process runs: its options, its fault kinds and its vehicles' stable GUIDs."""

from __future__ import annotations

import uuid
from dataclasses import dataclass, field
from pathlib import Path

from sem_console.umaa.guid import stable_guid

FAULTS = ("reject", "fail-midway", "no-answer", "slow", "skip-commanded", "ins-failure")
MAX_VEHICLE = 10_000  # vehicle numbers run 1..MAX_VEHICLE


@dataclass
class SimOptions:
    vehicles: int = 1
    first_vehicle: int = 1  # the vehicles are numbers first_vehicle .. first_vehicle + vehicles - 1
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
    state_file: Path | None = None  # where the provider journals command states (default: see journal.default_state_file)
    health_file: Path | None = None  # touched every second while the simulator runs (for container healthchecks)
    slow_factor: float = 10.0
    faults: dict[int, set[str]] = field(default_factory=dict)  # vehicle number (0 = all) -> faults
    start_lat: float = 36.80
    start_lon: float = -75.70
    # CoMap over IMC (comap_vehicle.py): off unless imc_port is given
    imc_port: int | None = None
    imc_host: str = "0.0.0.0"
    imc_id: int = 0x2001  # the first vehicle's IMC system id; the next vehicles count up from it
    imc_peers: list[tuple[str, int]] = field(default_factory=list)  # C2s (consoles) the vehicles report to
    imc_sensors: tuple[str, ...] = ("SIDESCAN",)
    imc_resolution: float = 10.0  # px/m² of its survey sensors
    survey_spacing: float = 30.0  # m between lawnmower lanes
    survey_speed: float = 2.0  # m/s under way for a task
    identity_wait: float = 1.0  # s to look for another process already providing our vehicles (see Simulator.claim)

    @property
    def numbers(self) -> range:
        return range(self.first_vehicle, self.first_vehicle + self.vehicles)

    def faults_for(self, number: int) -> set[str]:
        return self.faults.get(0, set()) | self.faults.get(number, set())

    def imc_id_of(self, number: int) -> int:
        return self.imc_id + number - self.first_vehicle

    def scaled(self, seconds: float) -> float:
        return seconds * self.time_scale


def vehicle_guid(number: int) -> uuid.UUID:
    """Stable source GUID of simulated vehicle `number` (from 1), the same on every run and host."""
    return stable_guid(f"sim-vehicle-{number}")
