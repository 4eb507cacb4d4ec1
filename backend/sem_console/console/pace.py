"""When the report thread may take again: at once while input is sparse, once per window under load.

A token bucket of `burst` takes, refilled at one take per `window` seconds. Sparse input (a
vehicle's 10 Hz reports, or a burst of a few vehicles' samples written together) finds the
bucket full, so every arrival is taken as soon as it wakes the thread: no window is waited.
Dense input empties it, and from then on the thread takes at most once per `window`, exactly
the conflation it always had: report readers keep the latest sample per instance, so a
provider publishing faster than that is conflated by DDS itself and the console's cost follows
what it shows. Plain Python with an injectable clock, so its behaviour is tested without time.
"""

from __future__ import annotations

import time
from collections.abc import Callable


class Pacer:
    def __init__(self, window: float, burst: int, clock: Callable[[], float] = time.monotonic) -> None:
        self.window, self.burst, self.clock = window, max(1, burst), clock
        self.tokens = float(self.burst)
        self.at = clock()

    def _refill(self) -> None:
        now = self.clock()
        if self.window <= 0:
            self.tokens = float(self.burst)
        else:
            self.tokens = min(float(self.burst), self.tokens + (now - self.at) / self.window)
        self.at = now

    def took(self) -> None:
        """A take starts now."""
        self._refill()
        self.tokens -= 1

    def delay(self) -> float:
        """Seconds until the next take may start: 0 while the bucket holds a whole take."""
        self._refill()
        return 0.0 if self.tokens >= 1 else (1 - self.tokens) * self.window
