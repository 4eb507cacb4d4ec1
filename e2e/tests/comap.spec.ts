// CoMap over IMC against the real stack (sem-console and sem-sim talking IMC over UDP on 127.0.0.1), with
// every request to anything but the console's origin refused: the operator draws a polygon on the map,
// moves one of its vertices, sends the world model and assigns a SurveyTask on it to a simulated vehicle;
// the task goes ASSIGNED, ACCEPTED, IN_PROGRESS, COMPLETED, the vehicle's track crosses the polygon and the
// feature's coverage colour, in the feature list and on the map, goes PARTIAL (amber), then COMPLETED (green);
// then the operator deletes the feature.
import { expect, test, type Page } from "@playwright/test";
import { consoleOnly, jumpMap, vehicle } from "../helpers";
import { VEHICLE_3_NAME, load } from "../stack";

type LonLat = [number, number];
const PARTIAL = { hex: "#f5a623", rgb: "rgb(245, 166, 35)" }; // the legend's "Partly covered (amber)"
const COMPLETED = { hex: "#4caf50", rgb: "rgb(76, 175, 80)" }; // "Covered (green)"

/** The vehicle's latest GPSFixReport position on the console, [lon, lat] in degrees. */
async function position(page: Page, id: string): Promise<LonLat> {
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
  const p = (await (await page.request.get(`${load().url}/api/providers/${id}`)).json()) as { reports: { GPSFixReport: Fix } };
  const g = p.reports.GPSFixReport.report.position2DWithTime.geodeticPosition;
  return [g.geodeticLongitude.longitude, g.geodeticLatitude.latitude];
}

/** The page pixels where the map draws positions. */
async function pixels(page: Page, at: LonLat[]): Promise<{ x: number; y: number }[]> {
  const box = (await page.getByTestId("map").boundingBox())!;
  const xy = await page.evaluate((ps) => ps.map((p) => window.__semMap!.project(p)), at);
  return xy.map((p) => ({ x: box.x + p.x, y: box.y + p.y }));
}

/** Whether a position is inside a polygon ring (ray casting; fine at the size of a survey area). */
function inside([x, y]: LonLat, ring: number[][]): boolean {
  let hit = false;
  for (let i = 0, j = ring.length - 1; i < ring.length; j = i++) {
    const [xi, yi] = ring[i];
    const [xj, yj] = ring[j];
    if (yi > y !== yj > y && x < ((xj - xi) * (y - yi)) / (yj - yi) + xi) hit = !hit;
  }
  return hit;
}

/** The coverage and colour the map renders for a feature (its fill layer), null while not drawn. */
async function rendered(page: Page, featureId: number): Promise<{ coverage: unknown; color: unknown } | null> {
  return page.evaluate((fid) => {
    const f = window.__semMap!.queryRenderedFeatures({ layers: ["wm-fill"] }).find((x) => x.properties?.featureId === fid);
    return f ? { coverage: f.properties?.coverage ?? null, color: f.properties?.color } : null;
  }, featureId);
}

// the smallest supported layout: less for the software renderer (SwiftShader) to draw on a loaded machine
test.use({ viewport: { width: 1280, height: 720 } });

test("a polygon drawn and edited on the map is surveyed by a simulated vehicle over IMC: the track crosses it, coverage goes PARTIAL then COMPLETED", async ({
  page,
}) => {
  test.setTimeout(120_000); // the survey itself runs in real time (about 20 s); the rest waits on a loaded machine's renderer
  const foreign = await consoleOnly(page);
  const stack = load();
  const id = stack.vehicles[2];
  const tasks: { taskId: number; state: string }[] = []; // every `task` message the page receives
  page.on("websocket", (ws) =>
    ws.on("framereceived", ({ payload }) => {
      const m = JSON.parse(String(payload)) as {
        type: string;
        task?: { taskId: number; state: string };
      };
      if (m.type === "task" && m.task) tasks.push(m.task);
    }),
  );
  await page.goto(stack.url);
  await expect(page.getByTestId("connection-state")).toHaveText("Live");

  // the basemap and every vehicle are drawn
  const map = page.getByTestId("map");
  await expect(map).toHaveAttribute("data-ready", "true");
  await expect
    .poll(async () => Number(await map.getAttribute("data-vehicles")), {
      timeout: 30_000,
    })
    .toBe(stack.vehicles.length);
  await jumpMap(page, { center: [0, 20], zoom: 1 });
  await expect.poll(async () => Number(await map.getAttribute("data-land"))).toBeGreaterThan(0);

  // the vehicle to task, with its CoMap capabilities; the map stops following so it stays where we draw
  await vehicle(page, id).click();
  await expect(vehicle(page, id)).toHaveAttribute("aria-pressed", "true");
  const comap = page.getByTestId("comap");
  await expect(comap.getByTestId("capabilities")).toContainText(`IMC ${stack.imcVehicles[2]}: area survey side-scan sonar`, {
    timeout: 30_000,
  });
  await expect(comap.getByTestId("capabilities")).toContainText("move 8 m/s");
  const follow = page.getByTestId("map-follow");
  if ((await follow.getAttribute("aria-pressed")) === "true") await follow.click();
  await expect(follow).toHaveAttribute("aria-pressed", "false");

  // a 120 m square 60 m north of the vehicle, drawn by clicking its corners on the map
  const [lon0, lat0] = await position(page, id);
  const dLat = 1 / 111_320;
  const dLon = 1 / (111_320 * Math.cos((lat0 * Math.PI) / 180));
  const corner = (east: number, north: number): LonLat => [lon0 + east * dLon, lat0 + north * dLat];
  const square = [corner(-60, 60), corner(60, 60), corner(60, 180), corner(-60, 180)];
  await jumpMap(page, { center: corner(0, 120), zoom: 16 });
  const before = await comap.getByTestId("feature").count();
  await comap.getByRole("button", { name: "Draw feature" }).click();
  const corners = await pixels(page, square);
  for (const { x, y } of corners) await page.mouse.click(x, y);
  await comap.getByRole("button", { name: "Finish (4 points)" }).click();
  await expect(comap.getByTestId("feature")).toHaveCount(before + 1);
  const fid = Number(await comap.getByTestId("feature").last().getAttribute("data-feature-id"));
  const feature = comap.locator(`[data-testid="feature"][data-feature-id="${fid}"]`);
  await expect(feature).toContainText(`#${fid} Polygon`);

  // edit: drag the north-east corner's handle 40 px further east
  await comap.getByTestId("edit-features").click();
  await expect
    .poll(() => page.evaluate(() => window.__semMap!.queryRenderedFeatures({ layers: ["edit-handle"] }).length))
    .toBeGreaterThanOrEqual(4);
  const ne = corners[2];
  await page.mouse.move(ne.x, ne.y);
  await page.mouse.down();
  await page.mouse.move(ne.x + 20, ne.y, { steps: 4 });
  await page.mouse.move(ne.x + 40, ne.y, { steps: 4 });
  await page.mouse.up();
  await comap.getByTestId("edit-features").click(); // done editing

  // send the world model: the console has the edited polygon
  await comap.getByTestId("send-worldmodel").click();
  await expect(comap.getByTestId("send-worldmodel")).toBeDisabled(); // nothing left to send
  type Model = {
    features: {
      geometry: { type: string; coordinates: number[][][] };
      properties: { featureId: number; coverage: string | null };
    }[];
  };
  const model = (await (await page.request.get(`${stack.url}/api/worldmodel`)).json()) as Model;
  const sent = model.features.find((f) => f.properties.featureId === fid)!;
  expect(sent.geometry.type).toBe("Polygon");
  const ring = sent.geometry.coordinates[0];
  expect(ring).toHaveLength(5); // 4 vertices, closed
  // each vertex where the mouse put it (within 2 px, at about 2 m a pixel): the moved one 40 px east
  const want = corners.map((c, i) => (i === 2 ? { x: c.x + 40, y: c.y } : c));
  const got = await pixels(page, ring.slice(0, 4) as LonLat[]);
  got.forEach((p, i) => expect(Math.hypot(p.x - want[i].x, p.y - want[i].y), `vertex ${i}`).toBeLessThan(2));
  await expect(feature).toHaveAttribute("data-coverage", "");

  // assign a SurveyTask on it to the selected vehicle
  await comap.getByLabel("Feature", { exact: true }).selectOption(String(fid));
  await comap.getByLabel("Sensor", { exact: true }).selectOption("SIDESCAN");
  await comap.getByRole("button", { name: "Survey", exact: true }).click();
  const confirm = comap.getByRole("dialog", { name: "Confirm survey" }); // bound to the vehicle and named
  await expect(confirm).toContainText(`Survey feature #${fid} with ${VEHICLE_3_NAME} (${id.slice(0, 8)})`);
  await confirm.getByRole("button", { name: "Send survey" }).click();
  const row = comap.getByTestId("task").first();
  await expect(row.getByTestId("task-state")).toHaveAttribute("data-state", /ACCEPTED|IN_PROGRESS/, { timeout: 20_000 });
  const taskId = Number(await row.getAttribute("data-task-id"));
  // the station that assigned it, as every console on the database shows it
  const { consoleName } = (await (await page.request.get(`${stack.url}/api/health`)).json()) as { consoleName: string };
  await expect(row.getByTestId("task-station")).toHaveText(` on ${consoleName}`);

  // coverage PARTIAL, in the list (text and swatch) and on the map, in the same colour
  await expect(feature).toHaveAttribute("data-coverage", "PARTIAL", {
    timeout: 30_000,
  });
  await expect(feature.getByTestId("coverage")).toHaveAttribute("title", "IMC coverage: PARTIAL");
  await expect(feature.getByTestId("coverage-swatch")).toHaveCSS("background-color", PARTIAL.rgb);
  await expect.poll(() => rendered(page, fid)).toEqual({ coverage: "PARTIAL", color: PARTIAL.hex });

  // an edit draft opened now still shows the coverage the vehicle reports, and no survey is assigned from it
  await comap.getByTestId("edit-features").click();
  await expect(comap.getByTestId("draft-note")).toBeVisible();
  await expect(comap.getByRole("button", { name: "Survey", exact: true })).toBeDisabled();

  // then COMPLETED (shown through the draft), the task too
  await expect(feature).toHaveAttribute("data-coverage", "COMPLETED", {
    timeout: 60_000,
  });
  await expect(feature.getByTestId("coverage-swatch")).toHaveCSS("background-color", COMPLETED.rgb);
  await expect.poll(() => rendered(page, fid)).toEqual({ coverage: "COMPLETED", color: COMPLETED.hex });
  await expect(row.getByTestId("task-state")).toHaveAttribute("data-state", "COMPLETED");
  await expect(row.getByTestId("task-progress")).toHaveText("100%");
  const states = tasks.filter((t) => t.taskId === taskId).map((t) => t.state);
  expect(states.slice(0, 2)).toEqual(["ASSIGNED", "ACCEPTED"]);
  expect(states).toContain("IN_PROGRESS");
  expect(states[states.length - 1]).toBe("COMPLETED");

  // sending the draft opened while PARTIAL keeps the console's coverage (COMPLETED), not the draft's copy
  await comap.getByTestId("edit-features").click(); // done editing
  await comap.getByTestId("send-worldmodel").click();
  await expect(comap.getByTestId("send-worldmodel")).toBeDisabled();
  const resent = (await (await page.request.get(`${stack.url}/api/worldmodel`)).json()) as Model;
  expect(resent.features.find((f) => f.properties.featureId === fid)?.properties.coverage).toBe("COMPLETED");

  // the vehicle's stored UMAA track went over the polygon
  await expect
    .poll(async () => {
      const pts = (await (await page.request.get(`${stack.url}/api/providers/${id}/track`)).json()) as {
        latitude: number;
        longitude: number;
      }[];
      return pts.filter((p) => inside([p.longitude, p.latitude], ring)).length;
    })
    .toBeGreaterThanOrEqual(3);
  // and the map draws that track over it: vertices of the vehicle's drawn track (the fleet's canvas) lie inside the polygon
  const drawnTrack = () =>
    page.evaluate(
      (vid) =>
        window
          .__semFleet!.tracks()
          .filter((t) => t.id === vid)
          .flatMap((t) => t.points.map((p) => [p.lon, p.lat])),
      id,
    );
  await expect.poll(async () => (await drawnTrack()).filter((c) => inside([c[0], c[1]], ring)).length).toBeGreaterThanOrEqual(3);

  // delete it on the map (the edit tool: click it, Delete): gone from the console's world model once sent
  await comap.getByTestId("edit-features").click();
  await map.evaluate((e) => e.scrollIntoView({ block: "center" })); // the controls clicked below it may have scrolled it away
  const [mid] = await pixels(page, [corner(0, 120)]);
  await page.mouse.click(mid.x, mid.y);
  await expect(feature).toHaveAttribute("aria-current", "true");
  await comap.getByTestId("delete-picked").click();
  await expect(feature).toHaveCount(0);
  await comap.getByTestId("edit-features").click(); // done editing
  await comap.getByTestId("send-worldmodel").click();
  await expect(comap.getByTestId("send-worldmodel")).toBeDisabled();
  const after = (await (await page.request.get(`${stack.url}/api/worldmodel`)).json()) as Model;
  expect(after.features.map((f) => f.properties.featureId)).not.toContain(fid);

  // a feature drawn next does not take the deleted one's id (its survey's coverage would colour it)
  await comap.getByRole("button", { name: "Draw feature" }).click();
  await map.evaluate((e) => e.scrollIntoView({ block: "center" }));
  const [again] = await pixels(page, [corner(0, 120)]);
  await page.mouse.click(again.x, again.y);
  await comap.getByRole("button", { name: "Finish (1 points)" }).click();
  const drawnId = Number(await comap.getByTestId("feature").last().getAttribute("data-feature-id"));
  expect(drawnId).toBeGreaterThan(fid);
  await comap.getByRole("button", { name: "Discard changes" }).click();
  expect(foreign).toEqual([]);
});
