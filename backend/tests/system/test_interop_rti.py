"""Interoperability with a second DDS vendor: RTI Connext (its Python Connector) against our Cyclone stack.

RTI keeps UMAA's types as they are (our IDL as RTI's XML type representation, no extensibility given:
RTI's default, appendable; see rti/connector.py) and changes QoS only: the `rti` fixture runs Connext 6.1.2 and
7.7 on the recipe (the drop-in docs/rti/sem-console-interop.xml, profile AppendableGps; 7.7 with
NDDS_XTYPES_COMPLIANCE_MASK), other tests name RTI's plain defaults or the drop-in's Default. Covered both ways:
every topic whose type has no @optional member sample for sample, and the full command flow (ISSUED ->
COMPLETED, cancel by dispose, cleanup) with RTI as the vehicle and with RTI as the consumer.
The two types with @optional members (GPSReport, GPSFixReport) are exchanged in XCDR2 only; an
RTI endpoint left at XCDR1 for them is not matched, and the console and sem-check name the fix. An RTI
vehicle on AppendableGps is read through the console's appendable readers (one reader per extensibility);
an RTI consumer on that profile reads `sem-sim --gps-extensibility appendable`.
See docs/dds.md, "Other DDS vendors".
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import random
import subprocess
import sys
import threading
import time
import uuid
from collections import Counter
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest
from cyclonedds.core import Policy, Qos

from sem_console.codec.convert import to_json
from sem_console.codec.decode import REPORT_TOPICS
from sem_console.dds.bus import Bus, all_samples
from sem_console.dds.qos import TopicClass, reader_qos
from sem_console.dds.topics import Sem, Service, final_type_qos
from sem_console.sim.provider import vehicle_guid
from support import http
from support.rti.connector import RECIPE_ENV, RtiParticipant
from support.rti.connext7 import RemoteParticipant
from support.samplegen import random_sample, to_plain
from test_check import check, failed
from test_console import wait_until

pytestmark = pytest.mark.interop

PLAIN = [s for s in Sem if not s.spec.xcdr2_only]  # exchanged in XCDR1, RTI's default
COMMANDS = {Service.GPS_FIX: Sem.GPS_FIX_COMMAND, Service.INERTIAL_SENSOR: Sem.INS_COMMAND}
STATUS = {"FAILED": 0, "COMPLETED": 1, "ISSUED": 2, "COMMANDED": 3, "EXECUTING": 4, "CANCELED": 5}
REASON = {"CANCELED": 0, "SUCCEEDED": 8}
STATUS_NAME = {v: k for k, v in STATUS.items()}


def same(a: Any, b: Any) -> bool:
    """Equal as plain values. RTI's Connector hands samples over as JSON text: whole doubles come
    back as integers and a double may lose its last digits there (7.7's Connector prints some with 14
    significant digits), so doubles compare within 1e-14."""
    if isinstance(a, dict):
        return isinstance(b, dict) and set(a) == set(b) and all(same(a[k], b[k]) for k in a)
    if isinstance(a, list):
        return isinstance(b, list) and len(a) == len(b) and all(same(x, y) for x, y in zip(a, b, strict=True))
    if isinstance(a, float):
        return isinstance(b, (int, float)) and (math.isclose(a, b, rel_tol=1e-14) or (math.isnan(a) and math.isnan(b)))
    return a == b


class RtiFactory:
    """Makes RTI participants of one Connext version (closed by the fixture), on a profile of the drop-in unless the test
    names one (``recipe=None``: RTI's plain defaults). Connext 7 on AppendableGps gets the mask in its environment."""

    def __init__(self, version: str, request: pytest.FixtureRequest, profile: str | None) -> None:
        self.version, self.profile, self._request = version, profile, request
        self.made: list[Any] = []

    def __call__(self, domain: int, **kw: Any) -> Any:
        if self.profile is not None:
            kw.setdefault("recipe", self.profile)
        if self.version == "7":
            self._request.getfixturevalue("connext7")
            if kw.get("recipe") == "AppendableGps":
                kw.setdefault("env", RECIPE_ENV)
            p: Any = RemoteParticipant(domain, **kw)
        else:
            kw.pop("env", None)  # 6.1.2 reads no NDDS_XTYPES_COMPLIANCE_MASK
            p = RtiParticipant(domain, **kw)
        self.made.append(p)
        return p

    def close(self) -> None:
        for p in self.made:
            p.close()


def _factory(version: str, request: pytest.FixtureRequest, profile: str | None = None) -> Any:
    # Connext 7 on its defaults sends XTypes 1.3 type information that Cyclone cannot use, and then matches nothing
    # (test_connext7_on_defaults_matches_no_sem_topic): unless told otherwise it runs on the drop-in's Default profile
    # (docs/rti/sem-console-interop.xml: no type information), the least a console of today needs.
    f = RtiFactory(version, request, profile if profile is not None or version == "6" else "Default")
    return f.made, f


@pytest.fixture(params=["6", "7"], ids=["connext6.1.2", "connext7.7"])
def rti(request: pytest.FixtureRequest) -> Any:
    """An RTI participant factory on the recipe (the drop-in's AppendableGps profile; Connext 7 with the mask in its
    environment: docs/dds.md, "Which profile"), once with Connext 6.1.2 (in this process) and once with 7.7 (a child
    process). ``.version``: "6" or "7"."""
    f = RtiFactory(request.param, request, "AppendableGps")
    yield f
    f.close()


@pytest.fixture(
    params=[("6", None), ("6", "AppendableGps"), ("7", "Default"), ("7", "AppendableGps")],
    ids=["connext6.1.2-defaults", "connext6.1.2-recipe", "connext7.7-Default", "connext7.7-recipe"],
)
def rti_profile(request: pytest.FixtureRequest) -> Any:
    """As `rti`, on each profile the docs' matrix gives for the eight topics without optional members: Connext 6.1.2 on
    RTI's defaults and on the recipe, Connext 7.7 on the drop-in's Default (the least it needs) and on the recipe."""
    f = RtiFactory(request.param[0], request, request.param[1])
    yield f
    f.close()


@pytest.fixture
def rti6(request: pytest.FixtureRequest) -> Any:
    made, make = _factory("6", request)
    yield make
    for p in made:
        p.close()


@pytest.fixture
def rti7(request: pytest.FixtureRequest) -> Any:
    made, make = _factory("7", request)
    yield make
    for p in made:
        p.close()


def test_every_plain_topic_from_rti_decodes_in_cyclone(rti_profile: Callable[..., RtiParticipant], domain: int) -> None:
    bus = Bus(domain)
    readers = {s: bus.reader(s) for s in PLAIN}
    p = rti_profile(domain, writers=PLAIN)
    rng = random.Random(5)
    sent = {s: [random_sample(s.spec.type, rng) for _ in range(10)] for s in PLAIN}
    for s in PLAIN:
        p.wait_matched(s)
        for x in sent[s]:
            p.write(s, to_plain(x))
    for s in PLAIN:
        got: list[Any] = []
        wait_until(
            lambda s=s, got=got: got.extend(readers[s].take(N=100, condition=all_samples(readers[s]))) or len(got) >= 10,
            10,
            f"{s.spec.name} from RTI",
        )
        assert len(got) == len(sent[s])
        for x in sent[s]:
            assert any(same(to_plain(x), to_plain(g)) for g in got), (s.spec.name, to_plain(x))


def test_every_plain_topic_from_cyclone_decodes_in_rti(rti_profile: Callable[..., RtiParticipant], domain: int) -> None:
    bus = Bus(domain)
    p = rti_profile(domain, readers=PLAIN)
    writers = {s: bus.writer(s) for s in PLAIN}
    rng = random.Random(6)
    sent = {s: [random_sample(s.spec.type, rng) for _ in range(10)] for s in PLAIN}
    for s in PLAIN:
        p.wait_matched(s)
        for x in sent[s]:
            writers[s].write(x)
    for s in PLAIN:
        got: list[Any] = []
        wait_until(lambda s=s, got=got: got.extend(x for x, _ in p.take(s) if x) or len(got) >= 10, 10, f"{s.spec.name} in RTI")
        for x in sent[s]:
            assert any(same(to_plain(x), g) for g in got), (s.spec.name, to_plain(x))


def test_optional_member_topics_are_not_matched_in_xcdr1(rti6: Callable[..., RtiParticipant], domain: int) -> None:
    """RTI's default XCDR1 GPSReport/GPSFixReport endpoints do not match ours: nothing is exchanged in
    the one representation whose optional-member layout the two vendors read differently."""
    optional = [s for s in Sem if s.spec.xcdr2_only]
    readers = {s: Bus(domain).reader(s) for s in optional}  # each in a participant of its own,
    writers = {s: Bus(domain).writer(s) for s in optional}  # so a reader matches our writer only
    ins = Sem.INS_REPORT  # made last on both sides: once its endpoints match both ways, discovery has told each side of
    plain = (Bus(domain).reader(ins), Bus(domain).writer(ins))  # noqa: F841 - the other's GPS endpoints (SEDP is in order)
    p = rti6(domain, writers=[*optional, ins], readers=[*optional, ins])
    wait_until(
        lambda: len(p.outputs[ins].matched_subscriptions) == 2 and len(p.inputs[ins].matched_publications) == 2,
        10,
        "RTI's InertialSensorReport endpoints matched with ours",
    )
    for s in optional:
        assert len(readers[s].get_matched_publications()) == 1, s.spec.name  # our own XCDR2 writer
        assert len(writers[s].get_matched_subscriptions()) == 1, s.spec.name  # our own XCDR2 reader
        # RTI's writer and reader match each other (same participant, both named) and nothing of ours.
        assert p.outputs[s].matched_subscriptions == [{"name": s.name}], s.spec.name
        assert p.inputs[s].matched_publications == [{"name": s.name}], s.spec.name


class RtiVehicle:
    """A UMAA provider on RTI Connext: INS and fix-status reports, and the command flow of both services."""

    def __init__(self, p: Any) -> None:
        self.p = p
        self.guid = uuid.uuid4()
        self.handled: set[bytes] = set()
        self.ends: Counter[Sem] = Counter()  # command instances seen ending (disposed, unregistered), by topic
        self.hold: set[bytes] = set()  # commands to keep EXECUTING (to be canceled)

    def report(self) -> None:
        now = time.time()
        stamp = {"seconds": int(now), "nanoseconds": int((now % 1) * 1e9)}
        src = list(self.guid.bytes)
        self.p.write(Sem.INS_REPORT, {"state": 1, "status": 8, "source": src, "timeStamp": stamp})
        if Sem.GPS_FIX_REPORT in self.p.writers:  # read on the recipe (XCDR2); RTI's default XCDR1 must not reach the console
            self.p.write(
                Sem.GPS_FIX_REPORT,
                {
                    "altitudeMSL": {"altitude": 0.5},
                    "GPSFixCommandStatus": 2,
                    "GPSLatLongValid": True,
                    "magneticVariation": -0.17,
                    "position2DWithTime": {
                        "geodeticPosition": {"geodeticLatitude": {"latitude": 36.85}, "geodeticLongitude": {"longitude": -75.98}},
                        "timeAtPosition": now,
                    },
                    "SOG": 2.5,
                    "trueCourse": 1.2,
                    "velocity": {"downSpeed": 0.0, "eastSpeed": 1.0, "northSpeed": 2.0},
                    "source": src,
                    "timeStamp": stamp,
                },
            )
        if Sem.GPS_FIX_STATUS_REPORT not in self.p.writers:
            return
        self.p.write(
            Sem.GPS_FIX_STATUS_REPORT,
            {
                "carrierToNoise": [41.5, 38.0],
                "countDown": 3,
                "fixValid": True,
                "lowBkupBattery": False,
                "navSolution": 4,
                "originPosition": {
                    "geodeticPosition": {"geodeticLatitude": {"latitude": 36.85}, "geodeticLongitude": {"longitude": -75.98}},
                    "heightAboveEllipsoid": {"altitude": 12.5},
                },
                "pCode": False,
                "timeOut": False,
                "source": src,
                "timeStamp": stamp,
            },
        )

    @contextlib.contextmanager
    def reporting(self, period: float = 0.1) -> Iterator[None]:
        """Publish the reports every `period` s, in a thread, while the block runs (a vehicle sem-check watches)."""
        stop = threading.Event()

        def publish() -> None:
            while not stop.is_set():
                self.report()
                time.sleep(period)

        t = threading.Thread(target=publish, daemon=True)
        t.start()
        try:
            yield
        finally:
            stop.set()
            t.join()

    def status(self, service: Service, cmd: dict[str, Any], status: str, reason: str = "SUCCEEDED") -> None:
        now = time.time()
        self.p.write(
            service.status,
            {
                "source": list(self.guid.bytes),
                "sessionID": cmd["sessionID"],
                "commandStatus": STATUS[status],
                "commandStatusReason": REASON[reason],
                "logMessage": f"rti {status.lower()}",
                "timeStamp": {"seconds": int(now), "nanoseconds": int((now % 1) * 1e9)},
            },
        )

    def step(self) -> None:
        """Publish reports, answer new commands with the Figure 4 flow, cancel disposed running ones."""
        self.report()
        for service, sem in COMMANDS.items():
            for cmd, state in self.p.take(sem):
                if cmd is None or state != "ALIVE":  # kept for ended(): the consumer cancels or cleans up
                    self.ends[sem] += 1
                if cmd is None:
                    continue
                session = bytes(cmd["sessionID"])
                if session in self.handled or bytes(cmd["destination"]) != self.guid.bytes:
                    continue
                self.handled.add(session)
                ack = {"source": list(self.guid.bytes), "sessionID": cmd["sessionID"]}
                if service is Service.INERTIAL_SENSOR:
                    ack["state"] = cmd["state"]
                self.p.write(service.ack, ack)
                for s in ("ISSUED", "COMMANDED", "EXECUTING"):
                    self.status(service, cmd, s)
                if session in self.hold:
                    self.running = (service, cmd)
                else:
                    self.status(service, cmd, "COMPLETED")

    def ended(self, sem: Sem) -> bool:
        """Whether an instance of command topic `sem` ended since the last call: among the samples step() took (a
        cleanup can come while a test steps the vehicle to its command's end) and those waiting now."""
        self.ends[sem] += sum(1 for got, state in self.p.take(sem) if got is None or state != "ALIVE")
        seen, self.ends[sem] = self.ends[sem], 0
        return seen > 0

    def cancel_running_if_disposed(self) -> bool:
        service, cmd = self.running
        for got, state in self.p.take(COMMANDS[service]):
            if got is None or state != "ALIVE":
                self.status(service, cmd, "CANCELED", "CANCELED")
                return True
        return False


def test_console_commands_an_rti_vehicle(rti: RtiFactory, console: Any, domain: int) -> None:
    """An RTI vehicle on the recipe (Connext 7.7 and 6.1.2): the console shows its reports, its GPSFixReport through
    the appendable readers, and runs the command flow with it: set (to COMPLETED), cleanup, cancel by dispose. Nothing
    to tell its operator. (RTI's XCDR1 GPS writers and what the console says of them:
    test_console_tells_of_rti_writers_it_does_not_read.)"""
    c = console()
    topics = [
        Sem.INS_REPORT,
        Sem.GPS_FIX_STATUS_REPORT,
        Sem.GPS_FIX_COMMAND_STATUS,
        Sem.GPS_FIX_COMMAND_ACK,
        Sem.INS_COMMAND_STATUS,
        Sem.INS_COMMAND_ACK,
        Sem.GPS_FIX_REPORT,
        Sem.GPS_REPORT,
    ]
    v = RtiVehicle(rti(domain, writers=topics, readers=[Sem.GPS_FIX_COMMAND, Sem.INS_COMMAND]))
    me = str(v.guid)

    def shown() -> Any:
        v.step()
        r = http.get(f"{c.url}/api/providers/{me}")
        return (
            r.json()
            if r.status_code == 200
            and {"InertialSensorReport", "GPSFixStatusReport", "GPSFixReport"}
            <= set(k for k, x in r.json()["reports"].items() if x)
            else None
        )

    detail = wait_until(shown, 15, "the RTI vehicle in the console")
    assert detail["reports"]["InertialSensorReport"]["report"]["state"] == "ON"
    assert detail["reports"]["InertialSensorReport"]["report"]["status"] == "OPERATIONAL"
    assert (
        detail["reports"]["GPSFixStatusReport"]["report"]["originPosition"]["geodeticPosition"]["geodeticLatitude"]["latitude"]
        == 36.85
    )
    fix = detail["reports"]["GPSFixReport"]["report"]  # XCDR2, RTI's appendable type: the console's appendable readers
    assert (fix["SOG"], fix["trueCourse"], fix["magneticVariation"], fix["velocity"]["northSpeed"]) == (2.5, 1.2, -0.17, 2.0)
    assert fix["position2DWithTime"]["geodeticPosition"]["geodeticLongitude"]["longitude"] == -75.98
    metrics = http.get(f"{c.url}/api/metrics").json()
    assert (metrics["incompatibleWriters"], metrics["peerFindings"], metrics["undecodableSamples"]) == ({}, [], 0), metrics

    for path, body in (("gps-fix", {}), ("inertial-sensor", {"state": "RESTARTING"})):
        v.report()  # the vehicle reports only when the test steps it: a command to a vehicle silent 1 s is refused (lost)
        r = http.post(f"{c.url}/api/providers/{me}/{path}", json=body)
        assert r.status_code == 201, r.text
        session = r.json()["sessionId"]

        def done(session: str = session) -> Any:
            v.step()
            cmd = http.get(f"{c.url}/api/commands/{session}").json()
            return cmd if cmd["transitions"] and cmd["transitions"][-1]["status"] == "COMPLETED" else None

        cmd = wait_until(done, 15, f"{path} COMPLETED")
        assert [t["status"] for t in cmd["transitions"]] == ["ISSUED", "COMMANDED", "EXECUTING", "COMPLETED"]
        assert cmd["violations"] == [] and cmd["ackedAt"]
        # Cleanup: the console disposes the finished command; RTI's reader sees the instance end.
        wait_until(
            lambda path=path: v.ended(COMMANDS[Service.GPS_FIX if path == "gps-fix" else Service.INERTIAL_SENSOR]),
            30,
            "the cleanup dispose in RTI",
        )

    # Cancel by dispose: the vehicle holds the next command in EXECUTING until the console disposes it.
    v.report()
    r = http.post(f"{c.url}/api/providers/{me}/gps-fix", json={})
    assert r.status_code == 201, r.text
    session = r.json()["sessionId"]
    v.hold.add(uuid.UUID(session).bytes)
    wait_until(lambda: v.step() or getattr(v, "running", None), 10, "the held command")
    wait_until(
        lambda: (
            v.report()
            or [t["status"] for t in http.get(f"{c.url}/api/commands/{session}").json()["transitions"]][-1:] == ["EXECUTING"]
        ),
        10,
        "EXECUTING in the console",
    )
    assert http.delete(f"{c.url}/api/commands/{session}").status_code in (200, 202, 204)
    wait_until(lambda: v.report() or v.cancel_running_if_disposed(), 10, "the cancel dispose in RTI")
    cmd = wait_until(
        lambda: (
            v.report()
            or (lambda d: d if d["transitions"][-1]["status"] == "CANCELED" else None)(
                http.get(f"{c.url}/api/commands/{session}").json()
            )
        ),
        10,
        "CANCELED in the console",
    )
    assert [t["status"] for t in cmd["transitions"]] == ["ISSUED", "COMMANDED", "EXECUTING", "CANCELED"]
    assert cmd["violations"] == []
    assert http.get(f"{c.url}/api/metrics").json()["peerFindings"] == []


def test_console_sees_an_rti_vehicle_end_its_gps_fix_report(rti: RtiFactory, console: Any, domain: int) -> None:
    """An RTI vehicle on the recipe disposes its GPSFixReport instance (appendable, XCDR2: a key longer than 16 bytes):
    the console sees the instance end. The drop-in's serialize_key_with_dispose makes that work: on RTI's default the
    dispose carries only an MD5 key hash, and Cyclone drops it ("keyhash is MD5 and can't be converted to key value")."""
    c = console()
    v = RtiVehicle(rti(domain, writers=[Sem.INS_REPORT, Sem.GPS_FIX_REPORT]))
    me = str(v.guid)

    def topic() -> Any:
        r = http.get(f"{c.url}/api/providers/{me}")
        return r.json()["topics"].get("GPSFixReport") if r.status_code == 200 else None

    assert wait_until(lambda: v.report() or topic(), 15, "the RTI vehicle's GPSFixReport in the console")["alive"]
    v.p.write(Sem.GPS_FIX_REPORT, {"source": list(v.guid.bytes)}, action="dispose")
    wait_until(lambda: topic()["alive"] is False, 10, "the GPSFixReport instance ended in the console")
    assert http.get(f"{c.url}/api/metrics").json()["undecodableSamples"] == 0


def test_console_tells_an_rti7_on_defaults_to_stop_type_information(rti7: Callable[..., Any], console: Any, domain: int) -> None:
    """Connext 7 on its defaults sends type information Cyclone cannot add, and nothing
    of it matches (test_connext7_on_defaults_matches_no_sem_topic). The console names the participant and
    the one setting that fixes it, once for the participant (not per topic)."""
    c = console()
    p = rti7(domain, writers=[Sem.INS_REPORT, Sem.GPS_REPORT], readers=[Sem.INS_COMMAND], recipe=None, env={})
    findings = wait_until(lambda: http.get(f"{c.url}/api/metrics").json()["peerFindings"], 15, "a finding")
    assert [(f["name"], f["kind"], f["topic"]) for f in findings] == [("Rti", "typeInformation", None)]
    assert findings[0]["message"] == (
        "RTI participant Rti sends type information this console cannot use (none of its SEM topics match): set "
        "<resource_limits><type_object_max_serialized_length> to 0 in its participant QoS (the drop-in profile "
        "docs/rti/sem-console-interop.xml does) (docs/dds.md#rti-connext-7)"
    )
    assert p.matched(Sem.INS_REPORT, True) == []  # what the finding says: nothing of it matches
    assert c.stop().count(findings[0]["message"]) == 1


def test_console_tells_of_rti_writers_it_does_not_read(
    rti6: Callable[..., RtiParticipant], rti7: Callable[..., Any], console: Any, domain: int
) -> None:
    """In /api/metrics and the log: (a) RTI writers on XCDR1 for GPSFixReport and GPSReport, with
    Connext 7.7 (on the drop-in's Default) and 6.1.2; (c) a plain RTI 6.1.2 GPSReport writer (RTI's defaults); and an
    RTI writer of a SEM topic that no reader of the console matches with no incompatible QoS on either side to say why
    (a partition: Cyclone and RTI drop it in silence), and an RTI command reader there, which the console's commands
    do not reach. The console names each participant, the topic and the fix, once
    each in the log, and reads the InertialSensorReport of the two in the default partition; `incompatibleWriters` counts
    the RTI writers, not a Cyclone vehicle's final GPS writers beside them. (b), type information:
    test_console_tells_an_rti7_on_defaults_to_stop_type_information."""
    c = console()
    gps = [Sem.GPS_FIX_REPORT, Sem.GPS_REPORT]
    # a Cyclone vehicle's final GPS writers beside them: the console's appendable readers refuse those (type
    # consistency, read by its final readers), which must not count as writers nothing of the console reads
    cyclone = {s: Bus(domain).writer(s) for s in gps}  # noqa: F841
    plain = RtiVehicle(rti6(domain, writers=[Sem.INS_REPORT, *gps], name="Plain612"))
    elsewhere = RtiVehicle(
        rti6(domain, writers=[Sem.INS_REPORT], readers=[Sem.GPS_FIX_COMMAND], partition="fleetA", name="FleetA612")
    )
    default7 = RtiVehicle(rti7(domain, writers=[Sem.INS_REPORT, *gps], name="Default77"))
    fix, mask = (
        "set XCDR2 on that writer",
        (
            "set XCDR2 on that writer and NDDS_XTYPES_COMPLIANCE_MASK=0x1a9 in its "
            "environment (Connext 7; Connext 6 cannot write it readably)"
        ),
    )
    partition = "publish it in the default partition, as the console reads (it is in partition fleetA)"
    subscribe = "subscribe to it in the default partition, where the console publishes (it is in partition fleetA)"
    want = [
        ("Default77", "representation", "GPSFixReport", fix),
        ("Default77", "representation", "GPSReport", mask),
        ("FleetA612", "unmatchedReader", "GPSFixCommand", subscribe),
        ("FleetA612", "unmatched", "InertialSensorReport", partition),
        ("Plain612", "representation", "GPSFixReport", fix),
        ("Plain612", "representation", "GPSReport", mask),
    ]

    def found() -> Any:
        for v in (plain, elsewhere, default7):
            v.report()
        f = http.get(f"{c.url}/api/metrics").json()["peerFindings"]
        return f if len(f) >= len(want) else None

    findings = sorted(wait_until(found, 15, "the findings"), key=lambda f: (f["name"], f["topic"]))
    assert [(f["name"], f["kind"], f["topic"], f["fix"]) for f in findings] == want, findings
    assert {f["vendor"] for f in findings} == {"RTI"}
    assert [f["message"] for f in findings] == [
        f"RTI participant Default77 offers GPSFixReport in XCDR1: {fix} (docs/dds.md#rti-connext-7)",
        f"RTI participant Default77 offers GPSReport in XCDR1: {mask} (docs/dds.md#rti-connext-7)",
        f"RTI participant FleetA612 has a reader of GPSFixCommand that the console's commands do not reach: {subscribe} "
        "(docs/dds.md#rti-connext-7)",
        "RTI participant FleetA612 has a writer of InertialSensorReport that the console does not match: publish it in the "
        "default partition, as the console reads (it is in partition fleetA) (docs/dds.md#rti-connext-7)",
        f"RTI participant Plain612 offers GPSFixReport in XCDR1: {fix} (docs/dds.md#rti-connext-7)",
        f"RTI participant Plain612 offers GPSReport in XCDR1: {mask} (docs/dds.md#rti-connext-7)",
    ]
    for v in (plain, default7):  # their InertialSensorReport is read, their GPS topics are not
        detail = wait_until(
            lambda v=v: (
                v.report() or (lambda r: r.json() if r.status_code == 200 else None)(http.get(f"{c.url}/api/providers/{v.guid}"))
            ),
            10,
            "a vehicle in the default partition",
        )
        assert detail["reports"]["InertialSensorReport"]["report"]["state"] == "ON"
        assert not detail["reports"].get("GPSFixReport") and not detail["reports"].get("GPSReport")
    assert http.get(f"{c.url}/api/providers/{elsewhere.guid}").status_code == 404
    assert http.get(f"{c.url}/api/metrics").json()["incompatibleWriters"] == {s.spec.name: 2 for s in gps}
    log = c.stop()
    for f in findings:  # logged once per participant and finding
        assert log.count(f["message"]) == 1, (f["message"], log[-3000:])


def test_sem_check_names_the_fix_for_an_rti_vehicle(rti: RtiFactory, domain: int, tmp_path: Path) -> None:
    """In sem-check's discovery tests: an RTI vehicle on XCDR1 for GPSReport and GPSFixReport
    (RTI's default: Connext 6.1.2 on its plain defaults, Connext 7 on the drop-in's Default profile) fails
    discovery.GPSReport and discovery.GPSFixReport with the fix in RTI's terms; its other topics pass."""
    v = RtiVehicle(
        rti(
            domain,
            writers=[s for s in Sem if s.spec.cls is not TopicClass.COMMAND],
            readers=[Sem.GPS_FIX_COMMAND, Sem.INS_COMMAND],
            recipe=None if rti.version == "6" else "Default",
        )
    )
    v.report()  # transient-local: sem-check finds the vehicle by its reports
    run = check(tmp_path, "--domain", str(domain), "--only", "discovery.*", "--window", "1", "--timeout", "10")
    assert run.code == 1, run.out + run.err
    fails = failed(run)
    assert set(fails) == {"discovery.GPSReport", "discovery.GPSFixReport"}, fails
    # the first failure of each, which the run's table shows
    assert (
        ": RTI participant Rti offers GPSReport in XCDR1: set XCDR2 on that writer and NDDS_XTYPES_COMPLIANCE_MASK=0x1a9 "
        "in its environment"
    ) in fails["discovery.GPSReport"], fails
    assert ": RTI participant Rti offers GPSFixReport in XCDR1: set XCDR2 on that writer (docs" in fails["discovery.GPSFixReport"]
    assert run.cases["discovery.InertialSensorReport"][0] == "passed"


def test_sem_check_names_the_fix_for_an_rti7_on_defaults(rti7: Callable[..., Any], domain: int, tmp_path: Path) -> None:
    """Connext 7 on its defaults: nothing of it matches, so sem-check finds no provider, and says why in RTI's terms."""
    v = RtiVehicle(rti7(domain, writers=[Sem.INS_REPORT, Sem.GPS_FIX_STATUS_REPORT], recipe=None, env={}))
    v.report()
    run = check(tmp_path, "--domain", str(domain), "--only", "discovery.*", "--timeout", "4")
    assert run.code == 2, run.out + run.err
    assert run.err.splitlines()[-1].strip() == (
        "RTI participant Rti sends type information this console cannot use (none of its SEM topics match): set "
        "<resource_limits><type_object_max_serialized_length> to 0 in its participant QoS (the drop-in profile "
        "docs/rti/sem-console-interop.xml does) (docs/dds.md#rti-connext-7)"
    ), run.err


def test_sem_check_passes_an_rti7_vehicle_on_the_recipe(rti7: Callable[..., Any], domain: int, tmp_path: Path) -> None:
    """sem-check reads GPSReport and GPSFixReport as the console does (a reader per extensibility): an RTI 7 vehicle
    on AppendableGps with the mask passes every discovery test, and its GPSFixReports are read right (with a final
    reader that matched RTI by name they were misread, and no report of this vehicle's source would be seen)."""
    v = RtiVehicle(
        rti7(
            domain,
            writers=[s for s in Sem if s.spec.cls is not TopicClass.COMMAND],
            readers=[Sem.GPS_FIX_COMMAND, Sem.INS_COMMAND],
            recipe="AppendableGps",
            env=RECIPE_ENV,
        )
    )
    with v.reporting():
        run = check(
            tmp_path,
            "--domain",
            str(domain),
            "--provider",
            str(v.guid),
            "--only",
            "discovery,reports.GPSFixReport",
            "--window",
            "1.5",
            "--max-gap",
            "1",
        )
    assert run.code == 0 and failed(run) == {}, run.out + run.err
    assert {n: o for n, (o, _) in run.cases.items() if "GPS" in n and "Command" not in n} == {
        "discovery.GPSReport": "passed",
        "discovery.GPSFixReport": "passed",
        "discovery.GPSFixStatusReport": "passed",
        "reports.GPSFixReport.timing": "passed",
        "reports.GPSFixReport.values": "passed",
    }


def _command(service: Service, me: uuid.UUID, dest: uuid.UUID, state: int | None = None) -> dict[str, Any]:
    now = time.time()
    cmd: dict[str, Any] = {
        "source": list(me.bytes),
        "destination": list(dest.bytes),
        "sessionID": list(uuid.uuid4().bytes),
        "timeStamp": {"seconds": int(now), "nanoseconds": 0},
    }
    if state is not None:
        cmd["state"] = state
    return cmd


def _statuses(p: Any, service: Service, session: list[int], seen: list[tuple[str | None, str]]) -> list[tuple[str | None, str]]:
    for x, state in p.take(service.status):
        if x is None:
            seen.append((None, state))
        elif x["sessionID"] == session:
            seen.append((STATUS_NAME[x["commandStatus"]], state))
    return seen


@pytest.mark.parametrize(
    "service,state,recipe",
    [(Service.GPS_FIX, None, True), (Service.INERTIAL_SENSOR, 2, False)],
    ids=["GPSFix-recipe", "InertialSensor-defaults"],
)
def test_rti_consumer_commands_sem_sim(
    service: Service, state: int | None, recipe: bool, rti: RtiFactory, sim: Any, domain: int
) -> None:
    """An RTI consumer runs a command to COMPLETED and cleans up, with sem-sim as the vehicle, in both set-ups the docs
    give a consumer ("Which profile"): on the recipe (AppendableGps) against `sem-sim --gps-extensibility appendable`,
    and on the least each version needs (6.1.2 its defaults, 7.7 the drop-in's Default) against sem-sim's default.
    One service each: the two set-ups differ in GPS topics and readers' representations, not in the command flow."""
    if recipe:
        sim("--gps-extensibility", "appendable")
        p = rti(domain, writers=[COMMANDS[service]], readers=[service.status, service.ack])
    else:
        sim()
        p = rti(
            domain,
            writers=[COMMANDS[service]],
            readers=[service.status, service.ack],
            recipe=None if rti.version == "6" else "Default",
        )
    vehicle = vehicle_guid(1)
    sem = COMMANDS[service]
    me = uuid.uuid4()
    p.wait_matched(sem)
    p.wait_matched(service.status)
    cmd = _command(service, me, vehicle, state)
    p.write(sem, cmd)
    seen: list[tuple[str | None, str]] = []
    wait_until(lambda: ("COMPLETED", "ALIVE") in _statuses(p, service, cmd["sessionID"], seen), 20, "COMPLETED in RTI")
    assert [s for s, _ in seen] == ["ISSUED", "COMMANDED", "EXECUTING", "COMPLETED"]
    acks = [x for x, _ in p.take(service.ack) if x and x["sessionID"] == cmd["sessionID"]]
    assert acks and bytes(acks[0]["source"]) == vehicle.bytes
    # Cleanup: RTI disposes the finished command (its key travels with the dispose); the simulator
    # disposes the status and the ack.
    p.write(sem, {k: cmd[k] for k in ("source", "destination", "sessionID")}, action="dispose")
    wait_until(
        lambda: any(s is None or st != "ALIVE" for s, st in _statuses(p, service, cmd["sessionID"], [])),
        10,
        "the simulator's status dispose",
    )


def test_rti_consumer_cancels_by_dispose(rti: RtiFactory, sim: Any, domain: int) -> None:
    """An RTI consumer on the recipe cancels a running command of `sem-sim --gps-extensibility appendable` by disposing it."""
    sim("--fault", "slow", "--gps-extensibility", "appendable")
    vehicle = vehicle_guid(1)
    p = rti(domain, writers=[Sem.GPS_FIX_COMMAND], readers=[Sem.GPS_FIX_COMMAND_STATUS])
    p.wait_matched(Sem.GPS_FIX_COMMAND)
    p.wait_matched(Sem.GPS_FIX_COMMAND_STATUS)
    cmd = _command(Service.GPS_FIX, uuid.uuid4(), vehicle)
    p.write(Sem.GPS_FIX_COMMAND, cmd)
    seen: list[tuple[str | None, str]] = []
    wait_until(lambda: ("EXECUTING", "ALIVE") in _statuses(p, Service.GPS_FIX, cmd["sessionID"], seen), 20, "EXECUTING")
    p.write(Sem.GPS_FIX_COMMAND, {k: cmd[k] for k in ("source", "destination", "sessionID")}, action="dispose")
    wait_until(lambda: any(s == "CANCELED" for s, _ in _statuses(p, Service.GPS_FIX, cmd["sessionID"], seen)), 20, "CANCELED")
    assert [s for s, _ in seen if s] == ["ISSUED", "COMMANDED", "EXECUTING", "CANCELED"]


def test_gps_fix_report_with_rti_set_to_xcdr2_and_final(rti6: Callable[..., RtiParticipant], domain: int) -> None:
    """README's recipe for an RTI vehicle's position: GPSFixReport in XCDR2 with the type final."""
    s = Sem.GPS_FIX_REPORT
    reader, writer = Bus(domain).reader(s), Bus(domain).writer(s)
    p = rti6(domain, writers=[s], readers=[s], representation="XCDR2_DATA_REPRESENTATION", extensibility="final")
    rng = random.Random(8)
    theirs = [random_sample(s.spec.type, rng) for _ in range(10)]
    ours = [random_sample(s.spec.type, rng) for _ in range(10)]
    wait_until(
        lambda: len(p.outputs[s].matched_subscriptions) == 2 and len(p.inputs[s].matched_publications) == 2,
        10,
        "RTI matched with our reader and writer",
    )
    for x in theirs:
        p.write(s, to_plain(x))
    for x in ours:
        writer.write(x)
    got: list[Any] = []
    wait_until(
        lambda: got.extend(to_plain(g) for g in reader.take(N=100, condition=all_samples(reader))) or len(got) >= 20,
        10,
        "RTI's samples in Cyclone",
    )
    rti_got: list[Any] = []
    wait_until(lambda: rti_got.extend(x for x, _ in p.take(s) if x) or len(rti_got) >= 20, 10, "our samples in RTI")
    for x in theirs + ours:
        assert any(same(to_plain(x), g) for g in got), to_plain(x)
        assert any(same(to_plain(x), g) for g in rti_got), to_plain(x)


def _rti_matches(rti7: Callable[..., Any], domain: int, **kw: Any) -> dict[Sem, tuple[int, int]]:
    """For each SEM topic: whether Cyclone's reader matched RTI 7's writer, and Cyclone's writer RTI 7's reader."""
    readers = {s: Bus(domain).reader(s) for s in Sem}  # each in a participant of its own, so a reader
    writers = {s: Bus(domain).writer(s) for s in Sem}  # matches our writer (1) and RTI's or not
    rti7(domain, writers=list(Sem), readers=list(Sem), **kw)
    time.sleep(3)  # discovery on loopback takes well under a second
    return {s: (len(readers[s].get_matched_publications()) - 1, len(writers[s].get_matched_subscriptions()) - 1) for s in Sem}


def test_connext7_on_defaults_matches_no_sem_topic(rti7: Callable[..., Any], domain: int) -> None:
    """Connext 7.7 on its defaults announces XTypes 1.3 type information; Cyclone
    fetches the type object over TypeLookup, fails to add it, and matches no SEM topic either way.
    (The next test but one is the same set-up expected to match: it flips when that is fixed.)"""
    assert _rti_matches(rti7, domain, recipe=None, env={}) == {s: (0, 0) for s in Sem}


def test_connext7_without_type_information_matches_by_name(rti7: Callable[..., Any], domain: int) -> None:
    """With type_object_max_serialized_length 0 RTI sends no type information and topics match by
    name: every topic whose type has no @optional member (the other two need the recipe's XCDR2)."""
    got = _rti_matches(rti7, domain, recipe=None, env={}, type_object_max=0)
    assert {s: m for s, m in got.items() if s in PLAIN} == {s: (1, 1) for s in PLAIN}
    assert {s: m for s, m in got.items() if s not in PLAIN} == {s: (0, 0) for s in Sem if s not in PLAIN}


@pytest.mark.xfail(
    strict=True,
    raises=AssertionError,
    reason="Cyclone DDS 11.0.1 cannot add RTI Connext 7's type object (docs/dds.md, "
    "'RTI 7 type information'): flips when a fix lands",
)
def test_connext7_with_type_information_matches_the_console(rti7: Callable[..., Any], domain: int) -> None:
    """The upstream reproducer: an RTI 7.7 participant on its defaults and Cyclone 11 endpoints of the
    same UMAA types on one host. Expected: every topic whose type has no @optional member matches."""
    on_defaults = _rti_matches(rti7, domain, recipe=None, env={})
    assert {s: m for s, m in on_defaults.items() if s in PLAIN} == {s: (1, 1) for s in PLAIN}


# --- The recipe: GPSReport and GPSFixReport with the console's types appendable -----------------
# The console's types are final today (idlc's default). These tests run the Cyclone side of the two
# types in a child process whose UMAA package is generated appendable (sem_console.idlgen), to
# measure the recipe before the console changes: rti/appendable_peer.py.

_TESTS = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="session")
def appendable_umaa(tmp_path_factory: pytest.TempPathFactory) -> Path:
    from sem_console.idlgen import generate

    out = tmp_path_factory.mktemp("appendable-umaa")
    generate(out, extensibility="appendable")
    return out


def _peer(umaa: Path, *args: Any) -> dict[str, Any]:
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(umaa), str(_TESTS), str(_TESTS / "system"), str(_TESTS.parent)])}
    # cwd: not backend/, whose final UMAA package would come first on sys.path
    r = subprocess.run(
        [sys.executable, "-m", "support.rti.appendable_peer", *map(str, args)],
        cwd=umaa,
        env=env,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert r.returncode == 0, r.stderr[-2000:]
    return json.loads(r.stdout.strip().splitlines()[-1])


ALL_RIGHT = {"cyclone_matched_rti": 1, "rti_matched_cyclone": 1, "rti_to_cyclone_right": 20, "cyclone_to_rti_right": 20}


@pytest.mark.parametrize(
    "version,mask,gps_report_right",
    [("7", "mask", True), ("7", "nomask", False), ("6", "nomask", False)],
    ids=["connext7.7-recipe", "connext7.7-recipe-without-mask", "connext6.1.2-recipe"],
)
def test_recipe_with_appendable_gps_types(
    version: str, mask: str, gps_report_right: bool, appendable_umaa: Path, domain: int, request: pytest.FixtureRequest
) -> None:
    """RTI on the drop-in profile (XCDR2 writers for the two types, readers accepting
    XCDR and XCDR2, no type information) and Cyclone with GPSReport, GPSFixReport and their nested types
    appendable: 20 random samples each way, values compared. GPSReport needs
    NDDS_XTYPES_COMPLIANCE_MASK (Connext 7 only; 6.1.2 does not read it): without it RTI leaves out the
    DHEADER before sequence<GPSSatelliteType>, and neither side reads the other's GPSReport."""
    if version == "7":
        request.getfixturevalue("connext7")
    got = _peer(appendable_umaa, domain, version, mask)
    for m in got.values():
        m.pop("received"), m.pop("rti_received")
    none_right = {"cyclone_matched_rti": 1, "rti_matched_cyclone": 1, "rti_to_cyclone_right": 0, "cyclone_to_rti_right": 0}
    assert got["GPS_FIX_REPORT"] == ALL_RIGHT
    assert got["GPS_REPORT"] == (ALL_RIGHT if gps_report_right else none_right)


def test_appendable_gps_types_do_not_match_plain_cyclone_types(appendable_umaa: Path, domain: int) -> None:
    """Cyclone endpoints of the appendable GPSReport/GPSFixReport and of idlc's
    default (final, as a vehicle built from the plain UMAA IDL has, and as sem-sim has today) do not
    match either way: both send type information and XTypes does not assign final to appendable."""
    final = {s: (Bus(domain).reader(s), Bus(domain).writer(s)) for s in (Sem.GPS_REPORT, Sem.GPS_FIX_REPORT)}  # noqa: F841
    assert _peer(appendable_umaa, domain, "cyclone") == {"GPS_REPORT": [0, 0], "GPS_FIX_REPORT": [0, 0]}


GPS = [Sem.GPS_REPORT, Sem.GPS_FIX_REPORT]
REPORTS = list(REPORT_TOPICS)


def _shown(c: Any, sem: Sem, sent: list[Any]) -> dict[str, Any]:
    """What the console shows of each sample's source on this topic (None until it shows it)."""
    out = {}
    for x in sent:
        r = http.get(f"{c.url}/api/providers/{uuid.UUID(bytes=bytes(x.source))}")
        out[str(x.source)] = (r.json()["reports"].get(REPORT_TOPICS[sem]) or {}).get("report") if r.status_code == 200 else None
    return out


@pytest.mark.parametrize("version", ["7", "6"], ids=["connext7.7", "connext6.1.2"])
def test_console_reads_every_report_from_rti_on_the_recipe_and_from_cyclone(
    version: str, console: Any, domain: int, request: pytest.FixtureRequest
) -> None:
    """One reader per extensibility, merged. The console reads GPSReport and GPSFixReport from an
    RTI vehicle on the drop-in's AppendableGps profile (XCDR2, RTI's appendable types; Connext 7 with the mask in its
    environment) through its appendable readers, and from a Cyclone vehicle on plain idlc types (final, as sem-sim's)
    through its final readers, at once; 5 random samples per topic and vehicle, values compared, each decoded once.
    The other two report topics too (XCDR1, the same readers for both vehicles).
    Connext 6.1.2 reads no mask: Cyclone drops its GPSReport in C (never shown, never misread); GPSFixReport works."""
    made, make = _factory(version, request)
    c = console()
    try:
        p = make(domain, writers=REPORTS, recipe="AppendableGps", env=RECIPE_ENV)
        cyclone = {s: Bus(domain).writer(s) for s in REPORTS}
        rng = random.Random(31)
        theirs = {s: [random_sample(s.spec.type, rng) for _ in range(5)] for s in REPORTS}
        ours = {s: [random_sample(s.spec.type, rng) for _ in range(5)] for s in REPORTS}
        # three readers of the console each (for GPSReport and GPSFixReport: the appendable ones)
        wait_until(lambda: all(len(p.matched(s, True)) == 3 for s in REPORTS), 10, "RTI's writers matched by the console")
        for s in REPORTS:
            for x in theirs[s]:
                p.write(s, to_plain(x))
            for x in ours[s]:
                cyclone[s].write(x)
        readable = [
            (s, who, sent)
            for s in REPORTS
            for who, sent in (("RTI", theirs[s]), ("Cyclone", ours[s]))
            if not (version == "6" and who == "RTI" and s is Sem.GPS_REPORT)
        ]
        for s, who, sent in readable:
            want = {str(x.source): to_json(x)[0] for x in sent}
            got = wait_until(
                lambda s=s, sent=sent: (lambda g: g if all(g.values()) else None)(_shown(c, s, sent)),
                10,
                f"{who}'s {s.spec.name} in the console",
            )
            for k in want:
                assert same(want[k], got[k]), (who, s.spec.name, want[k], got[k])
        metrics = http.get(f"{c.url}/api/metrics").json()
        # each sample decoded once (from its writer's owner reader), one vehicle per source, nothing refused
        assert metrics["samplesDecoded"] == metrics["providers"] == 5 * len(readable), metrics
        assert (metrics["undecodableSamples"], metrics["incompatibleWriters"], metrics["peerFindings"]) == (0, {}, [])
        if version == "6":  # its GPSReport: matched, dropped by Cyclone before the console sees it
            assert not any(_shown(c, Sem.GPS_REPORT, theirs[Sem.GPS_REPORT]).values())
    finally:
        for x in made:
            x.close()


def test_rti_consumer_misreads_sem_sims_gps_topics(rti: Callable[..., Any], domain: int) -> None:
    """Measured, not wanted: an RTI consumer on the AppendableGps profile reads GPSReport and GPSFixReport with
    RTI's appendable types; sem-sim's writers (the console's final types, as here) send type information, which
    RTI does not hold against them: they match by name and nothing arrives right. Hence Default for an RTI consumer
    (docs/dds.md, "Which profile"). Flips if sem-sim or RTI changes."""
    writers = {s: Bus(domain).writer(s) for s in GPS}
    p = rti(domain, readers=GPS, recipe="AppendableGps", env=RECIPE_ENV)
    wait_until(lambda: all(len(p.matched(s, False)) == 1 for s in GPS), 10, "RTI's readers matched with the final writers")
    rng = random.Random(7)
    ours = {s: [random_sample(s.spec.type, rng) for _ in range(20)] for s in GPS}
    for s in GPS:
        for x in ours[s]:
            writers[s].write(x)
    got: dict[Sem, list[Any]] = {s: [] for s in GPS}
    wait_until(
        lambda: got[Sem.GPS_FIX_REPORT].extend(x for x, _ in p.take(Sem.GPS_FIX_REPORT) if x) or got[Sem.GPS_FIX_REPORT],
        10,
        "a GPSFixReport sample in RTI",
    )  # GPSReport: none arrived when measured
    for s in GPS:
        got[s] += [x for x, _ in p.take(s) if x]
    assert {s: sum(any(same(to_plain(x), g) for g in got[s]) for x in ours[s]) for s in GPS} == {s: 0 for s in GPS}


# RTI Connext 7.7.0's TypeLookup reply for the MINIMAL type object of InertialSensorReportType
# (captured on loopback with Cyclone's PacketCaptureFile; the bytes after the type identifier
# EK_MINIMAL 23681250e70ec42bb8fda372f23c): XCDR2 little endian, from the TypeObject's DHEADER.
RTI7_INS_REPORT_MINIMAL = bytes.fromhex(
    "92000000f1510200010000000000000082000000040000001a000000000000000100f1431172effd44d3f350b5c42cb009"
    "9ed39e2e0000001a000000010000000100f1d4eda04ef966c8d0e1eab88c284a9acb44540000001a000000020000003100"
    "f1c02c6d65a8318e236ed99e33c31b36cd38f40000001a000000030000000100f1f45382ce293f961a67b3cba95ad687a3cb5c00"
)


def test_why_cyclone_refuses_connext7_type_objects() -> None:
    """In bytes (no RTI needed): RTI's type identifier is the MD5 of RTI's own
    serialization of the type object, which writes each MinimalStructMember's DHEADER as 26 (0x1a)
    where the member is 25 bytes (member_id 4, member_flags 2, TypeIdentifier 15, name_hash 4), with
    one byte of what is alignment padding inside it, and the sequence and object DHEADERs to match.
    Cyclone deserializes the object, re-serializes it to compute its hash (ddsi_type_add_typeobj ->
    ddsi_typeobj_get_hash_id), gets DHEADER 25 and another MD5, so the identifier and the object
    disagree: "failed to add typeobj", and the endpoint never matches."""
    import hashlib

    from cyclonedds.idl._typesupport.DDS.XTypes import TypeObject

    rti_id = "23681250e70ec42bb8fda372f23c"
    assert hashlib.md5(RTI7_INS_REPORT_MINIMAL).hexdigest()[:28] == rti_id
    obj = TypeObject.deserialize(b"\x00\x07\x00\x00" + RTI7_INS_REPORT_MINIMAL)  # XCDR2, little endian
    members = obj.minimal.struct_type.member_seq
    assert [m.common.member_id for m in members] == [0, 1, 2, 3]
    again = obj.serialize(use_version_2=True)[4:]
    assert RTI7_INS_REPORT_MINIMAL[24:28] == b"\x1a\x00\x00\x00" and again[24:28] == b"\x19\x00\x00\x00"
    assert len(again) == len(RTI7_INS_REPORT_MINIMAL) - 1
    assert hashlib.md5(again).hexdigest()[:28] != rti_id  # what Cyclone compares with RTI's identifier


@pytest.mark.parametrize("force", [False, True], ids=["plain-reader", "force_type_validation"])
def test_final_reader_refuses_rti_only_with_force_type_validation(force: bool, rti7: Callable[..., Any], domain: int) -> None:
    """The building block of one reader per extensibility: the console's final
    GPSReport/GPSFixReport reader, as sem-sim and a plain-IDL Cyclone vehicle write them, must not
    also take an RTI vehicle's appendable samples (it would misread them: test_recipe_with_appendable_gps_types
    with final types). RTI on the recipe sends no type information and matches by name, unless the
    reader sets force_type_validation; Cyclone writers send theirs and still match."""
    from cyclonedds.core import Policy, Qos

    from sem_console.dds.qos import reader_qos

    topics = [Sem.GPS_REPORT, Sem.GPS_FIX_REPORT]
    extra = Qos(Policy.TypeConsistency.AllowTypeCoercion(force_type_validation=True)) if force else Qos()
    readers = {s: Bus(domain).reader(s, qos=reader_qos(s.spec.cls) + extra) for s in topics}
    cyclone = {s: Bus(domain).writer(s) for s in topics}  # noqa: F841 - the final writer, as sem-sim's
    # with force: a plain reader beside it, so that RTI's writers are seen matching something before the forced
    # reader is found unmatched (not a fixed wait that a slow discovery would also pass)
    plain = {s: Bus(domain).reader(s, qos=reader_qos(s.spec.cls)) for s in topics} if force else {}  # noqa: F841
    p = rti7(domain, writers=topics, recipe="AppendableGps", env=RECIPE_ENV)
    wait_until(lambda: all(len(p.matched(s, True)) >= 1 for s in topics), 10, "RTI's writers matched")
    time.sleep(1)
    assert {s: len(readers[s].get_matched_publications()) for s in topics} == {s: 1 if force else 2 for s in topics}
    assert {s: len(p.matched(s, True)) for s in topics} == {s: 1 for s in topics}  # the plain reader, never the forced


# --- An RTI consumer of sem-sim on AppendableGps: sem-sim --gps-extensibility appendable --------------------------


def _stamp(sample: dict[str, Any]) -> tuple[int, int]:
    """A sample's time stamp: which of a sem-sim writer's samples it is."""
    return int(sample["timeStamp"]["seconds"]), int(sample["timeStamp"]["nanoseconds"])


def _taken(readers: dict[Sem, Any], into: dict[Sem, list[Any]]) -> dict[Sem, list[Any]]:
    for s, r in readers.items():
        into[s] += r.take(N=1000, condition=all_samples(r))
    return into


@pytest.mark.parametrize("version,gps_report_right", [("7", True), ("6", False)], ids=["connext7.7", "connext6.1.2"])
def test_rti_consumer_reads_sem_sims_appendable_gps_topics(
    version: str, gps_report_right: bool, sim: Any, domain: int, request: pytest.FixtureRequest
) -> None:
    """RTI as consumer: on the drop-in's AppendableGps profile (Connext 7 with the mask in its environment)
    it reads `sem-sim --gps-extensibility appendable`'s GPSReport and GPSFixReport: at least 20 samples each equal to
    the sample of the same time stamp a Cyclone reader of the appendable copy took from the same writers, none
    different; and runs a GPS fix command to COMPLETED. Connext 6.1.2 reads no mask: its GPSFixReport is right, and no
    GPSReport arrives (matched, dropped by RTI; never misread), as Cyclone drops an RTI 6.1.2 vehicle's (docs/dds.md,
    the matrix)."""
    made, make = _factory(version, request)
    sim("--gps-extensibility", "appendable", "--gps-rate", "10")
    bus = Bus(domain)
    # keeping all: sem-sim writes faster than RTI's samples are collected
    cyclone = {s: bus.reader(s, reader_qos(TopicClass.REPORT) + Qos(Policy.History.KeepAll), appendable=True) for s in GPS}
    final = {s: bus.reader(s, final_type_qos(s)) for s in GPS}  # the console's final readers refuse them
    try:
        p = make(
            domain,
            readers=[*GPS, Sem.GPS_FIX_COMMAND_STATUS],
            writers=[Sem.GPS_FIX_COMMAND],
            recipe="AppendableGps",
            env=RECIPE_ENV,
        )
        wait_until(
            lambda: all(p.matched(s, False) for s in GPS) and all(r.get_matched_publications() for r in cyclone.values()),
            10,
            "sem-sim's appendable GPS writers matched by RTI and by Cyclone",
        )
        assert all(not r.get_matched_publications() for r in final.values())
        got: dict[Sem, list[Any]] = {s: [] for s in GPS}

        def rti_took(topics: list[Sem]) -> bool:
            for s in topics:
                got[s] += [x for x, _ in p.take(s) if x]
            return all(len(got[s]) >= 20 for s in topics)

        wait_until(lambda: rti_took(GPS if gps_report_right else [Sem.GPS_FIX_REPORT]), 20, "20 samples of each GPS topic in RTI")
        # Each sample RTI took against the one Cyclone took with the same time stamp (sem-sim's writers keep the last
        # sample only: on a loaded host either reader may miss one, so samples are paired, not looked up in a list).
        ours: dict[Sem, list[Any]] = {s: [] for s in GPS}
        need = {Sem.GPS_FIX_REPORT: 20, Sem.GPS_REPORT: 20 if gps_report_right else 0}

        def pairs() -> dict[Sem, list[tuple[Any, Any]]] | None:
            rti_took(GPS)
            _taken(cyclone, ours)
            stamps = {s: {_stamp(to_plain(y)): to_plain(y) for y in ours[s]} for s in GPS}
            out = {s: [(x, stamps[s][_stamp(x)]) for x in got[s] if _stamp(x) in stamps[s]] for s in GPS}
            return out if all(len(out[s]) >= need[s] for s in GPS) else None

        paired = wait_until(pairs, 20, "20 samples of each GPS topic that RTI and Cyclone both took")
        for s in GPS:
            for theirs, ours_ in paired[s]:
                assert same(ours_, theirs), (s.spec.name, ours_, theirs)
        if not gps_report_right:  # measured: 6.1.2 drops every one (20 sent meanwhile at 10 Hz), none misread
            assert got[Sem.GPS_REPORT] == []
        # the command flow, on the same profile
        cmd = _command(Service.GPS_FIX, uuid.uuid4(), vehicle_guid(1))
        p.wait_matched(Sem.GPS_FIX_COMMAND)
        p.write(Sem.GPS_FIX_COMMAND, cmd)
        seen: list[tuple[str | None, str]] = []
        wait_until(
            lambda: ("COMPLETED", "ALIVE") in _statuses(p, Service.GPS_FIX, cmd["sessionID"], seen), 20, "COMPLETED in RTI"
        )
        assert [s for s, _ in seen] == ["ISSUED", "COMMANDED", "EXECUTING", "COMPLETED"]
    finally:
        for x in made:
            x.close()


def test_console_reads_sem_sim_with_appendable_gps_writers(console: Any, sim: Any, domain: int) -> None:
    """`sem-sim --gps-extensibility appendable`: the console reads every report topic of it, GPSReport and GPSFixReport
    through its appendable readers (its final readers, force_type_validation, refuse the writers: no duplicate, no
    misread); what it shows of each topic is a sample a Cyclone reader took from the same writer."""
    c = console()
    sim("--gps-extensibility", "appendable")
    bus = Bus(domain)
    readers = {s: bus.reader(s, appendable=s in GPS) for s in REPORTS}
    taken: dict[Sem, list[Any]] = {s: [] for s in REPORTS}
    vehicle = str(vehicle_guid(1))

    def shown_right(s: Sem) -> bool:
        r = http.get(f"{c.url}/api/providers/{vehicle}")  # first: the samples taken after include the one shown
        shown = (r.json()["reports"].get(REPORT_TOPICS[s]) or {}).get("report") if r.status_code == 200 else None
        return shown is not None and any(same(to_json(x)[0], shown) for x in _taken(readers, taken)[s])

    for s in REPORTS:
        wait_until(lambda s=s: shown_right(s), 20, f"sem-sim's {s.spec.name} in the console")
    metrics = http.get(f"{c.url}/api/metrics").json()
    assert (metrics["providers"], metrics["undecodableSamples"], metrics["incompatibleWriters"]) == (1, 0, {}), metrics
