"""The console's view of vehicles and commands, as the rooms that share it see it: written once, here.

The console (`console/`) builds these messages, the WebSocket sends them (the API's contract, `api/schemas.py`,
re-uses these models), the recorder writes them to its JSON channels (`recording/recorder.py`) and the database
keeps the link configuration an operator set (validated with `LinkConfig` when read back).
"""

from __future__ import annotations

from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field, field_validator
from pydantic.alias_generators import to_camel
from sqlmodel import SQLModel
from sqlmodel._compat import SQLModelConfig

from sem_console.core import messages
from sem_console.core.versions import UmaaVersion as UmaaVersion
from sem_console.storage.models import CommandHandled, CommandIssued, TransitionBase

ReportTopic = Literal["GPSReport", "GPSFixReport", "GPSFixStatusReport", "InertialSensorReport"]
LinkState = Literal["live", "lost", "regained", "unchecked"]
InsStateName = Literal["OFF", "ON", "RESTARTING"]  # UMAA 3.0.1: InertialSensorStateEnumType
# UMAA 6.0: InertialSensorCmdEnumType, what its InertialSensorCommandType's state takes
InsCommandName = Literal["BEST_ALIGN", "GPS_ALIGN", "INIT", "SNAP_ALIGN", "STATIONARY_ALIGN", "TRANSFER_ALIGN"]


class StrictModel(BaseModel):
    """A model of the console's contract: an unknown field is an error."""

    model_config = ConfigDict(extra="forbid")


# a model of the contract derived from a base of storage/models/ (the shape declared once): its snake_case fields
# in camelCase, an unknown field an error
CAMEL = SQLModelConfig(extra="forbid", alias_generator=to_camel, populate_by_name=True)


class TopicHealth(StrictModel):
    ageSeconds: float = Field(description="seconds since the last sample on this topic")
    samples: int
    alive: bool = Field(description="false once the instance was disposed or lost its writers")
    receivedAt: float = Field(description="UTC seconds since the epoch of the last sample")


class LinkConfig(StrictModel):
    """A vehicle's link thresholds and comms-lost configuration (reported as JAUS ReportCommsLostConfiguration)."""

    commsLostTimeout: float = Field(ge=0.1, le=65535, description="seconds without any sample before the vehicle is lost")
    regainedTime: float = Field(ge=0, le=65535, description="seconds of continuous samples before a lost vehicle is regained")
    policy: Literal["STOP_MISSION", "CONTINUE_MISSION"] = Field(
        description="what the vehicle is set to do when it loses comms (recorded and reported; the console enforces nothing)"
    )
    regainedBehavior: int = Field(
        ge=0, le=255, description="the vehicle's CommsRegainedBehavior code (JAUS u8), recorded and reported"
    )

    @field_validator("commsLostTimeout", "regainedTime", "regainedBehavior", mode="before")
    @classmethod
    def _a_json_number(cls, v: Any) -> Any:
        """JSON numbers only: not true for 1, nor "5" for 5 (1.0 is the integer 1, as JSON Schema has it)."""
        if isinstance(v, (bool, str)):
            raise ValueError("Input should be a number")
        return v

    def to_json(self) -> messages.LinkConfig:
        return {
            "commsLostTimeout": self.commsLostTimeout,
            "regainedTime": self.regainedTime,
            "policy": self.policy,
            "regainedBehavior": self.regainedBehavior,
        }


class RelayHop(StrictModel):
    """The relay a vehicle is seen through (docs/relay.md#the-console-knows-the-hop)."""

    name: str = Field(description="the --name of the sem-relay of the vehicles' side that carries it")
    dataTime: float | None = Field(
        description=(
            "UTC seconds: the vehicle's own time stamp (timeStamp) of its newest report, null before one or while its"
            " time stamps are ahead of their receipt (its clock ahead: silent from arrival)"
        )
    )
    ageSeconds: float | None = Field(
        description="seconds from dataTime to now: how old its newest data is, the relay and the link included"
    )
    quietSeconds: float = Field(
        description=(
            "how long the relay's rate caps may keep its data quiet (its shortest periodic cap: 5 at the satellite"
            " defaults, 0 uncapped): added to its comms-lost timeout, and to the time before the dashboard says stale"
        )
    )


class ProviderSummary(StrictModel):
    id: str = Field(description="the provider's source GUID as a UUID string")
    name: str | None = Field(
        description="the vehicle's name: the one an operator set (PUT /api/providers/{id}/name), "
        "else the console's --vehicle-names one, or null"
    )
    link: LinkState
    umaaVersion: UmaaVersion = Field(
        description="the UMAA version the vehicle speaks: that of the report topics its samples come on (3.0.1 until one is seen)"
    )
    linkConfig: LinkConfig
    jausId: str | None = Field(
        description="its JAUS component 'S.1.C' (the order it appeared in) when the JAUS gateway is on, else null"
    )
    ageSeconds: float = Field(description="seconds since the last sample on any topic")
    topics: dict[str, TopicHealth]
    relay: RelayHop | None = Field(
        None,
        description="the relay the vehicle is seen through, with how old its newest data is; null: heard on this domain itself",
    )


class Transition(TransitionBase):
    model_config = CAMEL


class _CommandStatus(SQLModel):
    status: str | None = Field(description="the last commandStatus, null before ISSUED")
    terminal: bool


class Command(CommandHandled, _CommandStatus, CommandIssued):
    model_config = CAMEL
    service: Literal["GPSFix", "InertialSensor"]
    state: Literal[InsStateName, InsCommandName] | None = Field(
        description=(
            "the commanded INS state (InertialSensor only), a literal of its vehicle's UMAA version: 3.0.1, OFF, ON or "
            "RESTARTING; 6.0, BEST_ALIGN, GPS_ALIGN, INIT, SNAP_ALIGN, STATIONARY_ALIGN or TRANSFER_ALIGN"
        )
    )
    cancel_cause: Literal["operator", "shutdown"] | None = Field(
        None, description=CommandHandled.model_fields["cancel_cause"].description
    )
    closed_unheard: Literal["heard", "bound"] | None = Field(
        None, description=CommandHandled.model_fields["closed_unheard"].description
    )
    violations: list[str]
    transitions: list[Transition]


class ProviderMessage(StrictModel):
    type: Literal["provider"]
    event: Literal["appeared", "lost", "regained", "live", "configured", "unchecked"] = Field(
        description="live: a regained provider is back to normal; configured: its linkConfig, name or UMAA version "
        "changed; unchecked: silent while this console is behind, so not judged until it catches up"
    )
    provider: ProviderSummary


class CommandMessage(StrictModel):
    type: Literal["command"]
    command: Command


class TransitionMessage(StrictModel):
    type: Literal["transition"]
    sessionId: str
    transition: Transition
    command: Command
