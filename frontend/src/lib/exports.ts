// Export links (GPX, CSV) for a vehicle and a time range: pure, so the dashboard and tests agree.

export type ExportRange =
  | { kind: "last"; hours: number } // the last `hours` up to now
  | { kind: "all" } // everything the console keeps
  | { kind: "between"; since: string; until: string }; // UTC, 24-hour, as the operator writes it (YYYY-MM-DD HH:MM)

export type ExportKind = "gpx" | "csv" | "commands";

/** "2026-11-22T08:00" (taken as UTC) or a Date -> "2026-11-22T08:00:00Z"; null for an empty or bad value. */
export function utcParam(v: string | Date): string | null {
  if (v instanceof Date) return Number.isFinite(v.getTime()) ? v.toISOString().replace(/\.\d{3}Z$/, "Z") : null;
  const m = /^(\d{4}-\d{2}-\d{2})[T ](\d{2}:\d{2})(:\d{2})?$/.exec(v.trim());
  if (!m) return null;
  const iso = `${m[1]}T${m[2]}${m[3] ?? ":00"}Z`;
  const t = Date.parse(iso);
  return Number.isFinite(t) && new Date(t).toISOString().startsWith(iso.slice(0, 19)) ? iso : null; // not 30 February
}

/** The query of a range, or an error to show (a bad or reversed range sends nothing). */
export function rangeQuery(range: ExportRange, nowMs: number): { since?: string; until?: string } | { error: string } {
  if (range.kind === "all") return {};
  if (range.kind === "last") return { since: utcParam(new Date(nowMs - range.hours * 3_600_000))! };
  const since = range.since ? utcParam(range.since) : undefined;
  const until = range.until ? utcParam(range.until) : undefined;
  if (since === null) return { error: "From: write a UTC date and time, 24-hour, as YYYY-MM-DD HH:MM" };
  if (until === null) return { error: "To: write a UTC date and time, 24-hour, as YYYY-MM-DD HH:MM" };
  if (since && until && since > until) return { error: "From is after To" };
  return { ...(since ? { since } : {}), ...(until ? { until } : {}) };
}

/** The console's URL of an export; `providerId` null: the commands of every vehicle. */
export function exportUrl(kind: ExportKind, providerId: string | null, query: { since?: string; until?: string }): string {
  const q = new URLSearchParams();
  if (kind === "commands" && providerId) q.set("provider_id", providerId);
  if (query.since) q.set("since", query.since);
  if (query.until) q.set("until", query.until);
  const path = kind === "commands" ? "/api/commands.csv" : `/api/providers/${encodeURIComponent(providerId ?? "")}/track.${kind}`;
  const qs = q.toString();
  return qs ? `${path}?${qs}` : path;
}

/** The file name a download gets (the console sends the same in Content-Disposition). */
export function exportName(kind: ExportKind, providerId: string | null): string {
  if (kind === "commands") return providerId ? `commands_${providerId}.csv` : "commands.csv";
  return `track_${providerId}.${kind}`;
}

/** The name a download is saved under, for the operator's folder: the vehicle's name (else "Vehicle-<short id>"),
 * what it holds and when it was taken, in UTC to the minute: "Charlie-commands-2026-11-25T1432Z.csv",
 * "Vehicle-77b2ceb8-track-2026-11-25T1432Z.gpx"; `vehicle` null: the commands of every vehicle. */
export function exportFileName(kind: ExportKind, vehicle: { id: string; name: string | null } | null, nowMs: number): string {
  const who = vehicle === null ? "all-vehicles" : vehicle.name ? vehicle.name : `Vehicle-${vehicle.id.slice(0, 8)}`;
  const safe =
    who.replace(/[^\p{L}\p{N}._-]+/gu, "-").replace(/^[-.]+|-+$/g, "") || `Vehicle-${vehicle?.id.slice(0, 8) ?? "all"}`;
  const d = new Date(nowMs).toISOString(); // 2026-11-25T14:32:07.123Z
  const stamp = `${d.slice(0, 10)}T${d.slice(11, 13)}${d.slice(14, 16)}Z`;
  const what = kind === "commands" ? "commands.csv" : `track.${kind}`;
  return `${safe}-${what.replace(".", `-${stamp}.`)}`;
}
