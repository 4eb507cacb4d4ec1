"""WebSocket /ws: a snapshot on connect, then typed deltas (see /api/ws-schema); /ws?batch=1 takes reports in arrays;
/ws?ack=1 acknowledges the frames it takes (`ack` messages) and gets reports within a window of unacknowledged bytes;
a client that names the vehicle it draws (`select`) gets the others' GPSReports without their satellites and their
reports at a pace (`pace`); one that names it on connect (/ws?vehicle=<id>) gets a snapshot built for it: that vehicle
whole, every other as its brief."""

from __future__ import annotations

import asyncio
import contextlib
import json
import logging
import time
import uuid
from typing import Any

from fastapi import APIRouter, WebSocket, WebSocketDisconnect
from pydantic import ValidationError

from sem_console.api import audit
from sem_console.api.auth import DEVICE_COOKIE, WS_PROTOCOL, AuthError, ws_token
from sem_console.api.guard import refuse
from sem_console.api.schemas import client_messages, ws_schema
from sem_console.console.hub import dumps
from sem_console.core.messages import error_message, pong_message

router = APIRouter()
log = logging.getLogger("sem-console.ws")
CLOSE_WAIT = 10.0
"""How long the console waits for a client cut for not reading to take its close frame (its reason: a laptop that wakes
within it learns why it was cut); then it stops waiting, and the socket closes once the client reads or TCP gives up."""


@router.get("/api/ws-schema", tags=["meta"])
def get_ws_schema() -> dict[str, Any]:
    """JSON Schema of every WebSocket message, both directions, tagged by `type`."""
    return ws_schema()


@router.websocket("/ws")
async def websocket(ws: WebSocket) -> None:
    """With --auth-reads the token comes as the subprotocol `bearer.<base64url token>` beside `sem-console`."""
    console = ws.app.state.console
    if ws.app.state.settings.auth_reads:
        try:
            operators = ws.app.state.operators
            operators.authenticate(
                audit.client_of(ws.scope) or "?",
                ws_token(ws.scope.get("subprotocols", [])),
                device=operators.device(ws.cookies.get(DEVICE_COOKIE)),
            )
        except AuthError as e:
            audit.auditor(ws.scope).refused(ws.scope, e.status, e.detail, audit=e.audit)
            await refuse(ws.scope, ws.send, e.status, e.detail)
            return
    await ws.accept(subprotocol=WS_PROTOCOL if WS_PROTOCOL in ws.scope.get("subprotocols", []) else None)
    # ?batch=1: the reports waiting when the sender is free go out as one JSON array; ?ack=1: the client acknowledges
    # the frames it has taken, and its reports wait at the console, conflated, beyond a window (the dashboard asks both);
    # ?vehicle=<id>: the vehicle it draws, its snapshot built for it (a `select` of it)
    named = ws.query_params.get("vehicle")
    vehicle = _vehicle_id(named)
    client = console.attach_client(
        ws.send_text, batch=ws.query_params.get("batch") == "1", ack=ws.query_params.get("ack") == "1", vehicle=vehicle
    )
    if named is not None and vehicle is None:
        said = f"bad vehicle={named[:60]!r}: name a vehicle by its id (a UUID); the snapshot has every vehicle"
        client.push(json.dumps(error_message(said)))
    receiver = asyncio.create_task(_receive(ws, client, console))
    try:
        assert client.task is not None
        await asyncio.wait({receiver, client.task}, return_when=asyncio.FIRST_COMPLETED)
        if client.dropped:  # it stopped reading: tell it (if it still can hear), and let it go
            log.warning("closed the WebSocket of %s: %s", audit.client_of(ws.scope) or "?", client.dropped_for)
            with contextlib.suppress(Exception):
                await asyncio.wait_for(ws.close(code=1013, reason=close_reason(client.dropped_for)), timeout=CLOSE_WAIT)
    finally:
        receiver.cancel()
        console.detach_client(client)


async def _receive(ws: WebSocket, client: Any, console: Any) -> None:
    with contextlib.suppress(WebSocketDisconnect):
        while True:
            message = await ws.receive()
            if message["type"] == "websocket.disconnect":
                return
            text = message.get("text")
            if text is None:
                client.push(json.dumps(error_message("bad message: send JSON text, not binary")))
                continue
            try:
                msg = client_messages.validate_python(json.loads(text))
            except (ValueError, ValidationError) as e:
                client.push(json.dumps(error_message(f"bad message: {_short(e)}")))
                continue
            if msg.type == "ping":
                client.push(json.dumps(pong_message(time.time())))
            elif msg.type == "ack" and not client.ack(msg.frames):
                client.push(
                    json.dumps(
                        error_message(
                            f"bad message: ack of {msg.frames} frames, but {client.sent_frames} were "
                            "sent on this socket: acknowledge the frames received"
                        )
                    )
                )
            elif msg.type == "select":
                console.select_for(client, None if msg.providerId is None else str(msg.providerId))
                # whole and now: what it had of the vehicle was thin (GPSReport), paced, or the snapshot's brief
                for report in [] if msg.providerId is None else console.selected_reports(msg.providerId):
                    client.push(dumps(report), key=(report["providerId"], report["topic"]))
            elif msg.type == "resync":
                client.push_snapshot(json.dumps(console.snapshot(), separators=(",", ":")))


def _vehicle_id(text: str | None) -> str | None:
    """The vehicle named by /ws?vehicle= as the console writes ids (None: none, or not an id)."""
    if text is None:
        return None
    try:
        return str(uuid.UUID(text))
    except ValueError:
        return None


def close_reason(why: str) -> str:
    """The close frame's reason (at most 123 bytes): why, and what to do."""
    return f"{why}; the console cut it so no other screen waits. Reconnect"[:123]


def _short(e: Exception) -> str:
    if isinstance(e, ValidationError):
        return "; ".join(f"{'.'.join(map(str, err['loc'])) or 'message'}: {err['msg']}" for err in e.errors())[:300]
    return str(e)[:300]
