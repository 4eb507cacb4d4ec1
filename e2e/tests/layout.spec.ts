// The panel layout against the real stack: the default arrangement puts the selected vehicle's command
// buttons beside its status and the map on the first screen at 1440×900; nothing scrolls sideways at
// 1280, 1024 or 768 px, and at 768 px the fleet and the map come first. An operator drags a panel, moves
// one with the ↑ ↓ buttons or the keyboard, the order survives a reload, Reset layout brings back the
// default, a stored layout of another build still shows every panel, and a rearranged layout fits 1280×720.
import { expect, test, type Locator, type Page } from "@playwright/test";
import { open, vehicle } from "../helpers";

const STATUS = ["ins-panel", "commands-panel", "fix-panel"];
const MAIN = ["map-panel", "satellites-panel", "export-panel"];
const SIDE = ["alarms-panel", "gateways-panel"];
const ALL = [...STATUS, ...MAIN, ...SIDE];

/** The panels of a group ("status-panels", "main-panels" or "side-panels") in the page's order. */
function order(page: Page, group: string): Promise<string[]> {
  return page.getByTestId(group).evaluate((g) => [...g.children].map((c) => c.getAttribute("data-panel") ?? "?"));
}

async function center(page: Page, testId: string): Promise<{ x: number; y: number }> {
  const box = (await page.getByTestId(testId).boundingBox())!;
  return { x: box.x + box.width / 2, y: box.y + box.height / 2 };
}

/** Store a layout before the page's own scripts run (as a reload of an older or newer build would find it). */
async function storeLayout(page: Page, layout: unknown): Promise<void> {
  await page.addInitScript((v) => localStorage.setItem("sem-console.layout", v), JSON.stringify(layout));
}

/** Whether the page scrolls sideways. */
function scrollsSideways(page: Page): Promise<boolean> {
  return page.evaluate(() => document.scrollingElement!.scrollWidth > document.scrollingElement!.clientWidth);
}

/** The element's box lies wholly in the viewport as it is now (nothing scrolled). */
async function expectOnScreen(page: Page, el: Locator, what: string): Promise<void> {
  const viewport = page.viewportSize()!;
  const box = (await el.boundingBox())!;
  expect(box, what).not.toBeNull();
  expect(box.x, what).toBeGreaterThanOrEqual(0);
  expect(box.y, what).toBeGreaterThanOrEqual(0);
  expect(box.x + box.width, what).toBeLessThanOrEqual(viewport.width);
  expect(box.y + box.height, what).toBeLessThanOrEqual(viewport.height);
}

test("at 1440x900 the selected vehicle's INS and GPS fix buttons are on the first screen, beside its INS and fix status and the map", async ({
  page,
}) => {
  await page.setViewportSize({ width: 1440, height: 900 });
  await open(page);
  expect(await page.evaluate(() => window.scrollY)).toBe(0);
  const commands = page.getByTestId("commands-panel");
  for (const name of ["Request GPS fix", "INS OFF", "INS RESTART"])
    await expectOnScreen(page, commands.getByRole("button", { name, exact: true }), name);
  await expectOnScreen(page, page.getByTestId("ins-state"), "INS state");
  await expectOnScreen(page, page.getByTestId("fix-valid"), "fix status");
  await expectOnScreen(page, page.getByTestId("map"), "map");
  // beside: the status column's panels sit left of the map, the command buttons between the INS and the fix status
  const map = (await page.getByTestId("map").boundingBox())!;
  const insOff = (await commands.getByRole("button", { name: "INS OFF", exact: true }).boundingBox())!;
  expect(insOff.x + insOff.width).toBeLessThan(map.x);
  expect((await page.getByTestId("ins-state").boundingBox())!.y).toBeLessThan(insOff.y);
  expect((await page.getByTestId("fix-valid").boundingBox())!.y).toBeGreaterThan(insOff.y);
  expect(await scrollsSideways(page)).toBe(false);
});

for (const viewport of [
  { width: 1024, height: 768 },
  { width: 768, height: 1024 },
]) {
  test(`at ${viewport.width}x${viewport.height} nothing scrolls sideways, and the fleet and the map come first`, async ({
    page,
  }) => {
    await page.setViewportSize(viewport);
    await open(page);
    await expect(page.getByTestId("satellite-table").locator("tbody tr").first()).toBeVisible();
    expect(await scrollsSideways(page)).toBe(false);
    for (const id of [...ALL, "vehicles", "fleet-bar"]) {
      const box = (await page.getByTestId(id).boundingBox())!;
      expect(box.x, id).toBeGreaterThanOrEqual(0);
      expect(box.x + box.width, id).toBeLessThanOrEqual(viewport.width);
    }
    // first the fleet bar, then the map, on the first screen; the status and commands after the map
    await page.evaluate(() => window.scrollTo(0, 0));
    const fleet = (await page.getByTestId("fleet-bar").boundingBox())!;
    const map = (await page.getByTestId("map").boundingBox())!;
    expect(fleet.y + fleet.height).toBeLessThanOrEqual(map.y);
    expect(map.y).toBeLessThan(viewport.height / 2);
    for (const id of STATUS) expect((await page.getByTestId(id).boundingBox())!.y, id).toBeGreaterThan(map.y + map.height);
    // with the page scrolled down the fleet bar stays in view
    await page.getByTestId("commands-panel").scrollIntoViewIfNeeded();
    await page.getByTestId("fix-panel").scrollIntoViewIfNeeded();
    await expectOnScreen(page, page.getByTestId("fleet-bar"), "fleet bar after scrolling");
    expect(await scrollsSideways(page)).toBe(false);
  });
}

test("drag a panel by its handle: the new order survives a reload, and Reset layout brings back the default", async ({
  page,
}) => {
  await page.setViewportSize({ width: 1440, height: 900 }); // the status panels and their handles on the first screen
  await open(page);
  expect(await order(page, "status-panels")).toEqual(STATUS);
  // drag the fix panel onto the INS panel, above it
  // dnd-kit drops where the dragged panel's centre is closest: move the handle by the distance
  // between the two panels' centres, so the fix panel's centre lands on the INS panel's
  const from = await center(page, "fix-panel-drag");
  const [fixAt, insAt] = [await center(page, "fix-panel"), await center(page, "ins-panel")];
  const to = { x: from.x + insAt.x - fixAt.x, y: from.y + insAt.y - fixAt.y };
  await page.mouse.move(from.x, from.y);
  await page.mouse.down();
  await page.mouse.move(from.x, from.y - 20, { steps: 4 });
  await page.mouse.move(to.x, to.y, { steps: 15 });
  await page.mouse.up();
  const moved = ["fix-panel", "ins-panel", "commands-panel"];
  await expect.poll(() => order(page, "status-panels")).toEqual(moved);
  const fix = (await page.getByTestId("fix-panel").boundingBox())!;
  const ins = (await page.getByTestId("ins-panel").boundingBox())!;
  expect(fix.y).toBeLessThan(ins.y); // shown in that order too

  await page.getByTestId("export-panel-collapse").click();
  await page.reload();
  await expect(page.getByTestId("connection-state")).toHaveText("Live");
  await expect.poll(() => order(page, "status-panels")).toEqual(moved);
  await expect(page.getByTestId("export-panel-collapse")).toHaveAttribute("aria-expanded", "false");

  await page.getByRole("button", { name: "Reset layout" }).click();
  await expect.poll(() => order(page, "status-panels")).toEqual(STATUS);
  await expect(page.getByTestId("export-panel-collapse")).toHaveAttribute("aria-expanded", "true");
  await page.reload();
  await expect(page.getByTestId("connection-state")).toHaveText("Live");
  await expect.poll(() => order(page, "status-panels")).toEqual(STATUS);
  expect(await order(page, "main-panels")).toEqual(MAIN);
});

test("the ↑ ↓ buttons and the keyboard move a panel within its group, and keep the focus", async ({ page }) => {
  await open(page);
  await expect(page.getByTestId("map-panel-earlier")).toBeDisabled();
  await expect(page.getByTestId("export-panel-later")).toBeDisabled();
  await expect(page.getByTestId("ins-panel-earlier")).toBeDisabled();
  await expect(page.getByTestId("fix-panel-later")).toBeDisabled();
  const earlier = page.getByRole("button", { name: "Move Satellites earlier" });
  await earlier.click();
  await expect.poll(() => order(page, "main-panels")).toEqual(["satellites-panel", "map-panel", "export-panel"]);
  await expect(page.getByTestId("main-panels-status")).toHaveText("Satellites moved to place 1 of 3."); // a screen reader hears it
  await expect(page.getByRole("button", { name: "Move Satellites later" })).toBeFocused(); // the first place: "earlier" is off, the focus stays near
  await expect(page.getByTestId("satellite-table")).toBeVisible(); // still drawn where it moved
  const fixEarlier = page.getByTestId("fix-panel-earlier");
  await fixEarlier.click();
  await expect(fixEarlier).toBeFocused();
  await expect.poll(() => order(page, "status-panels")).toEqual(["ins-panel", "fix-panel", "commands-panel"]);

  // the side column, by keyboard: Space picks the panel up, the arrow moves it, Space drops it
  expect(await order(page, "side-panels")).toEqual(SIDE);
  // each key waits for its step to show: the handle pressed, then what a screen reader is told
  const handle = page.getByTestId("alarms-panel-drag");
  await handle.focus();
  await page.keyboard.press("Space");
  await expect(handle).toHaveAttribute("aria-pressed", "true");
  // (the sensor listens for the arrows from its next task on: press again until the move shows)
  await expect(async () => {
    await page.keyboard.press("ArrowDown");
    await expect(page.getByRole("status").filter({ hasText: "Alarms over place 2 of 2." })).toHaveCount(1, { timeout: 2_000 });
  }).toPass();
  await page.keyboard.press("Space");
  await expect(page.getByRole("status").filter({ hasText: "Alarms dropped at place 2 of 2." })).toHaveCount(1);
  await expect.poll(() => order(page, "side-panels")).toEqual(["gateways-panel", "alarms-panel"]);
  expect(await order(page, "main-panels")).not.toContain("alarms-panel"); // a group keeps its own panels
});

test("a stored layout that names unknown panels, misses others or puts one in another group still shows every panel", async ({
  page,
}) => {
  // "fix-panel" in main: a layout of the build before the status column; "ghost-panel": of a later build
  await storeLayout(page, {
    main: ["ghost-panel", "export-panel", "fix-panel", "export-panel"],
    status: ["commands-panel"],
    side: "not a list",
  });
  await open(page);
  await expect.poll(() => order(page, "main-panels")).toEqual(["export-panel", "map-panel", "satellites-panel"]);
  expect(await order(page, "status-panels")).toEqual(["commands-panel", "ins-panel", "fix-panel"]);
  expect(await order(page, "side-panels")).toEqual(SIDE);
  for (const id of ALL) await expect(page.getByTestId(id)).toHaveCount(1);
  await expect(page.getByTestId("ghost-panel")).toHaveCount(0);
});

test("at 1280x720 a rearranged layout fits the width and the satellite table's last column is shown", async ({ page }) => {
  const viewport = { width: 1280, height: 720 };
  await page.setViewportSize(viewport);
  await storeLayout(page, {
    main: ["satellites-panel", "export-panel", "map-panel"],
    status: ["fix-panel", "commands-panel", "ins-panel"],
    side: ["gateways-panel", "alarms-panel"],
  });
  await open(page);
  await expect(page.getByTestId("satellite-table").locator("tbody tr").first()).toBeVisible();
  expect(await scrollsSideways(page)).toBe(false);
  for (const id of ALL) {
    const box = (await page.getByTestId(id).boundingBox())!;
    expect(box.x, id).toBeGreaterThanOrEqual(0);
    expect(box.x + box.width, id).toBeLessThanOrEqual(viewport.width);
  }
  const wrap = page.getByTestId("satellite-table").locator("xpath=..");
  expect(await wrap.evaluate((e) => e.scrollWidth <= e.clientWidth)).toBe(true);
  const th = (await page.getByTestId("satellite-table").locator("thead th").last().boundingBox())!;
  const box = (await wrap.boundingBox())!;
  expect(th.x + th.width).toBeLessThanOrEqual(box.x + box.width + 1);
});

test("at 768 px the vehicle list is one column of vehicles, Rename right under the selected one", async ({ page }) => {
  await page.setViewportSize({ width: 768, height: 1024 });
  const id = await open(page);
  const rows = await page.getByTestId("vehicle").all();
  expect(rows.length).toBeGreaterThan(1);
  const boxes = await Promise.all(rows.map(async (r) => (await r.boundingBox())!));
  for (const b of boxes.slice(1)) {
    expect(b.x).toBe(boxes[0].x); // one column: none beside another
    expect(b.width).toBe(boxes[0].width);
  }
  const selected = (await vehicle(page, id).boundingBox())!;
  const rename = (await page.getByTestId("vehicles").getByRole("button", { name: "Rename", exact: true }).boundingBox())!;
  expect(rename.y).toBeGreaterThanOrEqual(selected.y + selected.height - 1);
  expect(rename.y - (selected.y + selected.height)).toBeLessThan(12);
  expect(Math.abs(rename.x - selected.x)).toBeLessThan(12);
  expect(await scrollsSideways(page)).toBe(false);
});
