// @vitest-environment jsdom
import { act, cleanup, screen, waitFor } from "@testing-library/react";
import { afterEach, describe, expect, it, vi } from "vitest";
import { TestSource, reportMessage, snapshotMessage, vehicle } from "../../data/testing";
import { renderWith } from "../testing";
import { SatellitesPanel } from "./Satellites";

// the history chart draws on a canvas (uPlot), which jsdom has not
vi.mock("../../components/TrendChart", () => ({ TrendChart: () => null }));

const A = "77b2ceb8-5afe-554e-8450-93db17c48923";

const gps = reportMessage(
  A,
  "GPSReport",
  {
    numberSatellitesInView: 1,
    satellites: [
      {
        azimuth: 1,
        elevation: 0.5,
        satelliteId: "ca5d35fb-bcc2-5b9a-b20c-df56b7b90207",
        usedInFix: true,
        antennaCarrierNoiseDensity: 40,
      },
    ],
    clock: { bias: 12 },
  },
  [],
  1000,
);

describe("SatellitesPanel", () => {
  afterEach(cleanup);

  it("greys a lost vehicle's satellite table, C/N0 bars and clock, as its counts and sky plot", async () => {
    const source = new TestSource(A);
    renderWith(source, <SatellitesPanel />);
    const send = (link: "live" | "lost") =>
      act(() => source.send(snapshotMessage({ providers: [vehicle(A, { name: "Alpha", link })] }), gps));
    send("live");
    await waitFor(() => expect(screen.getByTestId("satellite-table").className).toBe("sat-table"));
    expect(screen.getByTestId("cn0-chart").getAttribute("class")).toBe("cn0");
    expect(screen.getByText("Bias").parentElement!.className).toBe("field");
    send("lost");
    await waitFor(() => expect(screen.getByTestId("satellite-table").className).toBe("sat-table stale"));
    expect(screen.getByTestId("cn0-chart").getAttribute("class")).toBe("cn0 stale");
    expect(screen.getByText("Bias").parentElement!.className).toBe("field stale");
  });
});
