"""Documented error responses, so the OpenAPI document lists every status code the console answers."""

from __future__ import annotations

from typing import Any

from sem_console.api.schemas import Problem, ValidationProblem

Responses = dict[int | str, dict[str, Any]]


def problem(description: str) -> dict[str, Any]:
    return {"model": Problem, "description": description}


EVERY_ROUTE: Responses = {
    403: problem("refused: the Host, or for a POST, PUT, DELETE or /ws the Origin, is not allowed"),
    422: {"model": ValidationProblem, "description": "a parameter or the body is not valid"},
}
NEEDS_TOKEN: Responses = {
    401: problem("no operator token, or a wrong one"),
    429: problem("too many wrong operator tokens from this client: wait Retry-After seconds"),
}
JSON_BODY: Responses = {
    400: problem("the body could not be read (e.g. not UTF-8)"),
    415: problem("the request is not Content-Type: application/json"),
}
READ_ONLY: Responses = {
    409: problem("read-only: the console replays a recording (sem-console --replay); nothing is commanded or recorded"),
}
