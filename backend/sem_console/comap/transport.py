"""IMC over UDP: one endpoint (sans I/O: counts and decodes datagrams, makes packets) and the
asyncio protocol the console listens with. The simulator polls a plain socket with the same endpoint."""

from __future__ import annotations

import asyncio
import logging
import socket
from collections import Counter
from collections.abc import Callable
from typing import Any

from sem_console.comap.codec import BROADCAST, Header, ImcError, Message, decode_packet, encode_packet

log = logging.getLogger("sem-console.imc")
Addr = tuple[str, int]
BAD_KINDS = ("truncated", "bad_sync", "bad_size", "bad_crc", "unknown_id", "bad_message")


class Endpoint:
    """What one IMC system (id `imc_id`) receives and sends; every bad datagram is counted, none raises."""

    def __init__(self, imc_id: int, peers: list[Addr]) -> None:
        self.imc_id, self.peers = imc_id, list(peers)
        self.counters: Counter[str] = Counter(
            {k: 0 for k in ("received", "accepted", "sent", "sendErrors", "notForUs", *BAD_KINDS)}
        )
        self.addresses: dict[int, Addr] = {}  # IMC system id -> where its datagrams came from

    def feed(self, data: bytes, addr: Addr, ours: Callable[[int], bool] | None = None) -> tuple[Header, Message] | None:
        self.counters["received"] += 1
        try:
            header, m = decode_packet(data)
        except ImcError as e:
            self.counters[e.kind] += 1
            log.debug("dropped an IMC datagram from %s: %s", addr, e)
            return None
        except Exception:  # a codec bug must not stop the endpoint: counted as a bad message
            self.counters["bad_message"] += 1
            log.exception("could not decode an IMC datagram from %s", addr)
            return None
        if header.dst != BROADCAST and not (ours(header.dst) if ours else header.dst == self.imc_id):
            self.counters["notForUs"] += 1
            return None
        self.addresses[header.src] = addr
        self.counters["accepted"] += 1
        return header, m

    def targets(self, dst: int) -> list[Addr]:
        """Every peer, and where dst last spoke from (IMC routes by the header's dst)."""
        out = list(self.peers)
        if dst != BROADCAST and dst in self.addresses and self.addresses[dst] not in out:
            out.append(self.addresses[dst])
        return out

    def packets(self, m: Message, dst: int = BROADCAST, src: int | None = None) -> tuple[bytes, list[Addr]]:
        return encode_packet(m, self.imc_id if src is None else src, dst), self.targets(dst)


class _Protocol(asyncio.DatagramProtocol):
    def __init__(self, on_datagram: Callable[[bytes, Addr], None]) -> None:
        self.on_datagram = on_datagram

    def datagram_received(self, data: bytes, addr: tuple[str | Any, int]) -> None:  # asyncio's signature
        self.on_datagram(data, (addr[0], addr[1]))

    def error_received(self, exc: Exception) -> None:  # e.g. ICMP port unreachable from a peer that is down
        log.debug("IMC socket: %s", exc)


class AsyncNode:
    """The console's IMC node on the event loop."""

    def __init__(self, endpoint: Endpoint, on_message: Callable[[Header, Message, Addr], None]) -> None:
        self.endpoint, self.on_message = endpoint, on_message
        self.transport: asyncio.DatagramTransport | None = None

    async def open(self, host: str, port: int) -> None:
        loop = asyncio.get_running_loop()
        self.transport, _ = await loop.create_datagram_endpoint(
            lambda: _Protocol(self._datagram), local_addr=(host, port), family=socket.AF_INET
        )

    def _datagram(self, data: bytes, addr: Addr) -> None:
        got = self.endpoint.feed(data, addr)
        if got is not None:
            try:
                self.on_message(got[0], got[1], addr)
            except Exception:  # one message the C2 cannot apply must not stop the node
                self.endpoint.counters["applyErrors"] += 1
                log.exception("could not apply an IMC %s", got[1].name)

    def send(self, m: Message, dst: int = BROADCAST) -> int:
        """Send m to dst through every peer; the number of datagrams sent."""
        data, targets = self.endpoint.packets(m, dst)
        sent = 0
        for addr in targets:
            try:
                if self.transport is not None:
                    self.transport.sendto(data, addr)
                    sent += 1
            except (OSError, ValueError) as e:  # ValueError: uvloop's for an address it cannot send to as given
                self.endpoint.counters["sendErrors"] += 1
                log.warning("could not send IMC %s to %s: %s", m.name, addr, e)
        self.endpoint.counters["sent"] += sent
        return sent

    def close(self) -> None:
        if self.transport is not None:
            self.transport.close()
            self.transport = None


class SocketNode:
    """A non-blocking UDP socket polled from a thread's loop (the simulator)."""

    def __init__(self, endpoint: Endpoint, host: str, port: int) -> None:
        self.endpoint = endpoint
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.sock.bind((host, port))
        self.sock.setblocking(False)

    def poll(self, ours: Callable[[int], bool], limit: int = 256) -> list[tuple[Header, Message, Addr]]:
        out = []
        for _ in range(limit):
            try:
                data, addr = self.sock.recvfrom(65535)
            except (BlockingIOError, InterruptedError):
                break
            except OSError:  # e.g. ICMP port unreachable reported on this socket
                continue
            got = self.endpoint.feed(data, (addr[0], addr[1]), ours)
            if got is not None:
                out.append((got[0], got[1], (addr[0], addr[1])))
        return out

    def send(self, m: Message, src: int, dst: int = BROADCAST) -> None:
        data, targets = self.endpoint.packets(m, dst, src)
        for addr in targets:
            try:
                self.sock.sendto(data, addr)
                self.endpoint.counters["sent"] += 1
            except OSError:
                self.endpoint.counters["sendErrors"] += 1

    def close(self) -> None:
        self.sock.close()
