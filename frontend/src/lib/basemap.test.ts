import { describe, expect, it } from "vitest";
import type { FeatureCollection, Position } from "geojson";
import { loadLand, unwrapAntimeridian } from "./basemap";
import { nearestVertex } from "./geo";

const polygons = (...rings: Position[][]): FeatureCollection => ({
  type: "FeatureCollection",
  features: [{ type: "Feature", properties: {}, geometry: { type: "MultiPolygon", coordinates: rings.map((r) => [r]) } }],
});
const ringsOf = (fc: FeatureCollection): Position[][] =>
  fc.features.flatMap((f) =>
    f.geometry.type === "MultiPolygon"
      ? f.geometry.coordinates.flat()
      : f.geometry.type === "Polygon"
        ? f.geometry.coordinates
        : [],
  );
/** The longest step in longitude between two neighbours of `ring`. */
const longestStep = (ring: Position[]): number => Math.max(0, ...ring.slice(1).map((p, i) => Math.abs(p[0] - ring[i][0])));

describe("unwrapAntimeridian", () => {
  it("continues a ring that steps across the antimeridian past 180°, where most of it lies", () => {
    const east = [
      [170, 0],
      [179, 0],
      [-179, 0],
      [-179, 1],
      [179, 1],
      [170, 1],
      [170, 0],
    ];
    expect(ringsOf(unwrapAntimeridian(polygons(east)))[0]).toEqual([
      [170, 0],
      [179, 0],
      [181, 0],
      [181, 1],
      [179, 1],
      [170, 1],
      [170, 0],
    ]);
    // starting on the far side (as Eurasia's ring starts in Chukotka): moved back to where most of it is
    const west = [
      [-179, 0],
      [179, 0],
      [150, 0],
      [150, 1],
      [179, 1],
      [-179, 1],
      [-179, 0],
    ];
    expect(ringsOf(unwrapAntimeridian(polygons(west)))[0]).toEqual([
      [181, 0],
      [179, 0],
      [150, 0],
      [150, 1],
      [179, 1],
      [181, 1],
      [181, 0],
    ]);
  });

  it("leaves a ring round a pole and a ring that does not cross as they are", () => {
    const pole = [
      [-180, -80],
      [0, -70],
      [180, -80],
      [180, -90],
      [-180, -90],
      [-180, -80],
    ];
    const plain = [
      [0, 0],
      [1, 0],
      [1, 1],
      [0, 0],
    ];
    expect(ringsOf(unwrapAntimeridian(polygons(pole, plain)))).toEqual([pole, plain]);
  });

  it("leaves no edge across the whole world in Natural Earth's land but round the South Pole", async () => {
    const raw = ringsOf(await loadLandRaw());
    expect(raw.filter((r) => longestStep(r) > 180).length).toBeGreaterThan(2); // what the map drew as bands
    const crossing = ringsOf(await loadLand()).filter((r) => longestStep(r) > 180);
    expect(crossing.every((r) => Math.max(...r.map((p) => p[1])) < -60)).toBe(true); // Antarctica's rings only
  });

  it("finds the nearest coast the short way round the antimeridian", async () => {
    // just east of 180° off Wrangel Island, whose ring now runs on past -180° there: its coast is 3 km away
    const near = nearestVertex(await loadLand(), { lon: 179.9, lat: 71.0 }, 10_000);
    expect(near).not.toBeNull();
    expect(near!.lon).toBeLessThan(-180); // that side of its ring, reached the short way round
  });
});

async function loadLandRaw(): Promise<FeatureCollection> {
  const { topoToGeoJson } = await import("./basemap");
  const topo = (await import("world-atlas/land-50m.json")).default as unknown as Parameters<typeof topoToGeoJson>[0];
  return topoToGeoJson(topo, "land");
}
