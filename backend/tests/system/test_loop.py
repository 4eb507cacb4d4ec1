"""No route, nor another console's notification, blocks the event loop on the database. The app of `sem-console`
in this process (tests/system/test_routes.py's `app_client`: real Cyclone DDS, the embedded simulator, a SQLite or
PostgreSQL database), with its database made slow: a statement of the request under test waits in the thread that
runs it. A request that reads or writes the database on the event loop stops every other request with it; one that
reads it in a worker thread, or writes it on the database's writer thread, leaves the loop to answer /api/health
meanwhile."""

from __future__ import annotations

import json
import re
import threading
import time
import uuid
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

import psycopg
import pytest
from fastapi.testclient import TestClient
from sqlalchemy import Engine, event

from sem_console.storage import notify
from test_routes import UNKNOWN, V1, app_client, wait_until

HOLD = 10.0  # seconds a slowed statement waits at most: far beyond an answer of /api/health on a free loop
# every path parameter of the read routes: a known vehicle, a command no one issued, a task, a recording
PARAMETERS = {"provider_id": V1, "session_id": UNKNOWN, "task_id": "1", "name": "none.mcap"}


class SlowDatabase:
    """Statements of `verb` on `table` wait in their thread, once armed, until `release` or HOLD: a slow database
    server. Records the thread of every SELECT and of the held statement, and whether each held statement was released
    (not timed out). Listens for the engine's life (a listener removed while another thread runs a statement breaks
    that statement)."""

    def __init__(self, engine: Engine) -> None:
        self.engine, self.table, self.verb = engine, "", "SELECT"
        self.threads: set[int] = set()
        self.held_in: int | None = None  # the thread of the statement held
        self.entered, self.released = threading.Event(), threading.Event()
        self.released_in_time: list[bool] = []
        self.answered = False  # hold the statement once it has its rows (a read older than what follows), not before
        event.listen(engine, "before_cursor_execute", self._statement)
        event.listen(engine, "after_cursor_execute", self._answered)

    def _answered(self, *args: Any) -> None:
        if self.answered:
            self._statement(*args, answered=True)

    def _statement(self, _conn: Any, _cursor: Any, statement: str, *_args: Any, answered: bool = False) -> None:
        verb = statement.lstrip().split(None, 1)[0].upper()
        if verb == "SELECT":
            self.threads.add(threading.get_ident())
        if (
            self.table
            and verb == self.verb
            and self.answered == answered
            and re.search(rf"\b(FROM|INTO|UPDATE) {self.table}\b", statement)
        ):
            self.table = ""  # the first such statement only
            self.held_in = threading.get_ident()
            self.entered.set()
            self.released_in_time.append(self.released.wait(HOLD))

    def hold(self, table: str, answered: bool = False, verb: str = "SELECT") -> None:
        self.table, self.answered, self.verb, self.threads, self.held_in = table, answered, verb, set(), None
        self.entered.clear()
        self.released.clear()
        self.released_in_time.clear()

    def release(self) -> list[bool]:
        """Let the held statement go on; whether it was released in time (not by the HOLD timeout)."""
        self.released.set()
        if self.entered.is_set():
            wait_until(lambda: self.released_in_time, HOLD + 5, "the held statement to go on")
        return self.released_in_time


@pytest.fixture(scope="module")
def client(tmp_path_factory: pytest.TempPathFactory) -> Iterator[TestClient]:
    with app_client(tmp_path_factory.mktemp("loop")) as c:
        yield c


@pytest.fixture(scope="module")
def slowed(client: TestClient) -> SlowDatabase:
    return SlowDatabase(client.app.state.console.store.engine)  # type: ignore[attr-defined]


@pytest.fixture
def slow(slowed: SlowDatabase) -> Iterator[SlowDatabase]:
    yield slowed
    slowed.hold("")
    slowed.released.set()


def loop_thread(client: TestClient) -> int:
    """The thread of the app's event loop (TestClient runs it in a thread of its own)."""
    ident: int = client.portal.call(threading.get_ident)  # type: ignore[union-attr]
    return ident


def read_routes(client: TestClient) -> list[tuple[str, str]]:
    """(method, path) of every GET and DELETE route of the app's OpenAPI document, its path parameters filled in."""
    paths: dict[str, dict[str, Any]] = client.app.openapi()["paths"]  # type: ignore[attr-defined]
    return [
        (method.upper(), re.sub(r"\{(\w+)\}", lambda m: PARAMETERS[m.group(1)], path))
        for path, operations in paths.items()
        for method in operations
        if method in ("get", "delete")
    ]


def test_no_read_route_runs_a_statement_on_the_event_loop(client: TestClient, slow: SlowDatabase) -> None:
    """Every GET and DELETE route, once, with the thread of each SELECT it runs recorded: none is the loop's."""
    loop = loop_thread(client)
    routes = read_routes(client)
    assert ("GET", "/api/commands") in routes and ("GET", "/api/audit") in routes
    on_loop = []
    for method, path in routes:
        slow.hold("")
        client.request(method, path)
        if loop in slow.threads:
            on_loop.append(f"{method} {path}")
    assert on_loop == [], f"routes that read the database on the event loop: {on_loop}"


@pytest.mark.parametrize(
    "method,path,table",
    [
        ("GET", "/api/commands", "commands"),
        ("GET", f"/api/commands/{UNKNOWN}", "commands"),
        ("DELETE", f"/api/commands/{UNKNOWN}", "commands"),
        ("GET", "/api/audit", "audit"),
        ("GET", "/api/commands.csv", "commands"),
        ("GET", f"/api/providers/{V1}/track", "track"),
    ],
)
def test_the_loop_answers_while_a_route_waits_on_a_slow_database(
    client: TestClient, slow: SlowDatabase, method: str, path: str, table: str
) -> None:
    """While the route's statement waits (at most HOLD s), /api/health is asked: it is answered while the statement
    still waits (it is released by that answer, not by the HOLD timeout), within a small part of HOLD."""
    slow.hold(table)
    with ThreadPoolExecutor(1) as pool:
        pending = pool.submit(client.request, method, path)
        assert slow.entered.wait(30), f"{method} {path} read no {table}"
        started = time.monotonic()
        health = client.get("/api/health")
        answered = time.monotonic() - started
        released = slow.release()
        assert health.status_code == 200
        assert pending.result(timeout=60).status_code in (200, 404)
    print(f"{method} {path}: /api/health answered in {answered * 1000:.1f} ms while the database was held")
    assert released == [True], f"/api/health waited for {method} {path} ({answered:.1f} s): it blocked the loop"
    assert answered < HOLD / 2


def test_the_loop_answers_while_a_write_waits_on_a_slow_database(tmp_path: Path, database_url: str) -> None:
    """A command issued, an alarm acknowledged, a vehicle renamed, each with its write held in the thread that runs it
    (a database server that does not answer, as one that drops packets until the connect timeout): the write is not
    the loop's, /api/health is answered while it waits, and each request is answered."""
    with app_client(tmp_path, database_url=database_url) as client:
        console = client.app.state.console  # type: ignore[attr-defined]
        slow = SlowDatabase(console.store.engine)
        try:
            failed = "recording stopped: the disk is full (/recordings/x.mcap)"  # an alarm, raised at the next tick
            client.portal.call(lambda: setattr(console.recorder, "error", failed))  # type: ignore[union-attr]
            [alarm] = wait_until(lambda: client.get("/api/alarms").json(), 30, "the recording's alarm")
            writes = [
                ("POST", f"/api/providers/{V1}/gps-fix", {}, "INSERT", "commands"),
                ("POST", f"/api/alarms/{alarm['id']}/ack", {}, "UPDATE", "alarms"),
                ("PUT", f"/api/providers/{V1}/name", {"name": "Slow"}, "INSERT", "vehicle_names"),
            ]
            loop = loop_thread(client)
            for method, path, body, verb, table in writes:
                slow.hold(table, verb=verb)
                with ThreadPoolExecutor(1) as pool:
                    pending = pool.submit(client.request, method, path, json=body)
                    assert slow.entered.wait(30), f"{method} {path}: no {verb} on {table}"
                    started = time.monotonic()
                    health = client.get("/api/health")
                    answered = time.monotonic() - started
                    released = slow.release()
                    assert health.status_code == 200
                    assert pending.result(timeout=60).status_code in (200, 201)
                print(f"{method} {path}: /api/health answered in {answered * 1000:.1f} ms while its write was held")
                assert slow.held_in != loop, f"{method} {path} wrote {table} on the event loop"
                assert released == [True], f"/api/health waited for {method} {path}'s write ({answered:.1f} s)"
                assert answered < HOLD / 2
        finally:
            slow.released.set()


def test_another_consoles_change_is_read_off_the_loop(tmp_path: Path, pg_url: str) -> None:
    """On PostgreSQL another console's change comes as a notification (storage/notify.py): the command it names is read
    in a worker thread, and the loop answers /api/health while that read waits."""
    with app_client(tmp_path, database_url=pg_url) as client, psycopg.connect(pg_url, autocommit=True) as other:
        slow = SlowDatabase(client.app.state.console.store.engine)  # type: ignore[attr-defined]
        try:
            listening(client)  # the first connection's resync read the commands too: this read is the notification's
            slow.hold("commands")
            message = json.dumps({"kind": "command", "console": "relief", "session": UNKNOWN})
            other.execute("SELECT pg_notify('sem_console', %s)", (message,))
            assert slow.entered.wait(30), "no read of the command after the notification"
            started = time.monotonic()
            health = client.get("/api/health")
            answered = time.monotonic() - started
            released = slow.release()
            assert health.status_code == 200
            print(f"notified command: /api/health answered in {answered * 1000:.1f} ms while the database was held")
            assert released == [True], f"/api/health waited for the notification's read ({answered:.1f} s)"
        finally:
            slow.released.set()


def listening(client: TestClient) -> None:
    """Wait until the console listens to the other consoles' notifications, and has read what they changed before
    (the first connection's resync)."""
    listener = client.app.state.console._listener  # type: ignore[attr-defined]
    assert listener is not None and listener.connected.wait(30), "the console does not listen"
    settled(client)


def settled(client: TestClient) -> None:
    """Wait until the console has applied every read of the database it started after a notification."""
    console = client.app.state.console  # type: ignore[attr-defined]
    wait_until(
        lambda: not client.portal.call(lambda: set(console._reloads)),
        30,  # type: ignore[union-attr]
        what="the console's reads after notifications to end",
    )


def test_a_change_made_here_while_another_consoles_is_read_stands(tmp_path: Path, pg_url: str) -> None:
    """Another station's link configuration is read off the loop after its notification; an operator here sets the
    vehicle's configuration while that read (of the older row) is on its way: the configuration set here stands, as
    the database has it, not the older one read before it."""
    theirs = {"commsLostTimeout": 30.0, "regainedTime": 5.0, "policy": "CONTINUE_MISSION", "regainedBehavior": 0}
    ours = {"commsLostTimeout": 7.5, "regainedTime": 2.0, "policy": "CONTINUE_MISSION", "regainedBehavior": 3}
    with app_client(tmp_path, database_url=pg_url) as client, psycopg.connect(pg_url, autocommit=True) as other:
        slow = SlowDatabase(client.app.state.console.store.engine)  # type: ignore[attr-defined]
        try:
            other.execute(
                "INSERT INTO link_config (provider_id, config) VALUES (%s, %s) ON CONFLICT (provider_id) "
                "DO UPDATE SET config = excluded.config",
                (V1, json.dumps(theirs)),
            )
            listening(client)  # one notification, one read: a second would read the newer row after the held one
            slow.hold("link_config", answered=True)
            message = json.dumps({"kind": "link", "console": "relief", "provider": V1})
            other.execute("SELECT pg_notify('sem_console', %s)", (message,))
            assert slow.entered.wait(30), "no read of the link configurations after the notification"
            assert client.put(f"/api/providers/{V1}/link-config", json=ours).status_code == 200
            assert slow.release() == [True]
            settled(client)
            assert client.get(f"/api/providers/{V1}").json()["linkConfig"] == ours
            stored = other.execute("SELECT config FROM link_config WHERE provider_id = %s", (V1,)).fetchone()
            assert stored is not None and json.loads(stored[0]) == ours
        finally:
            slow.released.set()


def insert(other: psycopg.Connection[Any], table: str, row: dict[str, Any]) -> None:
    """Another station's write of `row` into `table`, as its own connection makes it."""
    other.execute(f"INSERT INTO {table} ({', '.join(row)}) VALUES ({', '.join(['%s'] * len(row))})", list(row.values()))


def test_a_shelf_heard_while_a_resync_reads_stands(tmp_path: Path, pg_url: str) -> None:
    """A resync (the listener reopened) reads the shelves off the loop; another station shelves an alarm after that
    read and before it is applied: the shelf it notified stands here, not undone by the older read."""
    now = time.time()
    row = {
        "id": str(uuid.uuid4()),
        "key": f"link-lost:{V1}",
        "kind": "link-lost",
        "provider_id": V1,
        "session_id": None,
        "severity": "alarm",
        "text": "Alpha: link lost",
        "reason": "maintenance",
        "shelved_by": "bob",
        "station": "relief",
        "shelved_at": now,
        "until": now + 3600,
        "ended_at": None,
        "ended_by": None,
        "end_reason": None,
    }
    with app_client(tmp_path, database_url=pg_url) as client, psycopg.connect(pg_url, autocommit=True) as other:
        console = client.app.state.console  # type: ignore[attr-defined]
        slow = SlowDatabase(console.store.engine)
        try:
            listening(client)
            slow.hold("alarm_shelves", answered=True)
            other.execute("SELECT pg_notify('sem_console', %s)", (json.dumps({"kind": "resync"}),))
            assert slow.entered.wait(30), "no read of the shelves after the resync"
            insert(other, "alarm_shelves", row)
            other.execute(
                "SELECT pg_notify('sem_console', %s)", (json.dumps({"kind": "shelf", "console": "relief", "row": row}),)
            )
            time.sleep(1.0)  # the shelf's notification heard meanwhile
            assert slow.release() == [True]
            settled(client)
            assert row["key"] in client.portal.call(lambda: set(console.alarms.shelves))  # type: ignore[union-attr]
        finally:
            slow.released.set()


def test_a_silence_another_station_planned_before_this_one_listened_is_in_force(
    tmp_path: Path, pg_url: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A console reads the shared shelves and silences as it is made, and listens to the other stations only once
    it starts: a silence another station planned in between was never heard here. The first LISTEN reads them again
    (a resync), so it is in force here as on the station that planned it."""
    now = time.time()
    row = {
        "id": str(uuid.uuid4()),
        "provider_id": V1,
        "reason": "dive",
        "set_by": "bob",
        "station": "relief",
        "set_at": now,
        "until": now + 3600,
        "ended_at": None,
        "ended_by": None,
        "end_reason": None,
    }
    start = notify.Listener.start

    def planned_meanwhile(listener: notify.Listener) -> None:  # after this console read the database, before LISTEN
        with psycopg.connect(pg_url, autocommit=True) as other:
            insert(other, "planned_silences", row)
            other.execute(
                "SELECT pg_notify('sem_console', %s)", (json.dumps({"kind": "silence", "console": "relief", "row": row}),)
            )
        start(listener)

    monkeypatch.setattr(notify.Listener, "start", planned_meanwhile)
    with app_client(tmp_path, database_url=pg_url) as client:
        listening(client)
        assert [s["id"] for s in client.get("/api/silences").json()] == [row["id"]]
