// The map's sources and layers (MapLibre style), and what the vehicles' reports become on it.
import { LngLatBounds, type GeoJSONSource, type Map as MapLibre } from "maplibre-gl";
import type { FeatureCollection, Position } from "geojson";
import type { PlannedSilence } from "../../api/generated/ws";
import { lastHeardAt, report, type ProviderView } from "../../data/slices/vehicles";
import { plannedUntil } from "../../data/slices/alarms";
import { freshness } from "../../lib/freshness";
import { EMPTY, validPosition, wrapLon, type LonLat, type VehicleMark } from "../../lib/geo";
import { deadReckon } from "../../lib/projection";
import { isNum, radToDeg } from "../../lib/units";
import { invalidFor } from "../../components/Panel";
import { memberNotReported } from "../../lib/labels";
import { shortId } from "../../lib/vehicle";

/** Closest zoom of a frame of the vehicles (a lone vehicle would else fill the map with a few metres of sea). */
const FRAME_MAX_ZOOM = 14;

/** `alarmed`: the vehicles with an unacknowledged alarm; `receiving`: the page hears the console (else nothing is
 * current: drawn stale); `silences`: the planned silences in force; `paceS`: the console sends its reports at most this
 * often (a vehicle the page does not draw: `paceOf`), so it is stale only once silent that much longer. */
export function vehicleMark(
  p: ProviderView,
  now: number,
  selected: string | null,
  alarmed: ReadonlySet<string>,
  receiving: boolean,
  silences: readonly PlannedSilence[],
  paceS = 0,
): VehicleMark | null {
  const fix = report(p, "GPSFixReport");
  const st = report(p, "GPSFixStatusReport");
  const g = fix?.position2DWithTime?.geodeticPosition;
  const position = validPosition(g?.geodeticLatitude?.latitude, g?.geodeticLongitude?.longitude);
  if (!position) return null;
  const view = p.topics.GPSFixReport;
  const f = view ? freshness(Math.max(0, now - view.at), "GPSFixReport", view.interval, p.link, receiving, paceS) : "none";
  const link =
    p.link === "lost" || f === "lost"
      ? "lost"
      : f === "stale" || f === "unreachable"
        ? "stale"
        : p.link === "regained"
          ? "regained"
          : "live";
  const course =
    typeof fix?.trueCourse === "number" && Number.isFinite(fix.trueCourse)
      ? ((radToDeg(fix.trueCourse) % 360) + 360) % 360
      : null;
  const fixValid = st?.fixValid === true;
  // lost: where it may be now, from its last fix (a speed or course the vehicle flagged invalid is not used)
  const invalid = view?.envelope.invalid;
  const speed = isNum(fix?.SOG) && !invalidFor(invalid, "SOG") ? fix.SOG : null;
  const projection =
    link === "lost" && view
      ? deadReckon(
          {
            at: position,
            speedMps: speed,
            courseDeg: invalidFor(invalid, "trueCourse") ? null : course,
            gpsFix: fixValid && fix?.GPSLatLongValid === true,
            noSpeed: memberNotReported(p.umaaVersion, "GPSFixReport", "SOG"),
          },
          now - view.at,
        )
      : null;
  return {
    id: p.id,
    label: p.name ?? shortId(p.id), // on the map: the name, or the short id of a vehicle without one
    position,
    courseDeg: course,
    fix: fixValid ? "valid" : st?.fixValid === false ? "invalid" : "unknown",
    gpsPosition: fix?.GPSLatLongValid ?? null,
    link,
    selected: p.id === selected,
    alarmed: alarmed.has(p.id),
    projection,
    heardS: link === "lost" ? Math.max(0, now - (lastHeardAt(p) ?? now)) : null,
    plannedUntil: plannedUntil(silences, p.id, link),
  };
}

export function originOf(p: ProviderView): LonLat | null {
  const o = report(p, "GPSFixStatusReport")?.originPosition?.geodeticPosition;
  return validPosition(o?.geodeticLatitude?.latitude, o?.geodeticLongitude?.longitude);
}

export function source(map: MapLibre, id: string): GeoJSONSource | undefined {
  return map.getSource(id) as GeoJSONSource | undefined;
}

/** The map's own sources and layers: the world model, the tools' points and the edit tool's handles (the fleet is
 * drawn on a canvas of its own over the map: FleetCanvas.ts). */
export function addLayers(map: MapLibre): void {
  for (const id of ["worldmodel", "measure", "handles"]) map.addSource(id, { type: "geojson", data: EMPTY });
  map.addLayer({
    id: "wm-fill",
    type: "fill",
    source: "worldmodel",
    filter: ["==", ["geometry-type"], "Polygon"],
    paint: { "fill-color": ["get", "color"], "fill-opacity": 0.25 },
  });
  map.addLayer({
    id: "wm-line",
    type: "line",
    source: "worldmodel",
    paint: { "line-color": ["get", "color"], "line-width": ["case", ["get", "picked"], 5, 2] },
  });
  map.addLayer({
    id: "wm-point",
    type: "circle",
    source: "worldmodel",
    filter: ["==", ["geometry-type"], "Point"],
    paint: { "circle-color": ["get", "color"], "circle-radius": 5 },
  });
  map.addLayer({
    id: "measure-line",
    type: "line",
    source: "measure",
    paint: { "line-color": "#fff", "line-width": 2, "line-dasharray": [2, 2] },
  });
  map.addLayer({
    id: "measure-point",
    type: "circle",
    source: "measure",
    filter: ["==", ["geometry-type"], "Point"],
    paint: { "circle-radius": 4, "circle-color": "#fff" },
  });
  // the edit tool's vertex handles, dragged to move a vertex
  map.addLayer({
    id: "edit-handle",
    type: "circle",
    source: "handles",
    paint: { "circle-radius": 6, "circle-color": "#fff", "circle-stroke-color": "#1e88e5", "circle-stroke-width": 2 },
  });
}

/** A box in degrees (west may exceed east by the map's wrap: a view over the antimeridian). */
export interface Bounds {
  west: number;
  south: number;
  east: number;
  north: number;
}

/** A polygon of the land (its outer ring) and its box. */
export interface LandRing extends Bounds {
  ring: Position[];
}

/** The outer ring and box of each polygon of the land (each part of a multipolygon its own). */
export function landRings(fc: FeatureCollection): LandRing[] {
  const rings: Position[][] = [];
  for (const f of fc.features) {
    if (f.geometry.type === "Polygon") rings.push(f.geometry.coordinates[0]);
    else if (f.geometry.type === "MultiPolygon") for (const poly of f.geometry.coordinates) rings.push(poly[0]);
  }
  return rings.map((ring) => {
    const b = { ring, west: Infinity, south: Infinity, east: -Infinity, north: -Infinity };
    for (const [lon, lat] of ring) {
      b.west = Math.min(b.west, lon);
      b.east = Math.max(b.east, lon);
      b.south = Math.min(b.south, lat);
      b.north = Math.max(b.north, lat);
    }
    return b;
  });
}

/** Whether `ring` (lon, lat) contains point `p` (even-odd rule). */
function inRing(ring: Position[], lon: number, lat: number): boolean {
  let inside = false;
  for (let i = 0, j = ring.length - 1; i < ring.length; j = i++) {
    const [xi, yi] = ring[i];
    const [xj, yj] = ring[j];
    if (yi > lat !== yj > lat && lon < ((xj - xi) * (lat - yi)) / (yj - yi) + xi) inside = !inside;
  }
  return inside;
}

/** How many of the land's polygons are in the view (its west and east as the map gives them, unwrapped): one with a
 * vertex in it, or around its middle (land filling the view). A box alone is not enough: the Americas' spans most of
 * the Pacific. */
export function countLandInView(rings: LandRing[], view: Bounds): number {
  const whole = view.east - view.west >= 360;
  const midLon = wrapLon((view.west + view.east) / 2);
  const midLat = (view.south + view.north) / 2;
  const shifts = whole ? [0] : [-360, 0, 360].filter((k) => k + 180 >= view.west && k - 180 <= view.east);
  const inView = (lon: number, lat: number) =>
    lat >= view.south && lat <= view.north && (whole || shifts.some((k) => lon + k >= view.west && lon + k <= view.east));
  return rings.filter((r) => {
    if (r.north < view.south || r.south > view.north) return false;
    if (!whole && !shifts.some((k) => r.east + k >= view.west && r.west + k <= view.east)) return false;
    return r.ring.some(([lon, lat]) => inView(lon, lat)) || inRing(r.ring, midLon, midLat);
  }).length;
}

/** The view that takes in every point (a jump: an animation would redraw the map every frame). */
export function fitAll(map: MapLibre, points: LonLat[]): void {
  if (!points.length) return;
  const b = new LngLatBounds();
  for (const p of points) b.extend([p.lon, p.lat]);
  map.fitBounds(b, { padding: 60, maxZoom: FRAME_MAX_ZOOM, duration: 0 });
}
