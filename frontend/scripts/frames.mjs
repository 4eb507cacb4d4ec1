// The dashboard in headless Chromium: frame times (requestAnimationFrame intervals), long tasks
// (PerformanceObserver "longtask"), renders per panel per second (the dashboard's ?renders counters) and
// JS heap, over one window. Optionally with the CPU throttled (DevTools Emulation.setCPUThrottlingRate)
// and panels collapsed by their collapse buttons.
// Usage: node scripts/frames.mjs <console URL> [seconds=20] [--throttle N] [--collapse <panel test id>]...
// Prints one JSON line.
import { launchChromium, startMeter } from "./browser.mjs";

const positional = [];
const collapse = [];
let throttle = 1;
const argv = process.argv.slice(2);
for (let i = 0; i < argv.length; i++) {
  if (argv[i] === "--throttle") throttle = Number(argv[++i]);
  else if (argv[i] === "--collapse") collapse.push(argv[++i]);
  else positional.push(argv[i]);
}
const [url, seconds = "20"] = positional;

const browser = await launchChromium(["--enable-precise-memory-info", "--js-flags=--expose-gc"]);
try {
  const context = await browser.newContext({ viewport: { width: 1440, height: 900 } });
  const page = await context.newPage();
  await page.goto(`${url}/?renders`);
  await page.getByTestId("connection-state").filter({ hasText: "Live" }).waitFor({ timeout: 30_000 });
  // the panels the operator folded (a collapsed panel is remembered per browser profile, so this context only)
  for (const id of collapse) {
    const button = page.getByTestId(`${id}-collapse`);
    if ((await button.getAttribute("aria-expanded")) === "true") await button.click();
  }
  await page.getByTestId("vehicle").first().click(); // the dashboard selects no vehicle by itself
  await page.getByTestId("sky-satellite").first().waitFor({ timeout: 30_000 });
  if (!collapse.includes("map-panel")) await page.locator('[data-testid="map"][data-ready="true"]').waitFor({ timeout: 60_000 });
  const cdp = await context.newCDPSession(page);
  await cdp.send("Emulation.setCPUThrottlingRate", { rate: throttle });
  await page.waitForTimeout(3000); // settle under the throttle
  const heap = () =>
    page.evaluate(() => {
      globalThis.gc?.();
      return performance.memory.usedJSHeapSize / 2 ** 20;
    });
  const heapStart = await heap();
  await page.evaluate(startMeter);
  await page.waitForTimeout(Number(seconds) * 1000);
  const run = await page.evaluate(() => window.__semMeter.stop());
  const heapEnd = await heap();
  const frames = [...run.frames].sort((a, b) => a - b);
  const q = (p) => frames[Math.min(frames.length - 1, Math.floor(p * frames.length))];
  const r2 = (x) => +x.toFixed(2);
  console.log(
    JSON.stringify({
      throttle,
      collapsed: collapse,
      frames: frames.length,
      p50_ms: r2(q(0.5)),
      p95_ms: r2(q(0.95)),
      max_ms: r2(frames.at(-1)),
      long_tasks: run.longTasks.length,
      long_task_max_ms: r2(Math.max(0, ...run.longTasks)),
      long_task_total_ms: r2(run.longTasks.reduce((a, b) => a + b, 0)),
      renders_per_s: run.renders,
      heap_start_mb: r2(heapStart),
      heap_end_mb: r2(heapEnd),
    }),
  );
} finally {
  await browser.close();
}
