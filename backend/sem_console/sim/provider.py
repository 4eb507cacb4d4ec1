"""Simulated vehicles: UMAA Service Providers for GPSFixControl, GPSFixStatus, GPSStatus,
InertialSensorControl and InertialSensorStatus (ICD 4.1 and 5.1).

One process, one participant, one writer per topic; each vehicle writes its own
instances (keyed by its source GUID). A single thread runs the polling loop
(`Simulator.run`), so no state is shared between threads. The parts: `options`,
`reports` (each vehicle's sensors and reports), `provider_flow` (the provider side of the command
flow), `journal` (command states across restarts) and, here, the polling loop.
"""

from __future__ import annotations

import contextlib
import logging
import math
import time
import uuid
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from cyclonedds.core import InstanceState, Policy, Qos
from cyclonedds.pub import DataWriter

from UMAA.Common.MaritimeEnumeration.CommandStatusEnumType import CommandStatusEnumType as Status

from sem_console.dds.bus import Bus, all_samples, take_each, wait_for_acks
from sem_console.dds.cyclone_private import InvalidSample
from sem_console.dds.qos import TopicClass, any_writer_reader_qos
from sem_console.dds.topics import AnySem, Sem, Service, to_appendable
from sem_console.sim.comap_vehicle import ComapVehicles
from sem_console.sim.journal import InUse, Journal, default_state_file
from sem_console.sim.options import FAULTS, MAX_VEHICLE, SimOptions, vehicle_guid
from sem_console.sim.prepared import PreparedWriter
from sem_console.sim.provider_flow import ProviderFlow
from sem_console.sim.reports import Out, Sensors
from sem_console.sim.umaa_6_0 import Writer60
from sem_console.umaa.guid import from_guid
from sem_console.versions import UmaaVersion
from sem_console.versions.commands import COMMANDING, Commanding

__all__ = ["FAULTS", "InUse", "SimOptions", "Simulator", "Vehicle", "vehicle_guid"]

log = logging.getLogger("sem-sim")
REPORT_TOPICS = [sem for sem in Sem if sem.spec.cls is TopicClass.REPORT]


_U64 = 0xFFFF_FFFF_FFFF_FFFF


@dataclass
class Vehicle:
    number: int
    guid: uuid.UUID
    faults: set[str]
    sensors: Sensors
    commands: ProviderFlow
    version: UmaaVersion  # what it speaks (--umaa, --umaa-6-0-vehicles)
    write: Out  # its samples, as its version writes them
    dispose: Out


def providers_on_bus(bus: Bus, wait: float, longest: float = 3.0) -> set[uuid.UUID]:
    """Source GUIDs whose reports are alive on the bus: what arrives within `wait` seconds (a
    best-effort or volatile writer's within its report period), and, up to `longest` seconds,
    the history of every transient-local writer matched by then (slow on a loaded machine)."""
    durable = [bus.reader(sem) for sem in REPORT_TOPICS]
    readers = durable + [bus.reader(sem, any_writer_reader_qos(sem.spec.cls)) for sem in REPORT_TOPICS]
    found: set[uuid.UUID] = set()
    heard: set[int] = set()  # writers (publication handles) whose samples arrived
    start = time.monotonic()
    while True:
        for r in readers:
            samples, _bad = take_each(r)  # a sample Python cannot decode must not stop the simulator
            for s in samples:
                heard.add(s.sample_info.publication_handle & 0xFFFF_FFFF_FFFF_FFFF)
                if not isinstance(s, InvalidSample) and s.sample_info.instance_state == InstanceState.Alive:
                    with contextlib.suppress(TypeError, ValueError):
                        found.add(from_guid(s.source))
        waiting = {h & 0xFFFF_FFFF_FFFF_FFFF for r in durable for h in r.get_matched_publications()} - heard
        elapsed = time.monotonic() - start
        if elapsed >= longest or (elapsed >= wait and not waiting):
            return found
        time.sleep(0.02)


class Simulator:
    """Runs the vehicles of one `sem-sim` process on one DDS participant."""

    TICK = 0.02  # s

    def __init__(self, bus: Bus, opts: SimOptions) -> None:
        self.bus, self.opts = bus, opts
        self.claim()  # before anything is published: a second process must not impersonate the first
        self.journal = Journal(opts.state_file or default_state_file(bus.domain_id, opts.first_vehicle))
        # Provider Startup Sequence: publishers of status and ack (and reports) first ...
        # --gps-extensibility appendable: GPSReport and GPSFixReport written with their appendable copies, which RTI
        # consumers on the AppendableGps profile read right (the console reads either: one reader per extensibility)
        self.appendable = {s for s in Sem if s.spec.appendable is not None} if opts.gps_extensibility == "appendable" else set()
        # --umaa 6.0 or --umaa-6-0-vehicles: those vehicles' samples written on the 6.0 topics (sim/umaa_6_0.py)
        versions = {opts.version_of(n) for n in opts.numbers}
        self.writer60 = Writer60.of_fleet(bus, opts)
        self.writers: dict[AnySem, DataWriter[Any]] = {  # the reports batched: sent at the end of each tick
            sem: bus.writer(sem, appendable=sem in self.appendable, batching=sem.spec.cls is TopicClass.REPORT)
            for sem in Sem
            if sem.spec.cls is not TopicClass.COMMAND and not all(Writer60.speaks(opts, n) for n in opts.numbers)
        }
        # the reports, a thousand vehicles' worth a second, from prepared bytes (sim/prepared.py)
        self.prepared = {sem: PreparedWriter(w) for sem, w in self.writers.items() if sem.spec.cls is TopicClass.REPORT}
        self.report_writers = [*self.prepared.values(), *(self.writer60.prepared.values() if self.writer60 else [])]
        self.vehicles = {v.guid: v for v in (self._vehicle(n) for n in opts.numbers)}
        self.comap: ComapVehicles | None = None
        if opts.imc_port is not None:  # CoMap vehicles over IMC (an OSError when the port is taken)
            self.comap = ComapVehicles(opts, [v.sensors for v in self.vehicles.values()])
        # ... then subscribe to commands; at startup the status readers tell where a persisted command stood.
        # the commands of the vehicles' versions (versions/commands.py): each vehicle answers its own version's only
        commandings = [c for c in COMMANDING.values() if c.version in versions]
        self.command_readers = {c: bus.reader(c.command) for c in commandings}
        self.status_readers = {c: bus.reader(c.status) for c in commandings}
        self.conditions = {c: all_samples(r) for c, r in self.command_readers.items()}
        self._bus_status: dict[tuple[uuid.UUID, uuid.UUID], Status] = {}
        # Watched for as long as it runs: another process that starts at the same moment passes claim().
        # Not our own samples (IgnoreLocal): a thousand vehicles' INS reports a second, each delivered to it and
        # decoded by cyclonedds to be skipped, cost more than the rest of the watch.
        self._twin_reader = (
            bus.reader(Sem.INS_REPORT, any_writer_reader_qos(TopicClass.REPORT) + Qos(Policy.IgnoreLocal.Participant))
            if Sem.INS_REPORT in self.writers
            else None
        )
        self._twin_at = 0.0
        self._health_at = 0.0
        # Until when no vehicle has anything to do: none has a report due, none is changing (a command executing, a
        # surfacing, an INS restarting, a CoMap task), and no command came since the vehicles were last looked at.
        self._quiet_until = 0.0
        self.started = False

    def claim(self) -> None:
        """Refuse to impersonate: another process already publishing one of our vehicles' GUIDs."""
        ours = {vehicle_guid(n): n for n in self.opts.numbers}
        on_bus = providers_on_bus(self.bus, self.opts.identity_wait)
        taken = sorted(n for g, n in ours.items() if g in on_bus)
        if taken:
            sims = {vehicle_guid(n): n for n in range(1, MAX_VEHICLE + 1)}
            free = max(sims[g] for g in on_bus if g in sims) + 1
            raise InUse(
                f"vehicle {', '.join(map(str, taken))} already runs on domain {self.bus.domain_id} in another process", free=free
            )

    def _vehicle(self, number: int) -> Vehicle:
        guid, faults = vehicle_guid(number), self.opts.faults_for(number)
        sensors = Sensors(self.opts, number, guid, faults)
        version = self.opts.version_of(number)
        if self.writer60 is not None and Writer60.speaks(self.opts, number):
            write, dispose, ins = self.writer60.write, self.writer60.dispose, self.writer60.alignments
        else:
            write, dispose, ins = self.write, self.dispose, None
        return Vehicle(
            number,
            guid,
            faults,
            sensors,
            ProviderFlow(self.opts, number, guid, faults, sensors, self.journal, write, dispose, ins),
            version,
            write,
            dispose,
        )

    def write(self, sem: AnySem, sample: Any) -> None:
        """A 3.0.1 vehicle's sample."""
        out = to_appendable(sample) if sem in self.appendable else sample
        prepared = self.prepared.get(sem)
        if prepared is not None:
            prepared.write(out)
        else:
            self.writers[sem].write(out)

    def dispose(self, sem: AnySem, sample: Any) -> None:
        self.writers[sem].dispose(to_appendable(sample) if sem in self.appendable else sample)

    def startup(self, window: float = 1.0) -> None:
        """Handle commands already on the bus addressed to our vehicles (ICD 4.1.2.1).

        For `window` seconds, commands that arrive are checked against the journal (and
        any status still on the bus) before they are treated as new.
        """
        deadline = time.monotonic() + window
        while time.monotonic() < deadline:
            self._take_bus_statuses()
            self.poll_commands(startup=True)
            self.step_vehicles()
            time.sleep(self.TICK)
        self.status_readers.clear()  # only needed for startup; they would keep our own statuses
        self.started = True

    def _take_bus_statuses(self) -> None:
        for c, reader in self.status_readers.items():
            for s in take_each(reader)[0]:
                if isinstance(s, InvalidSample) or c.source(s) not in self.vehicles:
                    continue
                status = c.read_status(s)[0]
                if isinstance(status, Status):
                    self._bus_status[(c.source(s), from_guid(s.sessionID))] = status

    def last_status(self, vehicle: Vehicle, service: Service, session: uuid.UUID) -> Status | None:
        return self.journal.get(vehicle.guid, service, session) or self._bus_status.get((vehicle.guid, session))

    def poll_commands(self, startup: bool = False) -> None:
        now = time.monotonic()
        for c, reader in self.command_readers.items():
            samples, bad = take_each(reader, self.conditions[c])
            if bad:  # a sample Python cannot decode costs only itself
                log.warning("%d undecodable %s command(s)", bad, c.service.value)
            for s in samples:
                self.handle(c, s, now, startup)

    def handle(self, commanding: Commanding, s: Any, now: float, startup: bool) -> None:
        self._quiet_until = 0.0  # a command may start work before any report is due: every vehicle is looked at
        state = s.sample_info.instance_state
        cmd: Any = s.key_sample if isinstance(s, InvalidSample) else s  # a generated command struct
        service = commanding.service
        try:
            dest, session = commanding.destination(cmd), from_guid(cmd.sessionID)
        except (TypeError, ValueError):
            return
        vehicle = self.vehicles.get(dest)
        if vehicle is None or vehicle.version != commanding.version:
            return  # addressed to another provider (or in a version this vehicle does not speak)
        flow = vehicle.commands
        if not isinstance(s, InvalidSample):
            last = self.last_status(vehicle, service, session) if startup else None
            flow.on_command(commanding, s, now, startup, last)
        # A dispose that follows an unread sample shows only in that sample's instance state.
        ex = flow.executions.get((service, session))
        if ex is None:
            return
        if state == InstanceState.NotAliveDisposed:
            flow.end(ex, now)
        elif state == InstanceState.NotAliveNoWriters and ex.orphan_since is None:
            ex.orphan_since = now

    def tick(self) -> None:
        self.poll_commands()
        self.step_vehicles()
        self.watch_for_twins()

    def watch_for_twins(self, every: float = 1.0) -> None:
        """Raise InUse when another process publishes one of our vehicles: two processes that
        started together both passed claim(). Both see it; the one whose report writer has the
        greater GUID leaves (without disposing the vehicle's reports, which the other still
        publishes), so exactly one stays."""
        now = time.monotonic()
        if now - self._twin_at < every or self._twin_reader is None:
            return
        self._twin_at = now
        mine = self.writers[Sem.INS_REPORT].guid
        for s in take_each(self._twin_reader)[0]:
            handle = s.sample_info.publication_handle & _U64
            if isinstance(s, InvalidSample):
                continue
            with contextlib.suppress(TypeError, ValueError):
                source = from_guid(s.source)
                if source in self.vehicles:
                    other = self._twin_reader.get_matched_publication_data(handle)
                    if other is not None and other.key.bytes > mine.bytes:
                        continue  # the other process leaves
                    number = self.vehicles[source].number
                    raise InUse(f"vehicle {number} is also published by another process on domain {self.bus.domain_id}")

    def step_vehicles(self) -> None:
        now = time.monotonic()
        if self.opts.health_file and now - self._health_at >= 1.0:
            self._health_at = now
            with contextlib.suppress(OSError):
                self.opts.health_file.touch()
        if self.comap is not None:  # moves the vehicles under way for a task before they report
            try:
                self.comap.step()
            except Exception:  # a CoMap fault must not stop the UMAA provider
                log.exception("CoMap step failed")
        if now < self._quiet_until and self.comap is None:  # a thousand vehicles, fifty ticks a second
            return
        quiet_until = math.inf
        for v in self.vehicles.values():  # only those with work
            sensors = v.sensors
            if now < sensors.next_due and not v.commands.executions and not sensors.moving and sensors.pilot is None:
                quiet_until = min(quiet_until, sensors.next_due)
                continue
            sensors.step(now)
            v.commands.step(now)
            sensors.publish(now, v.write)
            busy = v.commands.executions or sensors.moving or sensors.pilot is not None
            quiet_until = 0.0 if busy else min(quiet_until, sensors.next_due)
        self._quiet_until = quiet_until
        self.flush()

    def flush(self) -> None:
        """Send the reports written (their writers batch them)."""
        for p in self.report_writers:
            p.flush()

    def run(self, stop: Callable[[], bool]) -> None:
        if not self.started:
            self.startup()
        while not stop():
            self.tick()
            time.sleep(self.TICK)

    def shutdown(self, ack_timeout: float = 2.0, twin: bool = False) -> None:
        """Provider Shutdown Sequence: fail what is incomplete, dispose the reports, wait for acks.
        A process that found a twin (watch_for_twins) only closes its journal: the vehicle's
        commands and reports belong to the other process."""
        if self.comap is not None:
            self.comap.close()
        if twin:
            self.journal.close()
            return
        for v in self.vehicles.values():
            v.commands.shutdown()
            v.sensors.dispose(v.dispose)
        self.flush()
        wait_for_acks([*self.writers.values(), *(self.writer60.writers.values() if self.writer60 else [])], ack_timeout)
        self.journal.close()
