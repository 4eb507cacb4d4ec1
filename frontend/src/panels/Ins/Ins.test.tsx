// @vitest-environment jsdom
import { act, cleanup, screen, waitFor } from "@testing-library/react";
import { afterEach, describe, expect, it } from "vitest";
import { TestSource, brief, reportMessage, snapshotMessage, vehicle } from "../../data/testing";
import { update } from "../../data/store";
import { select } from "../../data/slices/vehicles";
import { renderWith } from "../testing";
import { InsPanel } from "./Ins";

const A = "77b2ceb8-5afe-554e-8450-93db17c48923";
const B = "0f3c52aa-1d7e-5b1e-9c1f-6f7d2d8e0c11";

function shown(selected: string | null): TestSource {
  const source = new TestSource(selected);
  renderWith(source, <InsPanel />);
  act(() => source.send(snapshotMessage({ providers: [vehicle(A, { name: "Alpha" }), vehicle(B)] })));
  return source;
}

describe("InsPanel", () => {
  afterEach(cleanup);

  it("says why it is empty: no vehicle selected, or no report of the selected one yet", async () => {
    shown(null);
    expect(screen.getByTestId("selection-gap")).toBeTruthy();
    cleanup();
    shown(A);
    await waitFor(() => expect(screen.getByTestId("ins-none").textContent).toBe("No InertialSensorReport yet."));
  });

  it("shows the selected vehicle's state and status in words, and the alignment step it is at", async () => {
    const source = shown(A);
    act(() => source.send(reportMessage(A, "InertialSensorReport", { state: "ON", status: "OPERATIONAL" }, [], 1000)));
    await waitFor(() => expect(screen.getByTestId("ins-state").textContent).toBe("INS on"));
    expect(screen.getByTestId("ins-state").dataset.state).toBe("ON");
    expect(screen.getByTestId("ins-status").textContent).toBe("Operational");
    expect(screen.getByRole("list", { name: "Alignment" }).querySelector("[aria-current=step]")?.textContent).toBe("Operational");
    expect(screen.getByTestId("ins-panel-freshness").textContent).toContain("Live");
    expect(screen.queryByTestId("ins-failure")).toBeNull();
  });

  it("does not call a vehicle just selected stale while its last report of the topic came at the others' pace", async () => {
    const source = shown(A);
    act(() =>
      source.send(
        { type: "pace", othersEvery: 2.5 },
        reportMessage(B, "InertialSensorReport", { state: "ON", status: "OPERATIONAL" }, [], 1000),
      ),
    );
    act(() => {
      source.clock = 1002.4; // B selected 2.4 s after its last INS report, before its next at full rate has come
      update(source.store, (s) => select(s, B));
      source.send(reportMessage(B, "GPSFixReport", {}, [], 1002.4)); // another topic's, at full rate, came first
    });
    await waitFor(() => expect(screen.getByTestId("ins-status").textContent).toBe("Operational"));
    // the panel's clock of ages ticks once a second
    await waitFor(() => expect(screen.getByTestId("ins-panel-freshness").textContent).toBe("Live · 2.4 s"));
  });

  it("raises a failure the operator cannot miss, and shows only the selected vehicle's reports", async () => {
    const source = shown(A);
    // B's failure: not the selected vehicle's, whose own report is drawn in the same frame
    act(() =>
      source.send(
        reportMessage(B, "InertialSensorReport", { state: "ON", status: "INERTIAL_SENSOR_FAILURE" }, [], 1000),
        reportMessage(A, "InertialSensorReport", { state: "ON", status: "OPERATIONAL" }, [], 1000),
      ),
    );
    await waitFor(() => expect(screen.getByTestId("ins-status").textContent).toBe("Operational"));
    expect(screen.queryByTestId("ins-failure")).toBeNull();
    act(() =>
      source.send(reportMessage(A, "InertialSensorReport", { state: "ON", status: "INERTIAL_SENSOR_FAILURE" }, [], 1001)),
    );
    await waitFor(() => expect(screen.getByRole("alert").textContent).toContain("navigation cannot rely on it"));
    expect(screen.getByTestId("ins-failure")).toBeTruthy();
  });

  it("says 'Not updating' once the console cannot be reached", async () => {
    const source = shown(A);
    act(() => source.send(reportMessage(A, "InertialSensorReport", { state: "ON", status: "OPERATIONAL" }, [], 1000)));
    await waitFor(() => expect(screen.getByTestId("ins-panel-freshness").textContent).toContain("Live"));
    act(() => source.setState("offline"));
    await waitFor(() => expect(screen.getByTestId("ins-panel-freshness").textContent).toContain("Not updating"));
  });

  it("shows the time of a report known from the vehicle's brief as loading, not as a dash, until it comes whole", async () => {
    const source = new TestSource(A);
    renderWith(source, <InsPanel />);
    act(() => source.send(snapshotMessage({ serverTime: 1000, fleet: [brief(A, 1000)] })));
    await waitFor(() => expect(screen.getByTestId("ins-state").textContent).toBe("INS on"));
    expect(screen.getByTestId("ins-time").textContent).toBe("at …");
    expect(screen.getByTestId("ins-time").title).toBe("Not known yet: this vehicle's details are on their way");
    act(() => source.send(reportMessage(A, "InertialSensorReport", { state: "ON", status: "OPERATIONAL" }, [], 1000)));
    await waitFor(() => expect(screen.getByTestId("ins-time").textContent).toBe("at —"));
  });
});
