"""DDS Security on the bus, on the secure build of Cyclone DDS (scripts/secure-build.sh; these tests skip, saying why,
without it): a fleet made by sem-keys, a secure console and a secure sem-sim, and what an open participant, a
read-only identity, an expired identity and a tampered governance get."""

from __future__ import annotations

import datetime as dt
import os
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

from sem_console.dds.config import loopback_config
from sem_console.dds.security import OPEN_BUS, plugins_missing
from sem_console.dds.topics import Service
from sem_console.keys.documents import Role
from sem_console.keys.fleet import Fleet
from sem_console.sim.provider import vehicle_guid
from support import http
from support.consumer import Consumer
from support.secure import secure_env
from test_console import HAPPY, REPORTS, V1, provider_ready, wait_command
from test_replay import synthetic_recording

ENV = secure_env()
pytestmark = pytest.mark.process
# the tests on the secure build: marked `security` (scripts/test runs them in a pass of their own, once the build is done)
secure = pytest.mark.skipif(isinstance(ENV, str), reason=f"no secure build of Cyclone DDS: {ENV}")
NOW = dt.datetime.now(dt.UTC)


def env() -> dict[str, str]:
    """The secure build's variables; none without it (the documents' own checks come before the plugins')."""
    return ENV if isinstance(ENV, dict) else {}


@pytest.fixture
def fleet(tmp_path: Path, domain: int) -> Path:
    """A fleet on the test's domain: a station, a vehicle, a read-only display, and a vehicle whose certificate
    expired yesterday."""
    folder = tmp_path / "fleet"
    f = Fleet(folder)
    f.init("Blue", [domain], 30, False, NOW - dt.timedelta(days=10))
    f.issue("ops-1", Role.STATION, 30, NOW)
    f.issue("usv-1", Role.VEHICLE, 30, NOW)
    f.issue("wall", Role.READONLY, 30, NOW)
    f.issue("usv-old", Role.VEHICLE, 1, NOW - dt.timedelta(days=2))
    return folder


def identity(fleet: Path, name: str) -> str:
    return str(fleet / "identities" / name)


def fix_valid(base: str) -> bool:
    return bool(http.get(f"{base}/api/providers/{V1}").json()["reports"]["GPSFixStatusReport"]["report"]["fixValid"])


@pytest.mark.security
@secure
def test_a_secure_console_and_sim_exchange_every_topic_and_commands_complete(sim, console, fleet: Path) -> None:
    sim("--dds-security", identity(fleet, "usv-1"), env=env())
    c = console("--dds-security", identity(fleet, "ops-1"), env=env())
    security = http.get(f"{c.url}/api/health").json()["ddsSecurity"]
    assert security["secured"] is True and security["identity"] == "ops-1"
    assert security["subject"] == "O=Blue,OU=station,CN=ops-1" and security["source"].endswith("identities/ops-1")
    provider_ready(c.url, V1, REPORTS)
    for service, state in ((Service.GPS_FIX, None), (Service.INERTIAL_SENSOR, "RESTARTING")):
        path = "gps-fix" if service is Service.GPS_FIX else "inertial-sensor"
        r = http.post(f"{c.url}/api/providers/{V1}/{path}", json={} if state is None else {"state": state})
        assert r.status_code == 201, r.text
        done = wait_command(c.url, r.json()["sessionId"], timeout=30)
        assert [t["status"] for t in done["transitions"]] == HAPPY


@pytest.mark.security
@secure
def test_a_participant_without_security_sees_nothing_and_commands_nothing(sim, console, fleet: Path, domain: int) -> None:
    sim("--dds-security", identity(fleet, "usv-1"), env=env())
    c = console("--dds-security", identity(fleet, "ops-1"), env=env())
    provider_ready(c.url, V1, REPORTS)
    assert not fix_valid(c.url)  # vehicles start submerged: a fix is what a GPS fix command would bring
    open_bus = Consumer(domain, "open")
    try:
        open_bus.command(Service.GPS_FIX, vehicle_guid(1))
        open_bus.command(Service.GPS_FIX, vehicle_guid(1))
        deadline = time.monotonic() + 8
        while time.monotonic() < deadline:
            open_bus.pump()
            time.sleep(0.1)
        assert not open_bus.reports and not open_bus.commands
    finally:
        open_bus.close()
    assert not fix_valid(c.url)  # the vehicle, heard all along by the secure console, never took the command


REFUSED_WRITER = textwrap.dedent(
    """
    import sys, uuid
    from sem_console.dds.bus import Bus, DdsConfigError
    from sem_console.dds.topics import Sem
    bus = Bus(int(sys.argv[1]))
    try:
        bus.writer(Sem.GPS_FIX_COMMAND)
    except DdsConfigError as e:  # raised for Cyclone's DDS_RETCODE_NOT_ALLOWED_BY_SECURITY
        print("refused:", e)
        raise SystemExit(0)
    print("a read-only identity was given a command writer")
    raise SystemExit(1)
    """
)


@pytest.mark.security
@secure
def test_a_read_only_identity_cannot_write_a_command(sim, console, fleet: Path, domain: int) -> None:
    """The read-only identity joins through the operator's own CYCLONEDDS_URI (<Security> beside the bus's config);
    access control refuses its command writer, and the vehicle never takes a command."""
    sim("--dds-security", identity(fleet, "usv-1"), env=env())
    c = console("--dds-security", identity(fleet, "ops-1"), env=env())
    provider_ready(c.url, V1, REPORTS)
    uri = f"{loopback_config()},file://{identity(fleet, 'wall')}/cyclonedds.xml"
    done = subprocess.run(
        [sys.executable, "-c", REFUSED_WRITER, str(domain)],
        capture_output=True,
        text=True,
        timeout=60,
        env={**os.environ, **env(), "CYCLONEDDS_URI": uri},
    )
    assert done.returncode == 0 and "refused:" in done.stdout, done.stdout + done.stderr
    assert "DDS Security as wall" in done.stdout and "do not let it write UMAA::SEM::GPSFixControl::GPSFixCommand" in done.stdout
    time.sleep(3)
    assert not fix_valid(c.url)


@pytest.mark.security
@secure
def test_a_console_under_a_read_only_identity_stops_with_one_line(fleet: Path, domain: int, tmp_path: Path) -> None:
    """Its command writers are refused by access control: said at the start, not a traceback of its lifespan."""
    line = one_line_refusal(
        [
            *(sys.executable, "-m", "sem_console.cli", "--port", "0", "--domain", str(domain)),
            *("--db", str(tmp_path / "c.sqlite3"), "--dds-security", identity(fleet, "wall")),
        ]
    )
    assert line.startswith("sem-console: DDS Security as wall")
    assert "its permissions do not let it write UMAA::SEM::GPSFixControl::GPSFixCommand" in line and "--role station" in line


@pytest.mark.security
@secure
def test_sem_sim_and_sem_replay_under_a_read_only_identity_stop_with_one_line(fleet: Path, domain: int, tmp_path: Path) -> None:
    """Their writers are refused by access control: one line naming the identity, the topic and the role it needs."""
    wall = ("--dds-security", identity(fleet, "wall"))
    line = one_line_refusal([sys.executable, "-m", "sem_console.sim.sem_sim", "--domain", str(domain), *wall])
    assert line.startswith("sem-sim: DDS Security as wall") and "its permissions do not let it write UMAA::SEM::" in line
    assert "--role vehicle" in line
    recording = synthetic_recording(tmp_path / "rec", seconds=0.5)
    line = one_line_refusal(
        [sys.executable, "-m", "sem_console.recording.sem_replay", str(recording), "--domain", str(domain), "--wait", "0", *wall]
    )
    assert line.startswith("sem-replay: DDS Security as wall") and "its permissions do not let it write UMAA::SEM::" in line


def sem_check(fleet: Path, domain: int, *args: str) -> subprocess.CompletedProcess[str]:
    """sem-check on the secure build under the read-only identity, against the vehicle usv-1 of a sem-sim."""
    return subprocess.run(
        [
            *(sys.executable, "-m", "sem_console.check.cli", "--domain", str(domain), "--timeout", "30"),
            *("--dds-security", identity(fleet, "wall"), *args),
        ],
        capture_output=True,
        text=True,
        timeout=120,
        env={**os.environ, **env()},
    )


@pytest.mark.security
@secure
def test_sem_check_tests_a_secure_vehicle_under_a_read_only_identity(sim, fleet: Path, domain: int) -> None:
    sim("--dds-security", identity(fleet, "usv-1"), env=env())
    done = sem_check(fleet, domain, "--only", "discovery.GPSFixReport,reports.GPSFixReport.values")
    assert done.returncode == 0, done.stdout + done.stderr


@pytest.mark.security
@secure
def test_sem_check_commands_under_a_read_only_identity_is_one_line(sim, fleet: Path, domain: int) -> None:
    sim("--dds-security", identity(fleet, "usv-1"), env=env())
    done = sem_check(fleet, domain, "--commands", "--only", "discovery.GPSFixReport")
    assert done.returncode == 2 and "Traceback" not in done.stderr, done.stdout + done.stderr
    said = [line for line in done.stderr.splitlines() if line.startswith("sem-check:")]
    assert len(said) == 1, done.stderr  # one line of its own (Cyclone DDS may log beside it)
    assert said[0].startswith("sem-check: DDS Security as wall") and "do not let it write UMAA::SEM::" in said[0]


def one_line_refusal(cmd: list[str]) -> str:
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=60, env={**os.environ, **env()})
    assert done.returncode == 2, done.stdout + done.stderr
    assert "Traceback" not in done.stderr, done.stderr
    lines = [line for line in done.stderr.splitlines() if line.strip()]
    return lines[-1]


def test_an_expired_identity_is_refused(fleet: Path, domain: int) -> None:
    line = one_line_refusal(
        [sys.executable, "-m", "sem_console.sim.sem_sim", "--domain", str(domain), "--dds-security", identity(fleet, "usv-old")]
    )
    assert "usv-old/cert.pem: the identity's certificate expired at" in line and "sem-keys issue" in line


@pytest.mark.security
@secure
def test_an_expired_identity_given_through_cyclonedds_uri_is_refused_by_cyclone(fleet: Path, domain: int) -> None:
    """Without the command's own check, Cyclone's authentication plugin refuses the participant: one line."""
    uri = f"{loopback_config()},file://{identity(fleet, 'usv-old')}/cyclonedds.xml"
    done = subprocess.run(
        [sys.executable, "-m", "sem_console.sim.sem_sim", "--domain", str(domain)],
        capture_output=True,
        text=True,
        timeout=60,
        env={**os.environ, **env(), "CYCLONEDDS_URI": uri},
    )
    assert done.returncode == 2 and "Traceback" not in done.stderr, done.stderr
    assert "Cyclone DDS refused a participant with the DDS Security of CYCLONEDDS_URI" in done.stderr.splitlines()[-1]


def test_a_tampered_governance_stops_the_console_with_one_line(fleet: Path, domain: int, tmp_path: Path) -> None:
    governance = fleet / "governance.p7s"
    signed = governance.read_bytes()
    assert b"<rtps_protection_kind>ENCRYPT</rtps_protection_kind>" in signed
    governance.write_bytes(signed.replace(b"<rtps_protection_kind>ENCRYPT", b"<rtps_protection_kind>NONE", 1))
    line = one_line_refusal(
        [
            sys.executable,
            "-m",
            "sem_console.cli",
            "--port",
            "0",
            "--domain",
            str(domain),
            "--db",
            str(tmp_path / "c.sqlite3"),
            "--dds-security",
            identity(fleet, "ops-1"),
        ]
    )
    assert line.startswith("sem-console: ") and "governance.p7s: its signature does not verify" in line


def test_permissions_of_another_identity_stop_the_start_with_one_line(fleet: Path, domain: int) -> None:
    usv = fleet / "identities" / "usv-1"
    (usv / "permissions.p7s").write_bytes((fleet / "identities" / "wall" / "permissions.p7s").read_bytes())
    line = one_line_refusal(
        [sys.executable, "-m", "sem_console.sim.sem_sim", "--domain", str(domain), "--dds-security", str(usv)]
    )
    assert "usv-1/permissions.p7s: no grant for the certificate's subject O=Blue,OU=vehicle,CN=usv-1" in line


def test_an_identity_of_another_fleet_stops_the_start_with_one_line(fleet: Path, domain: int, tmp_path: Path) -> None:
    other = Fleet(tmp_path / "other")
    other.init("Red", [domain], 30, False, NOW)
    other.issue("usv-1", Role.VEHICLE, 30, NOW)
    usv = fleet / "identities" / "usv-1"
    for name in ("cert.pem", "key.pem"):
        (usv / name).write_bytes((tmp_path / "other" / "identities" / "usv-1" / name).read_bytes())
    line = one_line_refusal(
        [sys.executable, "-m", "sem_console.sim.sem_sim", "--domain", str(domain), "--dds-security", str(usv)]
    )
    assert f"usv-1/cert.pem is not signed by the identity CA {fleet / 'identity_ca.pem'}" in line


def test_an_open_bus_is_said_in_health_and_once_in_the_log(console) -> None:
    c = console()
    assert http.get(f"{c.url}/api/health").json()["ddsSecurity"] == {
        "secured": False,
        "identity": None,
        "subject": None,
        "source": None,
        "notAfter": None,
    }
    assert c.stop().count(OPEN_BUS) == 1


@pytest.mark.skipif(plugins_missing() is None, reason="this pytest runs on a Cyclone DDS with the security plugins")
def test_the_wheel_without_plugins_refuses_dds_security_in_one_line(fleet: Path, domain: int) -> None:
    done = subprocess.run(
        [sys.executable, "-m", "sem_console.sim.sem_sim", "--domain", str(domain), "--dds-security", identity(fleet, "usv-1")],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert done.returncode == 2 and "Traceback" not in done.stderr, done.stderr
    assert "has no DDS Security plugins" in done.stderr and "scripts/setup.sh --secure" in done.stderr
