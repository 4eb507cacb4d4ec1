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
