"""sem-relay's pure parts: the rate caps (latest per instance wins), the caps' and endpoints' checks, the Zenoh keys,
and the command line's one-line refusals (no Zenoh session, no DDS)."""

from __future__ import annotations

import contextlib
import io
import uuid
from pathlib import Path

import pytest

from UMAA.Common.MaritimeEnumeration.GPSNavigationSolutionEnumType import GPSNavigationSolutionEnumType as NavSolution
from UMAA.Common.Measurement import Altitude_HAE, GeodeticLatitude, GeodeticLongitude, Position2D, Position3D_WGS84
from UMAA.SEM.GPSFixStatus import GPSFixStatusReportType

from sem_console.dds.topics import Sem
from sem_console.relay.access import access_control
from sem_console.relay.cli import build_parser, main, options_from
from sem_console.relay.domain import Taken
from sem_console.relay.hops import carries_key, parse_carries
from sem_console.relay.link import LINK_CLASSES, ON_CHANGE, Held, Limiter, SentLog, parse_caps, quiet_seconds, short_name
from sem_console.relay.options import RelayOptions, endpoint_host, endpoint_problem, tls_problem, vehicle_relays
from sem_console.relay.relay import Relay
from sem_console.relay.wire import Address, Kind, attachment, key, parse_key, read_attachment
from sem_console.umaa.guid import to_guid
from sem_console.umaa.samples import now_datetime
from support.certs import Authority


def test_a_capped_topic_sends_the_latest_sample_of_each_instance_at_its_slot() -> None:
    limiter: Limiter[str] = Limiter({"GPSReport": 60.0})
    assert limiter.offer("GPSReport", "a", "a1", now=0.0) == "a1"  # the first goes at once
    assert limiter.offer("GPSReport", "b", "b1", now=1.0) == "b1"  # another instance has its own slot
    assert limiter.offer("GPSReport", "a", "a2", now=10.0) is None
    assert limiter.offer("GPSReport", "a", "a3", now=20.0) is None  # replaces a2
    assert limiter.due(59.0) == []
    assert limiter.due(60.0) == ["a3"] and limiter.conflated == 1
    assert limiter.due(61.0) == []  # b has nothing waiting
    assert limiter.offer("GPSReport", "a", "a4", now=100.0) is None  # a's slot was taken at 60
    assert limiter.offer("GPSReport", "a", "a5", now=120.0) == "a5"
    assert limiter.offer("GPSFixCommandStatus", "c", "c1", now=120.0) == "c1"  # not capped: every one, at once
    assert limiter.offer("GPSFixCommandStatus", "c", "c2", now=120.0) == "c2"


def test_on_change_sends_what_differs_from_the_last_sent() -> None:
    limiter: Limiter[str] = Limiter({"InertialSensorReport": ON_CHANGE})
    assert limiter.offer("InertialSensorReport", "v", "1", 0.0, fingerprint=("ON", "ALIGNING")) == "1"
    assert limiter.offer("InertialSensorReport", "v", "2", 1.0, fingerprint=("ON", "ALIGNING")) is None
    assert limiter.offer("InertialSensorReport", "v", "3", 2.0, fingerprint=("ON", "OPERATIONAL")) == "3"
    assert limiter.unchanged == 1


def fix_status(valid: bool, cn0: float) -> Taken:
    origin = Position3D_WGS84(Position2D(GeodeticLatitude(0.0), GeodeticLongitude(0.0)), Altitude_HAE(0.0))
    sample = GPSFixStatusReportType(
        carrierToNoise=[cn0],
        countDown=0,
        fixValid=valid,
        lowBkupBattery=False,
        navSolution=NavSolution.GPS_3D if valid else NavSolution.GPS_DEAD_RECK,
        originPosition=origin,
        pCode=False,
        timeOut=not valid,
        source=to_guid(uuid.UUID(int=1)),
        timeStamp=now_datetime(),
    )
    spec = Sem.GPS_FIX_STATUS_REPORT.spec
    return Taken(Sem.GPS_FIX_STATUS_REPORT, Kind.SAMPLE, sample.serialize(), 0, uuid.UUID(int=1), (spec.name, False, 1))


def test_a_fix_lost_or_regained_goes_at_once_at_the_satellite_cap() -> None:
    cap = LINK_CLASSES["satellite"]["GPSFixStatusReport"]
    limiter: Limiter[str] = Limiter({"GPSFixStatusReport": cap})

    def offer(valid: bool, cn0: float, now: float) -> str | None:
        return limiter.offer("GPSFixStatusReport", "v", f"{valid} {cn0}", now, Relay.fingerprint(fix_status(valid, cn0), cap))

    assert offer(True, 40.0, 0.0) == "True 40.0"
    assert offer(True, 41.0, 1.0) is None  # only its carrier-to-noise changed: at its slot
    assert offer(False, 20.0, 2.0) == "False 20.0"  # the fix lost: at once (the older sample waiting is given up)
    assert offer(True, 39.0, 3.0) == "True 39.0"  # and regained
    assert offer(True, 38.0, 4.0) is None
    assert limiter.due(7.9) == [] and limiter.due(8.0) == ["True 38.0"]
    assert offer(True, 37.0, 9.0) is None and offer(False, 10.0, 9.5) == "False 10.0"
    assert Relay.fingerprint(fix_status(True, 40.0), 0.0) is None  # not capped: nothing to compare
    assert Relay.fingerprint(fix_status(True, 40.0), ON_CHANGE) != Relay.fingerprint(fix_status(True, 41.0), ON_CHANGE)


def test_a_waiting_sample_goes_before_its_instance_ends() -> None:
    limiter: Limiter[str] = Limiter({"GlobalPoseReport": 5.0})
    limiter.offer("GlobalPoseReport", "v", "p1", 0.0)
    limiter.offer("GlobalPoseReport", "v", "p2", 1.0)
    assert limiter.take("v") == "p2" and limiter.take("v") is None
    assert limiter.due(10.0) == []


def test_after_an_outage_what_was_sent_since_goes_again_an_ended_instance_only_its_end() -> None:
    sent: SentLog[str] = SentLog(depth=64)
    for at, status in enumerate(("ISSUED", "COMMANDED", "EXECUTING", "COMPLETED")):
        sent.add("old", f"old {status}", at, latest_only=False, ends=False)  # a command finished long ago, not cleaned up
    sent.add("running", "running ISSUED", 100.0, latest_only=False, ends=False)
    sent.add("running", "running EXECUTING", 101.0, latest_only=False, ends=False)
    sent.add("report", "fix 1", 100.0, latest_only=True, ends=False)
    sent.add("report", "fix 2", 102.0, latest_only=True, ends=False)
    sent.add("canceled", "canceled ISSUED", 101.0, latest_only=False, ends=False)
    sent.add("canceled", "canceled disposed", 103.0, latest_only=False, ends=True)
    # a relay back after an outage noticed at 105 (two leases of 1 s and 2 s before it: 101)
    assert sent.since(101.0) == ["running EXECUTING", "fix 2", "canceled disposed"]
    # a relay new to it gets every instance's (the ended one's end only)
    assert sent.since(float("-inf")) == [
        "old ISSUED",
        "old COMMANDED",
        "old EXECUTING",
        "old COMPLETED",
        "running ISSUED",
        "running EXECUTING",
        "fix 2",
        "canceled disposed",
    ]
    sent.forget(ended_before=104.0)
    assert len(sent) == 3 and "canceled disposed" not in sent.since(float("-inf"))


def test_a_command_ended_while_held_for_its_vehicle_is_never_delivered() -> None:
    held: Held[str] = Held(depth=3)
    held.hold("v", "canceled", "canceled command", ends=False)
    held.hold("v", "running", "running command", ends=False)
    held.hold("w", "gone", "command of a consumer gone", ends=False)
    held.hold("v", "canceled", "canceled dispose", ends=True)  # cancelled before the vehicle was heard
    held.hold("w", "gone", "gone unregistered", ends=True)
    held.hold("v", "never held", "a dispose alone", ends=True)
    assert len(held) == 1
    assert held.release("v") == ["running command"] and held.release("v") == [] and held.release("w") == []
    for n in range(5):  # the last `depth` messages per vehicle
        held.hold("v", n, f"command {n}", ends=False)
    assert held.release("v") == ["command 2", "command 3", "command 4"]


def test_access_control_gives_each_vehicles_relay_its_own_key_space_and_denies_the_rest() -> None:
    v1, v2 = uuid.UUID(int=1), uuid.UUID(int=2)
    acl = access_control({"ship-1": None, "ship-2": None, "ship-3": (v1, v2)}, ["ops"])
    assert acl["enabled"] and acl["default_permission"] == "deny"
    rules = {r["id"]: r for r in acl["rules"]}
    names = {s["id"]: s["cert_common_names"] for s in acl["subjects"]}
    granted = {
        names[subject][0]: sorted(k for rule in p["rules"] for k in rules[rule]["key_exprs"])
        for p in acl["policies"]
        for subject in p["subjects"]
    }
    assert granted == {
        "ops": ["**"],
        "ship-1": [
            "sem-relay-carries/ship-1/**",
            "sem-relay/operations/**",
            "sem-relay/operations/**",
            "sem-relay/vehicles/ship-1/**",
            "sem/ship-1/**",
        ],
        "ship-2": [
            "sem-relay-carries/ship-2/**",
            "sem-relay/operations/**",
            "sem-relay/operations/**",
            "sem-relay/vehicles/ship-2/**",
            "sem/ship-2/**",
        ],
        "ship-3": [  # its vehicles listed: their keys and tokens only (and its subscription to its key space)
            f"sem-relay-carries/ship-3/*/{v1}/**",
            f"sem-relay-carries/ship-3/*/{v2}/**",
            "sem-relay/operations/**",
            "sem-relay/operations/**",
            "sem-relay/vehicles/ship-3/**",
            "sem/ship-3/**",
            f"sem/ship-3/*/{v1}/**",
            f"sem/ship-3/*/{v2}/**",
        ],
    }
    assert rules["subscribes ship-3"]["messages"] == ["declare_subscriber"]  # its key space: subscribed, not put
    assert "put" not in rules["watch operations"]["messages"]  # a vehicles' relay only watches the operations relays
    assert rules["watch operations"]["flows"] == ["ingress"] and rules["told operations"]["flows"] == ["egress"]


def test_link_classes_and_caps() -> None:
    assert LINK_CLASSES["satellite"]["GPSReport"] == 60.0 and LINK_CLASSES["lan"] == {}
    assert short_name("UMAA::SEM::GPSStatus::GPSReportType") == short_name("UMAA::SEM::GPSStatus::GPSReport") == "GPSReport"
    assert parse_caps("GPSReport=30, InertialSensorReport=change,GlobalPoseReport=0") == {
        "GPSReport": 30.0,
        "InertialSensorReport": ON_CHANGE,
        "GlobalPoseReport": 0.0,
    }
    for bad in ("GPSReport", "GPSFixCommand=1", "GPSReport=-1", "GPSReport=soon", "GPSReport=nan"):
        with pytest.raises(ValueError, match=r"GPSReport|TOPIC"):
            parse_caps(bad)


def test_keys_and_attachments() -> None:
    v = uuid.uuid4()
    k = key("ship-1", 7, v, "UMAA::SEM::GPSStatus::GPSReport")
    assert k == f"sem/ship-1/7/{v}/UMAA::SEM::GPSStatus::GPSReport"
    assert parse_key(k) == Address("ship-1", 7, v, "UMAA::SEM::GPSStatus::GPSReport")
    assert parse_key(f"sem/7/{v}/x") is None and parse_key("sem/ship-1/x/y/z") is None and parse_key("other/1/2") is None
    assert read_attachment(attachment(Kind.DISPOSE, 123)) == (Kind.DISPOSE, 123)
    assert read_attachment(b"\x09" * 10) is None and read_attachment(None) is None


@pytest.mark.parametrize(
    "endpoint,host",
    [("tcp/10.0.0.1:7447", "10.0.0.1"), ("tcp/[::1]:7447", "::1"), ("tls/ops.example:7447#iface=eth0", "ops.example")],
)
def test_endpoint_host(endpoint: str, host: str) -> None:
    assert endpoint_host(endpoint) == host


def test_only_loopback_goes_without_tls_unless_insecure() -> None:
    assert endpoint_problem(RelayOptions(connect="tcp/127.0.0.1:7447,tcp/localhost:7448")) is None
    assert endpoint_problem(RelayOptions(connect="tcp/192.0.2.1:7447", insecure=True)) is None
    assert "--listen tcp/0.0.0.0:7447 leaves this machine without TLS" in str(
        endpoint_problem(RelayOptions(router=True, listen="tcp/0.0.0.0:7447"))
    )
    assert "needs --tls-root-ca" in str(endpoint_problem(RelayOptions(connect="tls/192.0.2.1:7447")))
    for endpoint in ("tcp/10.0.0.1:7447", "tcp/ops.example.org:7447", "tcp/localhost.example.org:7447", "udp/10.0.0.1:7447"):
        assert "leaves this machine without TLS" in str(endpoint_problem(RelayOptions(connect=endpoint))), endpoint


def run(*argv: str) -> tuple[int, str]:
    err = io.StringIO()
    with contextlib.redirect_stderr(err), pytest.raises(SystemExit) as exit_:
        raise SystemExit(main(list(argv)))
    return int(exit_.value.code or 0), err.getvalue()


def test_the_command_line_refuses_in_one_line(monkeypatch: pytest.MonkeyPatch) -> None:
    assert run("--connect", "tcp/192.0.2.1:7447") == (
        2,
        (
            "sem-relay: error: --connect tcp/192.0.2.1:7447 leaves this machine without TLS: use a tls/ endpoint with "
            "--tls-root-ca, or give --insecure to send the fleet's traffic in the clear\n"
        ),
    )
    monkeypatch.setenv("SEM_RELAY_CONNECT", "tcp/192.0.2.9:7447")  # the environment's form of the option
    assert run()[1].startswith("sem-relay: error: --connect tcp/192.0.2.9:7447 leaves this machine")
    assert run("--caps", "GPSReport=often") == (
        2,
        "sem-relay: error: --caps 'GPSReport=often': the cap is seconds 0..86400 or 'change'\n",
    )
    assert run("--tls-certificate", "a.pem") == (2, "sem-relay: error: --tls-certificate and --tls-private-key go together\n")
    assert run("--name", "ship/1") == (
        2,
        "sem-relay: error: --name 'ship/1': a relay's name is one Zenoh key chunk: no '/', '*', '$', '?', '#', no "
        "leading '@' (a chunk no wildcard matches) and no surrounding spaces\n",
    )
    assert run("--name", "@ship-1")[1].startswith("sem-relay: error: --name '@ship-1': a relay's name is one Zenoh key")
    code, err = run("--router", "--vehicle-relays", "ship-1")  # access control knows relays by their certificates
    assert (
        code == 2
        and err.startswith("sem-relay: error: --vehicle-relays and --operations-relays are a router's")
        and (err.count("\n") == 1)
    )
    acl = ("--router", "--tls-root-ca", "ca.pem", "--tls-certificate", "router.pem", "--tls-private-key", "router.key")
    assert run(*acl, "--vehicle-relays", "ship-1") == (  # the router's default endpoint, tcp/
        2,
        "sem-relay: error: --listen tcp/127.0.0.1:7447: --vehicle-relays and --operations-relays know the relays by "
        "their certificates, which a tcp/ endpoint carries none of (a relay through it would get nothing): give tls/ "
        "or quic/ endpoints only\n",
    )
    acl = (*acl, "--listen", "tls/0.0.0.0:7447")
    assert run(*acl, "--vehicle-relays", "ship-1,ship-1") == (
        2,
        "sem-relay: error: --vehicle-relays, --operations-relays: 'ship-1' named twice: each relay's certificate once, "
        "in one list\n",
    )
    assert run(*acl, "--vehicle-relays", "ship-1", "--operations-relays", "ops,ship-1")[1].startswith(
        "sem-relay: error: --vehicle-relays, --operations-relays: 'ship-1' named twice"
    )
    v1 = "00000000-0000-0000-0000-000000000001"
    assert run(*acl, "--vehicle-relays", f"ship-1={v1}+v2") == (
        2,
        "sem-relay: error: --vehicle-relays 'ship-1=00000000-0000-0000-0000-000000000001+v2': give NAME or "
        "NAME=GUID+GUID..., each GUID a vehicle's source GUID\n",
    )
    assert run(*acl, "--vehicle-relays", f"ship-1={v1},ship-2={v1}") == (
        2,
        f"sem-relay: error: --vehicle-relays: vehicle {v1} is given to 'ship-1' and 'ship-2': a vehicle is carried by "
        "one relay\n",
    )
    assert run(*acl, "--vehicle-relays", "ship-1=")[1].startswith("sem-relay: error: --vehicle-relays 'ship-1=': no vehicle")
    assert vehicle_relays(f"ship-1={v1}+{v1}, ship-2") == {"ship-1": (uuid.UUID(v1),), "ship-2": None}  # once is enough
    code, err = run("--lease-seconds", "0")
    assert code == 2 and err.startswith("sem-relay: error: --lease-seconds: ") and err.count("\n") == 1
    monkeypatch.delenv("SEM_RELAY_CONNECT")
    monkeypatch.setenv("SEM_RELAY_STATUS_PORT", "abc")  # named by the variable that exists
    assert run() == (2, "sem-relay: error: SEM_RELAY_STATUS_PORT: 'abc' is not a whole number\n")
    monkeypatch.delenv("SEM_RELAY_STATUS_PORT")
    monkeypatch.setenv("SEM_RELAY_CAPS", "GPSReport=often")
    assert run() == (2, "sem-relay: error: SEM_RELAY_CAPS 'GPSReport=often': the cap is seconds 0..86400 or 'change'\n")


def test_tls_files_that_cannot_serve_are_one_line(tmp_path: Path) -> None:
    fleet = Authority(tmp_path, "fleet")
    cert, key_file = fleet.issue("ship-1")
    missing, unreadable = tmp_path / "missing.pem", tmp_path / "garbage.pem"
    unreadable.write_text("not a certificate")
    tls = ("--connect", "tls/10.0.0.1:7447", "--tls-root-ca")
    assert run(*tls, str(missing)) == (
        2,
        f"sem-relay: error: --tls-root-ca {missing}: cannot read it as PEM certificates "
        "(No such file or directory): give the fleet authority's certificate\n",
    )
    code, err = run(*tls, str(unreadable))
    assert code == 2 and err.startswith(f"sem-relay: error: --tls-root-ca {unreadable}: cannot read it") and err.count("\n") == 1
    code, err = run(*tls, str(fleet.pem), "--tls-certificate", str(cert), "--tls-private-key", str(cert))  # its key: the cert
    assert (
        code == 2
        and err.count("\n") == 1
        and err.startswith(
            f"sem-relay: error: --tls-certificate {cert} and --tls-private-key {cert}: not a readable PEM certificate"
        )
    )
    assert (
        tls_problem(
            RelayOptions(connect="tls/10.0.0.1:7447", tls_root_ca=fleet.pem, tls_certificate=cert, tls_private_key=key_file)
        )
        is None
    )


def test_a_status_file_that_cannot_be_written_is_one_line(tmp_path: Path) -> None:
    missing, fix = tmp_path / "missing" / "near.json", "give a file in a folder the relay may write\n"
    assert run("--status-file", str(missing)) == (
        2,
        f"sem-relay: error: --status-file {missing}: no folder {missing.parent}: {fix}",
    )
    assert run("--status-file", str(tmp_path)) == (2, f"sem-relay: error: --status-file {tmp_path}: a folder: {fix}")


def test_a_deployment_s_options_come_from_one_file_under_the_environment_and_the_command_line(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """--config FILE: SEM_RELAY_* lines (a systemd EnvironmentFile, a compose env_file); the environment, then the
    command line, come before it; a bad value in it, or a file that cannot be read, is one line naming it."""
    for name in ("SEM_RELAY_NAME", "SEM_RELAY_SIDE", "SEM_RELAY_CONNECT", "SEM_RELAY_LINK_CLASS"):
        monkeypatch.delenv(name, raising=False)
    config = tmp_path / "relay.env"
    config.write_text(
        "# ship-7's relay\nSEM_RELAY_NAME=ship-7\nSEM_RELAY_SIDE=operations\nSEM_RELAY_CONNECT=tcp/127.0.0.1:7999\n"
        "SEM_RELAY_LINK_CLASS=lan\n"
    )
    opts = options_from(build_parser().parse_args(["--config", str(config)]))
    assert (opts.name, opts.side, opts.connect, opts.link_class) == ("ship-7", "operations", "tcp/127.0.0.1:7999", "lan")
    assert options_from(build_parser().parse_args(["--config", str(config), "--name", "ship-8"])).name == "ship-8"
    monkeypatch.setenv("SEM_RELAY_NAME", "ship-9")
    assert options_from(build_parser().parse_args(["--config", str(config)])).name == "ship-9"

    config.write_text("SEM_RELAY_LINK_CLASS=iridium\n")
    assert run("--config", str(config)) == (
        2,
        f"sem-relay: error: SEM_RELAY_LINK_CLASS: Input should be 'satellite' or 'lan' (in --config {config})\n",
    )
    assert run("--config", str(tmp_path / "none.env")) == (
        2,
        f"sem-relay: error: --config {tmp_path / 'none.env'}: No such file or directory: give a readable file\n",
    )


def test_the_caps_say_how_long_a_vehicle_of_each_version_may_be_quiet_and_its_token_carries_it() -> None:
    """The shortest periodic cap of the version's report topics: a console adds it to the comms-lost timeout."""
    v3 = ("GPSFixReport", "GPSFixStatusReport", "GPSReport", "InertialSensorReport")
    v6 = ("GPSReport", "GlobalPoseReport", "InertialSensorReport")
    satellite = LINK_CLASSES["satellite"]
    assert quiet_seconds(satellite, v3) == 5.0 and quiet_seconds(satellite, v6) == 5.0
    assert quiet_seconds(LINK_CLASSES["lan"], v3) == 0.0  # nothing capped: the vehicle's own rate
    custom = {**satellite, **parse_caps("GlobalPoseReport=30")}
    assert quiet_seconds(custom, v6) == 30.0 and quiet_seconds(custom, v3) == 5.0  # each version its own topics
    assert quiet_seconds({**satellite, **parse_caps("GPSFixStatusReport=0")}, v3) == 0.0  # one uncapped topic
    assert quiet_seconds({t: ON_CHANGE for t in v6}, v6) == 0.0  # on change promises nothing
    vehicle = uuid.uuid4()
    assert parse_carries(carries_key("Ship One", 3, vehicle, 5000)) == (("Ship One", 3), vehicle, 5000)
    assert parse_carries(f"sem-relay-carries/ship-1/3/{vehicle}") == (("ship-1", 3), vehicle, 0)  # an earlier relay's
    assert parse_carries(f"sem-relay-carries/ship-1/3/{vehicle}/soon") is None
    assert parse_carries(f"sem-relay-carries/ship-1/3/{vehicle}/86400001") is None  # more than a day: no token
    assert parse_carries(f"sem-relay-carries/ship-1/3/{vehicle}/{10**30}") is None
