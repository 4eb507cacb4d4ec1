import { describe, expect, it } from "vitest";
import { initialState, reduce, type ProviderView } from "../../data/store";
import { reportMessage } from "../../data/testing";
import { originOf, vehicleMark } from "./layers";

const P = "77b2ceb8-5afe-554e-8450-93db17c48923";
const NONE: ReadonlySet<string> = new Set();
const at = (lat: number, lon: number) => ({ geodeticPosition: { geodeticLatitude: { latitude: lat }, geodeticLongitude: { longitude: lon } } });

function vehicle(...msgs: Parameters<typeof reportMessage>[]): ProviderView {
  const s = msgs.reduce((st, m, i) => reduce(st, reportMessage(...m), 100 + i), initialState);
  return s.providers[P];
}

describe("the map's marks", () => {
  it("marks a vehicle at its GPSFixReport position, with course, fix validity, name and selection", () => {
    const p = vehicle([P, "GPSFixReport", { position2DWithTime: at(0.5, 0.25), trueCourse: -Math.PI / 2, GPSLatLongValid: true }], [P, "GPSFixStatusReport", { fixValid: false, originPosition: at(0.1, 0.2) }]);
    const m = vehicleMark(p, 101, P, NONE, true)!;
    expect(m.position).toEqual({ lat: 0.5, lon: 0.25 });
    expect(m.courseDeg).toBeCloseTo(270);
    expect(m).toMatchObject({ id: P, label: P.slice(0, 8), fix: "invalid", gpsPosition: true, link: "live", selected: true });
    expect(vehicleMark(p, 101, null, NONE, true)!.selected).toBe(false);
    expect(originOf(p)).toEqual({ lat: 0.1, lon: 0.2 });
  });

  it("has no mark without a valid position, marks a silent vehicle stale and a lost one lost", () => {
    expect(vehicleMark(vehicle([P, "GPSFixReport", { position2DWithTime: at(200, 0) }]), 101, null, NONE, true)).toBeNull();
    const p = vehicle([P, "GPSFixReport", { position2DWithTime: at(1, 2) }]);
    expect(originOf(p)).toBeNull();
    expect(vehicleMark(p, 100, null, NONE, true)!.link).toBe("live");
    expect(vehicleMark(p, 1000, null, NONE, true)!.link).toBe("stale"); // silent: stale until the console says lost
    expect(vehicleMark({ ...p, link: "lost" }, 100, null, NONE, true)!.link).toBe("lost");
    expect(vehicleMark({ ...p, link: "regained" }, 100, null, NONE, true)!.link).toBe("regained");
    expect(vehicleMark(p, 100, null, NONE, false)!.link).toBe("stale"); // the console unreachable: not current
    expect(vehicleMark(p, 100, null, new Set([P]), true)!.alarmed).toBe(true);
  });
});
