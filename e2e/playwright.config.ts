import { defineConfig } from "@playwright/test";

// Debian's Chromium: `npx playwright install` cannot download browsers on these machines. Its headless shell
// (Debian's chromium-headless-shell, installed by scripts/test), as Playwright's own headless runs use: no window's
// own pages to render beside the tested one; `CHROMIUM=/usr/bin/chromium` runs the full browser instead.
const SHELL = "/usr/lib/chromium/chromium-headless-shell";

export default defineConfig({
  testDir: "tests",
  globalSetup: "./global-setup.ts",
  globalTeardown: "./global-teardown.ts",
  // Two workers: the tests of the one stack (global-setup.ts) one at a time, as some stop and restart parts of it, and
  // beside them, one at a time too, the tests tagged OWN_STACK (stack.ts), each on a console and domain of its own:
  // most of their time is spent waiting on their processes, not on the CPU.
  workers: 2,
  fullyParallel: false,
  projects: [
    { name: "stack", grepInvert: /@own-stack/, workers: 1 },
    { name: "own-stack", grep: /@own-stack/, workers: 1 },
  ],
  timeout: 90_000,
  // No retries, as pytest (scripts/test): a test that fails once fails the run; a flaky test is fixed at its root.
  retries: 0,
  expect: { timeout: 20_000 },
  reporter: process.env.CI ? [["list"], ["html", { open: "never" }]] : "list",
  outputDir: "test-results",
  use: {
    // 1280x720, the smallest screen the layout tests hold the dashboard to (they set their own sizes where they test
    // one): the software compositor, the map's WebGL and its read-back work per pixel, a third fewer than 1440x900's.
    viewport: { width: 1280, height: 720 },
    screenshot: "only-on-failure",
    // No trace: recording one for every test (its screencast and snapshots) cost about a quarter of the suite's CPU
    // (measured: dashboard.spec 79 CPU-seconds with, 59.5 without), and the suite shares two cores with pytest. A
    // failure keeps its screenshot; `npx playwright test --trace on tests/x.spec.ts` records one for a failing test.
    trace: "off",
    // --disable-gpu leaves WebGL (the map, MapLibre GL) to SwiftShader, the software renderer. Chromium
    // still falls back to it by itself but has deprecated that fallback; --enable-unsafe-swiftshader
    // keeps it explicitly ("unsafe" only for pages of untrusted origins, and these tests load our console).
    // --js-flags=--no-opt: V8 without its optimizing compiler (TurboFan). A test's page lives seconds, and optimizing
    // its code cost more CPU than it saved: `dashboard.spec` and `map.spec` took 127 to 137 CPU-seconds of the machine
    // against 143 and 147 with it (rounds in turns), in no more time; the fleet's 200-vehicle search took 46 ms.
    launchOptions: {
      executablePath: process.env.CHROMIUM ?? SHELL,
      args: [
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--enable-unsafe-swiftshader",
        "--js-flags=--no-opt",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--no-first-run",
      ],
    },
  },
});
