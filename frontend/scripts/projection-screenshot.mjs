// Screenshot of a lost vehicle projected on the map (docs/projection.png) in headless Chromium: the vehicle, lost,
// selected, and the map zoomed in on its projection. Usage: node scripts/projection-screenshot.mjs <console URL> <out.png> <lost vehicle id>
import { launchChromium, refuseOtherOrigins } from "./browser.mjs";

const [url = "http://127.0.0.1:8000", out = "../docs/projection.png", lost = ""] = process.argv.slice(2);
const browser = await launchChromium();
try {
  const page = await browser.newPage({ viewport: { width: 1440, height: 900 } });
  const foreign = await refuseOtherOrigins(page, url);
  await page.goto(`${url}/?vehicle=${lost}`);
  await page.getByTestId("connection-state").filter({ hasText: "Live" }).waitFor({ timeout: 20_000 });
  const projection = page.locator(`[data-testid="map-projection"][data-vehicle="${lost}"][data-kind="projected"]`);
  await projection.waitFor({ timeout: 30_000 });
  await page.getByTestId("map-follow").click(); // stop following: the view stays on the projection
  await page.getByTestId("map-follow").blur();
  const at = [Number(await projection.getAttribute("data-lon")), Number(await projection.getAttribute("data-lat"))];
  await page.evaluate((c) => window.__semMap.jumpTo({ center: c, zoom: 16.5 }), at);
  await page.waitForTimeout(2500);
  await page.getByTestId("map-panel").screenshot({ path: out });
  console.log(`screenshot: ${out}${foreign.length ? ` (refused: ${foreign.join(", ")})` : ""}`);
} finally {
  await browser.close();
}
