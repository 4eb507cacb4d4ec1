"""The tests' wss:// helper gives up at its deadline against a server that never answers the upgrade, where the
websockets client alone waits for ever (see support/wss.py)."""

from __future__ import annotations

import socket
import ssl
import threading
import time
from pathlib import Path

import pytest

from support.certs import Authority
from support.wss import connect_tls


def test_a_tls_server_that_never_answers_the_upgrade_times_out(tmp_path: Path) -> None:
    ca = Authority(tmp_path, "ca")
    cert, key = ca.issue("server")
    server_context = ssl.SSLContext(ssl.PROTOCOL_TLS_SERVER)
    server_context.load_cert_chain(cert, key)
    held: list[socket.socket] = []
    with socket.create_server(("127.0.0.1", 0)) as listener:

        def accept() -> None:
            conn, _ = listener.accept()
            held.append(server_context.wrap_socket(conn, server_side=True))  # TLS 1.3, then silence

        threading.Thread(target=accept, daemon=True).start()
        start = time.monotonic()
        with pytest.raises(TimeoutError):
            connect_tls(f"wss://127.0.0.1:{listener.getsockname()[1]}/ws", ssl.create_default_context(cafile=ca.pem), 0.5)
        assert time.monotonic() - start < 10
    for s in held:
        s.close()
