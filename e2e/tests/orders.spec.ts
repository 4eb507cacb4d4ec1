// Every order bound to its vehicle: a CoMap Move-to armed for one vehicle is void once another is
// selected, and nothing reaches the other; a command to a lost vehicle needs an explicit confirmation that says
// it is lost; confirmations take the focus and close on Esc; CoMap controls say why when CoMap is off.
import { expect, test, type APIRequestContext, type Locator, type Page } from "@playwright/test";
import { history, latestCommand, open, vehicle } from "../helpers";
import { VEHICLE_3_NAME, load, restartSim, startGuardedConsole, stopSim } from "../stack";

type TaskRecord = { taskId: number; vehicle: string; kind: string };

async function tasks(request: APIRequestContext): Promise<TaskRecord[]> {
  return (await (await request.get(`${load().url}/api/tasks`)).json()) as TaskRecord[];
}

/** Arm Move-to for the selected vehicle and click its destination: the map's centre (the map follows the
 * selected vehicle, so the destination is where it is: the vehicle does not go far). */
async function armMove(page: Page, label: string): Promise<void> {
  const move = page.getByTestId("move-to");
  await move.click();
  await expect(move).toHaveAttribute("aria-pressed", "true");
  await expect(move).toHaveText(`Move ${label}: click its destination`);
  await page.getByTestId("map").click();
  await expect(move).toHaveText(`Send move of ${label}…`);
}

test("Move-to armed for Charlie, then another vehicle selected: nothing is armed and nothing reaches it", async ({
  page,
  request,
}) => {
  const stack = load();
  const a = stack.vehicles[2]; // Charlie
  const b = stack.vehicles[0];
  const labelA = `${VEHICLE_3_NAME} (${a.slice(0, 8)})`;
  await open(page, 2);
  await expect(page.getByTestId("map")).toHaveAttribute("data-ready", "true");
  await expect(page.getByTestId("capabilities")).toContainText(`IMC ${stack.imcVehicles[2]}`, { timeout: 30_000 });
  const move = page.getByTestId("move-to");
  const before = await tasks(request);

  // armed for Charlie, a destination clicked; then B selected
  await armMove(page, labelA);
  await expect(move).toHaveAttribute("data-vehicle", a);
  await vehicle(page, b).click();
  await expect(vehicle(page, b)).toHaveAttribute("aria-pressed", "true");
  await expect(move).toHaveText("Move to…"); // the armed control is gone
  await expect(move).toHaveAttribute("aria-pressed", "false");
  await expect(move).not.toHaveAttribute("data-vehicle");
  await expect(page.getByTestId("comap-note")).toHaveText(`Move-to for ${labelA} not sent: the selected vehicle changed.`);
  await page.getByTestId("map").click(); // a click on the map now picks nothing for B
  await expect(move).toHaveText("Move to…");

  // the same with the confirmation open: it names Charlie, has the focus, and goes when B is selected
  await vehicle(page, a).click();
  await armMove(page, labelA);
  await move.click();
  const confirm = page.getByRole("dialog", { name: "Confirm move-to" });
  await expect(confirm).toBeFocused();
  await expect(confirm).toHaveAttribute("data-vehicle", a);
  await expect(confirm).toContainText(
    new RegExp(`Move ${VEHICLE_3_NAME} \\(${a.slice(0, 8)}\\) to \\d+\\.\\d{4} [NS], \\d+\\.\\d{4} [EW]\\?`),
  );
  await vehicle(page, b).click();
  await expect(confirm).toHaveCount(0);
  await expect(page.getByRole("button", { name: "Send move" })).toHaveCount(0);
  await expect(page.getByTestId("comap-note")).toHaveText(`Move-to for ${labelA} not sent: the selected vehicle changed.`);

  await page.waitForTimeout(1000); // what a wrongly sent task would take to reach the console
  const after = await tasks(request);
  expect(after.filter((t) => t.vehicle === b).length).toBe(before.filter((t) => t.vehicle === b).length);
  expect(after.length).toBe(before.length);

  // confirmed for Charlie: the task goes to Charlie, and its row names it
  await vehicle(page, a).click();
  await armMove(page, labelA);
  await move.click();
  await page.getByRole("dialog", { name: "Confirm move-to" }).getByRole("button", { name: "Send move" }).click();
  await expect
    .poll(async () =>
      (await tasks(request)).filter((t) => !before.some((x) => x.taskId === t.taskId)).map((t) => [t.vehicle, t.kind]),
    )
    .toEqual([[a, "move"]]);
  const row = page.getByTestId("task").first();
  await expect(row).toHaveAttribute("data-vehicle", a);
  await expect(row.getByTestId("task-vehicle")).toContainText(VEHICLE_3_NAME);
  await expect(move).toHaveText("Move to…");

  // an order that does not get through says which order and which vehicle, the confirmation that named them gone
  await page.route("**/api/tasks", (route) =>
    route.request().method() === "POST" ? route.abort("connectionrefused") : route.continue(),
  );
  await armMove(page, labelA);
  await move.click();
  await page.getByRole("dialog", { name: "Confirm move-to" }).getByRole("button", { name: "Send move" }).click();
  await expect(page.getByTestId("comap-error")).toHaveText(`Move-to for ${labelA} not sent: console unreachable`);
  await page.unroute("**/api/tasks");
});

test("a command to a lost vehicle says it is lost and is sent only on an explicit confirmation; unanswered, it can be cancelled, and ends when the vehicle is back without it", async ({
  page,
  request,
}) => {
  test.setTimeout(120_000);
  const stack = load();
  const id = await open(page, 0);
  const label = `Vehicle ${id.slice(0, 8)}`;
  const fix = page.getByRole("button", {
    name: "Request GPS fix",
    exact: true,
  });
  await expect(fix).toBeEnabled();
  await stopSim();
  let cmd: Locator | undefined;
  let restarted = false;
  let session = "";
  try {
    await expect(page.getByTestId("command-lost")).toContainText(`${label} is lost: last heard`);
    const lostFix = page.getByRole("button", {
      name: "Request GPS fix (vehicle lost)",
      exact: true,
    });
    await expect(lostFix).toBeVisible();
    await expect(page.getByRole("button", { name: "INS OFF (vehicle lost)", exact: true })).toBeVisible();
    // the console refuses it without the confirmation
    const refused = await request.post(`${stack.url}/api/providers/${id}/gps-fix`, { data: {} });
    expect(refused.status()).toBe(409);
    const before = new Set((await history(request)).map((c) => c.sessionId));

    // asked, focused, closed with Esc: nothing sent, the focus back on the button
    await lostFix.click();
    const dialog = page.getByRole("dialog", { name: "Confirm command" });
    await expect(dialog).toBeFocused();
    await expect(dialog).toHaveAttribute("data-vehicle", id);
    await expect(dialog.getByTestId("confirm-lost")).toContainText(`${label} is lost: last heard`);
    await expect(dialog.getByTestId("confirm-lost")).toContainText("Send a GPS fix request anyway?");
    await page.keyboard.press("Escape");
    await expect(dialog).toHaveCount(0);
    await expect(lostFix).toBeFocused();
    // asked again, kept as is
    await lostFix.click();
    await dialog.getByRole("button", { name: "Keep as is" }).click();
    await expect(dialog).toHaveCount(0);
    await page.waitForTimeout(1000);
    expect((await history(request)).filter((c) => !before.has(c.sessionId))).toEqual([]);

    // a CoMap order to it says so as well, and its confirmation names the lost state (Esc: nothing sent)
    const tasksBefore = (await tasks(request)).length;
    const move = page.getByTestId("move-to");
    await expect(move).toHaveText("Move to… (vehicle lost)");
    await move.click();
    await page.getByTestId("map").click();
    await expect(move).toHaveText(`Send move of ${label}…`);
    await move.click();
    const moveDialog = page.getByRole("dialog", { name: "Confirm move-to" });
    await expect(moveDialog).toBeFocused();
    await expect(moveDialog.getByTestId("comap-confirm-lost")).toContainText(`${label} is lost`);
    await expect(moveDialog.getByRole("button", { name: "Send anyway" })).toBeVisible();
    await page.keyboard.press("Escape");
    await expect(moveDialog).toHaveCount(0);
    await page.waitForTimeout(1000);
    expect((await tasks(request)).length).toBe(tasksBefore);

    // confirmed: sent, with confirmLost
    await lostFix.click();
    await dialog.getByRole("button", { name: "Send anyway" }).click();
    await expect
      .poll(async () => (await history(request)).filter((c) => !before.has(c.sessionId)).map((c) => c.providerId))
      .toEqual([id]);
    await expect(page.getByTestId("command-error")).toHaveCount(0);

    // nobody answers it: it says so in words, and Cancel takes it back (DELETE /api/commands/{id})
    cmd = latestCommand(page);
    await expect(cmd.getByTestId("command-status")).toHaveText("No answer", {
      timeout: 20_000,
    });
    await expect(cmd.getByTestId("unanswered")).toContainText(`${label} has not confirmed receiving this command`);
    await expect(cmd.getByTestId("command-elapsed")).toContainText("expected");
    session = (await cmd.getAttribute("data-session"))!;
    await cmd.getByRole("button", { name: "Cancel" }).click();
    await expect
      .poll(
        async () =>
          ((await (await request.get(`${stack.url}/api/commands/${session}`)).json()) as { cancelRequested: boolean })
            .cancelRequested,
      )
      .toBe(true);
    await expect(cmd.getByTestId("cancel-asked")).toBeVisible();
    // no "Cancel it" left where there is no Cancel button any more
    await expect(cmd.getByTestId("unanswered")).toContainText("Cancel requested: it may not hear the cancel either");
    await expect(cmd.getByTestId("unanswered")).not.toContainText("Cancel it if");

    // heard again while a CoMap order's lost confirmation is open: it says the vehicle was lost, not that it is
    if ((await move.textContent())?.startsWith("Move to")) {
      await move.click();
      await page.getByTestId("map").click();
    }
    await expect(move).toHaveText(`Send move of ${label}…`);
    await move.click();
    await expect(moveDialog.getByTestId("comap-confirm-lost")).toContainText(`${label} is lost: last heard`);
    await restartSim();
    restarted = true;
    await expect(page.getByTestId("command-lost")).toHaveCount(0, {
      timeout: 30_000,
    });
    await expect(moveDialog.getByTestId("comap-confirm-lost")).toHaveText(
      `${label} was lost. Send anyway? It may reach the vehicle late, or not at all.`,
    );
    await page.keyboard.press("Escape");
    await expect(moveDialog).toHaveCount(0);
  } finally {
    if (!restarted) await restartSim(); // the next tests need the vehicles, whatever happened here
  }
  // back without ever hearing it (the cancel withdrew it): the command ends, it no longer counts up
  expect(cmd).toBeDefined();
  await expect(cmd!.getByTestId("command-status")).toHaveText("Cancelled before the vehicle heard it", { timeout: 30_000 });
  await expect(cmd!.getByTestId("command-elapsed")).toHaveCount(0);
  // finished, it no longer says "No answer … it may still run it": its record keeps unanswered, the card does not
  expect(((await (await request.get(`${stack.url}/api/commands/${session}`)).json()) as { unanswered: boolean }).unanswered).toBe(
    true,
  );
  await expect(cmd!.getByTestId("unanswered")).toHaveCount(0);
  await expect(cmd!).toHaveClass(/\bmuted\b/);
  await expect(page.getByTestId("command-lost")).toHaveCount(0, {
    timeout: 30_000,
  });
  await expect(fix).toBeEnabled();
  for (const v of stack.vehicles) {
    await expect
      .poll(async () => ((await (await request.get(`${stack.url}/api/providers/${v}`)).json()) as { link: string }).link, {
        timeout: 30_000,
      })
      .toBe("live");
  }
});

test("a confirmation takes the focus and Esc closes it without sending", async ({ page, request }) => {
  await open(page, 0);
  const before = (await history(request)).length;
  const off = page.getByRole("button", { name: "INS OFF", exact: true });
  await off.click();
  const dialog = page.getByRole("dialog", { name: "Confirm command" });
  await expect(dialog).toBeFocused();
  await page.keyboard.press("Escape");
  await expect(dialog).toHaveCount(0);
  await expect(off).toBeFocused();
  await page.waitForTimeout(1000);
  expect((await history(request)).length).toBe(before);
});

test("with CoMap off the console says so in place of the CoMap controls", async ({ page }) => {
  const guarded = await startGuardedConsole("e2e-orders"); // no --imc-port: CoMap off
  try {
    await page.goto(guarded.url);
    await expect(page.getByTestId("connection-state")).toHaveText("Live");
    await page.getByTestId("vehicle").first().click();
    await expect(page.getByTestId("comap-off")).toContainText("CoMap is off: this console was started without --imc-port");
    await expect(page.getByTestId("move-to")).toHaveCount(0);
    await expect(page.getByRole("button", { name: "Survey", exact: true })).toHaveCount(0);
  } finally {
    await guarded.stop();
  }
});
