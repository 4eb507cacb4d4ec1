"""The console's database, one facade over the storage room: the engine (engine.py: open, migrate, back up), the
outage write-behind (outage.py), the console's name lock (locks.py), and one module per aggregate (commands, alarms
with their shelves and silences, comap, names, audit, links), each returning typed rows.

Reads are synchronous: a route on the event loop reads in a worker thread (asyncio.to_thread), and sees every write
this console asked before it. Writes return at once: each runs in order on the write-behind's one writer thread, held
without a connect attempt during an outage; a write whose result the caller uses returns a Future of it."""

from __future__ import annotations

import sqlite3
import uuid
from collections.abc import Callable
from concurrent.futures import Future
from pathlib import Path
from typing import Any

from sqlalchemy.exc import SQLAlchemyError

from sem_console.storage.alarms import Alarms
from sem_console.storage.audit import Audit
from sem_console.storage.comap import Comap, TaskRow, WorldRow
from sem_console.storage.commands import CommandRow, Commands
from sem_console.storage.context import Context
from sem_console.storage.engine import StorageError, migrate, open_engine, problem
from sem_console.storage.links import Links
from sem_console.storage.locks import NameLock, VehicleWriters
from sem_console.storage.models import AlarmRecord, AlarmShelfRecord, AuditRecord, PlannedSilenceRecord
from sem_console.storage.names import Names
from sem_console.storage.notify import Listener
from sem_console.storage.outage import Unavailable, WriteBehind
from sem_console.storage.url import DatabaseUrl, sqlite_file

__all__ = ["Database", "StorageError", "Unavailable", "VehicleWriters"]


class Database:
    def __init__(self, db: DatabaseUrl | Path, audit_max_rows: int = 100_000) -> None:
        """Open (and upgrade) the database (a Path: a SQLite file); StorageError when it cannot be used."""
        self.db = db = sqlite_file(db) if isinstance(db, Path) else db
        self.engine = open_engine(db)
        try:
            migrate(self.engine, db)
        except StorageError:
            self.engine.dispose()
            raise
        except (SQLAlchemyError, sqlite3.Error, OSError) as e:
            self.engine.dispose()
            raise StorageError(problem(db, e)) from e
        self.writes = WriteBehind(db, self.engine)
        self.ctx = Context(db, self.engine, self.writes)
        self.name_lock = NameLock(self.writes)
        self.names, self.links, self.audit_trail = Names(self.ctx), Links(self.ctx), Audit(self.ctx, audit_max_rows)
        self.command_rows, self.alarm_rows, self.comap = Commands(self.ctx), Alarms(self.ctx), Comap(self.ctx)

    # ---- identity, and the outage -----------------------------------------------------------
    def claim(self, name: str, hold: bool = True) -> uuid.UUID:
        """This console's source GUID, by its name (names.Names.identity). The name is held while the console runs: a
        second console of the same name on this database is refused (StorageError). `hold=False`: the identity only
        (tests that restart a console's parts in one process)."""
        if hold:
            self.name_lock.hold(name)
        self.ctx.station = name
        return self.names.identity(name)

    @property
    def station(self) -> str | None:
        """The console name claimed: sent with each notification, so a console skips its own."""
        return self.ctx.station

    def lock_path(self) -> Path:
        return self.name_lock.path()

    @property
    def unavailable_since(self) -> float | None:
        return self.writes.unavailable_since

    @property
    def held(self) -> int:
        return self.writes.held

    @property
    def dropped(self) -> int:
        return self.writes.dropped

    @property
    def writes_asked(self) -> int:
        """Writes asked of this console so far: a read in another thread while it changes may be older than one."""
        return self.writes.asked

    def unreachable(self, e: Exception) -> Unavailable:
        return self.writes.unreachable(e)

    def maintain(self) -> bool:
        """For a worker thread, every few seconds on PostgreSQL (the console's tick): during an outage, find the
        server back and write what was held; re-take this console's name when the server restarted (its session
        lock went with the old connection). True when the database can be used."""
        return self.writes.reachable() and self.writes.write_held() and self.name_lock.keep()

    def write_held(self) -> bool:
        return self.writes.write_held()

    def flush(self, timeout: float | None = None) -> bool:
        """Wait until the writes asked so far are written, or held in an outage (for a worker thread, or a test)."""
        return self.writes.flush(timeout)

    def listen(self, on_message: Callable[[dict[str, Any]], object]) -> Listener | None:
        """A started Listener of the other consoles' notifications (None on SQLite: one console per file)."""
        if self.db.path is not None:
            return None
        listener = Listener(self.db.url, on_message)
        listener.start()
        return listener

    def consoles(self) -> dict[str, uuid.UUID]:
        return self.names.consoles()

    # ---- commands -----------------------------------------------------------------------
    def add_command(self, rec: dict[str, Any], command_: dict[str, Any], console: str | None = None) -> None:
        self.command_rows.add(rec, command_, console)

    def add_transition(self, session_id: str, seq: int, t: dict[str, Any]) -> None:
        self.command_rows.add_transition(session_id, seq, t)

    def set_flag(self, session_id: str, flag: str, value: bool = True) -> None:
        assert flag in ("unanswered", "cleaned_up")
        self.command_rows.update(session_id, **{flag: value})

    def set_acked(self, session_id: str, at: float) -> None:
        self.command_rows.update(session_id, acked_at=at)

    def set_canceled(
        self, session_id: str, operator: str | None, station: str | None, at: float, cause: str | None = "operator"
    ) -> Future[CommandRow | None]:
        """The cancel of a command, written behind unless one is stored already (`CommandRows.cancel`); the future is
        done once it is stored and the other stations told, or refused (the command as stored)."""
        return self.command_rows.cancel(session_id, operator, station, at, cause)

    def set_canceller(
        self, session_id: str, operator: str | None, station: str | None, at: float | None, cause: str | None
    ) -> None:
        """Who cancelled a command, as a recording says the console showed it (a replay: the cancel stored first)."""
        self.command_rows.update(session_id, canceled_by=operator, canceled_on=station, canceled_at=at, cancel_cause=cause)

    def set_closed_unheard(self, session_id: str, why: str, at: float) -> Future[CommandRow | None]:
        return self.command_rows.close_unheard(session_id, why, at)

    def commands(
        self,
        limit: int | None = None,
        offset: int = 0,
        unfinished: bool = False,
        session_id: str | None = None,
        provider_id: str | None = None,
        console: str | None = None,
    ) -> list[CommandRow]:
        return self.command_rows.read(limit, offset, unfinished, session_id, provider_id, console)

    def export_commands(self, provider_id: str | None, since: float | None, until: float | None) -> list[CommandRow]:
        return self.command_rows.export(provider_id, since, until)

    def clear_commands(self) -> None:
        self.command_rows.clear()

    # ---- audit, link configurations, vehicle names -------------------------------------------
    def add_audit(self, entry: dict[str, Any]) -> None:
        self.audit_trail.add(entry)

    def audit(self, limit: int, offset: int) -> list[AuditRecord]:
        return self.audit_trail.newest(limit, offset)

    def link_configs(self) -> dict[str, Any]:
        return self.links.link_configs()

    def set_link_config(self, provider_id: str, config: dict[str, Any]) -> None:
        self.links.set_link_config(provider_id, config)

    def vehicle_names(self) -> dict[str, str]:
        return self.names.vehicle_names()

    def set_vehicle_name(self, provider_id: str, name: str | None, by: str | None) -> None:
        self.names.set_vehicle_name(provider_id, name, by)

    # ---- CoMap ----------------------------------------------------------------------------
    def comap_world(self) -> WorldRow | None:
        return self.comap.world()

    def comap_tasks(self, task_id: int | None = None) -> list[TaskRow]:
        return self.comap.tasks(task_id)

    def set_comap_world(self, world: dict[str, Any]) -> None:
        self.comap.set_world(world)

    def set_comap_task(self, task: dict[str, Any], final: frozenset[str]) -> None:
        self.comap.set_task(task, final)

    def new_comap_task(self, task: dict[str, Any], final: frozenset[str]) -> int | None:
        return self.comap.new_task(task, final)

    # ---- alarms, shelves and planned silences --------------------------------------------------
    def add_alarm(self, alarm: dict[str, Any]) -> int:
        return self.alarm_rows.add(alarm)

    def update_alarm(self, alarm: dict[str, Any]) -> None:
        self.alarm_rows.update(alarm)

    def open_alarms(self) -> list[AlarmRecord]:
        return self.alarm_rows.open()

    def acked_elsewhere(self, since: dict[str, float]) -> dict[str, tuple[float, str | None]]:
        return self.alarm_rows.acked_elsewhere(since)

    def add_shelf(self, shelf: dict[str, Any]) -> None:
        self.alarm_rows.add_shelf(shelf)

    def end_shelf(self, shelf_id: str, at: float, by: str | None, why: str) -> None:
        self.alarm_rows.end_shelf(shelf_id, at, by, why)

    def add_silence(self, silence: dict[str, Any]) -> None:
        self.alarm_rows.add_silence(silence)

    def end_silence(self, silence_id: str, at: float, by: str | None, why: str) -> None:
        self.alarm_rows.end_silence(silence_id, at, by, why)

    def shelves(self) -> list[AlarmShelfRecord]:
        return self.alarm_rows.shelves()

    def silences(self) -> list[PlannedSilenceRecord]:
        return self.alarm_rows.silences()

    def clear_alarms(self) -> None:
        self.alarm_rows.clear()

    def close(self) -> None:
        """Write what is asked and held, or say what is lost (WriteBehind.close: its writer thread ends); let the
        console's name go."""
        self.writes.close()
        self.name_lock.close()
        self.engine.dispose()
