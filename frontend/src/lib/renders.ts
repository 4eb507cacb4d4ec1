// Render counts per panel for the browser benchmark (bench/browser.py): off unless the page is opened
// with ?renders, and then one counter per name in window.__semRenders. Off, a call is one branch.
declare global {
  interface Window {
    __semRenders?: Record<string, number>;
  }
}

/** Whether this page counts renders (opened with ?renders). */
export const countingRenders = typeof window !== "undefined" && new URLSearchParams(window.location.search).has("renders");

/** Count one render (or one map source update) of `name`, when the page counts them. */
export function countRender(name: string): void {
  if (!countingRenders) return;
  const counts = (window.__semRenders ??= {});
  counts[name] = (counts[name] ?? 0) + 1;
}
