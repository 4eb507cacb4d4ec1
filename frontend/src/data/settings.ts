// The operator's display settings, kept in localStorage so a reload keeps them:
// decimal or DMS coordinates (the Fix panel and the map share it), the panel layout and the theme.
import { useSyncExternalStore } from "react";
import { groupOrder, type Group } from "../lib/layout";
import { THEME, isThemeChoice, readSetting, subscribe, writeSetting, type ThemeChoice } from "./settingStore";

export { THEME, isThemeChoice, readSetting, subscribe, writeSetting, type ThemeChoice } from "./settingStore";

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

/** The colour theme the operator chose: the system's (light by day if the system says so), light or dark. */
export function useThemeSetting(): [ThemeChoice, (v: ThemeChoice) => void] {
  return useSetting<ThemeChoice>(THEME, "system", isThemeChoice);
}
