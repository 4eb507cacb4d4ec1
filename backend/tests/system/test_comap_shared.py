"""The CoMap world model and tasks shared by the consoles of one database (an operations centre): real consoles,
a real sem-sim over IMC on 127.0.0.1 and a real PostgreSQL (tests/pg.py); and kept across a restart on SQLite."""

from __future__ import annotations

import concurrent.futures
from collections.abc import Callable
from typing import Any

import psycopg
import pytest

from conftest import ConsoleProcess, free_udp_port
from sem_console.comap.c2 import FINAL
from sem_console.storage.database import Database
from sem_console.storage.url import parse_database_url
from support import http
from support.pg import Cluster
from test_comap import V1, capabilities, last_position, polygon_feature, square
from test_console import WsClient, wait_until


def task_heard(ws: WsClient, tid: int, state: str) -> dict[str, Any] | None:
    """The first `task` message of task `tid` in `state` on this WebSocket."""
    return next((m["task"] for m in ws.of("task") if m["task"]["taskId"] == tid and m["task"]["state"] == state), None)


def task(c: ConsoleProcess, tid: int) -> dict[str, Any]:
    return http.get(f"{c.url}/api/tasks/{tid}").json()


def comap_args(c_port: int, s_port: int, imc_id: str) -> tuple[str, ...]:
    return (
        "--imc-port",
        str(c_port),
        "--imc-host",
        "127.0.0.1",
        "--imc-peers",
        f"127.0.0.1:{s_port}",
        "--imc-id",
        imc_id,
        "--imc-vehicles",
        f"{V1}=0x2001",
    )


@pytest.mark.slow
def test_world_model_and_tasks_reach_the_other_console_which_synchs_and_a_restart_keeps_them(
    sim: Callable[..., Any], console: Callable[..., ConsoleProcess], pg_url: str
) -> None:
    """A puts the world model and assigns a survey; B (CoMap on, its own IMC port) hears both on its WebSocket and
    answers GETs as A does; C (CoMap off) is refused a synch in one line naming A; B holds and interrupts the task
    itself (it has a CoMap link to the vehicle) and A sees it; A restarted still has the world model and the task."""
    a_port, b_port, s_port = free_udp_port(), free_udp_port(), free_udp_port()
    sim(
        "--imc-port",
        str(s_port),
        "--imc-host",
        "127.0.0.1",
        "--imc-id",
        "0x2001",
        "--imc-peers",
        f"127.0.0.1:{a_port}",
        "--time-scale",
        "0.02",
        "--survey-spacing",
        "50",
        "--survey-speed",
        "1",
    )
    a_args = ("--database-url", pg_url, "--console-name", "watch", *comap_args(a_port, s_port, "0x4001"))
    a = console(*a_args)
    b = console("--database-url", pg_url, "--console-name", "relief", *comap_args(b_port, s_port, "0x4002"))
    off = console("--database-url", pg_url, "--console-name", "night")
    ws_b = WsClient(b.ws_url)
    try:
        here = last_position(a.url)
        capabilities(a.url)
        put = http.put(
            f"{a.url}/api/worldmodel", json={"type": "FeatureCollection", "features": [polygon_feature(square(here, 50, 400), 7)]}
        )
        assert put.status_code == 200, put.text
        heard = wait_until(
            lambda: next(
                (m["worldModel"] for m in ws_b.of("worldmodel") if m["worldModel"]["updatedAt"] == put.json()["updatedAt"]), None
            ),
            10,
            "A's world model on B's WebSocket",
        )
        assert heard == put.json() == http.get(f"{b.url}/api/worldmodel").json() and heard["source"] == "operator"

        r = http.post(f"{a.url}/api/tasks", json={"kind": "survey", "vehicle": V1, "featureId": 7})
        assert r.status_code == 201 and r.json()["station"] == "watch", r.text
        tid = r.json()["taskId"]
        on_b = wait_until(lambda: task_heard(ws_b, tid, "IN_PROGRESS"), 20, "A's task IN_PROGRESS on B's WebSocket")
        assert on_b["station"] == "watch" and on_b["vehicle"] == V1 and on_b["featureId"] == 7
        wait_until(lambda: task(b, tid) == task(a, tid), 10, "the same task on A and B")
        assert [t["taskId"] for t in http.get(f"{b.url}/api/tasks").json()] == [tid]

        r = http.post(f"{off.url}/api/tasks/{tid}/synch", json={"action": "HOLD"})  # no CoMap link: refused
        assert r.status_code == 409 and "'watch'" in r.json()["detail"] and "\n" not in r.json()["detail"], r.text
        assert http.get(f"{b.url}/api/comap").json()["counters"].get("sent", 0) == 0
        r = http.post(f"{b.url}/api/tasks/{tid}/synch", json={"action": "HOLD"})  # B sends it itself
        assert r.status_code == 200 and r.json()["state"] == "HELD" and r.json()["station"] == "watch", r.text
        assert http.get(f"{b.url}/api/comap").json()["counters"]["sent"] == 1
        wait_until(lambda: task(a, tid)["state"] == "HELD", 10, "B's HOLD on A")
        assert http.post(f"{b.url}/api/tasks/{tid}/synch", json={"action": "INTERRUPT"}).json()["state"] == "INTERRUPTED"
        done = wait_until(lambda: (t := task(a, tid))["state"] == "INTERRUPTED" and t, 10, "B's INTERRUPT on A")
        assert done["synch"] == "INTERRUPT" and done["progress"] < 100
        assert not ws_b.errors, ws_b.errors
    finally:
        ws_b.close()
    world = http.get(f"{a.url}/api/worldmodel").json()
    a.stop()
    again = console(*a_args)
    assert http.get(f"{again.url}/api/worldmodel").json() == world
    assert task(again, tid) == task(b, tid)


@pytest.mark.slow
def test_a_restart_keeps_the_world_model_and_tasks_on_sqlite(console: Callable[..., ConsoleProcess]) -> None:
    args = comap_args(free_udp_port(), free_udp_port(), "0x4001")  # no vehicle needed: the task stays ASSIGNED
    c = console(*args)
    point = {"type": "Feature", "properties": {"name": "buoy"}, "geometry": {"type": "Point", "coordinates": [-8.7, 41.2]}}
    world = http.put(f"{c.url}/api/worldmodel", json={"type": "FeatureCollection", "features": [point]}).json()
    first = http.post(f"{c.url}/api/tasks", json={"kind": "survey", "vehicle": V1, "featureId": 1}).json()
    assert first["station"] == "test-console" and first["state"] == "ASSIGNED"
    c.stop()
    again = console(*args)
    assert http.get(f"{again.url}/api/worldmodel").json() == world
    assert http.get(f"{again.url}/api/tasks").json() == [first]
    # the ids go on (not from 1 again: the vehicle may still run task 1), and a new feature is numbered above 1
    assert (
        http.post(f"{again.url}/api/tasks", json={"kind": "move", "vehicle": V1, "point": {"lat": 41.2, "lon": -8.7}}).json()[
            "taskId"
        ]
        == 2
    )
    r = http.put(f"{again.url}/api/worldmodel", json={"type": "FeatureCollection", "features": [point, point]})
    assert [f["properties"]["featureId"] for f in r.json()["features"]] == [2, 3], r.text


@pytest.mark.slow
def test_task_ids_never_collide_between_consoles(console: Callable[..., ConsoleProcess], pg_url: str) -> None:
    """Two consoles assigning at once on one database: every id once (each console alone would count from 1)."""
    a = console("--database-url", pg_url, "--console-name", "watch", *comap_args(free_udp_port(), free_udp_port(), "0x4001"))
    b = console("--database-url", pg_url, "--console-name", "relief", *comap_args(free_udp_port(), free_udp_port(), "0x4002"))

    def assign(c: ConsoleProcess) -> int:
        r = http.post(f"{c.url}/api/tasks", json={"kind": "move", "vehicle": V1, "point": {"lat": 1, "lon": 2}})
        assert r.status_code == 201, r.text
        return int(r.json()["taskId"])

    with concurrent.futures.ThreadPoolExecutor(8) as pool:
        ids = list(pool.map(assign, [a, b] * 15))
    assert sorted(ids) == list(range(1, 31))
    for c in (a, b):  # each lists every task, the other's too, with its station
        wait_until(lambda c=c: len(http.get(f"{c.url}/api/tasks").json()) == 30, 10, "all 30 tasks")
        assert {t["station"] for t in http.get(f"{c.url}/api/tasks").json()} == {"watch", "relief"}


def test_task_ids_wrap_and_run_out_across_stations(database_url: str) -> None:
    """The u16 ids: after 65534 comes 1; ids of unfinished tasks are skipped, whichever station has them; when every
    id is taken by an unfinished task there is none (the route answers 409)."""
    one, two = Database(parse_database_url(database_url)), Database(parse_database_url(database_url))
    try:
        one.claim("watch", hold=False)
        two.claim("relief", hold=False)
        row = {
            "task_id": 0,
            "kind": "move",
            "vehicle": V1,
            "imc_id": 0x2001,
            "operator": None,
            "feature_id": None,
            "sensor": None,
            "resolution": None,
            "deadline": 1e10,
            "point": {"lat": 1.0, "lon": 2.0},
            "state": "ASSIGNED",
            "progress": 0,
            "quality": None,
            "created_at": 1.0,
            "updated_at": 1.0,
            "state_at": 1.0,
            "last_synch": None,
        }
        final = frozenset(FINAL)
        assert one.new_comap_task({**row, "station": "watch"}, final) == 1
        assert two.new_comap_task({**row, "station": "relief"}, final) == 2
        with one.engine.begin() as c:  # every other id but 65534 taken by an unfinished task; task 1 finished
            c.exec_driver_sql("UPDATE comap_task_ids SET next_task = 65533")
            c.exec_driver_sql("UPDATE comap_tasks SET state = 'COMPLETED' WHERE task_id = 1")
            c.exec_driver_sql(
                "WITH RECURSIVE n(i) AS (SELECT 3 UNION ALL SELECT i + 1 FROM n WHERE i < 65533) "
                "INSERT INTO comap_tasks (task_id, kind, vehicle, imc_id, state, progress, created_at, updated_at, station) "
                f"SELECT i, 'move', '{V1}', 8193, 'IN_PROGRESS', 0, 1.0, 1.0, 'relief' FROM n"
            )
        assert one.new_comap_task({**row, "station": "watch"}, final) == 65534
        assert two.new_comap_task({**row, "station": "relief"}, final) == 1  # wrapped; the finished task 1 replaced
        assert [t["station"] for t in one.comap_tasks(1)] == ["relief"]
        assert one.new_comap_task({**row, "station": "watch"}, final) is None
        assert two.new_comap_task({**row, "station": "relief"}, final) is None
    finally:
        one.close()
        two.close()


@pytest.mark.slow
def test_a_database_outage_keeps_comap_working_and_writes_it_after(
    console: Callable[..., ConsoleProcess], pg_cluster: Cluster, pg_url: str
) -> None:
    """PostgreSQL stopped: A's world model and a synch of its task go on (held), a new task is refused in one line
    (its id is taken in the database); started again, B reads and hears what A changed."""
    a = console("--database-url", pg_url, "--console-name", "watch", *comap_args(free_udp_port(), free_udp_port(), "0x4001"))
    b = console("--database-url", pg_url, "--console-name", "relief")
    move = {"kind": "move", "vehicle": V1, "point": {"lat": 1, "lon": 2}}
    tid = http.post(f"{a.url}/api/tasks", json=move).json()["taskId"]
    wait_until(lambda: http.get(f"{b.url}/api/tasks/{tid}").status_code == 200, 10, "the task on B")
    ws_b = WsClient(b.ws_url)
    point = {"type": "Feature", "properties": {}, "geometry": {"type": "Point", "coordinates": [2, 1]}}
    pg_cluster.stop()
    try:
        put = http.put(f"{a.url}/api/worldmodel", json={"type": "FeatureCollection", "features": [point]})
        assert put.status_code == 200, put.text
        assert http.post(f"{a.url}/api/tasks/{tid}/synch", json={"action": "HOLD"}).json()["state"] == "HELD"
        r = http.post(f"{a.url}/api/tasks", json=move)
        assert r.status_code == 503 and "no new CoMap task" in r.json()["detail"] and "\n" not in r.json()["detail"], r.text
        assert "pg-test-s3cret" not in r.text
        assert http.get(f"{a.url}/api/health").json()["databaseWritesHeld"] > 0
    finally:
        pg_cluster.start()
    try:
        wait_until(lambda: http.get(f"{a.url}/api/health").json()["databaseWritesHeld"] == 0, 20, "A's held writes written")
        wait_until(lambda: task_heard(ws_b, tid, "HELD"), 20, "the HOLD made during the outage on B's WebSocket")
        wait_until(lambda: http.get(f"{b.url}/api/worldmodel").json() == put.json(), 20, "A's world model on B")
        assert not ws_b.errors, ws_b.errors
    finally:
        ws_b.close()
    with psycopg.connect(pg_url) as db:
        assert db.execute("SELECT state, station FROM comap_tasks WHERE task_id = %s", (tid,)).fetchone() == ("HELD", "watch")


def test_task_ids_taken_at_once_by_one_console_on_sqlite(tmp_path: Any) -> None:
    """Assigns of one console at once (each in its own worker thread): every id once, none refused. SQLite has no
    FOR UPDATE: two read-then-write transactions at once would deadlock ('database is locked')."""
    db = Database(parse_database_url(f"sqlite:///{tmp_path / 'c.db'}"))
    try:
        db.claim("watch", hold=False)
        row = {
            "task_id": 0,
            "kind": "move",
            "vehicle": V1,
            "imc_id": 0x2001,
            "operator": None,
            "feature_id": None,
            "sensor": None,
            "resolution": None,
            "deadline": 1e10,
            "point": {"lat": 1.0, "lon": 2.0},
            "state": "ASSIGNED",
            "progress": 0,
            "quality": None,
            "created_at": 1.0,
            "updated_at": 1.0,
            "state_at": 1.0,
            "last_synch": None,
            "station": "watch",
        }
        with concurrent.futures.ThreadPoolExecutor(8) as pool:
            ids = list(pool.map(lambda _i: db.new_comap_task(row, frozenset(FINAL)), range(40)))
        assert sorted(ids) == list(range(1, 41))  # type: ignore[type-var]
    finally:
        db.close()
