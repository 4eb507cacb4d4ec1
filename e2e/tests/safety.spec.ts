// Operator safety and security in the browser: every command goes to the vehicle the operator means,
// the selection never moves by itself, reads can need a token, and another site cannot command.
import { createServer } from "node:http";
import type { AddressInfo } from "node:net";
import { expect, test, type Page, type WebSocketRoute } from "@playwright/test";
import { history, open, vehicle } from "../helpers";
import { VEHICLE_3_NAME, load, restartConsole, startGuardedConsole } from "../stack";

async function markColour(page: Page, scope: string): Promise<string> {
  return page
    .locator(scope)
    .locator(".vehicle-mark")
    .first()
    .evaluate((e) => getComputedStyle(e).backgroundColor);
}

test("wrong vehicle: INS OFF on A, select B, Confirm is gone and nothing is sent; the prompt names A", async ({
  page,
  request,
}) => {
  const stack = load();
  const [a, , b] = stack.vehicles;
  await open(page, 0);
  const before = new Set((await history(request)).map((c) => c.sessionId));

  await expect(page.getByTestId("command-target")).toContainText(`Vehicle ${a.slice(0, 8)}`);
  await expect(page.getByRole("button", { name: "INS OFF", exact: true })).toHaveAttribute(
    "title",
    `INS OFF on Vehicle ${a.slice(0, 8)} (UMAA state: OFF)`,
  );
  await page.getByRole("button", { name: "INS OFF", exact: true }).click();
  const dialog = page.getByRole("dialog", { name: "Confirm command" });
  await expect(dialog).toContainText(`INS OFF on Vehicle ${a.slice(0, 8)}`);
  await expect(dialog.getByTestId("vehicle-tag")).toHaveAttribute("data-vehicle", a);
  expect(await markColour(page, '[role="dialog"]')).toBe(
    await markColour(page, `[data-testid="vehicle"]:has-text("${a.slice(0, 8)}")`),
  );

  await vehicle(page, b).click(); // look at B while the confirmation for A is open
  await expect(vehicle(page, b)).toHaveAttribute("aria-pressed", "true");
  await expect(dialog).toHaveCount(0);
  await expect(page.getByRole("button", { name: "Confirm" })).toHaveCount(0);
  await expect(page.getByTestId("command-note")).toContainText(`INS OFF for Vehicle ${a.slice(0, 8)} not sent`);
  await expect(page.getByTestId("command-target")).toContainText(`${VEHICLE_3_NAME} ${b.slice(0, 8)}`);
  expect(await markColour(page, '[data-testid="command-target"]')).toBe(
    await markColour(page, `[data-testid="vehicle"]:has-text("${b.slice(0, 8)}")`),
  );
  await page.waitForTimeout(1000);
  expect((await history(request)).filter((c) => !before.has(c.sessionId))).toEqual([]);

  // A confirmation goes to the vehicle it was prepared for, and only there.
  await vehicle(page, a).click();
  await page.getByRole("button", { name: "INS RESTART", exact: true }).click();
  await page.getByRole("dialog", { name: "Confirm command" }).getByRole("button", { name: "Confirm" }).click();
  await expect
    .poll(async () => (await history(request)).filter((c) => !before.has(c.sessionId)).map((c) => [c.providerId, c.state]))
    .toEqual([[a, "RESTARTING"]]);
  await expect(page.getByTestId("ins-state")).toHaveAttribute("data-state", "ON", { timeout: 30_000 }); // leave A as it was
});

test("a double click on a command button sends the command once", async ({ page, request }) => {
  const a = await open(page, 0);
  const before = new Set((await history(request)).map((c) => c.sessionId));
  const statuses = async () => {
    const all = (await (await request.get(`${load().url}/api/commands?limit=1000`)).json()) as {
      sessionId: string;
      providerId: string;
      status: string | null;
    }[];
    return all.filter((c) => !before.has(c.sessionId) && c.providerId === a).map((c) => c.status);
  };
  await page.getByRole("button", { name: "INS ON", exact: true }).dblclick();
  // twice sent, the first would be superseded by the second and end FAILED beside it
  await expect.poll(statuses, { timeout: 30_000 }).toEqual(["COMPLETED"]);
});

test("the selection survives a reconnect and a backend restart, lives in ?vehicle= and opens from a link", async ({ page }) => {
  const stack = load();
  const b = stack.vehicles[2];
  const sockets: WebSocketRoute[] = [];
  await page.routeWebSocket(/\/ws(\?|$)/, (ws) => {
    ws.connectToServer();
    sockets.push(ws);
  });
  await page.goto(`${stack.url}/?vehicle=${b}`); // a link opens that vehicle
  await expect(page.getByTestId("connection-state")).toHaveText("Live");
  await expect(vehicle(page, b)).toHaveAttribute("aria-pressed", "true");
  await expect(page.getByTestId("command-target")).toContainText(b.slice(0, 8));

  await vehicle(page, stack.vehicles[1]).click();
  expect(new URL(page.url()).searchParams.get("vehicle")).toBe(stack.vehicles[1]);
  await vehicle(page, b).click();
  expect(new URL(page.url()).searchParams.get("vehicle")).toBe(b);

  await sockets[0].close({ code: 1012, reason: "test: connection dropped" }); // a reconnect
  await expect.poll(() => sockets.length).toBe(2);
  await expect(page.getByTestId("connection-state")).toHaveText("Live");
  await expect(vehicle(page, b)).toHaveAttribute("aria-pressed", "true");

  await restartConsole(); // its first snapshot may know none or only some of the vehicles
  await expect(page.getByTestId("connection-state")).toHaveText("Live", {
    timeout: 30_000,
  });
  await expect(page.getByTestId("vehicle")).toHaveCount(3);
  await expect(vehicle(page, b)).toHaveAttribute("aria-pressed", "true");
  await expect(page.getByTestId("vehicle").and(page.locator('[aria-pressed="true"]'))).toHaveCount(1);
  expect(new URL(page.url()).searchParams.get("vehicle")).toBe(b);

  await page.reload();
  await expect(vehicle(page, b)).toHaveAttribute("aria-pressed", "true");
});

test("with --auth-reads: nothing is shown until sign-in, a wrong token is refused, the token then opens /ws", async ({
  page,
}) => {
  const token = "e2e-reader";
  const guarded = await startGuardedConsole(token, ["--auth-reads"]);
  try {
    await page.goto(guarded.url);
    await expect(page.getByTestId("sign-in-to-read")).toBeVisible();
    await expect(page.getByTestId("connection-state")).toHaveText("Not signed in");
    await expect(page.getByTestId("vehicle")).toHaveCount(0);
    await page.getByLabel("Operator token").fill("wrong");
    await page.getByRole("button", { name: "Sign in" }).click();
    await expect(page.getByTestId("sign-in-error")).toContainText("not valid");
    await page.getByLabel("Operator token").fill(token);
    await page.getByRole("button", { name: "Sign in" }).click();
    await expect(page.getByTestId("signed-in")).toBeVisible();
    await expect(page.getByTestId("connection-state")).toHaveText("Live");
    await expect(page.getByTestId("vehicle")).toHaveCount(3);
    const chosen = await page.getByTestId("vehicle").nth(1).getByTestId("vehicle-tag").getAttribute("data-vehicle");

    // Sign out: nothing of the vehicles stays on screen, and the header does not claim "Live".
    await page.getByTestId("vehicle").nth(1).click();
    await page.getByRole("button", { name: "Sign out" }).click();
    await expect(page.getByTestId("connection-state")).toHaveText("Not signed in");
    await expect(page.getByTestId("sign-in-to-read")).toBeVisible();
    await expect(page.getByTestId("vehicle")).toHaveCount(0);
    await expect(page.getByTestId("ins-state")).toHaveCount(0);
    await expect(page.getByTestId("selected-missing")).toContainText("shown after sign-in");
    await page.waitForTimeout(1500); // no report brings them back
    await expect(page.getByTestId("vehicle")).toHaveCount(0);
    expect(new URL(page.url()).searchParams.get("vehicle")).toBe(chosen); // the selection stays
    await page.getByLabel("Operator token").fill(token);
    await page.getByRole("button", { name: "Sign in" }).click();
    await expect(page.getByTestId("connection-state")).toHaveText("Live");
    await expect(
      page.getByTestId("vehicle").and(page.locator('[aria-pressed="true"]')).getByTestId("vehicle-tag"),
    ).toHaveAttribute("data-vehicle", chosen!);
  } finally {
    await guarded.stop();
  }
});

test("a page of another site cannot command a vehicle nor read /ws", async ({ page, request }) => {
  // Another web application on this machine (a loopback origin: Chromium's local-network rules let its
  // requests through, as they would from any local tool's page or an older browser).
  const evil = createServer((_req, res) =>
    res.writeHead(200, { "content-type": "text/html" }).end("<html><body>another site</body></html>"),
  );
  await new Promise<void>((resolve) => evil.listen(0, "127.0.0.1", resolve));
  const origin = `http://127.0.0.1:${(evil.address() as AddressInfo).port}`;
  try {
    const stack = load();
    const id = stack.vehicles[0];
    const before = (await history(request)).length;
    await page.goto(origin);
    const outcome = await page.evaluate(
      async ({ url, id }) => {
        // the "simple" cross-site request: no CORS preflight, the answer is opaque to the page
        await fetch(`${url}/api/providers/${id}/gps-fix`, {
          method: "POST",
          mode: "no-cors",
          body: "{}",
        }).catch(() => null);
        return new Promise<string>((resolve) => {
          const ws = new WebSocket(`${url.replace("http", "ws")}/ws`);
          ws.onmessage = () => resolve("read");
          ws.onerror = () => resolve("refused");
        });
      },
      { url: stack.url, id },
    );
    expect(outcome).toBe("refused");
    expect((await history(request)).length).toBe(before);
    const audit = (await (await request.get(`${stack.url}/api/audit?limit=5`)).json()) as {
      outcome: string;
      origin: string;
      status: number;
    }[];
    expect(audit.find((a) => a.origin === origin)).toMatchObject({
      outcome: "refused",
      status: 403,
    });
  } finally {
    evil.close();
  }
});
