// Commanding a UMAA 6.0 vehicle on screen: its alignments offered in words (no GPS fix, and why), GPS_ALIGN sent and
// followed on its command card to COMPLETED and on its INS panel through the GPS-aided alignment's stages; its GPS fix
// panel says it has no fix service; the 3.0.1 vehicle beside it keeps its own commands.
import { expect, test, type Locator } from "@playwright/test";
import { latestCommand, vehicle } from "../helpers";
import { OWN_STACK, startMixedFleet } from "../stack";

async function statuses(cmd: Locator): Promise<string[]> {
  return cmd.getByTestId("transition").evaluateAll((els) => els.map((e) => (e as HTMLElement).dataset.status ?? ""));
}

test(
  "GPS_ALIGN sent to a UMAA 6.0 vehicle walks the flow to COMPLETED on its command card",
  { tag: OWN_STACK },
  async ({ page }) => {
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
      // its GPS fix panel: no fix service (not a fix lost, no red), its position's quality its navigation solution
      const fixBadge = page.getByTestId("fix-panel").getByTestId("fix-valid");
      await expect(fixBadge).toHaveText("No fix service", { timeout: 15_000 });
      await expect(fixBadge).toHaveAttribute("data-tone", "muted");
      await expect(fixBadge).not.toHaveClass(/\bbad\b/);
      await expect(fixBadge).toHaveAttribute(
        "title",
        /^UMAA 6\.0 has no GPS fix service: .*\. Position quality: measured position$/,
      );
      const align = panel.getByRole("button", {
        name: "INS GPS-aided alignment",
        exact: true,
      });
      await expect(align).toHaveAttribute("title", /\(UMAA state: GPS_ALIGN\)$/);
      await align.click();
      const cmd = latestCommand(page);
      await expect(cmd.getByText("INS GPS-aided alignment", { exact: true })).toBeVisible();
      await expect(cmd).toHaveAttribute("data-status", "COMPLETED", {
        timeout: 40_000,
      });
      expect(await statuses(cmd)).toEqual(["ISSUED", "COMMANDED", "EXECUTING", "COMPLETED"]);
      await expect(cmd.getByTestId("ack")).toHaveCount(1);
      await expect(cmd.getByTestId("command-status")).toHaveAttribute("title", "UMAA commandStatus: COMPLETED");
      // its INS panel: the stages of the GPS-aided alignment it was commanded, each its 6.0 literal in the tooltip, done
      const ins = page.getByTestId("ins-panel");
      const steps = ins.getByRole("list", { name: "Alignment" }).getByRole("listitem");
      await expect(ins.getByTestId("ins-status")).toHaveText("Fine alignment done, GPS-aided");
      await expect(ins.getByTestId("ins-status")).toHaveAttribute("title", "UMAA status: FINE_GPS_ALIGNMENT_COMPLETE");
      await expect(steps).toHaveText(["Starting up", "Coarse alignment", "Fine alignment", "Alignment done"]);
      await expect(ins.locator("[aria-current=step]")).toHaveText("Alignment done");
      await expect(steps.getByText("Coarse alignment", { exact: true })).toHaveAttribute(
        "title",
        "UMAA status: COARSE_GPS_ALIGNMENT",
      );
      await expect(steps.getByText("Fine alignment", { exact: true })).toHaveAttribute(
        "title",
        "UMAA status: FINE_GPS_ALIGNMENT_STARTED",
      );
      await expect(steps.getByText("Alignment done", { exact: true })).toHaveAttribute(
        "title",
        "UMAA status: FINE_GPS_ALIGNMENT_COMPLETE",
      );
      await expect(
        steps.filter({
          hasText: /^(Starting up|Coarse alignment|Fine alignment)$/,
        }),
      ).toHaveClass(["done", "done", "done"]);
    } finally {
      await fleet.stop();
    }
  },
);
