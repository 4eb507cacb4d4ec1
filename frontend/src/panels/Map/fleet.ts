// The fleet as drawn on the 2D canvas over the map (FleetCanvas.ts): where each vehicle's dot and course arrow go on
// the screen, which vehicle a pointer is over, and how many are in view. Pure geometry, no canvas or map.
import { destination, type LonLat, type VehicleMark } from "../../lib/geo";
import type { Projection } from "../../lib/projection";

export interface Point {
  x: number;
  y: number;
}

/** A position in Web Mercator's unit square (x east from the antimeridian, y south from the top), the map's own
 * projection before zoom and rotation. */
export function mercator(p: LonLat): Point {
  const s = Math.sin((Math.max(-85.051129, Math.min(85.051129, p.lat)) * Math.PI) / 180);
  return { x: (p.lon + 180) / 360, y: 0.5 - Math.log((1 + s) / (1 - s)) / (4 * Math.PI) };
}

/** `m` moved by whole worlds to the copy nearest Mercator x `cx` (the map's centre): the map draws the world again
 * east and west of itself, so a vehicle at 179°W seen from 179°E is just east of the centre, not a world away. */
export function nearestCopy(m: Point, cx: number): Point {
  const k = Math.round(cx - m.x);
  return k ? { x: m.x + k, y: m.y } : m;
}

/** A track's points with no jump of more than half a world between two (one over the antimeridian goes the short
 * way, as the vehicle did, not round the world). */
export function unwrapped(points: Point[]): Point[] {
  const out: Point[] = [];
  for (const p of points) out.push(out.length ? nearestCopy(p, out[out.length - 1].x) : p);
  return out;
}

/** The screen point of a Mercator point, for a map without pitch: a scale, a rotation (the bearing) and a shift, so
 * two known pairs fix it. One `map.project` per vehicle and track point was the cost; this is a few multiplications. */
export type ToScreen = (m: Point) => Point;

export function similarity(mA: Point, qA: Point, mB: Point, qB: Point): ToScreen {
  // complex numbers: q = qA + s (m - mA), s = (qB - qA) / (mB - mA)
  const dx = mB.x - mA.x;
  const dy = mB.y - mA.y;
  const ex = qB.x - qA.x;
  const ey = qB.y - qA.y;
  const d = dx * dx + dy * dy || 1;
  const sr = (ex * dx + ey * dy) / d;
  const si = (ey * dx - ex * dy) / d;
  return (m) => {
    const x = m.x - mA.x;
    const y = m.y - mA.y;
    return { x: qA.x + sr * x - si * y, y: qA.y + si * x + sr * y };
  };
}

/** Dot radii (px) as MapLibre drew them: the selected vehicle's larger. */
export const DOT_R = 7;
export const SELECTED_DOT_R = 9;
/** The course arrow's middle, this far ahead of the dot along the course (px). */
export const ARROW_AHEAD = 14;
/** How near (px) a pointer must be to a dot's or an arrow's middle to be over it, beyond the dot's radius. */
const HIT_SLACK = 4;
const ARROW_HIT_R = 9;

/** A vehicle where it is drawn: its dot's middle and radius, its course arrow's middle (none without a course). */
export interface Placed {
  mark: VehicleMark;
  at: Point;
  r: number;
  arrow: Point | null;
  /** the arrow's direction on the screen, radians clockwise from up */
  angle: number;
}

/** The vehicles' places on the screen: `bearingDeg` is the map's rotation (a course is drawn turned with the map),
 * each vehicle at its copy of the world nearest the map's centre (Mercator x `cx`). */
export function place(marks: VehicleMark[], toScreen: ToScreen, bearingDeg: number, cx = 0.5): Placed[] {
  return marks.map((mark) => {
    const at = toScreen(nearestCopy(mercator(mark.position), cx));
    const angle = (((mark.courseDeg ?? 0) - bearingDeg) * Math.PI) / 180;
    const arrow =
      mark.courseDeg === null ? null : { x: at.x + ARROW_AHEAD * Math.sin(angle), y: at.y - ARROW_AHEAD * Math.cos(angle) };
    return { mark, at, r: mark.selected ? SELECTED_DOT_R : DOT_R, arrow, angle };
  });
}

/** The vehicle under screen point `p`: the nearest whose dot or course arrow it is on (null: none). */
export function hitVehicle(placed: Placed[], p: Point): string | null {
  let best: string | null = null;
  let bestD = Infinity;
  for (const v of placed) {
    const dDot = Math.hypot(p.x - v.at.x, p.y - v.at.y);
    if (dDot <= v.r + HIT_SLACK && dDot < bestD) [best, bestD] = [v.mark.id, dDot];
    const dArrow = v.arrow ? Math.hypot(p.x - v.arrow.x, p.y - v.arrow.y) : Infinity;
    if (dArrow <= ARROW_HIT_R && dArrow < bestD) [best, bestD] = [v.mark.id, dArrow];
  }
  return best;
}

/** How many vehicles' dots are (at least partly) on a `width` x `height` screen. */
export function countInView(placed: Placed[], width: number, height: number): number {
  return placed.filter((v) => v.at.x >= -v.r && v.at.y >= -v.r && v.at.x <= width + v.r && v.at.y <= height + v.r).length;
}

/** A track's points, thinned to those at least `minPx` from the last one kept (a track of 900 points zoomed out is a
 * few pixels: drawing each is work for nothing). The last point is always kept. */
export function thinned(points: Point[], minPx: number): Point[] {
  if (points.length < 3) return points;
  const out = [points[0]];
  for (let i = 1; i < points.length - 1; i++) {
    const last = out[out.length - 1];
    if (Math.abs(points[i].x - last.x) >= minPx || Math.abs(points[i].y - last.y) >= minPx) out.push(points[i]);
  }
  out.push(points[points.length - 1]);
  return out;
}

/** Whether screen point `p` is outside the middle of a `width` x `height` map (the middle half each way): a
 * followed vehicle there is centred again. */
export function outsideMiddle(p: Point, width: number, height: number): boolean {
  return Math.abs(p.x - width / 2) > width / 4 || Math.abs(p.y - height / 2) > height / 4;
}

/** A projection drawn: its ghost's radius (px), the least its circle of uncertainty is drawn at. */
export const PROJECTED_R = 7;

export type Projected = Extract<Projection, { kind: "projected" }>;

/** Where a lost vehicle's projection goes on the screen: its last report (`from`, at its copy of the world nearest the
 * map's centre, as its dot), the projected position (`at`, at its copy nearest that: the line between goes the short
 * way) and the circle's radius in px (its edge due north of `at`: Mercator keeps a small circle round), at least
 * `minR`. */
export function placeProjection(
  p: Projected,
  toScreen: ToScreen,
  cx: number,
  minR: number,
): { from: Point; at: Point; r: number } {
  const mFrom = nearestCopy(mercator(p.from), cx);
  const mAt = nearestCopy(mercator(p.at), mFrom.x);
  const mEdge = nearestCopy(mercator(destination(p.at, 0, p.radiusM)), mAt.x);
  const at = toScreen(mAt);
  const edge = toScreen(mEdge);
  return { from: toScreen(mFrom), at, r: Math.max(minR, Math.hypot(edge.x - at.x, edge.y - at.y)) };
}

/** Vehicles drawn as one mark when zoomed out: where (the middle of their dots), which, and the mark's radius. */
export interface Cluster {
  at: Point;
  ids: string[];
  r: number;
}

/** The screen's cells (px) within which vehicles are drawn as one cluster, and the fewest vehicles that make one. */
export const CLUSTER_CELL = 40;
export const CLUSTER_MIN = 5;

/** A vehicle never drawn in a cluster: the selected one, one in alarm, one lost (the operator must see each). */
export function keptApart(mark: VehicleMark): boolean {
  return mark.selected || mark.alarmed || mark.link === "lost";
}

/** The vehicles as drawn: those whose dots fall `min` or more to one `cell` x `cell` square of the screen are one
 * cluster (zoomed out, a fleet of a thousand is tens of marks, not a thousand overlapping dots), the rest (and every
 * one `keptApart`) on their own. `zoomable`: the map can zoom in further; at its closest zoom a cluster's click could
 * not draw its vehicles apart (vehicles side by side on a pier), so none is clustered there. */
export function clustered(
  placed: Placed[],
  zoomable = true,
  cell = CLUSTER_CELL,
  min = CLUSTER_MIN,
): { singles: Placed[]; clusters: Cluster[] } {
  const cells = new Map<string, Placed[]>();
  const singles: Placed[] = [];
  for (const v of placed) {
    if (!zoomable || keptApart(v.mark)) {
      singles.push(v);
      continue;
    }
    const key = `${Math.floor(v.at.x / cell)},${Math.floor(v.at.y / cell)}`;
    const group = cells.get(key);
    if (group) group.push(v);
    else cells.set(key, [v]);
  }
  const clusters: Cluster[] = [];
  for (const group of cells.values()) {
    if (group.length < min) {
      singles.push(...group);
      continue;
    }
    const x = group.reduce((s, v) => s + v.at.x, 0) / group.length;
    const y = group.reduce((s, v) => s + v.at.y, 0) / group.length;
    clusters.push({ at: { x, y }, ids: group.map((v) => v.mark.id), r: Math.min(22, 10 + 3 * Math.log10(group.length)) });
  }
  // the kept-apart ones last, so that they are drawn over any cluster (the selected one last of all, as placed)
  const apart = singles.filter((v) => keptApart(v.mark));
  return { singles: [...singles.filter((v) => !keptApart(v.mark)), ...apart], clusters };
}

/** The cluster under screen point `p` (null: none). */
export function hitCluster(clusters: Cluster[], p: Point): Cluster | null {
  return clusters.find((c) => Math.hypot(p.x - c.at.x, p.y - c.at.y) <= c.r + 2) ?? null;
}
