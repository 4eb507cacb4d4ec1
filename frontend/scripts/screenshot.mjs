// Screenshot of the dashboard and a quick smoothness measurement, in headless Chromium.
// Usage: node scripts/screenshot.mjs <console URL> <out.png>
// Prints frame-time figures (requestAnimationFrame intervals) while it switches vehicles under live updates.
import { launchChromium } from "./browser.mjs";

const [url = "http://127.0.0.1:8000", out = "../docs/dashboard.png", show = ""] = process.argv.slice(2);
const browser = await launchChromium();
try {
  const page = await browser.newPage({ viewport: { width: 1440, height: 900 } });
  await page.goto(show ? `${url}/?vehicle=${show}` : url); // the dashboard selects no vehicle by itself
  await page.getByTestId("connection-state").filter({ hasText: "Live" }).waitFor({ timeout: 20_000 });
  await page.getByTestId("sky-satellite").first().waitFor({ timeout: 20_000 });
  const vehicles = page.getByTestId("vehicle");
  if (!show) await vehicles.first().click();
  const count = await vehicles.count();

  // frame times while switching vehicles every 500 ms for 10 s
  await page.evaluate(() => {
    const w = window;
    w.__frames = [];
    let last = performance.now();
    const tick = (t) => {
      w.__frames.push(t - last);
      last = t;
      if (!w.__stopFrames) requestAnimationFrame(tick);
    };
    requestAnimationFrame(tick);
  });
  for (let i = 0; i < 20; i++) {
    await vehicles.nth(i % count).click();
    await page.waitForTimeout(500);
  }
  const frames = await page.evaluate(() => {
    window.__stopFrames = true;
    return window.__frames.slice(1);
  });
  frames.sort((a, b) => a - b);
  const q = (p) => frames[Math.min(frames.length - 1, Math.floor(p * frames.length))];
  const fig = {
    vehicles: count,
    frames: frames.length,
    p50_ms: +q(0.5).toFixed(1),
    p95_ms: +q(0.95).toFixed(1),
    max_ms: +frames[frames.length - 1].toFixed(1),
    over_50ms: frames.filter((f) => f > 50).length,
  };
  console.log(JSON.stringify({ frame_times_while_switching: fig }));

  await (show ? vehicles.filter({ hasText: show.slice(0, 8) }) : vehicles.first()).click();
  await page.waitForTimeout(1500);
  await page.screenshot({ path: out, fullPage: false });
  console.log(`screenshot: ${out}`);
} finally {
  await browser.close();
}
