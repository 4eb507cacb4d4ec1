"""Whether this console is the one behind: its own delays, so that a silence it cannot vouch for is not a vehicle's.

Measured on the event loop thread: how late its tick ran (the event loop's delay: a loop busy with a backlog, or a
process the machine did not run), how long a sample waited between its take by an ingest thread and its handling on
the loop (the ingest lag), the process's CPU, and the samples Cyclone DDS says its readers lost (`sample lost`).

The console is behind from a delay past `BEHIND_AFTER` until none has passed it for `settle` seconds (the comms-lost
timeout: time for every live vehicle to be heard again once it keeps up). While it is behind, a vehicle's silence is
not judged while its delays may explain it (`excuse`) (`Providers.tick`: "not checked: console behind"; silent longer,
it is lost whatever the console's load) and, when that withheld a vehicle's check, the console
says so once, as its own alarm ("console-overloaded"), not one link-lost per vehicle.
"""

from __future__ import annotations

import time
from collections import deque
from collections.abc import Callable

from sem_console.core.messages import ConsoleLoad

BEHIND_AFTER = 0.5  # s: the loop's delay or a sample's wait on the loop past this: the console is behind
WINDOW = 1.0  # s: the delays and CPU shown are the worst and the mean of the last window this long


class Load:
    def __init__(self, settle: float, wall: Callable[[], float] = time.time) -> None:
        self.settle, self.wall = settle, wall
        self.behind_since: float | None = None  # UTC seconds
        self.withheld = 0  # vehicles whose check this episode withheld
        self._last_late = -float("inf")  # monotonic: the last delay past BEHIND_AFTER
        self._lates: deque[tuple[float, float]] = deque()  # (monotonic, delay) of the delays past it, the last settle
        self._window_start: float | None = None  # monotonic: the current window's start (the first tick's)
        self._cpu_start = time.process_time()
        self._loop_max = self._lag_max = 0.0  # the current window's worst
        self.loop_delay = self.ingest_lag = self.cpu = 0.0  # the last whole window's
        self.worst = 0.0  # the worst delay of the episode, for its words
        self.samples_lost = 0

    @property
    def behind(self) -> bool:
        return self.behind_since is not None

    def tick(self, delay: float, now: float) -> bool:
        """The tick ran `delay` seconds late at `now` (monotonic). Returns whether `behind` changed."""
        self._loop_max = max(self._loop_max, delay)
        self._late(delay, now)
        if self._window_start is None:
            self._window_start = now
        elif now - self._window_start >= WINDOW:
            cpu = time.process_time()
            self.cpu = (cpu - self._cpu_start) / (now - self._window_start)
            self.loop_delay, self.ingest_lag = self._loop_max, self._lag_max
            self._window_start, self._cpu_start, self._loop_max, self._lag_max = now, cpu, 0.0, 0.0
        if self.behind_since is None and now - self._last_late < self.settle:
            self.behind_since, self.withheld = self.wall(), 0
            return True
        if self.behind_since is not None and now - self._last_late >= self.settle:
            self.behind_since, self.worst = None, 0.0
            return True
        return False

    def handled(self, lag: float, now: float) -> None:
        """A take of samples was handled on the loop `lag` seconds after the ingest thread took it."""
        self._lag_max = max(self._lag_max, lag)
        self._late(lag, now)

    def excuse(self, now: float) -> float | None:
        """While it is behind, how much of a vehicle's silence its own delays may explain: the worst of those of the
        last `settle` seconds (one older was followed by `settle` seconds in which every live vehicle was heard, and one
        spurious, a wall clock stepped between a take and its handling, counts no longer); None while it keeps up."""
        while self._lates and now - self._lates[0][0] >= self.settle:
            self._lates.popleft()
        if self.behind_since is None or not self._lates:
            return None
        return max(d for _, d in self._lates)

    def _late(self, delay: float, now: float) -> None:
        if delay > BEHIND_AFTER:
            self._last_late = now
            self._lates.append((now, delay))
            self.worst = max(self.worst, delay)

    def state(self) -> ConsoleLoad:
        return {
            "behind": self.behind,
            "behindSince": self.behind_since,
            "loopDelayMs": round(max(self.loop_delay, self._loop_max) * 1000, 1),
            "ingestLagMs": round(max(self.ingest_lag, self._lag_max) * 1000, 1),
            "cpuCores": round(self.cpu, 2),
            "samplesLost": self.samples_lost,
            "vehiclesNotChecked": self.withheld if self.behind else 0,
        }
