"""The console's time: the system's when live, the recording's in a replay.

Everything that stamps or ages state (link health, ages in summaries, when a transition or an
ack was received, the unanswered deadline) asks the console's clock, so a replay rebuilds the
state a live console had at each instant of the recording.
"""

from __future__ import annotations

import time


class Clock:
    """The system clock."""

    def wall(self) -> float:
        """UTC seconds since the epoch."""
        return time.time()

    def monotonic(self) -> float:
        """Seconds for intervals and deadlines."""
        return time.monotonic()


class RecordingClock(Clock):
    """A replay's clock: the recording's time (UTC seconds), set by the replay as it applies each message.
    Both readings are that time, so intervals are the recording's intervals."""

    def __init__(self, at: float = 0.0) -> None:
        self.at = at

    def wall(self) -> float:
        return self.at

    def monotonic(self) -> float:
        return self.at
