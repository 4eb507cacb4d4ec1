import { describe, expect, it } from "vitest";
import type { VehicleMark } from "../../lib/geo";
import {
  CLUSTER_CELL,
  clustered,
  countInView,
  hitCluster,
  hitVehicle,
  mercator,
  nearestCopy,
  outsideMiddle,
  place,
  placeProjection,
  similarity,
  thinned,
  unwrapped,
} from "./fleet";
import { destination } from "../../lib/geo";
import { countLandInView, landRings } from "./layers";

const mark = (id: string, lon: number, lat: number, courseDeg: number | null = null, selected = false): VehicleMark => ({
  id,
  label: id,
  position: { lon, lat },
  courseDeg,
  fix: "valid",
  gpsPosition: true,
  link: "live",
  selected,
  alarmed: false,
  projection: null,
  heardS: null,
  plannedUntil: null,
});

// a view of 1000 x 500 px, north up, 1 px per 1e-6 of Mercator's unit square, its top left at mercator(0, 0)
const m0 = mercator({ lon: 0, lat: 0 });
const northUp = similarity(m0, { x: 0, y: 0 }, { x: m0.x + 1e-3, y: m0.y + 5e-4 }, { x: 1000, y: 500 });

describe("the fleet's canvas", () => {
  it("projects as Web Mercator: the equator and the antimeridian at the unit square's middle and edge", () => {
    expect(mercator({ lon: 0, lat: 0 })).toEqual({ x: 0.5, y: 0.5 });
    expect(mercator({ lon: -180, lat: 0 }).x).toBe(0);
    expect(mercator({ lon: 0, lat: 85.051129 }).y).toBeCloseTo(0, 6);
  });

  it("maps Mercator to the screen by two known points, rotation included", () => {
    expect(northUp({ x: m0.x + 5e-4, y: m0.y + 2.5e-4 })).toMatchObject({ x: expect.closeTo(500, 6), y: expect.closeTo(250, 6) });
    // a map turned 90° (east up): a point east of A is above it on the screen
    const east = similarity({ x: 0, y: 0 }, { x: 100, y: 100 }, { x: 1, y: 0 }, { x: 100, y: 0 });
    expect(east({ x: 0.5, y: 0 })).toMatchObject({ x: expect.closeTo(100, 9), y: expect.closeTo(50, 9) });
    expect(east({ x: 0, y: 1 })).toMatchObject({ x: expect.closeTo(200, 9), y: expect.closeTo(100, 9) });
  });

  it("puts a course arrow ahead of its dot along the course, turned with the map", () => {
    const [v] = place([mark("a", 0, 0, 90)], () => ({ x: 100, y: 100 }), 0);
    expect(v.arrow).toMatchObject({ x: expect.closeTo(114, 9), y: expect.closeTo(100, 9) }); // east: right
    const [turned] = place([mark("a", 0, 0, 90)], () => ({ x: 100, y: 100 }), 90);
    expect(turned.arrow).toMatchObject({ x: expect.closeTo(100, 9), y: expect.closeTo(86, 9) }); // east up: up
    expect(place([mark("a", 0, 0)], () => ({ x: 0, y: 0 }), 0)[0].arrow).toBeNull();
  });

  it("draws a vehicle over the antimeridian at the world's copy nearest the map's centre, and a track the short way", () => {
    // the map centred on 179°E, 1 px per 1e-6 of the unit square: a vehicle at 179°W is 2° (5556 px) east, not 358° west
    const c = mercator({ lon: 179, lat: 0 });
    const toScreen = similarity(c, { x: 0, y: 0 }, { x: c.x + 1, y: c.y }, { x: 1e6, y: 0 });
    const [v] = place([mark("a", -179, 0)], toScreen, 0, c.x);
    expect(v.at.x).toBeCloseTo((2 / 360) * 1e6, 3);
    expect(nearestCopy({ x: 0.2, y: 0.5 }, 0.6)).toEqual({ x: 0.2, y: 0.5 });
    // a track from 179°E to 179°W: its second point just east of its first
    const [a, b] = unwrapped([mercator({ lon: 179, lat: 0 }), mercator({ lon: -179, lat: 0 })]);
    expect(b.x - a.x).toBeCloseTo(2 / 360, 9);
  });

  it("hits the vehicle whose dot or arrow the pointer is on, the nearest of two, and none beside them", () => {
    const placed = place([mark("a", 0, 0, 0), mark("b", 0, 0)], (m) => (m.x === 0.5 ? { x: 100, y: 100 } : { x: 0, y: 0 }), 0);
    placed[1].at = { x: 110, y: 100 }; // b's dot beside a's
    expect(hitVehicle(placed, { x: 101, y: 100 })).toBe("a");
    expect(hitVehicle(placed, { x: 108, y: 101 })).toBe("b");
    expect(hitVehicle(placed, { x: 100, y: 86 })).toBe("a"); // a's arrow, north of its dot
    expect(hitVehicle(placed, { x: 100, y: 130 })).toBeNull();
  });

  it("counts the vehicles whose dot is on the screen", () => {
    const placed = place([mark("in", 0, 0), mark("edge", 0, 0), mark("out", 0, 0)], () => ({ x: 0, y: 0 }), 0);
    placed[0].at = { x: 50, y: 50 };
    placed[1].at = { x: -5, y: 50 }; // half on the screen
    placed[2].at = { x: 50, y: 600 };
    expect(countInView(placed, 100, 100)).toBe(2);
  });

  it("thins a track to points a pixel apart, keeping its ends", () => {
    const pts = [0, 0.2, 0.4, 1.5, 1.6, 1.7].map((x) => ({ x, y: 0 }));
    expect(thinned(pts, 1).map((p) => p.x)).toEqual([0, 1.5, 1.7]);
  });

  it("centres a followed vehicle again only outside the middle half of the map", () => {
    expect(outsideMiddle({ x: 500, y: 250 }, 1000, 500)).toBe(false);
    expect(outsideMiddle({ x: 740, y: 360 }, 1000, 500)).toBe(false);
    expect(outsideMiddle({ x: 760, y: 250 }, 1000, 500)).toBe(true);
    expect(outsideMiddle({ x: 500, y: 10 }, 1000, 500)).toBe(true);
  });

  it("counts the land's polygons in view: a vertex in it, or around its middle; each part of a multipolygon its own", () => {
    const square = (w: number, s: number, size = 1) => [
      [
        [w, s],
        [w + size, s],
        [w + size, s + size],
        [w, s + size],
        [w, s],
      ],
    ];
    // a C open to the east: its box covers 0..10 x 0..10, its land only the edges
    const c = [
      [
        [0, 0],
        [10, 0],
        [10, 2],
        [2, 2],
        [2, 8],
        [10, 8],
        [10, 10],
        [0, 10],
        [0, 0],
      ],
    ];
    const rings = landRings({
      type: "FeatureCollection",
      features: [
        { type: "Feature", properties: {}, geometry: { type: "Polygon", coordinates: c } },
        { type: "Feature", properties: {}, geometry: { type: "MultiPolygon", coordinates: [square(-170, 0), square(170, 0)] } },
        { type: "Feature", properties: {}, geometry: { type: "Polygon", coordinates: square(40, 40, 20) } },
      ],
    });
    expect(rings).toHaveLength(4);
    expect(countLandInView(rings, { west: 4, south: 4, east: 8, north: 6 })).toBe(0); // the C's bay: sea
    expect(countLandInView(rings, { west: -1, south: 4, east: 3, north: 6 })).toBe(1); // its back
    expect(countLandInView(rings, { west: 45, south: 45, east: 50, north: 50 })).toBe(1); // inside a large one
    expect(countLandInView(rings, { west: 165, south: -5, east: 195, north: 5 })).toBe(2); // over the antimeridian
    expect(countLandInView(rings, { west: -200, south: -80, east: 200, north: 80 })).toBe(4); // the whole world
  });
});

describe("a lost vehicle's projection on the screen", () => {
  // the view above: 1 px is 1e-6 of the world's 2πR = 40,030,174 m round the equator, 40.03 m
  const PX_M = 40.030174;
  it("goes from the last report to the projected point, its circle's radius in px at the map's scale", () => {
    const from = { lon: 0, lat: 0 };
    const at = destination(from, 90, 100 * PX_M);
    const p = placeProjection({ kind: "projected", from, at, radiusM: 10 * PX_M, seconds: 60 }, northUp, 0.5, 7);
    expect(p.from.x).toBeCloseTo(0, 6);
    expect(p.at.x).toBeCloseTo(100, 3);
    expect(p.at.y).toBeCloseTo(0, 6);
    expect(p.r).toBeCloseTo(10, 3);
    // a circle smaller than the ghost is drawn at the ghost's size
    expect(placeProjection({ kind: "projected", from, at, radiusM: PX_M, seconds: 1 }, northUp, 0.5, 7).r).toBe(7);
  });
  it("across the antimeridian the line goes the short way, not round the world", () => {
    const from = { lon: 179.9999, lat: 0 };
    const at = destination(from, 90, 50 * PX_M); // past 180°: at about -179.9997°
    expect(at.lon).toBeLessThan(0);
    const p = placeProjection({ kind: "projected", from, at, radiusM: 10 * PX_M, seconds: 60 }, northUp, 1, 7);
    expect(p.at.x - p.from.x).toBeCloseTo(50, 3);
  });

  it("draws vehicles close together on the screen as one cluster, and keeps the selected, alarmed and lost ones apart", () => {
    // twelve vehicles within one cell, three of them the selected, one in alarm and one lost; one far away
    const marks = Array.from({ length: 12 }, (_, i) => mark(`v${i}`, 0, 0));
    marks[0] = { ...marks[0], selected: true };
    marks[1] = { ...marks[1], alarmed: true };
    marks[2] = { ...marks[2], link: "lost" };
    const placed = marks.map((m, i) => ({
      mark: m,
      at: { x: 100 + (i % 4) * 5, y: 100 + Math.floor(i / 4) * 5 },
      r: 7,
      arrow: null,
      angle: 0,
    }));
    placed.push({ mark: mark("far", 0, 0), at: { x: 100 + 3 * CLUSTER_CELL, y: 100 }, r: 7, arrow: null, angle: 0 });
    const { singles, clusters } = clustered(placed);
    expect(clusters).toHaveLength(1);
    expect(clusters[0].ids.sort()).toEqual(["v10", "v11", "v3", "v4", "v5", "v6", "v7", "v8", "v9"].sort());
    expect(singles.map((v) => v.mark.id)).toEqual(["far", "v0", "v1", "v2"]); // the kept-apart ones drawn last, on top
    expect(hitCluster(clusters, clusters[0].at)).toBe(clusters[0]);
    expect(hitCluster(clusters, { x: 0, y: 0 })).toBeNull();
    // four close together are not a cluster: each is drawn
    expect(clustered(placed.slice(3, 7)).clusters).toHaveLength(0);
    // at the map's closest zoom a cluster's click could not draw its vehicles apart: each is drawn on its own there
    const closest = clustered(placed, false);
    expect(closest.clusters).toHaveLength(0);
    expect(closest.singles).toHaveLength(placed.length);
  });
});
