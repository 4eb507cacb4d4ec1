// The operator's display settings in localStorage, without React: the page's entry (boot.ts) reads the theme
// from here before React and the panels have loaded; settings.ts adds the hooks.

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

export type ThemeChoice = "system" | "light" | "dark";
export const THEME = "sem-console.theme";
export const isThemeChoice = (v: unknown): v is ThemeChoice => v === "system" || v === "light" || v === "dark";
