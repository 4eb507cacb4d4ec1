import { describe, expect, it } from "vitest";
import { edgeMark } from "./geo";
import type { VehicleMark } from "./geo";
import { clearOf, edgeBoxes, labelRank, type Box } from "./mapOverlay";

const W = 800;
const H = 500;
const overlap = (a: Box, b: Box) => a.x < b.x + b.w && b.x < a.x + a.w && a.y < b.y + b.h && b.y < a.y + a.h;

describe("whose name wins where names overlap", () => {
  const mark = (id: string, over: Partial<VehicleMark> = {}): VehicleMark => ({
    id, label: id, position: { lon: 0, lat: 0 }, courseDeg: null, fix: "valid", gpsPosition: true, link: "live", selected: false, alarmed: false, projection: null, heardS: null, plannedUntil: null, ...over,
  });
  it("the selected vehicle's first, then those in alarm or lost, then the others in the fleet's order", () => {
    const fleet = [mark("well"), mark("alarmed", { alarmed: true }), mark("lost", { link: "lost" }), mark("selected", { selected: true })];
    const placed = [...fleet].sort((a, b) => labelRank(a) - labelRank(b)).map((m) => m.id);
    expect(placed).toEqual(["selected", "alarmed", "lost", "well"]);
    // placed first, an alarmed vehicle's name is the one shown where it would cover a well one's
    const box = { x: 10, y: 10, w: 80, h: 16 };
    expect(clearOf([box, box])).toEqual([true, false]);
  });
});

describe("edge arrows", () => {
  it("a few arrows all get a place, none moved", () => {
    const arrows = [[2000, 100], [2000, 400], [-900, 250]].map(([x, y]) => ({ edge: edgeMark(x, y, W, H, 22)!, w: 120, h: 20 }));
    const boxes = edgeBoxes(arrows, W, H);
    expect(boxes.every((b) => b !== null)).toBe(true);
  });

  it("with a fleet outside the view, each arrow stays near its edge point and clear of the others; the rest are left out, the first in order kept", () => {
    // 250 vehicles far to the east, nearly in one direction (the map zoomed in on one of them): 250 arrows at one point
    const arrows = Array.from({ length: 250 }, (_, i) => ({ edge: edgeMark(5000, 260 + (i % 5), W, H, 22)!, w: 140, h: 20 }));
    const boxes = edgeBoxes(arrows, W, H);
    const placed = boxes.filter((b): b is Box => b !== null);
    expect(boxes[0]).not.toBeNull(); // the first (the selected vehicle's, then the lost ones': place sorts them first)
    expect(placed.length).toBeGreaterThan(1);
    expect(placed.length).toBeLessThanOrEqual(4); // its own place and three stacked: never a column over the map
    for (const [i, b] of boxes.entries()) {
      if (!b) continue;
      expect(Math.abs(b.y + b.h / 2 - arrows[i].edge.y)).toBeLessThanOrEqual(3 * 22 + 1);
      expect(b.x >= 0 && b.y >= 0 && b.x + b.w <= W && b.y + b.h <= H).toBe(true);
    }
    for (const [i, a] of placed.entries()) for (const b of placed.slice(i + 1)) expect(overlap(a, b)).toBe(false);
  });

  it("no arrow covers the '+N more' note in the top left corner", () => {
    const arrows = Array.from({ length: 10 }, () => ({ edge: edgeMark(-3000, -3000, W, H, 22)!, w: 140, h: 20 }));
    for (const b of edgeBoxes(arrows, W, H)) if (b) expect(overlap(b, { x: 0, y: 0, w: 190, h: 26 })).toBe(false);
  });
});

describe("names on the map", () => {
  it("a name that would cover one shown before it is left out; those clear of the others all shown", () => {
    // a coast of vehicles 10 px apart, names 80 px wide: one in eight shown, and the first (the selected) always
    const names = Array.from({ length: 40 }, (_, i) => ({ x: 100 + i * 10, y: 200, w: 80, h: 18 }));
    const shown = clearOf(names);
    expect(shown[0]).toBe(true);
    expect(shown.filter(Boolean)).toHaveLength(5);
    const kept = names.filter((_, i) => shown[i]);
    for (const [i, a] of kept.entries()) for (const b of kept.slice(i + 1)) expect(overlap(a, b)).toBe(false);
    expect(clearOf([{ x: 0, y: 0, w: 50, h: 18 }, { x: 0, y: 20, w: 50, h: 18 }])).toEqual([true, true]);
  });

  it("no name covers the '+N more' note but the selected vehicle's", () => {
    const note = { x: 0, y: 0, w: 190, h: 26 };
    const names = [{ x: 20, y: 5, w: 80, h: 18 }, { x: 120, y: 10, w: 80, h: 18 }, { x: 300, y: 10, w: 80, h: 18 }];
    expect(clearOf(names, [note])).toEqual([false, false, true]); // both under the note left to their dots
    expect(clearOf(names, [note], 1)).toEqual([true, false, true]); // the first the selected's: shown all the same
  });
});
