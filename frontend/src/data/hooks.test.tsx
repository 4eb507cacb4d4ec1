// @vitest-environment jsdom
// The hooks' shallow selectors: a value built from every vehicle wakes its panel only when what it holds changes.
import { act, cleanup, renderHook } from "@testing-library/react";
import type { ReactNode } from "react";
import { afterEach, describe, expect, it } from "vitest";
import { DataContext, useLostVehicles, useVehicleNames } from "./hooks";
import { TestSource, reportMessage, snapshotMessage, vehicle } from "./testing";

function counted<T>(source: TestSource, hook: () => T): { renders: () => number; value: () => T } {
  let renders = 0;
  const wrapper = ({ children }: { children: ReactNode }) => (
    <DataContext.Provider value={{ store: source.store, source }}>{children}</DataContext.Provider>
  );
  const { result } = renderHook(() => (renders++, hook()), { wrapper });
  return { renders: () => renders, value: () => result.current };
}

describe("shallow selectors over every vehicle", () => {
  afterEach(cleanup);

  it("the vehicles' names: not woken by reports, woken by a rename", () => {
    const source = new TestSource();
    act(() => source.send(snapshotMessage({ providers: [vehicle("a", { name: "Alpha" }), vehicle("b")] })));
    const names = counted(source, useVehicleNames);
    expect([...names.value()]).toEqual([
      ["a", "Alpha"],
      ["b", ""],
    ]);
    const before = names.renders();
    act(() =>
      source.send(
        reportMessage("a", "InertialSensorReport", { state: "ON" }),
        reportMessage("b", "GPSFixStatusReport", { fixValid: true }),
      ),
    );
    expect(names.renders()).toBe(before);
    act(() => source.send({ type: "provider", event: "configured", provider: { ...vehicle("b"), name: "Bravo" } }));
    expect(names.renders()).toBe(before + 1);
    expect(names.value().get("b")).toBe("Bravo");
  });

  it("the lost vehicles: not woken by a live vehicle's reports, woken by a loss", () => {
    const source = new TestSource();
    act(() =>
      source.send(
        snapshotMessage({ providers: [vehicle("a"), vehicle("b")] }),
        reportMessage("b", "GPSFixStatusReport", { fixValid: true }),
      ),
    );
    const lost = counted(source, useLostVehicles);
    expect(lost.value().size).toBe(0);
    const before = lost.renders();
    act(() => source.send(reportMessage("a", "InertialSensorReport", { state: "ON" }, [], 2)));
    expect(lost.renders()).toBe(before);
    act(() => source.send({ type: "provider", event: "lost", provider: { ...vehicle("b"), link: "lost" } }));
    expect(lost.renders()).toBe(before + 1);
    expect([...lost.value()]).toEqual([["b", 1000]]);
  });
});
