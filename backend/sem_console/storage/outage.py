"""The write-behind: every write of the console runs on one thread of its own (`db-writer`), in the order asked,
never on the caller's (the event loop): a slow or hung database server delays the writes, not the console.

A PostgreSQL server that cannot be reached (stopped, restarting, the network) is an outage, not an error. Writes are
held in order and written when the server is back (`write_held`, from the console's upkeep in a worker thread); reads
fail at once with one line (`Unavailable`), not after a connect timeout. SQLite raises as it is (one file on this
machine: no outage to wait out).

A read (`reads`) waits for every write asked before it: what this console wrote, it reads back.

`outage()` is the one place a lost server is recognised: every statement that may meet one runs inside it."""

from __future__ import annotations

import logging
import threading
import time
from collections import deque
from collections.abc import Callable, Iterator
from concurrent.futures import Future
from contextlib import contextmanager
from typing import Any, NamedTuple, TypeVar

from sqlalchemy import Connection, Engine, select
from sqlalchemy.exc import InterfaceError, OperationalError, SQLAlchemyError

from sem_console.storage.engine import problem
from sem_console.storage.url import DatabaseUrl

log = logging.getLogger("sem-console.storage")
# Writes held while a PostgreSQL server cannot be reached, written in order when it is back. Past the bound the
# oldest held writes are dropped (counted in `dropped`, logged): at a few writes a second (commands, transitions,
# audit, alarms) that is hours of an outage, and memory stays bounded.
HELD_MAX = 50_000
T = TypeVar("T")
Write = Callable[[Connection], T]


class Pending(NamedTuple):
    """A write asked and not yet done with, and the future its result goes to."""

    fn: Write[Any]
    done: Future[Any]


class Unavailable(Exception):
    """A read of the shared database during an outage: the message is the one line a client reads (503)."""


class WriteBehind:
    def __init__(self, db: DatabaseUrl, engine: Engine) -> None:
        self.db, self.engine = db, engine
        self._queue: deque[Pending] = deque()  # asked and not yet written, oldest first (held during an outage)
        self._changed = threading.Condition()  # guards the queue and the counts below; notified at each change
        self.unavailable_since: float | None = None  # UTC seconds: the server was first found unreachable
        self.dropped = 0  # held writes dropped past HELD_MAX
        self.asked = 0  # writes asked of this console so far (run or held): a read that spans one may be older
        self._finished = 0  # writes done with: committed, refused by the database, dropped or lost at the stop
        self._written_back = 0  # held writes written since the outage began
        self._retry = False  # the writer is to try the held writes again (write_held, close)
        self._closing = self._closed = False
        self._thread = threading.Thread(target=self._run, name="db-writer", daemon=True)
        self._thread.start()

    @property
    def held(self) -> int:
        """Writes held in an outage (0 when there is none: a write waiting its turn is not held)."""
        return len(self._queue) if self.unavailable_since is not None else 0

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

    def write(self, fn: Write[T]) -> Future[T]:
        """Ask the writer thread to run `fn` in a transaction of its own, after every write asked before it; during an
        outage it is held (without a connect attempt) and written when the server is back. Returns at once: the future
        gets `fn`'s result once committed, the exception the database refused it with (logged), or is cancelled when
        the write is dropped past HELD_MAX or lost at the stop."""
        done: Future[T] = Future()
        with self._changed:
            self.asked += 1
            if self._closed:
                log.error("a change asked after the database %s was closed was not written", self.db.shown)
                done.cancel()
                self._finished += 1
                return done
            if len(self._queue) >= HELD_MAX:
                self._queue.popleft().done.cancel()  # the writer, running it, leaves it (_settle)
                self._finished += 1
                self.dropped += 1
                if self.dropped in (1, 10, 100) or self.dropped % 1000 == 0:
                    log.error(
                        "%d held writes dropped: the database has been unreachable too long (more than %d held)",
                        self.dropped,
                        HELD_MAX,
                    )
            self._queue.append(Pending(fn, done))
            self._changed.notify_all()
        return done

    def flush(self, timeout: float | None = None) -> bool:
        """Wait until every write asked so far is done with, or held in an outage (for a worker thread, or a test);
        False when `timeout` passed first."""
        with self._changed:
            asked = self.asked
            return self._changed.wait_for(
                lambda: self._finished >= asked or self.unavailable_since is not None or self._closed, timeout
            )

    @contextmanager
    def reads(self) -> Iterator[Connection]:
        """A connection for reads, once the writes asked before it are written (a read sees this console's writes).
        During an outage (found by a write or a read, ended by `write_held`) a read fails at once, not after a connect
        timeout on the caller's thread."""
        self.flush()
        if self.unavailable_since is not None:
            raise self.unavailable()
        with self.outage(), self.engine.connect() as c:
            yield c

    def _ready(self) -> bool:
        return self._closing or self._retry or bool(self._queue and self.unavailable_since is None)

    def _run(self) -> None:
        """The writer thread: the oldest write, in a transaction, until none is left; during an outage, only when
        asked to try again (`write_held`) or at the stop."""
        while True:
            with self._changed:
                self._changed.wait_for(self._ready)
                if not self._queue:
                    if self.unavailable_since is not None and self._retry:  # found by a read: nothing was held
                        self._back()
                    self._retry = False
                    self._changed.notify_all()
                    if self._closing:
                        return
                    continue
                pending = self._queue[0]
            try:
                with self.outage(), self.engine.begin() as c:
                    result = pending.fn(c)
            except Unavailable:  # held, with every write after it, until the server is back
                with self._changed:
                    self._retry = False
                    self._changed.notify_all()
                    if self._closing:
                        return
                continue
            except SQLAlchemyError as e:  # refused (SQLite's errors, a constraint): this change is lost, the next go on
                log.error("a change could not be written: %s", problem(self.db, e))
                self._settle(pending, error=e)
                continue
            except Exception as e:
                log.exception("a change could not be written to the database %s", self.db.shown)
                self._settle(pending, error=e)
                continue
            self._settle(pending, result)

    def _settle(self, pending: Pending, result: object = None, error: BaseException | None = None) -> None:
        with self._changed:
            if self._queue and self._queue[0] is pending:  # unless dropped meanwhile (the bound)
                self._queue.popleft()
                self._finished += 1
                if error is not None:
                    pending.done.set_exception(error)
                else:
                    pending.done.set_result(result)
                    if self.unavailable_since is not None:
                        self._written_back += 1
            if not self._queue and self.unavailable_since is not None:
                self._back()
            self._changed.notify_all()

    def _back(self) -> None:
        """The outage is over: every held write is written (under the lock)."""
        assert self.unavailable_since is not None
        log.warning(
            "the database %s is back after %.0f s: wrote %d held changes",
            self.db.shown,
            time.time() - self.unavailable_since,
            self._written_back,
        )
        self.unavailable_since, self._written_back, self._retry = None, 0, False

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
        with self._changed:
            if self.unavailable_since is None:
                self.unavailable_since = time.time()
                orig = getattr(e, "orig", None) or e
                log.warning(
                    "the database %s cannot be reached (%s): holding writes until it is back",
                    self.db.shown,
                    str(orig).strip().splitlines()[0] if str(orig).strip() else type(e).__name__,
                )
            self._changed.notify_all()

    def reachable(self) -> bool:
        """During an outage with nothing held: whether the server answers again (for a worker thread)."""
        if self.unavailable_since is None or self._queue:
            return True
        try:
            with self.engine.connect() as c:
                c.execute(select(1))
        except (OperationalError, InterfaceError):
            return False
        return True

    def write_held(self) -> bool:
        """During an outage, have the writer thread write what was held, oldest first, and wait for it (for a worker
        thread: the console's upkeep); True when the outage is over. It stops at the first write the server still
        refuses."""
        with self._changed:
            if self.unavailable_since is None or self._closed:
                return self.unavailable_since is None
            self._retry = True
            self._changed.notify_all()
            self._changed.wait_for(lambda: not self._retry)
            return self.unavailable_since is None

    def close(self) -> None:
        """At the console's stop (after its upkeep has ended): the writer thread writes what is still asked, and held
        when the server answers (it may be back since the upkeep last looked), then ends; what it could not write is
        said in one line (the changes lost with the console)."""
        with self._changed:
            if self._closed:
                return
            self._closing = True
            self._changed.notify_all()
        self._thread.join()
        with self._changed:
            if self._queue:
                log.error(
                    "%d changes held since %s were not written: the database %s cannot be reached as the console stops",
                    len(self._queue),
                    self.since(),
                    self.db.shown,
                )
            for pending in self._queue:
                pending.done.cancel()
            self._finished += len(self._queue)
            self._queue.clear()
            self._closed = True
            self._changed.notify_all()
