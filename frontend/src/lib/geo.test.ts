import { describe, expect, it } from "vitest";
import type { Topology } from "topojson-specification";
import { topoToGeoJson } from "./basemap";
import {
  bearingDeg,
  distanceM,
  distanceText,
  edgeMark,
  framePoints,
  measureGeoJson,
  middle,
  nearestVertex,
  pathLengthM,
  positionText,
  trimTrack,
  validPosition,
} from "./geo";
import { dms } from "./units";

describe("distances", () => {
  it("one degree of longitude on the equator is 111.2 km, east", () => {
    expect(distanceM({ lon: 0, lat: 0 }, { lon: 1, lat: 0 })).toBeCloseTo(111_195, -1);
    expect(bearingDeg({ lon: 0, lat: 0 }, { lon: 1, lat: 0 })).toBeCloseTo(90, 6);
  });
  it("a known pair: Norfolk VA to Bermuda, about 1,250 km", () => {
    const d = distanceM({ lat: 36.8508, lon: -76.2859 }, { lat: 32.3078, lon: -64.7505 });
    expect(d / 1000).toBeGreaterThan(1_150);
    expect(d / 1000).toBeLessThan(1_200);
  });
  it("a path adds its legs; one point is nothing", () => {
    const pts = [
      { lon: 0, lat: 0 },
      { lon: 0, lat: 1 },
      { lon: 0, lat: 2 },
    ];
    expect(pathLengthM(pts)).toBeCloseTo(2 * distanceM(pts[0], pts[1]), 6);
    expect(pathLengthM(pts.slice(0, 1))).toBe(0);
  });
  it("is shown in m or km with nautical miles", () => {
    expect(distanceText(850)).toBe("850 m (0.46 NM)");
    expect(distanceText(1852 * 10)).toBe("18.52 km (10.00 NM)");
    expect(distanceText(NaN)).toBe("—");
  });
});

describe("coordinates", () => {
  it("decimal or DMS with hemispheres", () => {
    expect(positionText(36.8, -76.25, false)).toBe("36.800000° N, 76.250000° W");
    expect(positionText(-0.5, 0.25, true)).toBe("0° 30′ 00.00″ S, 0° 15′ 00.00″ E");
    expect(dms(59.99999999, true)).toBe("60° 00′ 00.00″ N"); // rounding carries into minutes and degrees
    expect(positionText(null, 1, true)).toBe("—");
  });
  it("an out-of-range or missing position is not drawn", () => {
    expect(validPosition(200, 0)).toBeNull();
    expect(validPosition(0, NaN)).toBeNull();
    expect(validPosition(undefined, 0)).toBeNull();
    expect(validPosition(-90, 180)).toEqual({ lat: -90, lon: 180 });
  });
});

describe("GeoJSON for the layers", () => {
  it("tracks keep the last window in time order, one point per time", () => {
    const t = trimTrack(
      [
        { lon: 0, lat: 0, t: 5 },
        { lon: 1, lat: 0, t: 1 },
        { lon: 2, lat: 0, t: 5 },
        { lon: 3, lat: 0, t: 9 },
      ],
      10,
      6,
    );
    expect(t.map((p) => [p.lon, p.t])).toEqual([
      [2, 5],
      [3, 9],
    ]);
  });
  it("the measure path is its points and, from two points on, a line", () => {
    expect(measureGeoJson([{ lon: 0, lat: 0 }]).features).toHaveLength(1);
    expect(
      measureGeoJson([
        { lon: 0, lat: 0 },
        { lon: 1, lat: 1 },
      ]).features.map((f) => f.geometry.type),
    ).toEqual(["Point", "Point", "LineString"]);
  });
});

describe("the offline basemap", () => {
  it("turns a TopoJSON object into GeoJSON (arcs decoded, quantization applied)", () => {
    const topo = {
      type: "Topology",
      transform: { scale: [1, 1], translate: [10, 20] },
      objects: { land: { type: "GeometryCollection", geometries: [{ type: "Polygon", arcs: [[0]] }] } },
      arcs: [
        [
          [0, 0],
          [1, 0],
          [0, 1],
          [-1, -1],
        ],
      ],
    } as unknown as Topology;
    const fc = topoToGeoJson(topo, "land");
    expect(fc.features[0].geometry).toEqual({
      type: "Polygon",
      coordinates: [
        [
          [10, 20],
          [11, 20],
          [11, 21],
          [10, 20],
        ],
      ],
    });
    expect(() => topoToGeoJson(topo, "sea")).toThrow(/no object sea/);
  });
  it("the bundled Natural Earth land has the continents", async () => {
    const land = (await import("world-atlas/land-110m.json")).default as unknown as Topology;
    const fc = topoToGeoJson(land, "land");
    const polygons = fc.features.flatMap((f) =>
      f.geometry.type === "MultiPolygon" ? f.geometry.coordinates : f.geometry.type === "Polygon" ? [f.geometry.coordinates] : [],
    );
    expect(polygons.length).toBeGreaterThan(100);
  });
});

describe("the PMTiles chart", () => {
  it("a vector archive gets a layer set per vector layer, water and land in the basemap's colours", async () => {
    const { chartStyle, vectorLayers } = await import("./chart");
    const { TileType } = await import("pmtiles");
    const meta = { vector_layers: [{ id: "water" }, { id: "roads" }, { id: 3 }] };
    expect(vectorLayers(meta)).toEqual(["water", "roads"]);
    expect(vectorLayers(null)).toEqual([]);
    const s = chartStyle("http://x/api/basemap.pmtiles", { tileType: TileType.Mvt, minZoom: 0, maxZoom: 14 }, meta);
    expect(s.source).toMatchObject({ type: "vector", url: "pmtiles://http://x/api/basemap.pmtiles", maxzoom: 14 });
    expect(s.layers.map((l) => l.id)).toEqual([
      "chart-water-fill",
      "chart-water-line",
      "chart-water-point",
      "chart-roads-fill",
      "chart-roads-line",
      "chart-roads-point",
    ]);
    const r = chartStyle("http://x/c.pmtiles", { tileType: TileType.Png, minZoom: 2, maxZoom: 9 }, null);
    expect(r.source.type).toBe("raster");
    expect(r.layers).toHaveLength(1);
  });
});

describe("CoMap geometry", () => {
  it("1 vertex is a point, 2 a line, 3 or more a closed polygon; a closed ring is the same polygon", async () => {
    const { drawnGeometry } = await import("./geo");
    const a = { lon: 0, lat: 0 },
      b = { lon: 1, lat: 0 },
      c = { lon: 1, lat: 1 };
    expect(drawnGeometry([])).toBeNull();
    expect(drawnGeometry([a])).toEqual({ type: "Point", coordinates: [0, 0] });
    expect(drawnGeometry([a, b])).toEqual({
      type: "LineString",
      coordinates: [
        [0, 0],
        [1, 0],
      ],
    });
    const poly = {
      type: "Polygon",
      coordinates: [
        [
          [0, 0],
          [1, 0],
          [1, 1],
          [0, 0],
        ],
      ],
    };
    expect(drawnGeometry([a, b, c])).toEqual(poly);
    expect(drawnGeometry([a, b, c, a])).toEqual(poly);
  });
  it("an imported file keeps its featureIds and numbers the features without one", async () => {
    const { parseWorldModel, nextFeatureId } = await import("./geo");
    const fc = parseWorldModel(
      JSON.stringify({
        type: "FeatureCollection",
        features: [
          { type: "Feature", geometry: { type: "Point", coordinates: [0, 0] }, properties: { featureId: 7 } },
          { type: "Feature", geometry: { type: "Point", coordinates: [1, 0] }, properties: null },
        ],
      }),
    );
    expect(fc.features.map((f) => f.properties?.featureId)).toEqual([7, 8]);
    expect(fc.features[1].properties?.coverage).toBeNull();
    expect(nextFeatureId(fc)).toBe(9);
    expect(nextFeatureId(null)).toBe(1);
    expect(() => parseWorldModel('{"type": "Feature"}')).toThrow(/FeatureCollection/);
    expect(() => parseWorldModel("not json")).toThrow();
  });
  it("the edit tool's handles are the vertices as drawn, and moving one keeps the geometry's kind and a closed ring", async () => {
    const { drawnGeometry, moveVertex, vertexHandles } = await import("./geo");
    const square = drawnGeometry([
      { lon: 0, lat: 0 },
      { lon: 1, lat: 0 },
      { lon: 1, lat: 1 },
      { lon: 0, lat: 1 },
    ])!;
    const fc = {
      type: "FeatureCollection" as const,
      features: [
        { type: "Feature" as const, geometry: square, properties: { featureId: 3, coverage: "PARTIAL" } },
        { type: "Feature" as const, geometry: { type: "Point" as const, coordinates: [5, 5] }, properties: { featureId: 4 } },
      ],
    };
    const handles = vertexHandles(fc).features;
    expect(handles.map((h) => [h.properties?.featureId, h.properties?.index, h.geometry.coordinates])).toEqual([
      [3, 0, [0, 0]],
      [3, 1, [1, 0]],
      [3, 2, [1, 1]],
      [3, 3, [0, 1]],
      [4, 0, [5, 5]],
    ]);
    const moved = moveVertex(fc, 3, 0, { lon: -1, lat: -1 });
    expect(moved.features[0].geometry).toEqual({
      type: "Polygon",
      coordinates: [
        [
          [-1, -1],
          [1, 0],
          [1, 1],
          [0, 1],
          [-1, -1],
        ],
      ],
    });
    expect(moved.features[0].properties).toEqual({ featureId: 3, coverage: "PARTIAL" });
    expect(moved.features[1]).toBe(fc.features[1]); // the others untouched
    expect(moveVertex(fc, 4, 0, { lon: 6, lat: 7 }).features[1].geometry).toEqual({ type: "Point", coordinates: [6, 7] });
    expect(moveVertex(fc, 3, 9, { lon: 6, lat: 7 }).features[0]).toBe(fc.features[0]); // no such vertex
    expect(moveVertex(fc, 99, 0, { lon: 6, lat: 7 })).toEqual(fc);
    expect(vertexHandles(null).features).toEqual([]);
  });
  it("a moved vertex of a line of 3 or more vertices leaves it a line (not a polygon)", async () => {
    const { moveVertex } = await import("./geo");
    const line = {
      type: "LineString" as const,
      coordinates: [
        [0, 0],
        [1, 0],
        [2, 1],
      ],
    };
    const fc = {
      type: "FeatureCollection" as const,
      features: [{ type: "Feature" as const, geometry: line, properties: { featureId: 1 } }],
    };
    expect(moveVertex(fc, 1, 2, { lon: 3, lat: 3 }).features[0].geometry).toEqual({
      type: "LineString",
      coordinates: [
        [0, 0],
        [1, 0],
        [3, 3],
      ],
    });
  });
  it("a new featureId is above every id used: both models, tasks' features, ids deleted", async () => {
    const { nextFeatureId } = await import("./geo");
    const fc = (...ids: number[]) => ({
      type: "FeatureCollection" as const,
      features: ids.map((featureId) => ({
        type: "Feature" as const,
        geometry: { type: "Point" as const, coordinates: [0, 0] },
        properties: { featureId },
      })),
    });
    expect(nextFeatureId([fc(1, 2), fc(1, 2, 3)])).toBe(4); // #3 deleted in the draft, still in the console's model
    expect(nextFeatureId([fc(1), fc(1)], [5, null, undefined])).toBe(6); // #5 deleted and sent, or a task's feature
    expect(nextFeatureId([null, null], [])).toBe(1);
  });
  it("an edit draft shows and sends the console's coverage by featureId, not the coverage it was copied with", async () => {
    const { withLiveCoverage } = await import("./geo");
    const f = (featureId: number, coverage: string | null, x = 0) => ({
      type: "Feature" as const,
      geometry: { type: "Point" as const, coordinates: [x, 0] },
      properties: { featureId, coverage },
    });
    const draft = { type: "FeatureCollection" as const, features: [f(1, "NONE", 9), f(2, null), f(7, "PARTIAL")] };
    const live = { type: "FeatureCollection" as const, features: [f(1, "COMPLETED"), f(2, "PARTIAL")] };
    const out = withLiveCoverage(draft, live);
    expect(out.features.map((x) => x.properties?.coverage)).toEqual(["COMPLETED", "PARTIAL", null]); // #7 is new: none
    expect(out.features[0].geometry).toEqual({ type: "Point", coordinates: [9, 0] }); // the draft's geometry
    expect(withLiveCoverage(draft, null).features.map((x) => x.properties?.coverage)).toEqual([null, null, null]);
  });
});

describe("the map for a fleet", () => {
  it("an edge mark sits inside the border towards a point outside the view, and points at it", () => {
    expect(edgeMark(50, 40, 100, 80, 10)).toBeNull(); // in view
    expect(edgeMark(100, 80, 100, 80, 10)).toBeNull(); // on the border is in view
    const east = edgeMark(500, 40, 100, 80, 10)!;
    expect(east).toEqual({ x: 90, y: 40, angleDeg: 90 });
    const north = edgeMark(50, -300, 100, 80, 10)!;
    expect(north.x).toBeCloseTo(50, 9);
    expect(north.y).toBeCloseTo(10, 9);
    expect(north.angleDeg).toBeCloseTo(0, 9);
    // south-west, nearer the bottom side than the left one: on the bottom, inset
    const sw = edgeMark(-40, 400, 100, 80, 10)!;
    expect(sw.y).toBeCloseTo(70, 6);
    expect(sw.x).toBeGreaterThan(10);
    expect(sw.x).toBeLessThan(50);
    expect(sw.angleDeg).toBeGreaterThan(180);
    expect(sw.angleDeg).toBeLessThan(270);
    expect(edgeMark(NaN, 0, 100, 80, 10)).toBeNull();
  });
  it("the nearest coast vertex within a distance, else none", () => {
    const coast = {
      type: "FeatureCollection" as const,
      features: [
        {
          type: "Feature" as const,
          properties: {},
          geometry: {
            type: "MultiPolygon" as const,
            coordinates: [
              [
                [
                  [-76, 36],
                  [-75.97, 36.85],
                  [-76.2, 37],
                  [-76, 36],
                ],
              ],
            ],
          },
        },
        {
          type: "Feature" as const,
          properties: {},
          geometry: {
            type: "Polygon" as const,
            coordinates: [
              [
                [10, 10],
                [11, 10],
                [10, 11],
                [10, 10],
              ],
            ],
          },
        },
      ],
    };
    const sea = { lon: -75.7, lat: 36.82 };
    expect(nearestVertex(coast, sea, 60_000)).toEqual({ lon: -75.97, lat: 36.85 });
    expect(nearestVertex(coast, sea, 10_000)).toBeNull(); // 24 km away
    expect(nearestVertex({ type: "FeatureCollection", features: [] }, sea, 1e7)).toBeNull();
  });
  it("the first view frames the vehicles, and the coast with its mirror image across the followed vehicle", () => {
    const vs = [
      { lon: -75.7, lat: 36.8 },
      { lon: -75.66, lat: 36.84 },
    ];
    expect(middle(vs)).toEqual({ lon: -75.68, lat: 36.82 });
    expect(middle([])).toBeNull();
    expect(framePoints(vs, null, vs[0])).toEqual(vs);
    const pts = framePoints(vs, { lon: -76, lat: 36.9 }, vs[0]);
    expect(pts).toHaveLength(4);
    expect(pts[3].lon).toBeCloseTo(-75.4, 9);
    expect(pts[3].lat).toBeCloseTo(36.7, 9);
  });
});
