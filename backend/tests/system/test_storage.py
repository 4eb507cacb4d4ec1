"""The console's storage (sem_console/storage): Alembic migrations, console identities and the shipped database of
the first release, on SQLite and on a real PostgreSQL server (tests/pg.py) where a case applies to one console."""

from __future__ import annotations

import asyncio
import contextlib
import fcntl
import math
import re
import shutil
import sqlite3
import threading
import time
import uuid
from collections import Counter
from pathlib import Path
from typing import Any

import psycopg
import pytest
from alembic.autogenerate import compare_metadata
from alembic.runtime.migration import MigrationContext
from fastapi.testclient import TestClient
from sqlalchemy import Connection, event, text
from sqlalchemy.exc import OperationalError
from sqlmodel import Session, SQLModel, select

from sem_console.comap.geo import Local
from sem_console.console.history import History, Thinning, track_point
from sem_console.core.config import Settings
from sem_console.main import create_app
from sem_console.storage.alarms import IDS_AHEAD
from sem_console.storage.database import Database, StorageError, Unavailable, VehicleWriters
from sem_console.storage.engine import head_revision
from sem_console.storage.models import TrackPoint
from sem_console.storage.url import parse_database_url
from support.pg import Cluster
from test_routes import app_client, wait_until

LEGACY = Path(__file__).parents[1] / "data" / "legacy-8592e59.sqlite3"  # made by tests/data/make_legacy_db.py
LEGACY_GUID = uuid.UUID("77b09762-22b2-4bad-aab6-e87ed4b24833")  # its meta 'source'
V1 = "77b2ceb8-5afe-554e-8450-93db17c48923"


ALARM = {
    "kind": "link-lost",
    "severity": "alarm",
    "provider_id": V1,
    "vehicle": "Alpha",
    "session_id": None,
    "text": "Alpha: link lost",
    "since": 1.0,
    "cleared_at": None,
    "acked_at": None,
    "acked_by": None,
    "normal_at": None,
}


def open_db(url: str) -> Database:
    return Database(parse_database_url(url))


def test_a_new_database_has_the_models_schema(database_url: str) -> None:
    """The migrations make what the models say (no column, index or constraint of one missing in the other)."""
    db = open_db(database_url)
    try:
        with db.engine.connect() as c:
            context = MigrationContext.configure(c)
            assert context.get_current_revision() == head_revision()
            assert compare_metadata(context, SQLModel.metadata) == []
    finally:
        db.close()


def test_a_database_of_a_newer_release_is_refused_in_one_line(database_url: str) -> None:
    """A console of an older release on a database a newer one upgraded: one line naming the revision and the fix, the
    database left as it was (no backup copy, no traceback from Alembic's unknown revision)."""
    db = open_db(database_url)
    with db.engine.begin() as c:
        c.execute(text("UPDATE alembic_version SET version_num = '9999'"))
    db.close()
    with pytest.raises(StorageError) as e:
        open_db(database_url)
    assert "revision 9999, newer than this sem-console's" in str(e.value) and "\n" not in str(e.value)
    assert "run the sem-console release that wrote it" in str(e.value)


def test_identity_per_name_kept_across_restarts_never_shared(database_url: str) -> None:
    a = open_db(database_url)
    first = a.claim("watch")
    assert a.claim("watch") == first
    other = open_db(database_url)
    with pytest.raises(StorageError) as refused:  # the same name, running
        other.claim("watch")
    assert "pg-test-s3cret" not in str(refused.value)  # the URL is shown with its password hidden
    if a.db.path is None:
        assert "another console named 'watch' is running on" in str(refused.value) and "--console-name" in str(refused.value)
        relief = other.claim("relief")
        assert relief != first
    else:  # SQLite shares nothing live between consoles: a second one is refused whatever its name, and told of PostgreSQL
        with pytest.raises(StorageError) as second:
            other.claim("relief")
        for refusal in (refused, second):
            assert f"another console ('watch') is running on {a.db.path}" in str(refusal.value), refusal.value
            assert "--database-url" in str(refusal.value) and "\n" not in str(refusal.value)
        lock = a.lock_path()
        assert lock.exists()
    a.close()
    other.close()
    if a.db.path is not None:
        assert not lock.exists()  # a clean stop leaves no lock file behind
    again = open_db(database_url)  # a restart: the same name, the same GUID
    assert again.claim("watch") == first
    assert again.consoles() == ({"watch": first} if a.db.path is not None else {"watch": first, "relief": relief})
    again.close()


def test_a_console_stopping_as_another_starts_on_a_sqlite_file_leaves_one_holder(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The lock file is removed at a clean stop: a console that opened it just before (and locks it just after) held
    the removed file's lock, and a third then took a new file's: two consoles on one SQLite file."""
    url = str(tmp_path / "console.sqlite3")
    first, second, third = open_db(url), open_db(url), open_db(url)
    first.claim("watch")
    lock = fcntl.flock

    def first_stops_meanwhile(fd: int, operation: int) -> None:  # between the second's open and its lock
        monkeypatch.setattr(fcntl, "flock", lock)
        first.close()
        lock(fd, operation)

    monkeypatch.setattr(fcntl, "flock", first_stops_meanwhile)
    second.claim("relief")
    with pytest.raises(StorageError, match=r"another console \('relief'\) is running"):
        third.claim("night")
    second.close()
    third.close()


def test_a_status_of_a_command_and_its_ending_as_never_heard_never_stand_together(database_url: str) -> None:
    """The vehicle answers just as a station ends its cancelled command as never heard, or two stations race: whatever
    the order of their writes, a stored status withdraws the ending (one transaction: no crash leaves both)."""
    db = open_db(database_url)
    try:
        session = str(uuid.uuid4())
        db.add_command(
            {"sessionId": session, "service": "GPSFix", "providerId": V1, "state": None, "operator": "alice", "createdAt": 100.0},
            {"timeStamp": [100, 0]},
            "watch",
        )
        db.set_canceled(session, "bob", "relief", 101.0)
        assert db.set_closed_unheard(session, "heard", 108.0).result(30) is None  # stored
        # another station ends it too, later: refused, the first ending stands (each station shows the stored one)
        refused = db.set_closed_unheard(session, "bound", 109.0).result(30)
        assert refused is not None and (refused["closed_unheard"], refused["closed_at"]) == ("heard", 108.0)
        [row] = db.commands(session_id=session)
        assert (row["closed_unheard"], row["closed_at"], row["cleaned_up"]) == ("heard", 108.0, True)
        canceled = {
            "status": "CANCELED",
            "reason": "CANCELED",
            "logMessage": "",
            "violation": None,
            "providerTime": 1.0,
            "receivedAt": 109.0,
        }
        db.add_transition(session, 1, canceled)  # the vehicle answered after all
        [row] = db.commands(session_id=session)
        assert (row["closed_unheard"], row["closed_at"], row["cleaned_up"]) == (None, None, False), row
        refused = db.set_closed_unheard(session, "heard", 110.0).result(30)  # another station's, after that answer
        assert refused is not None and refused["closed_unheard"] is None and len(refused["transitions"]) == 1
        [row] = db.commands(session_id=session)
        assert (row["closed_unheard"], row["cleaned_up"], len(row["transitions"])) == (None, False, 1), row
    finally:
        db.close()


def test_commands_audit_link_configs_names_and_alarms_round_trip(database_url: str) -> None:
    db = open_db(database_url)
    db.audit_trail.max_rows = 3
    try:
        session = str(uuid.uuid4())
        db.add_command(
            {"sessionId": session, "service": "GPSFix", "providerId": V1, "state": None, "operator": "alice", "createdAt": 100.0},
            {"timeStamp": [100, 0]},
            "watch",
        )
        for seq, status in enumerate(("ISSUED", "COMMANDED", "COMMANDED"), start=1):
            db.add_transition(
                session,
                min(seq, 2),
                {
                    "status": status,
                    "reason": "SUCCEEDED",
                    "logMessage": "",
                    "violation": None,
                    "providerTime": 1.0,
                    "receivedAt": 2.0,
                },
            )
        db.set_canceled(session, "bob", "relief", 101.5)
        db.set_flag(session, "cleaned_up")
        [row] = db.commands(session_id=session)
        assert [t["seq"] for t in row["transitions"]] == [1, 2]  # a repeated (session, seq) is ignored
        assert row["cancel_requested"] is True and row["canceled_by"] == "bob" and row["cleaned_up"] is True
        assert (row["canceled_on"], row["canceled_at"]) == ("relief", 101.5)
        assert row["console"] == "watch" and row["command"] == {"timeStamp": [100, 0]}
        assert db.commands(limit=10, unfinished=True, console="relief") == []
        for n in range(5):
            db.add_audit(
                {"at": float(n), "outcome": "accepted", "status": 200, "method": "POST", "path": f"/{n}", "reason": "accepted"}
            )
        assert [e.path for e in db.audit(10, 0)] == ["/4", "/3", "/2"]  # the newest audit_max_rows
        db.set_link_config(V1, {"commsLostTimeout": 5})
        db.set_link_config(V1, {"commsLostTimeout": 7})
        assert db.link_configs() == {V1: {"commsLostTimeout": 7}}
        db.set_vehicle_name(V1, "Alpha", "alice")
        db.set_vehicle_name(V1, "Bravo", "bob")
        assert db.vehicle_names() == {V1: "Bravo"}
        db.set_vehicle_name(V1, None, "bob")
        assert db.vehicle_names() == {}
        alarm = {**ALARM, "key": "k"}
        assert db.flush(30)  # opened: alarm ids taken ahead
        first = db.add_alarm(alarm)  # its row's id, at once
        second = db.add_alarm({**alarm, "key": "k2"})
        db.update_alarm({**alarm, "id": first, "normal_at": 3.0})
        assert 0 < first < second and [(a.id, a.key) for a in db.open_alarms()] == [(second, "k2")]
    finally:
        db.close()


def test_writes_run_in_order_on_one_thread_of_their_own_and_the_stop_writes_every_one(database_url: str) -> None:
    """A write returns at once; the writes run on one thread, not the caller's, in the order asked; a read sees
    every write asked before it; the stop writes those still queued."""
    db = open_db(database_url)
    wrote_on: set[int] = set()

    def inserted(_conn: Connection, _cursor: object, statement: str, *_args: object) -> None:
        if statement.lstrip().upper().startswith("INSERT"):
            wrote_on.add(threading.get_ident())

    event.listen(db.engine, "before_cursor_execute", inserted)
    entry = {"at": 1.0, "outcome": "accepted", "status": 200, "method": "DELETE", "reason": "accepted"}
    try:
        for i in range(40):
            db.add_audit({**entry, "path": f"/{i}"})
        assert [e.path for e in db.audit(1, 0)] == ["/39"]  # the read waited for the 40 writes
        for i in range(40, 100):
            db.add_audit({**entry, "path": f"/{i}"})
    finally:
        db.close()
    assert len(wrote_on) == 1 and threading.get_ident() not in wrote_on, "writes on the caller's thread"
    again = open_db(database_url)
    try:
        assert [e.path for e in again.audit(200, 0)] == [f"/{i}" for i in reversed(range(100))]
    finally:
        again.close()


def test_an_alarm_raised_before_ids_are_taken_takes_none_of_them(database_url: str) -> None:
    """The writer slow (a statement that waits): the alarm ids taken ahead run out, the next alarm has a temporary id,
    and its row's id is not one of those taken ahead meanwhile, so the alarm after it is written too."""
    db = open_db(database_url)
    gate = threading.Event()
    alarm = dict(ALARM)
    try:
        assert db.flush(30)  # opened: alarm ids taken ahead
        db.writes.write(lambda _c: gate.wait(30))  # the next ids are taken behind it
        given = [db.add_alarm({**alarm, "key": f"k{i}"}) for i in range(IDS_AHEAD + 1)]
        assert given[-1] < 0 < min(given[:-1]), given
        gate.set()
        assert db.flush(30)
        after = db.add_alarm({**alarm, "key": "after"})
        assert db.flush(30)
        rows = {a.key: a.id for a in db.open_alarms()}
        assert len(rows) == IDS_AHEAD + 2 and rows["after"] == after, (after, rows)
    finally:
        gate.set()
        db.close()


def test_track_points_written_once_read_in_order(database_url: str) -> None:
    db = open_db(database_url)
    history = History(db.engine, retention_hours=24)
    provider = uuid.UUID(V1)
    fix = {
        "position2DWithTime": {
            "geodeticPosition": {"geodeticLatitude": {"latitude": 0.5}, "geodeticLongitude": {"longitude": 0.25}}
        },
        "GPSLatLongValid": True,
    }

    async def run() -> list[float]:
        now = math.floor(time.time()) + 0.25
        for t in (now, now + 0.5, now + 1, now + 2):  # at most one point a second: the second one is not taken
            history.on_fix(provider, t, fix, [], True)
        await history.flush()
        history._track.append({**(await history.track(provider, None, None))[0].model_dump()})  # the same point again
        await history.flush()
        return [p.time for p in await history.track(provider, None, None)]

    try:
        times = asyncio.run(run())
        assert len(times) == 3 and times == sorted(times)
    finally:
        db.close()


def test_the_first_releases_file_opens_with_its_history_and_identity(tmp_path: Path) -> None:
    """The file a console of 8592e59 wrote is upgraded in place, a copy kept beside it first; its commands with
    their transitions, audit, link configuration, alarm and track are there; its source GUID is the first name's."""
    path = tmp_path / "sem-console.sqlite3"
    shutil.copy(LEGACY, path)
    db = Database(path)  # upgraded here: the track is read before a console's retention could prune it
    with db.engine.connect() as c:
        assert c.execute(text("SELECT count(*) FROM track")).scalar() == 28
    db.close()
    settings = Settings(db_path=path, console_name="station-1", recordings_dir=tmp_path / "recordings", domain=231)
    with TestClient(create_app(settings), base_url="http://localhost") as client:
        console = client.app.state.console  # type: ignore[attr-defined]
        assert console.id == LEGACY_GUID
        commands = client.get("/api/commands").json()
        assert {c["service"]: c["status"] for c in commands} == {"GPSFix": "COMPLETED", "InertialSensor": "CANCELED"}
        assert [t["status"] for t in commands[1]["transitions"]] == ["ISSUED", "COMMANDED", "EXECUTING", "COMPLETED"]
        assert commands[0]["cancelRequested"] and commands[0]["canceledBy"] == "alice"
        audit = client.get("/api/audit").json()
        assert len(audit) == 6 and {e["outcome"] for e in audit} == {"accepted", "refused"}
        [alarm] = client.get("/api/alarms").json()
        assert alarm["kind"] == "link-lost" and alarm["ackedBy"] == "alice"
        assert console.store.link_configs()[V1]["policy"] == "CONTINUE_MISSION"
    [backup] = tmp_path.glob("sem-console.before-upgrade-from-first-release-*.sqlite3")
    with sqlite3.connect(backup) as old:  # the copy is the file as it was: no Alembic table, the same rows
        tables = {r[0] for r in old.execute("SELECT name FROM sqlite_master WHERE type='table'")}
        assert "alembic_version" not in tables and old.execute("SELECT count(*) FROM transitions").fetchone()[0] == 6
    old.close()
    db = Database(path)  # a second station on the file gets an identity of its own; the first keeps the old one
    try:
        assert db.claim("station-2", hold=False) != LEGACY_GUID
        assert db.consoles()["station-1"] == LEGACY_GUID
    finally:
        db.close()
    assert len(list(tmp_path.glob("*.before-upgrade-*"))) == 1  # upgraded once: no copy at the next start


def test_an_outage_holds_writes_fails_reads_at_once_and_keeps_the_name(pg_cluster: Cluster, pg_url: str) -> None:
    """PostgreSQL stopped: writes are held in order (an alarm has its row's id, taken ahead, or past those a temporary
    one), reads fail at once in one line
    (no connect attempt on the caller's thread); started again: `maintain` writes what was held (the alarm's
    acknowledgement to its row), and holds the console's name again, so a second console of the name is refused."""
    db = open_db(pg_url)
    db.claim("watch")
    alarm = {**ALARM, "key": "k"}
    try:
        assert db.flush(30)  # alarm ids taken ahead
        pg_cluster.stop()
        try:
            db.add_audit({"at": 1.0, "outcome": "accepted", "status": 201, "method": "POST", "path": "/a", "reason": "accepted"})
            given = [db.add_alarm({**alarm, "key": f"k{i}", "normal_at": 1.5}) for i in range(IDS_AHEAD)]
            temporary = db.add_alarm(alarm)
            assert db.flush(30)  # the writer thread met the outage
            assert all(i > 0 for i in given) and temporary < 0, (given, temporary)
            held = db.held
            assert db.unavailable_since is not None and held >= 2 + IDS_AHEAD
            db.update_alarm({**alarm, "id": temporary, "acked_at": 2.0, "acked_by": "alice"})
            assert db.held == held + 1
            started = time.monotonic()
            with pytest.raises(Unavailable) as refused:
                db.audit(10, 0)
            assert time.monotonic() - started < 1  # not a connect timeout
            assert "pg-test-s3cret" not in str(refused.value)
            # its time as every time the operator reads: "… since 2026-11-29 01:20:05 UTC: …", never "…Z"
            assert re.match(r"shared history unavailable since \d{4}-\d\d-\d\d \d\d:\d\d:\d\d UTC: ", str(refused.value))
            assert not db.maintain()  # still away
        finally:
            pg_cluster.start()
        assert db.maintain() and db.held == 0 and db.unavailable_since is None
        assert [e.path for e in db.audit(10, 0)] == ["/a"]
        [row] = db.open_alarms()
        assert row.acked_by == "alice" and row.acked_at == 2.0  # the held update found the row written late
        assert db.flush(30)  # ids taken ahead again: the next alarm has its row's id
        assert db.add_alarm({**alarm, "key": "next", "normal_at": 3.0}) > 0
        other = open_db(pg_url)
        try:
            with pytest.raises(StorageError):  # the name's lock went with the old server; maintain took it again
                other.claim("watch")
        finally:
            other.close()
    finally:
        db.close()


def test_what_is_held_when_the_console_stops_is_written_if_the_server_is_back(pg_cluster: Cluster, pg_url: str) -> None:
    """A write held during an outage, the server back before the console's upkeep found it (every 2 s) and the console
    stopped then: the held write is written as the console closes its database, not dropped with it."""
    db = open_db(pg_url)
    try:
        db.claim("watch")
        assert db.flush(30)  # opened: alarm ids taken ahead (not a held write)
        pg_cluster.stop()
        try:
            db.add_audit(
                {"at": 1.0, "outcome": "accepted", "status": 200, "method": "DELETE", "path": "/held", "reason": "accepted"}
            )
            assert db.flush(30) and db.held == 1 and db.unavailable_since is not None
        finally:
            pg_cluster.start()
    finally:
        db.close()
    again = open_db(pg_url)
    try:
        assert [e.path for e in again.audit(10, 0)] == ["/held"]
    finally:
        again.close()


def test_what_cannot_be_written_when_the_console_stops_is_said(
    pg_cluster: Cluster, pg_url: str, caplog: pytest.LogCaptureFixture
) -> None:
    """The server still away as the console stops: the changes held are lost with it, and one line says how many."""
    db = open_db(pg_url)
    try:
        assert db.writes.flush(30), "the writes of its opening not done"  # held too, they would be counted
        pg_cluster.stop()
        try:
            for path in ("/a", "/b"):
                db.add_audit(
                    {"at": 1.0, "outcome": "accepted", "status": 200, "method": "DELETE", "path": path, "reason": "accepted"}
                )
            with caplog.at_level("ERROR", logger="sem-console.storage"):
                db.close()
        finally:
            pg_cluster.start()
    finally:
        db.close()
    [line] = [r.getMessage() for r in caplog.records if r.levelname == "ERROR"]
    assert line.startswith("2 changes held since ") and "were not written" in line and "\n" not in line, line


def test_the_console_stops_after_its_upkeep_ends_and_lets_its_name_go(tmp_path: Path, pg_url: str) -> None:
    """The console's upkeep (every 2 s, in a worker thread) is on the name's lock connection as the console stops: the
    stop waits for it. It closed the database under it, and the upkeep, finding its connection closed, took the name
    again on a new one, held after the console had stopped: the console started again was refused as running."""
    on_lock, closed = threading.Event(), threading.Event()
    with app_client(tmp_path, database_url=pg_url) as client:
        store: Database = client.app.state.console.store  # type: ignore[attr-defined]

        def upkeep(conn: Connection, _cursor: object, statement: str, *_args: object) -> None:
            if conn is store.name_lock.lock and statement.strip() == "SELECT 1" and not on_lock.is_set():
                on_lock.set()
                closed.wait(5)  # until the store is closed (or, once the stop waits for the upkeep, 5 s)

        event.listen(store.engine, "before_cursor_execute", upkeep)
        event.listen(store.engine, "engine_disposed", lambda _engine: closed.set())
        assert on_lock.wait(30), "no upkeep on the name's lock connection"
    again = open_db(pg_url)
    try:

        def claimed() -> bool:
            try:
                again.claim("test-console")  # app_client's
            except StorageError:
                return False
            return True

        wait_until(claimed, 15, "the name let go by the stopped console")
    finally:
        again.close()


def test_an_alarm_whose_write_is_cut_before_its_commit_keeps_its_id_and_its_acknowledgement(pg_url: str) -> None:
    """The connection cut after the alarm's statements ran, before its commit (rolled back): the write is held; the
    alarm's id, its row's taken ahead, is the row's written when the server answers, where its acknowledgement, held
    after it, goes."""
    db = open_db(pg_url)
    alarm = {**ALARM, "key": "k"}
    cut: list[int] = []

    def cut_before_commit(conn: Connection, _cursor: object, statement: str, *_args: object) -> None:
        if statement.lstrip().upper().startswith("DELETE FROM ALARMS") and not cut:  # its last statement
            pid = conn.exec_driver_sql("SELECT pg_backend_pid()").scalar_one()
            cut.append(pid)
            with psycopg.connect(pg_url, autocommit=True) as other:
                other.execute("SELECT pg_terminate_backend(%s)", (pid,))

    try:
        db.claim("watch")
        assert db.flush(30)  # alarm ids taken ahead
        event.listen(db.engine, "after_cursor_execute", cut_before_commit)
        given = db.add_alarm(alarm)
        assert db.flush(30) and cut and db.held == 1, "the alarm's write was not cut"
        db.update_alarm({**alarm, "id": given, "acked_at": 2.0, "acked_by": "alice"})
        assert db.maintain() and db.held == 0
        [row] = db.open_alarms()
        assert (row.id, row.acked_by, row.acked_at) == (given, "alice", 2.0)
    finally:
        db.close()


def test_the_name_is_held_again_when_the_upkeep_finds_the_server_gone_first(pg_cluster: Cluster, pg_url: str) -> None:
    """The console's upkeep (`maintain`, every 2 s) is often the first to meet a stopped server, on the name's own
    lock connection, before any write has failed: that is an outage too, and the name is taken again when the server
    is back (it was let go for good: a second console of the same name then started and shared the UMAA identity)."""
    db = open_db(pg_url)
    db.claim("watch")
    try:
        pg_cluster.stop()
        try:
            assert not db.maintain() and db.unavailable_since is not None
            assert not db.maintain()  # still away
        finally:
            pg_cluster.start()
        assert db.maintain() and db.unavailable_since is None
        other = open_db(pg_url)
        try:
            with pytest.raises(StorageError):
                other.claim("watch")
        finally:
            other.close()
    finally:
        db.close()


def test_a_vehicles_writer_lets_it_go_when_the_server_restarts(pg_cluster: Cluster, pg_url: str) -> None:
    """The console that writes a vehicle's track holds a session lock, gone with a server restart. It must find that
    out at its next batch even when it has no new vehicle to take (no statement would touch its lock connection):
    it went on writing the vehicle beside the console that took it after the restart, two points a second in the
    shared track and chart history, and in every GPX and CSV export."""
    watch, relief = open_db(pg_url), open_db(pg_url)
    a, b = VehicleWriters(watch.engine), VehicleWriters(relief.engine)
    try:
        assert a.mine({V1}) == {V1} and b.mine({V1}) == set()
        pg_cluster.stop()
        try:
            for writers in (a, b):
                with pytest.raises(OperationalError):
                    writers.mine({V1})
        finally:
            pg_cluster.start()
        assert b.mine({V1}) == {V1}  # the first after the restart takes it
        assert a.mine({V1}) == set()
    finally:
        a.close()
        b.close()
        watch.close()
        relief.close()


def test_the_sessions_that_hold_locks_are_ended_by_the_server_soon_after_a_network_cut(pg_url: str) -> None:
    """A network cut (not a restart) left the server the sessions holding the console's name and its vehicles: with
    its default keepalives (two hours idle) the name was refused as another console's and no console wrote those
    vehicles' tracks for hours after the console reconnected. Those sessions ask the server to probe them soon."""
    db = open_db(pg_url)
    writers = VehicleWriters(db.engine)
    try:
        db.claim("watch")
        assert writers.mine({V1}) == {V1}
        for c in (db.name_lock.lock, writers._conn):  # the name's session, the vehicles' session (over TCP: 127.0.0.1)
            assert isinstance(c, Connection)
            assert [c.execute(text(f"SHOW tcp_keepalives_{s}")).scalar() for s in ("idle", "interval", "count")] == [
                "5",
                "2",
                "2",
            ]
    finally:
        writers.close()
        db.close()


@pytest.mark.parametrize(
    "url", ["postgresql://u:s3cret@127.0.0.1:abc/db", "postgresql://u:s3cret@h:5432/", "mysql://u:s3cret@h/db"]
)
def test_a_bad_database_url_is_one_line_naming_the_option_never_the_password(url: str) -> None:
    with pytest.raises(ValueError) as refused:
        parse_database_url(url)
    line = str(refused.value)
    assert line.startswith("--database-url") and "\n" not in line and "s3cret" not in line, line


def fix_at(lat: float, lon: float) -> dict[str, Any]:
    """A GPSFixReport's JSON with a valid position."""
    return {
        "position2DWithTime": {
            "geodeticPosition": {"geodeticLatitude": {"latitude": lat}, "geodeticLongitude": {"longitude": lon}}
        },
        "GPSLatLongValid": True,
    }


def test_a_vehicle_whose_fixes_stop_keeps_its_last_position_on_the_track(database_url: str) -> None:
    db = open_db(database_url)
    history = History(db.engine, retention_hours=24, thinning=Thinning(5.0, 10.0, math.inf, 60.0))
    gone, running = uuid.uuid4(), uuid.uuid4()
    origin = Local(10.0, 20.0)

    async def run() -> tuple[list[TrackPoint], list[TrackPoint]]:
        t0 = time.time() - 30
        for k in range(5):  # 1 m a second, then nothing: a vehicle lost 25 s ago
            history.on_fix(gone, t0 + k, fix_at(*origin.latlon(float(k), 0.0)), [], True)
        await history.flush()
        task = asyncio.create_task(history.run())
        await asyncio.sleep(0.05)
        now = time.time()
        for k in range(4):
            history.on_fix(running, now + k, fix_at(*origin.latlon(0.0, float(k))), [], True)
        task.cancel()  # the console stops
        with contextlib.suppress(asyncio.CancelledError):
            await task
        return await history.track(gone, None, None), await history.track(running, None, None)

    try:
        lost, stopped = asyncio.run(run())
        assert [round(origin.xy(p.latitude, p.longitude)[0], 3) for p in lost] == [0.0, 4.0], lost
        assert [round(origin.xy(p.latitude, p.longitude)[1], 3) for p in stopped] == [0.0, 3.0], stopped
        assert gone not in history._stored and not history._unstored  # the lost vehicle is forgotten
    finally:
        db.close()


def old_points(provider: str, start: float, seconds: int) -> list[dict[str, Any]]:
    return [track_point(provider, start + k, fix_at(1.0, 2.0), [], True) or {} for k in range(seconds)]


def test_a_backlog_of_old_history_is_rolled_up_a_minute_per_transaction_skipping_empty_time(database_url: str) -> None:
    db = open_db(database_url)
    history = History(db.engine, retention_hours=24, thinning=Thinning(0.0, 0.0, 3600.0, 60.0))
    vehicles = [str(uuid.uuid4()) for _ in range(3)]
    minute = math.floor(time.time() / 60) * 60
    # ten minutes 8 hours ago and ten 2 hours ago, a point a second each: a console started on a day's history
    blocks = (minute - 8 * 3600, minute - 2 * 3600)
    history._track = [p for v in vehicles for b in blocks for p in old_points(v, b, 600)]

    def per_minute() -> Counter[float]:
        with Session(db.engine) as s:
            return Counter(math.floor(t / 60) * 60 for t in s.exec(select(TrackPoint.time)).all())

    async def run() -> Counter[float]:
        await history.flush()
        first = per_minute()
        await history.flush()  # a step: the same minute again (points were written in it: they could have been held)
        read = per_minute()
        await history.track(uuid.UUID(vehicles[0]), None, None)  # a read waits for no step of the rollup
        assert per_minute() == read
        for _ in range(20):  # a minute a flush, and the 5 h 50 min between the two blocks in one step
            await history.flush()
        return first

    try:
        first = asyncio.run(run())
        assert first[blocks[0]] == 3 and first[blocks[0] + 60] == 180 and first[blocks[1]] == 180, first
        assert per_minute() == {b + 60 * k: 3 for b in blocks for k in range(10)}
        assert history.rows_rolled_up == 2 * 10 * 3 * 59
    finally:
        db.close()


def test_the_rollup_keeps_each_change_of_gps_lat_long_valid_and_fix_valid_at_its_time(database_url: str) -> None:
    db = open_db(database_url)
    history = History(db.engine, retention_hours=24, thinning=Thinning(0.0, 0.0, 3600.0, 60.0))
    ins, fix, steady = (str(uuid.uuid4()) for _ in range(3))
    minute = math.floor(time.time() / 60) * 60 - 2 * 3600
    # one vehicle from its INS (GPSLatLongValid false) for 10 s, one whose fix went invalid, one with no fix status
    history._track = [{**p, "latLongValid": not 20 <= k < 30} for k, p in enumerate(old_points(ins, minute, 60))]
    history._track += [{**p, "fixValid": k < 40} for k, p in enumerate(old_points(fix, minute, 60))]
    history._track += [{**p, "fixValid": None} for p in old_points(steady, minute, 60)]

    async def run() -> dict[str, list[tuple[float, bool, bool | None]]]:
        await history.flush()
        return {
            v: [(p.time - minute, p.latLongValid, p.fixValid) for p in await history.track(uuid.UUID(v), None, None)]
            for v in (ins, fix, steady)
        }

    try:
        kept = asyncio.run(run())
        assert kept[ins] == [(0, True, True), (20, False, True), (30, True, True)], kept[ins]
        assert kept[fix] == [(0, True, True), (40, True, False)], kept[fix]
        assert kept[steady] == [(0, True, None)], kept[steady]
    finally:
        db.close()


@pytest.mark.postgres
def test_a_console_does_not_wait_for_another_rolling_up_the_same_history(pg_url: str) -> None:
    a, b = open_db(pg_url), open_db(pg_url)
    thinning = Thinning(0.0, 0.0, 3600.0, 60.0)
    first, second = History(a.engine, 24, thinning=thinning), History(b.engine, 24, thinning=thinning)
    minute = math.floor(time.time() / 60) * 60 - 2 * 3600
    loader = History(a.engine, 24)
    loader._track = [p for v in range(3) for p in old_points(str(uuid.uuid4()), minute, 120)]
    asyncio.run(loader.flush())
    loader.close()

    deleting = threading.Event()

    def slow(conn: Connection, cursor: Any, statement: str, *args: Any) -> None:
        if statement.lstrip().upper().startswith("DELETE FROM TRACK") and "EXISTS" in statement.upper():
            deleting.set()
            time.sleep(6)  # the first console's rollup, rows deleted, not committed yet

    event.listen(a.engine, "after_cursor_execute", slow)
    try:
        rolling = threading.Thread(target=lambda: asyncio.run(first.flush()))
        rolling.start()
        assert deleting.wait(30)
        started = time.monotonic()
        asyncio.run(second.flush())
        waited = time.monotonic() - started
        rolling.join()
        assert waited < 3, waited
        assert first.rows_rolled_up == 3 * 59 and second.rows_rolled_up == 0
    finally:
        event.remove(a.engine, "after_cursor_execute", slow)
        for h in (first, second):
            h.close()
        a.close()
        b.close()
