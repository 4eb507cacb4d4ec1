"""The UMAA command status state machine (ICD 4.1, Figure 4), as plain Python.

    (new) --ISSUED/SUCCEEDED--> ISSUED --COMMANDED/SUCCEEDED--> COMMANDED --EXECUTING/SUCCEEDED--> EXECUTING
    EXECUTING --COMPLETED/SUCCEEDED--> COMPLETED
    ISSUED | COMMANDED | EXECUTING --FAILED/<a failure reason>--> FAILED
    ISSUED | COMMANDED | EXECUTING --CANCELED/CANCELED--> CANCELED

One addition to the figure, from the provider startup sequence (ICD 4.1.2.1): a
restarted provider that will not resume a persisted command fails it with
SERVICE_FAILED, which a consumer may see as the first status from that provider.
A status equal to the current one (same state and reason) is a repeat, not a transition; but each ISSUED/UPDATED with a
time stamp of its own is a new update (a command can be updated again before it moves on).

One model for every UMAA version: UMAA 6.0 adds the reason UPDATED (its ICD 4.1.4.2, Figure 15): a command with the
same source and sessionID and a newer time stamp is an update, and its status goes back to ISSUED from any of
ISSUED, COMMANDED and EXECUTING:

    ISSUED | COMMANDED | EXECUTING --ISSUED/UPDATED--> ISSUED

UMAA 3.0.1 has no such reason; its vehicles never send it. The model's reasons are UMAA 3.0.1's and `Updated`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum
from typing import TypeVar

from UMAA.Common.MaritimeEnumeration.CommandStatusEnumType import CommandStatusEnumType as Status
from UMAA.Common.MaritimeEnumeration.CommandStatusReasonEnumType import CommandStatusReasonEnumType as Reason

E = TypeVar("E", bound=Enum)


class Updated(Enum):
    """The model's reason beyond UMAA 3.0.1's (the module's docstring)."""

    UPDATED = "UPDATED"


UPDATED = Updated.UPDATED
AnyReason = Reason | Updated
TERMINAL = frozenset({Status.COMPLETED, Status.FAILED, Status.CANCELED})
FAILURE_REASONS = frozenset(
    {
        Reason.VALIDATION_FAILED,
        Reason.OBJECTIVE_FAILED,
        Reason.SERVICE_FAILED,
        Reason.RESOURCE_FAILED,
        Reason.RESOURCE_REJECTED,
        Reason.INTERRUPTED,
        Reason.TIMEOUT,
    }
)
_ACTIVE = (Status.ISSUED, Status.COMMANDED, Status.EXECUTING)

# state before (None: no status yet) -> states allowed next
NEXT: dict[Status | None, frozenset[Status]] = {
    None: frozenset({Status.ISSUED, Status.FAILED}),
    Status.ISSUED: frozenset({Status.COMMANDED, Status.FAILED, Status.CANCELED}),
    Status.COMMANDED: frozenset({Status.EXECUTING, Status.FAILED, Status.CANCELED}),
    Status.EXECUTING: frozenset({Status.COMPLETED, Status.FAILED, Status.CANCELED}),
    Status.COMPLETED: frozenset(),
    Status.FAILED: frozenset(),
    Status.CANCELED: frozenset(),
}

# The successful path, which a provider walks one step at a time.
SUCCESS_NEXT: dict[Status | None, Status] = {
    None: Status.ISSUED,
    Status.ISSUED: Status.COMMANDED,
    Status.COMMANDED: Status.EXECUTING,
    Status.EXECUTING: Status.COMPLETED,
}


def reason_allowed(status: Status, reason: AnyReason, first: bool = False) -> bool:
    if reason is UPDATED:
        return status is Status.ISSUED and not first
    if status is Status.FAILED:
        return reason is Reason.SERVICE_FAILED if first else reason in FAILURE_REASONS
    if status is Status.CANCELED:
        return reason is Reason.CANCELED
    return reason is Reason.SUCCEEDED


def name(v: Enum | int | None) -> str:
    """An enum literal's name; an ordinal the enum does not have (another vendor's bad sample) as UNKNOWN(n)."""
    if v is None:
        return "(no status)"
    return v.name if isinstance(v, Enum) else f"UNKNOWN({v})"


def parse(enum: type[E], text: str) -> E | int:
    """The inverse of `name`: a literal, or the ordinal of an UNKNOWN(n)."""
    if text in enum.__members__:
        return enum[text]
    if text.startswith("UNKNOWN(") and text.endswith(")") and text[8:-1].lstrip("-").isdigit():
        return int(text[8:-1])
    raise ValueError(f"{text!r} is not a {enum.__name__}")


def parse_reason(text: str) -> AnyReason | int:
    """`parse` for a reason of the model (UMAA 3.0.1's, or UPDATED)."""
    return UPDATED if text == UPDATED.name else parse(Reason, text)


def check_transition(prev: Status | None, status: Status | int, reason: AnyReason | int, figure: str = "Figure 4") -> str | None:
    """None when prev -> (status, reason) follows Figure 4 (an update: back to ISSUED), else what is wrong with it,
    naming the state machine as `figure` (its number in the vehicle's ICD: UMAA 6.0's is Figure 14)."""
    if not isinstance(status, Status):
        return f"unknown commandStatus ordinal {status!r}"
    if not isinstance(reason, AnyReason):
        return f"unknown commandStatusReason ordinal {reason!r}"
    if reason is UPDATED and prev in _ACTIVE and status is Status.ISSUED:
        return None
    if status not in NEXT[prev]:
        before = prev.name if prev is not None else "(no status)"
        return f"{before} -> {status.name} is not a {figure} transition"
    if not reason_allowed(status, reason, first=prev is None):
        return f"reason {reason.name} is not valid for {status.name}"
    return None


@dataclass
class Transition:
    status: Status | int  # an int only for an ordinal the enum does not have (always a violation)
    reason: AnyReason | int
    log_message: str
    violation: str | None = None
    stamp: float | None = None  # the status sample's timeStamp (seconds), when known


@dataclass
class CommandFlow:
    """Follows one command's statuses; records each transition and any violation."""

    transitions: list[Transition] = field(default_factory=list)
    figure: str = "Figure 4"  # the state machine's figure in the ICD of the command's version (versions/commands.py)

    @property
    def status(self) -> Status | None:
        """The last valid status (an unknown ordinal does not move the state machine)."""
        for t in reversed(self.transitions):
            if isinstance(t.status, Status) and isinstance(t.reason, AnyReason):
                return t.status
        return None

    @property
    def terminal(self) -> bool:
        return self.status in TERMINAL

    @property
    def violations(self) -> list[str]:
        return [t.violation for t in self.transitions if t.violation]

    def observe(
        self, status: Status | int, reason: AnyReason | int, log_message: str = "", stamp: float | None = None
    ) -> Transition | None:
        """Feed a received status (`stamp`: its timeStamp in seconds); returns the new transition, or None for a repeat:
        the last status again, unless it is an update (UPDATED) stamped otherwise, which is the next update; or an
        earlier status observed already, its time stamp included, stamped before the last status: the same sample
        delivered again (as a relay that restarted writes a running command's statuses again). One stamped at the last
        status's time is a provider that repeated itself: a transition, and its violation."""
        last = self.transitions[-1] if self.transitions else None
        if (
            last is not None
            and last.status is status
            and last.reason is reason
            and (reason is not UPDATED or stamp is None or stamp == last.stamp)
        ):
            return None
        if (
            last is not None
            and stamp is not None
            and last.stamp is not None
            and stamp < last.stamp
            and any(t.status is status and t.reason is reason and t.stamp == stamp for t in self.transitions)
        ):
            return None
        t = Transition(status, reason, log_message, check_transition(self.status, status, reason, self.figure), stamp)
        self.transitions.append(t)
        return t
