"""The commands a station issued and their status transitions."""

from __future__ import annotations

from sqlmodel import Field, SQLModel


class CommandIssued(SQLModel):
    """A command as issued; with CommandHandled, what the row (CommandRecord) and the API's command (core/contract.py,
    in camelCase) have in common."""

    session_id: str
    service: str
    provider_id: str
    state: str | None
    operator: str | None
    created_at: float


class CommandHandled(SQLModel):
    """What became of a command besides its statuses: unanswered, cancelled, closed, acknowledged, cleaned up."""

    unanswered: bool = Field(description="no ISSUED within the unanswered timeout")
    cancel_requested: bool
    canceled_by: str | None = Field(description="the operator who canceled it (null: no sign-in, or the console's shutdown)")
    canceled_on: str | None = Field(
        default=None,
        description=(
            "the console station its cancel was asked on (its --console-name); null: not canceled, or before stations were "
            "recorded with a cancel"
        ),
    )
    canceled_at: float | None = Field(default=None, description="when its cancel was asked, UTC seconds")
    cancel_cause: str | None = Field(
        default=None,
        description=(
            "why it was cancelled: operator, an operator asked it (canceledBy, when signed in); shutdown, the console station "
            "canceledOn cancelled it as it stopped (its Consumer Shutdown Sequence; canceledBy null). Null: not cancelled, "
            "or cancelled before the cause was recorded"
        ),
    )
    closed_unheard: str | None = Field(
        default=None,
        description=(
            "a canceled command the vehicle never answered (no status at all), ended by the console: heard, the vehicle was "
            "heard again for the unanswered timeout without answering it (it never heard the command); bound, the vehicle "
            "was not heard within --cancel-unheard-bound of the cancel. Such a command is terminal with a null status"
        ),
    )
    closed_at: float | None = Field(default=None, description="when the console ended it so (closedUnheard), UTC seconds")
    acked_at: float | None = Field(
        description="when the provider first acknowledged it (its CommandAckReport, published "
        "as it starts to process the command), UTC seconds"
    )
    cleaned_up: bool
    console: str | None = Field(
        default=None,
        description="the console station that issued it (its --console-name); null: a command of a release before station names",
    )


class CommandRecord(CommandHandled, CommandIssued, table=True):
    """A command this console (or another station on the same database) issued, with its flags."""

    __tablename__ = "commands"
    session_id: str = Field(primary_key=True)
    command: str = Field(description="the command sample's own fields as JSON (its timeStamp)")


class TransitionBase(SQLModel):
    """One status of a command: the row (TransitionRecord) and the API's transition (core/contract.py, in camelCase)."""

    seq: int = Field(description="1-based position in the command's history")
    status: str
    reason: str
    log_message: str
    violation: str | None = Field(
        description="why this transition breaks the command state machine (its ICD's figure: "
        "3.0.1's Figure 4, 6.0's Figure 14), or null"
    )
    provider_time: float | None = Field(description="the status sample's timeStamp, UTC seconds")
    received_at: float


class TransitionRecord(TransitionBase, table=True):
    """One status of a command, in the order received (seq from 1)."""

    __tablename__ = "transitions"
    session_id: str = Field(primary_key=True, foreign_key="commands.session_id")
    seq: int = Field(primary_key=True, description="1-based position in the command's history")
