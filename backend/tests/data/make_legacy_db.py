"""How tests/data/legacy-8592e59.sqlite3 was made: the console of commit 8592e59 (raw sqlite3 storage, before
SQLAlchemy and Alembic), in process with two simulated vehicles on a private DDS domain, driven through its REST API:
  - a GPS fix command to vehicle 1 that completes (transitions ISSUED .. COMPLETED), one canceled to vehicle 2;
  - a link configuration for vehicle 1; a refused and accepted requests in the audit trail;
  - a third vehicle heard a minute ago, so a link-lost alarm is raised, and acknowledged; the meta row 'source'.
Run from backend/ on that commit: `PYTHONPATH=. python tests/data/make_legacy_db.py OUT.sqlite3` (then VACUUM).
Kept for the record: it runs only on the old code (the one that wrote the file)."""

from __future__ import annotations

import random
import sqlite3
import sys
import time
import uuid
from pathlib import Path

from fastapi.testclient import TestClient

from sem_console.core.config import Settings
from sem_console.main import create_app
from sem_console.sim.options import vehicle_guid

V1, V2 = str(vehicle_guid(1)), str(vehicle_guid(2))
CHARLIE = uuid.UUID("3f2a9c01-0000-4000-8000-0000000000c3")  # a third vehicle, heard once a minute ago


def main(out: Path) -> None:
    out.unlink(missing_ok=True)
    settings = Settings(
        domain=random.randrange(150, 230),
        db_path=out,
        recordings_dir=out.parent / "recordings",
        sim=2,
        operator_tokens="alice:s3cret",
        vehicle_names=f"{V1}=Alpha,{V2}=Bravo",
    )
    auth = {"Authorization": "Bearer s3cret"}
    with TestClient(create_app(settings), base_url="http://localhost") as client:
        console = client.app.state.console  # type: ignore[attr-defined]
        deadline = time.monotonic() + 30
        while {p["id"] for p in client.get("/api/providers").json()} < {V1, V2}:
            assert time.monotonic() < deadline, "the simulated vehicles did not appear"
            time.sleep(0.2)
        time.sleep(2)  # their services discovered
        assert client.post(f"/api/providers/{V1}/gps-fix", json={}).status_code == 401  # refused: audited
        done = client.post(f"/api/providers/{V1}/gps-fix", json={}, headers=auth).json()["sessionId"]
        while client.get(f"/api/commands/{done}").json()["status"] != "COMPLETED":
            assert time.monotonic() < deadline + 60, client.get(f"/api/commands/{done}").json()
            time.sleep(0.2)
        r = client.put(
            f"/api/providers/{V1}/link-config",
            headers=auth,
            json={"commsLostTimeout": 7.5, "regainedTime": 2, "policy": "CONTINUE_MISSION", "regainedBehavior": 3},
        )
        assert r.status_code == 200, r.text
        canceled = client.post(f"/api/providers/{V2}/inertial-sensor", json={"state": "OFF"}, headers=auth).json()
        assert client.delete(f"/api/commands/{canceled['sessionId']}", headers=auth).status_code == 200
        time.sleep(2)

        def lost_a_minute_ago() -> None:  # on the console's loop: heard a minute ago, so it is lost
            now, wall = console.clock.monotonic(), console.clock.wall()
            console.providers.seen(
                "GPSReport", CHARLIE, {"report": {}, "invalid": [], "receivedAt": wall - 60}, now - 60, wall - 60, True
            )
            console.tick(now)

        client.portal.call(lost_a_minute_ago)
        alarms = client.get("/api/alarms").json()
        assert alarms, "no alarm"
        assert client.post(f"/api/alarms/{alarms[0]['id']}/ack", json={}, headers=auth).status_code == 200
    with sqlite3.connect(out) as db:
        db.execute("VACUUM")
        for table in ("meta", "commands", "transitions", "audit", "link_config", "alarms"):
            print(table, db.execute(f"SELECT count(*) FROM {table}").fetchone()[0])  # fixed names


if __name__ == "__main__":
    main(Path(sys.argv[1]))
