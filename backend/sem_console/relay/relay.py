"""One side of the link: the DDS domain's SEM traffic on Zenoh and back (docs/relay.md).

The vehicles' side sends every report, status and ack of both UMAA versions and writes the commands that come back;
the operations side writes the vehicles' samples into its domain and sends its consoles' commands, each to the relay
that owns its vehicle (relay/hops.py). Commands, statuses
and acks, their disposes and unregistrations included, are sent reliably at once, ahead of the reports (a higher Zenoh
priority, congestion control Block: never dropped, never conflated); reports go at their link class's caps (congestion
control Drop: a newer one follows), a report's dispose or unregistration reliably after its last sample."""

from __future__ import annotations

import hashlib
import json
import logging
import os
import threading
import time
import uuid
from collections import OrderedDict, defaultdict, deque
from dataclasses import dataclass
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from typing import Any, cast

import zenoh

from sem_console.dds import hops
from sem_console.dds.bus import Bus
from sem_console.dds.qos import TopicClass
from sem_console.dds.topics import AnySem, Sem, Sem60, delimited
from sem_console.relay.access import access_control
from sem_console.relay.domain import DomainSide, Taken
from sem_console.relay.hops import LIVELINESS, Carried, Hops, Origin
from sem_console.relay.link import (
    AT_ONCE_FIELDS,
    LINK_CLASSES,
    ON_CHANGE,
    Cap,
    Held,
    Limiter,
    SentLog,
    parse_caps,
    quiet_seconds,
    short_name,
)
from sem_console.relay.options import RelayOptions, endpoints, vehicle_relays
from sem_console.relay.wire import PREFIX, Address, Kind, attachment, key, parse_key, read_attachment

log = logging.getLogger("sem-relay")
TOPICS: dict[str, AnySem] = {s.spec.name: s for s in (*Sem, *Sem60)}  # every SEM topic of both UMAA versions
_URGENT = dict(priority=zenoh.Priority.INTERACTIVE_HIGH, congestion_control=zenoh.CongestionControl.BLOCK, express=True)
_REPORT = dict(priority=zenoh.Priority.DATA, congestion_control=zenoh.CongestionControl.DROP)
# a report's dispose or unregistration: reliable, but at the reports' priority, so it never overtakes their last sample
_REPORT_END = dict(priority=zenoh.Priority.DATA, congestion_control=zenoh.CongestionControl.BLOCK)
LOG_DEPTH = 64  # the messages of an instance kept to send again (a command has at most 5 statuses)
ENDED_KEPT_SECONDS = 600.0  # an ended instance's dispose or unregistration is sent again for this long
LOST_KEPT_SECONDS = 86400.0  # how long a lost relay of the other side is waited for (its ends kept to send again)
WAITING_DEPTH = 256  # the messages held per vehicle not heard yet: those of a vehicle of this domain are never sent
EARLY_VEHICLES = 1000  # the vehicles (and relays) whose samples are kept until a relay owns them
LOSS_MARGIN_SECONDS = 2.0  # beyond two leases: how long before a lost link was noticed what it carried may be lost
SEEN_KEPT = 100_000  # the messages received a receiver remembers, to write each once
TERMINAL = ("COMPLETED", "FAILED", "CANCELED")  # a command status's terminal states, by name in both UMAA versions


@dataclass
class Traffic:
    """What crossed the link for one vehicle: the key, payload and attachment bytes of each message."""

    sent_bytes: int = 0
    sent_messages: int = 0
    received_bytes: int = 0
    received_messages: int = 0


@dataclass(frozen=True)
class Incoming:
    """A message of the other side, to write into this domain."""

    address: Address
    sem: AnySem
    key_text: str
    extra: bytes  # the attachment
    meta: tuple[Kind, int]  # its kind and source timestamp
    payload: bytes


@dataclass(frozen=True)
class Outgoing:
    key: str
    payload: bytes
    attachment: bytes
    vehicle: uuid.UUID
    urgent: bool  # a command, status or ack: reliable, first
    report_end: bool = False  # a report's dispose or unregistration: reliable, after the report's samples
    instance: Any = None  # the instance on the sending domain
    ended: bool = False  # a dispose or unregistration
    session: bytes | None = None  # a command sample's sessionID


def decoded(sem: AnySem, data: bytes) -> Any:
    """A sample's CDR read as its type (an appendable writer's as the type's appendable copy)."""
    appendable = sem.spec.appendable if sem.spec.appendable is not None and delimited(data) else None
    return (appendable or sem.spec.type).deserialize(data)


def session_of(taken: Taken) -> bytes | None:
    """A command sample's sessionID (None: it cannot be read; the command goes all the same)."""
    try:
        return bytes(decoded(taken.sem, taken.data).sessionID)
    except Exception:
        return None


def zenoh_config(options: RelayOptions) -> zenoh.Config:
    config = zenoh.Config()
    config.insert_json5("mode", json.dumps("router" if options.router else "client"))
    config.insert_json5("scouting/multicast/enabled", "false")  # endpoints are configured, never discovered
    config.insert_json5("connect/endpoints", json.dumps(options.connect_endpoints))
    config.insert_json5("listen/endpoints", json.dumps(options.listen_endpoints))
    config.insert_json5("transport/link/tx/lease", str(round(options.lease_seconds * 1000)))
    if options.tls_root_ca is not None:
        tls = {"root_ca_certificate": str(options.tls_root_ca)}
        if options.tls_certificate is not None and options.tls_private_key is not None:
            tls |= {
                "enable_mtls": True,  # type: ignore[dict-item]  # (json5 values)
                "listen_certificate": str(options.tls_certificate),
                "listen_private_key": str(options.tls_private_key),
                "connect_certificate": str(options.tls_certificate),
                "connect_private_key": str(options.tls_private_key),
            }
        for name, value in tls.items():
            config.insert_json5(f"transport/link/tls/{name}", json.dumps(value))
    if options.access_controlled:
        acl = access_control(vehicle_relays(options.vehicle_relays), endpoints(options.operations_relays))
        config.insert_json5("access_control", json.dumps(acl))
    return config


class Relay:
    def __init__(self, options: RelayOptions, bus: Bus, session: zenoh.Session) -> None:
        self.options, self.bus, self.session = options, bus, session
        self.vehicles_side = options.side == "vehicles"
        self.caps = {**LINK_CLASSES[options.link_class], **parse_caps(options.caps)}
        # how long a vehicle of each UMAA version may be quiet over the link by the caps (its token says it)
        self.quiet = {
            version: quiet_seconds(self.caps, tuple(short_name(t.spec.name) for t in version if t.spec.cls is TopicClass.REPORT))
            for version in (Sem, Sem60)
        }
        self.limiter: Limiter[Outgoing] = Limiter(self.caps)
        self.traffic: dict[uuid.UUID, Traffic] = defaultdict(Traffic)
        self._lock = threading.Lock()  # the limiter, the traffic counts and the vehicles' domains
        # operations side: the commands for a vehicle no relay owns yet (relay/hops.py; sent once one does), and the
        # samples that came for it before its relay's token (written if that relay becomes its owner)
        self.held: Held[Taken] = Held(WAITING_DEPTH)
        self._early: dict[tuple[uuid.UUID, Origin], deque[Incoming]] = {}
        self._apply_lock = threading.Lock()  # the operations side's writes into its domain, in the order received
        self._refused: set[tuple[uuid.UUID, Origin]] = set()  # the other relays a vehicle's samples came through
        commands = [s for s in TOPICS.values() if s.spec.cls is TopicClass.COMMAND]
        others = [s for s in TOPICS.values() if s.spec.cls is not TopicClass.COMMAND]
        self.sends = others if self.vehicles_side else commands
        self.writes = {s.spec.name for s in (commands if self.vehicles_side else others)}
        self.dds = DomainSide(bus, self.sends, self._taken)
        self.started = time.monotonic()
        self.stopping = threading.Event()
        # A link that was down longer than the Zenoh lease lost what was under way: when a relay of the other side comes
        # (back), what this side sent is sent again, and the receiver writes only what it has not yet (`_seen`).
        self._sent: SentLog[Outgoing] = SentLog(LOG_DEPTH)
        self._seen: OrderedDict[bytes, None] = OrderedDict()
        self._resend_since: float | None = None  # send again what was sent since then (-inf: everything)
        self._peers: dict[str, float | None] = {}  # the other side's relays seen: when each was lost (None: there)
        self._was_connected, self._own_lost = False, cast(float | None, None)  # this session's link, and when it was lost last
        self._send_lock = threading.Lock()  # one message at a time on the link, in the order logged
        self._versions: set[type] = set()  # the UMAA versions (Sem, Sem60) whose topics this side writes already
        # the operations side: the commands (vehicle, sessionID) whose vehicle said they ended (a terminal status): never
        # sent again, so a vehicles' relay that restarts does not give a vehicle a finished command as if new
        self._finished: OrderedDict[tuple[uuid.UUID, bytes | None], None] = OrderedDict()
        other = "operations" if self.vehicles_side else "vehicles"
        self.peers = session.liveliness().declare_subscriber(f"{LIVELINESS}/{other}/**", self._peer, history=True)
        # which relay carries which vehicle, for the operations side's consoles (relay/hops.py)
        self.carried = Carried(session, options.name, bus.domain_id, options.vehicle_gone_seconds) if self.vehicles_side else None
        self.hops = None if self.vehicles_side else Hops(session, bus, self._owned)
        if self.hops is not None:
            self.hops.start()
        # the vehicles' side: the commands sent to its name (its key space) and domain (another relay of its name may
        # serve another domain); the operations side: every vehicle's samples
        watch = f"{PREFIX}/{options.name}/{bus.domain_id}/**" if self.vehicles_side else f"{PREFIX}/**"
        self.subscriber = session.declare_subscriber(watch, self._received)
        # the token last: the other side's relays send everything again the moment it comes, to this subscription
        self.token = session.liveliness().declare_token(f"{LIVELINESS}/{options.side}/{options.name}/{session.zid()}")
        self._timer = threading.Thread(target=self._tick, name="relay-timer", daemon=True)

    def start(self) -> None:
        self.dds.start()
        self._timer.start()

    # DDS -> Zenoh
    def _taken(self, taken: Taken) -> None:
        if not self.vehicles_side:
            # the lookup and the send in one step (`_send_lock`): a command, or its cancel, taken while its vehicle's
            # owner releases the ones held (`_owned`) goes after them, never before
            assert self.hops is not None
            with self._send_lock:
                origin = self.hops.owner_of(taken.vehicle)
                if origin is None:  # no relay owns the vehicle (yet): held until one does
                    with self._lock:
                        self.held.hold(taken.vehicle, taken.instance, taken, ends=taken.kind is not Kind.SAMPLE)
                    return
                self._send_locked(self._outgoing(taken, *origin))
            return
        assert self.carried is not None
        self.carried.saw(taken.vehicle, self.quiet[type(taken.sem)])
        out = self._outgoing(taken, self.options.name, self.bus.domain_id)
        if taken.sem.spec.cls is not TopicClass.REPORT:
            self._send(out)
            return
        topic = short_name(taken.sem.spec.name)
        with self._lock:
            if taken.kind is not Kind.SAMPLE:
                before = self.limiter.take(taken.instance)
                ready = [before, out] if before is not None else [out]
            else:
                fingerprint = self.fingerprint(taken, self.limiter.cap(topic))
                now = self.limiter.offer(topic, taken.instance, out, time.monotonic(), fingerprint)
                ready = [now] if now is not None else []
        for o in ready:
            self._send(o)

    @staticmethod
    def fingerprint(taken: Taken, cap: Cap) -> Any:
        """What the limiter compares of a report at this cap: on change, its content without its time stamp; at a cap
        in seconds, its AT_ONCE_FIELDS (None: nothing)."""
        fields = AT_ONCE_FIELDS.get(short_name(taken.sem.spec.name)) if cap != ON_CHANGE else None
        if cap != ON_CHANGE and (not cap or not fields):
            return None
        appendable = taken.sem.spec.appendable if taken.instance[1] else None
        sample = (appendable or taken.sem.spec.type).deserialize(taken.data)
        if fields:
            return repr({k: getattr(sample, k) for k in fields})
        return repr({k: v for k, v in vars(sample).items() if k not in ("timeStamp", "sample_info")})

    def _outgoing(self, taken: Taken, relay: str, domain: int) -> Outgoing:
        urgent = taken.sem.spec.cls is not TopicClass.REPORT
        ended = taken.kind is not Kind.SAMPLE
        command = taken.sem.spec.cls is TopicClass.COMMAND and not ended
        return Outgoing(
            key(relay, domain, taken.vehicle, taken.sem.spec.name),
            taken.data,
            attachment(taken.kind, taken.source_ns),
            taken.vehicle,
            urgent,
            report_end=not urgent and ended,
            instance=taken.instance,
            ended=ended,
            session=session_of(taken) if command else None,
        )

    def _peer(self, sample: zenoh.Sample) -> None:
        """A relay of the other side came or went. One new to this relay (started, or restarted: a new session) gets
        everything sent; one back after an outage, what was sent since two leases before the link's loss was noticed
        (its token went, or this relay's own session lost the router: `_watch_link`)."""
        peer, now = str(sample.key_expr), time.monotonic()
        with self._lock:
            if sample.kind != zenoh.SampleKind.PUT:
                self._peers[peer] = now
                return
            lost = self._peers.get(peer, float("-inf"))
            self._peers[peer] = None
            own, self._own_lost = self._own_lost, None  # a relay of the other side heard: this side's own link is up
            losses = [t for t in (lost, own) if t is not None]  # without its own loss: this side's own link was down
            if not losses:
                return
            lost = min(losses)
            since = self._resend_from(lost)
            self._resend_since = since if self._resend_since is None else min(self._resend_since, since)
        log.info("the other side's relay %s is there: sending again what it may have missed since %.1f s ago", peer, now - since)

    def _resend_from(self, lost: float) -> float:
        """Zenoh notices a silent link a lease or more after it went silent (up to two, with its keep-alive period and
        the link's delay): what was sent from two leases and a margin before the loss was noticed is sent again."""
        return lost - 2 * self.options.lease_seconds - LOSS_MARGIN_SECONDS

    def _forget_ended(self, now: float) -> None:
        """Forget the instances that ended ENDED_KEPT_SECONDS ago, but none a relay of the other side that is lost (or
        this relay's own lost link) is to be sent again: a cancel sent just before an outage longer than that still
        goes after it. A loss older than LOST_KEPT_SECONDS no longer counts (that relay is gone for good)."""
        with self._lock:
            losses = [t for t in (*self._peers.values(), self._own_lost) if t is not None and now - t < LOST_KEPT_SECONDS]
            self._sent.forget(min([now - ENDED_KEPT_SECONDS, *(self._resend_from(t) for t in losses)]))

    def _watch_link(self) -> None:
        """When this relay's session lost every router and peer it had (Zenoh closes a link silent for a lease)."""
        info = self.session.info
        connected = bool(list(info.routers_zid()) or list(info.peers_zid()))
        with self._lock:
            if connected:
                self._was_connected = True
            elif self._was_connected:
                self._was_connected, self._own_lost = False, time.monotonic()

    def _send_again(self, since: float) -> None:
        """What was sent since `since`: each instance's messages (an ended one's end only), in the order they were
        sent; no new message goes in between (`_send_lock`), so none overtakes one of its instance sent again."""
        with self._send_lock:
            with self._lock:
                again = [o for o in self._sent.since(since) if (o.vehicle, o.session) not in self._finished]
            for out in again:
                self._put(out)
        log.info("sent %d messages again", len(again))

    def _send(self, out: Outgoing) -> None:
        with self._send_lock:
            self._send_locked(out)

    def _send_locked(self, out: Outgoing) -> None:
        """`_send`, its caller holding `_send_lock`."""
        with self._lock:
            self._sent.add(out.instance, out, time.monotonic(), latest_only=not out.urgent, ends=out.ended)
        self._put(out)

    def _put(self, out: Outgoing) -> None:
        qos = _URGENT if out.urgent else _REPORT_END if out.report_end else _REPORT
        self.session.put(out.key, out.payload, attachment=out.attachment, **qos)
        with self._lock:
            t = self.traffic[out.vehicle]
            t.sent_bytes += len(out.key) + len(out.payload) + len(out.attachment)
            t.sent_messages += 1

    # Zenoh -> DDS
    def _received(self, sample: zenoh.Sample) -> None:
        key_text = str(sample.key_expr)
        address = parse_key(key_text)
        sem = TOPICS.get(address.topic) if address is not None else None
        extra = sample.attachment.to_bytes() if sample.attachment is not None else None
        meta = read_attachment(extra)
        if address is None or sem is None or meta is None or extra is None or sem.spec.name not in self.writes:
            return  # not for this side (its own messages come back too)
        incoming = Incoming(address, sem, key_text, extra, meta, sample.payload.to_bytes())
        if self.hops is None:  # the vehicles' side
            self._apply(incoming)
            return
        origin = (address.relay, address.domain)
        with self._apply_lock:
            owner = self.hops.owner_of(address.vehicle)
            with self._lock:
                early = self._early.get((address.vehicle, origin))
            # its relay's token not here yet (or two relays say they carry it): kept until one owns it; and kept behind
            # those kept before it while its owner, just decided, has not written them yet (`_owned`)
            if owner is None or (owner == origin and early is not None):
                with self._lock:
                    if early is None:
                        early = self._early[(address.vehicle, origin)] = deque(maxlen=WAITING_DEPTH)
                        if len(self._early) > EARLY_VEHICLES:  # ids no relay ever declares: the oldest given up
                            del self._early[next(iter(self._early))]
                    early.append(incoming)
            elif owner == origin:
                self.hops.heard_from(address.vehicle, time.monotonic())
                self._apply(incoming)
            elif (address.vehicle, origin) not in self._refused:  # another relay's vehicle: not written
                self._refused.add((address.vehicle, origin))
                log.warning(
                    "vehicle %s is carried by relay %s, domain %d: its samples through relay %s, domain %d are not written",
                    address.vehicle,
                    *owner,
                    *origin,
                )

    def _owned(self, vehicle: uuid.UUID, origin: Origin) -> None:
        """Operations side: a relay now owns `vehicle` (relay/hops.py): what it sent before its token came is written,
        and the commands held for the vehicle go to it, in one step (`_send_lock`), so that none taken meanwhile (a
        cancel) goes before them."""
        with self._send_lock, self._apply_lock:
            with self._lock:
                early = self._early.pop((vehicle, origin), ())
                for other in [k for k in self._early if k[0] == vehicle]:
                    del self._early[other]
                release = self.held.release(vehicle)
            if early:
                assert self.hops is not None
                self.hops.heard_from(vehicle, time.monotonic())
            for incoming in early:
                self._apply(incoming)
            for taken in release:
                self._send_locked(self._outgoing(taken, *origin))

    def _apply(self, incoming: Incoming) -> None:
        """A message of the other side written into this domain."""
        address, sem, kind = incoming.address, incoming.sem, incoming.meta[0]
        digest = hashlib.blake2b(incoming.key_text.encode() + incoming.extra + incoming.payload, digest_size=16).digest()
        with self._lock:
            if digest in self._seen:  # sent again after an outage, and written already
                return
            self._seen[digest] = None
            if len(self._seen) > SEEN_KEPT:
                self._seen.popitem(last=False)
            t = self.traffic[address.vehicle]
            t.received_bytes += len(incoming.key_text) + len(incoming.payload) + len(incoming.extra)
            t.received_messages += 1
        if type(sem) not in self._versions:  # the first sample of a UMAA version: every topic of it written from now on
            self._versions.add(type(sem))
            self.dds.open_writers([s for s in type(sem) if s.spec.name in self.writes])
        if sem.spec.cls is TopicClass.STATUS and kind is Kind.SAMPLE and self.hops is not None:
            self._note_finished(address.vehicle, sem, incoming.payload)
        try:
            self.dds.write(sem, kind, incoming.payload, incoming.meta[1])
        except Exception as e:  # one bad message costs only itself
            log.warning("could not write a %s of %s for vehicle %s: %s", kind.name.lower(), sem.spec.name, address.vehicle, e)

    def _note_finished(self, vehicle: uuid.UUID, sem: AnySem, payload: bytes) -> None:
        try:
            status = decoded(sem, payload)
            ended = getattr(status.commandStatus, "name", None) in TERMINAL
            session = bytes(status.sessionID)
        except Exception:  # a status this relay cannot read is written all the same; its command is sent again
            return
        if ended:
            with self._lock:
                self._finished[(vehicle, session)] = None
                if len(self._finished) > SEEN_KEPT:
                    self._finished.popitem(last=False)

    # the caps' slots and the link's status
    def _tick(self) -> None:
        next_stats = time.monotonic() + self.options.stats_seconds
        next_hops = time.monotonic()
        while not self.stopping.wait(0.1):
            if time.monotonic() >= next_hops:
                next_hops += hops.PERIOD
                if self.hops is not None:
                    self.hops.write()
                if self.carried is not None:
                    self.carried.forget(time.monotonic())
            with self._lock:
                due = self.limiter.due(time.monotonic())
            for out in due:
                self._send(out)
            self._watch_link()
            with self._lock:
                since, self._resend_since = self._resend_since, None
            if since is not None:
                self._send_again(since)
            if time.monotonic() >= next_stats:
                next_stats += self.options.stats_seconds
                self._forget_ended(time.monotonic())
                self.report()

    def status(self) -> dict[str, Any]:
        elapsed = max(time.monotonic() - self.started, 1e-6)
        with self._lock:
            vehicles = {
                str(v): {
                    "sentBytes": t.sent_bytes,
                    "sentMessages": t.sent_messages,
                    "sentBytesPerHour": round(t.sent_bytes * 3600 / elapsed),
                    "receivedBytes": t.received_bytes,
                    "receivedMessages": t.received_messages,
                    "receivedBytesPerHour": round(t.received_bytes * 3600 / elapsed),
                }
                for v, t in sorted(self.traffic.items())
            }
            return {
                "name": self.options.name,
                "side": self.options.side,
                "domain": self.bus.domain_id,
                "linkClass": self.options.link_class,
                "caps": self.caps,
                "seconds": round(elapsed, 1),
                "conflated": self.limiter.conflated,
                "unchanged": self.limiter.unchanged,
                "waitingCommands": len(self.held),
                "vehicles": vehicles,
            }

    def report(self) -> None:
        status = self.status()
        for vehicle, t in status["vehicles"].items():
            log.info(
                "link: vehicle %s: sent %d B in %d messages (%d B/h), received %d B in %d messages (%d B/h)",
                vehicle,
                t["sentBytes"],
                t["sentMessages"],
                t["sentBytesPerHour"],
                t["receivedBytes"],
                t["receivedMessages"],
                t["receivedBytesPerHour"],
            )
        if self.options.status_file is not None:
            write_json(self.options.status_file, status)

    def close(self) -> None:
        self.stopping.set()
        if self._timer.is_alive():
            self._timer.join(timeout=2)
        self.dds.stop()
        self.subscriber.undeclare()
        self.peers.undeclare()
        self.token.undeclare()
        if self.carried is not None:
            self.carried.close()
        if self.hops is not None:
            self.hops.close()


def serve_status(relay: Relay, port: int) -> ThreadingHTTPServer:
    """GET /status on 127.0.0.1:`port`: `Relay.status()` as JSON, in a thread of its own (OSError: the port is taken)."""

    class Handler(BaseHTTPRequestHandler):
        def do_GET(self) -> None:
            found = self.path.split("?", 1)[0] == "/status"
            body = json.dumps(relay.status() if found else {"detail": "GET /status"}).encode()
            self.send_response(200 if found else 404)
            self.send_header("Content-Type", "application/json")
            self.send_header("Content-Length", str(len(body)))
            self.end_headers()
            self.wfile.write(body)

        def log_message(self, format: str, *args: Any) -> None:
            pass  # not a line per request in the relay's log

    server = ThreadingHTTPServer(("127.0.0.1", port), Handler)
    threading.Thread(target=server.serve_forever, name="relay-status", daemon=True).start()
    return server


def write_json(path: Path, data: Any) -> None:
    """Written whole or not at all: a reader never sees half a file."""
    tmp = path.with_name(path.name + ".tmp")
    try:
        tmp.write_text(json.dumps(data, indent=1))
        os.replace(tmp, path)
    except OSError as e:
        log.warning("could not write the status file %s: %s", path, e)
