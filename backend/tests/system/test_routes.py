"""Route validation through FastAPI's TestClient: the app of `sem-console` in this process, its lifespan run by
the client, on a fresh DDS domain with real Cyclone; the embedded simulator (`--sim 1`) is the known vehicle V1.

Each case is a request the console refuses, so none changes what the next one sees, and one app serves them all.
Processes are what tests/test_console.py tests; here only the HTTP answers are."""

from __future__ import annotations

import logging
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import pytest
from fastapi.testclient import TestClient

from conftest import free_domain
from sem_console.api.auth import FREE_FAILURES
from sem_console.core.config import Settings
from sem_console.main import create_app
from sem_console.sim.provider import vehicle_guid
from test_security import TOKENS

V1 = str(vehicle_guid(1))
UNKNOWN = "00000000-0000-4000-8000-000000000000"


# the timers of tests/conftest.py's ConsoleProcess
TIMERS: dict[str, Any] = {"comms_lost_timeout": 1, "regained_time": 1, "unanswered_timeout": 2}


@contextmanager
def app_client(tmp: Path, peer: tuple[str, int] = ("testclient", 50000), **options: Any) -> Iterator[TestClient]:
    """The app of `sem-console` with these `Settings` on a fresh domain, once V1 is known; `peer`: the client's
    address as the app sees it; a SQLite file in `tmp` unless `database_url` is given."""
    database = {} if "database_url" in options else {"db_path": tmp / "console.sqlite3"}
    settings = Settings(
        domain=free_domain(),
        recordings_dir=tmp / "recordings",
        console_name="test-console",
        sim=1,
        **{**database, **TIMERS, **options},
    )
    # an allowed Host (the guard refuses TestClient's default "testserver")
    with TestClient(create_app(settings), base_url="http://127.0.0.1", client=peer) as c:
        wait_until(lambda: c.get(f"/api/providers/{V1}").status_code == 200, what="the embedded simulator's vehicle")
        yield c


def wait_until(predicate: Callable[[], Any], timeout: float = 60, what: str = "condition") -> Any:
    """A wait, not a timed assertion: generous for a loaded machine."""
    deadline = time.monotonic() + timeout
    while not (result := predicate()):
        assert time.monotonic() < deadline, f"no {what} within {timeout} s"
        time.sleep(0.1)
    return result


@pytest.fixture(scope="module")
def client(tmp_path_factory: pytest.TempPathFactory) -> Iterator[TestClient]:
    with app_client(tmp_path_factory.mktemp("routes")) as c:
        yield c


@pytest.mark.parametrize(
    "method,path,body,code,needle",
    [
        ("GET", "/api/providers/not-a-uuid", None, 422, "provider_id"),
        ("GET", f"/api/providers/{UNKNOWN}", None, 404, "no provider"),
        ("POST", "/api/providers/xyz/gps-fix", {}, 422, "provider_id"),
        ("POST", f"/api/providers/{UNKNOWN}/gps-fix", {}, 404, "no provider"),
        ("POST", f"/api/providers/{V1}/gps-fix", None, 415, "Content-Type: application/json"),
        ("POST", f"/api/providers/{V1}/gps-fix", {"force": True}, 422, "body.force"),
        (
            "POST",
            f"/api/providers/{V1}/inertial-sensor",
            {"state": "SIDEWAYS"},
            422,
            "'OFF', 'ON', 'RESTARTING', 'BEST_ALIGN', 'GPS_ALIGN', 'INIT', 'SNAP_ALIGN', 'STATIONARY_ALIGN' or 'TRANSFER_ALIGN'",
        ),
        ("POST", f"/api/providers/{V1}/inertial-sensor", {"state": 1}, 422, "body.state"),
        ("POST", f"/api/providers/{V1}/inertial-sensor", {}, 422, "body.state: Field required"),
        ("POST", f"/api/providers/{V1}/inertial-sensor", "{not json", 422, "the body is not valid JSON (at character 2)"),
        ("POST", f"/api/providers/{V1}/inertial-sensor", '{"state": }', 422, "the body is not valid JSON (at character 11)"),
        ("POST", f"/api/providers/{V1}/inertial-sensor", {"state": "ON", "extra": 1}, 422, "body.extra"),
        ("POST", f"/api/providers/{UNKNOWN}/inertial-sensor", {"state": "ON"}, 404, "no provider"),
        ("DELETE", "/api/commands/42", None, 422, "session_id"),
        ("DELETE", f"/api/commands/{UNKNOWN}", None, 404, "no command"),
        ("GET", "/api/commands/42", None, 422, "session_id"),
        ("GET", "/api/commands?limit=0", None, 422, "query.limit"),
        ("GET", "/api/commands?offset=-1", None, 422, "query.offset"),
        ("GET", "/api/commands?limit=many", None, 422, "query.limit"),
        ("GET", f"/api/commands/{UNKNOWN}", None, 404, "no command"),
        ("GET", "/api/commands?provider_id=7", None, 422, "query.provider_id"),
        ("GET", f"/api/providers/{UNKNOWN}/track", None, 404, "no provider"),
        ("GET", f"/api/providers/{UNKNOWN}/track.gpx", None, 404, "no provider"),
        ("GET", f"/api/providers/{V1}/track?since=yesterday", None, 422, "query.since"),
        ("GET", f"/api/providers/{V1}/series?until=2026-13-01T00:00:00Z", None, 422, "query.until"),
        ("GET", f"/api/providers/{V1}/track.csv?until=1795393808.5", None, 422, "query.until: Value error, expected an ISO 8601"),
        ("GET", "/api/commands.csv?since=soon", None, 422, "query.since"),
    ],
)
def test_every_route_rejects_bad_input(client: TestClient, method: str, path: str, body: Any, code: int, needle: str) -> None:
    kwargs: dict[str, Any] = {}
    if isinstance(body, str):
        kwargs = {"content": body, "headers": {"content-type": "application/json"}}
    elif body is not None:
        kwargs = {"json": body}
    r = client.request(method, path, **kwargs)
    assert r.status_code == code and needle in r.json()["detail"], r.text


# ---- security: what only the HTTP answers show (tests/test_security.py keeps what crosses a process) ----
SLOW = 30  # a first wait long enough that a loaded machine's slow requests still fall inside it


def test_an_operators_refused_commands_are_recorded(tmp_path: Path) -> None:
    """Every command request, accepted or refused: a bad body (422), an unknown vehicle or command
    (404), a finished command (409), with the operator's name."""
    # the simulator ten times faster: the INS's 12 s alignment to ON in 1.2 s, which no assertion depends on
    with app_client(tmp_path, operator_tokens="alice:s3cret", throttle_first_wait=SLOW, sim_time_scale=0.1) as c:
        alice = {"Authorization": "Bearer s3cret"}
        done = c.post(f"/api/providers/{V1}/inertial-sensor", json={"state": "ON"}, headers=alice).json()["sessionId"]
        wait_until(
            lambda: (lambda x: x["terminal"] and x["cleanedUp"])(c.get(f"/api/commands/{done}").json()),
            what=f"command {done} to finish",
        )
        unknown = "00000000-0000-0000-0000-000000000001"
        for method, path, body, status in (
            ("POST", f"/api/providers/{V1}/inertial-sensor", {"state": "SIDEWAYS"}, 422),
            ("POST", f"/api/providers/{V1}/gps-fix", {"extra": 1}, 422),
            ("POST", f"/api/providers/{unknown}/gps-fix", {}, 404),
            ("DELETE", f"/api/commands/{unknown}", None, 404),
            ("DELETE", f"/api/commands/{done}", None, 409),
            # refused before the token check ran (the body is read first): the
            # operator of the valid token it carries, not null
            ("POST", f"/api/providers/{V1}/gps-fix", b"{nope", 422),
            ("POST", f"/api/providers/{V1}/gps-fix", b"[" + b"0," * (1 << 20) + b"0]", 413),
        ):
            raw = (
                {"content": body, "headers": {**alice, "content-type": "application/json"}}
                if isinstance(body, bytes)
                else {"json": body, "headers": alice}
            )
            r = c.request(method, path, **raw)
            assert r.status_code == status, (method, path, r.text[:200])
        trail = list(reversed(c.get("/api/audit").json()))
        refusals = (("POST", 422), ("POST", 422), ("POST", 404), ("DELETE", 404), ("DELETE", 409), ("POST", 422), ("POST", 413))
        assert [(a["outcome"], a["status"], a["method"], a["operator"]) for a in trail] == [
            ("accepted", 201, "POST", "alice")
        ] + [("refused", s, m, "alice") for m, s in refusals]
        assert "body.state" in trail[1]["reason"] and "already finished" in trail[5]["reason"]
        assert trail[6]["reason"] == "the body is not valid JSON (at character 2)"
        wrong = c.post(
            f"/api/providers/{V1}/gps-fix",
            content=b"{nope",
            headers={"Authorization": "Bearer guess", "content-type": "application/json"},
        )
        assert wrong.status_code == 422 and c.get("/api/audit").json()[0]["operator"] is None  # a wrong token names no one
        assert c.get(f"/api/commands/{unknown}").status_code == 404  # a read's 404 is no refusal of a command
        assert len(c.get("/api/audit").json()) == 9


def test_tokens_file_bad_tokens_slowed_down_and_audited(tmp_path: Path) -> None:
    tokens = tmp_path / "tokens"
    tokens.write_text(TOKENS)
    tokens.chmod(0o600)
    with app_client(tmp_path, operator_tokens_file=tokens, operator_tokens="carol:c4rol", throttle_first_wait=SLOW) as c:
        url = f"/api/providers/{V1}/gps-fix"

        def post(token: str) -> Any:
            return c.post(url, json={}, headers={"Authorization": f"Bearer {token}"})

        assert post("s3cret").json()["operator"] == "alice"
        assert post("t0k:en").json()["operator"] == "bob"  # the name ends at the first colon
        assert post("c4rol").json()["operator"] == "carol"  # the environment's tokens count too
        assert c.get("/api/operator", headers={"Authorization": "Bearer t0k:en"}).json() == {"operator": "bob"}
        for _ in range(FREE_FAILURES - 1):
            assert post("guess").status_code == 401
        r = post("guess")  # the FREE_FAILURES-th wrong token: from here on the client waits
        assert r.status_code == 401
        r = post("s3cret")
        assert r.status_code == 429 and int(r.headers["Retry-After"]) >= 1
        assert "too many wrong operator tokens" in r.json()["detail"]
        assert c.get("/api/operator", headers={"Authorization": "Bearer s3cret"}).status_code == 429
        assert c.get("/api/providers").status_code == 200  # reads stay open without --auth-reads
        trail = c.get("/api/audit").json()
        refused = [a for a in trail if a["outcome"] == "refused"]
        assert [(a["status"], a["method"]) for a in refused] == [(429, "GET"), (429, "POST")] + [(401, "POST")] * FREE_FAILURES
        assert refused[-1]["reason"] == "the operator token is not valid" and refused[-1]["operator"] is None
        assert [a["operator"] for a in trail if a["outcome"] == "accepted"] == ["carol", "bob", "alice"]


def test_refusals_per_client_are_rate_limited_and_bad_tokens_recorded_on_any_route(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    caplog.set_level(logging.WARNING, logger="sem-console")  # what sem-console --log-level warning prints
    with app_client(
        tmp_path, peer=("127.0.0.1", 50000), operator_tokens="alice:s3cret", audit_refusals_per_minute=5, throttle_first_wait=SLOW
    ) as c:
        alice = {"Authorization": "Bearer s3cret"}
        assert c.post(f"/api/providers/{V1}/gps-fix", json={}, headers=alice).status_code == 201
        assert c.get("/api/operator").status_code == 401  # no token on a read: logged, not recorded
        assert c.get("/api/operator", headers={"Authorization": "Bearer nope"}).status_code == 401  # the sign-in check
        for _ in range(30):  # wrong tokens, then the slow-down's 429s: one client
            r = c.post(f"/api/providers/{V1}/gps-fix", json={}, headers={"Authorization": "Bearer guess"})
            assert r.status_code in (401, 429)
        trail = c.get("/api/audit", headers=alice).json()
        assert [(a["outcome"], a["status"], a["method"]) for a in reversed(trail)] == [
            ("accepted", 201, "POST"),
            ("refused", 401, "GET"),
        ] + [("refused", 401, "POST")] * 3 + [("rate-limited", 401, "POST")]
        assert trail[-2]["path"] == "/api/operator" and trail[-2]["reason"] == "the operator token is not valid"
        assert "more than 5 refusals from 127.0.0.1 within a minute" in trail[0]["reason"]
    out = "\n".join(r.getMessage() for r in caplog.records if r.levelno >= logging.WARNING)
    assert "refused GET '/api/operator' from 127.0.0.1 (origin None): 401 'the operator token is not valid'" in out
    assert out.count("refused POST") == 4 and "more than 5 refusals from 127.0.0.1 within a minute" in out
