"""The console's view of vehicles and commands, as the rooms that share it see it: written once, here.

The console (`console/`) builds these messages, the WebSocket sends them (the API's contract, `api/schemas.py`,
re-uses these models), the recorder writes them to its JSON channels (`recording/recorder.py`) and the database
keeps the link configuration an operator set (validated with `LinkConfig` when read back).
"""

from __future__ import annotations

from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field, field_validator

from sem_console.core import messages

ReportTopic = Literal["GPSReport", "GPSFixReport", "GPSFixStatusReport", "InertialSensorReport"]
LinkState = Literal["live", "lost", "regained"]
InsStateName = Literal["OFF", "ON", "RESTARTING"]  # UMAA 3.0.1: InertialSensorStateEnumType
# UMAA 6.0: InertialSensorCmdEnumType, what its InertialSensorCommandType's state takes
InsCommandName = Literal["BEST_ALIGN", "GPS_ALIGN", "INIT", "SNAP_ALIGN", "STATIONARY_ALIGN", "TRANSFER_ALIGN"]
UmaaVersion = Literal["3.0.1", "6.0"]


class StrictModel(BaseModel):
    """A model of the console's contract: an unknown field is an error."""

    model_config = ConfigDict(extra="forbid")


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
        description="what the vehicle is set to do when it loses comms (recorded and reported; the console enforces nothing)")
    regainedBehavior: int = Field(ge=0, le=255, description="the vehicle's CommsRegainedBehavior code (JAUS u8), recorded and "
                                                            "reported")

    @field_validator("commsLostTimeout", "regainedTime", "regainedBehavior", mode="before")
    @classmethod
    def _a_json_number(cls, v: Any) -> Any:
        """JSON numbers only: not true for 1, nor "5" for 5 (1.0 is the integer 1, as JSON Schema has it)."""
        if isinstance(v, (bool, str)):
            raise ValueError("Input should be a number")
        return v

    def to_json(self) -> messages.LinkConfig:
        return {"commsLostTimeout": self.commsLostTimeout, "regainedTime": self.regainedTime, "policy": self.policy,
                "regainedBehavior": self.regainedBehavior}


class ProviderSummary(StrictModel):
    id: str = Field(description="the provider's source GUID as a UUID string")
    name: str | None = Field(description="the vehicle's name: the one an operator set (PUT /api/providers/{id}/name), "
                                         "else the console's --vehicle-names one, or null")
    link: LinkState
    umaaVersion: UmaaVersion = Field(description="the UMAA version the vehicle speaks: that of the report topics its "
                                                 "samples come on (3.0.1 until one is seen)")
    linkConfig: LinkConfig
    jausId: str | None = Field(description="its JAUS component 'S.1.C' (the order it appeared in) when the JAUS gateway "
                                           "is on, else null")
    ageSeconds: float = Field(description="seconds since the last sample on any topic")
    topics: dict[str, TopicHealth]


class Transition(StrictModel):
    seq: int = Field(description="1-based position in the command's history")
    status: str
    reason: str
    logMessage: str
    violation: str | None = Field(description="why this transition breaks ICD Figure 4, or null")
    providerTime: float | None = Field(description="the status sample's timeStamp, UTC seconds")
    receivedAt: float


class Command(StrictModel):
    sessionId: str
    service: Literal["GPSFix", "InertialSensor"]
    providerId: str
    state: Literal[InsStateName, InsCommandName] | None = Field(description=(
        "the commanded INS state (InertialSensor only), a literal of its vehicle's UMAA version: 3.0.1, OFF, ON or "
        "RESTARTING; 6.0, BEST_ALIGN, GPS_ALIGN, INIT, SNAP_ALIGN, STATIONARY_ALIGN or TRANSFER_ALIGN"))
    operator: str | None
    createdAt: float
    status: str | None = Field(description="the last commandStatus, null before ISSUED")
    terminal: bool
    unanswered: bool = Field(description="no ISSUED within the unanswered timeout")
    cancelRequested: bool
    canceledBy: str | None = Field(description="the operator who canceled it (null: no sign-in, or the console's shutdown)")
    canceledOn: str | None = Field(None, description="the console station its cancel was asked on (its --console-name); "
                                                     "null: not canceled, or before stations were recorded with a cancel")
    canceledAt: float | None = Field(None, description="when its cancel was asked, UTC seconds")
    cancelCause: Literal["operator", "shutdown"] | None = Field(None, description=(
        "why it was cancelled: operator, an operator asked it (canceledBy, when signed in); shutdown, the console station "
        "canceledOn cancelled it as it stopped (its Consumer Shutdown Sequence; canceledBy null). Null: not cancelled, "
        "or cancelled before the cause was recorded"))
    closedUnheard: Literal["heard", "bound"] | None = Field(None, description=(
        "a canceled command the vehicle never answered (no status at all), ended by the console: heard, the vehicle was "
        "heard again for the unanswered timeout without answering it (it never heard the command); bound, the vehicle "
        "was not heard within --cancel-unheard-bound of the cancel. Such a command is terminal with a null status"))
    closedAt: float | None = Field(None, description="when the console ended it so (closedUnheard), UTC seconds")
    ackedAt: float | None = Field(description="when the provider first acknowledged it (its CommandAckReport, published as it "
                                                  "starts to process the command), UTC seconds")
    cleanedUp: bool
    console: str | None = Field(None, description="the console station that issued it (its --console-name); null: a "
                                            "command of a release before station names")
    violations: list[str]
    transitions: list[Transition]


class ProviderMessage(StrictModel):
    type: Literal["provider"]
    event: Literal["appeared", "lost", "regained", "live", "configured"] = Field(
        description="live: a regained provider is back to normal; configured: its linkConfig, name or UMAA version changed")
    provider: ProviderSummary


class CommandMessage(StrictModel):
    type: Literal["command"]
    command: Command


class TransitionMessage(StrictModel):
    type: Literal["transition"]
    sessionId: str
    transition: Transition
    command: Command
