import { describe, expect, it } from "vitest";
import { initialState, reduce } from "../../data/state";
import { type ProviderView } from "../../data/slices/vehicles";
import { reportMessage } from "../../data/testing";
import { originOf, vehicleMark } from "./layers";
import { projectionText } from "../../lib/projection";

const P = "77b2ceb8-5afe-554e-8450-93db17c48923";
const NONE: ReadonlySet<string> = new Set();
const at = (lat: number, lon: number) => ({
  geodeticPosition: { geodeticLatitude: { latitude: lat }, geodeticLongitude: { longitude: lon } },
});

function vehicle(...msgs: Parameters<typeof reportMessage>[]): ProviderView {
  const s = msgs.reduce((st, m, i) => reduce(st, reportMessage(...m), 100 + i), initialState);
  return s.providers[P];
}

describe("the map's marks", () => {
  it("marks a vehicle at its GPSFixReport position, with course, fix validity, name and selection", () => {
    const p = vehicle(
      [P, "GPSFixReport", { position2DWithTime: at(0.5, 0.25), trueCourse: -Math.PI / 2, GPSLatLongValid: true }],
      [P, "GPSFixStatusReport", { fixValid: false, originPosition: at(0.1, 0.2) }],
    );
    const m = vehicleMark(p, 101, P, NONE, true, [])!;
    expect(m.position).toEqual({ lat: 0.5, lon: 0.25 });
    expect(m.courseDeg).toBeCloseTo(270);
    expect(m).toMatchObject({ id: P, label: P.slice(0, 8), fix: "invalid", gpsPosition: true, link: "live", selected: true });
    expect(vehicleMark(p, 101, null, NONE, true, [])!.selected).toBe(false);
    expect(originOf(p)).toEqual({ lat: 0.1, lon: 0.2 });
  });

  it("has no mark without a valid position, marks a silent vehicle stale and a lost one lost", () => {
    expect(vehicleMark(vehicle([P, "GPSFixReport", { position2DWithTime: at(200, 0) }]), 101, null, NONE, true, [])).toBeNull();
    const p = vehicle([P, "GPSFixReport", { position2DWithTime: at(1, 2) }]);
    expect(originOf(p)).toBeNull();
    expect(vehicleMark(p, 100, null, NONE, true, [])!.link).toBe("live");
    expect(vehicleMark(p, 1000, null, NONE, true, [])!.link).toBe("stale"); // silent: stale until the console says lost
    // paced by the console (a vehicle the page does not draw, every 10 s): live within its pace and 3 s, stale past
    // them, as its row in the vehicle list
    expect(vehicleMark(p, 108, null, NONE, true, [])!.link).toBe("stale");
    expect(vehicleMark(p, 112, null, NONE, true, [], 10)!.link).toBe("live");
    expect(vehicleMark(p, 114, null, NONE, true, [], 10)!.link).toBe("stale");
    expect(vehicleMark({ ...p, link: "lost" }, 100, null, NONE, true, [])!.link).toBe("lost");
    expect(vehicleMark({ ...p, link: "regained" }, 100, null, NONE, true, [])!.link).toBe("regained");
    expect(vehicleMark(p, 100, null, NONE, false, [])!.link).toBe("stale"); // the console unreachable: not current
    expect(vehicleMark(p, 100, null, new Set([P]), true, [])!.alarmed).toBe(true);
    // lost in its planned silence: the map names it by the silence's end, as the rest of the page does
    const silence = { id: "s1", providerId: P, vehicle: "P", until: 5000, reason: "dive", at: 0, by: null, station: null };
    expect(vehicleMark({ ...p, link: "lost" }, 100, null, NONE, true, [silence])!.plannedUntil).toBe(5000);
    expect(vehicleMark(p, 100, null, NONE, true, [silence])!.plannedUntil).toBeNull(); // heard: not named out of comms
  });

  it("projects a lost vehicle from its last fix (time since its arrival, SOG, true course), and only a lost one", () => {
    // a valid GPS fix at 100 s, heading east (π/2) at 2 m/s; lost, looked at 130 s after its fix
    const p = vehicle(
      [P, "GPSFixReport", { position2DWithTime: at(0, 0), SOG: 2, trueCourse: Math.PI / 2, GPSLatLongValid: true }],
      [P, "GPSFixStatusReport", { fixValid: true }],
    );
    expect(vehicleMark(p, 230, null, NONE, true, [])!.projection).toBeNull(); // stale, not lost: no guess
    const m = vehicleMark({ ...p, link: "lost" }, 230, null, NONE, true, [])!;
    expect(m.position).toEqual({ lat: 0, lon: 0 }); // the mark stays at the report
    expect(m.projection).toMatchObject({ kind: "projected", from: { lat: 0, lon: 0 }, seconds: 130, radiusM: 127 });
    const pr = m.projection!.kind === "projected" ? m.projection!.at : null;
    expect(pr!.lon).toBeCloseTo(260 / 111_195.08, 8); // 2 m/s × 130 s east along the equator
    expect(pr!.lat).toBeCloseTo(0, 9);
  });

  it("says when a lost vehicle was last heard: its newest report of any topic, not its fix's", () => {
    // its fix at 100 s, its INS report at 101 s
    const p = vehicle(
      [P, "GPSFixReport", { position2DWithTime: at(0, 0), SOG: 0 }],
      [P, "InertialSensorReport", { state: "ON" }],
    );
    expect(vehicleMark(p, 230, null, NONE, true, [])!.heardS).toBeNull(); // not lost
    expect(vehicleMark({ ...p, link: "lost" }, 230, null, NONE, true, [])!.heardS).toBe(129);
  });

  it("does not project from a speed or course the vehicle flagged invalid, nor from an INS position's small circle", () => {
    const fix = { position2DWithTime: at(0, 0), SOG: 2, trueCourse: 0, GPSLatLongValid: false };
    const flagged = vehicle([P, "GPSFixReport", fix, ["SOG: not a number"]]);
    expect(vehicleMark({ ...flagged, link: "lost" }, 110, null, NONE, true, [])!.projection?.kind).toBe("no-motion");
    const ins = vehicle([P, "GPSFixReport", fix], [P, "GPSFixStatusReport", { fixValid: true }]);
    expect(vehicleMark({ ...ins, link: "lost" }, 110, null, NONE, true, [])!.projection).toMatchObject({
      kind: "projected",
      radiusM: 100 + 0.9 * 10,
    });
  });

  it("draws a lost UMAA 6.0 vehicle at its last position and says why it is not projected: its position report has no speed", () => {
    // a 6.0 vehicle's position report (from its GlobalPoseReport) has no SOG, ever: no speed is made up for it
    const p: ProviderView = {
      ...vehicle([P, "GPSFixReport", { position2DWithTime: at(0, 0), SOG: null, trueCourse: 0, GPSLatLongValid: true }]),
      umaaVersion: "6.0",
    };
    const m = vehicleMark({ ...p, link: "lost" }, 230, null, NONE, true, [])!;
    expect(m.position).toEqual({ lat: 0, lon: 0 });
    expect(m.projection).toMatchObject({ kind: "last-position", seconds: 130 });
    expect(projectionText(m.projection!)).toBe(
      "at its last position, not projected: its UMAA 6.0 position report (GlobalPoseReport) has no speed",
    );
    // a 3.0.1 vehicle that sent no speed is not said to be of a version without one
    const old = vehicleMark({ ...p, umaaVersion: "3.0.1", link: "lost" }, 230, null, NONE, true, [])!;
    expect(projectionText(old.projection!)).toBe("not projected: speed or course unknown");
  });
});
