"""Documented error responses, so the OpenAPI document lists every status code the console answers."""

from __future__ import annotations

from typing import Any

from sem_console.api.schemas import Problem, ValidationProblem

Responses = dict[int | str, dict[str, Any]]


def problem(description: str) -> dict[str, Any]:
    return {"model": Problem, "description": description}


# Starlette's body limit (main.MAX_BODY_BYTES) answers before any route runs: in plain text when the size was declared
# (Content-Length), as a JSON `detail` when a chunked body passed the limit while it was read.
BODY_TOO_LARGE: dict[str, Any] = {
    "model": Problem,
    "content": {"text/plain": {"schema": {"type": "string", "example": "Content Too Large"}}},
    "description": "the request body is over 1 MiB: refused before it is read, whatever the route ('Content Too Large')",
}
EVERY_ROUTE: Responses = {
    403: problem("refused: the Host, or for a POST, PUT, DELETE or /ws the Origin, is not allowed"),
    413: BODY_TOO_LARGE,
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
# A read that goes to the database (the history beyond memory, the audit, the track and chart history, the exports)
# while it cannot be reached: main.database_unavailable.
DATABASE_READ: Responses = {
    503: problem(
        "the database cannot be reached (e.g. a PostgreSQL outage): one line saying since when; try again after "
        "Retry-After seconds"
    ),
}
READ_ONLY: Responses = {
    409: problem("read-only: the console replays a recording (sem-console --replay); nothing is commanded or recorded"),
}
