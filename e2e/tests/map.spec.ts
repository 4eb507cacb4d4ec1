// The map against the real stack, with every request to anything but the console's origin refused:
// the offline basemap and the vehicles are drawn, clicking a vehicle selects it, measure, follow; for a
// fleet: the first view with the coast, the vehicles' names, Fit all, and arrows at the edge to those outside.
import { expect, test, type Page } from "@playwright/test";
import { consoleOnly, jumpMap, open, vehicle } from "../helpers";
import { VEHICLE_3_NAME, load } from "../stack";

async function drawn(page: Page, attr: "data-land" | "data-vehicles"): Promise<number> {
  return Number((await page.getByTestId("map").getAttribute(attr)) ?? "0");
}

/** The pixel (in the page) where the map draws a vehicle, from its latest position on the console. */
async function vehiclePixel(page: Page, id: string): Promise<{ x: number; y: number }> {
  const r = await page.request.get(`${load().url}/api/providers/${id}`);
  type Fix = {
    report: {
      position2DWithTime: {
        geodeticPosition: {
          geodeticLatitude: { latitude: number };
          geodeticLongitude: { longitude: number };
        };
      };
    };
  };
  const p = (await r.json()) as { reports: { GPSFixReport: Fix } };
  const g = p.reports.GPSFixReport.report.position2DWithTime.geodeticPosition;
  const box = (await page.getByTestId("map").boundingBox())!;
  const xy = await page.evaluate(([lon, lat]) => window.__semMap!.project([lon, lat]), [
    g.geodeticLongitude.longitude,
    g.geodeticLatitude.latitude,
  ] as [number, number]);
  return { x: box.x + xy.x, y: box.y + xy.y };
}

test("offline: the map draws the Natural Earth basemap and every vehicle, and requests nothing from another origin", async ({
  page,
}) => {
  const foreign = await consoleOnly(page);
  const stack = load();
  await page.goto(stack.url);
  await expect(page.getByTestId("connection-state")).toHaveText("Live");
  await expect(page.getByTestId("map")).toHaveAttribute("data-ready", "true");
  await expect.poll(() => drawn(page, "data-vehicles"), { timeout: 30_000 }).toBe(stack.vehicles.length);
  await expect(page.getByTestId("map-vehicle-count")).toHaveText(
    `${stack.vehicles.length} of ${stack.vehicles.length} vehicles drawn`,
  );
  // the CoMap controls are there exactly when the console has a world model
  const hasWorldModel = (await page.request.get(`${stack.url}/api/worldmodel`)).ok();
  await expect(page.getByTestId("comap")).toHaveCount(hasWorldModel ? 1 : 0);
  // zoomed out, the land of the world is drawn from the bundled data (rendered land features, one or more per tile)
  await jumpMap(page, { center: [0, 20], zoom: 1 });
  await expect.poll(() => drawn(page, "data-land")).toBeGreaterThan(0);
  // the status line's count is the land's polygons in view, from its data: the map itself renders them too
  await expect
    .poll(() => page.evaluate(() => window.__semMap!.queryRenderedFeatures({ layers: ["land"] }).length))
    .toBeGreaterThan(0);
  // and nothing where there is only sea (mid-Pacific)
  await page.getByTestId("map-follow").click(); // stop following, so the view stays put
  await jumpMap(page, { center: [-140, -30], zoom: 5 });
  await expect.poll(() => drawn(page, "data-land")).toBe(0);
  expect(foreign).toEqual([]);
});

/** The colour (#rrggbbaa) of the fleet's canvas (FleetCanvas.ts) where the map puts `id`'s latest position: a fix's
 * colour, opaque, where its dot is drawn (its track, under the dot, ends there too, in the vehicle's colour). */
async function fleetColourAt(page: Page, id: string): Promise<string> {
  const r = await page.request.get(`${load().url}/api/providers/${id}`);
  type Fix = {
    report: {
      position2DWithTime: {
        geodeticPosition: {
          geodeticLatitude: { latitude: number };
          geodeticLongitude: { longitude: number };
        };
      };
    };
  };
  const g = ((await r.json()) as { reports: { GPSFixReport: Fix } }).reports.GPSFixReport.report.position2DWithTime
    .geodeticPosition;
  return page.evaluate(
    ([lon, lat]) => {
      const xy = window.__semMap!.project([lon, lat]);
      const canvas = document.querySelector<HTMLCanvasElement>("[data-testid=map-fleet]")!;
      const dpr = canvas.width / canvas.clientWidth;
      const px = canvas.getContext("2d")!.getImageData(Math.round(xy.x * dpr), Math.round(xy.y * dpr), 1, 1).data;
      return "#" + [...px].map((v) => v.toString(16).padStart(2, "0")).join("");
    },
    [g.geodeticLongitude.longitude, g.geodeticLatitude.latitude] as [number, number],
  );
}

test("clicking a vehicle on the map selects it everywhere; the map follows it until the operator pans", async ({ page }) => {
  const foreign = await consoleOnly(page);
  const stack = load();
  await page.goto(stack.url);
  await expect(page.getByTestId("connection-state")).toHaveText("Live");
  await expect.poll(() => drawn(page, "data-vehicles"), { timeout: 30_000 }).toBe(stack.vehicles.length);
  const id = stack.vehicles[1];
  // its dot is drawn on the fleet's canvas where the map puts it (the vehicle moves a pixel or two in between)
  // (FleetCanvas.ts's FIX_COLORS: valid, invalid, unknown)
  await expect.poll(() => fleetColourAt(page, id)).toMatch(/^#(4caf50|e0593f|9fb3c8)ff$/);
  const { x, y } = await vehiclePixel(page, id);
  await page.mouse.click(x, y);
  await expect(vehicle(page, id)).toHaveAttribute("aria-pressed", "true");
  await expect(page).toHaveURL(new RegExp(`vehicle=${id}`));
  await expect(page.getByTestId("map-follow")).toHaveAttribute("aria-pressed", "true");

  // a drag is the operator panning away: following stops; the toggle brings it back
  const box = (await page.getByTestId("map").boundingBox())!;
  await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  await page.mouse.down();
  await page.mouse.move(box.x + box.width / 2 + 120, box.y + box.height / 2 + 60, { steps: 8 });
  await page.mouse.up();
  await expect(page.getByTestId("map-follow")).toHaveAttribute("aria-pressed", "false");
  await page.getByTestId("map-follow").click();
  await expect(page.getByTestId("map-follow")).toHaveAttribute("aria-pressed", "true");
  await expect
    .poll(async () => {
      const p = await vehiclePixel(page, id);
      return Math.hypot(p.x - (box.x + box.width / 2), p.y - (box.y + box.height / 2));
    })
    .toBeLessThan(40);
  expect(foreign).toEqual([]);
});

test("cursor coordinates follow the decimal/DMS setting, and the measure tool gives a distance", async ({ page }) => {
  await consoleOnly(page);
  const stack = load();
  await page.goto(stack.url);
  await expect(page.getByTestId("map")).toHaveAttribute("data-ready", "true");
  // the first frame (every vehicle, and the coast once the land has loaded) is over before the map is moved away
  await expect.poll(() => drawn(page, "data-vehicles"), { timeout: 30_000 }).toBe(stack.vehicles.length);
  await expect.poll(() => drawn(page, "data-land")).toBeGreaterThan(0);
  await jumpMap(page, { center: [0, 0], zoom: 6 });
  const box = (await page.getByTestId("map").boundingBox())!;
  const cx = box.x + box.width / 2;
  const cy = box.y + box.height / 2;
  await page.mouse.move(cx, cy);
  await expect(page.getByTestId("map-cursor")).toHaveText(/^0\.\d{6}° [NS], 0\.\d{6}° [EW]$/);
  await page.getByTestId("map-panel").getByRole("button", { name: "Decimal" }).click();
  await page.mouse.move(cx + 1, cy);
  await expect(page.getByTestId("map-cursor")).toHaveText(/^0° \d\d′ \d\d\.\d\d″ [NS], 0° \d\d′ \d\d\.\d\d″ [EW]$/);
  await page.getByTestId("map-panel").getByRole("button", { name: "DMS" }).click(); // back to decimal for the other tests

  await page.getByTestId("map-measure").click();
  // two points one degree of longitude apart on the equator: 111.2 km
  const a = await page.evaluate(() => window.__semMap!.project([-0.5, 0]));
  const b = await page.evaluate(() => window.__semMap!.project([0.5, 0]));
  await page.mouse.click(box.x + a.x, box.y + a.y);
  await page.mouse.click(box.x + b.x, box.y + b.y);
  await expect(page.getByTestId("map-distance")).toHaveText(/^111\.\d\d km \(60\.\d\d NM\) · last leg 90°$/);
});

test("a collapsed panel stays collapsed across a reload, and expands again", async ({ page }) => {
  await open(page);
  const sats = page.getByTestId("satellites-panel");
  await expect(sats.getByTestId("satellite-table")).toBeVisible();
  await page.getByTestId("satellites-panel-collapse").click();
  await expect(page.getByTestId("satellites-panel-collapse")).toHaveAttribute("aria-expanded", "false");
  await expect(sats.getByTestId("satellite-table")).toHaveCount(0);
  await page.reload();
  await expect(page.getByTestId("connection-state")).toHaveText("Live");
  await expect(page.getByTestId("satellites-panel-collapse")).toHaveAttribute("aria-expanded", "false");
  await expect(page.getByTestId("fix-panel").getByTestId("latitude")).toBeVisible(); // the others are untouched
  await expect(sats.getByTestId("satellite-table")).toHaveCount(0);
  await page.getByTestId("satellites-panel-collapse").click();
  await expect(sats.getByTestId("satellite-table")).toBeVisible();
});

test("the map collapsed and expanded again frames the vehicles again and keeps the tool's cursor", async ({ page }) => {
  await open(page);
  const map = page.getByTestId("map");
  await expect(map).toHaveAttribute("data-ready", "true");
  const zoom = () => page.evaluate(() => window.__semMap?.getZoom() ?? 0);
  await expect.poll(zoom, { timeout: 30_000 }).toBeGreaterThan(3); // the first frame: the vehicles, not the world (zoom 1)
  await page.getByTestId("map-measure").click();
  await page.getByTestId("map-panel-collapse").click();
  await expect(map).toHaveCount(0);
  await page.getByTestId("map-panel-collapse").click();
  await expect(map).toHaveAttribute("data-ready", "true");
  await expect.poll(zoom, { timeout: 30_000 }).toBeGreaterThan(3);
  await expect.poll(() => page.evaluate(() => window.__semMap!.getCanvas().style.cursor)).toBe("crosshair");
});

for (const viewport of [
  { width: 1280, height: 720 },
  { width: 1440, height: 900 },
]) {
  test(`at ${viewport.width}x${viewport.height} every panel fits the width and the satellite table is not cut off`, async ({
    page,
  }) => {
    await page.setViewportSize(viewport);
    await open(page);
    await expect(page.getByTestId("satellite-table").locator("tbody tr").first()).toBeVisible();
    expect(await page.evaluate(() => document.documentElement.scrollWidth)).toBeLessThanOrEqual(viewport.width);
    for (const id of ["map-panel", "satellites-panel", "fix-panel", "ins-panel", "export-panel", "commands-panel", "vehicles"]) {
      const box = (await page.getByTestId(id).boundingBox())!;
      expect(box.x, id).toBeGreaterThanOrEqual(0);
      expect(box.x + box.width, id).toBeLessThanOrEqual(viewport.width);
    }
    // the whole table is in its box: no column hidden behind a horizontal scroll
    const wrap = page.getByTestId("satellite-table").locator("xpath=..");
    const { scroll, client } = await wrap.evaluate((e) => ({
      scroll: e.scrollWidth,
      client: e.clientWidth,
    }));
    expect(scroll).toBeLessThanOrEqual(client);
    const lastHeader = page.getByTestId("satellite-table").locator("thead th").last();
    const th = (await lastHeader.boundingBox())!;
    const box = (await wrap.boundingBox())!;
    expect(th.x + th.width).toBeLessThanOrEqual(box.x + box.width + 1);
    // the map is on the first screen
    const map = (await page.getByTestId("map").boundingBox())!;
    expect(map.y + map.height).toBeLessThanOrEqual(viewport.height);
  });
}

/** Whether the map draws vehicle `id` inside its view now. */
async function inView(page: Page, id: string): Promise<boolean> {
  const box = (await page.getByTestId("map").boundingBox())!;
  const p = await vehiclePixel(page, id);
  return p.x >= box.x && p.x <= box.x + box.width && p.y >= box.y && p.y <= box.y + box.height;
}

test("the first view frames every vehicle with the coast in view, and each vehicle is named on the map", async ({ page }) => {
  const foreign = await consoleOnly(page);
  const stack = load();
  await page.goto(stack.url);
  await expect(page.getByTestId("connection-state")).toHaveText("Live");
  await expect.poll(() => drawn(page, "data-vehicles"), { timeout: 30_000 }).toBe(stack.vehicles.length);
  // the built-in basemap's coastline is drawn in the first view, which is not the whole world
  await expect.poll(() => drawn(page, "data-land")).toBeGreaterThan(0);
  expect(await page.evaluate(() => window.__semMap!.getZoom())).toBeGreaterThan(7);
  // a label per vehicle, by its name (or short id), beside it: right of its dot, or left where the right would
  // cover another's (2 km apart with the coast 25 km away, the vehicles' dots are some 15 px apart)
  const labels = page.getByTestId("map-label");
  await expect(labels).toHaveCount(stack.vehicles.length);
  for (const [i, id] of stack.vehicles.entries()) {
    const label = labels.and(page.locator(`[data-vehicle="${id}"]`));
    await expect(label).toBeVisible();
    await expect(label).toHaveText(i === 2 ? VEHICLE_3_NAME : id.slice(0, 8));
    const at = await vehiclePixel(page, id);
    const box = (await label.boundingBox())!;
    expect(Math.min(Math.abs(box.x - at.x), Math.abs(box.x + box.width - at.x))).toBeLessThan(30);
    expect(Math.abs(box.y + box.height / 2 - at.y)).toBeLessThan(30);
  }
  expect(foreign).toEqual([]);
});

test("Fit all brings every vehicle into view and stops following", async ({ page }) => {
  const stack = load();
  await open(page);
  await expect.poll(() => drawn(page, "data-vehicles"), { timeout: 30_000 }).toBe(stack.vehicles.length);
  await page.getByTestId("map-follow").click(); // stop following, so the view stays where it is put
  await jumpMap(page, { center: [0, 0], zoom: 12 });
  await expect.poll(() => drawn(page, "data-vehicles")).toBe(0);
  await page.getByTestId("map-follow").click();
  await expect(page.getByTestId("map-follow")).toHaveAttribute("aria-pressed", "true");
  await page.getByTestId("map-fit-all").click();
  await expect(page.getByTestId("map-follow")).toHaveAttribute("aria-pressed", "false");
  for (const id of stack.vehicles) await expect.poll(() => inView(page, id), { message: id }).toBe(true);
  await expect.poll(() => drawn(page, "data-vehicles")).toBe(stack.vehicles.length);
  await expect(page.getByTestId("map-edge").filter({ visible: true })).toHaveCount(0);
});

test("a vehicle outside the view gets an arrow at the map's edge with its name; clicking it selects and centres that vehicle", async ({
  page,
}) => {
  const stack = load();
  const first = await open(page);
  await expect.poll(() => drawn(page, "data-vehicles"), { timeout: 30_000 }).toBe(stack.vehicles.length);
  // close in on the selected vehicle (followed): the others, 2 km and more away, leave the view
  await jumpMap(page, { zoom: 16 });
  const charlie = stack.vehicles[2];
  await expect.poll(() => inView(page, charlie)).toBe(false);
  const edge = page.getByTestId("map-edge").and(page.locator(`[data-vehicle="${charlie}"]`));
  await expect(edge).toBeVisible();
  await expect(edge).toHaveText(VEHICLE_3_NAME);
  await expect(edge).toHaveAccessibleName(new RegExp(`^${VEHICLE_3_NAME}: outside the map, [\\d.]+ k?m`));
  await expect(page.getByTestId("map-label").and(page.locator(`[data-vehicle="${charlie}"]`))).toBeHidden();
  await expect(page.getByTestId("map-edge").and(page.locator(`[data-vehicle="${first}"]`))).toBeHidden(); // in view: its label instead
  // at the map's edge, on the side towards the vehicle (north-east of the first: up and right)
  const box = (await page.getByTestId("map").boundingBox())!;
  const e = (await edge.boundingBox())!;
  expect(e.x).toBeGreaterThanOrEqual(box.x);
  expect(e.x + e.width).toBeLessThanOrEqual(box.x + box.width);
  expect(e.y).toBeGreaterThanOrEqual(box.y);
  expect(e.y + e.height).toBeLessThanOrEqual(box.y + box.height);
  const nearEdge = Math.min(e.x - box.x, box.x + box.width - (e.x + e.width), e.y - box.y, box.y + box.height - (e.y + e.height));
  expect(nearEdge).toBeLessThan(40);
  const at = await vehiclePixel(page, charlie);
  expect(Math.sign(at.x - (box.x + box.width / 2))).toBe(Math.sign(e.x + e.width / 2 - (box.x + box.width / 2)));

  await edge.click();
  await expect(vehicle(page, charlie)).toHaveAttribute("aria-pressed", "true");
  await expect(page.getByTestId("map-follow")).toHaveAttribute("aria-pressed", "true");
  await expect
    .poll(async () => {
      const p = await vehiclePixel(page, charlie);
      return Math.hypot(p.x - (box.x + box.width / 2), p.y - (box.y + box.height / 2));
    })
    .toBeLessThan(40);
  await expect(edge).toBeHidden();
  await expect(page.getByTestId("map-label").and(page.locator(`[data-vehicle="${charlie}"]`))).toBeVisible();
});
