"""The audit trail (SQLite, GET /api/audit) and the log lines of refused requests, both bounded.

Recorded in the audit:
- every command request (a POST, PUT or DELETE of a command route: commands, recording control, a
  vehicle's link configuration), accepted or refused, whatever
  refused it: a foreign origin or host (403), not JSON (415), no or a wrong token (401), the
  slow-down (429), a bad body (422), an unknown vehicle or command (404), a finished command (409);
- a wrong token (401) or the slow-down (429) on any route, the sign-in check GET /api/operator and
  /ws included.

Other refusals (a POST to a path that is no command route, a foreign Host on a read, a read
without a token) are only logged: at INFO, /ws at WARNING (like every recorded one).

Bounds, since a refusal costs its sender nothing: at most `per_minute` refusals of one client
address are logged and recorded per minute; the next one leaves one line and one "rate-limited"
row saying so, the rest of that minute are only counted (the count is logged when the minute is
over). Client-sent text (path, origin, reasons quoting them) is logged as repr() and cut to about
200 characters. The table keeps the newest `Settings.audit_max_rows` rows (Database.add_audit).
"""

from __future__ import annotations

import logging
import sqlite3
import time
from collections import OrderedDict
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from starlette.datastructures import Headers
from starlette.routing import BaseRoute, Match
from starlette.types import Scope

from sem_console.storage.models import AuditRecord

log = logging.getLogger("sem-console.audit")
CLIP = 200
WINDOW = 60.0
MAX_CLIENTS = 10_000


def clip(value: str | None, limit: int = CLIP) -> str:
    """repr() of a string a client sent, cut to `limit` characters: one log line whatever it holds
    (a percent-decoded path can hold a newline)."""
    r = repr(value)
    return r if len(r) <= limit else r[: limit - 3] + "..."


def client_of(scope: Scope) -> str | None:
    client = scope.get("client")
    return str(client[0]) if client else None


def method_of(scope: Scope) -> str:
    return str(scope.get("method", "GET")) if scope["type"] == "http" else "WEBSOCKET"


@dataclass
class _Window:
    start: float
    count: int = 0


class Auditor:
    """Decides what a refusal leaves behind (see the module), and writes the audit rows."""

    def __init__(self, command_routes: Sequence[BaseRoute], per_minute: int) -> None:
        self.routes = list(command_routes)
        self.per_minute = per_minute
        self.windows: OrderedDict[str, _Window] = OrderedDict()

    def is_command(self, scope: Scope) -> bool:
        """A request to a command route (the state-changing API routes), matched by method and path."""
        return scope["type"] == "http" and any(r.matches(scope)[0] is Match.FULL for r in self.routes)

    def accepted(self, scope: Scope, status: int, operator: str | None, session_id: str | None, reason: str = "accepted") -> None:
        _write(scope, "accepted", status, reason, operator, session_id)

    def refused(
        self,
        scope: Scope,
        status: int,
        reason: str,
        *,
        audit: bool = False,
        operator: str | None = None,
        now: float | None = None,
    ) -> None:
        """Log a refused request and, when `audit` or it is a command request, record it; within the limits."""
        audit = audit or self.is_command(scope)
        now = time.monotonic() if now is None else now
        client = client_of(scope) or "?"
        w = self.windows.pop(client, None)
        if w is None or now - w.start >= WINDOW:
            if w is not None and w.count > self.per_minute + 1:
                log.warning(
                    "%d more refusals from %s in a minute were neither logged nor recorded (rate limit)",
                    w.count - self.per_minute - 1,
                    client,
                )
            w = _Window(now)
        w.count += 1
        self.windows[client] = w  # most recent last
        while len(self.windows) > MAX_CLIENTS:
            self.windows.popitem(last=False)
        if w.count > self.per_minute + 1:
            return
        line = (
            f"refused {method_of(scope)} {clip(scope['path'])} from {client} (origin "
            f"{clip(Headers(scope=scope).get('origin'))}): {status} {clip(reason, 2 * CLIP)}"
        )
        if w.count == self.per_minute + 1:
            note = (
                f"more than {self.per_minute} refusals from {client} within a minute: "
                f"the rest of this minute's are neither logged nor recorded"
            )
            log.warning("%s; %s", line, note)
            _write(scope, "rate-limited", status, f"{reason}; {note}", operator)
            return
        log.log(logging.WARNING if audit or scope["type"] == "websocket" else logging.INFO, "%s", line)
        if audit:
            _write(scope, "refused", status, reason, operator)


def auditor(scope: Scope) -> Auditor:
    auditor: Auditor = scope["app"].state.auditor  # set by main.create_app
    return auditor


def _write(
    scope: Scope, outcome: str, status: int, reason: str, operator: str | None = None, session_id: str | None = None
) -> None:
    """Add one entry for the request in `scope` to the history database."""
    console = getattr(scope["app"].state, "console", None)
    if console is None:
        return
    origin = Headers(scope=scope).get("origin")
    entry: dict[str, Any] = {
        "at": time.time(),
        "outcome": outcome,
        "status": status,
        "method": method_of(scope),
        "path": scope["path"][:CLIP],
        "client": client_of(scope),
        "origin": origin[:CLIP] if origin else origin,
        "operator": operator,
        "session_id": session_id,
        "reason": reason[: 3 * CLIP],
    }
    try:
        console.add_audit(entry)
    except sqlite3.Error as e:  # the store closes during shutdown
        log.warning("audit entry not recorded (%s): %s", e, entry)


def entry_json(row: AuditRecord) -> dict[str, Any]:
    return {
        "id": row.id,
        "at": row.at,
        "outcome": row.outcome,
        "status": row.status,
        "method": row.method,
        "path": row.path,
        "client": row.client,
        "origin": row.origin,
        "operator": row.operator,
        "sessionId": row.session_id,
        "reason": row.reason,
    }
