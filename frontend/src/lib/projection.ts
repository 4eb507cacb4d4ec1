// Where a lost vehicle may be now: dead reckoning from its last GPSFixReport (position, speed over ground, true
// course) along the great circle, with a circle of uncertainty that grows with the time since. A projection is a
// guess drawn as one (dashed, labelled "projected"), never a report. The model and its numbers are in
// docs/dashboard.md ("A lost vehicle projected"): change them together.
import { destination, type LonLat } from "./geo";
import { isNum } from "./units";

export const DEAD_RECKONING = {
  /** No projection once the last fix is older than this (s): the guess would say more than is known. */
  maxSeconds: 30 * 60,
  /** The radius at the last fix (m) when it was a valid GPS fix: a typical GPS horizontal error (the reports carry
   * no accuracy of their own). */
  baseFixM: 10,
  /** The radius at the last fix (m) when it was not (an INS position, or no valid fix). */
  baseOtherM: 100,
  /** Growth (m/s) whatever the speed: an unknown current or wind set. */
  driftMps: 0.5,
  /** Growth as a fraction of the speed over ground: the speed's and course's errors (0.2 is a course error of
   * about 11°, or a fifth of the speed). */
  speedFraction: 0.2,
  /** The radius stops growing here (m). */
  maxRadiusM: 5000,
} as const;

/** What the last fix said. `speedMps`, `courseDeg`: null when not reported or flagged invalid. */
export interface LastFix {
  at: LonLat;
  speedMps: number | null;
  courseDeg: number | null;
  /** a valid GPS fix (GPSFixStatusReport.fixValid and GPSLatLongValid), not an INS position */
  gpsFix: boolean;
  /** why the vehicle's reports never carry a speed (its UMAA version's position report has none), when they do not */
  noSpeed?: string | null;
}

export type Projection =
  | { kind: "projected"; from: LonLat; at: LonLat; radiusM: number; seconds: number }
  /** the last fix is older than DEAD_RECKONING.maxSeconds */
  | { kind: "too-old"; seconds: number }
  /** the speed, or the course of a vehicle under way, is not known */
  | { kind: "no-motion"; seconds: number }
  /** its reports never carry a speed (`why`): it is drawn where it was last heard, not projected */
  | { kind: "last-position"; seconds: number; why: string };

/** The uncertainty circle's radius `seconds` after a fix: base + (drift + fraction × speed) × seconds, capped. */
export function uncertaintyM(gpsFix: boolean, speedMps: number, seconds: number): number {
  const m = DEAD_RECKONING;
  const base = gpsFix ? m.baseFixM : m.baseOtherM;
  return Math.min(m.maxRadiusM, base + (m.driftMps + m.speedFraction * Math.max(0, speedMps)) * Math.max(0, seconds));
}

/** The projection of `fix`, `seconds` after it. */
export function deadReckon(fix: LastFix, seconds: number): Projection {
  const s = Math.max(0, seconds);
  if (s > DEAD_RECKONING.maxSeconds) return { kind: "too-old", seconds: s };
  const speed = fix.speedMps;
  if (!isNum(speed) && fix.noSpeed) return { kind: "last-position", seconds: s, why: fix.noSpeed };
  if (!isNum(speed) || speed < 0) return { kind: "no-motion", seconds: s };
  if (speed > 0 && !isNum(fix.courseDeg)) return { kind: "no-motion", seconds: s };
  const at = speed > 0 ? destination(fix.at, fix.courseDeg!, speed * s) : fix.at;
  return { kind: "projected", from: fix.at, at, radiusM: uncertaintyM(fix.gpsFix, speed, s), seconds: s };
}

/** What the map says of a projection: "projected · within 127 m", or why there is none. */
export function projectionText(p: Projection): string {
  if (p.kind === "projected")
    return `projected · within ${p.radiusM < 1000 ? `${Math.round(p.radiusM)} m` : `${(p.radiusM / 1000).toFixed(1)} km`}`;
  if (p.kind === "too-old") return `not projected: no fix for over ${DEAD_RECKONING.maxSeconds / 60} min`;
  if (p.kind === "last-position") return `at its last position, not projected: ${p.why}`;
  return "not projected: speed or course unknown";
}
