// The order of the panels, per group (the side column, the selected vehicle's status and commands,
// the map's column). An operator moves a panel only within its group (each column has its width). A stored order
// is merged with the panels this build has, so every panel is always shown exactly once.

export type Group = "side" | "status" | "main";

/** A stored order made safe: only the `known` panels, each once, in the stored order; known panels
 * the stored order misses (new in this build) appended in their default (`known`) order. */
export function mergeOrder(stored: unknown, known: readonly string[]): string[] {
  const kept = Array.isArray(stored)
    ? stored.filter((id, i): id is string => typeof id === "string" && known.includes(id) && stored.indexOf(id) === i)
    : [];
  return [...kept, ...known.filter((id) => !kept.includes(id))];
}

/** The order of `group` in a stored layout (anything JSON.parse gave, or null), merged with `known`. */
export function groupOrder(stored: unknown, group: Group, known: readonly string[]): string[] {
  return mergeOrder(stored !== null && typeof stored === "object" ? (stored as Record<string, unknown>)[group] : null, known);
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
