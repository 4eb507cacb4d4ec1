// An operations centre: two console stations on one real PostgreSQL (started for this spec), alice on "watch" and bob
// on "relief". Bob cancels alice's command and both stations' finished cards name him and his station; the
// database stopped, the shared-database banner shows within 2 s of the station knowing, and goes when it is back.
import { execFileSync } from "node:child_process";
import { join } from "node:path";
import { expect, test, type Page } from "@playwright/test";
import { SEM_SIM } from "../helpers";
import { OWN_STACK, freeDomain, load, startExtraConsole, startPostgres, startSpecSim, type SpecSim } from "../stack";

type Running = { url: string; stop: () => Promise<void> };
let pg: Awaited<ReturnType<typeof startPostgres>>;
let watch: Running;
let relief: Running;
let sim: SpecSim | undefined;
let vehicleId: string;

test.describe.configure({ mode: "serial" });

test.beforeAll(async () => {
  test.setTimeout(120_000);
  const stack = load();
  const domain = await freeDomain([stack.domain]);
  pg = await startPostgres();
  // a GPS fix that surfaces only after 400 s: running long enough to be cancelled from the other station
  vehicleId = execFileSync(SEM_SIM, ["--list", "--vehicles", "1", "--first-vehicle", "70"], { encoding: "utf8" })
    .trim()
    .split(": ")[1];
  sim = await startSpecSim([
    "--domain",
    String(domain),
    "--vehicles",
    "1",
    "--first-vehicle",
    "70",
    "--surface-seconds",
    "400",
    "--state-file",
    join(stack.dir, "opscentre-sim.json"),
    "--log-level",
    "warning",
  ]);
  const station = (name: string, operator: string) =>
    startExtraConsole(
      [
        "--domain",
        String(domain),
        "--database-url",
        pg.url,
        "--console-name",
        name,
        "--recordings-dir",
        join(stack.dir, "recordings"),
      ],
      { SEM_OPERATOR_TOKENS: `${operator}:${operator}-token` },
    );
  watch = await station("watch", "alice");
  relief = await station("relief", "bob");
});

test.afterAll(async () => {
  await Promise.all([watch?.stop(), relief?.stop(), sim?.stop()]);
  pg?.close();
});

async function signedIn(page: Page, url: string, operator: string): Promise<void> {
  await page.goto(`${url}/?vehicle=${vehicleId}`);
  await page.getByLabel("Operator token").fill(`${operator}-token`);
  await page.getByRole("button", { name: "Sign in" }).click();
  await expect(page.getByTestId("operator-name")).toHaveText(operator);
}

test(
  "bob on relief cancels alice's command from watch: both stations' finished cards name him and his station",
  { tag: OWN_STACK },
  async ({ browser, request }) => {
    const alicePage = await (await browser.newContext()).newPage();
    const bobPage = await (await browser.newContext()).newPage();
    await signedIn(alicePage, watch.url, "alice");
    await signedIn(bobPage, relief.url, "bob");
    await expect(alicePage.getByTestId("command-target")).toContainText(vehicleId.slice(0, 8), { timeout: 30_000 });
    await expect
      .poll(async () => (await request.get(`${watch.url}/api/providers/${vehicleId}`)).ok(), { timeout: 30_000 })
      .toBe(true);
    const sent = await request.post(`${watch.url}/api/providers/${vehicleId}/gps-fix`, {
      headers: { Authorization: "Bearer alice-token" },
      data: {},
    });
    expect(sent.ok()).toBe(true);
    const session = ((await sent.json()) as { sessionId: string }).sessionId;
    const card = (page: Page) => page.getByTestId("command").and(page.locator(`[data-session="${session}"]`));
    await expect(card(bobPage)).toHaveAttribute("data-status", "EXECUTING", {
      timeout: 30_000,
    });
    await card(bobPage).getByRole("button", { name: "Cancel" }).click();
    for (const page of [alicePage, bobPage]) {
      await expect(card(page)).toHaveAttribute("data-status", "CANCELED", {
        timeout: 30_000,
      });
      await expect(card(page).getByTestId("command-canceller")).toHaveText("cancel asked by bob on relief");
      await card(page).locator("summary").click(); // its timeline
      await expect(card(page).getByTestId("cancel-asked")).toContainText("Cancel asked by bob on relief");
    }
  },
);

test(
  "the database stopped: the shared-database banner about a second after the station knows, and gone once it is back",
  { tag: OWN_STACK },
  async ({ page }) => {
    await page.goto(watch.url);
    await expect(page.getByTestId("connection-state")).toHaveText("Live");
    const banner = page.getByTestId("database-banner");
    await expect(banner).toHaveCount(0);
    // the instant the banner enters the page, taken by the page itself (Playwright's polling would add up to a second)
    await page.evaluate(() => {
      const w = window as unknown as { bannerAt?: number };
      new MutationObserver((_, o) => {
        if (document.querySelector("[data-testid=database-banner]")) {
          w.bannerAt = Date.now();
          o.disconnect();
        }
      }).observe(document.body, { childList: true, subtree: true });
    });
    pg.stop();
    try {
      await expect(banner).toBeVisible({ timeout: 20_000 });
      const seen = (await page.evaluate(() => (window as unknown as { bannerAt?: number }).bannerAt)) ?? Date.now();
      const since = /since (\d{4}-\d\d-\d\d) (\d\d:\d\d:\d\d\.\d{3}) UTC/.exec((await banner.textContent()) ?? "");
      expect(since).not.toBeNull();
      // pushed at the console's next tick: 0.2 s on a quiet machine (bench/opscentre.py, banner_after_max_s);
      // the bound leaves room for this machine loaded by the whole test command, and still fails the 12 s of the defect
      expect(seen / 1000 - Date.parse(`${since![1]}T${since![2]}Z`) / 1000).toBeLessThan(4);
    } finally {
      pg.start();
    }
    await expect(banner).toHaveCount(0, { timeout: 30_000 });
  },
);
