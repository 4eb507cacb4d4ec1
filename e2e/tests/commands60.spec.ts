// Commanding a UMAA 6.0 vehicle on screen: its alignments offered in words (no GPS fix, and why), GPS_ALIGN sent and
// followed on its command card to COMPLETED; the 3.0.1 vehicle beside it keeps its own commands.
import { expect, test, type Locator } from "@playwright/test";
import { latestCommand, vehicle } from "../helpers";
import { startMixedFleet } from "../stack";

async function statuses(cmd: Locator): Promise<string[]> {
  return cmd.getByTestId("transition").evaluateAll((els) => els.map((e) => (e as HTMLElement).dataset.status ?? ""));
}

test("GPS_ALIGN sent to a UMAA 6.0 vehicle walks the flow to COMPLETED on its command card", async ({ page }) => {
  const fleet = await startMixedFleet();
  try {
    await page.goto(fleet.url);
    const [old, six] = fleet.vehicles;
    await expect(vehicle(page, six).getByTestId("vehicle-umaa")).toHaveText("UMAA 6.0", { timeout: 30_000 });
    await vehicle(page, old).click();
    const panel = page.getByTestId("commands-panel");
    await expect(panel.getByRole("button", { name: "Request GPS fix", exact: true })).toBeVisible();
    await expect(panel.getByTestId("command-no-gps-fix")).toHaveCount(0);

    await vehicle(page, six).click();
    await expect(panel.getByRole("button", { name: "Request GPS fix", exact: true })).toHaveCount(0);
    await expect(panel.getByRole("button", { name: "INS ON", exact: true })).toHaveCount(0);
    await expect(panel.getByTestId("command-no-gps-fix")).toHaveText("UMAA 6.0 has no GPS fix service: no GPS fix to request.");
    const align = panel.getByRole("button", { name: "INS GPS-aided alignment", exact: true });
    await expect(align).toHaveAttribute("title", /\(UMAA state: GPS_ALIGN\)$/);
    await align.click();
    const cmd = latestCommand(page);
    await expect(cmd.getByText("INS GPS-aided alignment", { exact: true })).toBeVisible();
    await expect(cmd).toHaveAttribute("data-status", "COMPLETED", { timeout: 40_000 });
    expect(await statuses(cmd)).toEqual(["ISSUED", "COMMANDED", "EXECUTING", "COMPLETED"]);
    await expect(cmd.getByTestId("ack")).toHaveCount(1);
    await expect(cmd.getByTestId("command-status")).toHaveAttribute("title", "UMAA commandStatus: COMPLETED");
  } finally {
    await fleet.stop();
  }
});
