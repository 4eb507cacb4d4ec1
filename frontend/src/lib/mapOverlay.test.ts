import { describe, expect, it } from "vitest";
import { edgeMark } from "./geo";
import type { VehicleMark } from "./geo";
import {
  edgeBoxes,
  firstClear,
  labelOrigin,
  labelRank,
  markName,
  placedByRank,
  projectionBox,
  shownByRank,
  type Box,
} from "./mapOverlay";

const W = 800;
const H = 500;
/** Names with one place each: which are shown (firstClear). */
const clearOf = (boxes: Box[], taken: Box[] = [], keep = 0) =>
  firstClear(
    boxes.map((b) => [b]),
    taken,
    keep,
  ).map((k) => k >= 0);
const overlap = (a: Box, b: Box) => a.x < b.x + b.w && b.x < a.x + a.w && a.y < b.y + b.h && b.y < a.y + a.h;

const mark = (id: string, over: Partial<VehicleMark> = {}): VehicleMark => ({
  id,
  label: id,
  position: { lon: 0, lat: 0 },
  courseDeg: null,
  fix: "valid",
  gpsPosition: true,
  link: "live",
  selected: false,
  alarmed: false,
  projection: null,
  heardS: null,
  plannedUntil: null,
  ...over,
});

describe("whose name wins where names overlap", () => {
  it("the selected vehicle's first, then those in alarm or lost, then the others in the fleet's order", () => {
    const fleet = [
      mark("well"),
      mark("alarmed", { alarmed: true }),
      mark("lost", { link: "lost" }),
      mark("selected", { selected: true }),
    ];
    const placed = [...fleet].sort((a, b) => labelRank(a) - labelRank(b)).map((m) => m.id);
    expect(placed).toEqual(["selected", "alarmed", "lost", "well"]);
    // placed first, an alarmed vehicle's name is the one shown where it would cover a well one's
    const box = { x: 10, y: 10, w: 80, h: 16 };
    expect(clearOf([box, box])).toEqual([true, false]);
  });
});

describe("edge arrows", () => {
  it("a few arrows all get a place, none moved", () => {
    const arrows = [
      [2000, 100],
      [2000, 400],
      [-900, 250],
    ].map(([x, y]) => ({ edge: edgeMark(x, y, W, H, 22)!, w: 120, h: 20 }));
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
    expect(
      clearOf([
        { x: 0, y: 0, w: 50, h: 18 },
        { x: 0, y: 20, w: 50, h: 18 },
      ]),
    ).toEqual([true, true]);
  });

  it("no name covers the '+N more' note but the selected vehicle's", () => {
    const note = { x: 0, y: 0, w: 190, h: 26 };
    const names = [
      { x: 20, y: 5, w: 80, h: 18 },
      { x: 120, y: 10, w: 80, h: 18 },
      { x: 300, y: 10, w: 80, h: 18 },
    ];
    expect(clearOf(names, [note])).toEqual([false, false, true]); // both under the note left to their dots
    expect(clearOf(names, [note], 1)).toEqual([true, false, true]); // the first the selected's: shown all the same
  });
});

describe("a name on either side of its dot", () => {
  const size = { w: 80, h: 18 };
  const sides = ["right", "left"] as const;
  const boxesAt = (p: { x: number; y: number }, order: readonly ("right" | "left")[] = sides) =>
    order.map((side) => ({ ...labelOrigin(p, side, size.w), ...size }));
  it("three vehicles 15 px apart on a diagonal (2 km apart, the coast in view): every name shown, none over another", () => {
    const dots = [0, 1, 2].map((i) => ({ x: 300 + 15 * i, y: 300 - 17 * i }));
    const items = dots.map((p, i) => ({ mark: mark(`v${i}`, { alarmed: i === 2 }), boxes: boxesAt(p) }));
    // right of each dot only, the middle one's touches both the others: left to its dot
    expect(shownByRank(items.map(({ mark: m, boxes }) => ({ mark: m, box: boxes[0] })))).toEqual([true, false, true]);
    const placed = placedByRank(items);
    expect(placed.every((k) => k >= 0)).toBe(true);
    const shown = items.map((it, i) => it.boxes[placed[i]]);
    for (const [i, a] of shown.entries()) for (const b of shown.slice(i + 1)) expect(overlap(a, b)).toBe(false);
    expect(placed[2]).toBe(0); // the one in alarm, placed first, right of its dot
    // each beside its own dot: the nearer end of its box 14 px from the dot, centred on it
    for (const [i, b] of shown.entries()) {
      expect(Math.min(Math.abs(b.x - dots[i].x), Math.abs(b.x + b.w - dots[i].x))).toBe(14);
      expect(b.y + b.h / 2).toBe(dots[i].y);
    }
  });
  it("a name keeps the side it is on while that side is clear; one left out only where neither side is", () => {
    const p = { x: 300, y: 300 };
    const far = { x: 600, y: 100 };
    expect(placedByRank([{ mark: mark("a"), boxes: boxesAt(p, ["left", "right"]) }])).toEqual([0]);
    // three at one place: the one in alarm keeps its name, the first in the fleet's order the other side, the third none
    const three = [mark("first"), mark("middle"), mark("last", { alarmed: true })].map((m) => ({ mark: m, boxes: boxesAt(p) }));
    expect(placedByRank(three)).toEqual([1, -1, 0]);
    expect(placedByRank([...three, { mark: mark("far"), boxes: boxesAt(far) }])).toEqual([1, -1, 0, 0]);
    // the selected vehicle's is shown whatever it covers, on its first side clear of the "+N more" note
    const note = { x: 0, y: 0, w: 190, h: 26 };
    const corner = { mark: mark("selected", { selected: true }), boxes: boxesAt({ x: 150, y: 10 }) };
    expect(placedByRank([corner], [note])).toEqual([0]);
    expect(placedByRank([{ ...corner, boxes: boxesAt({ x: 150, y: 10 }, ["left", "right"]) }], [note])).toEqual([0]);
    expect(placedByRank([{ ...corner, mark: mark("other") }], [note])).toEqual([-1]);
    // a name whose own side covers the note takes the other
    const nearNote = { mark: mark("other"), boxes: boxesAt({ x: 200, y: 10 }, ["left", "right"]) };
    expect(placedByRank([nearNote], [note])).toEqual([1]);
    expect(placedByRank([{ ...nearNote, mark: mark("selected", { selected: true }) }], [note])).toEqual([1]);
  });
  it("a name takes the side clear of a lost vehicle's 'projected' label where one is, and is not hidden for it", () => {
    const p = { x: 300, y: 300 };
    const ghost = projectionBox("projected", { x: 500, y: 300 }, { w: 150, h: 16 }); // over the right of p
    expect(placedByRank([{ mark: mark("a"), boxes: boxesAt(p) }], [], [ghost])).toEqual([1]);
    // both sides covered (a ghost left too): its own side all the same
    const left = projectionBox("projected", { x: 300, y: 300 }, { w: 150, h: 16 });
    expect(placedByRank([{ mark: mark("a"), boxes: boxesAt(p) }], [], [ghost, left])).toEqual([0]);
  });
});

describe("the lost vehicles' projection labels", () => {
  const size = { w: 150, h: 16 };
  const lost = (id: string, over: Partial<VehicleMark> = {}) => mark(id, { link: "lost", heardS: 30, ...over });
  it("by the names' rule: where they would cover one another, the one in alarm wins over one in its planned silence", () => {
    // three lost at one place (a relay down: their ghosts together), one far away
    const at = { x: 400, y: 200 };
    const items = [
      { mark: lost("planned", { plannedUntil: 1e9 }), box: projectionBox("projected", at, size) },
      { mark: lost("acked"), box: projectionBox("projected", { x: 405, y: 204 }, size) },
      { mark: lost("alarmed", { alarmed: true }), box: projectionBox("projected", { x: 410, y: 196 }, size) },
      { mark: lost("far", { plannedUntil: 1e9 }), box: projectionBox("projected", { x: 700, y: 400 }, size) },
    ];
    expect(shownByRank(items)).toEqual([false, false, true, true]);
    // the selected vehicle's is shown, whatever it covers: no alarm outranks it
    items[0].mark = lost("planned", { plannedUntil: 1e9, selected: true });
    expect(shownByRank(items)).toEqual([true, false, false, true]);
    // and none over the "+N more" note but the selected's
    expect(
      shownByRank(
        [{ mark: lost("corner", { alarmed: true }), box: projectionBox("projected", { x: 170, y: 10 }, size) }],
        [{ x: 0, y: 0, w: 190, h: 26 }],
      ),
    ).toEqual([false]);
  });
  it("a projection's box is left of its ghost; a reason for none, under the vehicle's name", () => {
    expect(projectionBox("projected", { x: 400, y: 200 }, size)).toEqual({ x: 238, y: 192, w: 150, h: 16 });
    expect(projectionBox("too-old", { x: 400, y: 200 }, size)).toEqual({ x: 414, y: 211, w: 150, h: 16 });
    // under a name left of its dot, ending where the name ends
    expect(projectionBox("too-old", { x: 400, y: 200 }, size, "left")).toEqual({ x: 236, y: 211, w: 150, h: 16 });
  });
});

describe("a vehicle's name on the map", () => {
  const now = Date.parse("2026-11-28T22:00:00Z") / 1000;
  it("names a vehicle lost in its planned silence by the page's one rule, with when it was last heard; lost, as lost", () => {
    const until = now + 20 * 60;
    const planned = mark("Alpha (77b2ceb8)", { link: "lost", heardS: 12, plannedUntil: until });
    expect(markName(planned)).toMatch(
      /^Alpha \(77b2ceb8\) · out of comms \(planned\) until (2026-11-28 )?22:20 UTC · last heard 12 s ago$/,
    );
    expect(markName(planned, true)).toMatch(/^Alpha \(77b2ceb8\) · out of comms \(planned\) until (2026-11-28 )?22:20 UTC$/); // its edge arrow: short
    expect(markName(mark("Alpha (77b2ceb8)", { link: "lost", heardS: 12 }))).toBe(
      "Alpha (77b2ceb8) · lost · last heard 12 s ago",
    );
    expect(markName(mark("Alpha (77b2ceb8)", { link: "lost", heardS: null }))).toBe("Alpha (77b2ceb8) · lost"); // never heard
    expect(markName(mark("Alpha (77b2ceb8)", { plannedUntil: null }))).toBe("Alpha (77b2ceb8)"); // live: the name alone
  });
});
