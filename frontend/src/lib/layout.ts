// The order of the panels, per group: the side column and the main area. An operator moves a panel
// only within its group (the side column is too narrow for the main area's panels). A stored order
// is merged with the panels this build has, so every panel is always shown exactly once.

export type Group = "side" | "main";
export type Layout = Record<Group, string[]>;

/** The panels of each group, by test id, in their default order. */
export const DEFAULT_LAYOUT: Layout = {
  side: ["alerts-panel", "gateways-panel"],
  main: ["map-panel", "fix-panel", "ins-panel", "satellites-panel", "export-panel", "commands-panel"],
};

/** A stored order made safe: only the `known` panels, each once, in the stored order; known panels
 * the stored order misses (new in this build) appended in their default order. */
export function mergeOrder(stored: unknown, known: readonly string[]): string[] {
  const kept = Array.isArray(stored) ? stored.filter((id, i): id is string => typeof id === "string" && known.includes(id) && stored.indexOf(id) === i) : [];
  return [...kept, ...known.filter((id) => !kept.includes(id))];
}

/** A stored layout (anything JSON.parse gave, or null) merged with the defaults, group by group. */
export function mergeLayout(stored: unknown, defaults: Layout = DEFAULT_LAYOUT): Layout {
  const s = stored !== null && typeof stored === "object" ? (stored as Partial<Record<Group, unknown>>) : {};
  return { side: mergeOrder(s.side, defaults.side), main: mergeOrder(s.main, defaults.main) };
}

/** `order` with `id` moved to the index `to` (clamped); unchanged if `id` is not in it. */
export function moveTo(order: readonly string[], id: string, to: number): string[] {
  const from = order.indexOf(id);
  if (from < 0) return [...order];
  const rest = order.filter((x) => x !== id);
  const at = Math.max(0, Math.min(rest.length, to));
  return [...rest.slice(0, at), id, ...rest.slice(at)];
}

/** `order` with `id` moved `by` places (negative: earlier). */
export function moveBy(order: readonly string[], id: string, by: number): string[] {
  return moveTo(order, id, order.indexOf(id) + by);
}

