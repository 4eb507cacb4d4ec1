"""A UMAA 6.0 Service Provider for the sem-check tests, written from the SEM ICD 6.0 (section 4.1, 5.1) and the SA ICD
6.0 (GlobalPoseStatus), not from `sem-sim`: it serves GPSStatus, GlobalPoseStatus, InertialSensorStatus and
InertialSensorControl on a participant of its own, on the topics named after their types, with the QoS of RTI's
UMAAQoSLib (reports TelemetryQoS: best-effort, volatile; statuses, acks and the command reader CommandQoS: reliable,
volatile, keep-all, a liveliness lease of 5 s for a writer and 10 s for a reader), and can break the ICD in one of
`BREACHES` at a time.

Per InertialSensorCommandType addressed to it (ICD 6.0 4.1: `destination`, its `id`): ISSUED/SUCCEEDED (4.1.4 step
3); a step later the ack, which carries the command (5.1.2.1, Table 11), and COMMANDED, then EXECUTING a step after
(4.1.4.1); COMPLETED `execute` seconds later (4.1.4.3). From EXECUTING the InertialSensorReportType shows INIT, or the
coarse stage of the commanded kind of alignment, and at COMPLETED its completed stage (5.3.3, 5.3.4). The same command
again with a newer timeStamp while it runs is an update: ISSUED/UPDATED, and the flow again from the start with the
ack of the updated command (4.1.4.2); an update of a finished command is ignored (4.1.4.2's first paragraph), or with
`terminal_update="fail"` answered FAILED/VALIDATION_FAILED (its step 2). With `busy` it finishes the work in hand
before it reads an update: an update that reaches a command at EXECUTING finds it COMPLETED (the update crossed the
end), and once one has, a later command waits at EXECUTING for its update, which the checker sends at its first status:
each whenever the update arrives, not within a time. The consumer's dispose before the
end cancels it: CANCELED/CANCELED, then its status and ack disposed (4.1.4.5); after the end it cleans up: status and
ack disposed (4.1.5).

The breaches:
- `ignore-cancel`: a dispose before the end is ignored; the command runs to COMPLETED and its status and ack are
  never disposed (4.1.4.5);
- `silent-same-state`: a command for the alignment the sensor has completed (GPS_ALIGN after a GPS alignment) gets
  no status at all (4.1: the provider responds to every command addressed to it);
- `answer-any-destination`: commands addressed to any identifier are run as its own (4.1: `destination`);
- `fail-after-cleanup`: a moment after disposing a finished command's status and ack it publishes FAILED/TIMEOUT for
  it (Figure 14: nothing follows COMPLETED);
- `ignore-update`: an update is taken for the command already running: no ISSUED/UPDATED (4.1.4.2);
- `wrong-failure-reason`: BEST_ALIGN rejected at once with FAILED/RESOURCE_REJECTED, a reason Figure 15 allows after
  COMMANDED only;
- `attitude-in-degrees`: GlobalPoseReportType's attitude in degrees (SA ICD 6.0 Table 67: PitchHalfAngle, radians);
- `reliable-reports`: its report writers reliable and transient-local, which UMAAQoSLib's TelemetryQoS is not (no
  rule: a warning, not a failure);
- `exclusive-gps`: its GPSReportType writer of EXCLUSIVE ownership, which no reader of SHARED ownership matches;
- `best-effort-statuses`: its status and ack writers best-effort, which UMAAQoSLib's CommandQoS is not (no rule: a
  warning, not a failure).
"""

from __future__ import annotations

import math
import threading
import time
import uuid
from dataclasses import dataclass, field
from typing import Any

from cyclonedds.core import InstanceState, Policy, Qos
from cyclonedds.pub import DataWriter
from cyclonedds.sub import DataReader
from cyclonedds.util import duration

from UMAA_6_0.Common import IdentifierType
from UMAA_6_0.Common.MaritimeEnumeration.CommandStatusEnumModule import CommandStatusEnumType as Status
from UMAA_6_0.Common.MaritimeEnumeration.CommandStatusReasonEnumModule import CommandStatusReasonEnumType as Reason
from UMAA_6_0.Common.MaritimeEnumeration.GPSConstellationEnumModule import GPSConstellationEnumType as Constellation
from UMAA_6_0.Common.MaritimeEnumeration.InertialSensorCmdEnumModule import InertialSensorCmdEnumType as Cmd
from UMAA_6_0.Common.MaritimeEnumeration.InertialSensorOpStatusEnumModule import InertialSensorOpStatusEnumType as Op
from UMAA_6_0.Common.MaritimeEnumeration.NavigationSolutionEnumModule import NavigationSolutionEnumType as Nav
from UMAA_6_0.Common.MaritimeEnumeration.TFOMEnumModule import TFOMEnumType as Tfom
from UMAA_6_0.Common.Measurement import DateTime, GeoPosition2D
from UMAA_6_0.Common.Orientation import Orientation3DNEDType, PitchYNEDType, RollXNEDType, YawZNEDType
from UMAA_6_0.SEM.GPSStatus import GPSClockType, GPSSatelliteType

from sem_console.dds.bus import Bus
from sem_console.dds.qos import representation
from sem_console.dds.topics import Sem60
from sem_console.umaa.samples import make

BREACHES = (
    "ignore-cancel",
    "silent-same-state",
    "answer-any-destination",
    "fail-after-cleanup",
    "ignore-update",
    "wrong-failure-reason",
    "attitude-in-degrees",
    "reliable-reports",
    "exclusive-gps",
    "best-effort-statuses",
)
REPORT_PERIOD = 0.1  # s between reports
LATE = 0.2  # s after the cleanup that `fail-after-cleanup` publishes FAILED
NIL = bytes(16)

TELEMETRY = Qos(Policy.Reliability.BestEffort, Policy.Durability.Volatile, Policy.History.KeepLast(1))
RELIABLE_REPORTS = Qos(
    Policy.Reliability.Reliable(duration(seconds=1)), Policy.Durability.TransientLocal, Policy.History.KeepLast(1)
)
COMMAND_WRITER = Qos(
    Policy.Reliability.Reliable(duration(seconds=5)),
    Policy.Durability.Volatile,
    Policy.History.KeepAll,
    Policy.Liveliness.Automatic(duration(seconds=5)),
    Policy.WriterDataLifecycle(autodispose=False),
)
BEST_EFFORT_COMMAND_WRITER = Qos(
    Policy.Reliability.BestEffort,
    Policy.Durability.Volatile,
    Policy.History.KeepAll,
    Policy.Liveliness.Automatic(duration(seconds=5)),
    Policy.WriterDataLifecycle(autodispose=False),
)
COMMAND_READER = Qos(
    Policy.Reliability.Reliable(duration(seconds=5)),
    Policy.Durability.Volatile,
    Policy.History.KeepAll,
    Policy.Liveliness.Automatic(duration(seconds=10)),
)
# What a command's EXECUTING and COMPLETED show in the InertialSensorReportType (ICD 6.0 5.3.4, Table 28)
STAGES = {
    Cmd.INIT: (Op.INIT, Op.INIT),
    Cmd.GPS_ALIGN: (Op.COARSE_GPS_ALIGNMENT, Op.FINE_GPS_ALIGNMENT_COMPLETE),
    Cmd.BEST_ALIGN: (Op.COARSE_BEST_ALIGNMENT, Op.FINE_BEST_ALIGNMENT_COMPLETE),
    Cmd.STATIONARY_ALIGN: (Op.COARSE_STATIONARY_ALIGNMENT, Op.FINE_STATIONARY_ALIGNMENT_COMPLETE),
    Cmd.TRANSFER_ALIGN: (Op.COARSE_TRANSFER_ALIGNMENT, Op.FINE_TRANSFER_ALIGNMENT_COMPLETE),
    Cmd.SNAP_ALIGN: (Op.SNAP_ALIGNMENT_COMPLETE, Op.SNAP_ALIGNMENT_COMPLETE),
}


def stamp() -> DateTime:
    t = time.time()
    return DateTime(seconds=int(t), nanoseconds=min(int((t - int(t)) * 1e9), 999_999_999))


@dataclass
class Command:
    sample: Any
    due: list[tuple[float, Status]]  # the statuses still to publish, and when
    status: Status = Status.ISSUED
    disposed_early: bool = False  # the consumer disposed it before COMPLETED, and it was not canceled
    acked: bool = False
    late: list[float] = field(default_factory=list)
    updated: bool = False


class IcdProvider60:
    def __init__(
        self,
        domain: int,
        breach: str | None = None,
        execute: float = 0.4,
        step: float = 0.05,
        terminal_update: str = "ignore",
        busy: bool = False,
    ) -> None:
        assert breach is None or breach in BREACHES, breach
        self.breach, self.execute, self.step = breach, execute, step
        self.terminal_update, self.busy = terminal_update, busy
        self.crossed = False  # an update reached a finished command (`busy`: later commands wait for theirs)
        self.bus = Bus(domain)
        self.guid = uuid.uuid4()
        self.source = make(IdentifierType, id=self.guid.bytes, parentID=NIL)
        reports = RELIABLE_REPORTS if breach == "reliable-reports" else TELEMETRY
        p = self.bus.participant

        def writer(sem: Sem60, qos: Qos) -> DataWriter[Any]:
            return DataWriter(p, self.bus.topic(sem), qos + representation(sem.spec.xcdr2_only, writer=True))

        self.gps = writer(Sem60.GPS_REPORT, reports + Qos(Policy.Ownership.Exclusive) if breach == "exclusive-gps" else reports)
        self.pose, self.report = writer(Sem60.GLOBAL_POSE_REPORT, reports), writer(Sem60.INS_REPORT, reports)
        statuses = BEST_EFFORT_COMMAND_WRITER if breach == "best-effort-statuses" else COMMAND_WRITER
        self.status, self.ack = writer(Sem60.INS_COMMAND_STATUS, statuses), writer(Sem60.INS_COMMAND_ACK, statuses)
        self.reader: DataReader[Any] = DataReader(
            p, self.bus.topic(Sem60.INS_COMMAND), COMMAND_READER + representation(False, writer=False)
        )
        self.op = Op.FINE_GPS_ALIGNMENT_COMPLETE
        self.sessions: dict[int, uuid.UUID] = {}  # command instance handle -> its session
        self.running: dict[uuid.UUID, Command] = {}
        self.cleaned: dict[uuid.UUID, Command] = {}
        self.reported_at = 0.0
        self.stop = threading.Event()
        self.thread = threading.Thread(target=self.loop, daemon=True)
        self.thread.start()

    def close(self) -> None:
        self.stop.set()
        self.thread.join()
        self.bus.close()

    def loop(self) -> None:
        while not self.stop.is_set():
            now = time.monotonic()
            for s in self.reader.take(N=16):
                self.on_sample(s, now)
            for session, cmd in list(self.running.items()):
                while cmd.due and cmd.due[0][0] <= now and not self.waits_for_update(cmd, cmd.due[0][1]):
                    self.publish(cmd, cmd.due.pop(0)[1])
                if cmd.status is Status.COMPLETED and cmd.disposed_early:
                    del self.running[session]  # ignore-cancel: its status and ack stay on the bus
            for session, cmd in list(self.cleaned.items()):
                if cmd.late[0] <= now:
                    self.status.write(self.status_sample(cmd, Status.FAILED, Reason.TIMEOUT))
                    del self.cleaned[session]
            if now - self.reported_at >= REPORT_PERIOD:
                self.publish_reports(now)
            time.sleep(0.01)

    def on_sample(self, s: Any, now: float) -> None:
        info = s.sample_info
        session = self.sessions.get(info.instance_handle)
        if info.valid_data and session is None:
            self.start(s, info.instance_handle, now)
        elif info.valid_data and session is not None and session in self.running:
            self.update(self.running[session], s, now)
        cmd = self.running.get(session) if session is not None else None
        if info.instance_state == InstanceState.NotAliveDisposed and session is not None and cmd is not None:
            self.end(session, cmd, now)

    def schedule(self, now: float) -> list[tuple[float, Status]]:
        return [
            (now + self.step, Status.COMMANDED),
            (now + 2 * self.step, Status.EXECUTING),
            (now + 2 * self.step + self.execute, Status.COMPLETED),
        ]

    def start(self, s: Any, handle: int, now: float) -> None:
        if bytes(s.destination.id) != self.guid.bytes and self.breach != "answer-any-destination":
            return
        done = STAGES[s.state][1]
        if self.breach == "silent-same-state" and s.state is not Cmd.INIT and self.op is done:
            return
        session = uuid.UUID(bytes=bytes(s.sessionID))
        self.sessions[handle] = session
        cmd = Command(s, self.schedule(now))
        self.running[session] = cmd
        self.status.write(self.status_sample(cmd, Status.ISSUED, Reason.SUCCEEDED))
        if self.breach == "wrong-failure-reason" and s.state is Cmd.BEST_ALIGN:
            cmd.due.clear()
            cmd.status = Status.FAILED
            self.status.write(self.status_sample(cmd, Status.FAILED, Reason.RESOURCE_REJECTED))

    def waits_for_update(self, cmd: Command, status: Status) -> bool:
        return self.busy and self.crossed and not cmd.updated and status is Status.COMPLETED

    def update(self, cmd: Command, s: Any, now: float) -> None:
        """The same source and sessionID with a newer timeStamp: an update (ICD 6.0 4.1.4.2)."""
        newer = (s.timeStamp.seconds, s.timeStamp.nanoseconds) > (cmd.sample.timeStamp.seconds, cmd.sample.timeStamp.nanoseconds)
        if newer and self.busy and not self.crossed and cmd.status is Status.EXECUTING:
            cmd.due.clear()
            self.publish(cmd, Status.COMPLETED)  # the work in hand first: the update crosses the end
        terminal = cmd.status in (Status.COMPLETED, Status.FAILED, Status.CANCELED)
        self.crossed = self.crossed or (newer and terminal)
        if newer and terminal and self.terminal_update == "fail" and cmd.status is not Status.FAILED:
            cmd.status = Status.FAILED
            self.status.write(self.status_sample(cmd, Status.FAILED, Reason.VALIDATION_FAILED))
        if not newer or terminal or self.breach == "ignore-update":
            return
        cmd.sample, cmd.due, cmd.acked, cmd.updated = s, self.schedule(now), False, True
        cmd.status = Status.ISSUED
        self.status.write(self.status_sample(cmd, Status.ISSUED, Reason.UPDATED))

    def end(self, session: uuid.UUID, cmd: Command, now: float) -> None:
        """The consumer disposed the command: cancel it (ICD 6.0 4.1.4.5), or clean it up (4.1.5)."""
        if cmd.status not in (Status.COMPLETED, Status.FAILED):
            if self.breach == "ignore-cancel":
                cmd.disposed_early = True
                return
            cmd.due.clear()
            self.publish(cmd, Status.CANCELED)
        self.status.dispose(self.status_sample(cmd, cmd.status, Reason.SUCCEEDED))
        if cmd.acked:
            self.ack.dispose(self.ack_sample(cmd))
        del self.running[session]
        if self.breach == "fail-after-cleanup" and cmd.status is Status.COMPLETED:
            cmd.late.append(now + LATE)
            self.cleaned[session] = cmd

    def publish(self, cmd: Command, status: Status) -> None:
        if status is Status.COMMANDED:
            self.ack.write(self.ack_sample(cmd))
            cmd.acked = True
        cmd.status = status
        if status is Status.EXECUTING:
            self.set_op(STAGES[cmd.sample.state][0])
        if status is Status.COMPLETED:
            self.set_op(STAGES[cmd.sample.state][1])
        reason = Reason.CANCELED if status is Status.CANCELED else Reason.SUCCEEDED
        self.status.write(self.status_sample(cmd, status, reason))

    def set_op(self, op: Op) -> None:
        self.op = op
        self.publish_reports(time.monotonic())

    def publish_reports(self, now: float) -> None:
        self.reported_at = now
        t = stamp()
        self.report.write(Sem60.INS_REPORT.spec.type(status=self.op, timeStamp=t, source=self.source))
        n = 8
        degrees = 180 / math.pi if self.breach == "attitude-in-degrees" else 1.0
        sats = [
            GPSSatelliteType(
                antennaCarrierNoiseDensity=40.0,
                azimuth=-3.0 + 6 * i / n,
                basebandCarrierNoiseDensity=38.0,
                carrierFrequency=1575.42e6,
                constellationType=Constellation.GPS,
                containsAlmanacData=True,
                elevation=0.5,
                ephemerisData=True,
                satelliteID=float(i + 1),
                usedInFix=i < 6,
            )
            for i in range(n)
        ]
        clock = GPSClockType(
            bias=0,
            biasUncertainty=10,
            drift=0,
            driftUncertainty=1,
            elapsedRealtime=1_000_000,
            elapsedRealtimeUncertainty=10,
            fullBias=0,
            hardwareClockDiscontinuityCount=0,
            leapSecond=18,
            referenceCarrierFrequency=1575.42e6,
            referenceCodeTypeFor="C/A",
            referenceConstellationType=Constellation.GPS,
            time=1,
            timeFigureOfMerit=Tfom.TFOM_3,
        )
        self.gps.write(
            Sem60.GPS_REPORT.spec.type(clock=clock, numberSatellitesInView=n, satellites=sats, timeStamp=t, source=self.source)
        )
        self.pose.write(
            Sem60.GLOBAL_POSE_REPORT.spec.type(
                altitude=None,
                altitudeAGL=None,
                altitudeASF=12.5,
                altitudeGeodetic=None,
                attitude=Orientation3DNEDType(
                    pitch=PitchYNEDType(pitch=0.1 * degrees),
                    roll=RollXNEDType(roll=-0.02 * degrees),
                    yaw=YawZNEDType(yaw=math.pi / 4 * degrees),
                ),
                attitudeCovariance=None,
                course=math.pi / 4,
                depth=3.0,
                navigationSolution=Nav.MEASURED,
                position=GeoPosition2D(geodeticLatitude=43.1, geodeticLongitude=5.9),
                positionCovariance=None,
                timeStamp=t,
                source=self.source,
            )
        )

    def status_sample(self, cmd: Command, status: Status, reason: Reason) -> Any:
        return Sem60.INS_COMMAND_STATUS.spec.type(
            timeStamp=stamp(),
            source=self.source,
            sessionID=cmd.sample.sessionID,
            commandStatus=status,
            commandStatusReason=reason,
            logMessage="",
        )

    def ack_sample(self, cmd: Command) -> Any:
        return Sem60.INS_COMMAND_ACK.spec.type(
            command=cmd.sample, timeStamp=stamp(), source=self.source, sessionID=cmd.sample.sessionID
        )
