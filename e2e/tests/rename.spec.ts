// Renaming a vehicle from the dashboard (PUT /api/providers/{id}/name) on a console with an operator token: the
// control needs the token, Esc cancels, a refused name is said in words, a saved one names the vehicle in the list.
import { expect, test } from "@playwright/test";
import { vehicle } from "../helpers";
import { load, startGuardedConsole } from "../stack";

test("rename the selected vehicle: needs the token, Esc cancels, a refusal in words, the new name shown", async ({ page, request }) => {
  const token = "e2e-secret";
  const guarded = await startGuardedConsole(token);
  const id = load().vehicles[0];
  const auth = { Authorization: `Bearer ${token}` };
  try {
    await page.goto(guarded.url);
    await expect(page.getByTestId("connection-state")).toHaveText("Live");
    await vehicle(page, id).click();
    const list = page.getByRole("navigation", { name: "Vehicles" });
    await expect(list.getByRole("button", { name: "Rename" })).toBeDisabled(); // no token yet

    await page.getByLabel("Operator token").fill(token);
    await page.getByRole("button", { name: "Sign in" }).click();
    await list.getByRole("button", { name: "Rename" }).click();
    const form = list.getByRole("form", { name: /^Rename / });
    await form.getByLabel("Name").fill("Not this one");
    await form.getByLabel("Name").press("Escape");
    await expect(form).toHaveCount(0);
    await expect(vehicle(page, id)).not.toContainText("Not this one");

    await list.getByRole("button", { name: "Rename" }).click();
    await form.getByLabel("Name").fill("bad\u0007name"); // a control character: the console refuses it
    await form.getByRole("button", { name: "Save" }).click();
    await expect(form.getByRole("alert")).toContainText("422");
    await expect(form.getByRole("alert")).toContainText("printable characters only");

    await form.getByLabel("Name").fill("  Harbour Pilot ");
    await form.getByRole("button", { name: "Save" }).click();
    await expect(form).toHaveCount(0);
    await expect(vehicle(page, id).getByTestId("vehicle-tag")).toContainText("Harbour Pilot");
    expect((await (await request.get(`${guarded.url}/api/providers/${id}`)).json()).name).toBe("Harbour Pilot");

    // an alarm raised before a rename names the vehicle by its name now, as the rest of the page does
    const rejecting = load().vehicles[1]; // --fault reject:2: its command fails, an alarm
    expect((await request.post(`${guarded.url}/api/providers/${rejecting}/gps-fix`, { data: {}, headers: auth })).status()).toBe(201);
    const alarm = page.getByTestId("alarm").filter({ hasText: `${rejecting.slice(0, 8)}: GPS fix command failed` }).first();
    await expect(alarm).toBeVisible();
    expect((await request.put(`${guarded.url}/api/providers/${rejecting}/name`, { data: { name: "Tug Two" }, headers: auth })).status()).toBe(200);
    await expect(alarm.getByTestId("vehicle-tag")).toContainText("Tug Two");
    // and one raised while it was named, once its name is taken away: by its id, not by the name it no longer has
    expect((await request.post(`${guarded.url}/api/providers/${rejecting}/gps-fix`, { data: {}, headers: auth })).status()).toBe(201);
    const named = page.getByTestId("alarm").filter({ hasText: "Tug Two: GPS fix command failed" }).first();
    await expect(named.getByTestId("vehicle-tag")).toContainText("Tug Two");
    expect((await request.put(`${guarded.url}/api/providers/${rejecting}/name`, { data: { name: null }, headers: auth })).status()).toBe(200);
    await expect(named.getByTestId("vehicle-tag")).toHaveText(`Vehicle ${rejecting.slice(0, 8)}`);
  } finally {
    await request.put(`${guarded.url}/api/providers/${load().vehicles[1]}/name`, { data: { name: null }, headers: auth });
    await request.put(`${guarded.url}/api/providers/${id}/name`, { data: { name: null }, headers: auth }); // the file is shared
    await guarded.stop();
  }
});
