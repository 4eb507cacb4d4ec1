// @vitest-environment jsdom
import { act, cleanup, fireEvent, screen, waitFor } from "@testing-library/react";
import { afterEach, describe, expect, it } from "vitest";
import { TestSource, reportMessage, snapshotMessage, vehicle } from "../../data/testing";
import { renderWith } from "../testing";
import { VehicleSelector } from "./VehicleSelector";

const A = "77b2ceb8-5afe-554e-8450-93db17c48923";
const B = "0f3c52aa-1d7e-5b1e-9c1f-6f7d2d8e0c11";

function shown(): TestSource {
  const source = new TestSource();
  renderWith(source, <VehicleSelector />);
  act(() =>
    source.send(
      snapshotMessage({
        providers: [vehicle(A, { name: "Alpha" }), vehicle(B, { name: "Bravo", link: "lost", umaaVersion: "6.0" })],
      }),
      reportMessage(A, "GPSFixStatusReport", { fixValid: true }, [], 1000),
      reportMessage(A, "InertialSensorReport", { state: "ON", status: "OPERATIONAL" }, [], 1000),
    ),
  );
  return source;
}

const row = (name: string) => screen.getAllByTestId("vehicle").find((r) => r.textContent?.includes(name))!;

describe("VehicleSelector", () => {
  afterEach(cleanup);

  it("lists every vehicle with its link, UMAA version, fix and INS in words", async () => {
    shown();
    await waitFor(() => expect(screen.getAllByTestId("vehicle")).toHaveLength(2));
    expect(screen.getAllByTestId("vehicle-link").map((l) => l.textContent)).toEqual(["Lost", "Live"]);
    expect(row("Alpha").textContent).toContain("fix valid");
    expect(row("Alpha").textContent).toContain("INS operational");
    expect(row("Alpha").querySelector("[data-testid=vehicle-umaa]")?.textContent).toBe("UMAA 3.0.1");
    expect(row("Bravo").querySelector("[data-testid=vehicle-umaa]")?.textContent).toBe("UMAA 6.0");
    expect(row("Bravo").querySelector("[data-testid=last-heard]")?.textContent).toBe("No report received");
  });

  it("selects the vehicle pressed, and a rename shows at once", async () => {
    const source = shown();
    await waitFor(() => expect(row("Bravo")).toBeTruthy());
    fireEvent.click(row("Bravo"));
    expect(source.store.getState().selected).toBe(B);
    await waitFor(() => expect(row("Bravo").getAttribute("aria-pressed")).toBe("true"));
    act(() =>
      source.send({
        type: "provider",
        event: "configured",
        provider: { ...vehicle(B, { link: "lost", umaaVersion: "6.0" }), name: "Charlie" },
      }),
    );
    await waitFor(() => expect(row("Charlie").getAttribute("aria-pressed")).toBe("true"));
  });

  it("finds a vehicle by name", async () => {
    shown();
    await waitFor(() => expect(screen.getAllByTestId("vehicle")).toHaveLength(2));
    fireEvent.change(screen.getByTestId("find-vehicle"), { target: { value: "brav" } });
    await waitFor(() => expect(screen.getAllByTestId("vehicle")).toHaveLength(1));
    expect(row("Bravo")).toBeTruthy();
  });

  it("says 'Not updating' for a live vehicle once the console cannot be reached (a lost one stays lost)", async () => {
    const source = shown();
    await waitFor(() => expect(screen.getAllByTestId("vehicle")).toHaveLength(2));
    act(() => source.setState("reconnecting"));
    await waitFor(() =>
      expect(screen.getAllByTestId("vehicle-link").map((l) => l.textContent)).toEqual(["Lost", "Not updating"]),
    );
  });
});
