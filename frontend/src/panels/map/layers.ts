// The map's sources and layers (MapLibre style), and what the vehicles' reports become on it.
import { LngLatBounds, type ExpressionSpecification, type GeoJSONSource, type Map as MapLibre } from "maplibre-gl";
import { report, type ProviderView } from "../../data/store";
import { freshness } from "../../lib/freshness";
import { EMPTY, validPosition, type LonLat, type VehicleMark } from "../../lib/geo";
import { radToDeg } from "../../lib/units";
import { shortId } from "../../lib/vehicle";

/** Closest zoom of a frame of the vehicles (a lone vehicle would else fill the map with a few metres of sea). */
const FRAME_MAX_ZOOM = 14;

const FIX_COLOR: ExpressionSpecification = ["match", ["get", "fix"], "valid", "#4caf50", "invalid", "#e0593f", "#9fb3c8"];

export function vehicleMark(p: ProviderView, now: number, selected: string | null): VehicleMark | null {
  const fix = report(p, "GPSFixReport");
  const st = report(p, "GPSFixStatusReport");
  const g = fix?.position2DWithTime?.geodeticPosition;
  const position = validPosition(g?.geodeticLatitude?.latitude, g?.geodeticLongitude?.longitude);
  if (!position) return null;
  const view = p.topics.GPSFixReport;
  const f = view ? freshness(Math.max(0, now - view.at), "GPSFixReport", view.interval, p.link) : "none";
  const link = p.link === "lost" || f === "lost" ? "lost" : f === "stale" ? "stale" : p.link === "regained" ? "regained" : "live";
  const course = typeof fix?.trueCourse === "number" && Number.isFinite(fix.trueCourse) ? ((radToDeg(fix.trueCourse) % 360) + 360) % 360 : null;
  return {
    id: p.id,
    label: p.name ?? shortId(p.id), // on the map: the name, or the short id of a vehicle without one
    position,
    courseDeg: course,
    fix: st?.fixValid === true ? "valid" : st?.fixValid === false ? "invalid" : "unknown",
    gpsPosition: fix?.GPSLatLongValid ?? null,
    link,
    selected: p.id === selected,
  };
}

export function originOf(p: ProviderView): LonLat | null {
  const o = report(p, "GPSFixStatusReport")?.originPosition?.geodeticPosition;
  return validPosition(o?.geodeticLatitude?.latitude, o?.geodeticLongitude?.longitude);
}

/** A course arrow as an SDF image (coloured by the layer), pointing up (north) at rotation 0. */
function arrowImage(size = 32): ImageData {
  const c = document.createElement("canvas");
  c.width = c.height = size;
  const g = c.getContext("2d")!;
  g.fillStyle = "#fff";
  g.beginPath();
  g.moveTo(size / 2, 1);
  g.lineTo(size - 5, size - 3);
  g.lineTo(size / 2, size * 0.7);
  g.lineTo(5, size - 3);
  g.closePath();
  g.fill();
  return g.getImageData(0, 0, size, size);
}

export function source(map: MapLibre, id: string): GeoJSONSource | undefined {
  return map.getSource(id) as GeoJSONSource | undefined;
}

export function addLayers(map: MapLibre): void {
  for (const id of ["worldmodel", "tracks", "origins", "vehicles", "selected", "measure", "handles"]) map.addSource(id, { type: "geojson", data: EMPTY });
  map.addImage("course-arrow", arrowImage(), { sdf: true });
  map.addLayer({ id: "wm-fill", type: "fill", source: "worldmodel", filter: ["==", ["geometry-type"], "Polygon"], paint: { "fill-color": ["get", "color"], "fill-opacity": 0.25 } });
  map.addLayer({ id: "wm-line", type: "line", source: "worldmodel", paint: { "line-color": ["get", "color"], "line-width": ["case", ["get", "picked"], 5, 2] } });
  map.addLayer({ id: "wm-point", type: "circle", source: "worldmodel", filter: ["==", ["geometry-type"], "Point"], paint: { "circle-color": ["get", "color"], "circle-radius": 5 } });
  map.addLayer({
    id: "tracks",
    type: "line",
    source: "tracks",
    paint: { "line-color": ["get", "color"], "line-width": ["case", ["get", "selected"], 2.5, 1.5], "line-opacity": 0.8 },
  });
  map.addLayer({
    id: "origins",
    type: "circle",
    source: "origins",
    paint: { "circle-radius": 4, "circle-color": "#0000", "circle-stroke-color": ["get", "color"], "circle-stroke-width": 2 },
  });
  // the fleet, then the selected vehicle on top, in a source of its own: it moves on every frame after its fix, and
  // updating a one-feature source does not make MapLibre's worker lay out the whole fleet again
  addVehicleLayers(map, "vehicle", "vehicles");
  addVehicleLayers(map, "selected", "selected");
  map.addLayer({ id: "measure-line", type: "line", source: "measure", paint: { "line-color": "#fff", "line-width": 2, "line-dasharray": [2, 2] } });
  map.addLayer({ id: "measure-point", type: "circle", source: "measure", filter: ["==", ["geometry-type"], "Point"], paint: { "circle-radius": 4, "circle-color": "#fff" } });
  // the edit tool's vertex handles, dragged to move a vertex
  map.addLayer({ id: "edit-handle", type: "circle", source: "handles", paint: { "circle-radius": 6, "circle-color": "#fff", "circle-stroke-color": "#1e88e5", "circle-stroke-width": 2 } });
}

/** The layers that draw `source`'s vehicles: `<prefix>-link` (a ring when stale or lost), `-dot`, `-arrow` (course). */
function addVehicleLayers(map: MapLibre, prefix: string, source: string): void {
  map.addLayer({
    id: `${prefix}-link`,
    type: "circle",
    source,
    filter: ["in", ["get", "link"], ["literal", ["stale", "lost"]]],
    paint: {
      "circle-radius": 15,
      "circle-color": "#0000",
      "circle-stroke-width": 2,
      "circle-stroke-color": ["match", ["get", "link"], "lost", "#e0593f", "#f5a623"],
    },
  });
  map.addLayer({
    id: `${prefix}-dot`,
    type: "circle",
    source,
    paint: {
      "circle-radius": ["case", ["get", "selected"], 9, 7],
      "circle-color": FIX_COLOR,
      "circle-opacity": ["case", ["==", ["get", "link"], "lost"], 0.4, 1],
      "circle-stroke-color": ["case", ["get", "selected"], "#ffffff", ["get", "color"]],
      "circle-stroke-width": ["case", ["get", "selected"], 3, 2],
    },
  });
  map.addLayer({
    id: `${prefix}-arrow`,
    type: "symbol",
    source,
    filter: ["get", "hasCourse"],
    layout: {
      "icon-image": "course-arrow",
      "icon-rotate": ["get", "course"],
      "icon-rotation-alignment": "map",
      "icon-allow-overlap": true,
      "icon-ignore-placement": true,
      "icon-offset": [0, -20],
      "icon-size": 0.7,
    },
    paint: { "icon-color": FIX_COLOR, "icon-halo-color": "#000", "icon-halo-width": 1 },
  });
}

/** The layers a click on a vehicle hits, and that count the vehicles drawn. */
export const VEHICLE_DOTS = ["vehicle-dot", "selected-dot"];
export const VEHICLE_HITS = ["vehicle-dot", "vehicle-arrow", "selected-dot", "selected-arrow"];

/** The view that takes in every point (a jump: an animation would redraw the map every frame). */
export function fitAll(map: MapLibre, points: LonLat[]): void {
  if (!points.length) return;
  const b = new LngLatBounds();
  for (const p of points) b.extend([p.lon, p.lat]);
  map.fitBounds(b, { padding: 60, maxZoom: FRAME_MAX_ZOOM, duration: 0 });
}
