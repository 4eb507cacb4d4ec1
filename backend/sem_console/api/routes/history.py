"""Track and chart history per vehicle, and exports: GPX and CSV tracks, the command history as CSV.

Every route is `async def`; the database is read in worker threads (see console/history.py).
"""

from __future__ import annotations

import asyncio
import csv
import io
import uuid
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from datetime import UTC, datetime
from typing import Annotated, Any
from xml.etree import ElementTree

import gpxpy.gpx
from fastapi import APIRouter, Depends, HTTPException, Query, status
from fastapi.exceptions import RequestValidationError
from fastapi.responses import Response
from pydantic import BeforeValidator

from sem_console import __version__
from sem_console.api.deps import ConsoleDep
from sem_console.api.responses import DATABASE_READ, Responses, problem
from sem_console.api.schemas import iso_only
from sem_console.console.service import Console
from sem_console.core import messages
from sem_console.core.words import word
from sem_console.storage.models import SeriesPoint, TrackPoint

router = APIRouter(tags=["history"], responses=DATABASE_READ)  # every route reads the database
EXT_NS = "urn:sem-console:gpx-extensions:1"  # namespace of the course/SOG extensions (a name, not a location)
UNKNOWN_PROVIDER: Responses = {404: problem("no such provider on the bus nor in the history")}


class CsvResponse(Response):
    media_type = "text/csv"


class GpxResponse(Response):
    media_type = "application/gpx+xml"


def _document(media: str, description: str) -> Responses:
    return {200: {"description": description, "content": {media: {"schema": {"type": "string"}}}}}


# ---- the time range -----------------------------------------------------------------------
@dataclass(frozen=True)
class TimeRange:
    since: float | None
    until: float | None


def epoch(name: str, value: datetime | None) -> float | None:
    if value is None:
        return None
    try:
        return (value if value.tzinfo else value.replace(tzinfo=UTC)).timestamp()
    except (OverflowError, ValueError):  # e.g. 0001-01-01T00:00:00+05:00 is before the year 1 in UTC
        raise _invalid(name, f"{value.isoformat()} is out of range") from None


def _invalid(name: str, message: str) -> RequestValidationError:
    """A 422 like every other bad parameter's (see main.validation_error)."""
    return RequestValidationError([{"loc": ("query", name), "msg": message, "type": "value_error"}])


IsoTime = Annotated[datetime | None, BeforeValidator(iso_only)]
SINCE_DOC = "from this time on (ISO 8601, e.g. 2026-11-22T08:00:00Z; without an offset: UTC)"
UNTIL_DOC = "up to this time (ISO 8601; without an offset: UTC); before `since`: nothing"


async def time_range(
    since: Annotated[IsoTime, Query(description=SINCE_DOC)] = None, until: Annotated[IsoTime, Query(description=UNTIL_DOC)] = None
) -> TimeRange:
    return TimeRange(epoch("since", since), epoch("until", until))


Range = Annotated[TimeRange, Depends(time_range)]


async def known(console: Console, provider_id: uuid.UUID) -> None:
    if console.provider(provider_id) is None and not await console.has_history(provider_id):
        raise HTTPException(status.HTTP_404_NOT_FOUND, f"no provider {provider_id} on the bus nor in the history")


# ---- JSON ---------------------------------------------------------------------------------
@router.get("/api/providers/{provider_id}/track", response_model=list[TrackPoint], responses=UNKNOWN_PROVIDER)
async def get_track(provider_id: uuid.UUID, console: ConsoleDep, when: Range) -> list[TrackPoint]:
    """The vehicle's track in time order, from its GPSFixReports: at most one point per second, stored when the
    vehicle moved `--track-thin-metres` (5 m), `--track-thin-seconds` (10 s) passed or its GPSLatLongValid or fixValid
    changed; older than `--track-rollup-after-hours` (1 h), the first point of each `--track-rollup-seconds` (60 s) and
    each change of GPSLatLongValid or fixValid; kept for the console's track retention (`--track-retention-hours`)."""
    await known(console, provider_id)
    return await console.track(provider_id, when.since, when.until)


@router.get("/api/providers/{provider_id}/series", response_model=list[SeriesPoint], responses=UNKNOWN_PROVIDER)
async def get_series(provider_id: uuid.UUID, console: ConsoleDep, when: Range) -> list[SeriesPoint]:
    """The dashboard's chart values in time order: mean C/N0, satellites used and in view, at most one
    point per second from the vehicle's GPSReports; older than `--track-rollup-after-hours` (1 h), the first point of
    each `--track-rollup-seconds` (60 s)."""
    await known(console, provider_id)
    return await console.series(provider_id, when.since, when.until)


# ---- exports --------------------------------------------------------------------------------
def _utc(t: float | None) -> str:
    return "" if t is None else datetime.fromtimestamp(t, UTC).isoformat(timespec="milliseconds").replace("+00:00", "Z")


def _cell(v: Any) -> Any:
    if v is None:
        return ""
    if isinstance(v, bool):
        return "true" if v else "false"
    return v


def _csv(header: Sequence[str], rows: Iterable[Sequence[Any]]) -> str:
    out = io.StringIO()
    w = csv.writer(out, lineterminator="\r\n")  # RFC 4180
    w.writerow(header)
    w.writerows([_cell(v) for v in row] for row in rows)
    return out.getvalue()


def _filename(provider_id: uuid.UUID, when: TimeRange, ext: str) -> str:
    span = "".join(f"_{_utc(t).replace(':', '').replace('-', '')}" for t in (when.since, when.until) if t is not None)
    return f"track_{provider_id}{span}.{ext}"


def _attachment(name: str) -> dict[str, str]:
    return {"Content-Disposition": f'attachment; filename="{name}"'}


TRACK_CSV_HEADER = (
    "time_utc",
    "latitude_deg",
    "longitude_deg",
    "altitude_msl_m",
    "course_deg",
    "sog_mps",
    "fix_valid",
    "gps_lat_long_valid",
    "position_time_utc",
    "umaa_version",
)


def track_csv(points: Sequence[TrackPoint], version: str | None = None) -> str:
    return _csv(
        TRACK_CSV_HEADER,
        (
            (
                _utc(p.time),
                p.latitude,
                p.longitude,
                p.altitudeMsl,
                p.course,
                p.sog,
                p.fixValid,
                p.latLongValid,
                _utc(p.positionTime),
                version,
            )
            for p in points
        ),
    )


def track_gpx(provider_id: uuid.UUID, name: str | None, points: Sequence[TrackPoint], version: str | None = None) -> str:
    """GPX 1.1: one track, one segment, the points in time order; course (degrees) and speed (m/s) in an
    extension of our namespace; <desc> says where each point came from, and the track's the vehicle's UMAA version."""
    gpx = gpxpy.gpx.GPX()
    gpx.creator = f"SEM Console {__version__}"
    gpx.nsmap["sem"] = EXT_NS
    label = f"{name} ({provider_id})" if name else str(provider_id)
    speaks = f"a UMAA {version} vehicle; " if version else ""
    track = gpxpy.gpx.GPXTrack(
        name=f"Track of {label}",
        description=(f"{speaks}its position reports at most once per second; time: when the console received them"),
    )
    segment = gpxpy.gpx.GPXTrackSegment()
    for p in points:
        pt = gpxpy.gpx.GPXTrackPoint(p.latitude, p.longitude, elevation=p.altitudeMsl, time=datetime.fromtimestamp(p.time, UTC))
        pt.description = (
            f"fix {'valid' if p.fixValid else 'not valid' if p.fixValid is False else 'unknown'}, "
            f"position from {'GPS' if p.latLongValid else 'INS'}"
        )
        for tag, value in (("course", p.course), ("speed", p.sog)):
            if value is not None:
                ext = ElementTree.Element(f"{{{EXT_NS}}}{tag}")
                ext.text = repr(value)
                pt.extensions.append(ext)
        segment.points.append(pt)
    track.segments.append(segment)
    gpx.tracks.append(track)
    return gpx.to_xml(version="1.1")


@router.get(
    "/api/providers/{provider_id}/track.gpx",
    response_class=Response,
    responses={
        **_document(
            "application/gpx+xml",
            "GPX 1.1: the track in time order, elevation MSL (m), course (degrees) and speed (m/s) as extensions",
        ),
        **UNKNOWN_PROVIDER,
    },
)
async def get_track_gpx(provider_id: uuid.UUID, console: ConsoleDep, when: Range) -> Response:
    """The track as a GPX 1.1 file (a download, made with gpxpy): one track, one segment, the points in time order
    with `<time>` (UTC), `<ele>` (altitude MSL, m) and `<desc>` (fix valid, GPS or INS position); course (degrees)
    and speed (m/s) as `<sem:course>` and `<sem:speed>` extensions."""
    await known(console, provider_id)
    points = await console.track(provider_id, when.since, when.until)
    p = console.provider(provider_id)
    body = await asyncio.to_thread(track_gpx, provider_id, p.name if p else None, points, p.umaa_version if p else None)
    return GpxResponse(body, headers=_attachment(_filename(provider_id, when, "gpx")))


@router.get(
    "/api/providers/{provider_id}/track.csv",
    response_class=Response,
    responses={**_document("text/csv", f"CSV (RFC 4180), units in the header: {','.join(TRACK_CSV_HEADER)}"), **UNKNOWN_PROVIDER},
)
async def get_track_csv(provider_id: uuid.UUID, console: ConsoleDep, when: Range) -> Response:
    """The track as CSV, one row per point in time order, times UTC ISO 8601, with the vehicle's UMAA version
    (`umaa_version`; empty: a vehicle the console has not seen since it started) (a download)."""
    await known(console, provider_id)
    points = await console.track(provider_id, when.since, when.until)
    p = console.provider(provider_id)
    body = await asyncio.to_thread(track_csv, points, p.umaa_version if p else None)
    return CsvResponse(body, headers=_attachment(_filename(provider_id, when, "csv")))


COMMANDS_CSV_HEADER = (
    "session_id",
    "service",
    "provider_id",
    "ins_state",
    "operator",
    "station",
    "created_utc",
    "acked_utc",
    "final_status",
    "terminal",
    "unanswered",
    "cancel_requested",
    "canceled_by",
    "canceled_on",
    "canceled_utc",
    "cancel_cause",
    "closed_unheard",
    "closed_utc",
    "cleaned_up",
    "seq",
    "status",
    "status_words",
    "reason",
    "reason_words",
    "log_message",
    "violation",
    "provider_time_utc",
    "received_utc",
    "umaa_version",
)


def commands_csv(commands: Sequence[messages.Command], versions: dict[str, str] | None = None) -> str:
    """One row per transition, the command's columns repeated; a command with no transition yet has one
    row with the transition columns empty. The transition's status and reason are also in the operator's words, as the
    dashboard says them (`core/words.py`); `versions`: the UMAA version each command was issued in, by its sessionId
    (its commanding's, `versions/commands.py`)."""
    versions = versions or {}

    def rows() -> Iterable[list[Any]]:
        for c in commands:
            head = [
                c["sessionId"],
                c["service"],
                c["providerId"],
                c["state"],
                c["operator"],
                c["console"],
                _utc(c["createdAt"]),
                _utc(c["ackedAt"]),
                c["status"],
                c["terminal"],
                c["unanswered"],
                c["cancelRequested"],
                c["canceledBy"],
                c["canceledOn"],
                _utc(c["canceledAt"]),
                c["cancelCause"],
                c["closedUnheard"],
                _utc(c["closedAt"]),
                c["cleanedUp"],
            ]
            transitions: list[messages.Transition | None] = [*c["transitions"]] or [None]
            for t in transitions:
                yield (
                    head
                    + (
                        [None] * 9
                        if t is None
                        else [
                            t["seq"],
                            t["status"],
                            word("CommandStatusEnumType", t["status"]),
                            t["reason"],
                            word("CommandStatusReasonEnumType", t["reason"]),
                            t["logMessage"],
                            t["violation"],
                            _utc(t["providerTime"]),
                            _utc(t["receivedAt"]),
                        ]
                    )
                    + [versions.get(c["sessionId"])]
                )

    return _csv(COMMANDS_CSV_HEADER, rows())


@router.get(
    "/api/commands.csv",
    response_class=Response,
    tags=["commands"],
    responses=_document("text/csv", f"CSV (RFC 4180): {','.join(COMMANDS_CSV_HEADER)}"),
)
async def get_commands_csv(
    console: ConsoleDep,
    when: Range,
    provider_id: Annotated[uuid.UUID | None, Query(description="only commands to this provider")] = None,
) -> Response:
    """The command history, oldest first, one row per status transition with the command's columns repeated
    (among them `operator` and `station`, who issued it and where; `canceled_by`, `canceled_on`, `canceled_utc`, `cancel_cause`;
    `closed_unheard`, `closed_utc`); a command with no status yet is one row, its transition columns empty. Each
    status and reason is given as its UMAA literal and, beside it, in the dashboard's words (`status_words`,
    `reason_words`); `umaa_version`, the UMAA version the command was issued in (its vehicle's), by whose standard its
    state, statuses and reasons read. Times UTC ISO 8601; `since`/`until` select by the time the command was created
    (a download)."""

    def build() -> str:
        commands = console.export_commands(provider_id, when.since, when.until)
        return commands_csv([c.to_json() for c in commands], {str(c.session_id): c.commanding.version for c in commands})

    body = await asyncio.to_thread(build)
    name = f"commands{f'_{provider_id}' if provider_id else ''}.csv"
    return CsvResponse(body, headers=_attachment(name))
