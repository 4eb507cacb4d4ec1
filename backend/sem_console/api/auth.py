"""Operator tokens: compared in constant time, bad ones slowed down per client.

After `FREE_FAILURES` bad tokens in a row from one client, every request of that client that
carries or needs a token is answered 429 with `Retry-After` for 1 s, then 2, 4, ... up to
`MAX_DELAY` s after each further bad token; a good token clears the count, and a client quiet for
`FORGET_AFTER` s starts afresh. A good token is refused too while its client waits: were it let
through, the answer (429 or 200) would tell a guesser which guess was right, and the slow-down
would slow nothing.

A client is its IP address, so every local process shares 127.0.0.1 with the operator's browser,
and one of them could keep the operator waiting. Hence device cookies (after OWASP's "Slow Down
Online Guessing Attacks with Device Cookies"): a good token earns the client a cookie
`DEVICE_COOKIE` (a random id and its HMAC under a secret of this process), and a request that
carries a valid one is throttled as that device, apart from its address. A signed-in dashboard
goes on commanding while another process on its address is slowed down; the cookie grants
nothing else (the token is checked as ever), and only a good token gets one.
"""

from __future__ import annotations

import base64
import binascii
import hashlib
import hmac
import math
import secrets
import time
from collections import OrderedDict
from dataclasses import dataclass

FREE_FAILURES = 5
MAX_DELAY = 60.0
FORGET_AFTER = 900.0
MAX_CLIENTS = 10_000
WS_PROTOCOL = "sem-console"
WS_TOKEN_PREFIX = "bearer."
DEVICE_COOKIE = "sem-console-device"


@dataclass
class _Client:
    failures: int = 0
    blocked_until: float = 0.0
    last: float = 0.0


class Throttle:
    def __init__(self, first_wait: float = 1.0) -> None:
        self.first_wait = first_wait
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
            c.blocked_until = now + min(MAX_DELAY, self.first_wait * 2.0 ** (c.failures - FREE_FAILURES))
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

    def __init__(self, tokens: dict[str, str], first_wait: float = 1.0) -> None:
        self.tokens = [(t.encode(), name) for t, name in tokens.items()]
        self.throttle = Throttle(first_wait)
        self._device_secret = secrets.token_bytes(32)

    def _mac(self, device: str) -> str:
        return hmac.new(self._device_secret, device.encode(), hashlib.sha256).hexdigest()

    def new_device(self) -> str:
        """A device cookie's value: a random id and its HMAC."""
        device = secrets.token_hex(16)
        return f"{device}.{self._mac(device)}"

    def device(self, cookie: str | None) -> str | None:
        """The device id of a valid device cookie, else None."""
        device, _, mac = (cookie or "").partition(".")
        return device if device and hmac.compare_digest(mac, self._mac(device)) else None

    def __bool__(self) -> bool:
        return bool(self.tokens)

    def lookup(self, token: str) -> str | None:
        """The operator of `token`: every configured token is compared, each in constant time."""
        given, found = token.encode(), None
        for t, name in self.tokens:
            if hmac.compare_digest(given, t):
                found = name
        return found

    def authenticate(self, client: str, token: str | None, now: float | None = None, device: str | None = None) -> str:
        """The operator's name, or AuthError 401 (no or wrong token) / 429 (too many wrong ones).
        `device`: the id of a valid device cookie; the request is then throttled as that device."""
        now = time.monotonic() if now is None else now
        client = f"device {device}" if device else client
        wait = self.throttle.retry_after(client, now)
        if wait > 0:
            raise AuthError(429, f"too many wrong operator tokens from {client}: retry in {math.ceil(wait)} s", math.ceil(wait))
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
            raw = p[len(WS_TOKEN_PREFIX) :]
            try:
                return base64.urlsafe_b64decode(raw + "=" * (-len(raw) % 4)).decode()
            except (binascii.Error, UnicodeDecodeError, ValueError):
                return ""
    return None
