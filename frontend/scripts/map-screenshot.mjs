// Screenshot of the map panel (docs/map.png) in headless Chromium, with every request to another origin
// refused (the map must draw from the console alone). Usage: node scripts/map-screenshot.mjs <console URL> <out.png> [vehicle id]
import { chromium } from "playwright-core";

const [url = "http://127.0.0.1:8000", out = "../docs/map.png", show = ""] = process.argv.slice(2);
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM ?? "/usr/bin/chromium",
  args: ["--headless", "--no-sandbox", "--disable-gpu", "--enable-unsafe-swiftshader", "--disable-background-networking", "--disable-component-update", "--disable-sync", "--no-first-run"],
});
try {
  const page = await browser.newPage({ viewport: { width: 1440, height: 900 } });
  const origin = new URL(url).origin;
  const foreign = [];
  await page.route("**/*", (route) => {
    if (new URL(route.request().url()).origin === origin) return route.continue();
    foreign.push(route.request().url());
    return route.abort();
  });
  await page.goto(show ? `${url}/?vehicle=${show}` : url);
  await page.getByTestId("connection-state").filter({ hasText: "Live" }).waitFor({ timeout: 20_000 });
  const count = await page.getByTestId("vehicle").count();
  await page.waitForFunction((n) => Number(document.querySelector('[data-testid="map"]')?.getAttribute("data-vehicles")) >= Math.min(n, 1), count, { timeout: 30_000 });
  // zoomed out far enough to show the coast, then the vehicles' area
  await page.evaluate(() => window.__semMap.jumpTo({ zoom: 8.5 }));
  await page.waitForTimeout(2500);
  await page.getByTestId("map-panel").screenshot({ path: out });
  console.log(`screenshot: ${out}${foreign.length ? ` (refused: ${foreign.join(", ")})` : ""}`);
} finally {
  await browser.close();
}
