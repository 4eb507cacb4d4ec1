import { cleanup, configure } from "@testing-library/react";
import { afterEach, vi } from "vitest";

// What jsdom lacks that the panels' libraries ask for when loaded (uPlot reads the device's pixel ratio through
// matchMedia): set up before each component test (vite.config.ts, test.setupFiles).
if (typeof window !== "undefined" && !window.matchMedia)
  window.matchMedia = (query: string) =>
    ({
      matches: false,
      media: query,
      onchange: null,
      addEventListener: () => undefined,
      removeEventListener: () => undefined,
      addListener: () => undefined,
      removeListener: () => undefined,
      dispatchEvent: () => false,
    }) as MediaQueryList;

// no console behind a component test: a panel's REST request fails as one that got no answer, unless the test stubs fetch
if (typeof window !== "undefined") globalThis.fetch = () => Promise.reject(new TypeError("no console in a component test"));

// Waits, not timed checks: the units run beside pytest and Playwright on two cores (scripts/test), where a render and
// a tick of the panels' clock can take seconds (Testing Library's default wait is 1 s; a test of a wait of 3 s failed
// so in a clean-clone run). A wait ends as soon as what it waits for is drawn.
configure({ asyncUtilTimeout: 10_000 });

// The test files share their workers (vite.config.ts, isolate: false): what a test drew is unmounted after it, and the
// real clock, globals and empty storage are back, whether or not its file says so too, so that no later file finds
// them.
afterEach(() => {
  cleanup();
  vi.useRealTimers();
  vi.unstubAllGlobals();
  if (typeof window !== "undefined" && typeof localStorage !== "undefined") {
    localStorage.clear();
    sessionStorage.clear();
    window.dispatchEvent(new StorageEvent("storage", { key: null })); // the settings' cache forgets them too
  }
});
