"""The console's database on SQLAlchemy 2.0 (sync engine), SQLite or PostgreSQL: commands and their transitions,
audit, link configurations, alarms and console identities (storage/models.py). The schema is Alembic's
(storage/migrations), upgraded when the database is opened; a SQLite file is copied beside itself first.

Calls are synchronous, where the console made them before (most on the event loop: single-row writes;
the exports and the track and chart history in worker threads)."""

from __future__ import annotations

import contextlib
import fcntl
import hashlib
import itertools
import json
import logging
import math
import os
import sqlite3
import threading
import time
import uuid
from collections import deque
from collections.abc import Callable
from pathlib import Path
from typing import Any

from alembic import command
from alembic.config import Config
from alembic.runtime.migration import MigrationContext
from alembic.script import ScriptDirectory
from sqlalchemy import Connection, Engine, and_, case, create_engine, delete, event, func, insert, inspect, or_, select, update
from sqlalchemy.dialects import postgresql, sqlite
from sqlalchemy.exc import IntegrityError, InterfaceError, OperationalError, SQLAlchemyError

from sem_console.storage.models import (
    AlarmRecord,
    AlarmShelfRecord,
    AuditRecord,
    ComapTaskIds,
    ComapTaskRecord,
    ComapWorldRecord,
    CommandRecord,
    ConsoleIdentity,
    LinkConfigRecord,
    Meta,
    PlannedSilenceRecord,
    SeriesPoint,
    TrackPoint,
    TransitionRecord,
    VehicleNameRecord,
    table,
)
from sem_console.storage.notify import CHANNEL, PG_CONNECT_ARGS, Listener
from sem_console.storage.url import DatabaseUrl, sqlite_file

log = logging.getLogger("sem-console.storage")
logging.getLogger("alembic").setLevel(logging.WARNING)  # its INFO lines name plugins and contexts: our own say what changed
MIGRATIONS = Path(__file__).parent / "migrations"
ALARMS_KEPT = 100_000  # alarms back to normal kept in the database
AUDIT_COLUMNS = ("at", "outcome", "status", "method", "path", "client", "origin", "operator", "session_id", "reason")
ALARM_COLUMNS = ("key", "kind", "severity", "provider_id", "vehicle", "session_id", "text", "since", "cleared_at", "acked_at",
                 "acked_by", "normal_at")
MIGRATION_LOCK = 0x53454D_0001  # pg advisory lock key: one console upgrades the schema at a time
# Writes held while a PostgreSQL server cannot be reached, written in order when it is back. Past the bound the
# oldest held writes are dropped (counted in `dropped`, logged): at a few writes a second (commands, transitions,
# audit, alarms) that is hours of an outage, and memory stays bounded.
HELD_MAX = 50_000
NAME_REFUSED_GRACE = 15.0  # seconds the name is refused before that is an error (see Database._name_refused)


# the Core tables: statements below are on their columns
COMMANDS, TRANSITIONS, AUDIT, ALARMS = table(CommandRecord), table(TransitionRecord), table(AuditRecord), table(AlarmRecord)
CONSOLES, META, LINK_CONFIG = table(ConsoleIdentity), table(Meta), table(LinkConfigRecord)
TRACK_POINTS, SERIES_POINTS = table(TrackPoint), table(SeriesPoint)
VEHICLE_NAMES = table(VehicleNameRecord)
COMAP_WORLD, COMAP_TASKS, COMAP_TASK_IDS = table(ComapWorldRecord), table(ComapTaskRecord), table(ComapTaskIds)
SHELVES, SILENCES = table(AlarmShelfRecord), table(PlannedSilenceRecord)
TASK_IDS = 0xFFFE  # CoMap task ids 1..65534 (a u16 on IMC), wrapping


class StorageError(Exception):
    """The console cannot use its database: the message is the one line the operator reads (problem and fix)."""


class Unavailable(Exception):
    """A read of the shared database during an outage: the message is the one line a client reads (503)."""


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
    c.execute(select(func.set_config("tcp_keepalives_idle", "5", False),
                     func.set_config("tcp_keepalives_interval", "2", False),
                     func.set_config("tcp_keepalives_count", "2", False)))
    return c


def open_engine(db: DatabaseUrl) -> Engine:
    if db.path is None:
        # pre-ping: a connection the server dropped (restart, outage) is replaced, not handed out broken
        return create_engine(db.url, pool_pre_ping=True, connect_args=PG_CONNECT_ARGS)
    db.path.parent.mkdir(parents=True, exist_ok=True)
    engine = create_engine(db.url, connect_args={"check_same_thread": False, "timeout": 10})

    @event.listens_for(engine, "connect")
    def _pragmas(dbapi_connection: Any, _record: Any) -> None:
        cur = dbapi_connection.cursor()
        cur.execute("PRAGMA journal_mode=WAL")
        cur.execute("PRAGMA synchronous=NORMAL")
        cur.close()

    return engine


def _option(db: DatabaseUrl) -> str:
    """The option that named the database, as an error names it."""
    return f"--database-url {db.shown}" if db.path is None else f"--db {db.path}"


def problem(db: DatabaseUrl, e: Exception) -> str:
    """One line for an error reaching or reading the database: what is wrong and what to do."""
    where = _option(db)
    message = str(getattr(e, "orig", None) or e).strip().splitlines()[0] if str(e).strip() else type(e).__name__
    lower = message.lower()
    if db.path is not None:
        return f"{where}: {message}: move it aside or pass another --db"
    if "password authentication failed" in lower or "no password supplied" in lower:
        return f"{where}: {message}: fix the user name or password in --database-url"
    if "does not exist" in lower:
        return f"{where}: {message}: create it (createdb, or CREATE DATABASE) or fix --database-url"
    if "connection refused" in lower or "timeout" in lower or "could not translate host name" in lower \
            or "no route to host" in lower:
        return f"{where}: cannot reach the PostgreSQL server ({message}): start it, or fix the host and port in --database-url"
    return f"{where}: {message}: fix --database-url or the server"


def alembic_config(connection: Connection) -> Config:
    cfg = Config()
    cfg.set_main_option("script_location", str(MIGRATIONS))
    cfg.attributes["connection"] = connection
    return cfg


def _scripts() -> ScriptDirectory:
    cfg = Config()
    cfg.set_main_option("script_location", str(MIGRATIONS))
    return ScriptDirectory.from_config(cfg)


def head_revision() -> str | None:
    return _scripts().get_current_head()


def migrate(engine: Engine, db: DatabaseUrl) -> None:
    """Upgrade the schema to the newest revision. A SQLite file with tables at an older revision (or of the
    first release, without Alembic's table) is copied beside itself first, with a name that says why."""
    scripts = _scripts()
    head = scripts.get_current_head()
    with engine.connect() as c:
        if db.path is None:  # two consoles starting together: one upgrades, the other then finds it done
            c.execute(select(func.pg_advisory_lock(MIGRATION_LOCK)))
        try:
            current = MigrationContext.configure(c).get_current_revision()
            if current == head:
                return
            if current is not None and current not in {r.revision for r in scripts.walk_revisions()}:
                raise StorageError(f"{_option(db)}: its schema is at revision {current}, newer than this sem-console's {head}: "
                                   "run the sem-console release that wrote it (the consoles of one database run one release)")
            tables = set(inspect(c).get_table_names())
            c.commit()
            if db.path is not None and tables - {"alembic_version"}:
                backup = backup_sqlite(db.path, current)
                log.warning("copied %s to %s before upgrading its schema (from %s to %s)", db.path, backup,
                            current or "the first release's", head)
            with c.begin():
                command.upgrade(alembic_config(c), "head")
            log.info("database %s upgraded to schema revision %s", db.shown, head)
        finally:
            if db.path is None:
                c.execute(select(func.pg_advisory_unlock(MIGRATION_LOCK)))
                c.commit()


def backup_sqlite(path: Path, revision: str | None) -> Path:
    """A consistent copy of the file (SQLite's backup API: the WAL included) named
    <name>.before-upgrade-from-<revision>-<UTC time>.sqlite3 beside it."""
    stamp = time.strftime("%Y%m%dT%H%M%SZ", time.gmtime())
    target = path.with_name(f"{path.stem}.before-upgrade-from-{revision or 'first-release'}-{stamp}.sqlite3")
    src, dst = sqlite3.connect(path), sqlite3.connect(target)
    try:
        src.backup(dst)
    finally:
        src.close()
        dst.close()
    return target


class Database:
    def __init__(self, db: DatabaseUrl | Path, audit_max_rows: int = 100_000) -> None:
        """Open (and upgrade) the database (a Path: a SQLite file); StorageError when it cannot be used."""
        self.db = db = sqlite_file(db) if isinstance(db, Path) else db
        self.audit_max_rows = audit_max_rows
        self.engine = open_engine(db)
        self._lock: Connection | int | None = None  # what holds this console's name (claim)
        self._taking_task_id = threading.Lock()  # new_comap_task, from the assigns' worker threads
        self._held: str | None = None
        # monotonic seconds the name has been refused since (another console took it while the server was away), and
        # whether that was said: not at the first refusal, which can be this console's own session from before a
        # network cut until the server ends it (`lock_session`: within about 10 s)
        self._name_refused: tuple[float, bool] | None = None
        self.station: str | None = None  # the name claimed: sent with each notification, so a console skips its own
        self._held_writes: deque[Callable[[Connection], object]] = deque()  # during an outage, oldest first
        self.unavailable_since: float | None = None  # UTC seconds: the server was first found unreachable
        self.dropped = 0  # held writes dropped past HELD_MAX
        self._temporary_ids = itertools.count(-1, -1)  # alarms raised during an outage, until written
        self._alarm_ids: dict[int, int] = {}  # such a temporary id -> the row's id once written
        try:
            migrate(self.engine, db)
        except StorageError:
            self.engine.dispose()
            raise
        except (SQLAlchemyError, sqlite3.Error, OSError) as e:
            self.engine.dispose()
            raise StorageError(problem(db, e)) from e
        self._insert = (postgresql if self.engine.dialect.name == "postgresql" else sqlite).insert

    # ---- identity -----------------------------------------------------------------------
    def claim(self, name: str, hold: bool = True) -> uuid.UUID:
        """This console's source GUID, by its name: the one it had, else the first release's (meta 'source')
        when no name took it yet, else a new one. The name is held while the console runs: a second console
        of the same name on this database is refused (StorageError). `hold=False`: the identity only (tests that
        restart a console's parts in one process)."""
        if hold and self._held != name:
            self._hold(name)
            self._held = name
        self.station = name
        for _attempt in range(3):  # another console may take the first release's GUID at the same moment
            try:
                with self.engine.begin() as c:
                    guid = c.execute(select(CONSOLES.c.guid).where(CONSOLES.c.name == name)).scalar()
                    if guid is not None:
                        return uuid.UUID(guid)
                    legacy = c.execute(select(META.c.value).where(META.c.key == "source")).scalar()
                    if legacy is None or c.execute(select(CONSOLES.c.name).where(CONSOLES.c.guid == legacy)).first():
                        legacy = None
                    guid = legacy or str(uuid.uuid4())
                    c.execute(insert(CONSOLES).values(name=name, guid=guid, created_at=time.time()))
                    if legacy is not None:  # the first release's commands and alarms were this station's
                        c.execute(update(COMMANDS).where(COMMANDS.c.console.is_(None)).values(console=name))
                        c.execute(update(ALARMS).where(ALARMS.c.console.is_(None)).values(console=name))
                    return uuid.UUID(guid)
            except IntegrityError:
                continue
        raise StorageError(f"{self.db.shown}: could not record the console name {name!r}: try again")

    def _hold(self, name: str) -> None:
        taken = StorageError(f"another console named {name!r} is running on {self.db.shown}: give this one another "
                             "--console-name")
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
            self._lock = c
            return
        # SQLite: an flock on a file beside the database, let go when the process ends, removed at a clean stop. One
        # console per file, whatever its name: SQLite tells a console nothing of another's changes (no live sharing)
        if isinstance(self._lock, int):  # this console's already (a name claimed again, in one process)
            return
        lock = self.lock_path()
        while True:
            fd = os.open(lock, os.O_RDWR | os.O_CREAT, 0o644)
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                holder = os.read(fd, 200).decode(errors="replace").strip()
                os.close(fd)
                raise StorageError(f"another console{f' ({holder!r})' if holder else ''} is running on {self.db.path}: "
                                   "consoles cannot share a SQLite file; stop it, pass another --db, or share a "
                                   "PostgreSQL database with --database-url") from None
            if _same_file(fd, lock):
                break
            os.close(fd)  # removed by the console that held it as it stopped, after this one opened it: a new one
        os.ftruncate(fd, 0)
        os.write(fd, f"{name}\n".encode())  # for an operator wondering what the file is, and the refusal of a second
        self._lock = fd

    def lock_path(self) -> Path:
        """The SQLite file's lock: held by the one console running on it."""
        assert self.db.path is not None
        return self.db.path.with_name(f"{self.db.path.name}.lock")

    # ---- writes, and what happens to them during an outage -----------------------------------
    def _write(self, fn: Callable[[Connection], object]) -> None:
        """Run `fn` in a transaction. A PostgreSQL server that cannot be reached (stopped, restarting, the network)
        is an outage, not an error: the write is held, in order behind any held before, and written by
        `write_held` when the server is back. SQLite raises as before (one file on this machine)."""
        if self._held_writes or self.unavailable_since is not None:  # in order; no connect timeout on the loop
            self._hold_write(fn)
            return
        try:
            with self.engine.begin() as c:
                fn(c)
        except (OperationalError, InterfaceError) as e:
            if self.db.path is not None:
                raise
            self._went_away(e)
            self._hold_write(fn)

    def _hold_write(self, fn: Callable[[Connection], object]) -> None:
        if len(self._held_writes) >= HELD_MAX:
            self._held_writes.popleft()
            self.dropped += 1
            if self.dropped in (1, 10, 100) or self.dropped % 1000 == 0:
                log.error("%d held writes dropped: the database has been unreachable too long (more than %d held)",
                          self.dropped, HELD_MAX)
        self._held_writes.append(fn)

    @property
    def held(self) -> int:
        return len(self._held_writes)

    def _reads(self) -> Connection:
        """A connection for a read. During an outage (found by a write or a read, cleared by `maintain`) a read
        fails at once, not after a connect timeout on the caller's thread (most often the event loop)."""
        if self.unavailable_since is not None:
            raise self._unavailable()
        try:
            return self.engine.connect()
        except (OperationalError, InterfaceError) as e:
            if self.db.path is not None:
                raise
            self._went_away(e)
            raise self._unavailable() from e

    def unreachable(self, e: Exception) -> Unavailable:
        """A read elsewhere (the track and chart history) that could not reach the server: an outage, one line."""
        if self.db.path is not None:  # one file on this machine: no outage to wait out
            return Unavailable(problem(self.db, e))
        self._went_away(e)
        return self._unavailable()

    def _since(self) -> str:
        """When the database went away, as the operator reads every time: "2026-11-29 01:20:05 UTC"."""
        return time.strftime("%Y-%m-%d %H:%M:%S UTC", time.gmtime(self.unavailable_since or time.time()))

    def _unavailable(self) -> Unavailable:
        since = self._since()
        return Unavailable(f"shared history unavailable since {since}: the database {self.db.shown} cannot be reached; "
                           "live monitoring goes on and changes are held here until it is back")

    def _went_away(self, e: Exception) -> None:
        if self.unavailable_since is None:
            self.unavailable_since = time.time()
            orig = getattr(e, "orig", None) or e
            log.warning("the database %s cannot be reached (%s): holding writes until it is back", self.db.shown,
                        str(orig).strip().splitlines()[0] if str(orig).strip() else type(e).__name__)

    def maintain(self) -> bool:
        """For a worker thread, every few seconds on PostgreSQL (the console's tick): during an outage, find the
        server back and write what was held; re-take this console's name when the server restarted (its session
        lock went with the old connection). True when the database can be used."""
        if self.unavailable_since is not None and not self._held_writes:
            try:
                with self.engine.connect() as c:
                    c.execute(select(1))
            except (OperationalError, InterfaceError):
                return False
        if not self.write_held():
            return False
        return self._keep_name()

    def _keep_name(self) -> bool:
        """Hold this console's name on PostgreSQL (see `maintain`): False when the server cannot be reached. The
        name is let go only while the server is away: it is taken again at the first call that finds it back."""
        if self.db.path is not None or self._held is None:
            return True
        lock = self._lock
        if isinstance(lock, Connection):
            try:
                lock.execute(select(1))
                lock.commit()
                return True
            except (OperationalError, InterfaceError):
                pass  # the server restarted (the session, and the name's lock with it, are gone) or cannot be reached
            try:
                lock.invalidate()
                lock.close()
            except SQLAlchemyError:
                pass
            self._lock = None
        try:
            self._hold(self._held)
        except StorageError as e:
            since, said = self._name_refused or (time.monotonic(), False)
            if not said and time.monotonic() - since >= NAME_REFUSED_GRACE:
                log.error("%s (it started while the database was away); the two share one UMAA identity: stop one", e)
                said = True
            self._name_refused = (since, said)
            return True  # tried again at each call: taken as soon as the other console stops
        except (OperationalError, InterfaceError) as e:  # away (found here before any write): an outage, tried again
            self._went_away(e)
            return False
        log.warning("the database %s is back: console name %r held again", self.db.shown, self._held)
        self._name_refused = None
        return True

    def write_held(self) -> bool:
        """Write what was held during an outage, oldest first (for a worker thread: see `maintain`); True when
        nothing is left. Stops at the first write the server still refuses."""
        written = 0
        while self._held_writes:
            fn = self._held_writes[0]
            try:
                with self.engine.begin() as c:
                    fn(c)
            except (OperationalError, InterfaceError):
                return False
            if self._held_writes and self._held_writes[0] is fn:  # unless the loop dropped it meanwhile (the bound)
                self._held_writes.popleft()
            written += 1
        if self.unavailable_since is not None:
            log.warning("the database %s is back after %.0f s: wrote %d held changes", self.db.shown,
                        time.time() - self.unavailable_since, written)
            self.unavailable_since = None
        return True

    # ---- between consoles (PostgreSQL) ------------------------------------------------------
    def _notify(self, c: Connection, kind: str, **fields: Any) -> None:
        """Tell the other consoles on this database what changed (delivered when the transaction commits)."""
        if self.db.path is None:
            payload = json.dumps({"kind": kind, "console": self.station, **fields})
            c.execute(select(func.pg_notify(CHANNEL, payload)))

    def listen(self, on_message: Callable[[dict[str, Any]], object]) -> Listener | None:
        """A started Listener of the other consoles' notifications (None on SQLite: one console per file)."""
        if self.db.path is not None:
            return None
        listener = Listener(self.db.url, on_message)
        listener.start()
        return listener

    def consoles(self) -> dict[str, uuid.UUID]:
        """Every console name that used this database -> its source GUID."""
        with self._reads() as c:
            return {n: uuid.UUID(g) for n, g in c.execute(select(CONSOLES.c.name, CONSOLES.c.guid))}

    # ---- commands -----------------------------------------------------------------------
    def add_command(self, rec: dict[str, Any], command_: dict[str, Any], console: str | None = None) -> None:
        row = dict(session_id=rec["sessionId"], service=rec["service"], provider_id=rec["providerId"], state=rec["state"],
                   operator=rec["operator"], created_at=rec["createdAt"], command=json.dumps(command_), unanswered=False,
                   cancel_requested=False, cleaned_up=False, console=console)

        def write(c: Connection) -> None:
            c.execute(insert(COMMANDS).values(row))
            self._notify(c, "command", session=rec["sessionId"])
        self._write(write)

    def add_transition(self, session_id: str, seq: int, t: dict[str, Any]) -> None:
        stmt = self._insert(TRANSITIONS).values(
            session_id=session_id, seq=seq, status=t["status"], reason=t["reason"], log_message=t["logMessage"],
            violation=t["violation"], provider_time=t["providerTime"], received_at=t["receivedAt"],
        ).on_conflict_do_nothing()

        def write(c: Connection) -> None:
            c.execute(stmt)
            # the vehicle answered after all: what it says stands, whatever station ended the command as never heard
            c.execute(update(COMMANDS).where(COMMANDS.c.session_id == session_id, COMMANDS.c.closed_unheard.is_not(None))
                      .values(closed_unheard=None, closed_at=None, cleaned_up=False))
            self._notify(c, "command", session=session_id)
        self._write(write)

    def set_flag(self, session_id: str, flag: str, value: bool = True) -> None:
        assert flag in ("unanswered", "cleaned_up")
        self._update_command(session_id, **{flag: value})

    def set_acked(self, session_id: str, at: float) -> None:
        self._update_command(session_id, acked_at=at)

    def set_canceled(self, session_id: str, operator: str | None, station: str | None, at: float,
                     cause: str | None = "operator") -> None:
        self._update_command(session_id, cancel_requested=True, canceled_by=operator, canceled_on=station, canceled_at=at,
                             cancel_cause=cause)

    def set_closed_unheard(self, session_id: str, why: str, at: float) -> bool | None:
        """A cancelled command the vehicle never answered, ended by the console (`why`): not once a status of it is
        stored (another station heard the vehicle answer; `add_transition` withdraws an ending stored before), nor once
        another station ended it (every station shows the one stored ending). True: stored; False: refused (the
        caller reads what is stored); None: held in an outage."""
        answered = select(TRANSITIONS.c.seq).where(TRANSITIONS.c.session_id == session_id).exists()
        stored: list[bool] = []

        def write(c: Connection) -> None:
            done = c.execute(update(COMMANDS).where(COMMANDS.c.session_id == session_id, ~answered,
                                                    COMMANDS.c.closed_unheard.is_(None))
                             .values(closed_unheard=why, closed_at=at, cleaned_up=True))
            stored.append(done.rowcount > 0)
            self._notify(c, "command", session=session_id)
        self._write(write)
        return stored[-1] if stored else None

    def _update_command(self, session_id: str, where: Any = None, **values: Any) -> None:
        def write(c: Connection) -> None:
            c.execute(update(COMMANDS).where(COMMANDS.c.session_id == session_id, *([] if where is None else [where]))
                      .values(**values))
            self._notify(c, "command", session=session_id)
        self._write(write)

    def commands(self, limit: int | None = None, offset: int = 0, unfinished: bool = False,
                 session_id: str | None = None, provider_id: str | None = None,
                 console: str | None = None) -> list[dict[str, Any]]:
        """Commands newest first with their transitions: `limit` of them from `offset` (to `provider_id`,
        issued by `console`, when given), plus every command not yet cleaned up when `unfinished`, or the one
        `session_id`."""
        q = select(*COMMANDS.c)
        if session_id is not None:
            q = q.where(COMMANDS.c.session_id == session_id)
        else:
            page = select(COMMANDS.c.session_id).order_by(COMMANDS.c.created_at.desc())
            if provider_id is not None:
                page = page.where(COMMANDS.c.provider_id == provider_id)
            if console is not None:
                page, q = page.where(COMMANDS.c.console == console), q.where(COMMANDS.c.console == console)
            page = page.limit(limit).offset(offset)
            chosen = COMMANDS.c.session_id.in_(page)
            q = q.where(or_(chosen, COMMANDS.c.cleaned_up.is_(False)) if unfinished else chosen)
            q = q.order_by(COMMANDS.c.created_at.desc())
        with self._reads() as c:
            return _with_transitions(c, [dict(r) for r in c.execute(q).mappings()])

    def export_commands(self, provider_id: str | None, since: float | None, until: float | None) -> list[dict[str, Any]]:
        """Commands created in [since, until] (to `provider_id` when given), oldest first, with their
        transitions; for a worker thread (a connection of its own from the pool)."""
        q = select(*COMMANDS.c).order_by(COMMANDS.c.created_at)
        if provider_id is not None:
            q = q.where(COMMANDS.c.provider_id == provider_id)
        if since is not None:
            q = q.where(COMMANDS.c.created_at >= since)
        if until is not None:
            q = q.where(COMMANDS.c.created_at <= until)
        with self._reads() as c:
            return _with_transitions(c, [dict(r) for r in c.execute(q).mappings()])

    def clear_commands(self) -> None:
        """Forget every command and transition (a replay rebuilding its state); the audit trail stays."""
        with self.engine.begin() as c:
            c.execute(delete(TRANSITIONS))
            c.execute(delete(COMMANDS))

    # ---- audit ----------------------------------------------------------------------------
    def add_audit(self, entry: dict[str, Any]) -> None:
        """One entry (keys: AUDIT_COLUMNS); the table keeps the newest audit_max_rows. Ids count up (never
        reused), so the prune is one range delete on the key."""
        row = {k: entry.get(k) for k in AUDIT_COLUMNS}

        def write(c: Connection) -> None:
            new_id = c.execute(insert(AUDIT).values(row).returning(AUDIT.c.id)).scalar_one()
            c.execute(delete(AUDIT).where(AUDIT.c.id <= new_id - self.audit_max_rows))
            self._notify(c, "audit", id=new_id)
        self._write(write)

    def audit(self, limit: int, offset: int) -> list[dict[str, Any]]:
        """Newest first."""
        with self._reads() as c:
            q = select(*AUDIT.c).order_by(AUDIT.c.id.desc()).limit(limit).offset(offset)
            return [dict(r) for r in c.execute(q).mappings()]

    # ---- link configurations ----------------------------------------------------------
    def link_configs(self) -> dict[str, Any]:
        """provider GUID string -> the link configuration an operator set for it (as stored: the caller validates)."""
        out: dict[str, Any] = {}
        with self._reads() as c:
            for provider, config in c.execute(select(LINK_CONFIG.c.provider_id, LINK_CONFIG.c.config)):
                try:
                    out[provider] = json.loads(config)
                except ValueError:  # not JSON: the caller's validation refuses it
                    out[provider] = config
        return out

    def set_link_config(self, provider_id: str, config: dict[str, Any]) -> None:
        stmt = self._insert(LINK_CONFIG).values(provider_id=provider_id, config=json.dumps(config))
        upsert = stmt.on_conflict_do_update(index_elements=["provider_id"], set_={"config": stmt.excluded.config})

        def write(c: Connection) -> None:
            c.execute(upsert)
            self._notify(c, "link", provider=provider_id)
        self._write(write)

    # ---- vehicle names ------------------------------------------------------------------
    def vehicle_names(self) -> dict[str, str]:
        """provider GUID string -> the name an operator set for it from the dashboard."""
        with self.engine.connect() as c:
            return {p: n for p, n in c.execute(select(VEHICLE_NAMES.c.provider_id, VEHICLE_NAMES.c.name))}

    def set_vehicle_name(self, provider_id: str, name: str | None, by: str | None) -> None:
        """Store a vehicle's name; None removes it (the configured name applies again)."""
        if name is None:
            stmt: Any = delete(VEHICLE_NAMES).where(VEHICLE_NAMES.c.provider_id == provider_id)
        else:
            ins = self._insert(VEHICLE_NAMES).values(provider_id=provider_id, name=name, set_by=by, set_at=time.time())
            stmt = ins.on_conflict_do_update(index_elements=["provider_id"], set_={
                "name": ins.excluded.name, "set_by": ins.excluded.set_by, "set_at": ins.excluded.set_at})

        def write(c: Connection) -> None:
            c.execute(stmt)
            self._notify(c, "name", provider=provider_id)
        self._write(write)

    # ---- CoMap: the world model and tasks ------------------------------------------------
    def comap_world(self) -> dict[str, Any] | None:
        """The stored world model (its row, features parsed), None before any."""
        with self._reads() as c:
            row = c.execute(select(*COMAP_WORLD.c)).mappings().first()
        return None if row is None else {**row, "features": json.loads(row["features"])}

    def comap_tasks(self, task_id: int | None = None) -> list[dict[str, Any]]:
        """Every stored task (or the one `task_id`), oldest first, as rows (point parsed)."""
        q = select(*COMAP_TASKS.c).order_by(COMAP_TASKS.c.created_at)
        if task_id is not None:
            q = q.where(COMAP_TASKS.c.task_id == task_id)
        with self._reads() as c:
            rows = [dict(r) for r in c.execute(q).mappings()]
        return [{**r, "point": json.loads(r["point"]) if r["point"] else None} for r in rows]

    def set_comap_world(self, world: dict[str, Any]) -> None:
        """Store the world model (keys: features, updated_at, source, highest_feature), unless the row holds a newer
        one (written by another console meanwhile, or before this console's held write after an outage)."""
        t = COMAP_WORLD
        values = {**world, "id": 1, "features": json.dumps(world["features"]), "station": self.station}
        ins = self._insert(t).values(values)
        stmt = ins.on_conflict_do_update(index_elements=[t.c.id], set_={k: ins.excluded[k] for k in values if k != "id"},
                                         where=t.c.updated_at <= ins.excluded.updated_at)

        def write(c: Connection) -> None:
            c.execute(stmt)
            self._notify(c, "worldmodel")
        self._write(write)

    def set_comap_task(self, task: dict[str, Any], final: frozenset[str]) -> None:
        """Store a task's change (keys: ComapTaskRecord's). Its state and synch are written where decided after the
        row's (`state_at`), its progress and quality where newer than the row's (`updated_at`), each by its own stamp:
        a station's progress write carries the stamp of the state it read, so it never stores that state over another
        station's newer one (a HOLD), and a HOLD held through an outage is stored after it even though the vehicle's
        progress, stored by another station meanwhile, is newer. A `final` state stored is never replaced by one that
        is not, nor by a final one decided after it (comap.c2.decided_over: the same rule on each console). Never over
        another task of that id."""
        t = COMAP_TASKS
        ins = self._insert(t).values(_task_row(task))
        new = ins.excluded
        stored_final, new_final = t.c.state.in_(final), new.state.in_(final)
        state_wins = or_(and_(new_final, or_(~stored_final, new.state_at < t.c.state_at)),
                         and_(~new_final, ~stored_final, t.c.state_at <= new.state_at))
        progress_wins = t.c.updated_at <= new.updated_at

        def newest(column: Any, wins: Any) -> Any:
            return case((wins, new[column.name]), else_=column)
        stmt = ins.on_conflict_do_update(
            index_elements=[t.c.task_id],
            set_={**{c.name: newest(c, state_wins) for c in (t.c.state, t.c.last_synch, t.c.state_at)},
                  **{c.name: newest(c, progress_wins) for c in (t.c.progress, t.c.quality, t.c.updated_at)}},
            where=(t.c.created_at == new.created_at) & (state_wins | progress_wins))

        def write(c: Connection) -> None:
            c.execute(stmt)
            self._notify(c, "task", id=task["task_id"])
        self._write(write)

    def new_comap_task(self, task: dict[str, Any], final: frozenset[str]) -> int | None:
        """Take a task id for `task` and store it, in one transaction on the locked counter row: ids go up from the
        last one any console took and wrap at 65534; an id whose task is not in a `final` state is skipped. None:
        every id is taken by an unfinished task. For a worker thread; Unavailable during an outage (the id could
        collide with one another console takes meanwhile)."""
        if self.unavailable_since is not None:
            raise self._unavailable_for_tasks()
        # one at a time in this console: SQLite has no FOR UPDATE (two assigns at once read one counter, and the
        # second deleted the first's task of that id and took it again)
        try:
            with self._taking_task_id, self.engine.begin() as c:
                start = c.execute(select(COMAP_TASK_IDS.c.next_task).where(COMAP_TASK_IDS.c.id == 1)
                                  .with_for_update()).scalar_one()
                busy = set(c.execute(select(COMAP_TASKS.c.task_id).where(COMAP_TASKS.c.state.not_in(final))).scalars())
                order = (((start - 1 + k) % TASK_IDS) + 1 for k in range(TASK_IDS))  # from start, wrapping
                tid: int | None = next((i for i in order if i not in busy), None)
                if tid is None:
                    return None
                c.execute(delete(COMAP_TASKS).where(COMAP_TASKS.c.task_id == tid))  # a finished task of that id
                c.execute(insert(COMAP_TASKS).values(_task_row({**task, "task_id": tid})))
                c.execute(update(COMAP_TASK_IDS).where(COMAP_TASK_IDS.c.id == 1).values(next_task=tid % TASK_IDS + 1))
                self._notify(c, "task", id=tid)
                return tid
        except (OperationalError, InterfaceError) as e:
            if self.db.path is not None:
                raise
            self._went_away(e)
            raise self._unavailable_for_tasks() from e

    def _unavailable_for_tasks(self) -> Unavailable:
        since = self._since()
        return Unavailable(f"no new CoMap task while the database {self.db.shown} cannot be reached (since {since}): "
                           "task ids are taken there so that no two stations send the same one; assign it when the "
                           "database is back (the tasks already assigned go on)")

    # ---- alarms -------------------------------------------------------------------------
    def add_alarm(self, alarm: dict[str, Any]) -> int:
        """A new alarm (keys: ALARM_COLUMNS); returns its id. The oldest alarms back to normal beyond ALARMS_KEPT go.
        During an outage the id is a temporary negative one (the alarm's in this console's memory); its held
        updates go to the row written for it."""
        row = {**{k: alarm.get(k) for k in ALARM_COLUMNS}, "console": self.station}
        temporary = next(self._temporary_ids)
        ids: list[int] = []

        def write(c: Connection) -> None:
            new_id: int = c.execute(insert(ALARMS).values(row).returning(ALARMS.c.id)).scalar_one()
            c.execute(delete(ALARMS).where(ALARMS.c.id <= new_id - ALARMS_KEPT, ALARMS.c.normal_at.is_not(None)))
            self._alarm_ids[temporary] = new_id
            ids.append(new_id)
        self._write(write)
        if ids:  # written now: no temporary id to map
            self._alarm_ids.pop(temporary, None)
            return ids[0]
        return temporary

    def update_alarm(self, alarm: dict[str, Any]) -> None:
        values = {k: alarm[k] for k in ("since", "cleared_at", "acked_at", "acked_by", "normal_at")}

        def write(c: Connection) -> None:
            c.execute(update(ALARMS).where(ALARMS.c.id == self._alarm_ids.get(alarm["id"], alarm["id"])).values(values))
            if alarm["acked_at"] is not None:  # the other stations' alarm of the same key is acknowledged too
                self._notify(c, "alarm-ack", key=alarm["key"], at=alarm["acked_at"], by=alarm["acked_by"])
        self._write(write)

    def open_alarms(self) -> list[dict[str, Any]]:
        """This console's alarms not back to normal, oldest first."""
        with self._reads() as c:
            q = select(*ALARMS.c).where(ALARMS.c.normal_at.is_(None)).order_by(ALARMS.c.id)
            if self.station is not None:
                q = q.where(ALARMS.c.console == self.station)
            return [dict(r) for r in c.execute(q).mappings()]

    def acked_elsewhere(self, since: dict[str, float]) -> dict[str, tuple[float, str | None]]:
        """Alarm key -> (when, by whom) another console station acknowledged its alarm of that key, at or after
        `since[key]` (this console's alarm of the key was raised then): what a reopened listener may have missed."""
        out: dict[str, tuple[float, str | None]] = {}
        if not since:
            return out
        q = select(ALARMS.c.key, ALARMS.c.acked_at, ALARMS.c.acked_by).where(
            ALARMS.c.key.in_(list(since)), ALARMS.c.acked_at.is_not(None),
            or_(ALARMS.c.console.is_(None), ALARMS.c.console != self.station)).order_by(ALARMS.c.acked_at)
        with self._reads() as c:
            for key, at, by in c.execute(q):
                if at >= since[key]:
                    out[key] = (at, by)
        return out

    # ---- shelves and planned silences (shared by the stations: storage/notify.py kinds "shelf" and "silence") -----
    def add_shelf(self, shelf: dict[str, Any]) -> None:
        """A new shelf (keys: AlarmShelfRecord's); the other stations hear it with the row."""
        self._add_shared(SHELVES, "shelf", shelf)

    def end_shelf(self, shelf_id: str, at: float, by: str | None, why: str) -> None:
        """End a shelf, unless it has ended already (another station, or its time, ended it first)."""
        self._end_shared(SHELVES, "shelf", shelf_id, at, by, why)

    def add_silence(self, silence: dict[str, Any]) -> None:
        """A new planned silence (keys: PlannedSilenceRecord's)."""
        self._add_shared(SILENCES, "silence", silence)

    def end_silence(self, silence_id: str, at: float, by: str | None, why: str) -> None:
        self._end_shared(SILENCES, "silence", silence_id, at, by, why)

    def shelves(self) -> list[dict[str, Any]]:
        """The shelves not ended, oldest first."""
        return self._open_rows(SHELVES, SHELVES.c.shelved_at)

    def silences(self) -> list[dict[str, Any]]:
        """The planned silences not ended, oldest first."""
        return self._open_rows(SILENCES, SILENCES.c.set_at)

    def _add_shared(self, t: Any, kind: str, values: dict[str, Any]) -> None:
        row = {c.name: values.get(c.name) for c in t.c}

        def write(c: Connection) -> None:
            c.execute(insert(t).values(row))
            self._notify(c, kind, row=row)
        self._write(write)

    def _end_shared(self, t: Any, kind: str, row_id: str, at: float, by: str | None, why: str) -> None:
        def write(c: Connection) -> None:
            ended = c.execute(update(t).where(t.c.id == row_id, t.c.ended_at.is_(None))
                              .values(ended_at=at, ended_by=by, end_reason=why)).rowcount
            if ended:
                self._notify(c, kind, row={"id": row_id, "ended_at": at, "ended_by": by, "end_reason": why})
        self._write(write)

    def _open_rows(self, t: Any, order: Any) -> list[dict[str, Any]]:
        with self._reads() as c:
            return [dict(r) for r in c.execute(select(*t.c).where(t.c.ended_at.is_(None)).order_by(order)).mappings()]

    def clear_alarms(self) -> None:
        """Forget every alarm (a replay rebuilding its state)."""
        with self.engine.begin() as c:
            c.execute(delete(ALARMS))
            c.execute(delete(SHELVES))
            c.execute(delete(SILENCES))

    def close(self) -> None:
        if isinstance(self._lock, Connection):
            self._lock.close()
        elif isinstance(self._lock, int):
            with contextlib.suppress(FileNotFoundError):  # removed while held: no other console can hold it now
                self.lock_path().unlink()
            os.close(self._lock)
        self._lock = None
        self.engine.dispose()


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


def _task_row(task: dict[str, Any]) -> dict[str, Any]:
    return {**{k: task[k] for k in (col.name for col in COMAP_TASKS.c)}, "vehicle": str(task["vehicle"]),
            "point": json.dumps(task["point"]) if task["point"] is not None else None}


def _with_transitions(c: Connection, rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    ids = [r["session_id"] for r in rows]
    trans: dict[str, list[dict[str, Any]]] = {}
    table = TRANSITIONS
    for chunk in (ids[i:i + 500] for i in range(0, len(ids), 500)):
        q = select(*table.c).where(table.c.session_id.in_(chunk)).order_by(table.c.session_id, table.c.seq)
        for t in c.execute(q).mappings():
            trans.setdefault(t["session_id"], []).append(dict(t))
    return [{**r, "command": json.loads(r["command"]), "transitions": trans.get(r["session_id"], [])} for r in rows]


