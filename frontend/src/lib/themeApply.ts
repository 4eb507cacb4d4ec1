// The colour theme: dark for the night watch, light for daylight on a bright screen. The operator's
// choice (settings: system, light or dark) resolves to one of the two, set on <html data-theme> for
// the style sheet's variables; "system" follows prefers-color-scheme as it changes. Applied when this
// module loads, before the first paint, so a light-theme page does not flash dark. Without React: the page's
// entry (boot.ts) loads it before React and the panels; theme.ts adds the hook.
import { THEME, isThemeChoice, readSetting, subscribe, type ThemeChoice } from "../data/settingStore";

export type Theme = "light" | "dark";

const query = typeof window !== "undefined" && window.matchMedia ? window.matchMedia("(prefers-color-scheme: light)") : null;

/** The theme shown for a choice, given whether the system prefers light. */
export function resolveTheme(choice: ThemeChoice, systemLight: boolean): Theme {
  return choice === "system" ? (systemLight ? "light" : "dark") : choice;
}

/** The theme shown now. */
export function currentTheme(): Theme {
  return resolveTheme(readSetting<ThemeChoice>(THEME, "system", isThemeChoice), query?.matches ?? false);
}

const listeners = new Set<() => void>();

/** Call `l` whenever the theme shown changes. */
export function onThemeChange(l: () => void): () => void {
  listeners.add(l);
  return () => listeners.delete(l);
}

function apply(): void {
  if (typeof document === "undefined") return;
  const theme = currentTheme();
  if (document.documentElement.dataset.theme === theme) return;
  document.documentElement.dataset.theme = theme;
  for (const l of listeners) l();
}

apply();
subscribe(apply); // the operator's toggle, here or in another tab
query?.addEventListener("change", apply); // the system's preference, e.g. at dusk
