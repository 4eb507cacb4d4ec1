// The optional offline chart: a PMTiles file the console serves (sem-console --basemap), read in the
// browser with HTTP range requests by the pmtiles package through MapLibre's pmtiles:// protocol.
import type { LayerSpecification, SourceSpecification } from "maplibre-gl";
import { TileType, type Header } from "pmtiles";
import { COAST, LAND, WATER } from "./basemap";

export const CHART_PATH = "/api/basemap.pmtiles";
export const CHART_SOURCE = "chart";

interface VectorLayer {
  id: string;
}

/** The vector layers a PMTiles file's metadata lists (tippecanoe and Protomaps builds both write `vector_layers`). */
export function vectorLayers(metadata: unknown): string[] {
  const list = (metadata as { vector_layers?: VectorLayer[] } | null)?.vector_layers;
  return Array.isArray(list) ? list.map((l) => l?.id).filter((id): id is string => typeof id === "string") : [];
}

const colour = (layer: string): string =>
  /water|ocean|sea|lake|river/i.test(layer)
    ? WATER
    : /earth|land(?!use)|coast/i.test(layer)
      ? LAND
      : /road|transport|transit/i.test(layer)
        ? "#6b7886"
        : "#3a4856";

/** Source and layers that draw a chart: a raster archive as a raster layer; a vector one (MVT) with a
 * plain style for every vector layer (areas filled, lines, points), water and land in the basemap's colours. */
export function chartStyle(
  url: string,
  header: Pick<Header, "tileType" | "minZoom" | "maxZoom">,
  metadata: unknown,
): { source: SourceSpecification; layers: LayerSpecification[] } {
  const base = { url: `pmtiles://${url}`, minzoom: header.minZoom, maxzoom: header.maxZoom, attribution: "offline chart" };
  if (header.tileType !== TileType.Mvt) {
    return {
      source: { type: "raster", tileSize: 256, ...base },
      layers: [{ id: "chart-raster", type: "raster", source: CHART_SOURCE }],
    };
  }
  const layers: LayerSpecification[] = [];
  for (const id of vectorLayers(metadata)) {
    const c = colour(id);
    layers.push(
      {
        id: `chart-${id}-fill`,
        type: "fill",
        source: CHART_SOURCE,
        "source-layer": id,
        filter: ["==", ["geometry-type"], "Polygon"],
        paint: { "fill-color": c, "fill-opacity": 0.9 },
      },
      {
        id: `chart-${id}-line`,
        type: "line",
        source: CHART_SOURCE,
        "source-layer": id,
        paint: { "line-color": c === WATER || c === LAND ? COAST : c, "line-width": 0.8 },
      },
      {
        id: `chart-${id}-point`,
        type: "circle",
        source: CHART_SOURCE,
        "source-layer": id,
        filter: ["==", ["geometry-type"], "Point"],
        paint: { "circle-radius": 2, "circle-color": "#9fb3c8" },
      },
    );
  }
  return { source: { type: "vector", ...base }, layers };
}
