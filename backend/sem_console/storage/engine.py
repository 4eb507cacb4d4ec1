"""The console's database engine on SQLAlchemy 2.0 (sync), SQLite or PostgreSQL: opened, its schema upgraded by
Alembic (migrations/) when the console starts, a SQLite file copied beside itself first; and the one line an
operator reads when it cannot be used."""

from __future__ import annotations

import logging
import sqlite3
import time
from pathlib import Path
from typing import Any

from alembic import command
from alembic.config import Config
from alembic.runtime.migration import MigrationContext
from alembic.script import ScriptDirectory
from sqlalchemy import Connection, Engine, create_engine, event, func, inspect, select

from sem_console.storage.notify import PG_CONNECT_ARGS
from sem_console.storage.url import DatabaseUrl

log = logging.getLogger("sem-console.storage")
logging.getLogger("alembic").setLevel(logging.WARNING)  # its INFO lines name plugins and contexts: our own say what changed
MIGRATIONS = Path(__file__).parent / "migrations"
MIGRATION_LOCK = 0x53454D_0001  # pg advisory lock key: one console upgrades the schema at a time


class StorageError(Exception):
    """The console cannot use its database: the message is the one line the operator reads (problem and fix)."""


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


def option(db: DatabaseUrl) -> str:
    """The option that named the database, as an error names it."""
    return f"--database-url {db.shown}" if db.path is None else f"--db {db.path}"


def problem(db: DatabaseUrl, e: Exception) -> str:
    """One line for an error reaching or reading the database: what is wrong and what to do."""
    where = option(db)
    message = str(getattr(e, "orig", None) or e).strip().splitlines()[0] if str(e).strip() else type(e).__name__
    lower = message.lower()
    if db.path is not None:
        return f"{where}: {message}: move it aside or pass another --db"
    if "password authentication failed" in lower or "no password supplied" in lower:
        return f"{where}: {message}: fix the user name or password in --database-url"
    if "does not exist" in lower:
        return f"{where}: {message}: create it (createdb, or CREATE DATABASE) or fix --database-url"
    if (
        "connection refused" in lower
        or "timeout" in lower
        or "could not translate host name" in lower
        or "no route to host" in lower
    ):
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
                raise StorageError(
                    f"{option(db)}: its schema is at revision {current}, newer than this sem-console's {head}: "
                    "run the sem-console release that wrote it (the consoles of one database run one release)"
                )
            tables = set(inspect(c).get_table_names())
            c.commit()
            if db.path is not None and tables - {"alembic_version"}:
                backup = backup_sqlite(db.path, current)
                log.warning(
                    "copied %s to %s before upgrading its schema (from %s to %s)",
                    db.path,
                    backup,
                    current or "the first release's",
                    head,
                )
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
