// Formatting of numbers with units. Every function returns "—" for a value that is missing or not finite.

import { utcParam } from "./exports";

export const DASH = "—";
/** What a value the vehicle may report shows while it is not known yet (its vehicle drawn from the snapshot's brief,
 * its details on their way): not the dash, which says the vehicle gives none. */
export const PENDING = "…";
export const PENDING_TITLE = "Not known yet: this vehicle's details are on their way";
const KNOTS_PER_MPS = 3600 / 1852;

export function isNum(v: unknown): v is number {
  return typeof v === "number" && Number.isFinite(v);
}

export function fixed(v: number | null | undefined, digits: number, unit = ""): string {
  if (!isNum(v)) return DASH;
  return unit ? `${v.toFixed(digits)} ${unit}` : v.toFixed(digits);
}

export function radToDeg(rad: number): number {
  return (rad * 180) / Math.PI;
}

/** An angle in radians shown in degrees; `wrap` maps it to 0..360 (bearings). */
export function degrees(rad: number | null | undefined, digits = 1, wrap = false): string {
  if (!isNum(rad)) return DASH;
  let d = radToDeg(rad);
  if (wrap) d = ((d % 360) + 360) % 360;
  return `${d.toFixed(digits)}°`;
}

export function speed(mps: number | null | undefined): string {
  if (!isNum(mps)) return DASH;
  return `${mps.toFixed(2)} m/s (${(mps * KNOTS_PER_MPS).toFixed(2)} kn)`;
}

/** Decimal degrees with hemisphere, e.g. 36.800123° N. */
export function latLon(deg: number | null | undefined, isLat: boolean): string {
  if (!isNum(deg)) return DASH;
  const hemi = isLat ? (deg >= 0 ? "N" : "S") : deg >= 0 ? "E" : "W";
  return `${Math.abs(deg).toFixed(6)}° ${hemi}`;
}

/** Degrees, minutes, seconds with hemisphere, e.g. 36° 48′ 00.44″ N. */
export function dms(deg: number | null | undefined, isLat: boolean): string {
  if (!isNum(deg)) return DASH;
  const hemi = isLat ? (deg >= 0 ? "N" : "S") : deg >= 0 ? "E" : "W";
  let totalSeconds = Math.round(Math.abs(deg) * 360000) / 100; // hundredths of a second
  const d = Math.floor(totalSeconds / 3600);
  totalSeconds -= d * 3600;
  const m = Math.floor(totalSeconds / 60);
  const s = totalSeconds - m * 60;
  return `${d}° ${String(m).padStart(2, "0")}′ ${s.toFixed(2).padStart(5, "0")}″ ${hemi}`;
}

/** To what a time is written: the minute, the second, the tenth or the thousandth of a second. */
export type TimeTo = "min" | "s" | "ds" | "ms";
const TIME_END: Readonly<Record<TimeTo, number>> = { min: 16, s: 19, ds: 21, ms: 23 };

/** A UTC time of an epoch in seconds, as the page writes every time it shows (the house style, "UTC" after it, never
 * "Z"): "2026-11-22 21:03:04.123 UTC", or without its date "21:03:04.123 UTC", to `to`. Exports keep ISO 8601. */
export function utc(epochSeconds: number | null | undefined, withDate = true, to: TimeTo = "ms"): string {
  if (!isNum(epochSeconds)) return DASH;
  const iso = new Date(epochSeconds * 1000).toISOString(); // 2026-11-22T21:03:04.123Z
  return `${iso.slice(withDate ? 0 : 11, TIME_END[to]).replace("T", " ")} UTC`;
}

/** HH:MM UTC of UTC seconds, as the watch says a time ("until 14:20 UTC"), with the date when it is not today's (UTC). */
export function clockTime(t: number, now = Date.now() / 1000): string {
  const day = (s: number) => new Date(s * 1000).toISOString().slice(0, 10);
  return utc(t, day(t) !== day(now), "min");
}

/** The next UTC time of day `hhmm` ("14:20", 24-hour) after `now` (UTC seconds): today's, else tomorrow's (at 23:30,
 * "01:00" is tomorrow's); null for anything else (a 12-hour "2:20 PM", "24:00", "14:60"). */
export function nextUtc(hhmm: string, now: number): number | null {
  const m = /^([01]\d|2[0-3]):([0-5]\d)$/.exec(hhmm.trim());
  if (!m) return null;
  const day = Math.floor(now / 86400) * 86400;
  const t = day + Number(m[1]) * 3600 + Number(m[2]) * 60;
  return t > now ? t : t + 86400;
}

/** A UTC time as the operator writes it, 24-hour: "14:20" (the next one, as nextUtc) or "2026-11-29 14:20" (that
 * day's, as an export's range takes it); null for anything else (a 12-hour time, a day that does not exist). */
export function utcWhen(text: string, now: number): number | null {
  const iso = utcParam(text);
  return iso !== null ? Date.parse(iso) / 1000 : nextUtc(text, now);
}

export function hertz(hz: number | null | undefined): string {
  if (!isNum(hz)) return DASH;
  return hz >= 1e6 ? `${(hz / 1e6).toFixed(3)} MHz` : `${hz.toFixed(0)} Hz`;
}

export function age(seconds: number | null | undefined): string {
  if (!isNum(seconds)) return DASH;
  if (seconds < 10) return `${seconds.toFixed(1)} s`;
  if (seconds < 120) return `${seconds.toFixed(0)} s`;
  return `${(seconds / 60).toFixed(0)} min`;
}

/** A duration in words, to the second: "45 s", "2 min 10 s", "1 h 5 min" (from an hour on, to the minute). */
export function elapsedText(seconds: number): string {
  const s = Math.max(0, Math.floor(seconds));
  if (s < 60) return `${s} s`;
  if (s < 3600) return `${Math.floor(s / 60)} min ${s % 60} s`;
  return `${Math.floor(s / 3600)} h ${Math.floor((s % 3600) / 60)} min`;
}

/** A duration as m:ss or h:mm:ss (floored to the second): "03:07", "1:02:09". */
export function clockDuration(seconds: number): string {
  const s = Math.max(0, Math.floor(seconds));
  const hh = Math.floor(s / 3600);
  const mm = String(Math.floor((s % 3600) / 60)).padStart(2, "0");
  const ss = String(s % 60).padStart(2, "0");
  return hh ? `${hh}:${mm}:${ss}` : `${mm}:${ss}`;
}

/** CoMap's (IMC's) survey resolution unit, of a vehicle's capabilities and of a SurveyTask alike. */
export const RESOLUTION_UNIT = "px/m²";

/** A survey resolution: "4 px/m²". */
export function resolution(v: number | null | undefined): string {
  return isNum(v) ? `${v} ${RESOLUTION_UNIT}` : DASH;
}

export function yesNo(v: boolean | null | undefined): string {
  return v === true ? "yes" : v === false ? "no" : DASH;
}
