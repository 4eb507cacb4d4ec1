"""Commands: each command a console station issued, its flags, and the statuses the vehicle sent (transitions),
shared by the consoles of one database (notification kind "command")."""

from __future__ import annotations

import json
from concurrent.futures import Future
from typing import Any, TypedDict, cast

from sqlalchemy import Connection, Select, delete, insert, or_, select, update

from sem_console.storage.context import Context
from sem_console.storage.models import CommandRecord, TransitionRecord, table

COMMANDS, TRANSITIONS = table(CommandRecord), table(TransitionRecord)


class TransitionRow(TypedDict):
    """A row of TransitionRecord."""

    session_id: str
    seq: int
    status: str
    reason: str
    log_message: str
    violation: str | None
    provider_time: float | None
    received_at: float


class CommandRow(TypedDict):
    """A row of CommandRecord, its `command` JSON parsed, with its transitions in order (a join)."""

    session_id: str
    service: str
    provider_id: str
    state: str | None
    operator: str | None
    created_at: float
    command: dict[str, Any]
    unanswered: bool
    cancel_requested: bool
    canceled_by: str | None
    cleaned_up: bool
    acked_at: float | None
    console: str | None
    canceled_on: str | None
    canceled_at: float | None
    closed_unheard: str | None
    closed_at: float | None
    cancel_cause: str | None
    transitions: list[TransitionRow]


class Commands:
    def __init__(self, ctx: Context) -> None:
        self.ctx = ctx

    def add(self, rec: dict[str, Any], command_: dict[str, Any], console: str | None = None) -> None:
        row = dict(
            session_id=rec["sessionId"],
            service=rec["service"],
            provider_id=rec["providerId"],
            state=rec["state"],
            operator=rec["operator"],
            created_at=rec["createdAt"],
            command=json.dumps(command_),
            unanswered=False,
            cancel_requested=False,
            cleaned_up=False,
            console=console,
        )

        def write(c: Connection) -> None:
            c.execute(insert(COMMANDS).values(row))
            self.ctx.notify(c, "command", session=rec["sessionId"])

        self.ctx.writes.write(write)

    def add_transition(self, session_id: str, seq: int, t: dict[str, Any]) -> None:
        stmt = (
            self.ctx.insert(TRANSITIONS)
            .values(
                session_id=session_id,
                seq=seq,
                status=t["status"],
                reason=t["reason"],
                log_message=t["logMessage"],
                violation=t["violation"],
                provider_time=t["providerTime"],
                received_at=t["receivedAt"],
            )
            .on_conflict_do_nothing()
        )

        def write(c: Connection) -> None:
            c.execute(stmt)
            # the vehicle answered after all: what it says stands, whatever station ended the command as never heard
            c.execute(
                update(COMMANDS)
                .where(COMMANDS.c.session_id == session_id, COMMANDS.c.closed_unheard.is_not(None))
                .values(closed_unheard=None, closed_at=None, cleaned_up=False)
            )
            self.ctx.notify(c, "command", session=session_id)

        self.ctx.writes.write(write)

    def update(self, session_id: str, **values: Any) -> Future[None]:
        """Set columns of a command (its flags, its acknowledgement, its cancel); the other stations are told the
        columns with the command (`changed`), so that they apply a cancel at once, before they read the row. The
        future is done once written (and the others told)."""

        def write(c: Connection) -> None:
            c.execute(update(COMMANDS).where(COMMANDS.c.session_id == session_id).values(**values))
            self.ctx.notify(c, "command", session=session_id, changed=values)

        return self.ctx.writes.write(write)

    def cancel(
        self, session_id: str, operator: str | None, station: str | None, at: float, cause: str | None
    ) -> Future[CommandRow | None]:
        """The cancel of a command, unless one is stored already: the first cancel stored stands (two operators, or an
        operator and another station's stop, cancelling at once), and the other stations are told the columns only when
        this one is stored, so that they apply it at once, before they read the row. The future, once written: None
        when stored; the command as stored when refused (the caller shows who cancelled it first)."""
        values = {
            "cancel_requested": True,
            "canceled_by": operator,
            "canceled_on": station,
            "canceled_at": at,
            "cancel_cause": cause,
        }

        def write(c: Connection) -> CommandRow | None:
            done = c.execute(
                update(COMMANDS)
                .where(COMMANDS.c.session_id == session_id, COMMANDS.c.cancel_requested.isnot(True))
                .values(**values)
            )
            if done.rowcount > 0:
                self.ctx.notify(c, "command", session=session_id, changed=values)
                return None
            stored = _rows(c, select(*COMMANDS.c).where(COMMANDS.c.session_id == session_id))
            return stored[0] if stored else None

        return self.ctx.writes.write(write)

    def close_unheard(self, session_id: str, why: str, at: float) -> Future[CommandRow | None]:
        """A cancelled command the vehicle never answered, ended by the console (`why`): not once a status of it is
        stored (another station heard the vehicle answer; `add_transition` withdraws an ending stored before), nor once
        another station ended it (every station shows the one stored ending). The future, once written: None when
        stored; the command as stored when refused (the caller shows what is stored)."""
        answered = select(TRANSITIONS.c.seq).where(TRANSITIONS.c.session_id == session_id).exists()

        def write(c: Connection) -> CommandRow | None:
            done = c.execute(
                update(COMMANDS)
                .where(COMMANDS.c.session_id == session_id, ~answered, COMMANDS.c.closed_unheard.is_(None))
                .values(closed_unheard=why, closed_at=at, cleaned_up=True)
            )
            self.ctx.notify(c, "command", session=session_id)
            if done.rowcount > 0:
                return None
            stored = _rows(c, select(*COMMANDS.c).where(COMMANDS.c.session_id == session_id))
            return stored[0] if stored else None

        return self.ctx.writes.write(write)

    def read(
        self,
        limit: int | None = None,
        offset: int = 0,
        unfinished: bool = False,
        session_id: str | None = None,
        provider_id: str | None = None,
        console: str | None = None,
    ) -> list[CommandRow]:
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
        return self._rows(q)

    def export(self, provider_id: str | None, since: float | None, until: float | None) -> list[CommandRow]:
        """Commands created in [since, until] (to `provider_id` when given), oldest first, with their
        transitions; for a worker thread (a connection of its own from the pool)."""
        q = select(*COMMANDS.c).order_by(COMMANDS.c.created_at)
        if provider_id is not None:
            q = q.where(COMMANDS.c.provider_id == provider_id)
        if since is not None:
            q = q.where(COMMANDS.c.created_at >= since)
        if until is not None:
            q = q.where(COMMANDS.c.created_at <= until)
        return self._rows(q)

    def _rows(self, q: Select[Any]) -> list[CommandRow]:
        with self.ctx.writes.reads() as c:
            return _rows(c, q)

    def clear(self) -> None:
        """Forget every command and transition (a replay rebuilding its state); the audit trail stays."""

        def write(c: Connection) -> None:
            c.execute(delete(TRANSITIONS))
            c.execute(delete(COMMANDS))

        self.ctx.writes.write(write)


def _rows(c: Connection, q: Select[Any]) -> list[CommandRow]:
    """The commands `q` selects, their JSON parsed, with their transitions."""
    rows = [dict(r) for r in c.execute(q).mappings()]
    trans = _transitions(c, [r["session_id"] for r in rows])
    return [
        cast(CommandRow, {**r, "command": json.loads(r["command"]), "transitions": trans.get(r["session_id"], [])}) for r in rows
    ]


def _transitions(c: Connection, ids: list[str]) -> dict[str, list[TransitionRow]]:
    """Session id -> its transitions in order."""
    out: dict[str, list[TransitionRow]] = {}
    for chunk in (ids[i : i + 500] for i in range(0, len(ids), 500)):
        q = (
            select(*TRANSITIONS.c)
            .where(TRANSITIONS.c.session_id.in_(chunk))
            .order_by(TRANSITIONS.c.session_id, TRANSITIONS.c.seq)
        )
        for t in c.execute(q).mappings():
            out.setdefault(t["session_id"], []).append(cast(TransitionRow, dict(t)))
    return out
