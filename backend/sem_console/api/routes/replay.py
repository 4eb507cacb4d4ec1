"""Replay in the console (`sem-console --replay FILE.mcap`): the playback's state (`reads`) and its
controls (`controls`: play, pause, seek, speed).

The controls need no operator token: a replay commands nothing and publishes nothing. They change
what every viewer of this console sees, so they take the POST rules of every state-changing route
(same origin, JSON body) and, with --auth-reads, a token like any read.
"""

from __future__ import annotations

from fastapi import APIRouter, HTTPException, status

from sem_console.api.deps import ConsoleDep
from sem_console.api.responses import JSON_BODY, problem
from sem_console.api.schemas import ReplayRequest, ReplayStatus
from sem_console.core import messages

reads = APIRouter(prefix="/api", tags=["replay"])
controls = APIRouter(prefix="/api", tags=["replay"])
NOT_REPLAYING = "this console is live: playback controls exist only with sem-console --replay FILE.mcap"


@reads.get("/replay", response_model=ReplayStatus | None)
async def replay_status(console: ConsoleDep) -> messages.ReplayStatus | None:
    """The replay's playback: playing or paused, speed, position, and the recording's start and end (UTC seconds);
    null for a live console."""
    replay = console.playback()
    return replay.status() if replay is not None else None


@controls.post(
    "/replay", response_model=ReplayStatus, responses={**JSON_BODY, 409: problem("the console is live, not replaying")}
)
async def control_replay(body: ReplayRequest, console: ConsoleDep) -> messages.ReplayStatus:
    """`{"action": "play"}`, `{"action": "pause"}`, `{"action": "seek", "position": <UTC seconds>}` (the state at
    that instant is rebuilt and every client gets a fresh snapshot; answered once it is) or
    `{"action": "speed", "speed": 0.25..20}`. Returns the playback's state. No operator token: a token only with
    --auth-reads, as for every read."""
    replay = console.playback()
    if replay is None:
        raise HTTPException(status.HTTP_409_CONFLICT, NOT_REPLAYING)
    if body.action == "play":
        await replay.play()
    elif body.action == "pause":
        replay.pause()
    elif body.action == "seek":
        await replay.seek(min(max(body.position, replay.start), replay.end))
    else:
        replay.set_speed(body.speed)
    return replay.status()
