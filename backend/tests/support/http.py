"""The tests' HTTP calls: httpx's own `get`, `post`, `put`, `delete` and `request` (a client per call: no connection
kept, no cookie carried from one call to the next), with the trust store read once. httpx builds each call's client
an SSL context, parsing certifi's bundle of CA certificates: about 20 ms of CPU even for a plain http:// URL, paid on
every poll of a test waiting for a console (hundreds a test). A call that gives its own `verify` (a console with a
certificate of its own) keeps it."""

from __future__ import annotations

import ssl
from typing import Any

import certifi
import httpx

# what httpx's create_ssl_context builds for verify=True, once
_TRUST = ssl.create_default_context(cafile=certifi.where())


def request(method: str, url: str, **kwargs: Any) -> httpx.Response:
    if kwargs.get("verify", True) is True:
        kwargs["verify"] = _TRUST
    return httpx.request(method, url, **kwargs)


def get(url: str, **kwargs: Any) -> httpx.Response:
    return request("GET", url, **kwargs)


def post(url: str, **kwargs: Any) -> httpx.Response:
    return request("POST", url, **kwargs)


def put(url: str, **kwargs: Any) -> httpx.Response:
    return request("PUT", url, **kwargs)


def delete(url: str, **kwargs: Any) -> httpx.Response:
    return request("DELETE", url, **kwargs)
