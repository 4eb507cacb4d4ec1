"""What a `sem-sim` process runs: its options, its fault kinds and its vehicles' stable GUIDs."""

from __future__ import annotations

import uuid
from pathlib import Path
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field, field_validator, model_validator

from sem_console.comap.messages import Sensor
from sem_console.core.config import ENV_ONLY, cli
from sem_console.core.versions import UmaaVersion
from sem_console.umaa.guid import stable_guid

FAULTS = ("reject", "fail-midway", "no-answer", "slow", "skip-commanded", "ins-failure")
MAX_VEHICLE = 10_000  # vehicle numbers run 1..MAX_VEHICLE
MAX_FLEET = 1_000  # vehicles one simulator runs


class SimOptions(BaseModel):
    """What a simulator runs. `sem-sim`'s options are generated from these fields (sim/sem_sim.py through
    core/command_line.add_model_options), so the ranges, defaults and help are written once, here."""

    model_config = ConfigDict(extra="forbid")

    vehicles: int = Field(
        1, ge=1, le=MAX_FLEET, description="number of vehicles, each with its own stable source GUID (default: 1)"
    )
    first_vehicle: int = Field(
        1,
        ge=1,
        le=MAX_VEHICLE,
        description=(
            "number of the first vehicle: vehicles N, N+1, ... (their GUIDs follow from their numbers). A simulator refuses to "
            "start a vehicle another process already runs on the domain (default: 1)"
        ),
    )
    time_scale: float = Field(
        1.0, ge=0.001, le=100, description=("multiply every duration below, e.g. 0.1 runs ten times faster (default: 1)")
    )
    step_seconds: float = Field(0.5, ge=0, le=600, description="delay between ISSUED, COMMANDED and EXECUTING (default: 0.5)")
    surface_seconds: float = Field(
        8.0, ge=0, le=3600, description=("time for a GPSFix command to surface and get a fix (default: 8)")
    )
    align_seconds: float = Field(
        12.0, ge=0, le=3600, description=("INS power-on to OPERATIONAL through four alignment stages (default: 12)")
    )
    fix_rate: float = Field(5.0, ge=1, le=10, description="GPSFixReport and GPSFixStatusReport rate in Hz, 1..10 (default: 5)")
    gps_rate: float = Field(1.0, ge=0.1, le=10, description="GPSReport (satellites) rate in Hz (default: 1)")
    ins_rate: float = Field(2.0, ge=0.1, le=50, description="InertialSensorReport rate in Hz (default: 2)")
    satellites: int = Field(32, ge=20, le=40, description="satellites per vehicle, 20..40 (default: 32)")
    sky_speed: float = Field(
        20.0, ge=0, le=1000, description=("how much faster than real satellites move across the sky (default: 20)")
    )
    on_startup: Literal["fail", "resume"] = Field(
        "fail",
        description=(
            "a command this provider was running before a restart (known from --state-file): fail it with SERVICE_FAILED, or "
            "resume it from its last status; commands it never saw start normally (default: fail)"
        ),
    )
    orphan_grace: float = Field(
        10.0,
        ge=0,
        le=3600,
        description=("seconds a command may have no live writer before it is treated as canceled (default: 10)"),
    )
    command_timeout: float = Field(
        300.0,
        ge=0.1,
        le=86400,
        description=("an executing command that has not finished after this many seconds fails with TIMEOUT (default: 300)"),
    )
    umaa: UmaaVersion = Field(
        "3.0.1",
        description=(
            "the UMAA version the vehicles speak. 6.0: their GPSReportType, GlobalPoseReportType and InertialSensorReportType "
            "on the 6.0 topics, reliable and transient-local (what the readers of RTI's UMAA kit ask); they answer "
            "InertialSensorCommandType, their INS walking the stages of the alignment commanded "
            "(default: 3.0.1)"
        ),
    )
    umaa_6_0_vehicles: set[int] = Field(
        default_factory=set,
        json_schema_extra=cli(type="numbers", metavar="N,M,..."),
        description=(
            "these vehicle numbers speak UMAA 6.0 whatever --umaa says: one simulator then runs a mixed fleet (default: none)"
        ),
    )
    gps_extensibility: Literal["final", "appendable"] = Field(
        "final",
        description=(
            "the types GPSReport and GPSFixReport are written with. final: the console's types (idlc's default, as a "
            "vehicle built from the plain UMAA IDL); appendable: UMAA's types appendable in XCDR2, for RTI Connext consumers "
            "on the drop-in's AppendableGps profile (docs/dds.md); with --umaa 6.0 GlobalPoseReportType likewise, for RTI "
            "consumers on RTI's UMAA kit (docs/umaa-versions.md); the console reads either (default: final)"
        ),
    )
    state_file: Path | None = Field(
        None,
        description=(
            "where command states are journaled so a restarted simulator can recover them; one simulator at a time "
            "(default: $XDG_STATE_HOME/sem-sim/domain-N.json, domain-N-from-F.json with --first-vehicle F)"
        ),
    )
    health_file: Path | None = Field(None, description="touch this file every second while running (for healthchecks)")
    faults: dict[int, set[str]] = Field(
        default_factory=dict,
        json_schema_extra=cli(flag="--fault", type="fault", action="append", metavar="KIND[:VEHICLE]"),
        description=(
            "inject a fault, for all vehicles or vehicle number N; repeatable. KIND: reject (FAILED/RESOURCE_REJECTED: after "
            "ISSUED in 3.0.1, after COMMANDED in 6.0, the only state its Figure 15 allows it after), "
            "fail-midway (FAILED/RESOURCE_FAILED while executing), no-answer (never answers), slow (every step "
            "--slow-factor times slower), skip-commanded (ISSUED -> EXECUTING, a breach of the command state machine: "
            "the 3.0.1 ICD's Figure 4, the 6.0 ICD's Figure 14), "
            "ins-failure (INS reports INERTIAL_SENSOR_FAILURE)"
        ),
    )  # vehicle number (0 = all) -> faults
    slow_factor: float = Field(10.0, ge=1, le=1000, description="slow-down of the 'slow' fault (default: 10)")
    start_lat: float = Field(36.80, json_schema_extra=ENV_ONLY)
    start_lon: float = Field(-75.70, json_schema_extra=ENV_ONLY)
    # CoMap over IMC (comap_vehicle.py): off unless imc_port is given
    imc_port: int | None = Field(
        None, ge=0, le=65535, description=("CoMap over IMC: UDP port the vehicles listen on (CoMap is off without it)")
    )
    imc_host: str = Field("0.0.0.0", description="address the IMC port listens on (default: 0.0.0.0)")
    imc_id: int = Field(
        0x2001,
        json_schema_extra=cli(type="imc_id"),
        description=("IMC system id of the first vehicle, decimal or 0x hex; the next ones count up (default: 0x2001)"),
    )
    imc_peers: list[tuple[str, int]] = Field(
        default_factory=list,
        json_schema_extra=cli(type="peers"),
        description=("C2s (consoles) the vehicles send to: 'host:port,...'"),
    )
    imc_sensors: tuple[str, ...] = Field(
        ("SIDESCAN",),
        json_schema_extra=cli(type="sensors"),
        description=(
            f"survey sensors the vehicles have, comma separated, of {', '.join(n for n in Sensor.__members__ if n != 'ANY')} "
            "(default: SIDESCAN)"
        ),
    )
    imc_resolution: float = Field(10.0, json_schema_extra=ENV_ONLY)  # px/m² of its survey sensors
    survey_spacing: float = Field(30.0, ge=1, le=10_000, description="metres between lawnmower lanes of a survey (default: 30)")
    survey_speed: float = Field(
        2.0, ge=0.1, le=100, description=("m/s under way for a CoMap task, before --time-scale (default: 2)")
    )
    identity_wait: float = Field(1.0, json_schema_extra=ENV_ONLY)  # s to look for another process providing our vehicles

    @field_validator("faults", mode="before")
    @classmethod
    def _faults(cls, value: Any) -> Any:
        """--fault's list of (kind, vehicle number) pairs -> {vehicle number (0: all): kinds}."""
        if isinstance(value, list):
            faults: dict[int, set[str]] = {}
            for kind, target in value:
                faults.setdefault(target, set()).add(kind)
            return faults
        return value

    @model_validator(mode="after")
    def _last_vehicle(self) -> SimOptions:
        """Vehicle numbers run 1..MAX_VEHICLE: the fleet must end there, wherever it starts."""
        if self.first_vehicle + self.vehicles - 1 > MAX_VEHICLE:
            raise ValueError(
                f"--first-vehicle {self.first_vehicle} with --vehicles {self.vehicles} runs past vehicle {MAX_VEHICLE}: "
                f"start at {MAX_VEHICLE - self.vehicles + 1} or lower"
            )
        return self

    @model_validator(mode="after")
    def _fault_targets(self) -> SimOptions:
        """A fault for a vehicle this simulator does not run would be injected nowhere, and the operator told nothing."""
        if missing := sorted(n for n in self.faults if n and n not in self.numbers):
            last = self.numbers[-1]
            runs = f"vehicle {last}" if len(self.numbers) == 1 else f"vehicles {self.numbers[0]}..{last}"
            raise ValueError(
                f"--fault {sorted(self.faults[missing[0]])[0]}:{missing[0]}: this simulator runs {runs}: "
                "name one of them, or change --vehicles or --first-vehicle"
            )
        return self

    @model_validator(mode="after")
    def _umaa_6_0_targets(self) -> SimOptions:
        """A vehicle number this simulator does not run would speak 6.0 nowhere, and the operator told nothing."""
        if missing := sorted(set(self.umaa_6_0_vehicles) - set(self.numbers)):
            raise ValueError(
                f"--umaa-6-0-vehicles {missing[0]}: this simulator runs vehicles {self.numbers[0]}.."
                f"{self.numbers[-1]}: name one of them, or change --vehicles or --first-vehicle"
            )
        return self

    def version_of(self, number: int) -> UmaaVersion:
        """The UMAA version vehicle `number` speaks."""
        return "6.0" if number in self.umaa_6_0_vehicles else self.umaa

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
