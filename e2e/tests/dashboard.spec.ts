// The dashboard against the real stack: sem-console and sem-sim over Cyclone DDS on loopback.
// Vehicle 1 is healthy, vehicle 2 rejects every command, vehicle 3 skips COMMANDED (a Figure 4 violation).
import { readFileSync } from "node:fs";
import { expect, test, type Locator } from "@playwright/test";
import { latestCommand, open, vehicle } from "../helpers";
import { load, restartConsole, restartSim, startGuardedConsole, stopSim } from "../stack";

const HAPPY = ["ISSUED", "COMMANDED", "EXECUTING", "COMPLETED"];

async function statuses(cmd: Locator): Promise<string[]> {
  return cmd.getByTestId("transition").evaluateAll((els) => els.map((e) => (e as HTMLElement).dataset.status ?? ""));
}

test("the dashboard shows the connection, the vehicles, satellites, sky plot, fix and INS", async ({ page, request }) => {
  const id = await open(page);
  await expect(page.getByTestId("vehicle")).toHaveCount(3);
  await expect(page.getByTestId("bus-security")).toHaveText("DDS bus open (no security)"); // the stack has no --dds-security
  const detail = await (await request.get(`${load().url}/api/providers/${id}`)).json();
  const listed = detail.reports.GPSReport.report.satellites.length;
  expect(listed).toBeGreaterThanOrEqual(20);
  await expect(page.getByTestId("sats-listed")).toHaveText(String(listed));
  await expect(page.getByRole("img", { name: "Sky plot" })).toBeVisible();
  await expect(page.getByTestId("sky-satellite")).toHaveCount(listed);
  await expect(page.getByTestId("cn0-bar")).toHaveCount(listed);
  await expect(page.getByTestId("satellite-table").locator("tbody tr")).toHaveCount(listed);
  await expect(page.getByTestId("fix-panel")).toBeVisible();
  await expect(page.getByTestId("latitude")).toContainText("° N");
  await expect(page.getByTestId("ins-panel")).toBeVisible();
  await expect(page.getByTestId("ins-state")).toHaveAttribute("data-state", "ON");
});

test("another vehicle selected: its satellites at once, though the console sent them only now and then while it was not", async ({
  page,
  request,
}) => {
  const selects: unknown[] = []; // what the page tells the console it draws
  const partial = new Set<string>(); // the vehicles of which the console sent a GPSReport without its satellites
  page.on("websocket", (ws) => {
    ws.on("framesent", ({ payload }) => {
      const msg = JSON.parse(String(payload)) as {
        type: string;
        providerId?: string | null;
      };
      if (msg.type === "select") selects.push(msg.providerId);
    });
    ws.on("framereceived", ({ payload }) => {
      const data = JSON.parse(String(payload)) as unknown;
      for (const m of (Array.isArray(data) ? data : [data]) as {
        type: string;
        providerId?: string;
        partial?: boolean;
      }[])
        if (m.type === "report" && m.partial && m.providerId) partial.add(m.providerId);
    });
  });
  const first = await open(page);
  await expect(page.getByTestId("sky-satellite").first()).toBeVisible();
  const second = load().vehicles[1];
  await expect.poll(() => selects.at(-1)).toBe(first);
  await expect.poll(() => partial.has(second)).toBe(true); // the other vehicles' GPSReports come without satellites
  await vehicle(page, second).click();
  await expect.poll(() => selects.at(-1)).toBe(second);
  const detail = await (await request.get(`${load().url}/api/providers/${second}`)).json();
  const listed = detail.reports.GPSReport.report.satellites.length;
  expect(listed).toBeGreaterThanOrEqual(20);
  await expect(page.getByTestId("sats-listed")).toHaveText(String(listed));
  await expect(page.getByTestId("sky-satellite")).toHaveCount(listed);
  await expect(page.getByTestId("satellite-table").locator("tbody tr")).toHaveCount(listed);
});

test("Request GPS fix: the timeline walks ISSUED to COMPLETED and the fix becomes valid", async ({ page }) => {
  await open(page);
  await expect(page.getByTestId("fix-valid")).toHaveText("No fix");
  // the receiver's own state, which the vehicle reports with no command sent too: said as what it reports, never as
  // a command's progress ("GPS fix starting")
  const fixState = page.getByTestId("gps-fix-state");
  await expect(fixState).toHaveText(/^Receiver: (initiating a fix|performing a fix|fix stable)$/);
  await expect(fixState).toHaveAttribute(
    "title",
    /^UMAA GPSFixCommandStatus: [A-Z]+ \(the receiver's state as the vehicle reports it, whether or not a fix was commanded\)$/,
  );
  await page.getByRole("button", { name: "Request GPS fix", exact: true }).click();
  const cmd = latestCommand(page);
  await expect(cmd).toHaveAttribute("data-status", "COMPLETED", {
    timeout: 30_000,
  });
  expect(await statuses(cmd)).toEqual(HAPPY);
  await expect(page.getByTestId("fix-valid")).toHaveText("Fix valid");
  await expect(page.getByTestId("gps-fix-state")).toHaveAttribute("data-state", "STABLE");
});

test("INS RESTART: RESTARTING, then alignment to OPERATIONAL, and the command completes", async ({ page }) => {
  await open(page);
  await expect(page.getByTestId("ins-status")).toHaveAttribute("data-status", "OPERATIONAL", { timeout: 30_000 });
  await page.getByRole("button", { name: "INS RESTART", exact: true }).click();
  await page.getByRole("dialog", { name: "Confirm command" }).getByRole("button", { name: "Confirm" }).click();
  await expect(page.getByTestId("ins-state")).toHaveAttribute("data-state", "RESTARTING");
  await expect(page.getByTestId("ins-status")).toHaveAttribute("data-status", "COURSE_STATIONARY_ALIGNMENT");
  await expect(page.getByTestId("ins-state")).toHaveAttribute("data-state", "ON");
  await expect(page.getByTestId("ins-status")).toHaveAttribute("data-status", "OPERATIONAL", { timeout: 30_000 });
  const cmd = latestCommand(page);
  await expect(cmd).toHaveAttribute("data-status", "COMPLETED");
  expect(await statuses(cmd)).toEqual(HAPPY);
});

test("cancel a running command: CANCELED appears", async ({ page }) => {
  const id = await open(page);
  await page.getByRole("button", { name: "INS OFF", exact: true }).click();
  await page.getByRole("dialog", { name: "Confirm command" }).getByRole("button", { name: "Confirm" }).click();
  // the INS OFF card itself (not the previous test's command) completed, and the sensor is off
  await expect(latestCommand(page).getByText("INS OFF", { exact: true })).toBeVisible();
  await expect(latestCommand(page)).toHaveAttribute("data-status", "COMPLETED");
  await expect(page.getByTestId("ins-state")).toHaveAttribute("data-state", "OFF");
  // off, in the same words everywhere: not "Starting up" beside it (an INS off reports INIT: UMAA has no off status),
  // and no alignment step is under way
  await expect(page.getByTestId("ins-state")).toHaveText("INS off");
  await expect(page.getByTestId("ins-status")).toHaveCount(0);
  await expect(page.getByRole("list", { name: "Alignment" }).locator('[aria-current="step"]')).toHaveCount(0);
  await expect(vehicle(page, id)).toContainText("INS off");
  await expect(vehicle(page, id)).not.toContainText("Starting up");
  await expect(page.getByTestId("fleet-vehicle").and(page.locator(`[data-vehicle="${id}"]`))).toContainText("INS off");
  await page.getByRole("button", { name: "INS ON", exact: true }).click(); // six seconds of alignment to cancel in
  const cmd = latestCommand(page);
  await expect(cmd.getByText("INS ON", { exact: true })).toBeVisible();
  await expect(cmd).toHaveAttribute("data-status", "EXECUTING");
  // by keyboard: the Cancel pressed goes once the console has the cancel, and the focus stays on the command, its row
  await cmd.getByRole("button", { name: "Cancel" }).focus();
  await page.keyboard.press("Enter");
  await expect(cmd).toHaveAttribute("data-status", "CANCELED");
  await expect(cmd.getByRole("button", { name: "Cancel" })).toHaveCount(0);
  await expect(cmd.getByTestId("command-summary")).toBeFocused();
  expect(await statuses(cmd)).toEqual(["ISSUED", "COMMANDED", "EXECUTING", "CANCELED"]);
  await expect(cmd.getByTestId("transition").last()).toHaveAttribute("data-status", "CANCELED");
});

test("injected faults: FAILED with its reason, and a state-machine violation flagged", async ({ page }) => {
  const stack = load();
  await open(page, 1);
  await page.getByRole("button", { name: "Request GPS fix", exact: true }).click();
  const rejected = latestCommand(page);
  await expect(rejected).toHaveAttribute("data-status", "FAILED");
  await expect(rejected.getByTestId("transition").last()).toHaveAttribute("data-reason", "RESOURCE_REJECTED");
  // the server's alarm, in the operator's words (the UMAA reason is the command card's data-reason)
  await expect(page.locator('[data-testid="alarm"][data-kind="command-failed"]').first()).toBeVisible();

  await vehicle(page, stack.vehicles[2]).click();
  await page.getByRole("button", { name: "Request GPS fix", exact: true }).click();
  const broken = latestCommand(page);
  await expect(broken.getByTestId("violation")).toHaveAttribute("title", /ISSUED -> EXECUTING is not a Figure 4 transition/);
  await expect(broken.getByTestId("command-violation")).toBeVisible();
  await expect(page.locator('[data-testid="alarm"][data-kind="flow-violation"]').first()).toBeVisible();
});

test("the simulator is stopped: the vehicle shows lost; restarted: regained", async ({ page }) => {
  const id = await open(page);
  const link = vehicle(page, id).getByTestId("vehicle-link");
  await expect(link).toHaveText("Live");
  const lostAlarm = page.locator('[data-testid="alarm"][data-kind="link-lost"]').filter({ hasText: id.slice(0, 8) });
  // a collapsed panel draws no reports, but its title bar still says how fresh they are
  await page.getByTestId("fix-panel-collapse").click();
  await expect(page.getByTestId("fix-panel").locator(".field")).toHaveCount(0);
  await expect(page.getByTestId("fix-panel-freshness")).toContainText("Live");
  await stopSim();
  try {
    await expect(link).toHaveText("Lost");
    await expect(lostAlarm).toHaveAttribute("data-state", "active-unacknowledged");
    await expect(page.getByTestId("satellites-panel-freshness")).toContainText("Lost");
    await expect(page.getByTestId("fix-panel-freshness")).toContainText("Lost");
  } finally {
    await restartSim(); // the next tests need the vehicles, whatever happened here
  }
  // regained: the alarm's condition cleared, and it waits for the operator's acknowledgement
  await expect(lostAlarm).toHaveAttribute("data-state", "cleared-unacknowledged", { timeout: 30_000 });
  await expect(link).toHaveText(/Regained|Live/);
  await expect(page.getByTestId("satellites-panel-freshness")).toContainText("Live");
});

test("the backend restarts: the page reconnects by itself and shows live data again", async ({ page }) => {
  await open(page);
  const before = await page.getByTestId("connection-state").textContent();
  expect(before).toBe("Live");
  await restartConsole();
  await expect(page.getByTestId("connection-state")).toHaveText("Live", {
    timeout: 30_000,
  });
  await expect(page.getByTestId("sky-satellite").first()).toBeVisible();
  await expect(page.getByTestId("satellites-panel-freshness")).toContainText("Live");
});

test("with an operator token: commands are refused until sign-in", async ({ page, request }) => {
  const token = "e2e-secret";
  const guarded = await startGuardedConsole(token);
  try {
    const id = load().vehicles[0];
    await page.goto(guarded.url);
    await expect(page.getByTestId("connection-state")).toHaveText("Live");
    await vehicle(page, id).click();
    await expect(page.getByTestId("read-only")).toBeVisible();
    await expect(page.getByTestId("commands-read-only")).toBeVisible();
    await expect(page.getByRole("button", { name: "Request GPS fix", exact: true })).toBeDisabled();
    expect((await request.post(`${guarded.url}/api/providers/${id}/gps-fix`)).status()).toBe(401);

    await page.getByLabel("Operator token").fill(token);
    await page.getByRole("button", { name: "Sign in" }).click();
    await expect(page.getByTestId("signed-in")).toBeVisible();
    await page.getByRole("button", { name: "Request GPS fix", exact: true }).click();
    const cmd = latestCommand(page);
    await expect(cmd).toHaveAttribute("data-status", /ISSUED|COMMANDED|EXECUTING|COMPLETED/);
    await expect(cmd).toContainText("by e2e-operator");
  } finally {
    await guarded.stop();
  }
});

test("a finished cancel names who asked it and on which station; the timeline is in time order; GPS fix on one line", async ({
  page,
}) => {
  const token = "e2e-canceller";
  const guarded = await startGuardedConsole(token, ["--console-name", "watch"]);
  try {
    await page.setViewportSize({ width: 360, height: 900 }); // a narrow screen: the running card's title stays one line
    await page.goto(guarded.url);
    await expect(page.getByTestId("connection-state")).toHaveText("Live");
    await vehicle(page, load().vehicles[0]).click();
    await page.getByLabel("Operator token").fill(token);
    await page.getByRole("button", { name: "Sign in" }).click();
    await expect(page.getByTestId("signed-in")).toBeVisible();
    await page.getByRole("button", { name: "Request GPS fix", exact: true }).click();
    const cmd = latestCommand(page);
    await expect(cmd).toHaveAttribute("data-status", "EXECUTING", {
      timeout: 20_000,
    });
    const title = cmd.locator(".c-title");
    await expect(title).toHaveText("GPS fix");
    const lines = await title.evaluate((el) => el.getBoundingClientRect().height / parseFloat(getComputedStyle(el).fontSize));
    expect(lines).toBeLessThan(2); // one line of text is about 1.2 font sizes high, two about 2.4
    // the acknowledgement (published with ISSUED) comes after "Received", not before it
    const order = await cmd
      .getByTestId("timeline")
      .locator("li")
      .evaluateAll((els) => els.map((e) => (e as HTMLElement).dataset.status ?? (e as HTMLElement).dataset.testid ?? ""));
    expect(order.indexOf("ack")).toBeGreaterThan(order.indexOf("ISSUED"));
    await expect(cmd.getByTestId("ack")).toContainText("the vehicle reports taking it up");
    await cmd.getByRole("button", { name: "Cancel" }).click();
    await expect(cmd).toHaveAttribute("data-status", "CANCELED");
    // finished, the card still says who asked for the cancel and where (the table's reason word alone, "on request",
    // does not say whose request), in the words table's status and reason words
    await expect(cmd.getByTestId("command-canceller")).toHaveText("cancel asked by e2e-operator on watch");
    await expect(cmd.getByTestId("transition").last()).toContainText("Cancelled on request by e2e-operator on watch");
    await expect(cmd.getByTestId("cancel-asked")).toContainText("Cancel asked by e2e-operator on watch");
    const done = await cmd
      .getByTestId("timeline")
      .locator("li")
      .evaluateAll((els) => els.map((e) => (e as HTMLElement).dataset.status ?? (e as HTMLElement).dataset.testid ?? ""));
    expect(done.indexOf("cancel-asked")).toBeLessThan(done.indexOf("CANCELED")); // asked, then the vehicle's answer
  } finally {
    await guarded.stop();
  }
});

test("gateways: state shown, JAUS id, Record ASPN log downloads a .lcm file, link thresholds saved", async ({
  page,
  request,
}) => {
  const id = await open(page);
  const panel = page.getByTestId("gateways-panel");
  for (const name of ["aspn", "jaus"]) {
    await expect(panel.getByTestId(`gateway-${name}`).getByTestId("gateway-state")).toHaveText("on");
  }
  await expect(panel.getByTestId("gateway-aspn").getByTestId("gateway-rate")).toContainText(/[1-9][0-9.]*\/s/, {
    timeout: 10_000,
  });
  await expect(panel.getByTestId("gateway-aspn").getByTestId("gateway-error")).toHaveText("none");
  await expect(panel.getByTestId("jaus-id")).toHaveText(/^7\.1\.[1-3]$/);

  await panel.getByTestId("aspn-record").click();
  await page.waitForTimeout(1500);
  const [download] = await Promise.all([page.waitForEvent("download"), panel.getByTestId("aspn-stop").click()]);
  expect(download.suggestedFilename()).toMatch(new RegExp(`^aspn-${id.slice(0, 8)}-.*\\.lcm$`));
  const bytes = readFileSync(await download.path());
  expect(bytes.length).toBeGreaterThan(100);
  expect(bytes.readUInt32BE(0)).toBe(0xeda1da01); // an LCM log event's sync word

  const form = panel.getByRole("form", { name: /Link configuration of/ });
  await form.getByLabel("Comms-lost timeout (s)").fill("9");
  await form.getByLabel("On comms lost").selectOption("CONTINUE_MISSION");
  await form.getByRole("button", { name: "Save" }).click();
  await expect(panel.getByRole("form", { name: /Link configuration of/ }).getByLabel("Comms-lost timeout (s)")).toHaveValue("9");
  await expect
    .poll(async () => (await (await request.get(`${load().url}/api/providers/${id}`)).json()).linkConfig)
    .toEqual({
      commsLostTimeout: 9,
      regainedTime: 1.5,
      policy: "CONTINUE_MISSION",
      regainedBehavior: 0,
    });
  const restored = await request.put(`${load().url}/api/providers/${id}/link-config`, {
    data: {
      commsLostTimeout: 1.5,
      regainedTime: 1.5,
      policy: "STOP_MISSION",
      regainedBehavior: 0,
    },
  });
  expect(restored.status()).toBe(200);
});

test("Record, then Stop: the header shows REC and the recording is listed complete", async ({ page, request }) => {
  await open(page);
  const control = page.getByTestId("recording");
  await expect(control).toHaveAttribute("data-state", "off");
  await control.getByRole("button", { name: "● Record" }).click();
  await expect(control).toHaveAttribute("data-state", "recording");
  await expect(page.getByTestId("recording-status")).toContainText("REC 00:0");
  const listed = await (await request.get(`${load().url}/api/recordings`)).json();
  expect(listed[0].state).toBe("recording");
  await control.getByRole("button", { name: "Stop" }).click();
  await expect(control).toHaveAttribute("data-state", "off");
  const after = await (await request.get(`${load().url}/api/recordings`)).json();
  expect(after[0]).toMatchObject({ name: listed[0].name, state: "complete" });
  expect(after[0].size).toBeGreaterThan(0);
});
