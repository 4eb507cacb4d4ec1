// Screenshot of the map panel (docs/map.png) in headless Chromium, with every request to another origin
// refused (the map must draw from the console alone). Usage: node scripts/map-screenshot.mjs <console URL> <out.png> [vehicle id]
import { launchChromium, refuseOtherOrigins } from "./browser.mjs";

const [url = "http://127.0.0.1:8000", out = "../docs/map.png", show = ""] = process.argv.slice(2);
const browser = await launchChromium();
try {
  const page = await browser.newPage({ viewport: { width: 1440, height: 900 } });
  const foreign = await refuseOtherOrigins(page, url);
  await page.goto(show ? `${url}/?vehicle=${show}` : url);
  await page.getByTestId("connection-state").filter({ hasText: "Live" }).waitFor({ timeout: 20_000 });
  const count = await page.getByTestId("vehicle").count();
  await page.waitForFunction(
    (n) => Number(document.querySelector('[data-testid="map"]')?.getAttribute("data-vehicles")) >= Math.min(n, 1),
    count,
    { timeout: 30_000 },
  );
  // zoomed out far enough to show the coast, then the vehicles' area
  await page.evaluate(() => window.__semMap.jumpTo({ zoom: 8.5 }));
  await page.waitForTimeout(2500);
  await page.getByTestId("map-panel").screenshot({ path: out });
  console.log(`screenshot: ${out}${foreign.length ? ` (refused: ${foreign.join(", ")})` : ""}`);
} finally {
  await browser.close();
}
