"""CoMap features as GeoJSON, and the geometry a vehicle needs (lawnmower lanes), with shapely.

The geometry rule of GeoFeature: 1 vertex is a point, 2 a line, 3 or more a polygon. A closed ring
(last vertex equal to the first) is the same polygon as the open one: the repeated vertex is not
sent over IMC, and GeoJSON polygons are given closed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from shapely.geometry.base import BaseGeometry

from sem_console.comap.codec import Message, msg
from sem_console.comap.messages import Coverage

EARTH_M_PER_DEG = 111_320.0
MAX_FEATURE_ID = 0xFFFF


@dataclass
class Feature:
    feature_id: int
    points: list[tuple[float, float]]  # (lat, lon) degrees, open (no repeated closing vertex)
    coverage: str | None = None  # COMPLETED, PARTIAL, NONE or None (unknown)
    properties: dict[str, Any] = field(default_factory=dict)  # other GeoJSON properties, kept as given

    @property
    def kind(self) -> str:
        return {1: "Point", 2: "LineString"}.get(len(self.points), "Polygon")


class GeoError(ValueError):
    pass


def open_ring(points: list[tuple[float, float]]) -> list[tuple[float, float]]:
    """Drop a closing vertex equal to the first (3+ vertices stay a polygon)."""
    if len(points) >= 4 and points[-1] == points[0]:
        return points[:-1]
    return points


def _latlon(pos: Any, where: str) -> tuple[float, float]:
    if (
        not isinstance(pos, (list, tuple))
        or len(pos) < 2
        or not all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in pos)
    ):
        raise GeoError(f"{where}: a position is [longitude, latitude] in degrees")
    lon, lat = float(pos[0]), float(pos[1])
    if not (math.isfinite(lat) and math.isfinite(lon) and -90 <= lat <= 90 and -180 <= lon <= 180):
        raise GeoError(f"{where}: [{lon}, {lat}] is not a longitude and latitude in degrees")
    return lat, lon


def feature_from_geojson(f: dict[str, Any], where: str) -> Feature:
    g = f.get("geometry") or {}
    props = dict(f.get("properties") or {})
    kind, coords = g.get("type"), g.get("coordinates")
    if kind == "Point":
        points = [_latlon(coords, where)]
    elif kind == "LineString":
        points = [_latlon(p, where) for p in coords or []]
        if len(points) != 2:
            raise GeoError(f"{where}: a CoMap line has exactly 2 vertices (3 or more make a polygon); this one has {len(points)}")
    elif kind == "Polygon":
        if not isinstance(coords, list) or len(coords) != 1:
            raise GeoError(f"{where}: a CoMap polygon is one ring without holes")
        points = open_ring([_latlon(p, where) for p in coords[0] or []])
        if len(set(points)) < 3:
            raise GeoError(f"{where}: a polygon needs 3 or more distinct vertices")
        from shapely.geometry import Polygon  # shapely (and numpy) loaded on first use: not by every process that starts

        if not Polygon([(lon, lat) for lat, lon in points]).is_valid:
            raise GeoError(f"{where}: not a valid polygon (it crosses itself or has no area)")
    else:
        raise GeoError(f"{where}: geometry must be a Point, LineString or Polygon, not {kind}")
    fid = props.pop("featureId", None)
    coverage = props.pop("coverage", None)
    return Feature(-1 if fid is None else int(fid), points, coverage, props)


def feature_to_geojson(feat: Feature) -> dict[str, Any]:
    coords: Any
    pts = [[lon, lat] for lat, lon in feat.points]
    if feat.kind == "Point":
        coords = pts[0]
    elif feat.kind == "LineString":
        coords = pts
    else:
        coords = [[*pts, pts[0]]]
    return {
        "type": "Feature",
        "id": feat.feature_id,
        "geometry": {"type": feat.kind, "coordinates": coords},
        "properties": {**feat.properties, "featureId": feat.feature_id, "coverage": feat.coverage},
    }


def collection(features: list[Feature]) -> dict[str, Any]:
    return {"type": "FeatureCollection", "features": [feature_to_geojson(f) for f in features]}


# ---- IMC -------------------------------------------------------------------------------------


def world_model_message(features: list[Feature]) -> Message:
    return msg(
        "WorldModel",
        geo_features=[
            msg(
                "GeoFeature",
                feature_id=f.feature_id,
                points=[msg("MapPoint", lat=math.radians(lat), lon=math.radians(lon), alt=0.0) for lat, lon in f.points],
            )
            for f in features
        ],
        cov_states=[
            msg("CoverageState", feature_id=f.feature_id, state=Coverage[f.coverage]) for f in features if f.coverage is not None
        ],
    )


def features_from_world_model(m: Message) -> list[Feature]:
    """The features of a received WorldModel; GeoError when a feature has no points or a non-finite or out-of-range
    vertex (the whole model is then refused: C2 counts it in refused_world_models)."""
    out: dict[int, Feature] = {}
    for g in m["geo_features"]:
        pts = [(math.degrees(p["lat"]), math.degrees(p["lon"])) for p in g["points"]]
        if not pts or not all(math.isfinite(a) and math.isfinite(b) and -90 <= a <= 90 and -180 <= b <= 180 for a, b in pts):
            raise GeoError(f"feature {g['feature_id']} has no vertices or one that is not a position")
        out[g["feature_id"]] = Feature(g["feature_id"], open_ring(pts))
    for c in m["cov_states"]:
        if c["feature_id"] in out:
            out[c["feature_id"]].coverage = coverage_name(c["state"])
    return list(out.values())


def coverage_name(state: int) -> str | None:
    try:
        return Coverage(state).name
    except ValueError:
        return None


# ---- vehicle geometry --------------------------------------------------------------------------


class Local:
    """Metres east and north of an origin (equirectangular: fine over a survey area)."""

    def __init__(self, lat0: float, lon0: float) -> None:
        self.lat0, self.lon0, self.k = lat0, lon0, math.cos(math.radians(lat0))

    def xy(self, lat: float, lon: float) -> tuple[float, float]:
        return (lon - self.lon0) * EARTH_M_PER_DEG * self.k, (lat - self.lat0) * EARTH_M_PER_DEG

    def latlon(self, x: float, y: float) -> tuple[float, float]:
        return self.lat0 + y / EARTH_M_PER_DEG, self.lon0 + x / (EARTH_M_PER_DEG * self.k)


def distance_m(a: tuple[float, float], b: tuple[float, float]) -> float:
    x, y = Local(*a).xy(*b)
    return math.hypot(x, y)


def lawnmower(points: list[tuple[float, float]], spacing: float) -> list[tuple[float, float]]:
    """Waypoints (lat, lon) that sweep the feature: east-west lanes `spacing` metres apart inside a
    polygon, boustrophedon; the vertices of a line; the point itself."""
    if len(points) < 3:
        return list(points)
    from shapely.geometry import LineString, MultiLineString, Polygon

    loc = Local(*points[0])
    poly: BaseGeometry = Polygon([loc.xy(*p) for p in points])
    minx, miny, maxx, maxy = poly.bounds
    out: list[tuple[float, float]] = []
    y, lane = miny + spacing / 2, 0
    if y > maxy:
        y = (miny + maxy) / 2
    while y <= maxy:
        cut = poly.intersection(LineString([(minx - 1, y), (maxx + 1, y)]))
        segs = (
            list(cut.geoms)
            if isinstance(cut, MultiLineString)
            else [cut]
            if isinstance(cut, LineString) and not cut.is_empty
            else []
        )
        xs = sorted((min(s.coords[0][0], s.coords[-1][0]), max(s.coords[0][0], s.coords[-1][0])) for s in segs)
        if lane % 2:
            xs = [(b, a) for a, b in reversed(xs)]
        for a, b in xs:
            out += [loc.latlon(a, y), loc.latlon(b, y)]
        y += spacing
        lane += 1
    return out or [loc.latlon(*poly.centroid.coords[0])]


def contains(points: list[tuple[float, float]], lat: float, lon: float) -> bool:
    from shapely.geometry import Point, Polygon

    return bool(Polygon([(b, a) for a, b in points]).contains(Point(lon, lat)))
