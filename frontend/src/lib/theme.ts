// The colour theme's hook; the theme itself is set on <html data-theme> by themeApply.ts (without React).
import { useSyncExternalStore } from "react";
import { currentTheme, onThemeChange, type Theme } from "./themeApply";

export { resolveTheme, type Theme } from "./themeApply";

/** The theme shown now (for what the style sheet cannot colour: the map's canvas). */
export function useTheme(): Theme {
  return useSyncExternalStore(onThemeChange, currentTheme);
}
