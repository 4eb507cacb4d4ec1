"""Vehicle names set from the dashboard (PUT /api/providers/{id}/name) on one console with its SQLite file: the
stored name is over --vehicle-names, is kept across a restart, names the vehicle in new alarms; bad names are
refused in one line; empty goes back to the configured name."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from conftest import ConsoleProcess
from support import http
from test_console import V1, WsClient, provider_ready, wait_until

AUTH = {"Authorization": "Bearer secret-1"}


def rename_heard(put_url: str, name: str, ws: WsClient, headers: dict[str, str] | None = None) -> None:
    """PUT the name; the WebSocket `ws` (this console's or another's) then says so in a `provider` message."""
    r = http.put(put_url, json={"name": f"  {name} "}, headers=headers)
    assert r.status_code == 200 and r.json()["name"] == name, r.text
    try:
        wait_until(
            lambda: any(m["event"] == "configured" and m["provider"]["name"] == name for m in ws.of("provider")),
            10,
            f"{name!r} on the WebSocket",
        )
        assert not ws.errors, ws.errors
    finally:
        ws.close()


def test_a_name_set_from_the_dashboard_is_stored_shown_and_refused_when_bad(
    sim: Callable[..., Any], console: Callable[..., ConsoleProcess]
) -> None:
    vehicle = sim()
    args = ("--operator-tokens", "alice:secret-1", "--vehicle-names", f"{V1}=Alpha")
    c = console(*args)
    assert provider_ready(c.url, V1, {"GPSFixReport"})["name"] == "Alpha"
    url = f"{c.url}/api/providers/{V1}/name"
    assert http.put(url, json={"name": "Bravo"}).status_code == 401
    for bad, why in (
        ({"name": "x" * 41}, "at most 40"),
        ({"name": "tab\there"}, "printable"),
        ({"name": "x\u202ex"}, "printable"),
        ({"name": "\u200b"}, "printable"),
        ({}, "name"),
        ({"name": 7}, "name"),
    ):
        r = http.put(url, json=bad, headers=AUTH)
        assert r.status_code == 422 and why in r.json()["detail"] and "\n" not in r.json()["detail"], r.text
    assert (
        http.put(f"{c.url}/api/providers/00000000-0000-0000-0000-000000000001/name", json={"name": "Z"}, headers=AUTH).status_code
        == 404
    )
    rename_heard(url, "Bravo 2", WsClient(c.ws_url), AUTH)
    assert http.get(f"{c.url}/api/providers/{V1}").json()["name"] == "Bravo 2"
    audit = http.get(f"{c.url}/api/audit").json()
    assert any(
        a["path"].endswith("/name")
        and a["outcome"] == "accepted"
        and a["operator"] == "alice"
        and a["sessionId"] == "name:Bravo 2"
        for a in audit
    )
    assert {401, 404, 422} <= {a["status"] for a in audit if a["path"].endswith("/name") and a["outcome"] == "refused"}
    c.stop()
    again = console(*args)  # a restart: the stored name is over --vehicle-names
    assert provider_ready(again.url, V1, {"GPSFixReport"})["name"] == "Bravo 2"
    vehicle.kill()  # a new alarm names the vehicle by its stored name
    lost = wait_until(
        lambda: next((x for x in http.get(f"{again.url}/api/alarms").json() if x["kind"] == "link-lost"), None), 15, "link-lost"
    )
    assert "Bravo 2" in lost["text"], lost
    r = http.put(f"{again.url}/api/providers/{V1}/name", json={"name": "  "}, headers=AUTH)  # back to --vehicle-names
    assert r.status_code == 200 and r.json()["name"] == "Alpha", r.text
    assert http.put(f"{again.url}/api/providers/{V1}/name", json={"name": None}, headers=AUTH).json()["name"] == "Alpha"
