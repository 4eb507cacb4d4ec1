"""Requests from other sites refused, in one place: an ASGI middleware in front of every route.

- **Host**: the Host header must name one of `Settings.host_names()` (any route, /ws too): a page
  whose DNS name is rebound to 127.0.0.1 reaches the port but sends its own name.
- **Origin**: a state-changing request (any method but GET, HEAD, OPTIONS) and every /ws handshake
  must come from the console's own origin (scheme and Host of the request) or an allowed origin.
  Without an Origin header, `Sec-Fetch-Site` must be same-origin or none where a browser sent it;
  a request with neither is not from a browser page (curl, scripts) and passes.
- **Content type** (`require_json`, a dependency of the command routes): every POST and PUT must say
  `Content-Type: application/json`: a page can send a cross-site "simple" request (one without
  a CORS preflight) only as text/plain, form or multipart, never as JSON.

A refused request gets a 403 (415 for the content type) with a `detail` (/ws: a bare 403), a log line and, for
a command request, an entry in the audit trail (both bounded: see api/audit.py).
"""

from __future__ import annotations

import ipaddress
import json
import re
from email.message import Message

from fastapi import HTTPException, Request
from starlette.datastructures import Headers
from starlette.types import ASGIApp, Receive, Scope, Send

from sem_console.api import audit
from sem_console.api.audit import clip
from sem_console.core.config import Settings

SAFE_METHODS = frozenset({"GET", "HEAD", "OPTIONS"})


HOST = re.compile(r"(?P<name>\[[0-9a-f:.]+\]|[a-z0-9_-]+(?:\.[a-z0-9_-]+)*\.?)(?::[0-9]{1,5})?")


def host_name(host: str) -> str | None:
    """The name part of a Host header (host[:port], an IPv6 address in brackets), lower case:
    'Example.org:8000' -> 'example.org', '[::1]:80' -> '[::1]'; None for anything else
    ('localhost:8123@evil.example', a bare IPv6 address, spaces, userinfo, a path)."""
    m = HOST.fullmatch(host.strip().lower())
    if m is None:
        return None
    name = m["name"]
    if name.startswith("["):
        try:
            ipaddress.IPv6Address(name[1:-1])
        except ValueError:
            return None
    return name


def is_json(content_type: str | None) -> bool:
    if not content_type:
        return False
    m = Message()
    m["content-type"] = content_type
    return m.get_content_type() == "application/json" or (
        m.get_content_maintype() == "application" and m.get_content_subtype().endswith("+json")
    )


class Guard:
    def __init__(self, app: ASGIApp, settings: Settings) -> None:
        self.app = app
        self.hosts = settings.host_names()
        self.origins = settings.origins()

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] not in ("http", "websocket"):
            await self.app(scope, receive, send)
            return
        refusal = self.refusal(scope, Headers(scope=scope))
        if refusal is None:
            await self.app(scope, receive, send)
            return
        status, reason = refusal
        audit.auditor(scope).refused(scope, status, reason)  # recorded when it is a command request
        await refuse(scope, send, status, reason)

    def refusal(self, scope: Scope, headers: Headers) -> tuple[int, str] | None:
        host = headers.get("host")
        if not host:
            return 403, "no Host header"
        name = host_name(host)
        if name is None:
            return 403, f"host {clip(host)} is not a host name with an optional port"
        if "*" not in self.hosts and name not in self.hosts:
            return 403, f"host {clip(name)} is not allowed (--allowed-hosts)"
        websocket = scope["type"] == "websocket"
        method = scope.get("method", "GET")
        if not websocket and method in SAFE_METHODS:
            return None
        origin = headers.get("origin")
        if origin is not None:
            own = f"{'https' if scope.get('scheme') in ('https', 'wss') else 'http'}://{host.strip().lower()}"
            if origin.strip().rstrip("/").lower() not in self.origins | {own}:
                return 403, f"origin {clip(origin)} is not allowed (the console's own is {clip(own)}; --allowed-origins)"
        elif headers.get("sec-fetch-site", "same-origin") not in ("same-origin", "none"):
            return 403, f"a {clip(headers['sec-fetch-site'])} request without Origin is not allowed"
        return None


async def require_json(request: Request) -> None:
    """Dependency of the command routes: a POST or PUT must say Content-Type: application/json (checked
    after routing, so a POST to a route that has none is still a 405)."""
    if request.method in ("POST", "PUT") and not is_json(request.headers.get("content-type")):
        raise HTTPException(415, f"a {request.method} needs Content-Type: application/json and a JSON body (e.g. {{}})")


async def refuse(scope: Scope, send: Send, status: int, detail: str) -> None:
    """A JSON error response; a WebSocket handshake is closed before accept, which uvicorn answers
    with a plain 403 (its denial-response path logs a spurious error in uvicorn 0.54)."""
    if scope["type"] == "websocket":
        await send({"type": "websocket.close", "code": 1008})
        return
    body = json.dumps({"detail": detail}).encode()
    headers = [(b"content-type", b"application/json"), (b"content-length", str(len(body)).encode())]
    await send({"type": "http.response.start", "status": status, "headers": headers})
    await send({"type": "http.response.body", "body": body})
