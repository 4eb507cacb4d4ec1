"""Command history and audit in SQLite; also keeps the console's own source GUID and each vehicle's
link configuration across restarts."""

from __future__ import annotations

import json
import sqlite3
import uuid
from pathlib import Path
from typing import Any

SCHEMA = """
CREATE TABLE IF NOT EXISTS meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS commands (
    session_id TEXT PRIMARY KEY, service TEXT NOT NULL, provider_id TEXT NOT NULL, state TEXT,
    operator TEXT, created_at REAL NOT NULL, command TEXT NOT NULL, unanswered INTEGER NOT NULL DEFAULT 0,
    cancel_requested INTEGER NOT NULL DEFAULT 0, canceled_by TEXT, cleaned_up INTEGER NOT NULL DEFAULT 0,
    acked_at REAL
);
CREATE TABLE IF NOT EXISTS transitions (
    session_id TEXT NOT NULL REFERENCES commands(session_id), seq INTEGER NOT NULL, status TEXT NOT NULL,
    reason TEXT NOT NULL, log_message TEXT NOT NULL, violation TEXT, provider_time REAL, received_at REAL NOT NULL,
    PRIMARY KEY (session_id, seq)
);
CREATE TABLE IF NOT EXISTS audit (
    id INTEGER PRIMARY KEY AUTOINCREMENT, at REAL NOT NULL, outcome TEXT NOT NULL, status INTEGER NOT NULL,
    method TEXT NOT NULL, path TEXT NOT NULL, client TEXT, origin TEXT, operator TEXT, session_id TEXT, reason TEXT NOT NULL
);
"""
CREATE_LINK_CONFIG = "CREATE TABLE IF NOT EXISTS link_config (provider_id TEXT PRIMARY KEY, config TEXT NOT NULL)"
# console/alarms.py: normal_at is set when an alarm is back to normal (out of the active set)
CREATE_ALARMS = """
CREATE TABLE IF NOT EXISTS alarms (
    id INTEGER PRIMARY KEY AUTOINCREMENT, key TEXT NOT NULL, kind TEXT NOT NULL, severity TEXT NOT NULL, provider_id TEXT,
    vehicle TEXT, session_id TEXT, text TEXT NOT NULL, since REAL NOT NULL, cleared_at REAL, acked_at REAL, acked_by TEXT,
    normal_at REAL
);
CREATE INDEX IF NOT EXISTS alarms_open ON alarms (normal_at);
"""
ALARM_COLUMNS = ("key", "kind", "severity", "provider_id", "vehicle", "session_id", "text", "since", "cleared_at", "acked_at",
                 "acked_by", "normal_at")
ALARMS_KEPT = 100_000  # alarms back to normal kept in the database
AUDIT_COLUMNS = ("at", "outcome", "status", "method", "path", "client", "origin", "operator", "session_id", "reason")


class Database:
    def __init__(self, path: Path, audit_max_rows: int = 100_000) -> None:
        self.audit_max_rows = audit_max_rows
        path.parent.mkdir(parents=True, exist_ok=True)
        self.path = path
        self.db = sqlite3.connect(path, check_same_thread=False, isolation_level=None)
        self.db.row_factory = sqlite3.Row
        self.db.execute("PRAGMA journal_mode=WAL")
        self.db.execute("PRAGMA synchronous=NORMAL")
        self.db.executescript(SCHEMA)
        self.db.execute(CREATE_LINK_CONFIG)
        self.db.executescript(CREATE_ALARMS)
        self._migrate()

    def _migrate(self) -> None:
        """Add columns that a database from an earlier version lacks."""
        have = {r["name"] for r in self.db.execute("PRAGMA table_info(commands)")}
        for column, decl in (("canceled_by", "TEXT"), ("acked_at", "REAL")):
            if column not in have:
                self.db.execute(f"ALTER TABLE commands ADD COLUMN {column} {decl}")

    def console_guid(self) -> uuid.UUID:
        row = self.db.execute("SELECT value FROM meta WHERE key='source'").fetchone()
        if row:
            return uuid.UUID(row["value"])
        guid = uuid.uuid4()
        self.db.execute("INSERT INTO meta VALUES ('source', ?)", (str(guid),))
        return guid

    def add_command(self, rec: dict[str, Any], command: dict[str, Any]) -> None:
        self.db.execute(
            "INSERT INTO commands (session_id, service, provider_id, state, operator, created_at, command) VALUES "
            "(?,?,?,?,?,?,?)",
            (
                rec["sessionId"],
                rec["service"],
                rec["providerId"],
                rec["state"],
                rec["operator"],
                rec["createdAt"],
                json.dumps(command),
            ),
        )

    def add_transition(self, session_id: str, seq: int, t: dict[str, Any]) -> None:
        self.db.execute(
            "INSERT OR IGNORE INTO transitions VALUES (?,?,?,?,?,?,?,?)",
            (session_id, seq, t["status"], t["reason"], t["logMessage"], t["violation"], t["providerTime"], t["receivedAt"]))

    def set_flag(self, session_id: str, flag: str, value: bool = True) -> None:
        assert flag in ("unanswered", "cleaned_up")
        self.db.execute(f"UPDATE commands SET {flag}=? WHERE session_id=?", (int(value), session_id))

    def set_acked(self, session_id: str, at: float) -> None:
        self.db.execute("UPDATE commands SET acked_at=? WHERE session_id=?", (at, session_id))

    def set_canceled(self, session_id: str, operator: str | None) -> None:
        self.db.execute("UPDATE commands SET cancel_requested=1, canceled_by=? WHERE session_id=?", (operator, session_id))

    def commands(self, limit: int | None = None, offset: int = 0, unfinished: bool = False,
                 session_id: str | None = None, provider_id: str | None = None) -> list[dict[str, Any]]:
        """Commands newest first with their transitions: `limit` of them from `offset` (to `provider_id`
        when given), plus every command not yet cleaned up when `unfinished`, or the one `session_id`."""
        if session_id is not None:
            rows = self.db.execute("SELECT * FROM commands WHERE session_id=?", (session_id,)).fetchall()
        else:
            to = "WHERE provider_id=?" if provider_id is not None else ""
            page = f"SELECT session_id FROM commands {to} ORDER BY created_at DESC LIMIT ? OFFSET ?"
            params = (*([provider_id] if provider_id is not None else []), -1 if limit is None else limit, offset)
            rows = self.db.execute(
                f"SELECT * FROM commands WHERE session_id IN ({page}) {'OR cleaned_up=0' if unfinished else ''} "
                "ORDER BY created_at DESC", params).fetchall()
        return _with_transitions(self.db, rows)

    def export_commands(self, provider_id: str | None, since: float | None, until: float | None) -> list[dict[str, Any]]:
        """Commands created in [since, until] (to `provider_id` when given), oldest first, with their
        transitions; on a connection of its own, for a worker thread."""
        db = sqlite3.connect(self.path, timeout=10)
        db.row_factory = sqlite3.Row
        try:
            rows = db.execute(
                "SELECT * FROM commands WHERE (?1 IS NULL OR provider_id=?1) AND (?2 IS NULL OR created_at>=?2) "
                "AND (?3 IS NULL OR created_at<=?3) ORDER BY created_at", (provider_id, since, until)).fetchall()
            return _with_transitions(db, rows)
        finally:
            db.close()

    def clear_commands(self) -> None:
        """Forget every command and transition (a replay rebuilding its state); the audit trail stays."""
        self.db.execute("DELETE FROM transitions")
        self.db.execute("DELETE FROM commands")

    def add_audit(self, entry: dict[str, Any]) -> None:
        """One entry (keys: AUDIT_COLUMNS); the table keeps the newest audit_max_rows. Ids count up without
        gaps (AUTOINCREMENT, never deleted but from the old end), so the prune is one range delete on the key."""
        cur = self.db.execute(f"INSERT INTO audit ({','.join(AUDIT_COLUMNS)}) VALUES ({','.join('?' * len(AUDIT_COLUMNS))})",
                              tuple(entry.get(k) for k in AUDIT_COLUMNS))
        assert cur.lastrowid is not None
        self.db.execute("DELETE FROM audit WHERE id <= ?", (cur.lastrowid - self.audit_max_rows,))

    def audit(self, limit: int, offset: int) -> list[dict[str, Any]]:
        """Newest first."""
        return [dict(r) for r in self.db.execute("SELECT * FROM audit ORDER BY id DESC LIMIT ? OFFSET ?", (limit, offset))]

    def link_configs(self) -> dict[str, Any]:
        """provider GUID string -> the link configuration an operator set for it (as stored: the caller validates)."""
        out: dict[str, Any] = {}
        for r in self.db.execute("SELECT * FROM link_config"):
            try:
                out[r["provider_id"]] = json.loads(r["config"])
            except ValueError:  # not JSON: the caller's validation refuses it
                out[r["provider_id"]] = r["config"]
        return out

    def set_link_config(self, provider_id: str, config: dict[str, Any]) -> None:
        self.db.execute("INSERT OR REPLACE INTO link_config VALUES (?, ?)", (provider_id, json.dumps(config)))

    def add_alarm(self, alarm: dict[str, Any]) -> int:
        """A new alarm (keys: ALARM_COLUMNS); returns its id. The oldest alarms back to normal beyond ALARMS_KEPT go."""
        cur = self.db.execute(f"INSERT INTO alarms ({','.join(ALARM_COLUMNS)}) VALUES ({','.join('?' * len(ALARM_COLUMNS))})",
                              tuple(alarm.get(k) for k in ALARM_COLUMNS))
        assert cur.lastrowid is not None
        self.db.execute("DELETE FROM alarms WHERE id <= ? AND normal_at IS NOT NULL", (cur.lastrowid - ALARMS_KEPT,))
        return cur.lastrowid

    def update_alarm(self, alarm: dict[str, Any]) -> None:
        self.db.execute(
            "UPDATE alarms SET since=?, cleared_at=?, acked_at=?, acked_by=?, normal_at=? WHERE id=?",
            (alarm["since"], alarm["cleared_at"], alarm["acked_at"], alarm["acked_by"], alarm["normal_at"], alarm["id"]),
        )

    def open_alarms(self) -> list[dict[str, Any]]:
        """The alarms not back to normal, oldest first."""
        return [dict(r) for r in self.db.execute("SELECT * FROM alarms WHERE normal_at IS NULL ORDER BY id")]

    def clear_alarms(self) -> None:
        """Forget every alarm (a replay rebuilding its state)."""
        self.db.execute("DELETE FROM alarms")

    def close(self) -> None:
        self.db.close()


def _with_transitions(db: sqlite3.Connection, rows: list[sqlite3.Row]) -> list[dict[str, Any]]:
    ids = [r["session_id"] for r in rows]
    trans: dict[str, list[dict[str, Any]]] = {}
    for chunk in (ids[i:i + 500] for i in range(0, len(ids), 500)):
        marks = ",".join("?" * len(chunk))
        for t in db.execute(f"SELECT * FROM transitions WHERE session_id IN ({marks}) ORDER BY session_id, seq", chunk):
            trans.setdefault(t["session_id"], []).append(dict(t))
    return [{**dict(r), "command": json.loads(r["command"]), "transitions": trans.get(r["session_id"], [])} for r in rows]
