// Renaming a vehicle from the dashboard (PUT /api/providers/{id}/name) on a console with an operator token: the
// control needs the token, Esc cancels, a refused name is said in words, a saved one names the vehicle in the list.
import { expect, test } from "@playwright/test";
import { vehicle } from "../helpers";
import { load, startGuardedConsole } from "../stack";

test("rename the selected vehicle: needs the token, Esc cancels, a refusal in words, the new name shown", async ({
  page,
  request,
}) => {
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

    // an alarm raised before a rename names the vehicle by its name now, in its text as in its tag (the console sends
    // the text naming it so, and sends the set again on a rename)
    const rejecting = load().vehicles[1]; // --fault reject:2: its command fails, an alarm
    const short = rejecting.slice(0, 8);
    const failed = (who: string) => page.getByTestId("alarm").filter({ hasText: `${who}: GPS fix command failed` });
    expect((await request.post(`${guarded.url}/api/providers/${rejecting}/gps-fix`, { data: {}, headers: auth })).status()).toBe(
      201,
    );
    await expect(failed(short).first()).toBeVisible();
    expect(
      (
        await request.put(`${guarded.url}/api/providers/${rejecting}/name`, {
          data: { name: "Tug Two" },
          headers: auth,
        })
      ).status(),
    ).toBe(200);
    await expect(failed("Tug Two").first().getByTestId("vehicle-tag")).toContainText("Tug Two");
    await expect(failed(short)).toHaveCount(0); // no "3b5c56d2: … failed" left beside the tag Tug Two
    // and one raised while it was named, once its name is taken away: by its id, not by the name it no longer has
    expect((await request.post(`${guarded.url}/api/providers/${rejecting}/gps-fix`, { data: {}, headers: auth })).status()).toBe(
      201,
    );
    await expect.poll(() => failed("Tug Two").count()).toBeGreaterThanOrEqual(2);
    expect(
      (
        await request.put(`${guarded.url}/api/providers/${rejecting}/name`, {
          data: { name: null },
          headers: auth,
        })
      ).status(),
    ).toBe(200);
    await expect(page.getByTestId("alarm").filter({ hasText: "Tug Two" })).toHaveCount(0);
    await expect(failed(short).first().getByTestId("vehicle-tag")).toHaveText(`Vehicle ${short}`);
  } finally {
    await request.put(`${guarded.url}/api/providers/${load().vehicles[1]}/name`, { data: { name: null }, headers: auth });
    await request.put(`${guarded.url}/api/providers/${id}/name`, {
      data: { name: null },
      headers: auth,
    }); // the file is shared
    await guarded.stop();
  }
});
