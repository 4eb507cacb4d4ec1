import { describe, expect, it } from "vitest";
import { DEFAULT_LAYOUT, mergeLayout, mergeOrder, moveBy, moveTo } from "./layout";

const KNOWN = ["a", "b", "c", "d"];

describe("panel order", () => {
  it("keeps a stored order of the known panels", () => {
    expect(mergeOrder(["d", "b", "a", "c"], KNOWN)).toEqual(["d", "b", "a", "c"]);
  });
  it("drops unknown panels and duplicates, appends the panels the stored order misses", () => {
    expect(mergeOrder(["c", "gone", "a", "c", 7, null], KNOWN)).toEqual(["c", "a", "b", "d"]);
  });
  it("falls back to the default order for anything that is not a list", () => {
    for (const bad of [null, undefined, "a,b", 3, { a: 1 }]) expect(mergeOrder(bad, KNOWN)).toEqual(KNOWN);
  });
  it("merges a whole stored layout group by group, never moving a panel to another group", () => {
    const stored = { main: ["commands-panel", "alerts-panel", "map-panel"], side: ["gateways-panel"], extra: ["x"] };
    const l = mergeLayout(stored);
    expect(l.main).toEqual(["commands-panel", "map-panel", ...DEFAULT_LAYOUT.main.filter((id) => id !== "commands-panel" && id !== "map-panel")]);
    expect(l.side).toEqual(["gateways-panel", "alerts-panel"]);
    for (const bad of [null, "x", 1, [], { main: "map-panel" }]) expect(mergeLayout(bad)).toEqual(DEFAULT_LAYOUT);
  });
  it("every default panel is in exactly one group", () => {
    const all = [...DEFAULT_LAYOUT.side, ...DEFAULT_LAYOUT.main];
    expect(new Set(all).size).toBe(all.length);
  });
  it("moves a panel to an index or by a number of places, clamped to the list", () => {
    expect(moveTo(KNOWN, "a", 2)).toEqual(["b", "c", "a", "d"]);
    expect(moveTo(KNOWN, "d", 0)).toEqual(["d", "a", "b", "c"]);
    expect(moveTo(KNOWN, "b", 99)).toEqual(["a", "c", "d", "b"]);
    expect(moveTo(KNOWN, "zz", 0)).toEqual(KNOWN);
    expect(moveBy(KNOWN, "c", -1)).toEqual(["a", "c", "b", "d"]);
    expect(moveBy(KNOWN, "c", 1)).toEqual(["a", "b", "d", "c"]);
    expect(moveBy(KNOWN, "a", -1)).toEqual(KNOWN);
    expect(moveBy(KNOWN, "d", 1)).toEqual(KNOWN);
  });
});
