// Accessibility and the colour themes against the real stack: axe-core finds no violation (contrast,
// names, landmarks, ids, ...) on the dashboard in the light and the dark theme with the vehicles streaming
// and one selected; the theme follows the system's preference until the operator picks one in the header,
// and the choice survives a reload.
import { expect, test, type Page } from "@playwright/test";
import { jumpMap, open, settleLinkLost, violations } from "../helpers";
import { load, restartSim, stopSim } from "../stack";

/** The dashboard with live data in every panel of the selected vehicle and the vehicles on the map. */
async function streaming(page: Page): Promise<void> {
  await open(page);
  await expect(page.getByTestId("fix-valid")).toBeVisible();
  await expect(page.getByTestId("ins-state")).toBeVisible();
  await expect(page.getByTestId("satellite-table").locator("tbody tr").first()).toBeVisible();
  await expect(page.getByTestId("map")).toHaveAttribute("data-ready", "true");
  await expect(page.getByTestId("map-label")).toHaveCount(load().vehicles.length, { timeout: 30_000 });
  // the map's first frame waits for the land: over once land is drawn, so a later jump is not undone
  await expect.poll(async () => Number((await page.getByTestId("map").getAttribute("data-land")) ?? "0")).toBeGreaterThan(0);
}

for (const theme of ["light", "dark"] as const) {
  test(`axe finds no violation on the dashboard in the ${theme} theme, vehicles streaming and one selected`, async ({ page }) => {
    await page.emulateMedia({ colorScheme: theme });
    await streaming(page);
    await expect(page.locator("html")).toHaveAttribute("data-theme", theme);
    expect(await violations(page)).toEqual([]);
    // the same with an edge arrow on the map (a vehicle outside the view) and a panel collapsed
    await page.getByTestId("map-follow").click();
    await jumpMap(page, { center: [0, 0], zoom: 6 });
    await expect(page.getByTestId("map-edge").first()).toBeVisible();
    await page.getByTestId("export-panel-collapse").click();
    expect(await violations(page)).toEqual([]);
  });
}

test("axe finds no violation with the selected vehicle lost (its last values shown stale), its alarms and a confirmation open", async ({
  page,
  request,
}) => {
  await settleLinkLost(request);
  await streaming(page);
  await stopSim();
  try {
    await expect(page.getByTestId("fleet-lost")).toHaveText(`${load().vehicles.length} lost`, { timeout: 30_000 });
    await expect(page.getByTestId("fix-panel-freshness")).toContainText("Lost");
    await expect(page.getByTestId("alarm").first()).toBeVisible();
    for (const theme of ["light", "dark"] as const) {
      await page.emulateMedia({ colorScheme: theme });
      await expect(page.locator("html")).toHaveAttribute("data-theme", theme);
      expect(await violations(page)).toEqual([]);
    }
    await page.getByRole("button", { name: /^INS OFF/ }).click(); // to a lost vehicle: a confirmation saying so
    await expect(page.getByRole("dialog")).toBeFocused();
    expect(await violations(page)).toEqual([]);
    await page.keyboard.press("Escape");
  } finally {
    await restartSim(); // the next tests need the vehicles
  }
  await settleLinkLost(request);
});

test("the theme follows the system until the operator picks one in the header; the choice survives a reload", async ({
  page,
}) => {
  await page.emulateMedia({ colorScheme: "dark" });
  await open(page);
  const html = page.locator("html");
  const theme = page.getByRole("combobox", { name: "Theme" });
  await expect(theme).toHaveValue("system");
  await expect(html).toHaveAttribute("data-theme", "dark");
  await page.emulateMedia({ colorScheme: "light" }); // the system turns light (the day comes): so does the page
  await expect(html).toHaveAttribute("data-theme", "light");
  const background = () => page.evaluate(() => getComputedStyle(document.documentElement).backgroundColor);
  const light = await background();

  await theme.selectOption("dark"); // the operator's choice wins over the system's
  await expect(html).toHaveAttribute("data-theme", "dark");
  expect(await background()).not.toBe(light);
  await page.reload();
  await expect(page.getByTestId("connection-state")).toHaveText("Live");
  await expect(html).toHaveAttribute("data-theme", "dark");
  await expect(page.getByRole("combobox", { name: "Theme" })).toHaveValue("dark");

  await page.getByRole("combobox", { name: "Theme" }).selectOption("system");
  await expect(html).toHaveAttribute("data-theme", "light");
  expect(await background()).toBe(light);
});
