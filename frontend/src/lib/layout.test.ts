import { describe, expect, it } from "vitest";
import { groupOrder, mergeOrder, moveBy, moveTo } from "./layout";

const KNOWN = ["a", "b", "c", "d"];

describe("panel order", () => {
  it("keeps a stored order of the known panels", () => {
    expect(mergeOrder(["d", "b", "a", "c"], KNOWN)).toEqual(["d", "b", "a", "c"]);
  });
  it("drops unknown panels and duplicates, appends the panels the stored order misses", () => {
    expect(mergeOrder(["c", "gone", "a", "c", 7, null], KNOWN)).toEqual(["c", "a", "b", "d"]);
    expect(mergeOrder([], KNOWN)).toEqual(KNOWN);
  });
  it("falls back to the default order for anything that is not a list", () => {
    for (const bad of [null, undefined, "a,b", 3, { a: 1 }]) expect(mergeOrder(bad, KNOWN)).toEqual(KNOWN);
  });
  it("reads a group out of a stored layout, whatever else it holds", () => {
    const stored = { main: ["c", "x", "a"], side: ["s2"], extra: ["x"] };
    expect(groupOrder(stored, "main", KNOWN)).toEqual(["c", "a", "b", "d"]);
    expect(groupOrder(stored, "side", ["s1", "s2"])).toEqual(["s2", "s1"]);
    expect(groupOrder({ main: ["s2", "a"] }, "main", KNOWN)).toEqual(KNOWN); // a panel of another group stays there
    for (const bad of [null, "x", 1, [], ["a"], { main: "a" }, { side: ["a"] }])
      expect(groupOrder(bad, "main", KNOWN)).toEqual(KNOWN);
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
