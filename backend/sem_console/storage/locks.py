"""Name locks: which console holds a console name on a database, and which console writes a vehicle's track.

On PostgreSQL each is a session advisory lock the server lets go when the holding connection ends (the console stops
or dies); those sessions ask the server to probe them soon (`lock_session`). On SQLite the console name is an flock on
a file beside the database, let go when the process ends: one console per file (SQLite tells a console nothing of
another's changes)."""

from __future__ import annotations

import contextlib
import fcntl
import hashlib
import logging
import math
import os
import time
from pathlib import Path
from typing import Any

from sqlalchemy import Connection, Engine, func, select
from sqlalchemy.exc import InterfaceError, OperationalError, SQLAlchemyError

from sem_console.storage.engine import StorageError
from sem_console.storage.models import SeriesPoint, TrackPoint, table
from sem_console.storage.outage import WriteBehind

log = logging.getLogger("sem-console.storage")
NAME_REFUSED_GRACE = 15.0  # seconds the name is refused before that is an error (see NameLock.keep)
TRACK_POINTS, SERIES_POINTS = table(TrackPoint), table(SeriesPoint)


def _same_file(fd: int, path: Path) -> bool:
    """Whether `path` still names the file open as `fd` (a lock file removed or replaced meanwhile does not)."""
    try:
        return os.path.samestat(os.fstat(fd), os.stat(path))
    except FileNotFoundError:
        return False


def _key(text_: str) -> int:
    """A stable signed 64-bit key (PostgreSQL advisory locks) of a name."""
    return int.from_bytes(hashlib.sha256(text_.encode()).digest()[:8], "big", signed=True)


def lock_session(c: Connection) -> Connection:
    """`c`, a PostgreSQL connection whose session is to hold advisory locks (the console's name, its vehicles), with
    the server's TCP keepalives set short for it. A network cut (not a restart) leaves the server the session, and its
    locks, after the console gave up on it: with the server's defaults (two hours of idle before a probe) no console
    could take those locks again for hours (the name seen as another console's, a vehicle's track written by none)."""
    c.execute(
        select(
            func.set_config("tcp_keepalives_idle", "5", False),
            func.set_config("tcp_keepalives_interval", "2", False),
            func.set_config("tcp_keepalives_count", "2", False),
        )
    )
    return c


class NameLock:
    """This console's name, held while it runs: a second console of the same name on the database is refused."""

    def __init__(self, writes: WriteBehind) -> None:
        self.db, self.engine, self.writes = writes.db, writes.engine, writes
        self.lock: Connection | int | None = None  # what holds the name
        self.name: str | None = None
        # monotonic seconds the name has been refused since (another console took it while the server was away), and
        # whether that was said: not at the first refusal, which can be this console's own session from before a
        # network cut until the server ends it (`lock_session`: within about 10 s)
        self._refused: tuple[float, bool] | None = None

    def hold(self, name: str) -> None:
        """Take `name` (StorageError: another console holds it)."""
        if self.name != name:
            self._take(name)
            self.name = name

    def _take(self, name: str) -> None:
        taken = StorageError(
            f"another console named {name!r} is running on {self.db.shown}: give this one another --console-name"
        )
        if self.db.path is None:  # a session advisory lock: the server lets it go when this console's connection ends
            c = self.engine.connect()
            try:
                held = lock_session(c).execute(select(func.pg_try_advisory_lock(_key(f"console:{name}")))).scalar()
                c.commit()  # not idle in a transaction for the console's lifetime
            except SQLAlchemyError:  # the server went away meanwhile (the upkeep tries again): not left checked out
                c.invalidate()
                c.close()
                raise
            if not held:
                c.close()
                raise taken
            self.lock = c
            return
        if isinstance(self.lock, int):  # this console's already (a name claimed again, in one process)
            return
        lock = self.path()
        while True:
            fd = os.open(lock, os.O_RDWR | os.O_CREAT, 0o644)
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                holder = os.read(fd, 200).decode(errors="replace").strip()
                os.close(fd)
                raise StorageError(
                    f"another console{f' ({holder!r})' if holder else ''} is running on {self.db.path}: "
                    "consoles cannot share a SQLite file; stop it, pass another --db, or share a "
                    "PostgreSQL database with --database-url"
                ) from None
            if _same_file(fd, lock):
                break
            os.close(fd)  # removed by the console that held it as it stopped, after this one opened it: a new one
        os.ftruncate(fd, 0)
        os.write(fd, f"{name}\n".encode())  # for an operator wondering what the file is, and the refusal of a second
        self.lock = fd

    def path(self) -> Path:
        """The SQLite file's lock: held by the one console running on it."""
        assert self.db.path is not None
        return self.db.path.with_name(f"{self.db.path.name}.lock")

    def keep(self) -> bool:
        """Hold the name on PostgreSQL (the console's upkeep, in a worker thread): False when the server cannot be
        reached. The name is let go only while the server is away: it is taken again at the first call that finds
        it back (a restarted server ended the session, and the lock with it)."""
        if self.db.path is not None or self.name is None:
            return True
        lock = self.lock
        if isinstance(lock, Connection):
            try:
                lock.execute(select(1))
                lock.commit()
                return True
            except (OperationalError, InterfaceError):
                pass  # the server restarted (the session, and the name's lock with it, are gone) or cannot be reached
            with contextlib.suppress(SQLAlchemyError):
                lock.invalidate()
                lock.close()
            self.lock = None
        try:
            self._take(self.name)
        except StorageError as e:
            since, said = self._refused or (time.monotonic(), False)
            if not said and time.monotonic() - since >= NAME_REFUSED_GRACE:
                log.error("%s (it started while the database was away); the two share one UMAA identity: stop one", e)
                said = True
            self._refused = (since, said)
            return True  # tried again at each call: taken as soon as the other console stops
        except (OperationalError, InterfaceError) as e:  # away (found here before any write): an outage, tried again
            self.writes.went_away(e)
            return False
        log.warning("the database %s is back: console name %r held again", self.db.shown, self.name)
        self._refused = None
        return True

    def close(self) -> None:
        if isinstance(self.lock, Connection):
            self.lock.close()
        elif isinstance(self.lock, int):
            with contextlib.suppress(FileNotFoundError):  # removed while held: no other console can hold it now
                self.path().unlink()
            os.close(self.lock)
        self.lock = None


class VehicleWriters:
    """Which vehicles' track and chart history this console writes, on PostgreSQL: one console per vehicle, so the
    consoles that hear it do not each write it. A session advisory lock per vehicle, taken on a connection of this
    console's own at its first point: the server lets it go when that connection ends (the console stops or dies),
    and another console that hears the vehicle takes it at its next batch. For a worker thread."""

    def __init__(self, engine: Engine) -> None:
        self.engine = engine
        self._conn: Connection | None = None
        self._held: set[str] = set()
        # (table, provider) -> the first UTC second this console writes: a vehicle taken over from a console that
        # stopped may have a point in the second this console's batch starts in (at most one point a second)
        self._start: dict[tuple[str, str], float] = {}

    def mine(self, providers: set[str]) -> set[str]:
        """The vehicles of `providers` this console writes (it takes those no other console holds)."""
        try:
            if self._conn is None:
                self._conn, self._held, self._start = self.engine.connect(), set(), {}
                lock_session(self._conn)
            elif self._held and not providers - self._held:
                # nothing to take: a statement all the same, or a server restart (and the locks gone with it) would
                # go unseen, and this console write the vehicles beside the one that took them since
                self._conn.execute(select(1))
            for provider in providers - self._held:
                if self._conn.execute(select(func.pg_try_advisory_lock(_key(f"track:{provider}")))).scalar():
                    self._held.add(provider)
                    for t in (TRACK_POINTS, SERIES_POINTS):
                        last = self._conn.execute(select(func.max(t.c.time)).where(t.c.providerId == provider)).scalar()
                        if last is not None:
                            self._start[(t.name, provider)] = math.floor(last) + 1
            self._conn.commit()  # not idle in a transaction between batches
        except (OperationalError, InterfaceError):  # the server restarted or is away: its locks went with it
            self.close()
            raise
        return providers & self._held

    def after_last(self, table_name: str, point: dict[str, Any]) -> bool:
        """Whether a point of a vehicle this console writes is in a later second than any already written for it."""
        return bool(point["time"] >= self._start.get((table_name, point["providerId"]), -math.inf))

    def close(self) -> None:
        if self._conn is not None:
            self._conn.invalidate()  # a connection whose session held locks is not given to anyone else
            self._conn.close()
        self._conn, self._held, self._start = None, set(), {}
