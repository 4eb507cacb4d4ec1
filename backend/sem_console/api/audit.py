"""The audit trail of command requests: accepted and refused, with time, client and reason (SQLite)."""

from __future__ import annotations

import logging
import sqlite3
import time
from typing import Any

from starlette.datastructures import Headers
from starlette.types import Scope

log = logging.getLogger("sem-console.audit")
CLIP = 200


def clip(value: str | None, limit: int = CLIP) -> str:
    """repr() of a string a client sent, cut to `limit` characters: one log line whatever it holds
    (a percent-decoded path can hold a newline)."""
    r = repr(value)
    return r if len(r) <= limit else r[: limit - 3] + "..."


def client_of(scope: Scope) -> str | None:
    client = scope.get("client")
    return str(client[0]) if client else None


def record(scope: Scope, outcome: str, status: int, reason: str, operator: str | None = None,
           session_id: str | None = None) -> None:
    """Add one entry for the request in `scope` (a command route: POST or DELETE) to the history database."""
    console = getattr(scope["app"].state, "console", None)
    if console is None:
        return
    entry: dict[str, Any] = {
        "at": time.time(), "outcome": outcome, "status": status, "method": scope.get("method", "GET"),
        "path": scope["path"], "client": client_of(scope), "origin": Headers(scope=scope).get("origin"),
        "operator": operator, "session_id": session_id, "reason": reason,
    }
    try:
        console.store.add_audit(entry)
    except sqlite3.Error as e:  # the store closes during shutdown
        log.warning("audit entry not recorded (%s): %s", e, entry)


def entry_json(row: dict[str, Any]) -> dict[str, Any]:
    return {"id": row["id"], "at": row["at"], "outcome": row["outcome"], "status": row["status"], "method": row["method"],
            "path": row["path"], "client": row["client"], "origin": row["origin"], "operator": row["operator"],
            "sessionId": row["session_id"], "reason": row["reason"]}
