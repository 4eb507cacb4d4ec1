// The built-in offline basemap: land and coastlines from Natural Earth 1:50m (world-atlas, TopoJSON),
// bundled into the dashboard. The style names no glyphs, sprite or remote source, so the map
// requests nothing from any origin; the land data is a chunk of the build, loaded from the console.
import type { StyleSpecification } from "maplibre-gl";
import type { FeatureCollection } from "geojson";
import type { GeometryCollection, Topology } from "topojson-specification";
import { feature } from "topojson-client";
import { EMPTY } from "./geo";

export const WATER = "#0d2233";
export const LAND = "#26313b";
export const COAST = "#5d7386";

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

/** The offline style: water background, land fill, coastline; a PMTiles chart (when the console has one) on top. */
export function offlineStyle(): StyleSpecification {
  return {
    version: 8,
    name: "SEM Console offline",
    sources: {
      land: { type: "geojson", data: EMPTY, attribution: "Natural Earth" },
    },
    layers: [
      { id: "water", type: "background", paint: { "background-color": WATER } },
      { id: "land", type: "fill", source: "land", paint: { "fill-color": LAND } },
      { id: "coastline", type: "line", source: "land", paint: { "line-color": COAST, "line-width": 0.8 } },
    ],
  };
}
