"""What the Foxglove gateway makes of the console's messages (gateways/foxglove/schemas.py): no process, no server."""

from __future__ import annotations

import math
from typing import Any

from sem_console.core.messages import Alarm, ReportEnvelope
from sem_console.gateways.foxglove import schemas
from sem_console.gateways.foxglove.schemas import alarm_logs, location_fix, transition_log

SCALARS = ("boolean", "string", "number", "integer")


def unreadable(schema: dict[str, Any], at: str = "") -> list[str]:
    """What Foxglove's and Lichtblick's reader of a JSON channel's schema (parseJsonSchema of @foxglove/mcap-support)
    refuses, as its rules are: an object with properties, each a boolean, string, number, integer, object or array of
    them, no $ref, anyOf or list of types. A channel it refuses is left out of the player (\"Failed to parse channel
    schema\"), with its panels."""
    if schema.get("type") != "object" or not isinstance(schema.get("properties"), dict):
        return [f"{at or '/'}: not an object with properties"]
    out = []
    for name, field in schema["properties"].items():
        kind = field.get("type")
        if kind == "object":
            out += unreadable(field, f"{at}/{name}")
        elif kind == "array":
            item = field.get("items", {})
            if item.get("type") == "object":
                out += unreadable(item, f"{at}/{name}[]")
            elif item.get("type") not in SCALARS:
                out.append(f"{at}/{name}[]: {item}")
        elif kind not in SCALARS:
            out.append(f"{at}/{name}: {field}")
    return out


def fix(lat: float, lon: float, invalid: list[str] | None = None, **report: Any) -> ReportEnvelope:
    position = {"geodeticLatitude": {"latitude": lat}, "geodeticLongitude": {"longitude": lon}}
    body = {"position2DWithTime": {"geodeticPosition": position}, "timeStamp": {"seconds": 100, "nanoseconds": 5}, **report}
    return {"report": body, "invalid": invalid or [], "receivedAt": 200.25}


def alarm(id: int, state: str = "active-unacknowledged", severity: str = "alarm") -> Alarm:
    return {
        "id": id,
        "kind": "link-lost",
        "severity": severity,
        "providerId": None,
        "vehicle": "Alpha",
        "sessionId": None,
        "text": f"Alpha: link lost {id}",
        "since": 50.5,
        "state": state,
        "clearedAt": None,
        "ackedAt": None,
        "ackedBy": None,
        "cause": "",
        "chattering": False,
        "shelf": None,
        "returned": None,
    }


def test_a_fix_is_a_location_fix_with_its_covariance_turned_to_east_north_up() -> None:
    covariance = {"pnPn": 16.0, "pePe": 9.0, "pdPd": 4.0}
    got = location_fix(fix(36.85, -75.98, positionCovariance=covariance), "Alpha")
    assert got == {
        "timestamp": {"sec": 100, "nsec": 5},
        "frame_id": "Alpha",
        "latitude": 36.85,
        "longitude": -75.98,
        "position_covariance": [9.0, 0.0, 0.0, 0.0, 16.0, 0.0, 0.0, 0.0, 4.0],
        "position_covariance_type": 2,
    }
    # a UMAA 6.0 GlobalPose gives no down variance: the covariance is then unknown, not made up
    partial = location_fix(fix(36.85, -75.98, positionCovariance={**covariance, "pdPd": None}), "Alpha")
    assert partial is not None and partial["position_covariance_type"] == 0 and partial["position_covariance"] == [0.0] * 9


def test_a_location_fix_s_altitude_is_the_height_above_the_ellipsoid_a_6_0_vehicle_gives() -> None:
    above_sea = {"altitudeMSL": {"altitude": 3.0}}
    got = location_fix(fix(36.85, -75.98, altitudeGeodetic=-33.5, **above_sea), "Alpha")
    assert got is not None and got["altitude"] == -33.5
    # a 3.0.1 vehicle gives only its height above mean sea level: no altitude rather than a wrong one
    old = location_fix(fix(36.85, -75.98, altitudeGeodetic=None, **above_sea), "Alpha")
    assert old is not None and "altitude" not in old
    flagged = location_fix(fix(1.0, 2.0, ["altitudeGeodetic: 900000.0 is out of range"], altitudeGeodetic=9e5), "A")
    assert flagged is not None and "altitude" not in flagged


def test_a_fix_without_a_valid_position_is_no_location_fix_and_a_bad_time_is_the_console_s() -> None:
    assert location_fix(fix(math.nan, 1.0), "A") is None
    bad = ["position2DWithTime.geodeticPosition.geodeticLatitude.latitude: 95.0 is out of range"]
    assert location_fix(fix(95.0, 1.0, bad), "A") is None
    stale = location_fix(fix(1.0, 2.0, ["timeStamp.nanoseconds: 2000000000 is out of range"]), "A")
    assert stale is not None and stale["timestamp"] == {"sec": 200, "nsec": 250_000_000}


def test_alarms_are_logged_when_raised_changed_and_gone() -> None:
    raised = alarm_logs({}, [alarm(1), alarm(2, severity="warning")], 60.0)
    assert [(x["level"], x["message"], x["name"], x["timestamp"]) for x in raised] == [
        (4, "Alpha: link lost 1", "alarm/link-lost", {"sec": 50, "nsec": 500_000_000}),
        (3, "Alpha: link lost 2", "alarm/link-lost", {"sec": 50, "nsec": 500_000_000}),
    ]
    before = {1: alarm(1), 2: alarm(2)}
    changed = alarm_logs(before, [alarm(1, state="active-acknowledged")], 61.0)
    assert [(x["level"], x["message"]) for x in changed] == [
        (2, "Acknowledged: Alpha: link lost 1"),
        (2, "No longer active: Alpha: link lost 2"),
    ]
    assert alarm_logs(before, list(before.values()), 62.0) == []


def test_a_failed_transition_is_an_error_in_the_operator_s_words() -> None:
    transition = {
        "seq": 3,
        "status": "FAILED",
        "reason": "RESOURCE_FAILED",
        "logMessage": "",
        "violation": None,
        "providerTime": None,
        "receivedAt": 70.0,
    }
    m: Any = {"type": "transition", "sessionId": "s", "transition": transition, "command": {"service": "GPSFix"}}
    got = transition_log(m, "Alpha")
    assert (got["level"], got["message"], got["name"]) == (
        4,
        "Alpha: GPSFix command failed: the equipment failed",
        "command/GPSFix",
    )


def test_every_channel_s_schema_is_one_foxglove_and_lichtblick_read() -> None:
    from sem_console.codec.jsonschema import report_schemas

    reports = [name for name, d in report_schemas().items() if name.endswith("ReportType") and d.get("type") == "object"]
    assert {"GPSReportType", "GPSFixReportType", "GPSFixStatusReportType", "InertialSensorReportType"} <= set(reports)
    for schema in [schemas.LOCATION_FIX, schemas.LOCATION_FIXES, schemas.LOG, *map(schemas.report_schema, reports)]:
        assert unreadable(schema) == [], schema["title"]
    fix = schemas.report_schema("GPSFixReportType")["properties"]["report"]
    # the report's members as the reader needs them: a nullable member is its type (a null reads as absent)
    assert fix["properties"]["SOG"]["type"] == "number" and fix["properties"]["GPSLatLongValid"]["type"] == "boolean"
