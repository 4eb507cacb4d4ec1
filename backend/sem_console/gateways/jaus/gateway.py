"""The JAUS gateway: one JAUS component per UMAA vehicle, answering QueryNavigation and
QueryCommsLostConfiguration over JUDP from what the console's feed says.

A vehicle is component S.1.C, C being its order of appearance on the bus (the console's `jausId`).
Malformed input (short, wrong size or version, a body of the wrong length, a component we do not have) is counted by
reason and dropped; a well-formed message we do not answer (QueryIdentification, QueryServices ...) is counted as
unsupported, not as malformed; nothing a peer sends raises.
"""

from __future__ import annotations

import asyncio
import math
import struct
import time
import uuid
from collections.abc import Mapping
from typing import Any

from sem_console.console.feed import Feed
from sem_console.core.messages import GatewayState
from sem_console.gateways import Stats
from sem_console.gateways.jaus import judp
from sem_console.gateways.jaus.judp import JausId, Malformed

NODE = 1
QUERY_NAVIGATION_BODY = struct.Struct("<HHHH")  # presence vectors: global pose, local pose, velocity state, acceleration state


def _finite(v: Any) -> float | None:
    return float(v) if isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) else None


def _valid(envelope: dict[str, Any], path: str) -> float | None:
    if any(x.startswith(f"{path}:") for x in envelope.get("invalid", [])):
        return None
    v: Any = envelope.get("report")
    for part in path.split("."):
        v = v.get(part) if isinstance(v, dict) else None
    return _finite(v)


def _angle(v: float | None) -> float | None:
    """An angle into JAUS's [-pi, pi] (UMAA's course is 0..2pi)."""
    return None if v is None else (v + math.pi) % (2 * math.pi) - math.pi


def navigation_values(
    fix: dict[str, Any] | None,
) -> tuple[dict[str, float], dict[str, float], dict[str, float], tuple[int, int] | None]:
    """(global pose, NED velocity, velocity state) values and the report's time from a GPSFixReport envelope."""
    if fix is None:
        return {}, {}, {}, None
    seconds, nanos = _valid(fix, "timeStamp.seconds"), _valid(fix, "timeStamp.nanoseconds")
    stamp = (int(seconds), int(nanos)) if seconds is not None and nanos is not None else None
    times = {"TimeSeconds": stamp[0], "TimeNanoSeconds": stamp[1]} if stamp else {}
    pose: dict[str, float] = {}
    if fix["report"].get("GPSLatLongValid") is True:
        lat = _valid(fix, "position2DWithTime.geodeticPosition.geodeticLatitude.latitude")
        lon = _valid(fix, "position2DWithTime.geodeticPosition.geodeticLongitude.longitude")
        if lat is not None and lon is not None:
            pose.update(Latitude=lat, Longitude=lon)
    for name, path in (
        ("AltitudeMSL", "altitudeMSL.altitude"),
        ("AltitudeAGL", "altitudeAGL"),
        ("AltitudeASF", "altitudeASF"),
        ("Depth", "depth"),
    ):
        if (v := _valid(fix, path)) is not None:
            pose[name] = v
    for name, path in (
        ("Roll", "attitude.roll.roll"),
        ("Pitch", "attitude.pitch.pitch"),
        ("Heading", "attitude.yaw.yaw"),
        ("Course", "trueCourse"),
    ):
        if (angle := _angle(_valid(fix, path))) is not None:
            pose[name] = angle
    # the horizontal position error (DRMS) from the position's covariance, when the vehicle reports it
    north, east = _valid(fix, "positionCovariance.pnPn"), _valid(fix, "positionCovariance.pePe")
    if north is not None and east is not None and north >= 0 and east >= 0:
        pose["XYPositionRMS"] = math.sqrt(north + east)
    pose.update(times)
    ned = {
        k: v
        for k, v in (
            ("Velocity_N", _valid(fix, "velocity.northSpeed")),
            ("Velocity_E", _valid(fix, "velocity.eastSpeed")),
            ("Velocity_D", _valid(fix, "velocity.downSpeed")),
        )
        if v is not None
    }
    state: dict[str, float] = {}
    if (sog := _valid(fix, "SOG")) is not None:
        state["SpeedOverGround"] = sog
    state.update(times)
    return pose, ned, state, stamp


def report_navigation(fix: dict[str, Any] | None, asked: tuple[int, int, int, int], now: float) -> tuple[bytes, bool]:
    """ReportNavigation 0x4421's body: SyncTimeRec, global pose, local pose, velocity (VelocityVar with the
    NED record, then the velocity state record), acceleration; each record holds what was asked for and the
    vehicle has. The NED record comes whenever any velocity-state field is asked for.
    SyncTimeRec is the report's time, or `now` when there is none or it does not fit u32 (negative seconds,
    after 2106, nanoseconds out of range): never a wrapped, plausible-looking wrong time. The second value
    is True when the report's time was there but did not fit."""
    pose, ned, state, stamp = navigation_values(fix)
    unfit = stamp is not None and not (0 <= stamp[0] <= 0xFFFFFFFF and 0 <= stamp[1] <= 999_999_999)
    if stamp is None or unfit:
        stamp = (int(now), int(now % 1 * 1e9))
    g, local, velocity, acceleration = asked
    return (
        struct.pack("<II", stamp[0], stamp[1])
        + judp.record(judp.GLOBAL_POSE, g, pose)
        + judp.record(judp.LOCAL_POSE, local, {})
        + struct.pack("<B", judp.VELOCITY_NED_TAG)
        + judp.record(judp.VELOCITY_NED, 0xFF if velocity else 0, ned)
        + judp.record(judp.VELOCITY_STATE, velocity, state)
        + judp.record(judp.ACCELERATION_STATE, acceleration, {})
    ), unfit


def report_comms_lost_configuration(config: dict[str, Any]) -> bytes:
    """ReportCommsLostConfiguration 0x4C03's body: CommsLostTimeout u16 s, the policy variant (tag u8, then its
    StopMission or ContinueMission u8, 1), CommsRegainedTimeout u16 s, CommsRegainedBehavior u8. Seconds
    are rounded up to whole seconds (the spec lets an implementation round up to what it supports)."""

    def seconds(v: Any) -> int:
        return min(65535, math.ceil(float(v)))

    return struct.pack(
        "<HBBHB",
        seconds(config["commsLostTimeout"]),
        judp.COMMS_LOST_POLICIES[config["policy"]],
        1,
        seconds(config["regainedTime"]),
        int(config["regainedBehavior"]) & 0xFF,
    )


class Unsupported(Exception):
    """A well-formed message of a kind the gateway does not answer (a legal JAUS message, not a malformed one)."""


class JausGateway(asyncio.DatagramProtocol):
    def __init__(self, feed: Feed, port: int | None, subsystem: int, host: str = "127.0.0.1") -> None:
        self.port, self.subsystem, self.host = port, subsystem, host
        self.stats = Stats("jaus", port is not None)
        self.vehicles: dict[int, uuid.UUID] = {}  # component -> vehicle
        self.configs: dict[uuid.UUID, dict[str, Any]] = {}
        self.fixes: dict[uuid.UUID, dict[str, Any]] = {}  # the latest GPSFixReport envelope
        self.transport: asyncio.DatagramTransport | None = None
        self.sequence = 0
        self._unsubscribe = feed.subscribe("jaus", self.on_message) if port is not None else None

    async def start(self) -> None:
        if self.port is None:
            return
        loop = asyncio.get_running_loop()
        self.stats.endpoint = f"udp://{self.host}:{self.port} subsystem {self.subsystem}"
        try:
            self.transport, _ = await loop.create_datagram_endpoint(lambda: self, local_addr=(self.host, self.port))
        except OSError as e:  # shown as the gateway's last error; the console runs on without it
            self.stats.error(f"cannot listen on UDP {self.host}:{self.port}: {e.strerror or e}")
            return
        bound = self.transport.get_extra_info("sockname")
        self.stats.endpoint = f"udp://{self.host}:{bound[1]} subsystem {self.subsystem}"

    def close(self) -> None:
        if self._unsubscribe:
            self._unsubscribe()
        if self.transport is not None:
            self.transport.close()

    def state(self) -> GatewayState:
        return self.stats.state()

    # ---- the console's feed --------------------------------------------------------
    def on_message(self, message: Mapping[str, Any]) -> None:
        kind = message.get("type")
        if kind == "provider":
            p = message["provider"]
            vehicle = uuid.UUID(p["id"])
            if p.get("jausId"):
                self.vehicles[int(p["jausId"].rsplit(".", 1)[1])] = vehicle
            self.configs[vehicle] = p["linkConfig"]
        elif kind == "report" and message.get("topic") == "GPSFixReport":
            self.fixes[uuid.UUID(message["providerId"])] = message["report"]

    # ---- JUDP ------------------------------------------------------------------------
    def datagram_received(self, data: bytes, addr: Any) -> None:
        """Each message of the datagram is answered in a datagram of its own; a malformed datagram (its framing) is
        counted once and nothing in it answered, a malformed message (e.g. for no such component) once each."""
        self.stats.count("received")
        try:
            packets = judp.parse(data)
        except Malformed as e:
            self._malformed(e)
            return
        for p in packets:
            try:
                reply = self.answer(p)
            except Unsupported:
                self.stats.count("unsupported message id")
                continue
            except Malformed as e:
                self._malformed(e)
                continue
            except Exception as e:  # a bug here must not stop the gateway
                self.stats.error(f"could not answer a datagram from {addr[0]}: {e!r}")
                continue
            if self.transport is not None:
                self.transport.sendto(reply, addr)
                self.stats.sent()

    def _malformed(self, e: Malformed) -> None:
        self.stats.count("malformed")
        self.stats.count(f"malformed: {e}")

    def error_received(self, exc: Exception) -> None:
        self.stats.error(f"UDP: {exc}")

    def answer(self, p: judp.Packet) -> bytes:
        me = p.destination
        if me.subsystem != self.subsystem or me.node != NODE or me.component not in self.vehicles:
            raise Malformed("no such component")
        vehicle = self.vehicles[me.component]
        if p.message_id == judp.QUERY_NAVIGATION:
            if len(p.body) != QUERY_NAVIGATION_BODY.size:
                raise Malformed("wrong body size")
            asked = QUERY_NAVIGATION_BODY.unpack(p.body)
            body, unfit = report_navigation(self.fixes.get(vehicle), asked, time.time())
            message_id = judp.REPORT_NAVIGATION
            if unfit:
                self.stats.count("report time outside u32: console time sent")
        elif p.message_id == judp.QUERY_COMMS_LOST_CONFIGURATION:
            if p.body:
                raise Malformed("wrong body size")
            message_id, body = judp.REPORT_COMMS_LOST_CONFIGURATION, report_comms_lost_configuration(self.configs[vehicle])
        else:
            raise Unsupported(f"message id 0x{p.message_id:04X}")
        self.sequence = (self.sequence + 1) & 0xFFFF
        return judp.packet(p.flags & 0x03, p.source, JausId(self.subsystem, NODE, me.component), message_id, body, self.sequence)
