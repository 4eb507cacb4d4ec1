"""Recordings: start and stop (`writes`, with the command routes' operator auth), list and download (`reads`).

File I/O (opening, finishing, listing files) runs in worker threads, never on the event loop.
"""

from __future__ import annotations

import asyncio
from typing import Annotated, Any

from fastapi import APIRouter, HTTPException, Path, Request, status
from fastapi.responses import FileResponse

from sem_console.api import audit
from sem_console.api.deps import ConsoleDep, OperatorDep
from sem_console.api.responses import JSON_BODY, problem
from sem_console.api.schemas import RecordingFile, RecordingRequest, RecordingStatus
from sem_console.core import messages
from sem_console.recording.recorder import NAME, RecordingError

RecordingName = Annotated[str, Path(pattern=NAME.pattern, description="<UTC start time>.mcap, e.g. 20261122T101530.123Z.mcap")]
writes = APIRouter(prefix="/api", tags=["recordings"])
reads = APIRouter(prefix="/api", tags=["recordings"])


@writes.post(
    "/recordings",
    response_model=RecordingStatus,
    responses={**JSON_BODY, 503: problem("the recording cannot start: its directory cannot be made or written")},
)
async def control_recording(
    body: RecordingRequest, request: Request, console: ConsoleDep, operator: OperatorDep
) -> messages.RecordingStatus:
    """Start recording every SEM sample, UMAA 3.0.1 and 6.0, to `<directory>/<UTC start>.mcap`, or stop.
    Starting a running recording, or stopping a stopped one, changes nothing. Returns the recording's status."""
    recorder = console.recording()
    try:
        result = await asyncio.to_thread(recorder.start if body.action == "start" else recorder.stop)
    except RecordingError as e:
        audit.auditor(request.scope).refused(request.scope, 503, str(e), audit=True, operator=operator)
        raise HTTPException(status.HTTP_503_SERVICE_UNAVAILABLE, str(e)) from None
    audit.auditor(request.scope).accepted(request.scope, 200, operator, None, f"recording {body.action}")
    return result


@reads.get("/recordings/status", response_model=RecordingStatus)
async def recording_status(console: ConsoleDep) -> messages.RecordingStatus:
    """Whether the console is recording, into which file, and why a recording failed."""
    return console.recording().status()


@reads.get("/recordings", response_model=list[RecordingFile])
async def list_recordings(console: ConsoleDep) -> list[dict[str, Any]]:
    """Every recording in the console's recording directory, newest first."""
    return await asyncio.to_thread(console.recording().list)


@reads.get(
    "/recordings/{name}",
    response_class=FileResponse,
    responses={
        200: {"content": {"application/octet-stream": {}}, "description": "the MCAP file"},
        404: problem("no such recording (a path is never a recording's name)"),
        409: problem("the file is being recorded: stop the recording (or wait for it to roll over)"),
    },
)
async def download_recording(name: RecordingName, console: ConsoleDep) -> FileResponse:
    """Download one recording (MCAP). A name that is not a recording's (`<UTC start>.mcap`) is a 422: never a path."""
    recorder = console.recording()
    if name == recorder.current():
        raise HTTPException(status.HTTP_409_CONFLICT, f"{name} is being recorded")
    path = await asyncio.to_thread(recorder.path_of, name)
    if path is None:
        raise HTTPException(status.HTTP_404_NOT_FOUND, f"no recording {name}")
    return FileResponse(path, media_type="application/octet-stream", filename=name)
