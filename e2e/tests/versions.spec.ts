// A mixed fleet on screen: a UMAA 3.0.1 and a UMAA 6.0 vehicle in one console, each with its version.
import { expect, test } from "@playwright/test";
import { vehicle } from "../helpers";
import { OWN_STACK, startMixedFleet } from "../stack";

test("a mixed fleet: each vehicle shows the UMAA version it speaks", { tag: OWN_STACK }, async ({ page }) => {
  const fleet = await startMixedFleet();
  try {
    await page.goto(fleet.url);
    await expect(page.getByTestId("connection-state")).toHaveText("Live");
    const [old, six] = fleet.vehicles;
    await expect(vehicle(page, old).getByTestId("vehicle-umaa")).toHaveText("UMAA 3.0.1", { timeout: 30_000 });
    await expect(vehicle(page, six).getByTestId("vehicle-umaa")).toHaveText("UMAA 6.0", { timeout: 30_000 });
    await expect(vehicle(page, six)).toHaveAttribute("data-link", "live");
    // a 6.0 vehicle's GlobalPose is its position on screen, as a 3.0.1 vehicle's fix: where it is, what kind of
    // position (its navigation solution, the literal in the tooltip) and its attitude; no fix status (no GPS fix service)
    await vehicle(page, six).click();
    const fix = page.getByTestId("fix-panel");
    await expect(fix.getByTestId("latitude")).toHaveText(/^36\.8\d+° N$/, {
      timeout: 15_000,
    });
    // on the surface (6.0 has no GPS fix command to surface it): a measured position, as a working 6.0 vehicle's
    await expect(fix.getByTestId("position-kind")).toHaveText("Measured position");
    await expect(fix.getByTestId("position-kind")).toHaveAttribute("title", "UMAA navigationSolution: MEASURED");
    await expect(fix.getByTestId("attitude")).toHaveText(/^0\.0° \/ 0\.0° \/ \d+\.\d°$/);
    await expect(fix.getByTestId("fix-valid")).toHaveAttribute("title", /UMAA 6.0 has no GPS fix service/);
    // its INS: the alignment kind and stage in words, the 6.0 literal in the tooltip, its step on the bar
    const ins = page.getByTestId("ins-panel");
    await expect(ins.getByTestId("ins-status")).toHaveText("Fine alignment done, stationary", { timeout: 30_000 });
    await expect(ins.getByTestId("ins-status")).toHaveAttribute("title", "UMAA status: FINE_STATIONARY_ALIGNMENT_COMPLETE");
    // the steps of its own alignment: 6.0 has no OPERATIONAL, so once aligned none is left pending
    await expect(ins.getByRole("list", { name: "Alignment" }).getByRole("listitem")).toHaveText([
      "Starting up",
      "Coarse alignment",
      "Fine alignment",
      "Alignment done",
    ]);
    await expect(ins.locator("[aria-current=step]")).toHaveText("Alignment done");
    await expect(ins.getByText("Alignment done", { exact: true })).toHaveAttribute(
      "title",
      "UMAA status: FINE_STATIONARY_ALIGNMENT_COMPLETE",
    );
    await expect(ins.getByTestId("ins-state")).toHaveCount(0); // 6.0 reports no power state: none said
    await expect(vehicle(page, six)).toContainText("INS fine alignment done, stationary");
  } finally {
    await fleet.stop();
  }
});
