// Frame times (requestAnimationFrame intervals) and JS heap of the dashboard in headless Chromium.
// Usage: node scripts/frames.mjs <console URL> [seconds=20]; prints one JSON line.
import { chromium } from "playwright-core";

const [url, seconds = "20"] = process.argv.slice(2);
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM ?? "/usr/bin/chromium",
  args: ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking", "--disable-component-update",
    "--disable-sync", "--no-first-run", "--enable-precise-memory-info", "--js-flags=--expose-gc"],
});
try {
  const page = await browser.newPage({ viewport: { width: 1440, height: 900 } });
  await page.goto(url);
  await page.getByTestId("connection-state").filter({ hasText: "Live" }).waitFor({ timeout: 30_000 });
  await page.getByTestId("vehicle").first().click(); // the dashboard selects no vehicle by itself
  await page.getByTestId("sky-satellite").first().waitFor({ timeout: 30_000 });
  await page.waitForTimeout(2000);
  const heap = () => page.evaluate(() => { globalThis.gc?.(); return performance.memory.usedJSHeapSize / 2 ** 20; });
  const heapStart = await heap();
  const frames = await page.evaluate((ms) => new Promise((resolve) => {
    const out = [];
    let last = performance.now();
    const end = last + ms;
    const tick = (t) => {
      out.push(t - last);
      last = t;
      if (t < end) requestAnimationFrame(tick);
      else resolve(out);
    };
    requestAnimationFrame(tick);
  }), Number(seconds) * 1000);
  const heapEnd = await heap();
  frames.sort((a, b) => a - b);
  const q = (p) => frames[Math.min(frames.length - 1, Math.floor(p * frames.length))];
  console.log(JSON.stringify({ frames: frames.length, p50_ms: +q(0.5).toFixed(2), p95_ms: +q(0.95).toFixed(2), max_ms: +frames.at(-1).toFixed(2),
    heap_start_mb: +heapStart.toFixed(1), heap_end_mb: +heapEnd.toFixed(1) }));
} finally {
  await browser.close();
}
