// The panel layout against the real stack: an operator drags a panel, moves one with the ↑ ↓
// buttons or the keyboard, the order survives a reload, Reset layout brings back the default, a
// stored layout of another build still shows every panel, and a rearranged layout fits 1280×720.
import { expect, test, type Page } from "@playwright/test";
import { open } from "../helpers";

const MAIN = ["map-panel", "fix-panel", "ins-panel", "satellites-panel", "export-panel", "commands-panel"];
const SIDE = ["alerts-panel", "gateways-panel"];

/** The panels of a group ("main-panels" or "side-panels") in the page's order. */
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

test("drag a panel by its handle: the new order survives a reload, and Reset layout brings back the default", async ({ page }) => {
  await open(page);
  expect(await order(page, "main-panels")).toEqual(MAIN);
  // drag the INS panel onto the fix panel, beside it on the left
  await page.getByTestId("ins-panel").scrollIntoViewIfNeeded();
  // dnd-kit drops where the dragged panel's centre is closest: move the handle by the distance
  // between the two panels' centres, so the INS panel's centre lands on the fix panel's
  const from = await center(page, "ins-panel-drag");
  const [insAt, fixAt] = [await center(page, "ins-panel"), await center(page, "fix-panel")];
  const to = { x: from.x + fixAt.x - insAt.x, y: from.y + fixAt.y - insAt.y };
  await page.mouse.move(from.x, from.y);
  await page.mouse.down();
  await page.mouse.move(from.x - 20, from.y, { steps: 4 });
  await page.mouse.move(to.x, to.y, { steps: 15 });
  await page.mouse.up();
  const moved = ["map-panel", "ins-panel", "fix-panel", "satellites-panel", "export-panel", "commands-panel"];
  await expect.poll(() => order(page, "main-panels")).toEqual(moved);
  const ins = (await page.getByTestId("ins-panel").boundingBox())!;
  const fix = (await page.getByTestId("fix-panel").boundingBox())!;
  expect(ins.x).toBeLessThan(fix.x); // shown in that order too

  await page.getByTestId("export-panel-collapse").click();
  await page.reload();
  await expect(page.getByTestId("connection-state")).toHaveText("Live");
  await expect.poll(() => order(page, "main-panels")).toEqual(moved);
  await expect(page.getByTestId("export-panel-collapse")).toHaveAttribute("aria-expanded", "false");

  await page.getByRole("button", { name: "Reset layout" }).click();
  await expect.poll(() => order(page, "main-panels")).toEqual(MAIN);
  await expect(page.getByTestId("export-panel-collapse")).toHaveAttribute("aria-expanded", "true");
  await page.reload();
  await expect(page.getByTestId("connection-state")).toHaveText("Live");
  await expect.poll(() => order(page, "main-panels")).toEqual(MAIN);
});

test("the ↑ ↓ buttons and the keyboard move a panel within its group, and keep the focus", async ({ page }) => {
  await open(page);
  await expect(page.getByRole("button", { name: "Move Map earlier" })).toBeDisabled();
  await expect(page.getByRole("button", { name: "Move Commands later" })).toBeDisabled();
  const earlier = page.getByRole("button", { name: "Move Satellites earlier" });
  await earlier.click();
  await expect(earlier).toBeFocused();
  await earlier.press("Enter");
  await expect.poll(() => order(page, "main-panels")).toEqual(["map-panel", "satellites-panel", "fix-panel", "ins-panel", "export-panel", "commands-panel"]);
  await expect(earlier).toBeFocused();
  await expect(page.getByTestId("main-panels-status")).toHaveText("Satellites moved to place 2 of 6."); // a screen reader hears it
  await expect(page.getByTestId("satellite-table")).toBeVisible(); // still drawn where it moved

  // the side column, by keyboard: Space picks the panel up, the arrow moves it, Space drops it
  expect(await order(page, "side-panels")).toEqual(SIDE);
  // each key waits for its step to show: the handle pressed, then what a screen reader is told
  const handle = page.getByTestId("alerts-panel-drag");
  await handle.focus();
  await page.keyboard.press("Space");
  await expect(handle).toHaveAttribute("aria-pressed", "true");
  // (the sensor listens for the arrows from its next task on: press again until the move shows)
  await expect(async () => {
    await page.keyboard.press("ArrowDown");
    await expect(page.getByRole("status").filter({ hasText: "Alerts over place 2 of 2." })).toHaveCount(1, { timeout: 2_000 });
  }).toPass();
  await page.keyboard.press("Space");
  await expect(page.getByRole("status").filter({ hasText: "Alerts dropped at place 2 of 2." })).toHaveCount(1);
  await expect.poll(() => order(page, "side-panels")).toEqual(["gateways-panel", "alerts-panel"]);
  expect(await order(page, "main-panels")).not.toContain("alerts-panel"); // a group keeps its own panels
});

test("a stored layout that names unknown panels and misses others still shows every panel", async ({ page }) => {
  await storeLayout(page, { main: ["ghost-panel", "commands-panel", "alerts-panel", "commands-panel"], side: "not a list" });
  await open(page);
  await expect.poll(() => order(page, "main-panels")).toEqual(["commands-panel", "map-panel", "fix-panel", "ins-panel", "satellites-panel", "export-panel"]);
  expect(await order(page, "side-panels")).toEqual(SIDE);
  for (const id of [...MAIN, ...SIDE]) await expect(page.getByTestId(id)).toHaveCount(1);
  await expect(page.getByTestId("ghost-panel")).toHaveCount(0);
});

test("at 1280x720 a rearranged layout fits the width and the satellite table's last column is shown", async ({ page }) => {
  const viewport = { width: 1280, height: 720 };
  await page.setViewportSize(viewport);
  await storeLayout(page, { main: ["commands-panel", "satellites-panel", "export-panel", "map-panel", "ins-panel", "fix-panel"], side: ["gateways-panel", "alerts-panel"] });
  await open(page);
  await expect(page.getByTestId("satellite-table").locator("tbody tr").first()).toBeVisible();
  expect(await page.evaluate(() => document.documentElement.scrollWidth)).toBeLessThanOrEqual(viewport.width);
  for (const id of [...MAIN, ...SIDE]) {
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
