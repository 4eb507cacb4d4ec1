"""A wss:// client connection whose opening handshake cannot hang the test.

websockets' sync client (17.4) reads in a thread that waits on select() and then calls a blocking recv(). Over TLS 1.3
the server's session tickets make the socket readable before any HTTP response; the TLS read then blocks for the
response. When the handshake times out, the client closes its socket and joins that thread, which a close does not
wake: the join waits for ever (a CI run hung here until pytest-timeout, 120 s). A shutdown() of the socket does wake
it, so a timer shuts a duplicate of the socket down shortly after the handshake's own deadline."""

from __future__ import annotations

import contextlib
import socket
import ssl
import threading
from typing import Any
from urllib.parse import urlsplit

from websockets.sync.client import ClientConnection, connect


def _shutdown(guard: socket.socket) -> None:
    with contextlib.suppress(OSError):  # already closed
        guard.shutdown(socket.SHUT_RDWR)


def connect_tls(url: str, context: ssl.SSLContext, open_timeout: float, **kwargs: Any) -> ClientConnection:
    parts = urlsplit(url)
    raw = socket.create_connection((parts.hostname or "127.0.0.1", parts.port or 443), timeout=open_timeout)
    guard = raw.dup()  # the same socket under a second descriptor: the TLS layer takes over `raw`
    timer = threading.Timer(open_timeout + 1, _shutdown, (guard,))
    timer.start()
    try:
        return connect(url, sock=raw, ssl=context, open_timeout=open_timeout, **kwargs)
    finally:
        timer.cancel()
        guard.close()
