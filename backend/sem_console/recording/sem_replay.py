"""`sem-replay FILE.mcap --domain N [--speed X] [--loop]`: republish a recording on DDS.

Every SEM sample of the recording, of either UMAA version, is written again on its topic, in the order and with the
spacing it was received (`log_time`, divided by `--speed`), as the CDR it was recorded with
(its keys, so its vehicle's source GUID and a command's sessionID, are the original ones) and,
unless `--retime`, with its original source timestamp. Writers use the project's QoS per topic
class. A sample recorded in a data representation the writer does not use (e.g. XCDR2 for a
type written in XCDR1) is decoded and written again in the writer's. Disposes and instances
that lost their writers (channel `sem-console/instances`) are republished as disposes and
unregistrations. Recorded commands (GPSFixCommand, InertialSensorCommand, 6.0's InertialSensorCommandType) are left out unless
`--commands`: a provider on the target domain would carry them out. The console's own channels (commands,
transitions, links, alarm acknowledgements, vehicle names) are not DDS topics and are not republished. An integrator
can test their own UMAA consumer against a trial this way.
"""

from __future__ import annotations

import argparse
import base64
import json
import logging
import signal
import sys
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from cyclonedds.pub import DataWriter
from mcap.exceptions import McapError

from sem_console.core.command_line import Parser, add_dds_security, from_environment, ranged
from sem_console.core.config import BusSettings
from sem_console.dds.bus import Bus, DdsConfigError, bus_security, wait_for_acks
from sem_console.dds.cyclone_private import write_cdr
from sem_console.dds.qos import TopicClass
from sem_console.dds.topics import AnySem, Sem, Sem60, delimited
from sem_console.recording.reader import INSTANCES, check_file, iter_messages

log = logging.getLogger("sem-replay")
BY_TOPIC: dict[str, AnySem] = {s.spec.name: s for s in (*Sem, *Sem60)}  # both UMAA versions' topics
# CDR encapsulation identifiers (first two bytes, big endian) of final types: XCDR1 and XCDR2
PLAIN_CDR, PLAIN_CDR2 = {0x0000, 0x0001}, {0x0006, 0x0007}


def build_parser() -> argparse.ArgumentParser:
    p = Parser(
        prog="sem-replay",
        description=(
            "Republish a sem-console recording (MCAP) on DDS: every SEM sample with its original keys, "
            "timing and source timestamps; disposes as disposes."
        ),
    )
    p.add_argument("file", type=Path, help="the recording (.mcap)")
    p.add_argument("--domain", type=ranged(int, 0, 232), required=True, help="DDS domain id to publish on, 0..232")
    add_dds_security(p, "sem-replay")
    # ranged: nan and inf were taken (inf published the whole file at once, a nan or negative --wait waited on)
    p.add_argument(
        "--speed", type=ranged(float, 0.01, 1000), default=1.0, help=("playback speed, e.g. 2 for twice as fast (default: 1)")
    )
    p.add_argument("--loop", action="store_true", help="start again at the end, until interrupted")
    p.add_argument(
        "--commands",
        action="store_true",
        help="republish the recorded commands too (a vehicle on that domain would carry them out)",
    )
    p.add_argument(
        "--retime", action="store_true", help="stamp samples with the replay's time instead of their recorded source timestamps"
    )
    p.add_argument(
        "--wait",
        type=ranged(float, 0, 3600),
        default=5.0,
        metavar="SECONDS",
        help="wait up to this long for a reader on the bus before the first sample (default: 5; 0: start at once)",
    )
    p.add_argument("--log-level", choices=("debug", "info", "warning", "error"), default="info")
    return p


class Replay:
    def __init__(self, bus: Bus, path: Path, speed: float, retime: bool, commands: bool = False) -> None:
        self.bus, self.path, self.speed, self.retime = bus, path, speed, retime
        self.topics = {name: sem for name, sem in BY_TOPIC.items() if commands or sem.spec.cls is not TopicClass.COMMAND}
        self.writers: dict[AnySem, DataWriter[Any]] = {}
        self.appendable_writers: dict[AnySem, DataWriter[Any]] = {}  # made at an appendable writer's first sample
        self.samples = self.disposes = self.unregisters = self.reencoded = self.skipped = 0
        self.stopping = False

    def writer(self, sem: AnySem) -> DataWriter[Any]:
        if sem not in self.writers:
            self.writers[sem] = self.bus.writer(sem)
        return self.writers[sem]

    def appendable_writer(self, sem: AnySem) -> DataWriter[Any]:
        """A writer of the topic's appendable copy, made at an appendable writer's first sample or key."""
        if sem not in self.appendable_writers:
            self.appendable_writers[sem] = self.bus.writer(sem, appendable=True)
        return self.appendable_writers[sem]

    def make_writers(self) -> None:
        """A writer for every topic to replay (DdsConfigError, one line, for one the identity may not write)."""
        for sem in self.topics.values():
            self.writer(sem)

    def wait_for_readers(self, seconds: float) -> bool:
        """Wait until a writer (make_writers) matches a reader (or `seconds` pass), so the first samples are not
        published before anyone listens."""
        deadline = time.monotonic() + seconds
        while time.monotonic() < deadline and not self.stopping:
            if any(w.get_matched_subscriptions() for w in self.writers.values()):
                return True
            time.sleep(0.05)
        return False

    def messages(self) -> Iterator[tuple[str, Any]]:
        """The recording's SEM and instance messages in log time order (see `iter_messages`)."""
        return iter_messages(self.path, {*self.topics, INSTANCES})

    def run_once(self) -> None:
        start_wall: float | None = None
        start_log = 0
        for topic, m in self.messages():
            if self.stopping:
                return
            if start_wall is None:
                start_wall, start_log = time.monotonic(), m.log_time
            delay = start_wall + (m.log_time - start_log) / 1e9 / self.speed - time.monotonic()
            while delay > 0 and not self.stopping:
                time.sleep(min(delay, 0.2))
                delay = start_wall + (m.log_time - start_log) / 1e9 / self.speed - time.monotonic()
            ts = time.time_ns() if self.retime else m.publish_time
            try:
                if topic == INSTANCES:
                    self.instance(json.loads(m.data), ts)
                else:
                    self.sample(BY_TOPIC[topic], m.data, ts)
            except Exception as e:  # one bad message costs only itself
                self.skipped += 1
                log.warning("skipped a message on %s at %d: %s", topic, m.log_time, e)

    def sample(self, sem: AnySem, data: bytes, ts: int) -> None:
        if sem.spec.appendable is not None and delimited(data):
            # an appendable writer's sample (an RTI vehicle's, delimited XCDR2): republished as it was sent, by a writer
            # of the appendable copy, which the console's readers of that copy match (the final type would misread it)
            w = self.appendable_writer(sem)
        else:
            w = self.writer(sem)
            encapsulation = int.from_bytes(data[:2], "big")
            if encapsulation not in (PLAIN_CDR2 if sem.spec.xcdr2_only else PLAIN_CDR):
                data = sem.spec.type.deserialize(data).serialize(use_version_2=sem.spec.xcdr2_only)
                self.reencoded += 1
        data = data.ljust((len(data) + 3) & ~3, b"\0")
        ret = write_cdr(w, data, ts)
        if ret < 0:
            raise RuntimeError(f"write failed ({ret})")
        self.samples += 1

    def instance(self, event: dict[str, Any], ts: int) -> None:
        sem = self.topics.get(event["topic"])
        if sem is None:
            return
        raw = base64.b64decode(event["key"])
        if sem.spec.appendable is not None and delimited(raw):  # an appendable writer's instance (recorder.py)
            key, w = sem.spec.appendable.deserialize_key(raw), self.appendable_writer(sem)
        else:
            key, w = sem.spec.type.deserialize_key(raw), self.writer(sem)
        if event["state"] == "disposed":
            w.dispose(key, timestamp=ts)
            self.disposes += 1
        else:
            w.unregister_instance(key, timestamp=ts)
            self.unregisters += 1


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    logging.basicConfig(level=args.log_level.upper(), format="%(asctime)s %(name)s %(levelname)s %(message)s")
    problem = check_file(args.file)
    if problem:
        parser.error(problem)
    settings = from_environment("sem-replay", BusSettings)
    try:
        bus = Bus(args.domain, settings.dds_interface, settings.dds_peers, bus_security(args.dds_security, args.domain))
        replay = Replay(bus, args.file, args.speed, args.retime, args.commands)
        replay.make_writers()
    except DdsConfigError as e:
        print(f"sem-replay: {e}", file=sys.stderr)
        return 2

    def stop(_sig: int, _frame: Any) -> None:
        replay.stopping = True

    signal.signal(signal.SIGINT, stop)
    signal.signal(signal.SIGTERM, stop)
    if args.wait > 0 and not replay.wait_for_readers(args.wait):
        log.info("no reader of the SEM topics after %.1f s: replaying anyway", args.wait)
    started = time.monotonic()
    try:
        while not replay.stopping:
            replay.run_once()
            if not args.loop:
                break
    except (McapError, OSError, EOFError) as e:  # a file cut short: what came before it was replayed
        log.error("the recording ends early: %s", e)
    wait_for_acks([*replay.writers.values(), *replay.appendable_writers.values()], 5.0)
    log.info(
        "replayed %d samples, %d disposes, %d unregistrations from %s in %.1f s%s%s",
        replay.samples,
        replay.disposes,
        replay.unregisters,
        args.file,
        time.monotonic() - started,
        f"; {replay.reencoded} re-encoded for the writer's data representation" if replay.reencoded else "",
        f"; {replay.skipped} skipped" if replay.skipped else "",
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
