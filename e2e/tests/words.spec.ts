// What the page says is true: who is signed in, nothing said live once the console cannot be reached, and a vehicle in
// alarm keeps its name on the map where names would cover one another.
import { execFileSync } from "node:child_process";
import { readFileSync } from "node:fs";
import { dirname, join } from "node:path";
import { fileURLToPath } from "node:url";
import { expect, test, type Page, type WebSocketRoute } from "@playwright/test";
import { jumpMap, SEM_SIM, vehicle } from "../helpers";
import { OWN_STACK, freeDomain, load, startGuardedConsole, startSpecSim } from "../stack";

test("the header names the signed-in operator; once the console cannot be reached, nothing says live, at once", async ({
  page,
}) => {
  const stack = load();
  const token = "words-token";
  const extra = await startGuardedConsole(token, ["--db", join(stack.dir, "words.sqlite3")]);
  let running = true;
  try {
    await page.goto(extra.url);
    await expect(page.getByTestId("connection-state")).toHaveText("Live");
    await page.getByLabel("Operator token").fill(token);
    await page.getByRole("button", { name: "Sign in" }).click();
    await expect(page.getByTestId("signed-in")).toContainText("Signed in as e2e-operator");
    await expect(page.getByTestId("operator-name")).toHaveText("e2e-operator");
    await page.reload(); // the token is kept: the name is asked again
    await expect(page.getByTestId("operator-name")).toHaveText("e2e-operator");

    const n = stack.vehicles.length;
    await expect(page.getByTestId("fleet-live")).toHaveText(`${n} live`, {
      timeout: 30_000,
    });
    await vehicle(page, stack.vehicles[0]).click();
    await expect(page.getByTestId("ins-panel-freshness")).toContainText("Live");
    await extra.stop();
    running = false;
    // within the time the page takes to see its socket closed, not after the vehicles' staleness runs out
    const soon = { timeout: 2_000 };
    await expect(page.getByTestId("connection-state")).not.toHaveText("Live", soon);
    await expect(page.getByTestId("fleet-not-updating")).toHaveText(`${n} not updating`, soon);
    await expect(page.getByTestId("fleet-live")).toHaveCount(0);
    await expect(page.getByTestId("fleet-link")).toHaveText(Array(n).fill("Not updating"));
    await expect(page.getByTestId("vehicle-link")).toHaveText(Array(n).fill("Not updating"));
    await expect(page.getByTestId("ins-panel-freshness")).toContainText("Not updating");
    await expect(page.getByTestId("fleet-bar").getByText(/\blive\b/i)).toHaveCount(0);
    await expect(page.getByTestId("vehicles").getByText(/\blive\b/i)).toHaveCount(0);
  } finally {
    if (running) await extra.stop();
  }
});

test("'Not updating' comes the moment the page's socket drops and goes once the console's snapshot is back", async ({ page }) => {
  const stack = load();
  const n = stack.vehicles.length;
  const sockets: WebSocketRoute[] = [];
  await page.routeWebSocket(/\/ws(\?|$)/, (ws) => {
    if (sockets.length === 0) ws.connectToServer(); // the reconnect waits for the test: the page hears nothing meanwhile
    sockets.push(ws);
  });
  await page.goto(stack.url);
  await expect(page.getByTestId("fleet-live")).toHaveText(`${n} live`, {
    timeout: 30_000,
  });
  await sockets[0].close({ code: 1012, reason: "test: connection dropped" });
  await expect(page.getByTestId("fleet-not-updating")).toHaveText(`${n} not updating`, { timeout: 2_000 });
  await expect.poll(() => sockets.length).toBe(2); // its reconnect is open, and still nothing comes: not updating
  await expect(page.getByTestId("fleet-link")).toHaveText(Array(n).fill("Not updating"));
  sockets[1].connectToServer();
  await expect(page.getByTestId("fleet-live")).toHaveText(`${n} live`, {
    timeout: 10_000,
  });
  await expect(page.getByTestId("fleet-not-updating")).toHaveCount(0);
  await expect(page.getByTestId("vehicle-link")).toHaveText(Array(n).fill("Live"));
});

/** The text of every element whose case CSS changes (text-transform), the panels' titles (headings, no state's words)
 * left aside: a word of the words table is shown as the table writes it. */
const caseChanged = (page: Page) =>
  page.evaluate(() =>
    [...document.querySelectorAll("body *")]
      .filter((e) => getComputedStyle(e).textTransform !== "none" && !e.matches(".panel-head h2"))
      .map((e) => e.textContent),
  );

test("the words table's words as written (no CSS case change); a link gone silent, its socket open, says 'Not updating' as a closed one", async ({
  page,
}) => {
  const stack = load();
  const n = stack.vehicles.length;
  let silent = false;
  const held: (() => void)[] = []; // what the silent link holds, as a network does, and brings when it is back
  await page.routeWebSocket(/\/ws(\?|$)/, (ws) => {
    const server = ws.connectToServer();
    server.onMessage((m) => {
      if (silent)
        held.push(() => ws.send(m)); // the console's frames stop coming, and the socket stays open
      else ws.send(m);
    });
  });
  await page.goto(stack.url);
  await expect(page.getByTestId("fleet-live")).toHaveText(`${n} live`, {
    timeout: 30_000,
  });
  await vehicle(page, stack.vehicles[0]).click();
  // the INS panel's alignment steps, on screen exactly as the words table says them
  const words = JSON.parse(
    readFileSync(join(dirname(fileURLToPath(import.meta.url)), "..", "..", "frontend", "schema", "words.json"), "utf8"),
  ) as Record<string, Record<string, string>>;
  const steps = page.getByTestId("ins-panel").getByRole("list", { name: "Alignment" }).getByRole("listitem");
  const stages = ["INIT", "COARSE", "FINE", "DONE", "OPERATIONAL"]; // a 3.0.1 INS's steps, by stage
  await expect(steps).toHaveText(
    stages.map((x) => words.insAlignmentStep[x]),
    { useInnerText: true },
  );
  expect(await caseChanged(page)).toEqual([]);

  await expect(page.getByTestId("ins-panel-freshness")).toContainText("Live");
  silent = true;
  // the page's pings go unanswered: within its silence bound (4 s) and a ping, the words of a closed socket, not "Stale"
  await expect(page.getByTestId("fleet-not-updating")).toHaveText(`${n} not updating`, { timeout: 7_000 });
  await expect(page.getByTestId("connection-state")).not.toHaveText("Live");
  await expect(page.getByTestId("ins-panel-freshness")).toContainText("Not updating");
  await expect(page.getByTestId("fleet-stale")).toHaveCount(0);
  silent = false; // the link is back: what it held comes, and the page's socket is heard again
  for (const send of held.splice(0)) send();
  await expect(page.getByTestId("fleet-live")).toHaveText(`${n} live`, {
    timeout: 15_000,
  });
});

test(
  "where names on the map would cover one another, a vehicle in alarm keeps its name",
  { tag: OWN_STACK },
  async ({ page, request }) => {
    const stack = load();
    const domain = await freeDomain([stack.domain]);
    const token = "words-map-token";
    const auth = { Authorization: `Bearer ${token}` };
    const extra = await startGuardedConsole(token, ["--domain", String(domain), "--db", join(stack.dir, "words-map.sqlite3")]);
    const ids = execFileSync(SEM_SIM, ["--list", "--vehicles", "3", "--first-vehicle", "20"], { encoding: "utf8" })
      .trim()
      .split("\n")
      .map((l) => l.split(": ")[1]);
    const sim = await startSpecSim([
      "--domain",
      String(domain),
      "--vehicles",
      "3",
      "--first-vehicle",
      "20",
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
      join(stack.dir, "words-map-sim.json"),
      "--log-level",
      "warning",
    ]);
    type AlarmRecord = { id: number; kind: string; providerId: string | null };
    const alarms = async () =>
      ((await (await request.get(`${extra.url}/api/alarms`)).json()) as AlarmRecord[]).filter((a) => a.kind === "ins-failure");
    try {
      await expect.poll(async () => (await alarms()).length, { timeout: 30_000 }).toBe(3);
      await page.goto(extra.url); // none selected: no name is kept for being the selected one's
      await expect(page.getByTestId("map")).toHaveAttribute("data-ready", "true");
      await expect(page.getByTestId("map-label")).toHaveCount(3, {
        timeout: 30_000,
      });
      // the fleet's order, as the list and the map take it: at one place, the first two in it would take the two
      // sides of the dot and the last would lose its name
      const order = await page
        .getByTestId("vehicle")
        .evaluateAll((rows, all) => rows.map((r) => all.find((id) => r.textContent?.includes(id.slice(0, 8)))!), ids);
      const [first, middle, last] = order;
      for (const a of await alarms()) {
        if (a.providerId !== last)
          expect(
            (
              await request.post(`${extra.url}/api/alarms/${a.id}/ack`, {
                headers: auth,
                data: {},
              })
            ).ok(),
          ).toBe(true);
      }
      await expect(page.getByTestId("fleet-alarms")).toHaveText("1 unacknowledged alarm");
      // zoomed out over the fleet (2 km apart): the three names fall on one another
      await page.getByTestId("map-follow").click();
      const at = (await (await request.get(`${extra.url}/api/providers/${first}`)).json()) as {
        reports: {
          GPSFixReport: {
            report: {
              position2DWithTime: {
                geodeticPosition: {
                  geodeticLatitude: { latitude: number };
                  geodeticLongitude: { longitude: number };
                };
              };
            };
          };
        };
      };
      const g = at.reports.GPSFixReport.report.position2DWithTime.geodeticPosition;
      await jumpMap(page, { center: [g.geodeticLongitude.longitude, g.geodeticLatitude.latitude], zoom: 5 });
      const label = (id: string) => page.getByTestId("map-label").and(page.locator(`[data-vehicle="${id}"]`));
      await expect(label(last)).toBeVisible();
      await expect(label(middle)).toBeHidden();
      await expect(label(first)).toBeVisible(); // the other side of the dot
      expect(await caseChanged(page)).toEqual([]); // the alarm's severity ("Alarm") too, as the words table writes it
    } finally {
      await sim.stop();
      await extra.stop();
    }
  },
);
