"""The outage write-behind: a PostgreSQL server that cannot be reached (stopped, restarting, the network) is an
outage, not an error. Writes are held in order and written when the server is back (`write_held`, from the console's
upkeep in a worker thread); reads fail at once with one line (`Unavailable`), not after a connect timeout. SQLite
raises as it is (one file on this machine: no outage to wait out).

`outage()` is the one place a lost server is recognised: every statement that may meet one runs inside it."""

from __future__ import annotations

import logging
import time
from collections import deque
from collections.abc import Callable, Iterator
from contextlib import contextmanager

from sqlalchemy import Connection, Engine, select
from sqlalchemy.exc import InterfaceError, OperationalError

from sem_console.storage.engine import problem
from sem_console.storage.url import DatabaseUrl

log = logging.getLogger("sem-console.storage")
# Writes held while a PostgreSQL server cannot be reached, written in order when it is back. Past the bound the
# oldest held writes are dropped (counted in `dropped`, logged): at a few writes a second (commands, transitions,
# audit, alarms) that is hours of an outage, and memory stays bounded.
HELD_MAX = 50_000
Write = Callable[[Connection], object]


class Unavailable(Exception):
    """A read of the shared database during an outage: the message is the one line a client reads (503)."""


class WriteBehind:
    def __init__(self, db: DatabaseUrl, engine: Engine) -> None:
        self.db, self.engine = db, engine
        self._held: deque[Write] = deque()  # during an outage, oldest first
        self.unavailable_since: float | None = None  # UTC seconds: the server was first found unreachable
        self.dropped = 0  # held writes dropped past HELD_MAX
        self.asked = 0  # writes asked of this console so far (run or held): a read that spans one may be older

    @property
    def held(self) -> int:
        return len(self._held)

    @contextmanager
    def outage(self, refusal: Callable[[], Exception] | None = None) -> Iterator[None]:
        """Around statements: a PostgreSQL server found unreachable starts an outage (if none is on) and raises
        `refusal()` (default: `unavailable()`) from the driver's error. SQLite's errors pass as they are."""
        try:
            yield
        except (OperationalError, InterfaceError) as e:
            if self.db.path is not None:
                raise
            self.went_away(e)
            raise (refusal or self.unavailable)() from e

    def write(self, fn: Write) -> bool:
        """Run `fn` in a transaction, or hold it (in order behind any held before) during an outage. True: committed;
        False: held (what `fn` saw of a transaction that did not commit is not so)."""
        self.asked += 1
        if self._held or self.unavailable_since is not None:  # in order; no connect timeout on the caller
            self._hold(fn)
            return False
        try:
            with self.outage(), self.engine.begin() as c:
                fn(c)
        except Unavailable:
            self._hold(fn)
            return False
        return True

    @contextmanager
    def reads(self) -> Iterator[Connection]:
        """A connection for reads. During an outage (found by a write or a read, ended by `write_held`) a read
        fails at once, not after a connect timeout on the caller's thread."""
        if self.unavailable_since is not None:
            raise self.unavailable()
        with self.outage(), self.engine.connect() as c:
            yield c

    def _hold(self, fn: Write) -> None:
        if len(self._held) >= HELD_MAX:
            self._held.popleft()
            self.dropped += 1
            if self.dropped in (1, 10, 100) or self.dropped % 1000 == 0:
                log.error(
                    "%d held writes dropped: the database has been unreachable too long (more than %d held)",
                    self.dropped,
                    HELD_MAX,
                )
        self._held.append(fn)

    def unreachable(self, e: Exception) -> Unavailable:
        """A read elsewhere (the track and chart history) that could not reach the server: an outage, one line."""
        if self.db.path is not None:  # one file on this machine: no outage to wait out
            return Unavailable(problem(self.db, e))
        self.went_away(e)
        return self.unavailable()

    def since(self) -> str:
        """When the database went away, as the operator reads every time: "2026-11-29 01:20:05 UTC"."""
        return time.strftime("%Y-%m-%d %H:%M:%S UTC", time.gmtime(self.unavailable_since or time.time()))

    def unavailable(self) -> Unavailable:
        return Unavailable(
            f"shared history unavailable since {self.since()}: the database {self.db.shown} cannot be "
            "reached; live monitoring goes on and changes are held here until it is back"
        )

    def went_away(self, e: Exception) -> None:
        if self.unavailable_since is None:
            self.unavailable_since = time.time()
            orig = getattr(e, "orig", None) or e
            log.warning(
                "the database %s cannot be reached (%s): holding writes until it is back",
                self.db.shown,
                str(orig).strip().splitlines()[0] if str(orig).strip() else type(e).__name__,
            )

    def reachable(self) -> bool:
        """During an outage with nothing held: whether the server answers again (for a worker thread)."""
        if self.unavailable_since is None or self._held:
            return True
        try:
            with self.engine.connect() as c:
                c.execute(select(1))
        except (OperationalError, InterfaceError):
            return False
        return True

    def write_held(self) -> bool:
        """Write what was held during an outage, oldest first (for a worker thread: the console's upkeep); True when
        nothing is left. Stops at the first write the server still refuses."""
        written = 0
        while self._held:
            fn = self._held[0]
            try:
                with self.engine.begin() as c:
                    fn(c)
            except (OperationalError, InterfaceError):
                return False
            if self._held and self._held[0] is fn:  # unless the loop dropped it meanwhile (the bound)
                self._held.popleft()
            written += 1
        if self.unavailable_since is not None:
            log.warning(
                "the database %s is back after %.0f s: wrote %d held changes",
                self.db.shown,
                time.time() - self.unavailable_since,
                written,
            )
            self.unavailable_since = None
        return True

    def close(self) -> None:
        """At the console's stop (after its upkeep has ended): write what is still held when the server answers (it
        may be back since the upkeep last looked); else say in one line how many changes are lost with the console."""
        if self._held and not self.write_held():
            log.error(
                "%d changes held since %s were not written: the database %s cannot be reached as the console stops",
                len(self._held),
                self.since(),
                self.db.shown,
            )
            self._held.clear()
