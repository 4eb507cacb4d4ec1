// A mixed fleet on screen: a UMAA 3.0.1 and a UMAA 6.0 vehicle in one console, each with its version.
import { expect, test } from "@playwright/test";
import { vehicle } from "../helpers";
import { startMixedFleet } from "../stack";

test("a mixed fleet: each vehicle shows the UMAA version it speaks", async ({ page }) => {
  const fleet = await startMixedFleet();
  try {
    await page.goto(fleet.url);
    await expect(page.getByTestId("connection-state")).toHaveText("Live");
    const [old, six] = fleet.vehicles;
    await expect(vehicle(page, old).getByTestId("vehicle-umaa")).toHaveText("UMAA 3.0.1", { timeout: 30_000 });
    await expect(vehicle(page, six).getByTestId("vehicle-umaa")).toHaveText("UMAA 6.0", { timeout: 30_000 });
    await expect(vehicle(page, six)).toHaveAttribute("data-link", "live");
    // a 6.0 vehicle has no GPS fix service: its missing fix reports are said as its version's, not awaited
    await vehicle(page, six).click();
    await expect(page.getByTestId("fix-panel").getByTestId("fix-none")).toContainText("UMAA 6.0 has no GPS fix service");
    await expect(page.getByTestId("ins-panel").getByTestId("ins-none")).toContainText("UMAA 6.0 inertial sensor's status");
    await expect(page.getByTestId("fix-panel")).not.toContainText("No GPS fix reports yet");
  } finally {
    await fleet.stop();
  }
});
