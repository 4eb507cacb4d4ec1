"""How `sem-console` reads the bus, against providers written here over real Cyclone DDS: every
sample applied once whatever its source timestamp, and nothing a reliable writer sends lost,
whatever its durability (the writer of the lossy-link test drops 30% of the packets it sends)."""

from __future__ import annotations

import time
import uuid
from typing import Any

import pytest
from cyclonedds.core import Policy, Qos
from cyclonedds.domain import Domain, DomainParticipant
from cyclonedds.internal import InvalidSample
from cyclonedds.pub import DataWriter
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic

from UMAA.Common.MaritimeEnumeration.CommandStatusEnumType import CommandStatusEnumType as St
from UMAA.Common.MaritimeEnumeration.CommandStatusReasonEnumType import CommandStatusReasonEnumType as Rs
from UMAA.Common.MaritimeEnumeration.InertialSensorOpStatusEnumType import InertialSensorOpStatusEnumType as Op
from UMAA.Common.MaritimeEnumeration.InertialSensorStateEnumType import InertialSensorStateEnumType as Ins
from UMAA.Common.Measurement import DateTime
from UMAA.SEM.InertialSensorStatus import InertialSensorReportType

from conftest import free_domain
from sem_console.dds.bus import Bus
from sem_console.dds.config import loopback_config
from sem_console.dds.qos import reader_qos
from sem_console.dds.topics import Sem
from sem_console.umaa.guid import from_guid, to_guid
from support import http
from test_console import HAPPY, WsClient, wait_command, wait_until


@pytest.fixture
def domain() -> int:
    """A domain no participant is in, this process's own included: a test here opens the domain with a configuration
    of its own, which Cyclone takes only from the first participant of a domain id in a process."""
    return free_domain(strict=True)


S = 1_000_000_000  # ns
RELIABLE_VOLATILE = Qos(Policy.Reliability.Reliable(S), Policy.Durability.Volatile, Policy.History.KeepAll)


class Provider:
    """A UMAA provider of InertialSensorReport and GPSFix command status, as another team would write
    one: its writers' QoS and source timestamps are chosen by the test."""

    def __init__(self, participant: DomainParticipant, qos: Qos | None = None, bus: Bus | None = None) -> None:
        self.id = uuid.uuid4()
        self.source = to_guid(self.id)

        def writer(sem: Sem) -> DataWriter:
            if qos is None and bus is not None:
                return bus.writer(sem)  # the project's own QoS: reliable, transient-local
            return DataWriter(participant, Topic(participant, sem.spec.name, sem.spec.type), qos=qos)

        self.reports = writer(Sem.INS_REPORT)
        self.statuses = writer(Sem.GPS_FIX_COMMAND_STATUS)
        self.commands = DataReader(
            participant,
            Topic(participant, Sem.GPS_FIX_COMMAND.spec.name, Sem.GPS_FIX_COMMAND.spec.type),
            qos=reader_qos(Sem.GPS_FIX_COMMAND.spec.cls),
        )
        self._received: dict[uuid.UUID, Any] = {}

    def report(self, at_ns: int, status: Op = Op.OPERATIONAL) -> None:
        stamp = DateTime(seconds=at_ns // S, nanoseconds=at_ns % S)
        self.reports.write(
            InertialSensorReportType(state=Ins.ON, status=status, source=self.source, timeStamp=stamp), timestamp=at_ns
        )

    def appear(self, url: str) -> None:
        def seen() -> bool:
            self.report(time.time_ns())
            return http.get(f"{url}/api/providers/{self.id}").status_code == 200

        wait_until(seen, 15, "the provider in the console")

    def gps_fix(self, url: str) -> Any:
        """Have the console command a GPS fix of this provider; returns the command as the provider received it."""
        # confirmLost: on a loaded machine this lossy provider may read as lost for a moment; the test is about statuses
        session = uuid.UUID(http.post(f"{url}/api/providers/{self.id}/gps-fix", json={"confirmLost": True}).json()["sessionId"])

        def received() -> Any:
            for s in self.commands.take(N=64):
                if not isinstance(s, InvalidSample):  # the console disposes what it has finished with
                    self._received[from_guid(s.sessionID)] = s
            return self._received.get(session)

        return wait_until(received, 15, f"command {session} at the provider")

    def status(self, cmd: Any, status: St, at_ns: int, reason: Rs = Rs.SUCCEEDED) -> None:
        stamp = DateTime(seconds=at_ns // S, nanoseconds=at_ns % S)
        self.statuses.write(
            Sem.GPS_FIX_COMMAND_STATUS.spec.type(
                source=self.source,
                commandStatus=status,
                commandStatusReason=reason,
                logMessage=status.name,
                sessionID=cmd.sessionID,
                timeStamp=stamp,
            ),
            timestamp=at_ns,
        )


def session_of(cmd: Any) -> str:
    return str(from_guid(cmd.sessionID))


def metrics(url: str) -> dict[str, Any]:
    return http.get(f"{url}/api/metrics").json()


def test_statuses_with_equal_or_earlier_source_timestamps_are_all_applied_in_order(console, domain: int) -> None:
    c = console()
    bus = Bus(domain)
    p = Provider(bus.participant, bus=bus)
    p.appear(c.url)
    ws = WsClient(c.ws_url)
    now = time.time_ns()
    tied = p.gps_fix(c.url)  # ISSUED then FAILED stamped in the same instant
    p.status(tied, St.ISSUED, now)
    p.status(tied, St.FAILED, now, Rs.RESOURCE_REJECTED)
    backward = p.gps_fix(c.url)  # a clock stepping back between every status
    for i, st in enumerate((St.ISSUED, St.COMMANDED, St.EXECUTING, St.COMPLETED)):
        p.status(backward, st, now - i * 60 * S)
    done = wait_command(c.url, session_of(tied))
    assert [(t["status"], t["reason"]) for t in done["transitions"]] == [("ISSUED", "SUCCEEDED"), ("FAILED", "RESOURCE_REJECTED")]
    assert done["transitions"][0]["providerTime"] == done["transitions"][1]["providerTime"] and done["violations"] == []
    done = wait_command(c.url, session_of(backward))
    assert [t["status"] for t in done["transitions"]] == HAPPY and done["violations"] == []
    times = [t["providerTime"] for t in done["transitions"]]
    assert times == sorted(times, reverse=True) and times[0] > times[-1]
    wait_until(lambda: ws.transitions(session_of(backward)) == HAPPY, 5, "every transition on the WebSocket, in order")
    assert ws.transitions(session_of(tied)) == ["ISSUED", "FAILED"]
    assert metrics(c.url)["samplesByReader"]["reliableTransientLocal"] >= 6


def test_a_report_clock_stepping_back_keeps_the_vehicle_live(console, domain: int) -> None:
    c = console()  # comms lost after 1 s without a sample
    bus = Bus(domain)
    p = Provider(bus.participant, bus=bus)
    p.appear(c.url)
    ws = WsClient(c.ws_url)
    start = time.time_ns()
    stepped_back = start - 3600 * S  # e.g. GPS time sync right after surfacing
    last = 0
    for i in range(60):  # 3 s at 20 Hz, the clock an hour back from the second sample on
        last = start if i == 0 else stepped_back + i * S // 20
        p.report(last, Op.OPERATIONAL if i % 2 else Op.INIT)
        time.sleep(0.05)
    want = {"seconds": last // S, "nanoseconds": last % S}

    def shown() -> bool:
        return http.get(f"{c.url}/api/providers/{p.id}").json()["reports"]["InertialSensorReport"]["report"]["timeStamp"] == want

    wait_until(shown, 5, "the last report, stamped an hour back")
    detail = http.get(f"{c.url}/api/providers/{p.id}").json()
    assert detail["link"] == "live"
    assert detail["topics"]["InertialSensorReport"]["samples"] >= 30  # the 5 ms conflation may merge a few, never the rest
    assert [m["event"] for m in ws.of("provider") if m["provider"]["id"] == str(p.id)] == []  # never lost


def lossy_participant(domain: int, per_mille: int) -> tuple[Domain, DomainParticipant]:
    """A participant of its own domain instance that drops `per_mille` of the packets it sends
    (Cyclone's Internal/Test/XmitLossiness): data, heartbeats and discovery alike."""
    # A lost participant announcement is otherwise repeated only every 30 s: announce twice a second.
    xml = (
        loopback_config()
        .replace("<Discovery>", "<Discovery><SPDPInterval>500 ms</SPDPInterval>")
        .replace("</Domain>", f"<Internal><Test><XmitLossiness>{per_mille}</XmitLossiness></Test></Internal></Domain>")
    )
    dom = Domain(domain, xml)  # first in this process for this domain id: Cyclone keeps this config
    return dom, DomainParticipant(domain)


def test_a_reliable_volatile_writer_loses_nothing_on_a_lossy_link(console, domain: int) -> None:
    """Every status of a reliable, volatile writer that loses 30% of its packets reaches the console,
    through its reliable volatile reader. Through the best-effort reader alone (as before), 32
    samples would all get through with a chance of 0.7^32, about 1 in 90,000."""
    c = console()
    _dom, participant = lossy_participant(domain, 300)
    p = Provider(participant, RELIABLE_VOLATILE)
    p.appear(c.url)
    commands = [p.gps_fix(c.url) for _ in range(8)]
    now = time.time_ns()
    for i, st in enumerate((St.ISSUED, St.COMMANDED, St.EXECUTING, St.COMPLETED)):
        for cmd in commands:
            p.status(cmd, st, now + i)
    for cmd in commands:
        done = wait_command(c.url, session_of(cmd), timeout=30)
        assert [t["status"] for t in done["transitions"]] == HAPPY and done["violations"] == []
    by_reader = metrics(c.url)["samplesByReader"]
    assert by_reader["reliableVolatile"] >= 32 + 1 and by_reader["bestEffort"] == 0


def test_a_transient_local_writer_that_published_before_the_console_started_is_shown(console, domain: int) -> None:
    bus = Bus(domain)
    p = Provider(bus.participant, bus=bus)
    p.report(time.time_ns(), Op.FINE_STATIONARY_ALIGNMENT_STARTED)  # once, before the console exists
    c = console()
    detail = wait_until(
        lambda: (lambda r: r.json() if r.status_code == 200 else None)(http.get(f"{c.url}/api/providers/{p.id}")),
        10,
        "the provider from the writer's history",
    )
    assert detail["reports"]["InertialSensorReport"]["report"]["status"] == "FINE_STATIONARY_ALIGNMENT_STARTED"
    assert metrics(c.url)["samplesByReader"] == {"reliableTransientLocal": 1, "reliableVolatile": 0, "bestEffort": 0}
