// Pure geometry for the map: distances, coordinate text, and the GeoJSON the map layers draw.
import type { Feature, FeatureCollection, LineString, Point, Polygon } from "geojson";
import type { Projection } from "./projection";
import { DASH, dms, isNum, latLon } from "./units";

export const EARTH_RADIUS_M = 6_371_008.8; // mean Earth radius (IUGG)

export interface LonLat {
  lon: number;
  lat: number;
}

const rad = (d: number) => (d * Math.PI) / 180;

/** Great-circle distance in metres (haversine on the mean sphere; within 0.5% of the ellipsoid). */
export function distanceM(a: LonLat, b: LonLat): number {
  const dLat = rad(b.lat - a.lat);
  const dLon = rad(b.lon - a.lon);
  const h = Math.sin(dLat / 2) ** 2 + Math.cos(rad(a.lat)) * Math.cos(rad(b.lat)) * Math.sin(dLon / 2) ** 2;
  return 2 * EARTH_RADIUS_M * Math.asin(Math.min(1, Math.sqrt(h)));
}

/** Length of a path in metres (the sum of its legs). */
export function pathLengthM(points: LonLat[]): number {
  let total = 0;
  for (let i = 1; i < points.length; i++) total += distanceM(points[i - 1], points[i]);
  return total;
}

/** Initial great-circle bearing from a to b, degrees 0..360 from true north. */
export function bearingDeg(a: LonLat, b: LonLat): number {
  const y = Math.sin(rad(b.lon - a.lon)) * Math.cos(rad(b.lat));
  const x =
    Math.cos(rad(a.lat)) * Math.sin(rad(b.lat)) - Math.sin(rad(a.lat)) * Math.cos(rad(b.lat)) * Math.cos(rad(b.lon - a.lon));
  return ((Math.atan2(y, x) * 180) / Math.PI + 360) % 360;
}

/** A longitude (or a difference of two) brought into [-180, 180): the short way round. */
export function wrapLon(lon: number): number {
  return ((((lon + 180) % 360) + 360) % 360) - 180;
}

/** The point `distance` metres from `from` along the great circle that starts at `courseDeg` (true, from north): the
 * direct problem on the mean sphere (as distanceM and bearingDeg), the longitude in -180..180. */
export function destination(from: LonLat, courseDeg: number, distance: number): LonLat {
  const d = distance / EARTH_RADIUS_M;
  const c = rad(courseDeg);
  const lat1 = rad(from.lat);
  const lat2 = Math.asin(Math.min(1, Math.max(-1, Math.sin(lat1) * Math.cos(d) + Math.cos(lat1) * Math.sin(d) * Math.cos(c))));
  const lon2 =
    rad(from.lon) + Math.atan2(Math.sin(c) * Math.sin(d) * Math.cos(lat1), Math.cos(d) - Math.sin(lat1) * Math.sin(lat2));
  return { lon: wrapLon((lon2 * 180) / Math.PI), lat: (lat2 * 180) / Math.PI };
}

/** "850 m", "12.35 km", with nautical miles beside: "12.35 km (6.67 NM)". */
export function distanceText(m: number): string {
  if (!isNum(m)) return DASH;
  const metric = m < 1000 ? `${m.toFixed(0)} m` : `${(m / 1000).toFixed(2)} km`;
  return `${metric} (${(m / 1852).toFixed(2)} NM)`;
}

/** A position as the console shows it: decimal degrees or DMS, latitude first. */
export function positionText(lat: number | null | undefined, lon: number | null | undefined, useDms: boolean): string {
  if (!isNum(lat) || !isNum(lon)) return DASH;
  const f = useDms ? dms : latLon;
  return `${f(lat, true)}, ${f(lon, false)}`;
}

/** A usable position: both finite and in range (a report may carry latitude 200, flagged invalid). */
export function validPosition(lat: number | null | undefined, lon: number | null | undefined): LonLat | null {
  if (!isNum(lat) || !isNum(lon) || Math.abs(lat) > 90 || Math.abs(lon) > 180) return null;
  return { lat, lon };
}

export type VehicleStatus = "valid" | "invalid" | "unknown";

export interface VehicleMark {
  id: string;
  label: string;
  position: LonLat;
  courseDeg: number | null; // true course, degrees from north
  fix: VehicleStatus; // GPSFixStatusReport.fixValid
  gpsPosition: boolean | null; // GPSLatLongValid (false: INS position)
  link: "live" | "stale" | "lost" | "regained";
  selected: boolean;
  alarmed: boolean; // an unacknowledged alarm about it
  /** a lost vehicle's dead-reckoned position (or why there is none); null while it is not lost */
  projection: Projection | null;
  /** seconds since a lost vehicle's newest report of any topic arrived (its "last heard"); null while it is not lost */
  heardS: number | null;
  /** lost in its planned silence: when the silence ends (named "out of comms (planned) until", not lost); else null */
  plannedUntil: number | null;
}

export interface TrackSample extends LonLat {
  t: number; // seconds since the epoch
}

/** Keep the points of the last `seconds` before `now`, in time order, without repeated times. */
export function trimTrack(points: TrackSample[], now: number, seconds: number): TrackSample[] {
  const from = now - seconds;
  const out: TrackSample[] = [];
  for (const p of [...points].sort((a, b) => a.t - b.t)) {
    if (p.t < from) continue;
    if (out.length && out[out.length - 1].t === p.t) out[out.length - 1] = p;
    else out.push(p);
  }
  return out;
}

/** The measure tool's path: the line and one point per vertex. */
export function measureGeoJson(points: LonLat[]): FeatureCollection {
  const features: Feature[] = points.map((p) => ({
    type: "Feature",
    geometry: { type: "Point", coordinates: [p.lon, p.lat] },
    properties: {},
  }));
  if (points.length >= 2)
    features.push({
      type: "Feature",
      geometry: { type: "LineString", coordinates: points.map((p) => [p.lon, p.lat]) },
      properties: {},
    });
  return { type: "FeatureCollection", features };
}

export const EMPTY: FeatureCollection = { type: "FeatureCollection", features: [] };

export type Coverage = "COMPLETED" | "PARTIAL" | "NONE" | null;

/** The colour of a CoMap feature by its coverage state. */
export function coverageColor(c: Coverage): string {
  switch (c) {
    case "COMPLETED":
      return "#4caf50";
    case "PARTIAL":
      return "#f5a623";
    case "NONE":
      return "#e0593f";
    default:
      return "#9fb3c8";
  }
}

/** A drawn vertex list as a CoMap geometry (the spec's rule: 1 vertex a point, 2 a line, 3 or more
 * a polygon, whose ring is closed here; a closed ring given is the same polygon). */
export function drawnGeometry(points: LonLat[]): Point | LineString | Polygon | null {
  const pts = points.map((p) => [p.lon, p.lat]);
  if (pts.length >= 4 && pts[0][0] === pts[pts.length - 1][0] && pts[0][1] === pts[pts.length - 1][1]) pts.pop();
  if (pts.length === 0) return null;
  if (pts.length === 1) return { type: "Point", coordinates: pts[0] };
  if (pts.length === 2) return { type: "LineString", coordinates: pts };
  return { type: "Polygon", coordinates: [[...pts, pts[0]]] };
}

/** The next featureId: above every id of the given world models and of `used` (tasks' features, ids deleted
 * this session), so a new feature never takes the id of a deleted one (whose CoverageState may still come). */
export function nextFeatureId(
  fcs: FeatureCollection | null | (FeatureCollection | null)[],
  used: Iterable<unknown> = [],
): number {
  let max = 0;
  const see = (v: unknown) => {
    const n = Number(v);
    if (v !== null && Number.isInteger(n) && n > max) max = n;
  };
  for (const fc of Array.isArray(fcs) ? fcs : [fcs]) for (const f of fc?.features ?? []) see(f.properties?.featureId);
  for (const v of used) see(v);
  return max + 1;
}

/** A file's text as a world model: a FeatureCollection whose features get an integer featureId when they lack
 * one (from `from` on at least, so an import does not take an id already used). */
export function parseWorldModel(text: string, from = 1): FeatureCollection {
  const j = JSON.parse(text) as FeatureCollection;
  if (j?.type !== "FeatureCollection" || !Array.isArray(j.features)) throw new Error("not a GeoJSON FeatureCollection");
  let next = Math.max(from, nextFeatureId(j));
  const features = j.features.map((f) => {
    const id = Number(f.properties?.featureId);
    return {
      ...f,
      properties: { ...f.properties, featureId: Number.isInteger(id) ? id : next++, coverage: f.properties?.coverage ?? null },
    };
  });
  return { type: "FeatureCollection", features };
}

/** An edit draft (geometry only) with each feature's coverage as the console's model has it now: coverage
 * reported while the operator edits shows, and is what a Send carries (a feature new in the draft: null). */
export function withLiveCoverage(draft: FeatureCollection, live: FeatureCollection | null): FeatureCollection {
  const coverage = new Map((live?.features ?? []).map((f) => [f.properties?.featureId, f.properties?.coverage ?? null]));
  const features = draft.features.map((f) => {
    const c = coverage.get(f.properties?.featureId) ?? null;
    return f.properties?.coverage === c ? f : { ...f, properties: { ...f.properties, coverage: c } };
  });
  return { ...draft, features };
}

/** The vertices of a geometry as drawn (a polygon's outer ring without its closing vertex). */
function vertices(g: Feature["geometry"] | null | undefined): number[][] {
  if (!g) return [];
  if (g.type === "Point") return [g.coordinates];
  if (g.type === "LineString") return g.coordinates;
  if (g.type === "Polygon") {
    const ring = g.coordinates[0] ?? [];
    const closed = ring.length > 1 && ring[0][0] === ring[ring.length - 1][0] && ring[0][1] === ring[ring.length - 1][1];
    return closed ? ring.slice(0, -1) : ring;
  }
  return [];
}

/** The edit tool's handles: one point per vertex of every feature, with its featureId and vertex index. */
export function vertexHandles(fc: FeatureCollection | null): FeatureCollection<Point> {
  const features = (fc?.features ?? []).flatMap((f) =>
    vertices(f.geometry).map((c, index) => ({
      type: "Feature" as const,
      geometry: { type: "Point" as const, coordinates: c },
      properties: { featureId: f.properties?.featureId, index },
    })),
  );
  return { type: "FeatureCollection", features };
}

/** The world model with vertex `index` of feature `featureId` moved to `to`: the geometry keeps its type (a
 * line stays a line), and a polygon's ring stays closed. */
export function moveVertex(fc: FeatureCollection, featureId: unknown, index: number, to: LonLat): FeatureCollection {
  const features = fc.features.map((f) => {
    const g = f.geometry;
    if (f.properties?.featureId !== featureId || !g) return f;
    const pts = vertices(g).map((c, i) => (i === index ? [to.lon, to.lat] : c));
    if (index < 0 || index >= pts.length) return f;
    if (g.type === "Point") return { ...f, geometry: { ...g, coordinates: pts[0] } };
    if (g.type === "LineString") return { ...f, geometry: { ...g, coordinates: pts } };
    if (g.type === "Polygon") return { ...f, geometry: { ...g, coordinates: [[...pts, pts[0]], ...g.coordinates.slice(1)] } };
    return f;
  });
  return { ...fc, features };
}

/** Every vertex of the polygons and lines of a feature collection. */
function* allVertices(fc: FeatureCollection): Generator<number[]> {
  for (const f of fc.features) {
    const g = f.geometry;
    if (!g) continue;
    const lines =
      g.type === "Polygon" || g.type === "MultiLineString"
        ? g.coordinates
        : g.type === "MultiPolygon"
          ? g.coordinates.flat()
          : g.type === "LineString"
            ? [g.coordinates]
            : [];
    for (const line of lines) yield* line;
  }
}

/** The vertex of `fc` (the coastline: the land polygons' rings) nearest to `at`, if one is within `withinM`.
 * One pass over the vertices, done once per framing, not per frame (Natural Earth 1:50m has about 100,000). */
export function nearestVertex(fc: FeatureCollection, at: LonLat, withinM: number): LonLat | null {
  // compare on a local flat approximation (cheap), then check the winner on the sphere
  const k = Math.cos(rad(at.lat));
  let best: number[] | null = null;
  let bestD = Infinity;
  for (const [lon, lat] of allVertices(fc)) {
    const dx = wrapLon(lon - at.lon) * k; // the short way round (the land runs past ±180°)
    const dy = lat - at.lat;
    const d = dx * dx + dy * dy;
    if (d < bestD) {
      bestD = d;
      best = [lon, lat];
    }
  }
  if (!best) return null;
  const p = { lon: best[0], lat: best[1] };
  return distanceM(at, p) <= withinM ? p : null;
}

/** The points the first view of the map frames: every vehicle and, when the coast is near, the nearest
 * coast point and its mirror image across `centre` (the vehicle the map follows, else the fleet's middle),
 * so the coast stays in view while the map keeps that vehicle in its middle. */
export function framePoints(vehicles: LonLat[], coast: LonLat | null, centre: LonLat): LonLat[] {
  if (!coast) return vehicles;
  return [...vehicles, coast, { lon: 2 * centre.lon - coast.lon, lat: 2 * centre.lat - coast.lat }];
}

/** The middle of the points' bounding box (no wrap across the antimeridian). */
export function middle(points: LonLat[]): LonLat | null {
  if (!points.length) return null;
  const lons = points.map((p) => p.lon);
  const lats = points.map((p) => p.lat);
  return { lon: (Math.min(...lons) + Math.max(...lons)) / 2, lat: (Math.min(...lats) + Math.max(...lats)) / 2 };
}

/** An edge marker: where on the border of a view a marker for a point outside it goes, and the direction
 * it points (degrees clockwise from up, the screen's y growing down). */
export interface EdgeMark {
  x: number;
  y: number;
  angleDeg: number;
}

/** The edge marker of the screen point (x, y) for a `width`×`height` view, on the line from the view's
 * middle towards the point, `inset` pixels inside the border; null when the point is in the view. */
export function edgeMark(x: number, y: number, width: number, height: number, inset: number): EdgeMark | null {
  if (!isNum(x) || !isNum(y)) return null;
  if (x >= 0 && x <= width && y >= 0 && y <= height) return null;
  const cx = width / 2;
  const cy = height / 2;
  const dx = x - cx;
  const dy = y - cy;
  // scale the direction down to the inset border: the nearer of the vertical and horizontal sides
  const sx = dx === 0 ? Infinity : Math.max(0, cx - inset) / Math.abs(dx);
  const sy = dy === 0 ? Infinity : Math.max(0, cy - inset) / Math.abs(dy);
  const s = Math.min(sx, sy);
  return { x: cx + dx * s, y: cy + dy * s, angleDeg: ((Math.atan2(dx, -dy) * 180) / Math.PI + 360) % 360 };
}
