// Screenshot of the map panel with the CoMap C2 (docs/comap.png): a square survey area near a vehicle
// (PUT /api/worldmodel), a SurveyTask on it (POST /api/tasks), taken while the vehicle is surveying it
// (coverage PARTIAL). Every request to another origin is refused. The console must run with --imc-port
// and the vehicle in its --imc-vehicles. Usage: node scripts/comap-screenshot.mjs <console URL> <out.png> <vehicle id>
import { launchChromium, refuseOtherOrigins } from "./browser.mjs";

const [url = "http://127.0.0.1:8000", out = "../docs/comap.png", id = ""] = process.argv.slice(2);
const json = async (path, init) => {
  const r = await fetch(`${url}${path}`, init);
  if (!r.ok) throw new Error(`${init?.method ?? "GET"} ${path}: ${r.status} ${await r.text()}`);
  return r.json();
};
const send = (method, path, body) =>
  json(path, { method, headers: { "Content-Type": "application/json" }, body: JSON.stringify(body) });

// a 200 m square 80 m north of the vehicle
const g = (await json(`/api/providers/${id}`)).reports.GPSFixReport.report.position2DWithTime.geodeticPosition;
const [lon0, lat0] = [g.geodeticLongitude.longitude, g.geodeticLatitude.latitude];
const dLat = 1 / 111_320;
const dLon = 1 / (111_320 * Math.cos((lat0 * Math.PI) / 180));
const at = (e, n) => [lon0 + e * dLon, lat0 + n * dLat];
const ring = [at(-100, 80), at(100, 80), at(100, 280), at(-100, 280), at(-100, 80)];
const area = {
  type: "Feature",
  geometry: { type: "Polygon", coordinates: [ring] },
  properties: { featureId: 1, name: "survey area" },
};
const done = {
  type: "Feature",
  geometry: { type: "Polygon", coordinates: [[at(-260, 60), at(-140, 60), at(-140, 180), at(-260, 60)]] },
  properties: { featureId: 2, coverage: "COMPLETED" },
};
await send("PUT", "/api/worldmodel", { type: "FeatureCollection", features: [area, done] });
await send("POST", "/api/tasks", { kind: "survey", vehicle: id, featureId: 1, sensor: "SIDESCAN", resolution: 1 });

const browser = await launchChromium();
try {
  const page = await browser.newPage({ viewport: { width: 1440, height: 1000 } });
  const foreign = await refuseOtherOrigins(page, url);
  await page.goto(`${url}/?vehicle=${id}`);
  await page.getByTestId("connection-state").filter({ hasText: "Live" }).waitFor({ timeout: 20_000 });
  await page.locator('[data-testid="feature"][data-coverage="PARTIAL"]').waitFor({ timeout: 60_000 });
  await page.getByTestId("capabilities").filter({ hasText: "area survey" }).waitFor({ timeout: 20_000 });
  const follow = page.getByTestId("map-follow");
  if ((await follow.getAttribute("aria-pressed")) === "true") await follow.click(); // stop following: the area stays in view
  await page.evaluate((c) => window.__semMap.jumpTo({ center: c, zoom: 15.6 }), at(-60, 150));
  await page.waitForTimeout(15_000); // some of the survey's track
  await page.getByTestId("map-panel").screenshot({ path: out });
  console.log(`screenshot: ${out}${foreign.length ? ` (refused: ${foreign.join(", ")})` : ""}`);
} finally {
  await browser.close();
}
