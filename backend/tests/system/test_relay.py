"""`sem-relay` over real Zenoh and Cyclone DDS on loopback: two DDS domains of this machine joined by two relays and a
`sem-relay --router`, the far domain's consumer commanding the near domain's `sem-sim` vehicles of both UMAA versions;
and the same through an impaired link (tests/support/impair.py)."""

from __future__ import annotations

import contextlib
import io
import json
import os
import socket
import subprocess
import sys
import threading
import time
import uuid
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest
import zenoh
from cyclonedds.core import InstanceState
from cyclonedds.util import duration
from fastapi.testclient import TestClient

from UMAA.Common.MaritimeEnumeration.CommandStatusEnumType import CommandStatusEnumType as S
from UMAA.Common.MaritimeEnumeration.CommandStatusReasonEnumType import CommandStatusReasonEnumType as Reason
from UMAA.Common.MaritimeEnumeration.InertialSensorOpStatusEnumType import InertialSensorOpStatusEnumType as Op
from UMAA.Common.MaritimeEnumeration.InertialSensorStateEnumType import InertialSensorStateEnumType as Ins
from UMAA.SEM.GPSFixControl import GPSFixCommandStatusType
from UMAA.SEM.InertialSensorStatus import InertialSensorReportType

from conftest import ConsoleProcess, Process, free_domain, free_port
from sem_console.check.cli import main as check_main
from sem_console.codec.decode import ReportItem
from sem_console.core.config import Settings
from sem_console.dds.bus import Bus, take_each
from sem_console.dds.hops import RelayLink
from sem_console.dds.topics import Sem, Sem60, Service
from sem_console.main import create_app
from sem_console.relay.cli import open_session
from sem_console.relay.domain import DomainSide, Taken
from sem_console.relay.hops import CARRIES, LEFT_GRACE, LIVELINESS, RELAYS, Carried, Hops, carries_key, parse_carries
from sem_console.relay.options import RelayOptions
from sem_console.relay.relay import EARLY_VEHICLES, ENDED_KEPT_SECONDS, Outgoing, Relay
from sem_console.relay.wire import PREFIX, Kind, attachment, key, read_attachment
from sem_console.sim.provider import vehicle_guid
from sem_console.umaa.guid import to_guid
from sem_console.umaa.samples import now_datetime
from sem_console.versions import UMAA_6_0
from sem_console.versions.commands import commanding
from support import http, warm
from support.certs import Authority
from support.consumer import Consumer
from support.impair import Impairment

pytestmark = pytest.mark.process
V1, V2 = vehicle_guid(1), vehicle_guid(2)  # vehicle 2 speaks UMAA 6.0
HAPPY = [S.ISSUED, S.COMMANDED, S.EXECUTING, S.COMPLETED]


class RelayProcess(Process):
    def __init__(self, out: Path, *args: str) -> None:
        self.proc = warm.launch(warm.RELAY, ["--log-level", "warning", *args], dict(os.environ), out)


@pytest.fixture
def relay(tmp_path: Path) -> Iterator[Callable[..., RelayProcess]]:
    started: list[RelayProcess] = []

    def start(*args: str) -> RelayProcess:
        started.append(RelayProcess(tmp_path / f"relay-{len(started)}.out", *args))
        return started[-1]

    yield start
    for p in started:
        p.end()


@dataclass
class Joined:
    port: int  # the router's
    near_args: list[str]  # the vehicles' relay's command line (to start it again)
    near: RelayProcess
    far_args: list[str]  # the operations relay's
    far: RelayProcess


def join(
    relay: Callable[..., RelayProcess],
    near: int,
    far: int,
    tmp_path: Path,
    *args: str,
    via: Callable[[int], str] | None = None,
    status_port: int | None = None,
) -> Joined:
    """A router and the two sides' relays; `via`: the near relay's endpoint for the router's port (an impaired
    link's); `status_port`: the near relay's."""
    port = free_port()
    router = f"tcp/127.0.0.1:{port}"
    relay("--router", "--listen", router)
    near_args = [
        "--domain",
        str(near),
        "--side",
        "vehicles",
        "--name",
        "ship-1",
        "--connect",
        via(port) if via else router,
        "--stats-seconds",
        "1",
        "--status-file",
        str(tmp_path / "near.json"),
        *(["--status-port", str(status_port)] if status_port else []),
        *args,
    ]
    far_args = [
        "--domain",
        str(far),
        "--side",
        "operations",
        "--name",
        "ops",
        "--connect",
        router,
        "--stats-seconds",
        "1",
        "--status-file",
        str(tmp_path / "far.json"),
        *args,
    ]
    return Joined(port, near_args, relay(*near_args), far_args, relay(*far_args))


def sources_60(readers: list[Any]) -> set[uuid.UUID]:
    """The vehicles of the UMAA 6.0 samples the readers have (their `source` an IdentifierType)."""
    return {uuid.UUID(bytes=bytes(s.source.id)) for r in readers for s in take_each(r)[0] if hasattr(s, "source")}


def command_60(bus: Bus, vehicle: uuid.UUID, state: str, cancel: bool = False) -> list[Any]:
    """A UMAA 6.0 INS command to `vehicle` from `bus` (`cancel`: disposed once EXECUTING): the statuses it went through,
    up to a terminal one."""
    c = commanding(UMAA_6_0, Service.INERTIAL_SENSOR)
    assert c is not None
    statuses, session = bus.reader(c.status), uuid.uuid4()
    writer = bus.writer(c.command)
    command = c.build(uuid.uuid4(), vehicle, session, state, (int(time.time()), 0))
    writer.write(command)
    seen: list[Any] = []
    deadline = time.monotonic() + 20
    while (not seen or seen[-1] not in (S.COMPLETED, S.FAILED, S.CANCELED)) and time.monotonic() < deadline:
        seen += [
            c.read_status(x)[0]
            for x in take_each(statuses)[0]
            if hasattr(x, "sessionID") and uuid.UUID(bytes=bytes(x.sessionID)) == session
        ]
        if cancel and seen and seen[-1] is S.EXECUTING:
            writer.dispose(command)
            cancel = False
        time.sleep(0.05)
    return seen


def test_a_far_consumer_commands_near_vehicles_of_both_versions(sim, domain: int, relay, tmp_path: Path) -> None:
    far = free_domain(taken=domain)
    sim("--vehicles", "2", "--umaa-6-0-vehicles", "2", "--surface-seconds", "60")  # a fix takes 3 s: time to cancel
    status_port = free_port()
    # the satellite link class (the default), its fix status capped to 10 minutes: only a change of fix crosses here
    join(relay, domain, far, tmp_path, "--caps", "GPSFixStatusReport=600", status_port=status_port)
    joined = time.monotonic()
    consumer = Consumer(far)
    bus60 = Bus(far)
    try:
        readers60 = [bus60.reader(sem) for sem in (Sem60.GLOBAL_POSE_REPORT, Sem60.INS_REPORT)]
        # both vehicles show on the far domain: the 3.0.1 one's reports, the 6.0 one's pose and INS
        consumer.wait(
            lambda: V1 in consumer.reports[Sem.GPS_REPORT] and V1 in consumer.reports[Sem.INS_REPORT],
            20,
            "vehicle 1's reports across the link",
        )
        seen60: set[uuid.UUID] = set()
        deadline = time.monotonic() + 20
        while V2 not in seen60 and time.monotonic() < deadline:
            seen60 |= sources_60(readers60)
            time.sleep(0.1)
        assert V2 in seen60
        # a cancel: the dispose of a running command crosses, the vehicle cancels it, its disposes come back
        first = consumer.command(Service.GPS_FIX, V1)
        canceled = consumer.wait_status(first, S.EXECUTING, 15)
        consumer.dispose(first)
        consumer.wait(lambda: canceled.status_disposed and canceled.ack_disposed, 15, "status and ack disposed after cancel")
        assert canceled.statuses == [S.ISSUED, S.COMMANDED, S.EXECUTING, S.CANCELED]
        # a GPS fix and an INS command complete
        fix = consumer.command(Service.GPS_FIX, V1)
        seen = consumer.wait_terminal(fix, 20)
        assert seen.statuses == HAPPY and seen.flow.violations == []
        # the vehicle surfaced: its fix, lost until then, crosses at once, not at the cap's next slot
        fixes = consumer.reports[Sem.GPS_FIX_STATUS_REPORT][V1]
        consumer.wait(lambda: fixes[-1].fixValid, 15, "the fix regained across the link")
        assert not fixes[0].fixValid
        ins = consumer.command(Service.INERTIAL_SENSOR, V1, Ins.RESTARTING)
        assert consumer.wait_terminal(ins, 20).statuses == HAPPY
        # the 6.0 vehicle's INS command (UMAA 6.0's InertialSensorCommandType) completes too
        assert command_60(bus60, V2, "STATIONARY_ALIGN")[-1] is S.COMPLETED
        # and its cancel: the dispose crosses as a dispose of the 6.0 key (an IdentifierType source and destination)
        assert command_60(bus60, V2, "STATIONARY_ALIGN", cancel=True) == [S.ISSUED, S.COMMANDED, S.EXECUTING, S.CANCELED]
        # the cleanup: the finished fix disposed, the vehicle disposes its status and ack
        consumer.dispose(fix)
        consumer.wait(lambda: seen.status_disposed and seen.ack_disposed, 15, "status and ack disposed after cleanup")
        assert seen.statuses == HAPPY
        # the satellite caps: the vehicle's 4 Hz GPSReport crosses once a minute (the first at once)
        consumer.pump()
        assert 1 <= len(consumer.reports[Sem.GPS_REPORT][V1]) <= 1 + (time.monotonic() - joined) // 60
        # the bytes per vehicle: in the status file, and served by the relay
        status = json.loads((tmp_path / "near.json").read_text())
        assert status["vehicles"][str(V1)]["sentBytes"] > 0 and status["vehicles"][str(V2)]["sentBytes"] > 0
        served = http.get(f"http://127.0.0.1:{status_port}/status").json()
        assert served["name"] == "ship-1" and served["linkClass"] == "satellite"
        assert served["vehicles"][str(V1)]["sentBytes"] >= status["vehicles"][str(V1)]["sentBytes"]
    finally:
        consumer.close()
        bus60.close()


def test_a_command_canceled_before_its_vehicle_is_heard_never_reaches_it(sim, domain: int, relay, tmp_path: Path) -> None:
    """ICD 4.1.2.1: a provider that starts later finds the commands persisted on the bus, not the cancelled ones."""
    far = free_domain(taken=domain)
    join(relay, domain, far, tmp_path, "--link-class", "lan")
    consumer = Consumer(far)
    try:
        canceled = consumer.command(Service.GPS_FIX, V1)
        consumer.dispose(canceled)
        kept = consumer.command(Service.GPS_FIX, V1)
        status = tmp_path / "far.json"
        consumer.wait(
            lambda: status.exists() and json.loads(status.read_text())["waitingCommands"] == 1,
            30,  # the relays' start, discovery and a status file a second: 15 s ran out on a loaded machine
            "the far relay holding the one command alive",
        )
        sim()  # the vehicle is heard
        assert consumer.wait_terminal(kept, 20).statuses == HAPPY
        consumer.pump()
        assert consumer.commands[canceled].statuses == []
    finally:
        consumer.close()


def test_a_vehicles_relay_restarted_does_not_give_the_vehicle_a_finished_command_again(
    sim, domain: int, relay, tmp_path: Path
) -> None:
    """The vehicles' relay restarts (a new writer on the vehicles' domain): the operations relay sends it again what is
    alive of its consoles' commands, but not a command the vehicle said has ended (COMPLETED, not yet cleaned up): a
    vehicle that took it for new would run it again."""
    far = free_domain(taken=domain)
    sim()
    joined = join(relay, domain, far, tmp_path, "--link-class", "lan")
    consumer, near = Consumer(far), Bus(domain)
    try:
        commands = near.reader(Sem.GPS_FIX_COMMAND)
        fix = consumer.command(Service.GPS_FIX, V1)
        assert consumer.wait_terminal(fix, 20).statuses == HAPPY  # and left alive: no cleanup yet
        take_each(commands)
        joined.near.end()
        relay(*joined.near_args)
        heard = len(consumer.reports[Sem.INS_REPORT][V1])
        consumer.wait(lambda: len(consumer.reports[Sem.INS_REPORT][V1]) > heard + 2, 20, "reports through the new relay")
        time.sleep(1)  # what the operations relay sends again to the new relay has come
        again = [x for x in take_each(commands)[0] if uuid.UUID(bytes=bytes(x.sessionID)) == fix]
        assert again == []
    finally:
        consumer.close()
        near.close()


def test_the_impairment_s_loss_costs_a_retransmission_after_an_outage_too() -> None:
    """A segment lost is sent again a retransmission timeout after it would have come: one held by an outage (or
    behind others at the link's rate) costs it as well, after it."""
    sink = socket.create_server(("127.0.0.1", 0))
    link = Impairment(sink.getsockname(), loss=1.0)  # every segment lost: each comes 200 ms late
    try:
        with socket.create_connection(("127.0.0.1", link.port)) as sender:
            receiver, _ = sink.accept()
            link.outage(0.5)
            started = time.monotonic()
            sender.sendall(b"x")
            receiver.settimeout(5)
            assert receiver.recv(1) == b"x"
            assert time.monotonic() - started >= 0.5 + link.retransmission - 0.02
            assert link.lost == 1
            receiver.close()
    finally:
        link.close()
        sink.close()


def test_commands_cross_an_impaired_link_and_an_outage(sim, domain: int, relay, tmp_path: Path) -> None:
    """600 ms round trip, 5 % loss, 64 kbit/s, and an outage of a few seconds while a command runs: nothing of the
    command flow is lost, and the reports go on after it (the minute-long outage belongs to a slow test: docs/relay.md)."""
    far = free_domain(taken=domain)
    links: list[Impairment] = []

    def impaired(port: int) -> str:
        links.append(Impairment(("127.0.0.1", port), rtt=0.6, rate_bytes=8000, loss=0.05))
        return links[0].endpoint

    sim("--surface-seconds", "60")
    join(relay, domain, far, tmp_path, "--caps", "GPSFixReport=1", via=impaired)
    consumer = Consumer(far)
    try:
        consumer.wait(lambda: V1 in consumer.reports[Sem.GPS_FIX_REPORT], 20, "vehicle 1's fix report across the link")
        started = time.monotonic()
        fix = consumer.command(Service.GPS_FIX, V1)
        consumer.wait_status(fix, S.ISSUED, 10)
        assert time.monotonic() - started >= 0.6  # the command there and its status back: one round trip at least
        links[0].outage(4)
        before = len(consumer.reports[Sem.GPS_FIX_REPORT][V1])
        seen = consumer.wait_terminal(fix, 25)
        assert seen.statuses == HAPPY and seen.flow.violations == []
        assert time.monotonic() - started >= 4
        consumer.wait(lambda: len(consumer.reports[Sem.GPS_FIX_REPORT][V1]) >= before + 2, 10, "reports after the outage")
        assert links[0].lost >= 1  # segments of the test's traffic were lost (and came a retransmission late)
    finally:
        consumer.close()
        for link in links:
            link.close()


@pytest.mark.slow
@pytest.mark.parametrize("lease,outage,thin", [(1, 4, False), (10, 60, True)])
def test_an_outage_longer_than_the_lease_loses_nothing_of_the_command_flow(
    sim, domain: int, relay, tmp_path: Path, lease: float, outage: float, thin: bool
) -> None:
    """The link is down longer than Zenoh's lease (1 s and 4 s on a 600 ms link; the default 10 s and the minute of a
    satellite's outage on the thin link: 600 ms, 5 % loss, 64 kbit/s): the sessions close and open again, and what was
    under way is sent again; each message is written once. Then each vehicle's capped reports cross at their cap again:
    neither the outage's backlog in a burst nor every sample (counted as they reach the router: what crossed the link)."""
    far = free_domain(taken=domain)
    links: list[Impairment] = []
    cap, window = 2.0, 16.0  # eight slots; the simulator writes GPSFixReport at 5 Hz

    def impaired(port: int) -> str:
        links.append(Impairment(("127.0.0.1", port), rtt=0.6, **(dict(rate_bytes=8000, loss=0.05) if thin else {})))
        return links[0].endpoint

    sim("--vehicles", "2", "--surface-seconds", "40")  # 2 s to surface: the fix completes during the outage
    joined = join(relay, domain, far, tmp_path, "--lease-seconds", str(lease), "--caps", f"GPSFixReport={cap}", via=impaired)
    config = zenoh.Config()
    config.insert_json5("connect/endpoints", json.dumps([f"tcp/127.0.0.1:{joined.port}"]))
    config.insert_json5("scouting/multicast/enabled", "false")
    watcher = zenoh.open(config)
    crossed: list[tuple[str, float]] = []  # (vehicle, when its report reached the router)
    consumer = Consumer(far)
    try:
        reports = f"{PREFIX}/ship-1/{domain}/*/{Sem.GPS_FIX_REPORT.spec.name}"
        watch = watcher.declare_subscriber(reports, lambda s: crossed.append((str(s.key_expr).split("/")[3], time.monotonic())))
        consumer.wait(lambda: {V1, V2} <= set(consumer.reports[Sem.GPS_FIX_REPORT]), 20, "both vehicles' fix reports")
        fix = consumer.command(Service.GPS_FIX, V1)
        consumer.wait_status(fix, S.EXECUTING, 10)
        links[0].outage(outage)
        seen = consumer.wait_terminal(fix, outage + 30)
        assert seen.statuses == HAPPY and seen.flow.violations == []  # each status once, in order
        consumer.dispose(fix)  # the cleanup still crosses
        consumer.wait(lambda: seen.status_disposed and seen.ack_disposed, 20, "status and ack disposed after cleanup")
        # the link is back and what was sent again has come (the latest report of each vehicle among it)
        time.sleep(1)
        start = time.monotonic()
        time.sleep(window)
        counts = {v: sum(1 for who, at in crossed if who == str(v) and start <= at < start + window) for v in (V1, V2)}
        for count in counts.values():
            assert window / cap / 2 <= count <= window / cap + 1, counts
        watch.undeclare()
    finally:
        consumer.close()
        watcher.close()
        for link in links:
            link.close()


def test_a_cancel_sent_before_an_outage_longer_than_ends_are_kept_goes_again_after_it(domain: int) -> None:
    """A relay of the other side lost for an hour, longer than the ten minutes an ended instance is kept: the cancel
    sent just before the loss is still sent again when it is back (real Cyclone DDS and Zenoh; the clock given)."""
    config = zenoh.Config()
    config.insert_json5("scouting/multicast/enabled", "false")
    session, bus = zenoh.open(config), Bus(domain)
    relay = Relay(RelayOptions(side="operations", name="ops", lease_seconds=10), bus, session)
    try:
        cancel = Outgoing(
            key("ship-1", domain, V1, Sem.GPS_FIX_COMMAND.spec.name),
            b"",
            attachment(Kind.DISPOSE, 0),
            V1,
            urgent=True,
            instance="canceled",
            ended=True,
        )
        relay._sent.add(cancel.instance, cancel, 1000.0, latest_only=False, ends=True)
        lost = 1010.0  # the other side's relay lost
        relay._peers["sem-relay/vehicles/ship-1/1"] = lost
        relay._forget_ended(lost + ENDED_KEPT_SECONDS + 3600)
        assert relay._sent.since(relay._resend_from(lost)) == [cancel]
        relay._peers["sem-relay/vehicles/ship-1/1"] = None  # back, and sent again: forgotten in time
        relay._forget_ended(lost + ENDED_KEPT_SECONDS + 3600)
        assert relay._sent.since(float("-inf")) == []
    finally:
        relay.close()
        bus.close()
        session.close()


def test_an_instance_disposed_after_several_unread_samples_ends_once_after_the_last(domain: int) -> None:
    """A status written twice and disposed before the relay takes them (one take, each sample's instance state then
    disposed): its samples cross, then its dispose once, never a sample after the dispose (which on the far side
    would bring the instance back: a command re-written after its cancel would start again)."""
    vehicle, relay_bus = Bus(domain), Bus(domain)
    taken: list[Taken] = []
    side = DomainSide(relay_bus, [Sem.GPS_FIX_COMMAND_STATUS], taken.append)
    try:
        writer = vehicle.writer(Sem.GPS_FIX_COMMAND_STATUS)
        deadline = time.monotonic() + 10
        while not writer.get_matched_subscriptions() and time.monotonic() < deadline:
            time.sleep(0.05)
        session = uuid.uuid4()
        for status in (S.ISSUED, S.CANCELED):
            sample = GPSFixCommandStatusType(
                source=to_guid(V1),
                commandStatus=status,
                commandStatusReason=Reason.SUCCEEDED,
                logMessage="",
                sessionID=to_guid(session),
                timeStamp=now_datetime(),
            )
            writer.write(sample)
        writer.dispose(sample)
        writer.wait_for_acks(duration(seconds=5))
        side.start()  # the three in one take
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline and not (
            sum(t.kind is Kind.SAMPLE for t in taken) == 2 and taken[-1].kind is Kind.DISPOSE
        ):
            time.sleep(0.05)
        assert [t.kind for t in taken] == [Kind.SAMPLE, Kind.SAMPLE, Kind.DISPOSE]
    finally:
        side.stop()
        vehicle.close()
        relay_bus.close()


def test_an_unregistered_instance_crosses_as_an_unregistration_both_ways(domain: int, relay, tmp_path: Path) -> None:
    """A writer that unregisters an instance (its vehicle's report on the vehicles' side, a console's command on the
    operations side) leaves the other side's readers the instance without writers, NOT_ALIVE_NO_WRITERS, as on one
    domain: not disposed (a command disposed is a cancel), not alive."""
    far = free_domain(taken=domain)
    join(relay, domain, far, tmp_path, "--link-class", "lan")
    near_bus, far_bus = Bus(domain), Bus(far)
    vehicle = uuid.uuid4()
    try:
        reports, commands = far_bus.reader(Sem.INS_REPORT), near_bus.reader(Sem.GPS_FIX_COMMAND)
        reporter, commander = near_bus.writer(Sem.INS_REPORT), far_bus.writer(Sem.GPS_FIX_COMMAND)
        report = InertialSensorReportType(state=Ins.ON, status=Op.OPERATIONAL, source=to_guid(vehicle), timeStamp=now_datetime())
        command = Sem.GPS_FIX_COMMAND.spec.type(
            source=to_guid(uuid.uuid4()), destination=to_guid(vehicle), sessionID=to_guid(uuid.uuid4()), timeStamp=now_datetime()
        )

        def states(reader: Any, until: InstanceState, what: str) -> list[InstanceState]:
            seen: list[InstanceState] = []
            deadline = time.monotonic() + 30  # the relays' start and discovery on a loaded machine
            while until not in seen and time.monotonic() < deadline:
                seen += [x.sample_info.instance_state for x in take_each(reader)[0]]
                time.sleep(0.05)
            assert until in seen, f"{what}: {seen}"
            return seen

        reporter.write(report)  # the vehicle heard: its relay carries it, and its commands go there
        states(reports, InstanceState.Alive, "the report across the link")
        commander.write(command)
        states(commands, InstanceState.Alive, "the command across the link")
        reporter.unregister_instance(report)
        commander.unregister_instance(command)
        assert states(reports, InstanceState.NotAliveNoWriters, "the report's unregistration") == [
            InstanceState.NotAliveNoWriters
        ]
        assert states(commands, InstanceState.NotAliveNoWriters, "the command's unregistration") == [
            InstanceState.NotAliveNoWriters
        ]
    finally:
        near_bus.close()
        far_bus.close()


def tls(authority: Authority, name: str, ca: Authority | None = None) -> list[str]:
    cert, key = authority.issue(name)
    return ["--tls-root-ca", str((ca or authority).pem), "--tls-certificate", str(cert), "--tls-private-key", str(key)]


@pytest.mark.slow
def test_mutual_tls_lets_in_only_the_fleets_certificates(sim, domain: int, relay, tmp_path: Path) -> None:
    far, other = free_domain(taken=domain), free_domain(taken=domain)
    fleet, stranger = Authority(tmp_path, "fleet-ca"), Authority(tmp_path, "other-ca")
    endpoint = f"tls/localhost:{free_port()}"
    sim()
    relay("--router", "--listen", endpoint, *tls(fleet, "router"))
    relay("--domain", str(domain), "--connect", endpoint, "--link-class", "lan", *tls(fleet, "ship-1"))
    relay("--domain", str(far), "--side", "operations", "--connect", endpoint, "--link-class", "lan", *tls(fleet, "ops"))
    # a relay whose certificate another authority signed, trusting the fleet's: the router refuses it
    intruder = relay(
        "--domain",
        str(other),
        "--side",
        "operations",
        "--connect",
        endpoint,
        "--log-level",
        "info",
        *tls(stranger, "intruder", ca=fleet),
    )
    consumer, outsider = Consumer(far), Consumer(other)
    try:
        fix = consumer.command(Service.GPS_FIX, V1)  # waits on the far side until the vehicle is heard
        assert consumer.wait_terminal(fix, 20).statuses == HAPPY
        outsider.pump()
        assert V1 not in outsider.reports[Sem.GPS_REPORT]
    finally:
        consumer.close()
        outsider.close()
    assert "cannot connect to any Zenoh endpoint yet" in intruder.stop()


def acl_router(relay: Callable[..., RelayProcess], fleet: Authority, vehicle_relays: str | None, operations: str = "ops") -> str:
    """A router with the fleet's mutual TLS and access control for these relays (None: mutual TLS, no access
    control); its endpoint."""
    endpoint = f"tls/localhost:{free_port()}"
    access = ["--vehicle-relays", vehicle_relays, "--operations-relays", operations] if vehicle_relays is not None else []
    relay("--router", "--listen", endpoint, *access, *tls(fleet, "router"))
    return endpoint


def fleet_session(fleet: Authority, name: str, endpoint: str) -> zenoh.Session:
    """A Zenoh session with the fleet's certificate for `name`, connected to `endpoint` (a router's)."""
    cert, private = fleet.issue(name)
    options = RelayOptions(name=name, connect=endpoint, tls_root_ca=fleet.pem, tls_certificate=cert, tls_private_key=private)
    opened = open_session(options, threading.Event())
    assert opened is not None
    return opened


@pytest.mark.slow
def test_access_control_keeps_a_vehicles_relay_from_passing_for_another_s_vehicle(
    sim, domain: int, relay, tmp_path: Path
) -> None:
    """In its own key space a vehicles' relay may still put samples under the id of a vehicle of another's: the
    operations relay writes a vehicle's samples only from the relay and domain it first heard it through (where its
    commands go), so ship-2 cannot report a status of ship-1's vehicle, which ship-1 can."""
    far = free_domain(taken=domain)
    fleet = Authority(tmp_path, "fleet-ca")
    endpoint = f"tls/localhost:{free_port()}"
    sim()
    relay(
        "--router", "--listen", endpoint, "--vehicle-relays", "ship-1,ship-2", "--operations-relays", "ops", *tls(fleet, "router")
    )
    lan = ("--connect", endpoint, "--link-class", "lan")
    relay("--domain", str(domain), "--name", "ship-1", *lan, *tls(fleet, "ship-1"))
    relay("--domain", str(far), "--side", "operations", "--name", "ops", *lan, *tls(fleet, "ops"))
    consumer = Consumer(far)
    statuses = consumer.bus.reader(Sem.GPS_FIX_COMMAND_STATUS)
    ships = {name: fleet_session(fleet, name, endpoint) for name in ("ship-1", "ship-2")}
    try:
        # the relays' start first (a start-up wait: on a loaded machine their TLS connections took seconds, and a command
        # sent before left 20 s too few for its flow), then the command's flow
        consumer.wait(lambda: bool(consumer.reports[Sem.GPS_FIX_REPORT][V1]), 60, "vehicle 1's reports through ship-1")
        assert consumer.wait_terminal(consumer.command(Service.GPS_FIX, V1), 20).statuses == HAPPY  # V1 heard via ship-1
        sessions = {name: uuid.uuid4() for name in ships}
        for name, zs in ships.items():
            status = GPSFixCommandStatusType(
                source=to_guid(V1),
                commandStatus=S.COMPLETED,
                commandStatusReason=Reason.SUCCEEDED,
                logMessage="",
                sessionID=to_guid(sessions[name]),
                timeStamp=now_datetime(),
            )
            topic = Sem.GPS_FIX_COMMAND_STATUS.spec.name
            zs.put(key(name, domain, V1, topic), status.serialize(), attachment=attachment(Kind.SAMPLE, 0))
        deadline, written = time.monotonic() + 10, set()
        while sessions["ship-1"] not in written and time.monotonic() < deadline:
            written |= {uuid.UUID(bytes=bytes(s.sessionID)) for s in take_each(statuses)[0]}
            time.sleep(0.05)
        assert sessions["ship-1"] in written  # the relay the vehicle is heard through
        time.sleep(1)
        written |= {uuid.UUID(bytes=bytes(s.sessionID)) for s in take_each(statuses)[0]}
        assert sessions["ship-2"] not in written
    finally:
        consumer.close()
        for zs in ships.values():
            zs.close()


def test_a_vehicle_s_commands_go_only_to_the_relay_that_alone_says_it_carries_it(sim, domain: int, relay, tmp_path: Path) -> None:
    """ship-1 carries vehicle 1 (its token); ship-2 says it carries it too and puts samples under its id. The operations
    relay, started then, hears ship-2's samples first (ship-1 is behind a 2 s round trip): it sends the console's command
    to neither while both say so, never to ship-2, writes none of ship-2's samples, and sends the command to ship-1
    once ship-1 alone says it carries the vehicle; the fix completes."""
    far = free_domain(taken=domain)
    port = free_port()
    router = f"tcp/127.0.0.1:{port}"
    link = Impairment(("127.0.0.1", port), rtt=2.0)
    sim()
    relay("--router", "--listen", router)
    relay("--domain", str(domain), "--name", "ship-1", "--connect", link.endpoint, "--link-class", "lan")
    config = zenoh.Config()
    config.insert_json5("connect/endpoints", json.dumps([router]))
    config.insert_json5("scouting/multicast/enabled", "false")
    rogue = zenoh.open(config)
    commands: list[str] = []
    consumer: Consumer | None = None
    posing = threading.Event()
    try:
        fixes = f"sem/ship-2/*/*/{Sem.GPS_FIX_COMMAND.spec.name}"
        listening = rogue.declare_subscriber(fixes, lambda s: commands.append(str(s.key_expr)))
        claim = rogue.liveliness().declare_token(carries_key("ship-2", domain, V1))
        deadline = time.monotonic() + 20
        while time.monotonic() < deadline and (("ship-1", domain), V1) not in {
            found[:2]
            for r in rogue.liveliness().get(f"{CARRIES}/**")
            if r.ok is not None and (found := parse_carries(str(r.ok.key_expr))) is not None
        }:
            time.sleep(0.2)
        sessions: list[uuid.UUID] = []

        def pose() -> None:  # ship-2's samples of vehicle 1, a status of a session of its own every 20 ms
            while not posing.wait(0.02):
                sessions.append(uuid.uuid4())
                status = GPSFixCommandStatusType(
                    source=to_guid(V1),
                    commandStatus=S.COMPLETED,
                    commandStatusReason=Reason.SUCCEEDED,
                    logMessage="",
                    sessionID=to_guid(sessions[-1]),
                    timeStamp=now_datetime(),
                )
                topic = Sem.GPS_FIX_COMMAND_STATUS.spec.name
                rogue.put(key("ship-2", domain, V1, topic), status.serialize(), attachment=attachment(Kind.SAMPLE, 0))

        poser = threading.Thread(target=pose, daemon=True)
        poser.start()
        relay("--domain", str(far), "--side", "operations", "--name", "ops", "--connect", router, "--link-class", "lan")
        consumer = Consumer(far)
        statuses = consumer.bus.reader(Sem.GPS_FIX_COMMAND_STATUS)
        fix = consumer.command(Service.GPS_FIX, V1)
        time.sleep(2)  # both say they carry vehicle 1: the command waits
        consumer.pump()
        assert commands == [] and consumer.commands[fix].statuses == []
        claim.undeclare()  # ship-1 alone
        seen = consumer.wait_terminal(fix, 20)
        assert seen.statuses == HAPPY
        posing.set()
        poser.join(5)
        written = {uuid.UUID(bytes=bytes(x.sessionID)) for x in take_each(statuses)[0]}
        assert commands == [] and written.isdisjoint(sessions)
        listening.undeclare()
    finally:
        posing.set()
        if consumer is not None:
            consumer.close()
        rogue.close()
        link.close()


@pytest.mark.slow
@pytest.mark.parametrize("controlled", [True, False], ids=["access-control", "no-access-control"])
def test_access_control_gives_no_other_relay_s_certificate_a_vehicles_commands(
    sim, domain: int, relay, tmp_path: Path, controlled: bool
) -> None:
    """The router's access control (--vehicle-relays, --operations-relays, by certificate common name): a session with
    ship-2's certificate subscribes to what ship-1's relay subscribes to (`sem/ship-1/<its domain>/**`, relay.py)
    while a GPS fix for ship-1's vehicle completes through ship-1's real relay and is cleaned up. With the access
    control it gets nothing; without it (mutual TLS only), the same subscription gets the command and its dispose."""
    far = free_domain(taken=domain)
    fleet = Authority(tmp_path, "fleet-ca")
    endpoint = acl_router(relay, fleet, "ship-1,ship-2" if controlled else None)
    sim()
    lan = ("--connect", endpoint, "--link-class", "lan")
    relay("--domain", str(domain), "--name", "ship-1", *lan, *tls(fleet, "ship-1"))
    relay("--domain", str(far), "--side", "operations", "--name", "ops", *lan, *tls(fleet, "ops"))
    impostor = fleet_session(fleet, "ship-2", endpoint)
    consumer = Consumer(far)
    got: list[tuple[str, Kind | None]] = []

    def heard(sample: zenoh.Sample) -> None:
        meta = read_attachment(sample.attachment.to_bytes() if sample.attachment is not None else None)
        got.append((str(sample.key_expr), meta[0] if meta is not None else None))

    try:
        watch = impostor.declare_subscriber(f"{PREFIX}/ship-1/{domain}/**", heard)
        consumer.wait(lambda: V1 in consumer.reports[Sem.INS_REPORT], 30, "vehicle 1 across the link")
        fix = consumer.command(Service.GPS_FIX, V1)
        seen = consumer.wait_terminal(fix, 20)
        assert seen.statuses == HAPPY
        consumer.dispose(fix)
        consumer.wait(lambda: seen.status_disposed and seen.ack_disposed, 15, "status and ack disposed after cleanup")
        time.sleep(1)  # what the router forwards the impostor has come
        command = key("ship-1", domain, V1, Sem.GPS_FIX_COMMAND.spec.name)
        if controlled:
            assert got == []
        else:
            assert list(dict.fromkeys(kind for k, kind in got if k == command)) == [Kind.SAMPLE, Kind.DISPOSE], got
        watch.undeclare()
    finally:
        consumer.close()
        impostor.close()


def test_a_vehicles_relay_writes_only_its_own_domain_s_commands(sim, domain: int, relay, tmp_path: Path) -> None:
    """Two vehicles' relays of one name (the default, the host's name, for two domains of one machine), no access
    control: the command for a vehicle of one domain, and its cleanup, are written on that domain only."""
    far, other = free_domain(taken=domain), free_domain(taken=domain)
    sim()
    port = join(relay, domain, far, tmp_path, "--link-class", "lan").port
    relay("--domain", str(other), "--name", "ship-1", "--connect", f"tcp/127.0.0.1:{port}", "--link-class", "lan")
    consumer, elsewhere = Consumer(far), Bus(other)
    try:
        commands = elsewhere.reader(Sem.GPS_FIX_COMMAND)
        time.sleep(2)  # the other relay's subscription known to the router
        fix = consumer.command(Service.GPS_FIX, V1)
        seen = consumer.wait_terminal(fix, 20)
        assert seen.statuses == HAPPY
        consumer.dispose(fix)
        consumer.wait(lambda: seen.status_disposed and seen.ack_disposed, 15, "status and ack disposed after cleanup")
        assert take_each(commands)[0] == []  # neither the command nor its dispose reached the other domain
    finally:
        consumer.close()
        elsewhere.close()


@pytest.mark.parametrize("impostor", ["ship-2", "operations"])
def test_access_control_lets_no_vehicles_relay_pose_as_an_operations_relay(relay, tmp_path: Path, impostor: str) -> None:
    """A new operations relay's liveliness token makes every vehicles' relay send again all it sent: the router keeps
    a vehicles' relay's token as an operations relay's from the others, as it keeps the operations relay's own."""
    fleet = Authority(tmp_path, "fleet-ca")
    endpoint = acl_router(relay, fleet, f"ship-1,{impostor}")
    ship, ops, intruder = (fleet_session(fleet, name, endpoint) for name in ("ship-1", "ops", impostor))
    heard: list[str] = []
    try:
        watch = ship.liveliness().declare_subscriber(
            f"{LIVELINESS}/operations/**", lambda s: heard.append(str(s.key_expr)), history=True
        )
        posing = intruder.liveliness().declare_token(f"{LIVELINESS}/operations/{impostor}/{intruder.zid()}")
        token = ops.liveliness().declare_token(f"{LIVELINESS}/operations/ops/{ops.zid()}")
        deadline = time.monotonic() + 10
        while not any("/ops/" in k for k in heard) and time.monotonic() < deadline:
            time.sleep(0.05)
        assert any("/ops/" in k for k in heard), "the operations relay's token never came"
        time.sleep(1)
        assert [k for k in heard if "/ops/" not in k] == []
        for declared in (watch, posing, token):
            declared.undeclare()
    finally:
        for s in (ship, ops, intruder):
            s.close()


def test_access_control_lets_a_vehicles_relay_say_which_vehicles_it_carries_and_no_other_relay_s(relay, tmp_path: Path) -> None:
    """The consoles learn the hop from the tokens of the vehicles a relay carries (relay/hops.py): the router lets a
    vehicles' relay declare them under its own name (one a key chunk holds as it is, or one it holds encoded: a space),
    for the operations relay to see, and not under another's."""
    fleet = Authority(tmp_path, "fleet-ca")
    endpoint = acl_router(relay, fleet, "Ship One,ship-2")
    ship, ops, other = (fleet_session(fleet, name, endpoint) for name in ("Ship One", "ops", "ship-2"))
    heard: list[str] = []
    try:
        watch = ops.liveliness().declare_subscriber(f"{CARRIES}/**", lambda s: heard.append(str(s.key_expr)), history=True)
        posing = other.liveliness().declare_token(carries_key("Ship One", 0, uuid.UUID(int=2)))
        token = ship.liveliness().declare_token(carries_key("Ship One", 0, uuid.UUID(int=1)))
        deadline = time.monotonic() + 10
        while not heard and time.monotonic() < deadline:
            time.sleep(0.05)
        time.sleep(1)
        assert heard == [carries_key("Ship One", 0, uuid.UUID(int=1))]
        for declared in (watch, posing, token):
            declared.undeclare()
    finally:
        for s in (ship, ops, other):
            s.close()


def test_access_control_with_each_relay_s_vehicles_listed_lets_no_relay_claim_or_report_another_s_vehicle(
    relay, tmp_path: Path
) -> None:
    """Ownership goes to the relay that alone declares a vehicle: without a list, a relay that declares another's
    vehicle before that vehicle's own relay does would own it and get its commands. With each relay's vehicles listed
    (`--vehicle-relays NAME=GUID+GUID`), the router refuses ship-2's token and samples for ship-1's vehicle, whichever
    comes first, and passes those of its own."""
    fleet = Authority(tmp_path, "fleet-ca")
    mine, theirs = uuid.UUID(int=1), uuid.UUID(int=2)
    endpoint = acl_router(relay, fleet, f"ship-1={mine},ship-2={theirs}")
    ops, other = (fleet_session(fleet, name, endpoint) for name in ("ops", "ship-2"))
    tokens: list[str] = []
    samples: list[str] = []
    try:
        watch = ops.liveliness().declare_subscriber(f"{CARRIES}/**", lambda s: tokens.append(str(s.key_expr)), history=True)
        data = ops.declare_subscriber(f"{PREFIX}/**", lambda s: samples.append(str(s.key_expr)))
        time.sleep(1)  # the subscriptions in place at the router
        claim = other.liveliness().declare_token(carries_key("ship-2", 0, mine, 5000))  # before ship-1 ever did
        token = other.liveliness().declare_token(carries_key("ship-2", 0, theirs, 5000))
        topic = Sem.GPS_FIX_COMMAND_STATUS.spec.name
        deadline = time.monotonic() + 10
        while (not tokens or not samples) and time.monotonic() < deadline:
            for vehicle in (mine, theirs):
                other.put(key("ship-2", 0, vehicle, topic), b"status", attachment=attachment(Kind.SAMPLE, 0))
            time.sleep(0.2)
        time.sleep(1)
        assert tokens == [carries_key("ship-2", 0, theirs, 5000)]
        assert set(samples) == {key("ship-2", 0, theirs, topic)}, samples
        for declared in (watch, data, claim, token):
            declared.undeclare()
    finally:
        for s in (ops, other):
            s.close()


@pytest.mark.slow
def test_sem_check_on_the_far_side_passes_a_near_vehicle(sim, domain: int, relay, tmp_path: Path) -> None:
    """The relay is transparent to the ICD's flow: sem-check, commands included, passes a vehicle of the other domain
    (on a LAN-class link: the satellite caps space reports beyond the check's gaps)."""
    far = free_domain(taken=domain)
    sim("--time-scale", "0.2")  # as test_check's sem-sim run: the cancel reaches the fix while EXECUTING
    join(relay, domain, far, tmp_path, "--link-class", "lan")
    consumer = Consumer(far)
    try:
        consumer.wait(lambda: V1 in consumer.reports[Sem.INS_REPORT], 20, "the vehicle across the link")
    finally:
        consumer.close()
    report = tmp_path / "junit.xml"
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = check_main(["--domain", str(far), "--commands", "--window", "1.5", "--max-gap", "3", "--junit", str(report)])
    assert code == 0, out.getvalue() + err.getvalue()


def test_a_status_port_in_use_is_one_line(domain: int, relay) -> None:
    endpoint = f"tcp/127.0.0.1:{free_port()}"
    relay("--router", "--listen", endpoint)
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        p = subprocess.run(
            [
                sys.executable,
                "-m",
                "sem_console.relay.cli",
                "--domain",
                str(domain),
                "--connect",
                endpoint,
                "--status-port",
                str(port),
                "--log-level",
                "error",
            ],
            capture_output=True,
            text=True,
            timeout=60,
        )
    assert (p.returncode, p.stderr) == (
        2,
        f"sem-relay: error: --status-port {port}: cannot listen on it (Address already in use): give another port\n",
    )


def test_a_cancel_taken_while_its_vehicle_s_owner_releases_the_held_command_goes_after_it(
    domain: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Operations side: a command held for a vehicle no relay owns yet is released when one does (its token); its
    cancel, taken from a console in that moment, goes after it, never before (the vehicle would then take the cancel
    of nothing, start the command and run it). Real Zenoh and Cyclone DDS; the write of the vehicle's sample that came
    before its relay's token, done in that step, held open."""
    config = zenoh.Config()
    config.insert_json5("scouting/multicast/enabled", "false")
    session, bus = zenoh.open(config), Bus(domain)
    relay = Relay(RelayOptions(side="operations", name="ops"), bus, session)
    sent: list[Kind] = []
    put = relay._put
    monkeypatch.setattr(relay, "_put", lambda out: (sent.append(Kind((read_attachment(out.attachment) or (0, 0))[0])), put(out)))
    entered, gate = threading.Event(), threading.Event()

    def held_open(*_: Any) -> None:
        entered.set()
        gate.wait(10)

    monkeypatch.setattr(relay.dds, "write", held_open)
    instance = (Sem.GPS_FIX_COMMAND.spec.name, False, 7)
    try:
        relay._taken(Taken(Sem.GPS_FIX_COMMAND, Kind.SAMPLE, b"command", 0, V1, instance))  # held: V1 not heard
        assert sent == []
        session.put(
            key("ship-1", domain, V1, Sem.GPS_FIX_COMMAND_STATUS.spec.name), b"status", attachment=attachment(Kind.SAMPLE, 0)
        )
        time.sleep(0.5)  # received, and kept: no relay owns V1 yet
        assert not entered.is_set()
        token = session.liveliness().declare_token(carries_key("ship-1", domain, V1))
        assert entered.wait(10), "the vehicle's sample was not written when ship-1 came to own it"
        cancel = threading.Thread(target=relay._taken, args=(Taken(Sem.GPS_FIX_COMMAND, Kind.DISPOSE, b"key", 0, V1, instance),))
        cancel.start()
        cancel.join(0.5)  # with the held command not sent yet, the cancel waits for it
        gate.set()
        cancel.join(10)
        deadline = time.monotonic() + 10
        while len(sent) < 2 and time.monotonic() < deadline:
            time.sleep(0.05)
        assert sent == [Kind.SAMPLE, Kind.DISPOSE]
        token.undeclare()
    finally:
        gate.set()
        relay.close()
        bus.close()
        session.close()


def test_a_sample_that_comes_as_its_vehicle_gets_its_owner_is_written_after_those_kept_before(
    domain: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Operations side: the samples that came before their relay's token are written, in the order they came, before
    one that comes between the relay being made the vehicle's owner and those being written (a status written before
    the one it followed is the console's newest; a report, the vehicle's state). Real Zenoh and Cyclone DDS; the
    writing of those kept held open."""
    config = zenoh.Config()
    config.insert_json5("scouting/multicast/enabled", "false")
    session, bus = zenoh.open(config), Bus(domain)
    relay = Relay(RelayOptions(side="operations", name="ops"), bus, session)
    assert relay.hops is not None
    written: list[bytes] = []
    monkeypatch.setattr(relay.dds, "write", lambda _sem, _kind, payload, _ns: written.append(payload))
    entered, gate = threading.Event(), threading.Event()
    owned = relay.hops.on_owned

    def held_open(vehicle: uuid.UUID, origin: tuple[str, int]) -> None:
        entered.set()
        gate.wait(10)
        owned(vehicle, origin)

    relay.hops.on_owned = held_open
    topic = key("ship-1", domain, V1, Sem.GPS_FIX_COMMAND_STATUS.spec.name)
    tokens: list[Any] = []
    declare = threading.Thread(
        target=lambda: tokens.append(session.liveliness().declare_token(carries_key("ship-1", domain, V1)))
    )
    try:
        session.put(topic, b"ISSUED", attachment=attachment(Kind.SAMPLE, 1))
        deadline = time.monotonic() + 10
        while (V1, ("ship-1", domain)) not in relay._early and time.monotonic() < deadline:
            time.sleep(0.05)
        declare.start()
        assert entered.wait(10), "ship-1 was not made vehicle 1's owner"
        assert relay.hops.owner_of(V1) == ("ship-1", domain)
        session.put(topic, b"COMMANDED", attachment=attachment(Kind.SAMPLE, 2))
        early = relay._early.get((V1, ("ship-1", domain)), ())
        deadline = time.monotonic() + 10
        while not written and len(early) < 2 and time.monotonic() < deadline:
            time.sleep(0.05)  # received: written at once, or kept behind the first
        gate.set()
        deadline = time.monotonic() + 10
        while len(written) < 2 and time.monotonic() < deadline:
            time.sleep(0.05)
        assert written == [b"ISSUED", b"COMMANDED"]
    finally:
        gate.set()
        declare.join(10)
        for token in tokens:
            token.undeclare()
        relay.close()
        bus.close()
        session.close()


def test_a_far_console_commands_vehicles_of_both_versions_through_its_rest_api_over_an_impaired_link(
    sim, domain: int, relay, tmp_path: Path
) -> None:
    """Two relays and a router joined through a link of 600 ms round trip, 5 % loss and 64 kbit/s, at the satellite
    class (its caps shortened): a console on the far domain sees vehicles of both UMAA versions, and through its REST
    API a GPS fix cancelled, a GPS fix, and an INS command of each version complete, each cleaned up. The operations
    relay is restarted while the fix runs: its new writer writes the fix's statuses again, and the console records
    each once."""
    far = free_domain(taken=domain)
    links: list[Impairment] = []

    def impaired(port: int) -> str:
        links.append(Impairment(("127.0.0.1", port), rtt=0.6, rate_bytes=8000, loss=0.05))
        return links[0].endpoint

    sim("--vehicles", "2", "--umaa-6-0-vehicles", "2", "--surface-seconds", "60")  # a fix takes 3 s: time to cancel
    caps = "GPSReport=5,GlobalPoseReport=2,GPSFixReport=2"
    joined = join(relay, domain, far, tmp_path, "--caps", caps, via=impaired)
    console = ConsoleProcess(far, tmp_path / "far.sqlite3", ["--comms-lost-timeout", "15"], {}).start()
    base = console.url

    def command(session: str) -> dict[str, Any]:
        return dict(http.get(f"{base}/api/commands/{session}").json())

    def wait(session: str, done: Callable[[dict[str, Any]], bool], timeout: float = 30) -> dict[str, Any]:
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            c = command(session)
            if done(c):
                return c
            time.sleep(0.1)
        raise AssertionError(f"command {session}: {command(session)}")

    def run(path: str, body: dict[str, Any]) -> str:
        r = http.post(f"{base}{path}", json=body)
        assert r.status_code == 201, r.text
        return str(r.json()["sessionId"])

    def finished(c: dict[str, Any]) -> bool:
        return bool(c["terminal"] and c["cleanedUp"])

    try:
        deadline, versions = time.monotonic() + 40, {}
        while versions != {str(V1): "3.0.1", str(V2): "6.0"} and time.monotonic() < deadline:
            time.sleep(0.2)
            providers = http.get(f"{base}/api/providers").json()
            versions = {p["id"]: p["umaaVersion"] for p in providers if p["link"] == "live"}
        assert versions == {str(V1): "3.0.1", str(V2): "6.0"}
        canceled = run(f"/api/providers/{V1}/gps-fix", {})
        wait(canceled, lambda c: c["status"] == "EXECUTING")
        assert http.delete(f"{base}/api/commands/{canceled}").status_code == 200
        c = wait(canceled, finished)
        assert [t["status"] for t in c["transitions"]] == ["ISSUED", "COMMANDED", "EXECUTING", "CANCELED"]
        fix = run(f"/api/providers/{V1}/gps-fix", {})
        # the vehicle surfaced for the first fix, so this one may take under a second, and its statuses cross the link
        # together: EXECUTING may never be seen alone. The operations relay is restarted while the fix runs or just
        # after; either way its new writer writes the fix's statuses again.
        wait(fix, lambda c: c["status"] in ("EXECUTING", "COMPLETED"))
        joined.far.end()
        relay(*joined.far_args)
        done = {fix: wait(fix, finished, 40)}
        for vehicle, state in ((V1, "RESTARTING"), (V2, "STATIONARY_ALIGN")):
            session = run(f"/api/providers/{vehicle}/inertial-sensor", {"state": state})
            done[session] = wait(session, finished)
        for c in done.values():
            assert [t["status"] for t in c["transitions"]] == ["ISSUED", "COMMANDED", "EXECUTING", "COMPLETED"], c
            assert c["violations"] == []
        assert links[0].lost >= 1  # the loss was on the link
    finally:
        console.end()
        for link in links:
            link.close()


def test_samples_of_vehicles_no_relay_declares_are_kept_for_a_bounded_number_of_vehicles(domain: int) -> None:
    """Operations side: samples under ids no relay declares (a relay that never does, or a flood of made-up ids) are
    kept for at most EARLY_VEHICLES vehicles, the oldest given up; the newest are there when a relay declares its own.
    Real Zenoh and Cyclone DDS."""
    config = zenoh.Config()
    config.insert_json5("scouting/multicast/enabled", "false")
    session, bus = zenoh.open(config), Bus(domain)
    relay = Relay(RelayOptions(side="operations", name="ops"), bus, session)
    try:
        topic = Sem.GPS_FIX_COMMAND_STATUS.spec.name
        ids = [uuid.UUID(int=i + 1) for i in range(EARLY_VEHICLES + 10)]
        for vehicle in ids:
            session.put(key("ship-9", domain, vehicle, topic), b"status", attachment=attachment(Kind.SAMPLE, 0))
        deadline = time.monotonic() + 10
        while (ids[-1], ("ship-9", domain)) not in relay._early and time.monotonic() < deadline:
            time.sleep(0.05)
        assert len(relay._early) == EARLY_VEHICLES
        assert (ids[0], ("ship-9", domain)) not in relay._early and (ids[-1], ("ship-9", domain)) in relay._early
    finally:
        relay.close()
        bus.close()
        session.close()


def test_a_relay_hears_what_the_other_side_sends_the_moment_its_token_comes(domain: int) -> None:
    """A relay of the other side sends everything again the moment a new relay's liveliness token comes: the relay
    subscribes to its keys before it declares its token, or what came at once would be lost (a vehicles' relay that
    saw the operations relay start before its subscription sent its statuses to no one). Real Zenoh and Cyclone DDS."""
    port = free_port()

    def config(mode: str, endpoints: str) -> zenoh.Config:
        c = zenoh.Config()
        c.insert_json5("mode", json.dumps(mode))
        c.insert_json5("scouting/multicast/enabled", "false")
        c.insert_json5(endpoints, json.dumps([f"tcp/127.0.0.1:{port}"]))
        return c

    router = zenoh.open(config("router", "listen/endpoints"))
    ship = zenoh.open(config("client", "connect/endpoints"))
    came = threading.Event()

    def answer(sample: zenoh.Sample) -> None:  # as a vehicles' relay does: the operations relay came, all goes again
        topic = Sem.GPS_FIX_COMMAND_STATUS.spec.name
        ship.put(key("ship-1", domain, V1, topic), b"status", attachment=attachment(Kind.SAMPLE, 0))
        came.set()

    watch = ship.liveliness().declare_subscriber(f"{LIVELINESS}/operations/**", answer)
    session, bus = zenoh.open(config("client", "connect/endpoints")), Bus(domain)
    relay = Relay(RelayOptions(side="operations", name="ops"), bus, session)
    try:
        deadline = time.monotonic() + 10
        while (V1, ("ship-1", domain)) not in relay._early and time.monotonic() < deadline:
            time.sleep(0.05)
        assert came.is_set() and (V1, ("ship-1", domain)) in relay._early  # kept until ship-1 says it carries V1
    finally:
        watch.undeclare()
        relay.close()
        bus.close()
        for s in (session, ship, router):
            s.close()


def test_a_far_console_marks_the_vehicles_via_the_relay_and_a_silent_relay_is_one_alarm(
    sim, domain: int, relay, tmp_path: Path
) -> None:
    """The console knows the hop: a console on the far domain shows each vehicle "via relay ship-1" with the age of its
    newest data; the link cut, it raises one alarm naming the relay and its two vehicles, and no link-lost for either;
    a vehicle then heard on the console's own domain is no longer marked (the mark follows its latest path)."""
    far = free_domain(taken=domain)
    links: list[Impairment] = []

    def impaired(port: int) -> str:
        links.append(Impairment(("127.0.0.1", port)))
        return links[0].endpoint

    sim("--vehicles", "2", "--umaa-6-0-vehicles", "2")
    join(relay, domain, far, tmp_path, "--link-class", "lan", via=impaired)
    console = ConsoleProcess(far, tmp_path / "far.sqlite3", ["--comms-lost-timeout", "3"], {}).start()
    try:

        def marked() -> dict[str, Any]:
            providers = http.get(f"{console.url}/api/providers").json()
            return {p["id"]: p["relay"] for p in providers if p.get("relay")}

        deadline = time.monotonic() + 30
        while set(marked()) != {str(V1), str(V2)} and time.monotonic() < deadline:
            time.sleep(0.2)
        hops = marked()
        assert set(hops) == {str(V1), str(V2)}, hops
        for hop in hops.values():
            assert hop["name"] == "ship-1" and 0 <= hop["ageSeconds"] < 3 and hop["dataTime"] > time.time() - 10
        assert http.get(f"{console.url}/api/alarms").json() == []
        links[0].outage(120)  # the link goes quiet
        deadline = time.monotonic() + 30
        alarms: list[dict[str, Any]] = []
        while not any(a["kind"] == "relay-silent" for a in alarms) and time.monotonic() < deadline:
            time.sleep(0.2)
            alarms = http.get(f"{console.url}/api/alarms").json()
        time.sleep(2)  # and nothing more comes: no alarm per vehicle
        alarms = http.get(f"{console.url}/api/alarms").json()
        assert [(a["kind"], a["text"], a["providerId"]) for a in alarms] == [
            ("relay-silent", "relay ship-1 silent: 2 vehicles", None)
        ]
        lost = {p["id"]: p["link"] for p in http.get(f"{console.url}/api/providers").json()}
        assert lost == {str(V1): "lost", str(V2): "lost"}  # lost, by their own time stamps: one alarm for both
        # vehicle 1 now heard on the console's own domain (the relay still says it carries it): the mark follows
        here = Bus(far)
        try:
            writer = here.writer(Sem.INS_REPORT)
            deadline = time.monotonic() + 20
            while set(marked()) != {str(V2)} and time.monotonic() < deadline:
                writer.write(
                    InertialSensorReportType(state=Ins.ON, status=Op.OPERATIONAL, source=to_guid(V1), timeStamp=now_datetime())
                )
                time.sleep(0.2)
            assert set(marked()) == {str(V2)}
        finally:
            here.close()
    finally:
        console.end()
        for link in links:
            link.close()


def test_a_relay_s_write_of_its_hops_that_fails_is_one_warning_not_the_end_of_its_timer(
    domain: int, caplog: pytest.LogCaptureFixture
) -> None:
    """Operations side: the write of the relays' topic failing in Cyclone (here: its participant already deleted) is one
    warning naming the relay, not an exception out of the relay's timer thread (its caps' slots and resends run on it)."""
    from sem_console.relay.hops import Hops

    config = zenoh.Config()
    config.insert_json5("scouting/multicast/enabled", "false")
    session, bus = zenoh.open(config), Bus(domain)
    hops = Hops(session, bus, lambda *_: None)
    try:
        hops.owner[V1] = ("ship-1", 0)
        hops.heard_from(V1, 100.0)
        bus.close()  # the writer's participant gone: Cyclone refuses the write
        hops.write(101.0)
        assert [r.getMessage().split(":")[0] for r in caplog.records if r.levelname == "WARNING"] == [
            "could not write relay ship-1's link to the consoles"
        ]
    finally:
        hops.close()
        bus.close()
        session.close()


def test_a_console_marks_a_vehicle_whose_relay_it_learns_after_the_relay_s_report(domain: int, tmp_path: Path) -> None:
    """The console learns the operations relays' participants from their samples of SEMConsole_RelayLink, which come in
    their own time: a report a relay wrote before the console learned it is the relay's once its sample comes (a
    console starting, an operations relay restarted: a new participant), not only at the vehicle's next report (a
    minute at the satellite caps); a vehicle heard from another participant is unmarked, and stays so while it is
    heard that way too (not marked and unmarked at each report: an event to every station each time)."""
    settings = Settings(domain=domain, db_path=tmp_path / "db", recordings_dir=tmp_path / "recordings", comms_lost_timeout=2.0)
    first, restarted, here = uuid.uuid4(), uuid.uuid4(), uuid.uuid4()  # two relays' participants, the vehicle's own
    with TestClient(create_app(settings), base_url="http://localhost") as client:
        console = client.app.state.console  # type: ignore[attr-defined]

        def report(writer: uuid.UUID) -> None:  # on the console's loop, as the ingest hands them
            console.on_reports([ReportItem("GPSReport", V1, {}, [], True, console.clock.wall(), writer=writer)])

        def link(writer: uuid.UUID) -> None:
            console.on_relay_links([(RelayLink(relay="ship-1", vehicles=[str(V1)], ageMs=0), writer)], console.clock.wall())

        def mark() -> str | None:
            [p] = client.get("/api/providers").json()
            return None if p["relay"] is None else str(p["relay"]["name"])

        client.portal.call(report, first)
        assert mark() is None  # not known for a relay's yet
        client.portal.call(link, first)
        assert mark() == "ship-1"
        client.portal.call(report, restarted)
        client.portal.call(link, restarted)
        assert mark() == "ship-1"
        client.portal.call(report, here)
        client.portal.call(link, restarted)
        assert mark() is None
        client.portal.call(report, restarted)  # heard both ways: shown direct, not marked at every other report
        assert mark() is None
        time.sleep(2.1)  # nothing directly for its comms-lost timeout: the relay's path is its path
        client.portal.call(report, restarted)
        assert mark() == "ship-1"


def test_a_far_console_at_its_default_timeout_keeps_vehicles_behind_the_satellite_caps_live(
    sim, domain: int, relay, tmp_path: Path
) -> None:
    """At the satellite caps a vehicle's newest data crosses the link every 5 s; the console's comms-lost timeout is 3 s
    by default. Each vehicles' relay says how long its caps may keep a vehicle quiet (its token), and the console adds
    it: a vehicle of either version stays live between its capped reports, with no link-lost alarm (each vehicle went
    lost and regained at every fix before)."""
    far = free_domain(taken=domain)
    sim("--vehicles", "2", "--umaa-6-0-vehicles", "2")
    join(relay, domain, far, tmp_path, "--link-class", "satellite")
    console = ConsoleProcess(far, tmp_path / "far.sqlite3", [], {}).start()
    try:
        ids = {str(V1), str(V2)}
        deadline = time.monotonic() + 40
        providers: list[dict[str, Any]] = []
        while time.monotonic() < deadline and {p["id"] for p in providers if p.get("relay")} != ids:
            time.sleep(0.25)
            providers = http.get(f"{console.url}/api/providers").json()
        assert {p["id"] for p in providers if p.get("relay")} == ids, providers
        deadline = time.monotonic() + 5  # said by the relay's next sample (once a second)
        while time.monotonic() < deadline and any(p["relay"]["quietSeconds"] != 5.0 for p in providers):
            time.sleep(0.25)
            providers = http.get(f"{console.url}/api/providers").json()
        assert [p["relay"]["quietSeconds"] for p in providers] == [5.0, 5.0]  # the dashboard waits as long for "stale"
        states: set[tuple[str, str]] = set()
        until = time.monotonic() + 12  # two of the caps' 5 s and more
        while time.monotonic() < until:
            states |= {(p["id"], p["link"]) for p in http.get(f"{console.url}/api/providers").json()}
            time.sleep(0.25)
        assert states == {(v, "live") for v in ids}, states
        assert [a for a in http.get(f"{console.url}/api/alarms").json() if a["kind"] == "link-lost"] == []
    finally:
        console.end()


def test_a_vehicle_moved_to_another_ship_s_network_is_carried_by_that_ship_s_relay_once_the_first_lets_it_go(
    domain: int,
) -> None:
    """ship-1 carries vehicle 1; the vehicle moves to ship-2's network. ship-1's relay, not hearing it for its
    --vehicle-gone-seconds, undeclares its token while ship-1 itself is still there: the operations side then gives the
    vehicle to ship-2, which says it carries it (refused while ship-1 did), and the vehicle's commands go there. A
    vehicle whose relay's link is lost (its relay's own token gone too) stays that relay's. Real Zenoh tokens."""
    config = zenoh.Config()
    config.insert_json5("scouting/multicast/enabled", "false")
    session, bus = zenoh.open(config), Bus(domain)
    owned: list[tuple[uuid.UUID, tuple[str, int]]] = []
    hops = Hops(session, bus, lambda vehicle, origin: owned.append((vehicle, origin)))
    ship_1 = Carried(session, "ship-1", domain, gone_after=60)
    declared: list[Any] = []
    try:
        hops.start()
        declared += [session.liveliness().declare_token(f"{RELAYS}/{name}/{name}-session") for name in ("ship-1", "ship-2")]
        ship_1.saw(V1, 5.0, now=0.0)
        ship_1.saw(V2, 5.0, now=0.0)

        def owner(vehicle: uuid.UUID, origin: tuple[str, int] | None) -> None:
            deadline = time.monotonic() + 10
            while hops.owner_of(vehicle) != origin and time.monotonic() < deadline:
                hops.release(time.monotonic() + LEFT_GRACE)
                time.sleep(0.05)
            assert hops.owner_of(vehicle) == origin, (vehicle, hops.owner_of(vehicle), origin)

        owner(V1, ("ship-1", domain))
        declared.append(session.liveliness().declare_token(carries_key("ship-2", domain, V1, 5000)))  # moved there
        time.sleep(0.5)
        hops.release(time.monotonic() + LEFT_GRACE)
        assert hops.owner_of(V1) == ("ship-1", domain)  # refused while ship-1 says it carries it
        ship_1.saw(V2, 5.0, now=30.0)  # vehicle 2 still heard by ship-1
        assert ship_1.forget(59.0) == [] and ship_1.forget(60.0) == [V1]
        owner(V1, ("ship-2", domain))
        assert owned[-1] == (V1, ("ship-2", domain))
        # ship-1's link lost: its vehicles' tokens and its own go, in any order (here its vehicle's first, its own
        # within LEFT_GRACE): vehicle 2 stays ship-1's
        ship_1.close()
        time.sleep(0.3)
        declared.pop(0).undeclare()
        time.sleep(0.5)
        hops.release(time.monotonic() + LEFT_GRACE)
        assert hops.owner_of(V2) == ("ship-1", domain)
    finally:
        for token in declared:
            token.undeclare()
        ship_1.close()
        hops.close()
        session.close()
        bus.close()


@pytest.mark.parametrize("watch", ["sem/ship-1/0/**", "sem/ship-1/0/00000000-0000-0000-0000-000000000001/**"])
def test_access_control_with_a_relay_s_vehicles_listed_still_gives_it_its_vehicles_commands(
    relay, tmp_path: Path, watch: str
) -> None:
    """A listed vehicles' relay subscribes as `sem-relay` does (`sem/<name>/<domain>/**`, relay.py): the commands the
    operations relay puts for one of its listed vehicles must reach it."""
    fleet = Authority(tmp_path, "fleet-ca")
    mine = uuid.UUID(int=1)
    endpoint = acl_router(relay, fleet, f"ship-1={mine}")
    ship, ops = (fleet_session(fleet, name, endpoint) for name in ("ship-1", "ops"))
    got: list[str] = []
    try:
        sub = ship.declare_subscriber(watch, lambda s: got.append(str(s.key_expr)))
        time.sleep(1)  # the subscription in place at the router
        topic = Sem.GPS_FIX_COMMAND.spec.name
        deadline = time.monotonic() + 10
        while not got and time.monotonic() < deadline:
            ops.put(key("ship-1", 0, mine, topic), b"command", attachment=attachment(Kind.SAMPLE, 0))
            time.sleep(0.2)
        assert got, "a listed relay's own vehicle's command never reached it"
        sub.undeclare()
    finally:
        for s in (ship, ops):
            s.close()
