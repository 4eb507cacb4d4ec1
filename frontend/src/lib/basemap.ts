// The built-in offline basemap: land and coastlines from Natural Earth 1:50m (world-atlas, TopoJSON),
// bundled into the dashboard. The style names no glyphs, sprite or remote source, so the map
// requests nothing from any origin; the land data is a chunk of the build, loaded from the console.
import type { Map as MapLibre, StyleSpecification } from "maplibre-gl";
import type { FeatureCollection, Position } from "geojson";
import type { GeometryCollection, Topology } from "topojson-specification";
import { feature } from "topojson-client";
import { EMPTY } from "./geo";

export const WATER = "#0d2233";
export const LAND = "#26313b";
export const COAST = "#5d7386";

/** The basemap's colours per theme: the dark ones above for the night; pale sea, sand-grey land and a
 * darker coastline for daylight. */
export const PALETTES = {
  dark: { water: WATER, land: LAND, coast: COAST },
  light: { water: "#b9d3e6", land: "#e9e5d8", coast: "#6f8190" },
} as const;
export type Palette = (typeof PALETTES)[keyof typeof PALETTES];

/** TopoJSON object `name` of a topology as a GeoJSON FeatureCollection. */
export function topoToGeoJson(topology: Topology, name: string): FeatureCollection {
  const obj = topology.objects[name];
  if (!obj) throw new Error(`no object ${name} in the topology`);
  return feature(topology, obj as GeometryCollection);
}

/** Natural Earth land, loaded from the build (a separate chunk, so the first paint does not wait for it). */
export async function loadLand(): Promise<FeatureCollection> {
  const topo = (await import("world-atlas/land-50m.json")).default as unknown as Topology;
  return unwrapAntimeridian(topoToGeoJson(topo, "land"));
}

/** `fc` with each ring that steps across the antimeridian made continuous past ±180°. world-atlas is drawn for d3's
 * sphere, where a ring may step from -180° to 180° (Eurasia's at Chukotka, Wrangel Island's, a Fiji island's); on
 * MapLibre's flat map each step is an edge across the whole world, and the land's triangulation filled bands of sea at
 * those latitudes with land (and a wedge of the North Sea at zoom 2). A ring is kept where most of it lies (MapLibre
 * draws the world's copies); a ring round a pole (Antarctica's, which comes back shifted a whole turn) is left as is. */
export function unwrapAntimeridian(fc: FeatureCollection): FeatureCollection {
  const ring = (r: Position[]): Position[] => {
    let shift = 0;
    let stepped = false;
    const out = r.map((p, i) => {
      if (i > 0) {
        const step = p[0] - r[i - 1][0];
        if (Math.abs(step) > 180) {
          shift -= Math.sign(step) * 360;
          stepped = true;
        }
      }
      return [p[0] + shift, p[1]];
    });
    if (!stepped || shift !== 0) return r; // no step, or round a pole
    const lons = out.map((p) => p[0]);
    const middle = (Math.min(...lons) + Math.max(...lons)) / 2;
    const back = middle > 180 ? -360 : middle < -180 ? 360 : 0;
    return back ? out.map(([lon, lat]) => [lon + back, lat]) : out;
  };
  const polygon = (rings: Position[][]): Position[][] => rings.map(ring);
  return {
    ...fc,
    features: fc.features.map((f) => {
      const g = f.geometry;
      if (g.type === "Polygon") return { ...f, geometry: { ...g, coordinates: polygon(g.coordinates) } };
      if (g.type === "MultiPolygon") return { ...f, geometry: { ...g, coordinates: g.coordinates.map(polygon) } };
      return f;
    }),
  };
}

/** The offline style: the water's background alone. Its land (a GeoJSON source, empty until the land is loaded)
 * is added by addLand once the map has loaded: a source in the style holds the map's `load` back for its round trips
 * to MapLibre's worker and their frames. */
export function offlineStyle(palette: Palette = PALETTES.dark): StyleSpecification {
  return {
    version: 8,
    name: "SEM Console offline",
    sources: {},
    layers: [{ id: "water", type: "background", paint: { "background-color": palette.water } }],
  };
}

/** The land fill and coastline over the water (a PMTiles chart, when the console has one, goes on top). */
export function addLand(map: Pick<MapLibre, "addSource" | "addLayer">, palette: Palette): void {
  map.addSource("land", { type: "geojson", data: EMPTY, attribution: "Natural Earth" });
  map.addLayer({ id: "land", type: "fill", source: "land", paint: { "fill-color": palette.land } });
  map.addLayer({ id: "coastline", type: "line", source: "land", paint: { "line-color": palette.coast, "line-width": 0.8 } });
}

/** Recolour a map drawn with offlineStyle for another theme: three paint properties, no reload of the style or data. */
export function setPalette(map: Pick<MapLibre, "getLayer" | "setPaintProperty">, palette: Palette): void {
  if (!map.getLayer("water")) return;
  map.setPaintProperty("water", "background-color", palette.water);
  map.setPaintProperty("land", "fill-color", palette.land);
  map.setPaintProperty("coastline", "line-color", palette.coast);
}
