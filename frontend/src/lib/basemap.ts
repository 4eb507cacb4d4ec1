// The built-in offline basemap: land and coastlines from Natural Earth 1:50m (world-atlas, TopoJSON),
// bundled into the dashboard. The style names no glyphs, sprite or remote source, so the map
// requests nothing from any origin; the land data is a chunk of the build, loaded from the console.
import type { Map as MapLibre, StyleSpecification } from "maplibre-gl";
import type { FeatureCollection } from "geojson";
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
  return topoToGeoJson(topo, "land");
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
