"""A user-space link impairment for the tests (this machine's kernel has no netem): a TCP proxy that delays each
direction by half the round trip, limits its rate, and can go silent for an outage (bytes held, connections kept, as a
satellite link's fade). Loss is modelled as TCP shows it: a lost segment comes a retransmission timeout (at least 200 ms
over the round trip, as Linux's) after it would have, held by an outage or the rate or not, and what follows it on its
connection waits behind it; loss on UDP is not modelled here."""

from __future__ import annotations

import contextlib
import socket
import threading
import time
from collections import deque

MSS = 1460  # bytes of a TCP segment on an Ethernet path


class Impairment:
    """Listens on 127.0.0.1:`port` (a free one), forwards each connection to `upstream`."""

    def __init__(self, upstream: tuple[str, int], rtt: float = 0.0, rate_bytes: float = 0.0, loss: float = 0.0) -> None:
        """`loss`: the share of TCP segments (MSS bytes each) lost, every 1/loss-th one, so a test's run is the same
        each time; each costs its chunk a retransmission timeout."""
        self.upstream, self.delay, self.rate, self.loss = upstream, rtt / 2, rate_bytes, loss
        self.retransmission = rtt + 0.2
        self.bytes = 0  # forwarded in both directions
        self.segments = 0  # forwarded in both directions
        self.lost = 0  # segments lost (and sent again)
        self._count = threading.Lock()
        self._outage_until = 0.0
        self._stop = threading.Event()
        self._server = socket.create_server(("127.0.0.1", 0))
        self.port = int(self._server.getsockname()[1])
        self._sockets: list[socket.socket] = [self._server]
        threading.Thread(target=self._accept, daemon=True).start()

    @property
    def endpoint(self) -> str:
        return f"tcp/127.0.0.1:{self.port}"

    def outage(self, seconds: float) -> None:
        """Nothing crosses for `seconds` from now (what was sent waits, in order)."""
        self._outage_until = time.monotonic() + seconds

    def _accept(self) -> None:
        while not self._stop.is_set():
            try:
                client, _ = self._server.accept()
            except OSError:
                return
            try:
                server = socket.create_connection(self.upstream)
            except OSError:  # the far end is not up yet: the client tries again
                client.close()
                continue
            self._sockets += [client, server]
            for a, b in ((client, server), (server, client)):
                queue: deque[tuple[float, bytes]] = deque()
                ready = threading.Condition()
                threading.Thread(target=self._read, args=(a, queue, ready), daemon=True).start()
                threading.Thread(target=self._write, args=(b, queue, ready), daemon=True).start()

    def _read(self, src: socket.socket, queue: deque[tuple[float, bytes]], ready: threading.Condition) -> None:
        while not self._stop.is_set():
            try:
                data = src.recv(65536)
            except OSError:
                data = b""
            with ready:
                queue.append((time.monotonic(), data))
                ready.notify()
            if not data:
                return

    def _write(self, dst: socket.socket, queue: deque[tuple[float, bytes]], ready: threading.Condition) -> None:
        while not self._stop.is_set():
            with ready:
                while not queue:
                    ready.wait(0.1)
                    if self._stop.is_set():
                        return
                arrived, data = queue.popleft()
            lost, due = self._loses(data), arrived + self.delay
            while True:
                while (wait := max(due, self._outage_until) - time.monotonic()) > 0:
                    time.sleep(min(wait, 0.05))
                if not lost:
                    break
                lost, due = False, time.monotonic() + self.retransmission  # a timeout after it would have come
            if not data:
                dst.close()
                return
            try:
                dst.sendall(data)
            except OSError:
                return
            self.bytes += len(data)
            if self.rate:
                time.sleep(len(data) / self.rate)

    def _loses(self, data: bytes) -> bool:
        """Whether a segment of this chunk is lost (the chunk's segments counted with every direction's before it)."""
        with self._count:
            before = self.segments
            self.segments += -(-len(data) // MSS)
            lost = int(self.segments * self.loss) - int(before * self.loss)
            self.lost += lost
        return lost > 0

    def close(self) -> None:
        self._stop.set()
        for s in self._sockets:
            with contextlib.suppress(OSError):  # wakes the threads blocked in accept() and recv() on it
                s.shutdown(socket.SHUT_RDWR)
            s.close()
