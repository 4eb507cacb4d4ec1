"""PostgreSQL LISTEN/NOTIFY between the consoles of one database: what one console writes (a command, its
transitions and flags, a link configuration...) the others hear within a second, without polling.

A write sends `pg_notify(CHANNEL, payload)` in its own transaction (delivered when it commits; `notify`);
`Listener` is a thread with a connection of its own that waits on LISTEN and hands each payload to a callback
(the console passes one that goes on to its event loop with call_soon_threadsafe). A lost connection (the server
restarts, an outage) is reopened, a second apart, until it is back; what was sent meanwhile is not delivered
again, so a reopened connection hands `{"kind": "resync"}` to the callback: the console reads what it may have
missed from the database. The first connection hands one too (`"first": true`): the console read the shared state
when it was made, before LISTEN was in place, and a change another station wrote in between was never sent to it."""

from __future__ import annotations

import json
import logging
import threading
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from sqlalchemy import Connection, func, select
from sqlalchemy.engine import URL

if TYPE_CHECKING:  # imported where a listener runs: a console on SQLite never loads the driver (about 0.08 s a start)
    import psycopg

log = logging.getLogger("sem-console.storage")
# Every PostgreSQL connection of the console (this listener's, storage/engine.py). connect_timeout: the
# seconds to reach a server (a start fails after it). A server gone without closing its connections (a network cut, a
# host powered off): without the TCP settings an open connection's next statement waits for TCP's retransmissions
# (many minutes; on the event loop for a write) and a listening connection never notices; with them a statement fails
# after about 5 s and the outage path takes over.
PG_CONNECT_ARGS: dict[str, Any] = {
    "connect_timeout": 5,
    "tcp_user_timeout": 5000,
    "keepalives": 1,
    "keepalives_idle": 5,
    "keepalives_interval": 2,
    "keepalives_count": 2,
}
CHANNEL = "sem_console"
RECONNECT = 1.0  # seconds between attempts to reopen a lost listening connection


def conninfo(url: URL) -> str:
    """The libpq URI of a SQLAlchemy postgresql+psycopg URL (with its password: never logged)."""
    return url.set(drivername="postgresql").render_as_string(hide_password=False)


def notify(c: Connection, message: dict[str, Any]) -> None:
    """Send `message` to the listening consoles, when `c`'s transaction commits."""
    c.execute(select(func.pg_notify(CHANNEL, json.dumps(message))))


class Listener:
    def __init__(self, url: URL, on_message: Callable[[dict[str, Any]], object]) -> None:
        self._conninfo, self._on_message = conninfo(url), on_message
        self._stop = threading.Event()
        self._conn: psycopg.Connection[Any] | None = None
        self._thread = threading.Thread(target=self._run, name="pg-listen", daemon=True)
        self.connected = threading.Event()  # set while LISTEN is in place (tests wait for it)

    def start(self) -> None:
        self._thread.start()

    def _run(self) -> None:
        import psycopg

        listened = False
        while not self._stop.is_set():
            try:
                with psycopg.connect(self._conninfo, autocommit=True, **PG_CONNECT_ARGS) as conn:
                    self._conn = conn
                    conn.execute(f"LISTEN {CHANNEL}")
                    # what was written before LISTEN (while it was away, or before its first connection) is not
                    # delivered: the console reads the database (asked before `connected` is set, for the tests)
                    self._on_message({"kind": "resync"} if listened else {"kind": "resync", "first": True})
                    listened = True
                    self.connected.set()
                    while not self._stop.is_set():
                        for n in conn.notifies(timeout=1.0):  # returns each second so a stop is seen
                            self._deliver(n.payload)
            except psycopg.Error as e:
                if not self._stop.is_set():
                    log.debug("listening connection lost (%s): reopening", e)
            finally:
                self.connected.clear()
                self._conn = None
            self._stop.wait(RECONNECT)

    def _deliver(self, payload: str) -> None:
        try:
            message = json.loads(payload)
        except ValueError:
            log.warning("ignored a notification that is not JSON: %.80s", payload)
            return
        if isinstance(message, dict):
            self._on_message(message)

    def stop(self) -> None:
        self._stop.set()
        self._thread.join(5)
