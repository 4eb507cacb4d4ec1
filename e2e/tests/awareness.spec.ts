// Operator awareness: the console's alarms (kept on the server) on the page, the fleet bar in
// view whatever is scrolled, the tab title's count, and an honest first screen.
import { execFileSync } from "node:child_process";
import { join } from "node:path";
import { expect, test, type APIRequestContext, type Page } from "@playwright/test";
import { SEM_SIM, settleLinkLost, vehicle } from "../helpers";
import { OWN_STACK, VEHICLE_3_NAME, freeDomain, load, restartSim, startGuardedConsole, startSpecSim, stopSim } from "../stack";

interface AlarmRecord {
  id: number;
  kind: string;
  providerId: string | null;
  state: string;
  ackedBy: string | null;
}

async function alarms(request: APIRequestContext, url: string): Promise<AlarmRecord[]> {
  return (await (await request.get(`${url}/api/alarms`)).json()) as AlarmRecord[];
}

/** The tab title's count of unacknowledged alarms ("(3) SEM Console"), 0 for none. */
async function titleCount(page: Page): Promise<number> {
  return Number(/^\((\d+)\) SEM Console$/.exec(await page.title())?.[1] ?? 0);
}

test("with several vehicles and none selected, the panels say so; a chip of the fleet bar selects one", async ({ page }) => {
  const stack = load();
  await page.goto(stack.url);
  await expect(page.getByTestId("connection-state")).toHaveText("Live");
  const bar = page.getByTestId("fleet-bar");
  await expect(bar.getByTestId("fleet-vehicle")).toHaveCount(stack.vehicles.length);
  await expect(page.getByTestId("fix-panel")).toContainText("Select a vehicle");
  await expect(page.getByTestId("fix-panel")).not.toContainText("No GPS fix reports yet");
  await expect(page.getByTestId("ins-panel")).toContainText("Select a vehicle");
  const chip = bar.getByTestId("fleet-vehicle").filter({ hasText: stack.vehicles[1].slice(0, 8) });
  await chip.click();
  await expect(chip).toHaveAttribute("aria-pressed", "true");
  await expect(vehicle(page, stack.vehicles[1])).toHaveAttribute("aria-pressed", "true");
  await expect(page.getByTestId("fix-panel")).not.toContainText("Select a vehicle");
});

test("a vehicle lost while the page is scrolled to the commands is in the viewport, and the tab title counts it", async ({
  page,
  request,
}) => {
  const stack = load();
  await settleLinkLost(request);
  await page.setViewportSize({ width: 1024, height: 768 });
  await page.goto(stack.url);
  await expect(page.getByTestId("connection-state")).toHaveText("Live");
  const chips = page.getByTestId("fleet-bar").getByTestId("fleet-vehicle");
  await expect(chips).toHaveCount(stack.vehicles.length);
  await chips.first().click();
  const commands = page.getByTestId("commands-panel");
  await commands.evaluate((el) => el.scrollIntoView({ block: "start" }));
  await expect(commands).toBeInViewport();
  // the page has scrolled past where the fleet bar sits at the top of the page: it did not scroll with it
  const bar = (await page.getByTestId("fleet-bar").boundingBox())!;
  expect(await page.evaluate(() => window.scrollY)).toBeGreaterThan(bar.y + bar.height);
  const before = await titleCount(page);
  await stopSim();
  try {
    // a chip names the vehicle: its configured name (the third's), else its short id
    for (const label of [stack.vehicles[0].slice(0, 8), stack.vehicles[1].slice(0, 8), VEHICLE_3_NAME]) {
      const chip = chips.filter({ hasText: label });
      await expect(chip).toHaveAttribute("data-link", "lost");
      await expect(chip).toContainText("Lost"); // in words, not by colour alone
      const box = (await chip.boundingBox())!;
      expect(box.y).toBeGreaterThanOrEqual(0);
      expect(box.y + box.height).toBeLessThanOrEqual(768);
    }
    await expect(page.getByTestId("fleet-lost")).toHaveText(`${stack.vehicles.length} lost`);
    await expect(commands).toBeInViewport(); // nothing scrolled the operator away from the commands
    await expect.poll(() => titleCount(page)).toBeGreaterThanOrEqual(before + stack.vehicles.length);
    await expect(page.getByTestId("fleet-alarms")).toHaveText(/^[1-9]\d* unacknowledged alarms?$/);
    // and a screen reader is told, in words, as the tone tells the room
    await expect(page.getByRole("alert").filter({ hasText: "link lost" })).toHaveAttribute("data-testid", "alarm-announcement");
    await expect(page.getByTestId("alarm-announcement")).toContainText(/^Alarm: .*: link lost, since \d\d:\d\d:\d\d UTC/);
  } finally {
    await restartSim(); // the next tests need the vehicles, whatever happened here
  }
  await settleLinkLost(request);
  await expect(page.getByTestId("fleet-lost")).toHaveText("0 lost");
});

test(
  "a vehicle whose INS failed before the page opened shows its alarm, through a reload, until acknowledged",
  { tag: OWN_STACK },
  async ({ page, request }) => {
    // Its own domain and console (with an operator token): a vehicle stopped at the end stays on a console as
    // lost, and the stack's console must keep its three vehicles for the other specs.
    const stack = load();
    const domain = await freeDomain([stack.domain]);
    const token = "awareness-token";
    const extra = await startGuardedConsole(token, ["--domain", String(domain), "--db", join(stack.dir, "awareness.sqlite3")]);
    const id = execFileSync(SEM_SIM, ["--list", "--vehicles", "1", "--first-vehicle", "9"], { encoding: "utf8" })
      .trim()
      .split(": ")[1];
    const sim = await startSpecSim([
      "--domain",
      String(domain),
      "--vehicles",
      "1",
      "--first-vehicle",
      "9",
      "--fault",
      "ins-failure",
      "--time-scale",
      "0.2",
      "--surface-seconds",
      "30",
      "--align-seconds",
      "30",
      "--ins-rate",
      "4",
      "--fix-rate",
      "2",
      "--state-file",
      join(stack.dir, "awareness-sim.json"),
      "--log-level",
      "warning",
    ]);
    try {
      await expect
        .poll(async () => (await alarms(request, extra.url)).some((a) => a.kind === "ins-failure" && a.providerId === id), {
          timeout: 30_000,
        })
        .toBe(true);
      await page.goto(extra.url); // only now: the page never saw the failure happen
      await expect(page.getByTestId("connection-state")).toHaveText("Live");
      const region = page.getByRole("region", { name: "Alarms" });
      const entry = region
        .getByTestId("alarm")
        .and(page.locator('[data-kind="ins-failure"]'))
        .filter({ hasText: id.slice(0, 8) });
      await expect(entry).toBeVisible();
      await expect(entry).toHaveAttribute("data-state", "active-unacknowledged");
      await expect(entry).toContainText("Alarm");
      await expect(entry).toContainText("Unacknowledged");
      await expect.poll(() => titleCount(page)).toBeGreaterThanOrEqual(1);
      // the lone vehicle is selected at once, and its chip says what failed
      const chip = page.getByTestId("fleet-bar").getByTestId("fleet-vehicle");
      await expect(chip).toHaveAttribute("aria-pressed", "true");
      await expect(chip).toContainText("INS failed");
      // the INS panel says it in the same words as the chip and the alarm (the words table), not a name of its own
      await expect(entry).toContainText("INS failed");
      await expect(page.getByTestId("ins-failure")).toHaveText("INS failed: navigation cannot rely on it");

      await page.reload();
      await expect(entry).toBeVisible();
      await expect(entry).toHaveAttribute("data-state", "active-unacknowledged");
      await expect(region.getByTestId("alarm-sign-in")).toBeVisible(); // acknowledging is an operator's action

      await page.getByLabel("Operator token").fill(token);
      await page.getByRole("button", { name: "Sign in" }).click();
      await expect(page.getByTestId("signed-in")).toBeVisible();
      const ack = entry.getByRole("button", { name: /^Acknowledge/ });
      // the console does not answer: said in words
      await page.route("**/api/alarms/*/ack", (route) => route.abort("connectionrefused"));
      await ack.click();
      await expect(entry.getByRole("alert")).toHaveText("Not acknowledged: console unreachable");
      await page.unroute("**/api/alarms/*/ack");
      await ack.focus(); // by keyboard: the button goes with the acknowledgement, the focus stays in the alarm list
      await page.keyboard.press("Enter");
      await expect(entry).toHaveAttribute("data-state", "active-acknowledged"); // the INS still fails: active, acknowledged
      await expect(region.locator(".alarm-list :focus")).toHaveCount(1);
      await expect(entry).toContainText("Acknowledged");
      await expect(entry.getByRole("alert")).toHaveCount(0);
      const kept = (await alarms(request, extra.url)).find((a) => a.kind === "ins-failure" && a.providerId === id);
      expect(kept?.state).toBe("active-acknowledged");
      expect(kept?.ackedBy).toBe("e2e-operator"); // audited with the operator's name
      await page.reload();
      await expect(entry).toHaveAttribute("data-state", "active-acknowledged");
    } finally {
      await sim.stop();
      await extra.stop();
    }
  },
);

test(
  "Acknowledge all by keyboard: said in words, and the focus goes to the alarm list's title, not the page's top",
  { tag: OWN_STACK },
  async ({ page, request }) => {
    const stack = load();
    const domain = await freeDomain([stack.domain]);
    const token = "ack-all-token";
    const extra = await startGuardedConsole(token, ["--domain", String(domain), "--db", join(stack.dir, "ack-all.sqlite3")]);
    const sim = await startSpecSim([
      "--domain",
      String(domain),
      "--vehicles",
      "2",
      "--first-vehicle",
      "7",
      "--fault",
      "ins-failure",
      "--fault",
      "reject",
      "--time-scale",
      "0.2",
      "--surface-seconds",
      "30",
      "--align-seconds",
      "30",
      "--ins-rate",
      "4",
      "--fix-rate",
      "2",
      "--state-file",
      join(stack.dir, "ack-all-sim.json"),
      "--log-level",
      "warning",
    ]);
    try {
      await expect
        .poll(async () => (await alarms(request, extra.url)).filter((a) => a.kind === "ins-failure").length, { timeout: 30_000 })
        .toBe(2);
      await page.goto(extra.url);
      await page.getByLabel("Operator token").fill(token);
      await page.getByRole("button", { name: "Sign in" }).click();
      await expect(page.getByTestId("signed-in")).toBeVisible();
      const region = page.getByRole("region", { name: "Alarms" });
      const all = region.getByRole("button", { name: "Acknowledge all" });
      const said = region.getByRole("status").and(page.getByTestId("alarms-acknowledged"));
      // the console does not answer: its button stays, the focus with it, and the region says none was acknowledged
      await page.route("**/api/alarms/*/ack", (route) => route.abort("connectionrefused"));
      await all.focus();
      await page.keyboard.press("Enter");
      await expect(said).toHaveText("0 alarms of 2 acknowledged; 2 not: see their entries.");
      await expect(all).toBeFocused();
      await page.unroute("**/api/alarms/*/ack");
      await page.keyboard.press("Enter");
      await expect(said).toHaveText("2 alarms acknowledged.");
      await expect(all).toHaveCount(0); // gone with the last unacknowledged alarm
      await expect(region.getByRole("heading", { name: "Alarms" })).toBeFocused();
      await expect(region.getByTestId("alarm").and(page.locator('[data-state="active-acknowledged"]'))).toHaveCount(2);

      // one of them acknowledged elsewhere meanwhile (another station's operator, the same alarm there): the console
      // answers 404 for it, which is no failure to report, and the focus still goes to the title
      const auth = { Authorization: `Bearer ${token}` };
      for (const v of new Set((await alarms(request, extra.url)).map((a) => a.providerId))) {
        expect(
          (
            await request.post(`${extra.url}/api/providers/${v}/gps-fix`, {
              data: {},
              headers: auth,
            })
          ).status(),
        ).toBe(201);
      }
      const failedCommands = async () => (await alarms(request, extra.url)).filter((a) => a.kind === "command-failed");
      await expect.poll(async () => (await failedCommands()).length, { timeout: 30_000 }).toBe(2);
      await expect(region.getByTestId("alarm").and(page.locator('[data-state="active-unacknowledged"]'))).toHaveCount(2);
      let first = true;
      await page.route("**/api/alarms/*/ack", async (route) => {
        if (first) {
          first = false;
          const pressed = Number(new URL(route.request().url()).pathname.split("/").at(-2));
          const [other] = (await failedCommands()).filter((a) => a.id !== pressed);
          expect(
            (
              await request.post(`${extra.url}/api/alarms/${other.id}/ack`, {
                data: {},
                headers: auth,
              })
            ).status(),
          ).toBe(200);
        }
        await route.continue();
      });
      await all.focus();
      await page.keyboard.press("Enter");
      await expect(said).toHaveText("1 alarm acknowledged; 1 already acknowledged elsewhere.");
      await expect(all).toHaveCount(0);
      await expect(region.getByRole("heading", { name: "Alarms" })).toBeFocused();
      await expect(region.getByText("Not acknowledged")).toHaveCount(0);
      expect(first).toBe(false);
    } finally {
      await sim.stop();
      await extra.stop();
    }
  },
);

test(
  "a fleet at 1280x720: the failed vehicle's chip comes first, the alarms are on the first screen, a vehicle picked is shown in the list, the chips are one Tab stop, and the alarm count opens the alarms",
  { tag: OWN_STACK },
  async ({ page, request }) => {
    // A dozen vehicles (a vehicle list taller than the window), the 11th failing: its id sorts near the end
    await page.setViewportSize({ width: 1280, height: 720 });
    const stack = load();
    const domain = await freeDomain([stack.domain]);
    const extra = await startGuardedConsole("fleet-token", [
      "--domain",
      String(domain),
      "--db",
      join(stack.dir, "fleet.sqlite3"),
    ]);
    const ids = execFileSync(SEM_SIM, ["--list", "--vehicles", "12"], {
      encoding: "utf8",
    })
      .trim()
      .split("\n")
      .map((l) => l.split(": ")[1]);
    const failed = ids[10];
    expect([...ids].sort()[0]).not.toBe(failed);
    const sim = await startSpecSim([
      "--domain",
      String(domain),
      "--vehicles",
      "12",
      "--fault",
      "ins-failure:11",
      "--state-file",
      join(stack.dir, "fleet-sim.json"),
      "--log-level",
      "warning",
    ]);
    try {
      await expect
        .poll(async () => (await alarms(request, extra.url)).some((a) => a.kind === "ins-failure" && a.providerId === failed), {
          timeout: 30_000,
        })
        .toBe(true);
      await page.goto(extra.url);
      await expect(page.getByTestId("vehicle")).toHaveCount(12, {
        timeout: 30_000,
      });
      // the vehicle with an alarm is not hidden behind the well ones in the bar's scroll
      await expect(page.getByTestId("fleet-vehicle").first()).toContainText(failed.slice(0, 8));
      await expect(page.getByTestId("fleet-vehicle").first()).toContainText("1 alarm");
      // the vehicle list scrolls within itself: the alarms under it are on the first screen
      const region = page.getByRole("region", { name: "Alarms" });
      const box = (await region.boundingBox())!;
      expect(box.y + 40).toBeLessThan(720);

      // a vehicle picked in the fleet bar is brought into the list's view (the list scrolls, the page does not)
      await page.getByTestId("fleet-vehicle").last().click();
      const list = page.getByTestId("vehicles");
      const row = list.locator('[data-testid="vehicle"][aria-pressed="true"]');
      await expect(row).toHaveCount(1);
      await expect
        .poll(async () => {
          const [l, r] = [(await list.boundingBox())!, (await row.boundingBox())!];
          return r.y >= l.y - 1 && r.y + r.height <= l.y + l.height + 1;
        })
        .toBe(true);
      expect(await page.evaluate(() => window.scrollY)).toBe(0);

      // found by a part of its id or of its name: the list shows the matches, the count is said; Esc or Clear: all again
      const find = page.getByRole("searchbox", { name: "Find" });
      const count = page.getByRole("status").and(page.getByTestId("find-vehicle-count"));
      const listTop = (await list.boundingBox())!.y;
      await find.fill(failed.slice(2, 8).toUpperCase());
      await expect(page.getByTestId("vehicle")).toHaveCount(1);
      expect((await list.boundingBox())!.y).toBe(listTop); // its Clear and count did not push the list down
      await expect(page.getByTestId("vehicle")).toContainText(failed);
      await expect(count).toHaveText("1 of 12 vehicles");
      await find.press("Escape");
      await expect(find).toHaveValue("");
      await expect(page.getByTestId("vehicle")).toHaveCount(12);
      await expect(count).toHaveText("");
      await find.fill("no such vehicle");
      await expect(page.getByTestId("vehicle")).toHaveCount(0);
      await expect(page.getByTestId("find-vehicle-none")).toBeVisible();
      await expect(count).toHaveText("0 of 12 vehicles");
      await page.getByRole("button", { name: "Clear the vehicle search" }).click();
      await expect(find).toBeFocused(); // its Clear gone, the focus back where the operator types
      await expect(page.getByTestId("vehicle")).toHaveCount(12);
      await find.fill(ids[0].slice(9, 18)); // across a dash of the id, as it is written in the list
      await expect(page.getByTestId("vehicle")).toHaveCount(1);
      await page.getByTestId("vehicle").press("Enter"); // the list's keys as before: a match selected
      await expect(page.getByTestId("vehicle")).toHaveAttribute("aria-pressed", "true");
      await expect(page.getByTestId("selected-hidden")).toHaveCount(0);
      // a vehicle selected elsewhere that the search hides: the list says which is selected, and shows it on a press
      await page
        .getByTestId("fleet-vehicle")
        .filter({ hasText: failed.slice(0, 8) })
        .click();
      const hidden = page.getByTestId("selected-hidden");
      await expect(hidden).toContainText(`${failed.slice(0, 8)} selected, not among the matches of the search`);
      await expect(page.getByTestId("vehicle")).toHaveCount(1);
      await hidden.getByRole("button", { name: "Show all vehicles" }).press("Enter");
      await expect(page.getByTestId("vehicle")).toHaveCount(12);
      await expect(find).toHaveValue("");
      await expect(count).toHaveText("");
      await expect(row).toContainText(failed);
      await expect(row).toBeFocused(); // the button pressed gone, the focus on the row it showed
      await find.fill(ids[0].slice(9, 18));
      await expect(page.getByTestId("vehicle")).toHaveCount(1);
      await find.press("Escape");
      await expect(page.getByTestId("vehicle")).toHaveCount(12);
      expect((await region.boundingBox())!.y + 40).toBeLessThan(720); // the search keeps the alarms on the first screen

      // by keyboard the chips are one Tab stop, the arrow keys going through them
      const chips = page.getByTestId("fleet-vehicle");
      await chips.first().focus();
      await page.keyboard.press("ArrowRight");
      await expect(chips.nth(1)).toBeFocused();
      await page.keyboard.press("End");
      await expect(chips.last()).toBeFocused();
      await page.keyboard.press("Tab");
      await expect(page.locator(".fleet-chip:focus")).toHaveCount(0);
      await expect(page.locator(":focus")).toHaveCount(1);

      // collapsed and scrolled to just under the top bars, the count opens it below the bars, the focus in its list
      await page.getByTestId("alarms-panel-collapse").click();
      const bars = (await page.locator(".top-bars").boundingBox())!;
      await page.evaluate((y) => window.scrollTo(0, y), box.y - bars.height + 60);
      await page.getByTestId("fleet-alarms").focus();
      await page.keyboard.press("Enter");
      await expect(page.getByTestId("alarms-panel-collapse")).toHaveAttribute("aria-expanded", "true");
      await expect(region.locator(".alarm-list :focus")).toHaveCount(1);
      await expect.poll(async () => (await region.boundingBox())!.y).toBeGreaterThanOrEqual(bars.y + bars.height);
    } finally {
      await sim.stop();
      await extra.stop();
    }
  },
);
