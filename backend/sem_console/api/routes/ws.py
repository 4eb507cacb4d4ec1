"""WebSocket /ws: a snapshot on connect, then typed deltas (see /api/ws-schema)."""

from __future__ import annotations

import json
import time
from typing import Any

from fastapi import APIRouter, WebSocket, WebSocketDisconnect
from pydantic import ValidationError

from sem_console.api.schemas import client_messages, ws_schema

router = APIRouter()


@router.get("/api/ws-schema", tags=["meta"])
def get_ws_schema() -> dict[str, Any]:
    """JSON Schema of every WebSocket message, both directions, tagged by `type`."""
    return ws_schema()


@router.websocket("/ws")
async def websocket(ws: WebSocket) -> None:
    console = ws.app.state.console
    await ws.accept()
    client = console.hub.attach(ws.send_text, console.snapshot())
    try:
        while True:
            text = await ws.receive_text()
            try:
                msg = client_messages.validate_python(json.loads(text))
            except (ValueError, ValidationError) as e:
                client.push(json.dumps({"type": "error", "message": f"bad message: {_short(e)}"}))
                continue
            if msg.type == "ping":
                client.push(json.dumps({"type": "pong", "serverTime": time.time()}))
            elif msg.type == "resync":
                client.push(json.dumps(console.snapshot()))
    except WebSocketDisconnect:
        pass
    finally:
        console.hub.detach(client)


def _short(e: Exception) -> str:
    if isinstance(e, ValidationError):
        return "; ".join(f"{'.'.join(map(str, err['loc'])) or 'message'}: {err['msg']}" for err in e.errors())[:300]
    return str(e)[:300]
