// A large fleet on one console: the fleet bar counts it and shows the exceptional vehicles first with a bounded number
// of chips, and the vehicle list (virtual rows) finds a vehicle by name as the operator types.
import { execFileSync } from "node:child_process";
import { join } from "node:path";
import { expect, test } from "@playwright/test";
import { jumpMap, SEM_SIM, violations } from "../helpers";
import { OWN_STACK, freeDomain, load, startExtraConsole, startSpecSim } from "../stack";

const FLEET = 200; // one sem-sim, every report at 1 Hz: the largest this test's minute allows beside the other worker
const NAMED = 137; // the vehicle given a name, found by it
const CHIP_LIMIT = 24; // FleetBar.tsx

test(
  "a fleet of 200: the bar counts it, a lost vehicle's chip comes first, the chips are bounded, and a search finds a vehicle by name in under a second",
  { tag: OWN_STACK },
  async ({ page }) => {
    test.setTimeout(120_000);
    const stack = load();
    const domain = await freeDomain([stack.domain]);
    const list = (n: number, first: number) =>
      execFileSync(SEM_SIM, ["--list", "--vehicles", String(n), "--first-vehicle", String(first)], { encoding: "utf8" })
        .trim()
        .split("\n")
        .map((l) => l.split(": ")[1]);
    const ids = list(FLEET, 1);
    const [lone] = list(1, FLEET + 1); // on a simulator of its own, stopped to lose it
    const console_ = await startExtraConsole([
      "--domain",
      String(domain),
      "--db",
      join(stack.dir, "fleet-scale.sqlite3"),
      "--vehicle-names",
      `${ids[NAMED - 1]}=Kestrel`,
    ]);
    const rates = ["--fix-rate", "1", "--gps-rate", "1", "--ins-rate", "1", "--satellites", "20", "--log-level", "warning"];
    const sim = (n: number, first: number) =>
      startSpecSim(["--domain", String(domain), "--vehicles", String(n), "--first-vehicle", String(first), ...rates]);
    const fleet = await sim(FLEET, 1);
    const single = await sim(1, FLEET + 1);
    try {
      await page.goto(console_.url);
      await expect(page.getByTestId("fleet-live")).toHaveText(`${FLEET + 1} live`, { timeout: 45_000 });
      // a page opened on the first vehicle heard selects it (the only one, kept in the address): this one opens on the fleet
      await page.goto(console_.url);
      await expect(page.getByTestId("select-vehicle")).toBeVisible();
      await expect(page.getByTestId("fleet-live")).toHaveText(`${FLEET + 1} live`);
      const chips = page.getByTestId("fleet-bar").getByTestId("fleet-vehicle");
      await expect(chips).toHaveCount(CHIP_LIMIT);
      await expect(page.getByTestId("fleet-more")).toHaveText(`${FLEET + 1 - CHIP_LIMIT} more in the vehicle list`);

      await single.stop();
      await expect(page.getByTestId("fleet-lost")).toHaveText("1 lost", { timeout: 30_000 });
      await expect(page.getByTestId("fleet-live")).toHaveText(`${FLEET} live`);
      await expect(chips.first()).toHaveAttribute("data-vehicle", lone);
      await expect(chips.first()).toHaveAttribute("data-link", "lost");
      await expect(chips).toHaveCount(CHIP_LIMIT);

      // the list draws the rows in its view, not the fleet
      const rows = page.getByTestId("vehicles").getByTestId("vehicle");
      expect(await rows.count()).toBeLessThan(60);
      const find = page.getByRole("searchbox", { name: "Find" });
      // from the search's input to the list of one row, timed in the page: the test's own round trips to a browser on
      // a busy machine are not the operator's wait
      type Timed = { searched?: Promise<number> };
      await page.evaluate(() => {
        const list = document.querySelector('[data-testid="vehicles"]')!;
        let typed = 0;
        document.querySelector('[data-testid="find-vehicle"]')!.addEventListener("input", () => (typed ||= performance.now()));
        (window as Timed).searched = new Promise<number>((resolve) => {
          const rows = new MutationObserver(() => {
            if (!typed || list.querySelectorAll('[data-testid="vehicle"]').length !== 1) return;
            rows.disconnect();
            resolve(performance.now() - typed);
          });
          rows.observe(list, { childList: true, subtree: true });
        });
      });
      await find.fill("kestrel");
      expect(await page.evaluate(() => (window as Timed).searched)).toBeLessThan(1_000);
      await expect(rows).toHaveCount(1);
      await expect(rows).toContainText("Kestrel");
      await expect(page.getByTestId("find-vehicle-count")).toHaveText(`1 of ${FLEET + 1} vehicles`);
      await find.press("Escape");
      await expect(rows.first()).toBeVisible();
      // the bar, the search, the filters and the virtual rows are clean for a screen reader; each row says its place
      expect(
        await violations(page, '[data-testid="fleet-bar"]', '[data-testid="vehicles"]', ".find-vehicle", ".fleet-filters"),
      ).toEqual([]);
      await expect(page.getByTestId("vehicles").getByRole("listitem").first()).toHaveAttribute("aria-setsize", String(FLEET + 1));
      // the row with the focus stays in the page (and focused) when the list is scrolled far from it
      await rows.first().focus();
      const focused = await rows.first().locator(".vehicle-id").textContent(); // the id: the row's ages change
      const vehicles = page.getByTestId("vehicles");
      await expect(async () => {
        await vehicles.evaluate((l) => l.scrollTo({ top: l.scrollHeight }));
        await expect(vehicles.getByRole("listitem").last()).toHaveAttribute("aria-posinset", String(FLEET + 1), { timeout: 500 });
      }).toPass();
      expect(
        await page.evaluate(() => document.activeElement?.closest(".vehicle-row")?.querySelector(".vehicle-id")?.textContent),
      ).toBe(focused);

      // the state filter: the lost one alone
      await page.getByRole("combobox", { name: "State" }).selectOption("lost");
      await expect(rows).toHaveCount(1);
      await expect(rows).toHaveAttribute("data-link", "lost");
      await expect(rows).toContainText(lone);

      // zoomed out, the map draws the fleet in clusters, the lost vehicle never among them
      await expect(page.getByTestId("map")).toHaveAttribute("data-ready", "true");
      await jumpMap(page, { zoom: 4 });
      await expect.poll(() => page.evaluate(() => window.__semFleet!.drawnClusters().length)).toBeGreaterThan(0);
      const clustered = await page.evaluate(() => window.__semFleet!.drawnClusters().flat());
      expect(clustered.length).toBeGreaterThan(FLEET / 2);
      expect(clustered).not.toContain(lone);
    } finally {
      await single.stop();
      await fleet.stop();
      await console_.stop();
    }
  },
);
