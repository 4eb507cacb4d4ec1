"""CoMap geometry: the 1/2/3+ vertex rule, closed rings, GeoJSON both ways, lawnmower lanes."""

from __future__ import annotations

import itertools
import math

import pytest

from sem_console.comap.codec import decode_packet, encode_packet
from sem_console.comap.geo import (
    Feature,
    GeoError,
    Local,
    contains,
    feature_from_geojson,
    feature_to_geojson,
    features_from_world_model,
    lawnmower,
    world_model_message,
)

SQUARE = [[-75.70, 36.80], [-75.698, 36.80], [-75.698, 36.8015], [-75.70, 36.8015]]


def gj(kind: str, coords: object, **props: object) -> dict[str, object]:
    return {"type": "Feature", "geometry": {"type": kind, "coordinates": coords}, "properties": props}


def test_vertex_count_makes_the_kind_and_a_closed_ring_is_the_same_polygon() -> None:
    point = feature_from_geojson(gj("Point", [-75.7, 36.8], featureId=1), "f")
    line = feature_from_geojson(gj("LineString", SQUARE[:2], featureId=2), "f")
    open_ = feature_from_geojson(gj("Polygon", [SQUARE], featureId=3), "f")
    closed = feature_from_geojson(gj("Polygon", [[*SQUARE, SQUARE[0]]], featureId=3), "f")
    assert (point.kind, line.kind, open_.kind) == ("Point", "LineString", "Polygon")
    assert open_.points == closed.points and len(closed.points) == 4
    # over IMC: the open ring; back from IMC: the same polygon, GeoJSON closes it
    back = features_from_world_model(decode_packet(encode_packet(world_model_message([point, line, closed]), src=1))[1])
    assert [len(f.points) for f in back] == [1, 2, 4]
    assert [x for p in back[2].points for x in p] == pytest.approx([x for p in closed.points for x in p])
    ring = feature_to_geojson(back[2])["geometry"]["coordinates"][0]
    assert ring[0] == ring[-1] and len(ring) == 5
    # a received closed ring (last vertex = first) is the same polygon too
    closed_imc = Feature(4, [*closed.points, closed.points[0]])
    reopened = features_from_world_model(world_model_message([closed_imc]))[0].points
    assert [x for p in reopened for x in p] == pytest.approx([x for p in closed.points for x in p]) and len(reopened) == 4


@pytest.mark.parametrize(
    "feature",
    [
        gj("Polygon", [[[0, 0], [1, 1], [1, 0], [0, 1]]]),  # crosses itself
        gj("Polygon", [[[0, 0], [1, 1], [0, 0], [0, 0]]]),  # 2 distinct vertices
        gj("Polygon", [SQUARE, SQUARE]),  # a hole
        gj("LineString", SQUARE[:3]),  # 3 vertices are a polygon, not a line
        gj("MultiPoint", SQUARE),
        gj("Point", [200, 0]),
    ],
)
def test_geometry_comap_cannot_carry(feature: dict[str, object]) -> None:
    with pytest.raises(GeoError):
        feature_from_geojson(feature, "f")


def test_lawnmower_sweeps_the_polygon_lane_by_lane() -> None:
    poly = [(lat, lon) for lon, lat in SQUARE]  # about 178 m east-west, 167 m north-south
    lanes = lawnmower(poly, 30.0)
    assert len(lanes) == 2 * 6 and all(contains(poly, *p) or _on_edge(poly, p) for p in lanes)
    loc = Local(*poly[0])
    ys = sorted({round(loc.xy(*p)[1], 3) for p in lanes})
    assert ys[0] == pytest.approx(15.0) and all(b - a == pytest.approx(30.0) for a, b in itertools.pairwise(ys))
    xs = [round(loc.xy(*p)[0]) for p in lanes]
    assert xs[:4] == [0, 178, 178, 0]  # boustrophedon: east, then back west
    assert lawnmower(poly[:2], 30.0) == poly[:2] and lawnmower(poly[:1], 30.0) == poly[:1]


def _on_edge(poly: list[tuple[float, float]], p: tuple[float, float]) -> bool:
    lat0, lon0 = min(a for a, _ in poly), min(b for _, b in poly)
    lat1, lon1 = max(a for a, _ in poly), max(b for _, b in poly)
    return lat0 - 1e-9 <= p[0] <= lat1 + 1e-9 and (
        math.isclose(p[1], lon0, abs_tol=1e-9) or math.isclose(p[1], lon1, abs_tol=1e-9)
    )
