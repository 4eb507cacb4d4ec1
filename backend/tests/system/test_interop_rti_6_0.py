"""UMAA 6.0 with RTI Connext 7.7: a vehicle built on RTI's UMAA kit, with the console and with `sem-sim --umaa 6.0`.

The RTI side is written as a vehicle on the kit is: the project's 6.0 IDL as RTI's XML types (no extensibility given:
RTI's default, appendable; rti/idl2xml.py), each topic named after its type and the type registered under its full
name, the kit's QoS (UMAAQoSLib: rti/umaa-qos-lib.xml, our file of the kit's settings) and NDDS_XTYPES_COMPLIANCE_MASK
as the kit's start scripts set it. The fewest changes it needs for the console are the drop-in
docs/rti/umaa-6.0-interop.xml (SemConsoleUmaa60); each is measured here (docs/umaa-versions.md, "RTI Connext").
"""

from __future__ import annotations

import io
import random
import time
import uuid
from collections.abc import Callable, Iterator
from typing import Any

import pytest
from cyclonedds.core import InstanceState

from sem_console.codec import fastcdr
from sem_console.codec.convert import to_json
from sem_console.codec.decode import Decoder, ReportItem
from sem_console.dds.bus import Bus, all_samples
from sem_console.dds.cyclone_private import take_cdr
from sem_console.dds.topics import Sem60, Service
from sem_console.umaa.guid import satellite_label
from sem_console.versions import umaa_6_0
from support import http
from support.rti.connector import RECIPE_ENV
from support.rti.connext7 import RemoteParticipant
from support.samplegen import random_sample, to_plain
from test_console import wait_until
from test_interop_rti import same

KIT = ("UMAAQoSLib::DefaultUMAAParticipant", "UMAAQoSLib::AssignerQoS")  # the kit as it ships
DROP_IN = ("SemConsoleUmaa60::Participant", "SemConsoleUmaa60::Endpoints")  # the kit and the fewest changes
REPORTS = [Sem60.GPS_REPORT, Sem60.GLOBAL_POSE_REPORT, Sem60.INS_REPORT]
POSE = Sem60.GLOBAL_POSE_REPORT
MASK = RECIPE_ENV  # NDDS_XTYPES_COMPLIANCE_MASK=0x1a9, as the kit's start_component.sh exports it
ALIVE = int(InstanceState.Alive)
NIL = [0] * 16
ATTITUDE = {"pitch": {"pitch": 0.01}, "roll": {"roll": -0.02}, "yaw": {"yaw": 1.2}}
HEALTH = {"GPSReport", "GPSFixReport", "InertialSensorReport"}  # the model's topics a 6.0 vehicle's reports count under


@pytest.fixture
def rti60(connext7: None) -> Iterator[Callable[..., Any]]:
    """Makes Connext 7.7 participants with 6.0 topics (closed at the end): a vehicle on the kit's QoS unless told
    otherwise (``umaa``), with the kit's mask in its environment unless ``env`` says."""
    made: list[RemoteParticipant] = []

    def make(domain: int, env: dict[str, str] | None = None, **kw: Any) -> RemoteParticipant:
        kw.setdefault("umaa", KIT)
        made.append(RemoteParticipant(domain, env=MASK if env is None else env, **kw))
        return made[-1]

    yield make
    for p in made:
        p.close()


def _stamp() -> dict[str, int]:
    now = time.time()
    return {"seconds": int(now), "nanoseconds": int((now % 1) * 1e9)}


# a 6.0 vehicle's GPS clock and satellites, as RTI's Connector takes them (enums as ordinals)
CLOCK: dict[str, Any] = {
    "bias": -12,
    "biasUncertainty": 7,
    "drift": 3,
    "driftUncertainty": 1,
    "elapsedRealtime": 1_000_000,
    "elapsedRealtimeUncertainty": 5,
    "fullBias": -1_234_567_890_123,
    "hardwareClockDiscontinuityCount": 2,
    "leapSecond": 18,
    "referenceCarrierFrequency": 1575.42e6,
    "referenceCodeTypeFor": "C",
    "referenceConstellationType": 3,
    "time": 42,
    "timeFigureOfMerit": 2,
}  # GPS, TFOM_3
SATELLITES: list[dict[str, Any]] = [  # GPS 17 used in the fix, Galileo 5 not
    {
        "antennaCarrierNoiseDensity": 41.5,
        "azimuth": 1.25,
        "basebandCarrierNoiseDensity": 40.0,
        "carrierFrequency": 1575.42e6,
        "constellationType": 3,
        "containsAlmanacData": True,
        "elevation": 0.5,
        "ephemerisData": True,
        "satelliteID": 17,
        "usedInFix": True,
    },
    {
        "antennaCarrierNoiseDensity": 30.25,
        "azimuth": 4.5,
        "basebandCarrierNoiseDensity": 29.0,
        "carrierFrequency": 1561.098e6,
        "constellationType": 1,
        "containsAlmanacData": False,
        "elevation": 0.25,
        "ephemerisData": False,
        "satelliteID": 5,
        "usedInFix": False,
    },
]


class KitVehicle:
    """A 6.0 vehicle on RTI: its GPSReportType, GlobalPoseReportType and InertialSensorReportType, known values."""

    def __init__(self, p: Any) -> None:
        self.p, self.guid = p, uuid.uuid4()
        self.source = {"id": list(self.guid.bytes), "parentID": NIL}

    def report(self) -> None:
        stamp = _stamp()
        self.p.write(
            Sem60.GPS_REPORT,
            {"clock": CLOCK, "numberSatellitesInView": 2, "satellites": SATELLITES, "timeStamp": stamp, "source": self.source},
        )
        self.p.write(Sem60.INS_REPORT, {"status": 7, "timeStamp": stamp, "source": self.source})  # FINE_GPS_ALIGNMENT_COMPLETE
        self.p.write(
            POSE,
            {
                "altitude": 0.5,
                "attitude": ATTITUDE,
                "course": 1.2,
                "navigationSolution": 2,  # MEASURED
                "position": {"geodeticLatitude": 36.85, "geodeticLongitude": -75.98},
                "timeStamp": stamp,
                "source": self.source,
            },
        )

    def model(self, detail: dict[str, Any]) -> None:
        """`detail` (REST) has this vehicle's GlobalPose as the model's position report and its INS status."""
        reports = detail["reports"]
        pose, ins = reports["GPSFixReport"]["report"], reports["InertialSensorReport"]["report"]
        assert reports["GPSFixReport"]["invalid"] == reports["InertialSensorReport"]["invalid"] == []
        assert pose["source"] == ins["source"] == str(self.guid)
        assert pose["position2DWithTime"]["geodeticPosition"] == {
            "geodeticLatitude": {"latitude": 36.85},
            "geodeticLongitude": {"longitude": -75.98},
        }
        assert pose["position2DWithTime"]["timeAtPosition"] > 1.7e9
        assert (pose["trueCourse"], pose["altitudeMSL"], pose["attitude"]) == (1.2, {"altitude": 0.5}, ATTITUDE)
        assert (pose["navigationSolution"], pose["GPSLatLongValid"]) == ("MEASURED", True)
        assert pose["SOG"] is None and pose["depth"] is None and pose["positionCovariance"] is None
        assert (ins["status"], ins["state"]) == ("FINE_GPS_ALIGNMENT_COMPLETE", None)


def _detail(c: Any, v: KitVehicle, topics: set[str]) -> dict[str, Any]:
    def shown() -> dict[str, Any] | None:
        v.report()
        r = http.get(f"{c.url}/api/providers/{v.guid}")
        return r.json() if r.status_code == 200 and topics <= {t for t, h in r.json()["topics"].items() if h["alive"]} else None

    return wait_until(shown, 15, f"the RTI vehicle's {sorted(topics)} in the console")


def test_console_reads_an_rti_kit_vehicle_on_the_drop_in(rti60: Callable[..., Any], console: Any, domain: int) -> None:
    """(a) An RTI 6.0 vehicle on the kit with the drop-in's profiles: the console lists it as UMAA 6.0 with its
    GPSReportType member for member (the clock and both satellites, as the 6.0 adapter maps them), its GlobalPose
    (RTI's appendable type) as the model's position report with its attitude, and its INS status; nothing
    undecodable, nothing to tell its operator."""
    c = console()
    v = KitVehicle(rti60(domain, writers=REPORTS, umaa=DROP_IN, name="Kit60"))
    detail = _detail(c, v, HEALTH)
    assert set(detail["topics"]) == HEALTH
    v.model(detail)
    assert detail["umaaVersion"] == "6.0" and detail["link"] == "live"
    gps = detail["reports"]["GPSReport"]["report"]
    assert gps["source"] == str(v.guid) and gps["numberSatellitesInView"] == 2
    clock = {
        k: gps["clock"][{"biasUncertainty": "biasUncertianty"}.get(k, k)]
        for k in CLOCK
        if k not in ("timeFigureOfMerit", "referenceConstellationType")
    }
    assert clock == {k: x for k, x in CLOCK.items() if k not in ("timeFigureOfMerit", "referenceConstellationType")}
    assert gps["clock"]["referenceConstellationType"] == "GPS"
    got = [{k: s[k] for k in s if k != "satelliteId"} for s in gps["satellites"]]
    assert got == [
        {**{k: x for k, x in s.items() if k != "satelliteID"}, "constellationType": name}
        for s, name in zip(SATELLITES, ("GPS", "GALILEO"), strict=True)
    ]
    assert [satellite_label(uuid.UUID(s["satelliteId"]).bytes) for s in gps["satellites"]] == ["G17", "E05"]
    assert detail["reports"]["GPSReport"]["invalid"] == []
    metrics = http.get(f"{c.url}/api/metrics").json()
    assert (metrics["undecodableSamples"], metrics["incompatibleWriters"], metrics["peerFindings"]) == (0, {}, []), metrics


@pytest.mark.parametrize("env", [MASK, {}], ids=["mask", "no-mask"])
def test_rti_globalpose_decodes_in_the_console(env: dict[str, str], rti60: Callable[..., Any], domain: int) -> None:
    """GlobalPoseReportType from an RTI vehicle on the drop-in (XCDR2, RTI's appendable type), random samples with
    the optional members present and absent: the console's reader of the appendable copy matches it (the final reader
    refuses it), and the console's decoder reads each sample member for member, from its source, into the model's
    position report: the same as the sample sent, as cyclonedds' decoding of it, and as the same sample in the final
    type."""
    bus = Bus(domain)
    appendable, final = bus.reader(POSE, appendable=True), bus.reader(POSE, final_qos())
    p = rti60(domain, writers=[POSE], umaa=DROP_IN, env=env)
    wait_until(lambda: appendable.get_matched_publications(), 10, "RTI's GlobalPose writer matched")
    rng = random.Random(60)
    sent = [random_sample(POSE.spec.type, rng) for _ in range(20)]
    for x in sent:
        p.write(POSE, to_plain(x))
    got: list[tuple[bytes, Any]] = []
    wait_until(lambda: got.extend(_cdr(appendable)) or len(got) >= len(sent), 10, "RTI's GlobalPose samples")
    assert final.get_matched_publications() == []
    assert POSE.spec.appendable is not None
    fast, adapt = fastcdr.decoder(POSE.spec.appendable), umaa_6_0.REPORTS[POSE].model
    decoder = Decoder()
    for x, (data, _info) in zip(sent, got, strict=True):
        assert same(fast.json(data)[0], to_json(x)[0]), (to_json(x)[0], fast.json(data)[0])
        item = decoder.decode(POSE, data, True, ALIVE, 0.0)
        assert isinstance(item, ReportItem) and item.source == uuid.UUID(bytes=bytes(x.source.id))
        assert (item.topic, item.version) == ("GPSFixReport", "6.0")
        model = adapt(*to_json(x))
        assert same(item.report, model[0]) and item.invalid == model[1], (model, item.report)
        assert (item.report, item.invalid) == adapt(*to_json(POSE.spec.appendable.deserialize(data)))
        final = decoder.decode(POSE, POSE.spec.type.serialize(x, use_version_2=True), True, ALIVE, 0.0)
        assert isinstance(final, ReportItem) and (final.report, final.invalid) == model
    assert decoder.undecodable == {}


def final_qos() -> Any:
    from sem_console.dds.qos import reader_qos
    from sem_console.dds.topics import final_type_qos

    return reader_qos(POSE.spec.cls) + final_type_qos(POSE)


def _cdr(reader: Any) -> list[tuple[bytes, Any]]:
    got = take_cdr(reader, all_samples(reader).mask, 100)
    assert not isinstance(got, int), got
    return got


def _findings(c: Any, n: int) -> list[dict[str, Any]]:
    return wait_until(
        lambda: (lambda f: f if len(f) >= n else None)(http.get(f"{c.url}/api/metrics").json()["peerFindings"]),
        15,
        f"{n} findings",
    )


def test_console_tells_an_rti_kit_vehicle_as_shipped_to_stop_type_information(
    rti60: Callable[..., Any], console: Any, domain: int
) -> None:
    """The kit as it ships sends its types' type information (type_object_max_serialized_length 30000), which
    Cyclone cannot add: nothing of the vehicle matches, the console lists nothing and names the fix."""
    c = console()
    v = KitVehicle(rti60(domain, writers=REPORTS, readers=[Sem60.INS_COMMAND], name="Kit60"))
    v.report()
    findings = _findings(c, 1)
    assert [(f["name"], f["kind"], f["topic"]) for f in findings] == [("Kit60", "typeInformation", None)]
    assert findings[0]["message"] == (
        "RTI participant Kit60 sends type information this console cannot use (none of its SEM topics match): set "
        "<resource_limits><type_object_max_serialized_length> to 0 in its participant QoS (the drop-in profile "
        "docs/rti/umaa-6.0-interop.xml does) (docs/dds.md#rti-connext-7)"
    )
    assert http.get(f"{c.url}/api/providers/{v.guid}").status_code == 404


def test_console_tells_an_rti_kit_vehicle_to_write_globalpose_in_xcdr2(
    rti60: Callable[..., Any], console: Any, domain: int
) -> None:
    """The kit with its type information off, nothing else changed: RTI writes every type in XCDR1, the console reads
    GPSReportType and InertialSensorReportType (its INS status in the model), and tells the operator the fix for
    GlobalPoseReportType (optional members: XCDR2 only), which it counts as a writer it does not read: the model has
    no position report of it."""
    c = console()
    v = KitVehicle(rti60(domain, writers=REPORTS, name="Kit60", type_object_max=0))
    detail = _detail(c, v, {"GPSReport", "InertialSensorReport"})
    assert "GPSFixReport" not in detail["topics"] and detail["reports"].get("GPSFixReport") is None
    ins = detail["reports"]["InertialSensorReport"]["report"]
    assert (ins["status"], ins["state"], ins["source"]) == ("FINE_GPS_ALIGNMENT_COMPLETE", None, str(v.guid))
    findings = _findings(c, 1)
    assert [(f["name"], f["kind"], f["topic"], f["message"]) for f in findings] == [
        (
            "Kit60",
            "representation",
            "GlobalPoseReportType",
            "RTI participant Kit60 offers GlobalPoseReportType in XCDR1: set XCDR2 on that writer (docs/dds.md#rti-connext-7)",
        )
    ]
    assert http.get(f"{c.url}/api/metrics").json()["incompatibleWriters"] == {POSE.spec.name: 1}


@pytest.mark.parametrize("drop_in", [True, False], ids=["drop-in", "without-serialize_key_with_dispose"])
def test_console_sees_an_rti_kit_vehicle_end_its_globalpose(
    drop_in: bool, rti60: Callable[..., Any], console: Any, domain: int
) -> None:
    """An RTI vehicle disposes its GlobalPoseReportType instance (XCDR2, its key an IdentifierType of 32 bytes): with
    the drop-in's serialize_key_with_dispose the console sees the instance end; without it the dispose carries only
    an MD5 key hash, which Cyclone cannot turn back into the key, and the instance stays alive in the console."""
    c = console()
    kw: dict[str, Any] = {"umaa": DROP_IN} if drop_in else {"type_object_max": 0, "representation": "XCDR2_DATA_REPRESENTATION"}
    v = KitVehicle(rti60(domain, writers=[POSE], **kw))

    def topic() -> Any:
        r = http.get(f"{c.url}/api/providers/{v.guid}")
        return r.json()["topics"].get("GPSFixReport") if r.status_code == 200 else None  # GlobalPose: the model's

    stamp = _stamp()
    pose = {
        "attitude": {"pitch": {"pitch": 0.0}, "roll": {"roll": 0.0}, "yaw": {"yaw": 0.0}},
        "course": 0.0,
        "navigationSolution": 0,
        "position": {"geodeticLatitude": 1.0, "geodeticLongitude": 2.0},
        "timeStamp": stamp,
        "source": v.source,
    }
    assert wait_until(lambda: v.p.write(POSE, pose) or topic(), 15, "the RTI vehicle's GlobalPose in the console")["alive"]
    v.p.write(POSE, {"source": v.source}, action="dispose")
    if drop_in:
        wait_until(lambda: topic()["alive"] is False, 10, "the GlobalPose instance ended in the console")
    else:
        time.sleep(2)
        assert topic()["alive"] is True
    assert http.get(f"{c.url}/api/metrics").json()["undecodableSamples"] == 0


def test_the_console_writers_reach_an_rti_kit_reader(rti60: Callable[..., Any], domain: int) -> None:
    """A subscriber of the kit asks TOPIC presentation with ordered access (DefaultUMAAParticipant): the console's
    writers (dds/bus.py, the command writers among them) and sem-sim's 6.0 report, status and ack writers offer it, so
    an RTI reader on the kit, its type information off and nothing else changed, matches them. A reader on the kit's
    CommandQoS also asks a writer's liveliness lease of 10 s at most: the console's command writer and sem-sim's status
    and ack writers (CommandQoS's automatic 5 s) meet it, and a writer of the command class's QoS alone (an infinite
    lease) does not."""
    from cyclonedds.pub import DataWriter

    from sem_console.check import umaa_6_0 as check_6_0
    from sem_console.check.commands import CommandLimits, Consumer
    from sem_console.check.observe import Observer
    from sem_console.dds.qos import TopicClass, writer_qos
    from sem_console.sim.umaa_6_0 import Writer60

    bus = Bus(domain)
    command = bus.writer(Sem60.INS_COMMAND)
    sim = Writer60(bus, align_seconds=30).writers
    p = rti60(domain, readers=[Sem60.INS_COMMAND, Sem60.GPS_REPORT, Sem60.INS_REPORT], type_object_max=0)
    wait_until(
        lambda: command.get_matched_subscriptions() and all(p.matched(s, False) for s in (Sem60.GPS_REPORT, Sem60.INS_REPORT)),
        10,
        "the kit's readers matched",
    )
    assert len(sim[Sem60.GPS_REPORT].get_matched_subscriptions()) == 1
    command_qos = ("UMAAQoSLib::DefaultUMAAParticipant", "UMAAQoSLib::CommandQoS")
    flow = [Sem60.INS_COMMAND, CMD_STATUS, CMD_ACK]
    q = rti60(domain, readers=flow, type_object_max=0, umaa=command_qos)
    wait_until(
        lambda: all(len(q.matched(s, False)) == 1 for s in flow),
        10,
        "the console's command writer and sem-sim's status and ack writers matched by CommandQoS readers",
    )
    unleased = DataWriter(bus.publisher, bus.topic(Sem60.INS_COMMAND), writer_qos(TopicClass.COMMAND))
    time.sleep(1)
    assert len(q.matched(Sem60.INS_COMMAND, False)) == 1 and len(unleased.get_matched_subscriptions()) == 1  # p's only
    # sem-check --umaa 6.0 commanding an RTI vehicle: its command writer reaches the kit's readers as the console's does
    checker = Consumer(Observer(bus), uuid.uuid4(), CommandLimits(0.5, 1, 1), io.StringIO(), version=check_6_0.V6_0)
    checker.writer(Service.INERTIAL_SENSOR)  # made at once; None: no provider of that GUID here to match
    wait_until(lambda: len(q.matched(Sem60.INS_COMMAND, False)) == 2, 10, "sem-check's command writer matched")
    assert len(checker.writers[Service.INERTIAL_SENSOR].get_matched_subscriptions()) == 2


def _by_stamp(samples: list[dict[str, Any]]) -> dict[tuple[int, int], dict[str, Any]]:
    return {(int(x["timeStamp"]["seconds"]), int(x["timeStamp"]["nanoseconds"])): x for x in samples}


def test_rti_kit_consumer_reads_sem_sims_6_0_reports(rti60: Callable[..., Any], sim: Any, domain: int) -> None:
    """(b) An RTI consumer on the kit with the drop-in reads `sem-sim --umaa 6.0 --gps-extensibility appendable`:
    each of its GPSReportType, GlobalPoseReportType and InertialSensorReportType samples equal, member by member, to
    the sample of the same time stamp a Cyclone reader took from the same writers (at least 10 of each)."""
    from cyclonedds.core import Policy, Qos

    from sem_console.dds.qos import TopicClass, any_writer_reader_qos

    sim("--umaa", "6.0", "--gps-extensibility", "appendable", "--gps-rate", "10")
    bus = Bus(domain)
    keep = any_writer_reader_qos(TopicClass.REPORT) + Qos(Policy.History.KeepAll)
    cyclone = {s: bus.reader(s, keep, appendable=s is POSE) for s in REPORTS}
    p = rti60(domain, readers=REPORTS, umaa=DROP_IN)
    wait_until(lambda: all(p.matched(s, False) for s in REPORTS), 10, "sem-sim's 6.0 writers matched by RTI")
    theirs: dict[Sem60, list[dict[str, Any]]] = {s: [] for s in REPORTS}
    ours: dict[Sem60, list[dict[str, Any]]] = {s: [] for s in REPORTS}

    def pairs() -> dict[Sem60, list[tuple[Any, Any]]] | None:
        for s in REPORTS:
            theirs[s] += [x for x, _ in p.take(s) if x]
            ours[s] += [to_plain(x) for x in cyclone[s].take(N=1000, condition=all_samples(cyclone[s]))]
        out = {
            s: [(x, _by_stamp(ours[s])[k]) for k, x in _by_stamp(theirs[s]).items() if k in _by_stamp(ours[s])] for s in REPORTS
        }
        return out if all(len(v) >= 10 for v in out.values()) else None

    paired = wait_until(pairs, 30, "10 samples of each 6.0 report that RTI and Cyclone both took")
    for s in REPORTS:
        for rti, cyc in paired[s]:
            assert same(cyc, rti), (s.spec.name, cyc, rti)


# ---- commanding: InertialSensorControl (UMAA 6.0 SEM ICD 4.1), as an RTI application writes it ----------------------
# the 6.0 IDL's ordinals (CommandStatusEnumType, CommandStatusReasonEnumType), which RTI's Connector takes and gives
STATUS60 = {"CANCELED": 0, "COMMANDED": 1, "COMPLETED": 2, "EXECUTING": 3, "FAILED": 4, "ISSUED": 5}
STATUS60_NAME = {v: k for k, v in STATUS60.items()}
REASON60 = {"CANCELED": 0, "SUCCEEDED": 6, "UPDATED": 8}
REASON60_NAME = {v: k for k, v in REASON60.items()}
GPS_ALIGN = 1  # InertialSensorCmdEnumType: BEST_ALIGN, GPS_ALIGN, ...
CMD_STATUS, CMD_ACK = Sem60.INS_COMMAND_STATUS, Sem60.INS_COMMAND_ACK
HAPPY = ["ISSUED", "COMMANDED", "EXECUTING", "COMPLETED"]


def _ident(guid: uuid.UUID) -> dict[str, list[int]]:
    return {"id": list(guid.bytes), "parentID": NIL}


class KitProvider(KitVehicle):
    """The 6.0 vehicle on RTI as the InertialSensorControl provider of the ICD: a new command gets ISSUED, its ack
    (the whole command), COMMANDED, EXECUTING and COMPLETED, unless held EXECUTING to be canceled."""

    def __init__(self, p: Any) -> None:
        super().__init__(p)
        self.commands: dict[bytes, dict[str, Any]] = {}  # by sessionID, as received
        self.disposed: list[dict[str, Any]] = []  # the disposes of commands, as RTI has them (their key members)
        self.hold: set[bytes] = set()

    def status(self, cmd: dict[str, Any], status: str, reason: str = "SUCCEEDED") -> None:
        self.p.write(
            CMD_STATUS,
            {
                "source": self.source,
                "sessionID": cmd["sessionID"],
                "commandStatus": STATUS60[status],
                "commandStatusReason": REASON60[reason],
                "logMessage": f"rti {status.lower()}",
                "timeStamp": _stamp(),
            },
        )

    def step(self) -> None:
        self.report()
        for cmd, _state, valid in self.p.take_with_keys(Sem60.INS_COMMAND):
            session = bytes(cmd["sessionID"])
            if not valid:
                self.disposed.append(cmd)
                if session in self.hold:
                    self.hold.discard(session)
                    self.status(self.commands[session], "CANCELED", "CANCELED")
                continue
            if session in self.commands or cmd["destination"] != self.source:
                continue
            self.commands[session] = cmd
            self.status(cmd, "ISSUED")
            self.p.write(CMD_ACK, {"command": cmd, "source": self.source, "sessionID": cmd["sessionID"], "timeStamp": _stamp()})
            for s in ("COMMANDED", "EXECUTING"):
                self.status(cmd, s)
            if session not in self.hold:
                self.status(cmd, "COMPLETED")


def test_console_commands_an_rti_kit_vehicle(rti60: Callable[..., Any], console: Any, domain: int) -> None:
    """(a) The console commands an RTI 6.0 vehicle on the kit with the drop-in: GPS_ALIGN through REST reaches it as
    InertialSensorCommandType (state GPS_ALIGN, source and destination IdentifierTypes); its answer in 6.0 values
    (ISSUED, the ack with the whole command, COMMANDED, EXECUTING, COMPLETED) is the flow to COMPLETED in REST and on
    the WebSocket; the cleanup dispose reaches it. A second command held EXECUTING is canceled by the console's
    dispose, which RTI receives with the command's key members (Cyclone serializes the key with a dispose: nothing
    to set on RTI's reader), and its CANCELED shows."""
    from test_console import WsClient

    c = console()
    v = KitProvider(
        rti60(domain, writers=[*REPORTS, CMD_STATUS, CMD_ACK], readers=[Sem60.INS_COMMAND], umaa=DROP_IN, name="Kit60")
    )
    _detail(c, v, HEALTH)
    ws = WsClient(c.ws_url)

    def post() -> str:
        v.report()  # a command to a vehicle silent 1 s is refused
        r = http.post(f"{c.url}/api/providers/{v.guid}/inertial-sensor", json={"state": "GPS_ALIGN"})
        assert r.status_code == 201, r.text
        return str(r.json()["sessionId"])

    def shown(session: str, last: str) -> dict[str, Any] | None:
        v.step()
        cmd = http.get(f"{c.url}/api/commands/{session}").json()
        return cmd if [t["status"] for t in cmd["transitions"]][-1:] == [last] else None

    session = post()
    done = wait_until(lambda: shown(session, "COMPLETED"), 15, "COMPLETED in the console")
    assert [(t["status"], t["reason"]) for t in done["transitions"]] == [(s, "SUCCEEDED") for s in HAPPY]
    assert done["violations"] == [] and done["ackedAt"] and done["state"] == "GPS_ALIGN"
    sent = v.commands[uuid.UUID(session).bytes]
    assert (sent["state"], sent["destination"], sent["source"]["parentID"]) == (GPS_ALIGN, v.source, NIL)
    wait_until(lambda: ws.transitions(session) == HAPPY, 5, "every transition on the WebSocket")
    wait_until(
        lambda: v.step() or [d for d in v.disposed if d["sessionID"] == sent["sessionID"]],
        30,
        "the console's cleanup dispose in RTI",
    )

    session = post()
    v.hold.add(uuid.UUID(session).bytes)
    wait_until(lambda: shown(session, "EXECUTING"), 15, "EXECUTING in the console")
    assert http.delete(f"{c.url}/api/commands/{session}").status_code == 200
    done = wait_until(lambda: shown(session, "CANCELED"), 15, "CANCELED in the console")
    assert [(t["status"], t["reason"]) for t in done["transitions"]][-1] == ("CANCELED", "CANCELED")
    assert [t["status"] for t in done["transitions"]] == ["ISSUED", "COMMANDED", "EXECUTING", "CANCELED"]
    held = v.commands[uuid.UUID(session).bytes]
    assert [{k: d[k] for k in ("source", "sessionID", "destination")} for d in v.disposed][-1] == {
        k: held[k] for k in ("source", "sessionID", "destination")
    }
    assert done["violations"] == [] and ws.errors == []
    metrics = http.get(f"{c.url}/api/metrics").json()
    assert (metrics["undecodableSamples"], metrics["incompatibleWriters"], metrics["peerFindings"]) == (0, {}, []), metrics


def _statuses60(p: Any, session: list[int], seen: list[tuple[str | None, str | None, str]]) -> list[Any]:
    """The statuses of `session` RTI took, added to `seen` as (status, reason, valid data); a dispose as (None, None,
    False)."""
    for x, _state, valid in p.take_with_keys(CMD_STATUS):
        if x["sessionID"] == session:
            seen.append(
                (STATUS60_NAME[x["commandStatus"]], REASON60_NAME.get(x["commandStatusReason"]), True)
                if valid
                else (None, None, False)
            )
    return seen


def _command60(me: uuid.UUID, vehicle: uuid.UUID) -> dict[str, Any]:
    return {
        "state": GPS_ALIGN,
        "source": _ident(me),
        "destination": _ident(vehicle),
        "sessionID": list(uuid.uuid4().bytes),
        "timeStamp": _stamp(),
    }


def test_rti_kit_consumer_commands_sem_sim_6_0(rti60: Callable[..., Any], sim: Any, domain: int) -> None:
    """(b) An RTI consumer on the kit with the drop-in commands `sem-sim --umaa 6.0`: GPS_ALIGN runs to COMPLETED in
    6.0 values (statuses ISSUED, COMMANDED, EXECUTING, COMPLETED as the IDL's ordinals, reason SUCCEEDED), the ack
    carries the command RTI wrote, whole, from the vehicle's IdentifierType; RTI's cleanup dispose of the command has
    the simulator dispose its status."""
    from sem_console.sim.provider import vehicle_guid

    sim("--umaa", "6.0", "--align-seconds", "30")
    vehicle = vehicle_guid(1)
    p = rti60(domain, writers=[Sem60.INS_COMMAND], readers=[CMD_STATUS, CMD_ACK], umaa=DROP_IN)
    for s in (Sem60.INS_COMMAND, CMD_STATUS, CMD_ACK):
        p.wait_matched(s)
    cmd = _command60(uuid.uuid4(), vehicle)
    p.write(Sem60.INS_COMMAND, cmd)
    seen: list[Any] = []
    wait_until(lambda: ("COMPLETED", "SUCCEEDED", True) in _statuses60(p, cmd["sessionID"], seen), 20, "COMPLETED in RTI")
    assert seen == [(s, "SUCCEEDED", True) for s in HAPPY]
    acks = [x for x, _ in p.take(CMD_ACK) if x and x["sessionID"] == cmd["sessionID"]]
    assert [(a["source"], a["command"]) for a in acks] == [(_ident(vehicle), cmd)]
    p.write(Sem60.INS_COMMAND, {k: cmd[k] for k in ("source", "destination", "sessionID")}, action="dispose")
    wait_until(
        lambda: any(s is None for s, _r, _st in _statuses60(p, cmd["sessionID"], [])), 10, "the simulator's status dispose"
    )


@pytest.mark.parametrize("drop_in", [True, False], ids=["drop-in", "without-serialize_key_with_dispose"])
def test_rti_kit_consumer_cancels_sem_sim_6_0_by_dispose(drop_in: bool, rti60: Callable[..., Any], sim: Any, domain: int) -> None:
    """An RTI consumer on the kit cancels a running GPS_ALIGN of `sem-sim --umaa 6.0` by disposing it: with the
    drop-in's serialize_key_with_dispose the simulator answers CANCELED (reason CANCELED); without it the dispose
    carries only the MD5 key hash of the 80-byte key, which Cyclone drops, and the command runs on."""
    from sem_console.sim.provider import vehicle_guid

    sim("--umaa", "6.0", "--align-seconds", "600")  # 10 s a stage: still aligning when canceled
    vehicle = vehicle_guid(1)
    kw: dict[str, Any] = {"umaa": DROP_IN} if drop_in else {"type_object_max": 0}
    p = rti60(domain, writers=[Sem60.INS_COMMAND], readers=[CMD_STATUS], **kw)
    p.wait_matched(Sem60.INS_COMMAND)
    p.wait_matched(CMD_STATUS)
    cmd = _command60(uuid.uuid4(), vehicle)
    p.write(Sem60.INS_COMMAND, cmd)
    seen: list[Any] = []
    wait_until(lambda: ("EXECUTING", "SUCCEEDED", True) in _statuses60(p, cmd["sessionID"], seen), 20, "EXECUTING")
    p.write(Sem60.INS_COMMAND, {k: cmd[k] for k in ("source", "destination", "sessionID")}, action="dispose")
    if drop_in:
        wait_until(lambda: any(s == "CANCELED" for s, _r, _st in _statuses60(p, cmd["sessionID"], seen)), 10, "CANCELED")
        assert [(s, r) for s, r, _st in seen if s] == [*[(s, "SUCCEEDED") for s in HAPPY[:3]], ("CANCELED", "CANCELED")]
    else:
        time.sleep(3)
        assert [s for s, _r, _st in _statuses60(p, cmd["sessionID"], seen)] == HAPPY[:3]
