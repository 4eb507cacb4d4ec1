"""Operator tokens: compared in constant time, bad ones slowed down per client.

After `FREE_FAILURES` bad tokens in a row from one client (its IP address), every request of that
client that carries or needs a token is answered 429 with `Retry-After` for 1 s, then 2, 4, ...
up to `MAX_DELAY` s after each further bad token; a good token clears the count, and a client
quiet for `FORGET_AFTER` s starts afresh.
"""

from __future__ import annotations

import base64
import binascii
import hmac
import math
import time
from collections import OrderedDict
from dataclasses import dataclass

FREE_FAILURES = 5
MAX_DELAY = 60.0
FORGET_AFTER = 900.0
MAX_CLIENTS = 10_000
WS_PROTOCOL = "sem-console"
WS_TOKEN_PREFIX = "bearer."


@dataclass
class _Client:
    failures: int = 0
    blocked_until: float = 0.0
    last: float = 0.0


class Throttle:
    def __init__(self) -> None:
        self.clients: OrderedDict[str, _Client] = OrderedDict()

    def retry_after(self, client: str, now: float) -> float:
        """Seconds this client must wait before its token is looked at again (0: go ahead)."""
        c = self.clients.get(client)
        if c is None:
            return 0.0
        if now - c.last > FORGET_AFTER:
            del self.clients[client]
            return 0.0
        return max(0.0, c.blocked_until - now)

    def failed(self, client: str, now: float) -> None:
        c = self.clients.pop(client, None) or _Client()
        c.failures, c.last = c.failures + 1, now
        if c.failures >= FREE_FAILURES:
            c.blocked_until = now + min(MAX_DELAY, 2.0 ** (c.failures - FREE_FAILURES))
        self.clients[client] = c  # most recent last
        while len(self.clients) > MAX_CLIENTS:
            self.clients.popitem(last=False)

    def succeeded(self, client: str) -> None:
        self.clients.pop(client, None)


class AuthError(Exception):
    """`audit`: a wrong token or the slow-down (recorded in the audit on any route), not a missing token."""

    def __init__(self, status: int, detail: str, retry_after: int | None = None, audit: bool = True) -> None:
        super().__init__(detail)
        self.status, self.detail, self.retry_after, self.audit = status, detail, retry_after, audit


class Operators:
    """The configured tokens and who they belong to, and the throttle of bad ones."""

    def __init__(self, tokens: dict[str, str]) -> None:
        self.tokens = [(t.encode(), name) for t, name in tokens.items()]
        self.throttle = Throttle()

    def __bool__(self) -> bool:
        return bool(self.tokens)

    def lookup(self, token: str) -> str | None:
        """The operator of `token`: every configured token is compared, each in constant time."""
        given, found = token.encode(), None
        for t, name in self.tokens:
            if hmac.compare_digest(given, t):
                found = name
        return found

    def authenticate(self, client: str, token: str | None, now: float | None = None) -> str:
        """The operator's name, or AuthError 401 (no or wrong token) / 429 (too many wrong ones)."""
        now = time.monotonic() if now is None else now
        wait = self.throttle.retry_after(client, now)
        if wait > 0:
            raise AuthError(429, f"too many wrong operator tokens from {client}: retry in {math.ceil(wait)} s",
                            math.ceil(wait))
        if not token:
            raise AuthError(401, "an operator token is required: Authorization: Bearer <token>", audit=False)
        name = self.lookup(token)
        if name is None:
            self.throttle.failed(client, now)
            raise AuthError(401, "the operator token is not valid")
        self.throttle.succeeded(client)
        return name


def ws_token(protocols: list[str]) -> str | None:
    """The token a browser offers as the subprotocol `bearer.<base64url of the token>` (beside
    `sem-console`), since a browser's WebSocket cannot send an Authorization header."""
    for p in protocols:
        if p.startswith(WS_TOKEN_PREFIX):
            raw = p[len(WS_TOKEN_PREFIX):]
            try:
                return base64.urlsafe_b64decode(raw + "=" * (-len(raw) % 4)).decode()
            except (binascii.Error, UnicodeDecodeError, ValueError):
                return ""
    return None
