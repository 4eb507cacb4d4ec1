// How a vehicle is named and marked everywhere (list, panels, command controls, confirmations):
// a short id, the configured name when there is one, and a colour derived from the id.
export interface VehicleIdentity {
  id: string;
  name: string | null;
}

export function shortId(id: string): string {
  return id.slice(0, 8);
}

/** "Alpha (77b2ceb8)" or "Vehicle 77b2ceb8". */
export function vehicleLabel(v: VehicleIdentity): string {
  return v.name ? `${v.name} (${shortId(v.id)})` : `Vehicle ${shortId(v.id)}`;
}

/** A stable hue per id (FNV-1a over the id), so the same vehicle has the same colour on every screen. */
export function vehicleHue(id: string): number {
  let h = 0x811c9dc5;
  for (let i = 0; i < id.length; i++) {
    h ^= id.charCodeAt(i);
    h = Math.imul(h, 0x01000193) >>> 0;
  }
  return h % 360;
}

export function vehicleColor(id: string): string {
  return `hsl(${vehicleHue(id)}, 70%, 55%)`;
}

/** Whether `v` is laid out as a vehicle id (a UUID): the console refuses any other in a `select` as a bad message. */
export function isVehicleId(v: string): boolean {
  return /^[0-9a-f]{8}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{12}$/i.test(v);
}

/** The selected vehicle from the page's address (`?vehicle=<id>`), so a link opens the same vehicle; a vehicle id's
 * layout only (the early socket names it to the console). */
export function vehicleFromUrl(search: string): string | null {
  const v = new URLSearchParams(search).get("vehicle");
  return v && isVehicleId(v) ? v.toLowerCase() : null;
}

/** The address with `?vehicle=<id>` set (or removed), other parameters kept. */
export function urlWithVehicle(href: string, id: string | null): string {
  const url = new URL(href);
  if (id) url.searchParams.set("vehicle", id);
  else url.searchParams.delete("vehicle");
  return url.toString();
}

/** A vehicle search's test: `query` (trimmed, any case) in the vehicle's name as the page shows it (`vehicleLabel`: an
 * unnamed one is "Vehicle 77b2ceb8") or in its id, dashes or none ("77b2ceb8", "b2ce-", "a1b2c3d4e5f6"). Made once per
 * query: each vehicle then costs a few `includes`. */
export function vehicleMatcher(query: string): (v: VehicleIdentity) => boolean {
  const q = query.trim().toLowerCase();
  if (!q) return () => true;
  const bare = q.replaceAll("-", "");
  return (v) =>
    vehicleLabel(v).toLowerCase().includes(q) || v.id.includes(q) || (bare !== "" && v.id.replaceAll("-", "").includes(bare));
}
