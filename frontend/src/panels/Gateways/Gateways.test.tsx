// @vitest-environment jsdom
// The Gateways panel of a vehicle built from the snapshot's brief, selected with the Satellites panel folded.
import { act, cleanup, fireEvent, screen, waitFor } from "@testing-library/react";
import { afterEach, describe, expect, it, vi } from "vitest";
import { TestSource, brief, snapshotMessage, vehicle } from "../../data/testing";
import { update } from "../../data/store";
import { select } from "../../data/slices/vehicles";
import { renderWith } from "../testing";
import { GatewaysPanel } from "./Gateways";
import { SatellitesPanel } from "../Satellites/Satellites";

const A = "77b2ceb8-5afe-554e-8450-93db17c48923";
const B = "0b6a4c1e-2f4d-5e8a-9c3b-7d1e2f3a4b5c";
const CONFIG = { commsLostTimeout: 9, regainedTime: 3, policy: "STOP_MISSION", regainedBehavior: 0 } as const;

describe("selecting a vehicle the snapshot sent as its brief", () => {
  afterEach(() => {
    cleanup();
    vi.unstubAllGlobals();
    localStorage.clear();
  });

  it("shows its link configuration though the operator folded the Satellites panel", async () => {
    vi.stubGlobal("fetch", async (request: Request) => {
      const path = new URL(request.url).pathname;
      if (path === `/api/providers/${B}`)
        return Response.json({ ...vehicle(B, { name: "Bravo", linkConfig: CONFIG }), reports: {} });
      return Response.json([]);
    });
    const source = new TestSource(A);
    renderWith(
      source,
      <>
        <SatellitesPanel />
        <GatewaysPanel />
      </>,
    );
    fireEvent.click(screen.getByTestId("satellites-panel-collapse")); // folded (remembered across reloads)
    // the page named A on connect: B comes as its brief
    act(() =>
      source.send(snapshotMessage({ providers: [vehicle(A, { name: "Alpha" })], fleet: [brief(B, 999, { name: "Bravo" })] })),
    );
    act(() => update(source.store, (s) => select(s, B)));
    await waitFor(() => expect(screen.getByRole("form", { name: /Link configuration of Bravo/ })).toBeTruthy());
  });
});
