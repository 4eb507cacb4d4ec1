"""What the Foxglove gateway sends, as JSON: Foxglove's well-known `foxglove.LocationFix`, `foxglove.LocationFixes`,
`foxglove.Log` and `foxglove.GeoJSON` (the fields their panels read, in Foxglove's JSON form: a time is {sec, nsec}),
and the console's decoded reports as the dashboard gets them; each with the JSON Schema its channel advertises."""

from __future__ import annotations

import functools
from typing import Any

import orjson

from sem_console.core.messages import Alarm, ReportEnvelope, TransitionMessage
from sem_console.core.words import inline, word
from sem_console.gateways import number

# foxglove.Log's levels
DEBUG, INFO, WARNING, ERROR = 1, 2, 3, 4
LEVEL_OF_SEVERITY = {"warning": WARNING, "alarm": ERROR}
LEVEL_OF_STATUS = {"FAILED": ERROR, "CANCELED": WARNING}
# foxglove.LocationFix's position_covariance_type
COVARIANCE_UNKNOWN, COVARIANCE_DIAGONAL_KNOWN = 0, 2

COVARIANCE_PATHS = ("positionCovariance.pnPn", "positionCovariance.pePe", "positionCovariance.pdPd")  # north, east, down
_TIME = {
    "type": "object",
    "properties": {"sec": {"type": "integer", "minimum": 0}, "nsec": {"type": "integer", "minimum": 0, "maximum": 999999999}},
    "required": ["sec", "nsec"],
}
LOCATION_FIX: dict[str, Any] = {
    "title": "foxglove.LocationFix",
    "description": "A vehicle's position (WGS 84 degrees) from its GPSFixReport (UMAA 3.0.1) or GlobalPose (UMAA 6.0)",
    "type": "object",
    "properties": {
        "timestamp": _TIME,
        "frame_id": {"type": "string", "description": "the vehicle's name, else its id"},
        "latitude": {"type": "number"},
        "longitude": {"type": "number"},
        "altitude": {
            "type": "number",
            "description": "metres above the WGS 84 ellipsoid: a UMAA 6.0 vehicle's altitudeGeodetic; left out without it "
            "(UMAA 3.0.1 gives only the height above mean sea level)",
        },
        "position_covariance": {"type": "array", "items": {"type": "number"}, "minItems": 9, "maxItems": 9},
        "position_covariance_type": {"type": "integer", "enum": [0, 1, 2, 3]},
    },
    "required": ["timestamp", "frame_id", "latitude", "longitude", "position_covariance", "position_covariance_type"],
}
LOCATION_FIXES: dict[str, Any] = {
    "title": "foxglove.LocationFixes",
    "description": "The latest position of every vehicle of the fleet",
    "type": "object",
    "properties": {"fixes": {"type": "array", "items": LOCATION_FIX}},
    "required": ["fixes"],
}
LOG: dict[str, Any] = {
    "title": "foxglove.Log",
    "description": "The console's alarms and its commands' transitions",
    "type": "object",
    "properties": {
        "timestamp": _TIME,
        "level": {"type": "integer", "enum": [0, 1, 2, 3, 4, 5], "description": "2 info, 3 warning, 4 error"},
        "message": {"type": "string"},
        "name": {"type": "string", "description": "alarm/<kind> or command/<service>"},
        "file": {"type": "string"},
        "line": {"type": "integer"},
    },
    "required": ["timestamp", "level", "message", "name", "file", "line"],
}
GEOJSON: dict[str, Any] = {
    "title": "foxglove.GeoJSON",
    "description": "CoMap's world model: its survey areas as a GeoJSON FeatureCollection (positions [lon, lat], degrees)",
    "type": "object",
    "properties": {"geojson": {"type": "string", "description": "the FeatureCollection, as GeoJSON text"}},
    "required": ["geojson"],
}


def geojson(world: dict[str, Any]) -> dict[str, Any]:
    """CoMap's world model (`C2.world_model`) as a foxglove.GeoJSON: its FeatureCollection, without the console's
    own members (when and by whom it was last changed)."""
    return {"geojson": orjson.dumps({"type": "FeatureCollection", "features": world["features"]}).decode()}


@functools.cache
def report_schema(type_name: str) -> dict[str, Any]:
    """A report channel's message: the vehicle, then the report's envelope as the dashboard gets it; in the JSON Schema
    Foxglove's and Lichtblick's reader takes (`readable`)."""
    from sem_console.codec.jsonschema import report_schemas

    schema: dict[str, Any] = readable(
        {
            "title": f"sem_console.{type_name}",
            "type": "object",
            "properties": {
                "providerId": {"type": "string", "format": "uuid"},
                "vehicle": {"type": ["string", "null"], "description": "the vehicle's name in the console"},
                "receivedAt": {"type": "number", "description": "UTC seconds the console received it"},
                "invalid": {"type": "array", "items": {"type": "string"}, "description": "values flagged invalid, and why"},
                "report": {"$ref": f"#/$defs/{type_name}"},
            },
            "required": ["providerId", "vehicle", "receivedAt", "invalid", "report"],
        },
        report_schemas(),
    )
    return schema


def readable(node: Any, defs: dict[str, Any]) -> Any:
    """A JSON Schema as Foxglove's and Lichtblick's reader of a JSON channel's schema takes it (it knows objects,
    arrays, booleans, strings and numbers, and refuses the whole channel for anything else): each `$ref` to `defs`
    inlined, a nullable member (`anyOf` with null, a list of types with null) its one other type, a null reading as
    absent."""
    if isinstance(node, list):
        return [readable(x, defs) for x in node]
    if not isinstance(node, dict):
        return node
    if "$ref" in node:
        rest = {k: v for k, v in node.items() if k != "$ref"}
        return {**readable(defs[node["$ref"].rsplit("/", 1)[-1]], defs), **readable(rest, defs)}
    if "anyOf" in node and len(others := [x for x in node["anyOf"] if x != {"type": "null"}]) == 1:
        rest = {k: v for k, v in node.items() if k != "anyOf"}
        return {**readable(others[0], defs), **readable(rest, defs)}
    out = {k: readable(v, defs) for k, v in node.items()}
    if isinstance(kinds := out.get("type"), list) and len(others := [k for k in kinds if k != "null"]) == 1:
        out["type"] = others[0]
    return out


def time_of(seconds: float) -> dict[str, int]:
    ns = max(0, round(seconds * 1e9))
    return {"sec": ns // 1_000_000_000, "nsec": ns % 1_000_000_000}


def location_fix(envelope: ReportEnvelope, frame_id: str) -> dict[str, Any] | None:
    """A GPSFixReport (a UMAA 6.0 GlobalPose is one in the console's model) as a LocationFix, or None without a valid
    latitude and longitude. Its time is the report's, else when the console received it."""
    report, invalid = envelope["report"], envelope["invalid"]
    lat = number(report, invalid, "position2DWithTime.geodeticPosition.geodeticLatitude.latitude")
    lon = number(report, invalid, "position2DWithTime.geodeticPosition.geodeticLongitude.longitude")
    if lat is None or lon is None:
        return None
    seconds, nanos = number(report, invalid, "timeStamp.seconds"), number(report, invalid, "timeStamp.nanoseconds")
    stamp = (
        {"sec": int(seconds), "nsec": int(nanos)}
        if seconds is not None and nanos is not None and seconds >= 0 and 0 <= nanos <= 999_999_999
        else time_of(envelope["receivedAt"])
    )
    # UMAA's covariance is north, east, down; LocationFix's is east, north, up (row-major 3x3): the diagonal is known
    # when the vehicle gives all three variances
    north, east, down = (number(report, invalid, path) for path in COVARIANCE_PATHS)
    known = north is not None and east is not None and down is not None
    covariance = [east, 0.0, 0.0, 0.0, north, 0.0, 0.0, 0.0, down] if known else [0.0] * 9
    fix: dict[str, Any] = {
        "timestamp": stamp,
        "frame_id": frame_id,
        "latitude": lat,
        "longitude": lon,
        "position_covariance": covariance,
        "position_covariance_type": COVARIANCE_DIAGONAL_KNOWN if known else COVARIANCE_UNKNOWN,
    }
    # LocationFix's altitude is above the WGS 84 ellipsoid: a 6.0 GlobalPose's altitudeGeodetic, never altitudeMSL
    if (height := number(report, invalid, "altitudeGeodetic")) is not None:
        fix["altitude"] = height
    return fix


def log(at: float, level: int, message: str, name: str) -> dict[str, Any]:
    return {"timestamp": time_of(at), "level": level, "message": message, "name": name, "file": "", "line": 0}


def transition_log(m: TransitionMessage, vehicle: str) -> dict[str, Any]:
    """A command's transition: "Alpha: GPSFix command failed: the equipment failed"."""
    t, service = m["transition"], m["command"]["service"]
    said = f"{vehicle}: {service} command {inline(word('CommandStatusEnumType', t['status']))}"
    if t["reason"] and t["reason"] != "SUCCEEDED":
        said += f": {inline(word('CommandStatusReasonEnumType', t['reason']))}"
    if t["logMessage"]:
        said += f" ({t['logMessage']})"
    if t["violation"]:
        said += f"; out of the command flow: {t['violation']}"
    return log(t["receivedAt"], LEVEL_OF_STATUS.get(t["status"], INFO), said, f"command/{service}")


def alarm_logs(before: dict[int, Alarm], now: list[Alarm], at: float) -> list[dict[str, Any]]:
    """The changes from the active alarms `before` to `now`: an alarm raised (at its severity's level), one whose state
    changed (acknowledged, cleared), and one no longer active (info)."""
    out = []
    for a in now:
        was = before.get(a["id"])
        if was is None:
            out.append(log(a["since"], LEVEL_OF_SEVERITY.get(a["severity"], WARNING), a["text"], f"alarm/{a['kind']}"))
        elif was["state"] != a["state"]:
            said = f"{word('alarmState', a['state'])}: {a['text']}"
            out.append(log(at, INFO, said, f"alarm/{a['kind']}"))
    ids = {a["id"] for a in now}
    gone = [a for a in before.values() if a["id"] not in ids]
    out.extend(log(at, INFO, f"No longer active: {a['text']}", f"alarm/{a['kind']}") for a in gone)
    return out
