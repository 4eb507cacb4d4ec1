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

/** The theme the system's preference and the operator's choice give now. Only apply() reads the system's preference:
 * in Chromium, reading a MediaQueryList's `matches` after the preference changed and before the next frame takes the
 * change in without its `change` event (measured: a list read in a loop missed it 3 times in 6), so a render reading
 * it there (a panel's theme hook, while the vehicles stream) kept the page in the old theme until a reload. */
function resolveNow(): Theme {
  return resolveTheme(readSetting<ThemeChoice>(THEME, "system", isThemeChoice), query?.matches ?? false);
}

let shown: Theme = resolveNow();

/** The theme shown now. */
export function currentTheme(): Theme {
  return shown;
}

const listeners = new Set<() => void>();

/** Call `l` whenever the theme shown changes. */
export function onThemeChange(l: () => void): () => void {
  listeners.add(l);
  return () => listeners.delete(l);
}

function apply(): void {
  const theme = resolveNow();
  const changed = theme !== shown;
  shown = theme;
  if (typeof document !== "undefined" && document.documentElement.dataset.theme !== theme)
    document.documentElement.dataset.theme = theme;
  if (changed) for (const l of listeners) l();
}

apply();
subscribe(apply); // the operator's toggle, here or in another tab
query?.addEventListener("change", apply); // the system's preference, e.g. at dusk
