// Azimuth/elevation to sky-plot coordinates: zenith at the centre, the horizon on the rim,
// north up, east to the right (as a receiver's sky view is drawn).

export interface Point {
  x: number;
  y: number;
}

/** Project azimuth and elevation (radians) into a circle of `radius` centred on 0,0; null when unplottable. */
export function project(azimuth: number | null | undefined, elevation: number | null | undefined, radius: number): Point | null {
  if (typeof azimuth !== "number" || typeof elevation !== "number") return null;
  if (!Number.isFinite(azimuth) || !Number.isFinite(elevation)) return null;
  const el = Math.min(Math.max(elevation, 0), Math.PI / 2);
  const r = radius * (1 - el / (Math.PI / 2));
  return { x: r * Math.sin(azimuth), y: -r * Math.cos(azimuth) };
}

/** SVG path through the points of a satellite's trail (oldest first); empty for fewer than two. */
export function trailPath(points: Point[]): string {
  if (points.length < 2) return "";
  return points.map((p, i) => `${i ? "L" : "M"}${p.x.toFixed(1)},${p.y.toFixed(1)}`).join(" ");
}
