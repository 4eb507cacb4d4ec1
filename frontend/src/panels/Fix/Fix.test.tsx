// @vitest-environment jsdom
import { act, cleanup, screen, waitFor } from "@testing-library/react";
import { afterEach, describe, expect, it, vi } from "vitest";
import { TestSource, brief, reportMessage, snapshotMessage, vehicle } from "../../data/testing";
import { renderWith } from "../testing";
import { FixPanel } from "./Fix";

// the history chart draws on a canvas (uPlot), which jsdom has not
vi.mock("../../components/TrendChart", () => ({ TrendChart: () => null }));

const A = "77b2ceb8-5afe-554e-8450-93db17c48923";

function shown(umaaVersion: "3.0.1" | "6.0" = "3.0.1"): TestSource {
  const source = new TestSource(A);
  renderWith(source, <FixPanel />);
  act(() => source.send(snapshotMessage({ providers: [vehicle(A, { name: "Alpha", umaaVersion })] })));
  return source;
}

const position = (lat: number) => ({
  GPSLatLongValid: true,
  position2DWithTime: { geodeticPosition: { geodeticLatitude: { latitude: lat }, geodeticLongitude: { longitude: 10 } } },
});

describe("FixPanel", () => {
  afterEach(cleanup);

  it("says no fix report has come yet", async () => {
    shown();
    await waitFor(() => expect(screen.getByTestId("fix-none").textContent).toBe("No GPS fix reports yet."));
  });

  it("shows whether the fix is valid in words, and the position of the selected vehicle's newest report", async () => {
    const source = shown();
    act(() =>
      source.send(
        reportMessage(A, "GPSFixStatusReport", { fixValid: true }, [], 1000),
        reportMessage(A, "GPSFixReport", position(59.5), [], 1000),
      ),
    );
    await waitFor(() => expect(screen.getByTestId("fix-valid").textContent).toBe("Fix valid"));
    expect(screen.getByTestId("fix-valid").dataset.tone).toBe("ok");
    expect(screen.getByTestId("latitude").textContent).toContain("59.5");
    act(() => source.send(reportMessage(A, "GPSFixStatusReport", { fixValid: false }, [], 1001)));
    await waitFor(() => expect(screen.getByTestId("fix-valid").textContent).toBe("No fix"));
    expect(screen.getByTestId("fix-valid").dataset.tone).toBe("bad");
  });

  it("greys the receiver's state and the navigation solution of a lost vehicle, as its other values", async () => {
    const source = new TestSource(A);
    renderWith(source, <FixPanel />);
    const send = (link: "live" | "lost") =>
      act(() =>
        source.send(
          snapshotMessage({ providers: [vehicle(A, { name: "Alpha", link })] }),
          reportMessage(A, "GPSFixStatusReport", { fixValid: true, navSolution: "GPS_3D" }, [], 1000),
          reportMessage(A, "GPSFixReport", { ...position(59.5), GPSFixCommandStatus: "STABLE" }, [], 1000),
        ),
      );
    send("live");
    await waitFor(() => expect(screen.getByTestId("nav-solution").className).toBe("badge"));
    expect(screen.getByTestId("gps-fix-state").className).toBe("badge");
    send("lost");
    await waitFor(() => expect(screen.getByTestId("nav-solution").className).toBe("badge stale"));
    expect(screen.getByTestId("gps-fix-state").className).toBe("badge stale");
    expect(screen.getByTestId("fix-valid").className).toContain("stale");
  });

  it("does not call a UMAA 6.0 vehicle's missing fix status a fix lost", async () => {
    const source = shown("6.0");
    act(() => source.send(reportMessage(A, "GPSFixReport", position(59.5), [], 1000)));
    await waitFor(() => expect(screen.getByTestId("fix-valid").textContent).toBe("No fix service"));
    expect(screen.getByTestId("fix-valid").dataset.tone).toBe("muted");
  });

  it("leaves out what a UMAA 6.0 vehicle never reports, and names it once, rather than a dash that reads 'no value now'", async () => {
    const source = shown("6.0");
    act(() => source.send(reportMessage(A, "GPSFixReport", { ...position(59.5), trueCourse: 248.5 }, [], 1000)));
    await waitFor(() => expect(screen.getByTestId("latitude").textContent).toContain("59.5"));
    const rows = [...screen.getByTestId("fix-panel").querySelectorAll(".field .label")].map((l) => l.textContent);
    for (const row of [
      "SOG",
      "Magnetic variation",
      "Velocity N / E / D",
      "Origin",
      "Countdown",
      "P-code",
      "Low backup battery",
      "Fix search",
      "Carrier-to-noise",
    ])
      expect(rows).not.toContain(row);
    expect(screen.queryByTestId("gps-fix-state")).toBeNull(); // "Receiver: —"
    expect(screen.queryByTestId("nav-solution")).toBeNull();
    expect(rows).toContain("True course");
    const note = screen.getByTestId("fix-not-in-version");
    expect(note.textContent).toBe(
      "Not in UMAA 6.0: Receiver state, SOG, Magnetic variation, Velocity N / E / D, GPS fix status (Origin, Countdown, P-code, Low backup battery, Fix search, Carrier-to-noise)",
    );
    expect(note.title).toContain("has no GPS fix service");
  });

  it("shows a UMAA 3.0.1 vehicle's rows with no value yet as a dash, and names nothing as not in its version", async () => {
    const source = shown("3.0.1");
    act(() => source.send(reportMessage(A, "GPSFixReport", position(59.5), [], 1000)));
    await waitFor(() => expect(screen.getByTestId("latitude").textContent).toContain("59.5"));
    const rows = [...screen.getByTestId("fix-panel").querySelectorAll(".field .label")].map((l) => l.textContent);
    for (const row of ["SOG", "Magnetic variation", "Velocity N / E / D", "Origin", "Countdown", "P-code", "Fix search"])
      expect(rows).toContain(row);
    expect(screen.getByTestId("gps-fix-state").textContent).toBe("Receiver: —");
    expect(screen.queryByTestId("fix-not-in-version")).toBeNull();
  });

  it("shows what a vehicle known from its brief does not say yet as loading, not as a dash, until its report comes whole", async () => {
    const source = new TestSource(A);
    renderWith(source, <FixPanel />);
    // the page named another vehicle: this one came as its brief (position, course, speed, fix validity, origin)
    act(() => source.send(snapshotMessage({ serverTime: 1000, fleet: [brief(A, 1000)] })));
    await waitFor(() => expect(screen.getByTestId("latitude").textContent).toContain("36.8"));
    const value = (label: string) =>
      [...screen.getByTestId("fix-panel").querySelectorAll(".field")]
        .find((f) => f.querySelector(".label")?.textContent === label)
        ?.querySelector(".value") as HTMLElement;
    for (const label of ["Time at position", "Altitude MSL", "Magnetic variation", "P-code", "Countdown", "Fix search"]) {
      expect(value(label).textContent, label).toBe("…");
      expect(value(label).title).toBe("Not known yet: this vehicle's details are on their way");
    }
    expect(value("Origin").textContent).toMatch(/, …$/); // its height: the brief has its latitude and longitude only
    expect(screen.getByTestId("gps-fix-state").textContent).toBe("Receiver: …");
    expect(value("True course").textContent).not.toBe("…"); // the brief has it
    // its reports whole (the `select`'s, or any next one): what is null now is the vehicle's, a dash
    act(() =>
      source.send(
        reportMessage(A, "GPSFixReport", { ...position(36.8), altitudeMSL: { altitude: 12 } }, [], 1000),
        reportMessage(A, "GPSFixStatusReport", { fixValid: true }, [], 1000),
      ),
    );
    await waitFor(() => expect(value("Altitude MSL").textContent).toBe("12.0 m"));
    expect(value("Magnetic variation").textContent).toBe("—");
    expect(value("P-code").textContent).toBe("—");
    expect(value("P-code").title).toBe("");
    expect(screen.getByTestId("gps-fix-state").textContent).toBe("Receiver: —");
  });

  it("does not name a UMAA 6.0 vehicle known from its brief by its 3.0.1 words: its navigation solution is not known yet", async () => {
    const source = new TestSource(A);
    renderWith(source, <FixPanel />);
    // a 6.0 vehicle's brief: its position and GPSLatLongValid (the console's, from its navigationSolution), no fix status
    act(() =>
      source.send(snapshotMessage({ serverTime: 1000, fleet: [brief(A, 1000, { umaaVersion: "6.0", fixStatus: null })] })),
    );
    await waitFor(() => expect(screen.getByTestId("latitude").textContent).toContain("36.8"));
    // its report says "Measured position" once whole: "GPS position" is no word of its version
    expect(screen.getByTestId("position-kind").textContent).toBe("…");
    expect(screen.getByTestId("position-kind").title).toBe("Not known yet: this vehicle's details are on their way");
    expect(screen.getByTestId("fix-valid").title).toContain("Position quality: …");
    act(() => source.send(reportMessage(A, "GPSFixReport", { ...position(36.8), navigationSolution: "MEASURED" }, [], 1000)));
    await waitFor(() => expect(screen.getByTestId("position-kind").textContent).toBe("Measured position"));
    expect(screen.getByTestId("fix-valid").title).toContain("Position quality: measured position");
  });
});
