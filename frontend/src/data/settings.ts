// The operator's display settings, kept in localStorage so a reload keeps them:
// decimal or DMS coordinates (the Fix panel and the map share it), the panel layout and the theme.
import { useSyncExternalStore } from "react";
import { groupOrder, type Group } from "../lib/layout";

const listeners = new Set<() => void>();
const cache = new Map<string, unknown>();

function storage(): Storage | null {
  try {
    return typeof localStorage !== "undefined" ? localStorage : null;
  } catch {
    return null; // storage disabled: settings last for the page only
  }
}

export function readSetting<T>(key: string, fallback: T, valid: (v: unknown) => v is T): T {
  if (cache.has(key)) return cache.get(key) as T;
  let value = fallback;
  try {
    const raw = storage()?.getItem(key);
    if (raw != null) {
      const parsed: unknown = JSON.parse(raw);
      if (valid(parsed)) value = parsed;
    }
  } catch {
    /* not JSON: the default */
  }
  cache.set(key, value);
  return value;
}

export function writeSetting<T>(key: string, value: T): void {
  cache.set(key, value);
  try {
    storage()?.setItem(key, JSON.stringify(value));
  } catch {
    /* full or disabled: kept for the page */
  }
  for (const l of listeners) l();
}

/** Call `l` whenever a setting changes (in this tab or another). */
export function subscribe(l: () => void): () => void {
  listeners.add(l);
  return () => listeners.delete(l);
}

// another tab of the console changed a setting: read it again, so this tab neither shows a stale
// layout nor writes its stale copy back over the other tab's change
if (typeof window !== "undefined") {
  window.addEventListener("storage", (e: StorageEvent) => {
    if (e.key === null) cache.clear();
    else if (!e.key.startsWith("sem-console.")) return;
    else cache.delete(e.key);
    for (const l of listeners) l();
  });
}

export function useSetting<T>(key: string, fallback: T, valid: (v: unknown) => v is T): [T, (v: T) => void] {
  const value = useSyncExternalStore(subscribe, () => readSetting(key, fallback, valid));
  return [value, (v: T) => writeSetting(key, v)];
}

const isBool = (v: unknown): v is boolean => typeof v === "boolean";

/** Coordinates in DMS (true) or decimal degrees (false), everywhere the console shows a position. */
export function useDmsSetting(): [boolean, (v: boolean) => void] {
  return useSetting("sem-console.dms", false, isBool);
}

const isStrings = (v: unknown): v is string[] => Array.isArray(v) && v.every((x) => typeof x === "string");
const COLLAPSED = "sem-console.collapsed";

/** Whether the panel `id` is collapsed to its title bar (the layout is remembered in localStorage). */
export function useCollapsed(id: string): [boolean, (v: boolean) => void] {
  const [ids, setIds] = useSetting<string[]>(COLLAPSED, [], isStrings);
  return [ids.includes(id), (v: boolean) => setIds(v ? [...ids.filter((x) => x !== id), id] : ids.filter((x) => x !== id))];
}

const LAYOUT = "sem-console.layout";
const isAny = (v: unknown): v is unknown => v !== undefined;

/** The order of the panels of `group` as the operator left it, merged with the group's `known`
 * panels (in their default order): a stored layout naming unknown panels or missing new ones still
 * shows every panel. And its setter. */
export function usePanelOrder(group: Group, known: readonly string[]): [string[], (order: string[]) => void] {
  const [stored, setStored] = useSetting<unknown>(LAYOUT, null, isAny);
  const others = stored !== null && typeof stored === "object" && !Array.isArray(stored) ? stored : {};
  return [groupOrder(stored, group, known), (order) => setStored({ ...others, [group]: order })];
}

/** Back to the default layout: the default panel order, nothing collapsed. */
export function resetLayout(): void {
  writeSetting(LAYOUT, null);
  writeSetting<string[]>(COLLAPSED, []);
}

export type ThemeChoice = "system" | "light" | "dark";
export const THEME = "sem-console.theme";
export const isThemeChoice = (v: unknown): v is ThemeChoice => v === "system" || v === "light" || v === "dark";

/** The colour theme the operator chose: the system's (light by day if the system says so), light or dark. */
export function useThemeSetting(): [ThemeChoice, (v: ThemeChoice) => void] {
  return useSetting<ThemeChoice>(THEME, "system", isThemeChoice);
}
