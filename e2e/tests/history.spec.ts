// Track and chart history, exports and the command pager against the real stack.
import { readFileSync } from "node:fs";
import { expect, test, type Locator, type Page } from "@playwright/test";
import { open } from "../helpers";

async function points(chart: Locator): Promise<number> {
  return Number((await chart.getAttribute("data-points")) ?? "0");
}

async function firstPoint(chart: Locator): Promise<number> {
  return Number((await chart.getAttribute("data-first")) ?? "Infinity");
}

async function lastPoint(chart: Locator): Promise<number> {
  return Number((await chart.getAttribute("data-last")) ?? "0");
}

async function downloaded(page: Page, testId: string): Promise<{ name: string; text: string }> {
  const [file] = await Promise.all([page.waitForEvent("download"), page.getByTestId(testId).click()]);
  return {
    name: file.suggestedFilename(),
    text: readFileSync((await file.path())!, "utf8"),
  };
}

test("after a reload the GPS chart (uPlot) shows the console's history, then appends live data", async ({ page }) => {
  await open(page);
  const chart = page.getByTestId("fix-history");
  await expect(chart.locator("canvas")).toBeVisible();
  await expect.poll(() => points(chart), { timeout: 30_000 }).toBeGreaterThanOrEqual(5);

  const reloadedAt = Date.now() / 1000;
  await page.reload();
  await expect(page.getByTestId("connection-state")).toHaveText("Live");
  await expect(chart.locator("canvas")).toBeVisible();
  // points from before the reload can only come from the console's history (GET /api/providers/{id}/series)
  await expect.poll(() => firstPoint(chart)).toBeLessThan(reloadedAt - 3);
  const loaded = await points(chart);
  expect(loaded).toBeGreaterThanOrEqual(4);
  // live points keep coming (the count alone stops growing once the chart's window is full, on a long-running stack)
  const newest = await lastPoint(chart);
  await expect.poll(() => lastPoint(chart)).toBeGreaterThan(newest);
});

test("export links download the vehicle's track as GPX and CSV, and the command history as CSV", async ({ page }) => {
  // at 1440x900, as before the suite's 1280x720: at that size the selected vehicle's row of links wraps, and once, under
  // a clean run's load, the click on the row below it brought no download (a tag re-wrapping under the click, we think)
  await page.setViewportSize({ width: 1440, height: 900 });
  const id = await open(page);
  await page.getByRole("combobox", { name: "Export range" }).selectOption({ label: "Everything kept" });

  const gpx = await downloaded(page, "export-gpx");
  expect(gpx.name).toMatch(new RegExp(`^Vehicle-${id.slice(0, 8)}-track-\\d{4}-\\d{2}-\\d{2}T\\d{4}Z\\.gpx$`)); // whose and when, not a GUID
  expect(gpx.text).toContain('<gpx xmlns="http://www.topografix.com/GPX/1/1"');
  expect(gpx.text.match(/<trkpt /g)?.length ?? 0).toBeGreaterThan(3);

  const csv = await downloaded(page, "export-csv");
  const lines = csv.text.trim().split(/\r?\n/);
  expect(lines[0]).toBe(
    "time_utc,latitude_deg,longitude_deg,altitude_msl_m,course_deg,sog_mps,fix_valid,gps_lat_long_valid,position_time_utc,umaa_version",
  );
  expect(lines.length).toBeGreaterThan(3);
  expect(lines[1]).toMatch(/^\d{4}-\d{2}-\d{2}T\d{2}:\d{2}:\d{2}\.\d{3}Z,.*,3\.0\.1$/);

  const commands = await downloaded(page, "export-commands-all");
  expect(commands.name).toMatch(/^all-vehicles-commands-\d{4}-\d{2}-\d{2}T\d{4}Z\.csv$/);
  expect(commands.text.split(/\r?\n/)[0]).toMatch(/^session_id,service,provider_id,/);

  // a reversed range sends nothing and says why
  await page.getByRole("combobox", { name: "Export range" }).selectOption({ label: "Between… (UTC)" });
  await page.getByLabel("From (UTC)").fill("2026-11-22 10:00"); // typed as written everywhere: 24-hour UTC, no browser locale
  await page.getByLabel("To (UTC)").fill("2026-11-22 09:00");
  await expect(page.getByLabel("From (UTC)")).toHaveValue("2026-11-22 10:00"); // shown as typed, not in a locale's picker
  await expect(page.getByTestId("export-panel").getByRole("alert")).toHaveText("From is after To");
  await expect(page.getByTestId("export-gpx")).toHaveAttribute("aria-disabled", "true");
});

test("the command pager shows older commands of the selected vehicle from the console's history", async ({ page, request }) => {
  const id = await open(page);
  const origin = new URL(page.url()).origin;
  for (let i = 0; i < 22; i++) {
    expect(
      (
        await request.post(`${origin}/api/providers/${id}/inertial-sensor`, {
          data: { state: "ON" },
        })
      ).status(),
    ).toBe(201);
  }
  const all = async () =>
    (await (await request.get(`${origin}/api/commands?limit=1000&provider_id=${id}`)).json()) as { terminal: boolean }[];
  await expect
    .poll(async () => (await all()).every((c) => c.terminal), {
      timeout: 60_000,
    })
    .toBe(true);
  const total = (await all()).length;
  expect(total).toBeGreaterThanOrEqual(22);

  const list = page.getByTestId("commands-panel").getByTestId("command");
  await expect(list).toHaveCount(20);
  expect(total).toBeLessThan(100); // the history's first page (100) holds them all: the count is known before any press
  await expect(page.getByTestId("command-count")).toHaveText(`20 of ${total} commands`);
  await page.getByRole("button", { name: "Older commands" }).click(); // past what the page holds: read from GET /api/commands
  await expect(page.getByTestId("command-count")).toHaveText(`${Math.min(40, total)} of ${total} commands`);
  await expect(list).toHaveCount(Math.min(40, total));
  const shown = await list.evaluateAll((els) => els.map((e) => e.getAttribute("data-session")));
  expect(new Set(shown).size).toBe(shown.length);
});
