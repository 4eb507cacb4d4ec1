"""Route validation through FastAPI's TestClient: the app of `sem-console` in this process, its lifespan run by
the client, on a fresh DDS domain with real Cyclone; the embedded simulator (`--sim 1`) is the known vehicle V1.

Each case is a request the console refuses, so none changes what the next one sees, and one app serves them all.
Processes are what tests/test_console.py tests; here only the HTTP answers are."""

from __future__ import annotations

import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from fastapi.testclient import TestClient

from conftest import free_domain
from sem_console.core.config import Settings
from sem_console.main import create_app
from sem_console.sim.provider import vehicle_guid

V1 = str(vehicle_guid(1))
UNKNOWN = "00000000-0000-4000-8000-000000000000"


@pytest.fixture(scope="module")
def client(tmp_path_factory: pytest.TempPathFactory) -> Iterator[TestClient]:
    tmp: Path = tmp_path_factory.mktemp("routes")
    settings = Settings(domain=free_domain(), db_path=tmp / "console.sqlite3", recordings_dir=tmp / "recordings",
                        console_name="test-console", sim=1)
    # an allowed Host (the guard refuses TestClient's default "testserver")
    with TestClient(create_app(settings), base_url="http://127.0.0.1") as c:
        # a wait for the simulator's first report, not a timed assertion: generous for a loaded machine
        deadline = time.monotonic() + 60
        while c.get(f"/api/providers/{V1}").status_code != 200:
            assert time.monotonic() < deadline, "the embedded simulator's vehicle was not seen"
            time.sleep(0.1)
        yield c


@pytest.mark.parametrize("method,path,body,code,needle", [
    ("GET", "/api/providers/not-a-uuid", None, 422, "provider_id"),
    ("GET", f"/api/providers/{UNKNOWN}", None, 404, "no provider"),
    ("POST", "/api/providers/xyz/gps-fix", {}, 422, "provider_id"),
    ("POST", f"/api/providers/{UNKNOWN}/gps-fix", {}, 404, "no provider"),
    ("POST", f"/api/providers/{V1}/gps-fix", None, 415, "Content-Type: application/json"),
    ("POST", f"/api/providers/{V1}/gps-fix", {"force": True}, 422, "body.force"),
    ("POST", f"/api/providers/{V1}/inertial-sensor", {"state": "SIDEWAYS"}, 422, "'OFF', 'ON' or 'RESTARTING'"),
    ("POST", f"/api/providers/{V1}/inertial-sensor", {"state": 1}, 422, "body.state"),
    ("POST", f"/api/providers/{V1}/inertial-sensor", {}, 422, "body.state: Field required"),
    ("POST", f"/api/providers/{V1}/inertial-sensor", "{not json", 422, "JSON decode error"),
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
])
@pytest.mark.xdist_group("routes")  # with pytest-xdist's --dist loadgroup: every case on the worker holding `client`
def test_every_route_rejects_bad_input(client: TestClient, method: str, path: str, body: Any, code: int,
                                       needle: str) -> None:
    kwargs: dict[str, Any] = {}
    if isinstance(body, str):
        kwargs = {"content": body, "headers": {"content-type": "application/json"}}
    elif body is not None:
        kwargs = {"json": body}
    r = client.request(method, path, **kwargs)
    assert r.status_code == code and needle in r.json()["detail"], r.text
