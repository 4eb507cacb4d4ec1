"""`sem-sim` against a test consumer over real Cyclone DDS on loopback, one fresh domain per test.

Every status sequence is checked against Figure 4 by CommandFlow as it arrives.
"""

from __future__ import annotations

import math
import signal
import socket
import subprocess
import sys
import time
import uuid
from collections.abc import Callable

import pytest

from UMAA.Common.MaritimeEnumeration.CommandStatusEnumType import CommandStatusEnumType as S
from UMAA.Common.MaritimeEnumeration.CommandStatusReasonEnumType import CommandStatusReasonEnumType as R
from UMAA.Common.MaritimeEnumeration.GPSFixEnumType import GPSFixEnumType as Fix
from UMAA.Common.MaritimeEnumeration.GPSNavigationSolutionEnumType import GPSNavigationSolutionEnumType as Nav
from UMAA.Common.MaritimeEnumeration.InertialSensorOpStatusEnumType import InertialSensorOpStatusEnumType as Op
from UMAA.Common.MaritimeEnumeration.InertialSensorStateEnumType import InertialSensorStateEnumType as Ins
from UMAA.Common.Measurement import DateTime

from sem_console.dds.bus import Bus
from sem_console.dds.topics import Sem, Service
from sem_console.sim.provider import vehicle_guid
from sem_console.umaa.guid import from_guid, satellite_label
from support.consumer import Consumer

V1, V2 = vehicle_guid(1), vehicle_guid(2)
HAPPY = [S.ISSUED, S.COMMANDED, S.EXECUTING, S.COMPLETED]


def wait_reports(c: Consumer, vehicle: uuid.UUID, sems: list[Sem] | None = None) -> None:
    sems = sems or [Sem.GPS_REPORT, Sem.GPS_FIX_REPORT, Sem.GPS_FIX_STATUS_REPORT, Sem.INS_REPORT]
    c.wait(lambda: all(c.reports[s].get(vehicle) for s in sems), 20, "a report of every type")


def test_every_report_type_with_plausible_values(sim, consumer: Consumer) -> None:
    sim("--vehicles", "2")
    for v in (V1, V2):
        wait_reports(consumer, v)
    gps = consumer.latest(Sem.GPS_REPORT, V1)
    assert 20 <= len(gps.satellites) <= 40 and gps.numberSatellitesInView == len(gps.satellites)
    consts = {s.constellationType.name for s in gps.satellites}
    assert {"GPS", "GALILEO", "GLONASS", "BEIDOU", "SBAS"} <= consts
    for s in gps.satellites:
        assert -math.pi <= s.azimuth <= math.pi and 0 < s.elevation < math.pi / 2
        assert 0 <= s.antennaCarrierNoiseDensity < 60 and s.carrierFrequency > 1.5e9
        assert satellite_label(s.satelliteId)[0] in "GERCS"
    assert gps.clock.leapSecond == 18 and gps.clock.biasUncertianty is not None
    # submerged at start: no valid fix, dead reckoning, nothing used in the fix
    fix, status = consumer.latest(Sem.GPS_FIX_REPORT, V1), consumer.latest(Sem.GPS_FIX_STATUS_REPORT, V1)
    assert fix.GPSLatLongValid is False and fix.altitudeMSL.altitude < 0
    assert status.fixValid is False and status.navSolution is Nav.GPS_DEAD_RECK
    assert not any(s.usedInFix for s in gps.satellites)
    assert -90 <= fix.position2DWithTime.geodeticPosition.geodeticLatitude.latitude <= 90
    assert 0 <= fix.trueCourse < 2 * math.pi and fix.SOG > 0
    assert math.isclose(math.hypot(fix.velocity.northSpeed, fix.velocity.eastSpeed), fix.SOG, rel_tol=1e-6)
    assert fix.position2DWithTime.timeAtPosition > 1.7e9
    # satellites move between reports; the two vehicles have their own sources and skies
    consumer.wait(lambda: len(consumer.reports[Sem.GPS_REPORT][V1]) >= 3, 10, "three GPS reports")
    first, last = consumer.reports[Sem.GPS_REPORT][V1][0], consumer.latest(Sem.GPS_REPORT, V1)
    assert first.satellites[0].azimuth != last.satellites[0].azimuth
    assert [s.satelliteId for s in gps.satellites] != [s.satelliteId for s in consumer.latest(Sem.GPS_REPORT, V2).satellites]


def test_ins_aligns_after_power_on(sim, consumer: Consumer) -> None:
    sim("--align-seconds", "20")  # 1 s at --time-scale 0.05
    consumer.wait(
        lambda: any(r.status is Op.OPERATIONAL for r in consumer.reports[Sem.INS_REPORT].get(V1, [])), 20, "OPERATIONAL"
    )
    seen = [r.status for r in consumer.reports[Sem.INS_REPORT][V1]]
    order = [
        Op.INIT,
        Op.COURSE_STATIONARY_ALIGNMENT,
        Op.FINE_STATIONARY_ALIGNMENT_STARTED,
        Op.FINE_STATIONARY_ALIGNMENT_COMPLETE,
        Op.OPERATIONAL,
    ]
    ranks = [order.index(s) for s in seen]
    assert ranks == sorted(ranks) and len(set(ranks)) >= 3


def test_gps_fix_surfaces_and_completes(sim, consumer: Consumer) -> None:
    sim()
    wait_reports(consumer, V1)
    session = consumer.command(Service.GPS_FIX, V1)
    seen = consumer.wait_terminal(session)
    assert seen.statuses == HAPPY and seen.reasons == [R.SUCCEEDED] * 4 and seen.flow.violations == []
    assert from_guid(seen.ack.sessionID) == session and from_guid(seen.ack.source) == V1
    consumer.wait(lambda: consumer.latest(Sem.GPS_FIX_REPORT, V1).GPSFixCommandStatus is Fix.STABLE, 5, "STABLE")
    fix_states = [r.GPSFixCommandStatus for r in consumer.reports[Sem.GPS_FIX_REPORT][V1]]
    assert Fix.PERFORMING in fix_states and Fix.STABLE in fix_states
    assert fix_states.index(Fix.PERFORMING) < len(fix_states) - 1 - fix_states[::-1].index(Fix.STABLE)
    consumer.wait(lambda: consumer.latest(Sem.GPS_FIX_STATUS_REPORT, V1).fixValid, 5, "a valid fix")
    assert consumer.latest(Sem.GPS_FIX_STATUS_REPORT, V1).navSolution is Nav.GPS_3D
    consumer.wait(lambda: any(s.usedInFix for s in consumer.latest(Sem.GPS_REPORT, V1).satellites), 5, "satellites used")
    # cleanup: the consumer disposes the finished command, the provider disposes status and ack
    consumer.dispose(session)
    consumer.wait(lambda: seen.status_disposed and seen.ack_disposed, 10, "status and ack disposed")
    assert seen.statuses == HAPPY  # no CANCELED for a finished command


@pytest.mark.parametrize("target,state_after", [(Ins.OFF, Ins.OFF), (Ins.ON, Ins.ON), (Ins.RESTARTING, Ins.ON)])
def test_inertial_sensor_commands(sim, consumer: Consumer, target: Ins, state_after: Ins) -> None:
    sim("--align-seconds", "20")
    wait_reports(consumer, V1, [Sem.INS_REPORT])
    if target is Ins.ON:  # switch it off first so ON has an alignment to go through
        assert consumer.wait_terminal(consumer.command(Service.INERTIAL_SENSOR, V1, Ins.OFF)).statuses == HAPPY
    mark = len(consumer.reports[Sem.INS_REPORT][V1])
    session = consumer.command(Service.INERTIAL_SENSOR, V1, target)
    seen = consumer.wait_terminal(session)
    assert seen.statuses == HAPPY and seen.flow.violations == [] and seen.ack.state is target
    after = consumer.reports[Sem.INS_REPORT][V1][mark:]
    consumer.pump()
    assert consumer.latest(Sem.INS_REPORT, V1).state is state_after
    if target is Ins.RESTARTING:
        assert any(r.state is Ins.RESTARTING for r in after)
    if state_after is Ins.ON:
        assert consumer.latest(Sem.INS_REPORT, V1).status is Op.OPERATIONAL
        assert any(r.status is Op.COURSE_STATIONARY_ALIGNMENT for r in after)


def test_cancel_by_dispose(sim, consumer: Consumer) -> None:
    sim("--surface-seconds", "400")  # 20 s to surface: plenty of time to cancel
    wait_reports(consumer, V1, [Sem.GPS_FIX_REPORT])
    session = consumer.command(Service.GPS_FIX, V1)
    seen = consumer.wait_status(session, S.EXECUTING)
    consumer.dispose(session)
    consumer.wait(lambda: seen.status_disposed and seen.ack_disposed, 10, "status and ack disposed after cancel")
    assert seen.statuses == [S.ISSUED, S.COMMANDED, S.EXECUTING, S.CANCELED]
    assert seen.reasons[-1] is R.CANCELED and seen.flow.violations == []


def test_commands_for_another_destination_are_ignored(sim, consumer: Consumer) -> None:
    sim()
    wait_reports(consumer, V1, [Sem.GPS_FIX_REPORT])
    other = consumer.command(Service.GPS_FIX, uuid.uuid4())
    mine = consumer.command(Service.GPS_FIX, V1)
    consumer.wait_terminal(mine)
    assert consumer.commands[other].statuses == []


def test_invalid_command_fails_validation(sim, consumer: Consumer) -> None:
    sim()
    wait_reports(consumer, V1, [Sem.GPS_FIX_REPORT])
    session = consumer.command(Service.GPS_FIX, V1, timeStamp=DateTime(seconds=1, nanoseconds=2_000_000_000))
    seen = consumer.wait_terminal(session)
    assert seen.statuses == [S.ISSUED, S.FAILED] and seen.reasons[-1] is R.VALIDATION_FAILED
    assert "timeStamp" in seen.flow.transitions[-1].log_message


def test_newer_command_interrupts_running_one(sim, consumer: Consumer) -> None:
    sim("--surface-seconds", "400")
    wait_reports(consumer, V1, [Sem.GPS_FIX_REPORT])
    first = consumer.command(Service.GPS_FIX, V1)
    consumer.wait_status(first, S.EXECUTING)
    second = consumer.command(Service.GPS_FIX, V1)
    seen = consumer.wait_terminal(first)
    assert seen.statuses[-1] is S.FAILED and seen.reasons[-1] is R.INTERRUPTED
    consumer.wait_status(second, S.EXECUTING)


@pytest.mark.parametrize(
    "fault,statuses,reason",
    [
        ("reject", [S.ISSUED, S.FAILED], R.RESOURCE_REJECTED),
        ("fail-midway", [S.ISSUED, S.COMMANDED, S.EXECUTING, S.FAILED], R.RESOURCE_FAILED),
        ("skip-commanded", [S.ISSUED, S.EXECUTING, S.COMPLETED], R.SUCCEEDED),
    ],
)
def test_injected_faults_on_one_vehicle(sim, consumer: Consumer, fault: str, statuses: list[S], reason: R) -> None:
    sim("--vehicles", "2", "--fault", f"{fault}:2")
    for v in (V1, V2):
        wait_reports(consumer, v, [Sem.GPS_FIX_REPORT])
    healthy, faulty = consumer.command(Service.GPS_FIX, V1), consumer.command(Service.GPS_FIX, V2)
    assert consumer.wait_terminal(healthy).statuses == HAPPY
    seen = consumer.wait_terminal(faulty)
    assert seen.statuses == statuses and seen.reasons[-1] is reason
    if fault == "skip-commanded":
        assert seen.flow.violations == ["ISSUED -> EXECUTING is not a Figure 4 transition"]
    else:
        assert seen.flow.violations == []


def test_no_answer_and_slow_faults(sim, consumer: Consumer) -> None:
    sim("--vehicles", "3", "--fault", "no-answer:2", "--fault", "slow:3", "--slow-factor", "100")
    for v in (V1, V2, vehicle_guid(3)):
        wait_reports(consumer, v, [Sem.GPS_FIX_REPORT])
    healthy = consumer.command(Service.GPS_FIX, V1)
    silent = consumer.command(Service.GPS_FIX, V2)
    slow = consumer.command(Service.GPS_FIX, vehicle_guid(3))
    consumer.wait_terminal(healthy)
    consumer.wait_status(slow, S.ISSUED)
    consumer.pump()
    # the healthy vehicle finished while the slow one has not moved past ISSUED (each step takes 2.5 s)
    assert consumer.commands[slow].statuses == [S.ISSUED]
    consumer.wait_status(slow, S.COMMANDED, timeout=10)
    assert consumer.commands[silent].statuses == [] and consumer.commands[silent].ack is None


def test_provider_restart_fails_persisted_command(sim, consumer: Consumer) -> None:
    first = sim("--surface-seconds", "400")
    wait_reports(consumer, V1, [Sem.GPS_FIX_REPORT])
    session = consumer.command(Service.GPS_FIX, V1)
    consumer.wait_status(session, S.EXECUTING)
    first.kill()  # no shutdown sequence: the command stays on the bus
    consumer.pump()
    consumer.commands[session].ack = None  # the first process's ack was seen
    sim("--surface-seconds", "400")
    seen = consumer.wait_terminal(session, timeout=20)
    assert seen.statuses == [S.ISSUED, S.COMMANDED, S.EXECUTING, S.FAILED]
    assert seen.reasons[-1] is R.SERVICE_FAILED and seen.flow.violations == []
    assert seen.ack is None  # the ack is published again only by a provider that resumes the command


def test_command_published_before_the_provider_started_runs_normally(sim, consumer: Consumer) -> None:
    session = consumer.command(Service.GPS_FIX, V1)
    sim()
    seen = consumer.wait_terminal(session, timeout=20)
    assert seen.statuses == HAPPY and seen.flow.violations == []


def test_provider_restart_resumes_persisted_command(sim, consumer: Consumer) -> None:
    first = sim("--surface-seconds", "100", "--on-startup", "resume")
    wait_reports(consumer, V1, [Sem.GPS_FIX_REPORT])
    session = consumer.command(Service.GPS_FIX, V1)
    consumer.wait_status(session, S.EXECUTING)
    first.kill()
    sim("--surface-seconds", "100", "--on-startup", "resume")
    seen = consumer.wait_terminal(session, timeout=20)
    assert seen.statuses == HAPPY and seen.flow.violations == []
    consumer.wait(lambda: seen.ack is not None, 5, "the ack again")


def test_provider_restart_leaves_finished_command_for_cleanup(sim, consumer: Consumer) -> None:
    first = sim()
    wait_reports(consumer, V1, [Sem.GPS_FIX_REPORT])
    session = consumer.command(Service.GPS_FIX, V1)
    seen = consumer.wait_terminal(session)
    first.kill()  # finished, not yet cleaned up by the consumer
    second = sim()
    consumer.wait(lambda: bool(consumer.reports[Sem.GPS_FIX_REPORT][V1]) and second.proc is not None, 10, "restart")
    consumer.reports[Sem.GPS_FIX_REPORT][V1].clear()
    wait_reports(consumer, V1, [Sem.GPS_FIX_REPORT])  # the new process is up and past its startup window
    consumer.wait(lambda: len(consumer.reports[Sem.GPS_FIX_REPORT][V1]) > 20, 10, "two seconds of reports")
    assert seen.statuses == HAPPY and seen.flow.violations == []


def test_orphaned_command_is_canceled_and_never_restarted(sim, consumer: Consumer, domain: int) -> None:
    sim("--surface-seconds", "400", "--orphan-grace", "0.5")
    wait_reports(consumer, V1, [Sem.GPS_FIX_REPORT])
    other = Consumer(domain, name="short-lived")
    session = other.command(Service.GPS_FIX, V1)
    service, sample = other.sent[session]
    consumer.wait_status(session, S.EXECUTING)
    other.close()
    del other  # its writer goes away: the command has no writer left
    seen = consumer.wait_terminal(session, timeout=15)
    assert seen.statuses[-1] is S.CANCELED
    writer = consumer.bus.writer(service.command)  # a new writer, as a restarted consumer would have
    consumer.wait(lambda: bool(writer.get_matched_subscriptions()), 10, "the new writer to match")
    # The writer sees the match before the provider's reader has matched the writer, and a
    # sample written in between does not arrive: give discovery a moment to settle both ways.
    time.sleep(1.0)
    writer.write(sample)  # the same command, published again
    mark = len(consumer.reports[Sem.GPS_FIX_REPORT][V1])
    consumer.wait(lambda: len(consumer.reports[Sem.GPS_FIX_REPORT][V1]) > mark + 20, 10, "two seconds to react")
    assert seen.statuses == [S.ISSUED, S.COMMANDED, S.EXECUTING, S.CANCELED] and seen.flow.violations == []


def test_invalid_command_does_not_interrupt_running_one(sim, consumer: Consumer) -> None:
    sim("--surface-seconds", "100")
    wait_reports(consumer, V1, [Sem.GPS_FIX_REPORT])
    running = consumer.command(Service.GPS_FIX, V1)
    consumer.wait_status(running, S.EXECUTING)
    bad = consumer.command(Service.GPS_FIX, V1, timeStamp=DateTime(seconds=-5, nanoseconds=0))
    assert consumer.wait_terminal(bad).reasons[-1] is R.VALIDATION_FAILED
    assert consumer.commands[bad].ack is None
    assert consumer.wait_terminal(running).statuses == HAPPY


def test_ins_command_fails_when_the_ins_has_failed(sim, consumer: Consumer) -> None:
    sim("--fault", "ins-failure")
    wait_reports(consumer, V1, [Sem.INS_REPORT])
    seen = consumer.wait_terminal(consumer.command(Service.INERTIAL_SENSOR, V1, Ins.RESTARTING))
    assert seen.statuses == [S.ISSUED, S.COMMANDED, S.EXECUTING, S.FAILED] and seen.reasons[-1] is R.RESOURCE_FAILED


def test_command_timeout(sim, consumer: Consumer) -> None:
    sim("--surface-seconds", "400", "--command-timeout", "10")  # 0.5 s at --time-scale 0.05
    wait_reports(consumer, V1, [Sem.GPS_FIX_REPORT])
    seen = consumer.wait_terminal(consumer.command(Service.GPS_FIX, V1))
    assert seen.statuses[-1] is S.FAILED and seen.reasons[-1] is R.TIMEOUT


def test_zero_alignment_time(sim, consumer: Consumer) -> None:
    p = sim("--align-seconds", "0")
    consumer.wait(
        lambda: any(r.status is Op.OPERATIONAL for r in consumer.reports[Sem.INS_REPORT].get(V1, [])), 10, "OPERATIONAL"
    )
    assert p.proc is not None and p.proc.poll() is None


def test_ctrl_c_runs_shutdown_sequence(sim, consumer: Consumer) -> None:
    p = sim("--surface-seconds", "400")
    wait_reports(consumer, V1)
    session = consumer.command(Service.GPS_FIX, V1)
    consumer.wait_status(session, S.EXECUTING)
    out = p.stop(signal.SIGINT)
    assert p.proc is not None and p.proc.returncode == 0, out
    assert "Traceback" not in out
    seen = consumer.wait_terminal(session)
    assert seen.statuses[-1] is S.FAILED and seen.reasons[-1] is R.SERVICE_FAILED
    consumer.wait(
        lambda: all(
            V1 in consumer.report_disposed[s]
            for s in (Sem.GPS_REPORT, Sem.GPS_FIX_REPORT, Sem.GPS_FIX_STATUS_REPORT, Sem.INS_REPORT)
        ),
        10,
        "reports disposed",
    )


@pytest.mark.parametrize(
    "args,message",
    [
        (["--vehicles", "0"], "--vehicles: 0 is outside 1..1000"),
        (["--domain", "x"], "sem-sim: error: --domain: 'x' is not a whole number"),
        (["--fault", "explode"], "unknown fault 'explode'"),
        (["--fault", "reject:zero"], "must be a vehicle number"),
        (["--vehicles", "2", "--fault", "reject:3"], "--fault reject:3: this simulator runs vehicles 1..2"),
        (["--first-vehicle", "4", "--fault", "ins-failure:1"], "--fault ins-failure:1: this simulator runs vehicle 4"),
        (["--fix-rate", "50"], "--fix-rate: 50 is outside 1..10"),
        (["--nope"], "unrecognized arguments: --nope"),
        # a fault for a vehicle it does not run was injected nowhere, silently; a health file it cannot write, never written
        (
            ["--vehicles", "2", "--first-vehicle", "3", "--fault", "reject:2"],
            "--fault reject:2: this simulator runs vehicles 3..4",
        ),
        (["--health-file", "/nonexistent/sem-sim.alive"], "--health-file /nonexistent/sem-sim.alive: cannot write it"),
    ],
)
def test_bad_options_one_line_exit_2(args: list[str], message: str) -> None:
    out = subprocess.run([sys.executable, "-m", "sem_console.sim.sem_sim", *args], capture_output=True, text=True, timeout=30)
    assert out.returncode == 2
    assert out.stdout == "" and out.stderr.count("\n") == 1 and message in out.stderr, out.stderr


def test_a_busy_imc_port_is_one_line_exit_2(domain: int) -> None:
    """The line had no 'error:' and no fix, unlike every other refusal of sem-sim."""
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as busy:
        busy.bind(("127.0.0.1", 0))
        port = busy.getsockname()[1]
        out = subprocess.run(
            [
                sys.executable,
                "-m",
                "sem_console.sim.sem_sim",
                "--domain",
                str(domain),
                "--imc-port",
                str(port),
                "--imc-host",
                "127.0.0.1",
            ],
            capture_output=True,
            text=True,
            timeout=60,
        )
    assert out.returncode == 2 and out.stderr.count("\n") == 1, out.stderr
    assert out.stderr.startswith(f"sem-sim: error: cannot listen for IMC on 127.0.0.1:{port}: ")
    assert "another --imc-port" in out.stderr
    # an address not of this machine (TEST-NET-1) is not a busy port: the fix names --imc-host, not another port
    out = subprocess.run(
        [
            sys.executable,
            "-m",
            "sem_console.sim.sem_sim",
            "--domain",
            str(domain),
            "--imc-port",
            "6099",
            "--imc-host",
            "192.0.2.1",
        ],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert out.returncode == 2 and out.stderr.count("\n") == 1, out.stderr
    assert "--imc-host address of this machine" in out.stderr and "another --imc-port" not in out.stderr, out.stderr


def test_help_documents_every_option() -> None:
    out = subprocess.run([sys.executable, "-m", "sem_console.sim.sem_sim", "--help"], capture_output=True, text=True, timeout=30)
    assert out.returncode == 0
    for opt in ("--domain", "--vehicles", "--time-scale", "--fault", "--on-startup", "--surface-seconds", "--align-seconds"):
        assert opt in out.stdout


def test_ins_failure_fault_on_one_vehicle(sim, consumer: Consumer) -> None:
    sim("--vehicles", "2", "--fault", "ins-failure:2")
    for v in (V1, V2):
        wait_reports(consumer, v, [Sem.INS_REPORT])
    consumer.wait(lambda: consumer.latest(Sem.INS_REPORT, V1).status is Op.OPERATIONAL, 10, "vehicle 1 OPERATIONAL")
    assert consumer.latest(Sem.INS_REPORT, V2).status is Op.INERTIAL_SENSOR_FAILURE


def test_writers_offer_the_representation_of_their_type(sim, consumer: Consumer) -> None:
    """XCDR1 (what every vendor's default reader accepts) for types without @optional members; XCDR2
    only for GPSReport and GPSFixReport, whose XCDR1 layout vendors read differently."""
    from cyclonedds.builtin import BuiltinDataReader, BuiltinTopicDcpsPublication
    from cyclonedds.core import Policy

    reader = BuiltinDataReader(consumer.bus.participant, BuiltinTopicDcpsPublication)
    sim()
    wait_reports(consumer, V1)
    reports = {s.spec.name for s in (Sem.GPS_REPORT, Sem.GPS_FIX_REPORT, Sem.GPS_FIX_STATUS_REPORT, Sem.INS_REPORT)}
    offered: dict[str, object] = {}
    consumer.wait(
        lambda: (
            offered.update({p.topic_name: p.qos[Policy.DataRepresentation] for p in reader.read(N=100)})
            or reports <= set(offered)
        ),
        10,
        "publications",
    )
    for sem in (Sem.GPS_REPORT, Sem.GPS_FIX_REPORT):
        rep = offered[sem.spec.name]
        assert rep.use_xcdrv2_representation and not rep.use_cdrv0_representation, rep
    for sem in (Sem.GPS_FIX_STATUS_REPORT, Sem.INS_REPORT):
        rep = offered[sem.spec.name]
        assert rep.use_cdrv0_representation and not rep.use_xcdrv2_representation, rep


def test_shutdown_with_a_vanished_reader_is_clean(sim, consumer: Consumer, domain: int) -> None:
    """wait_for_acks times out when a matched reader died without a goodbye; shutdown must still be clean."""
    p = sim("--surface-seconds", "400")
    wait_reports(consumer, V1)
    crashed = subprocess.Popen(
        [
            sys.executable,
            "-c",
            (
                "import sys, time; sys.path.insert(0, 'tests'); from support.consumer import Consumer; "
                f"c = Consumer({domain}, name='crashes'); time.sleep(30)"
            ),
        ],
        cwd=str(__import__('pathlib').Path(__file__).parents[2]),
    )
    time.sleep(2.0)  # it has matched the simulator's writers
    session = consumer.command(Service.GPS_FIX, V1)
    consumer.wait_status(session, S.EXECUTING)
    crashed.kill()
    crashed.wait()
    out = p.stop(signal.SIGINT)
    assert p.proc is not None and p.proc.returncode == 0 and "Traceback" not in out, out


def test_a_second_simulator_does_not_impersonate_the_first(sim, consumer: Consumer, tmp_path) -> None:
    """Two real processes on one domain: the second refuses vehicle 1, runs vehicles from 2 when told to,
    and never takes over the first one's journal."""
    first = sim()
    wait_reports(consumer, V1, [Sem.INS_REPORT])
    second = sim("--state-file", str(tmp_path / "second.json"))  # its own journal, the same vehicle 1
    assert second.proc is not None and second.proc.wait(timeout=20) == 1
    out = second.stop()
    assert out.strip().splitlines()[-1] == (
        f"sem-sim: error: vehicle 1 already runs on domain {second.domain} in another "
        "process; run these vehicles with --first-vehicle 2 or on another --domain"
    )
    same_journal = sim("--first-vehicle", "2")  # other vehicles, but the first one's journal
    assert same_journal.proc is not None and same_journal.proc.wait(timeout=20) == 1
    assert f"is in use by another simulator (pid {first.proc.pid})" in same_journal.stop()  # type: ignore[union-attr]
    both = sim("--first-vehicle", "2", "--vehicles", "2", "--state-file", str(tmp_path / "from-2.json"))
    for v in (V2, vehicle_guid(3)):
        wait_reports(consumer, v, [Sem.INS_REPORT])
    session = consumer.command(Service.GPS_FIX, V1)  # vehicle 1 is still the first process's, and answers
    assert consumer.wait_terminal(session, timeout=20).statuses == HAPPY
    assert first.proc is not None and first.proc.poll() is None and both.proc is not None and both.proc.poll() is None
    listed = subprocess.run(
        [sys.executable, "-m", "sem_console.sim.sem_sim", "--first-vehicle", "2", "--vehicles", "2", "--list"],
        capture_output=True,
        text=True,
        timeout=30,
    ).stdout
    assert listed.splitlines() == [f"vehicle 2: {V2}", f"vehicle 3: {vehicle_guid(3)}"]


def test_a_report_python_cannot_decode_does_not_stop_the_simulator(sim, domain: int, new_bus: Callable[[int], Bus]) -> None:
    """A GPSReport whose string is not UTF-8 passes Cyclone and fails Python's decoder; the
    simulator's look at the bus at start must not die of it (it is transient-local: it stays)."""
    import random

    from cyclonedds._clayer import ddspy_write

    from support.samplegen import random_sample

    w = new_bus(domain).writer(Sem.GPS_REPORT)
    rng = random.Random(1)
    x = random_sample(Sem.GPS_REPORT.spec.type, rng)
    while x.clock is None:
        x = random_sample(Sem.GPS_REPORT.spec.type, rng)
    x.clock.referenceCodeTypeFor = "ZZZZ"
    data = x.serialize(use_version_2=True).replace(b"ZZZZ", b"\xff\xfeZZ")
    with pytest.raises(UnicodeDecodeError):
        Sem.GPS_REPORT.spec.type.deserialize(data)
    assert ddspy_write(w._ref, data) == 0  # the bytes as a peer would send them
    p = sim()
    time.sleep(4)  # past the start-up look at the bus (1 to 3 s)
    assert p.proc is not None and p.proc.poll() is None, p.stop()
    assert "Traceback" not in p.stop()


def test_two_simulators_started_together_leave_one_vehicle(domain: int, tmp_path) -> None:
    """Both pass the start-up look at an empty bus when they start at the same moment; the watch
    that follows leaves exactly one of them running. The wait for the first to leave is a start-up wait (as a
    console's health): under a loaded run two simulators starting at once took 20 s to get as far as their look."""
    from conftest import FAST

    procs = [
        subprocess.Popen(
            [
                sys.executable,
                "-m",
                "sem_console.sim.sem_sim",
                "--domain",
                str(domain),
                "--state-file",
                str(tmp_path / f"s{i}.json"),
                *FAST,
            ],
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
        )
        for i in range(2)
    ]
    try:
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and all(p.poll() is None for p in procs):
            time.sleep(0.1)
        time.sleep(1)  # the one left runs on past its next watch (every second)
        running = [p for p in procs if p.poll() is None]
        assert len(running) == 1, [p.poll() for p in procs]
        stopped = next(p for p in procs if p.poll() is not None)
        assert stopped.returncode == 1 and "vehicle 1" in stopped.communicate()[0]
    finally:
        for p in procs:
            if p.poll() is None:
                p.terminate()
                p.communicate(timeout=15)
