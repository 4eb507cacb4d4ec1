import { describe, expect, it } from "vitest";
import { bearingDeg, destination, distanceM } from "./geo";
import { DEAD_RECKONING, deadReckon, projectionText, uncertaintyM } from "./projection";
import { elapsedText } from "./units";
import { lastHeardText } from "./labels";

// 1° of arc on the mean sphere (R 6,371,008.8 m): 2πR / 360
const DEG_M = 111_195.08;

describe("great-circle dead reckoning", () => {
  it("one degree of arc east along the equator, and a quarter circle north to the pole", () => {
    const e = destination({ lon: 0, lat: 0 }, 90, DEG_M);
    expect(e.lat).toBeCloseTo(0, 9);
    expect(e.lon).toBeCloseTo(1, 6);
    expect(destination({ lon: 10, lat: 0 }, 0, 90 * DEG_M).lat).toBeCloseTo(90, 5);
  });
  it("a published worked example: 53°19′14″N 1°43′47″W, 96°01′18″ for 124.8 km is 53°11′18″N 0°08′00″E", () => {
    // Chris Veness, "Calculate distance, bearing and more between Latitude/Longitude points" (movable-type.co.uk),
    // the destination-point example, rounded there to the second of arc
    const d = destination({ lat: 53 + 19 / 60 + 14 / 3600, lon: -(1 + 43 / 60 + 47 / 3600) }, 96 + 1 / 60 + 18 / 3600, 124_800);
    expect(Math.abs(d.lat - (53 + 11 / 60 + 18 / 3600))).toBeLessThan(0.6 / 3600);
    expect(Math.abs(d.lon - 8 / 60)).toBeLessThan(0.6 / 3600);
  });
  it("over a short leg it agrees with flat-earth dead reckoning worked by hand (1 km at 045° from 36.8°N 76.25°W)", () => {
    // north and east 707.107 m each: 707.107 / 111195.08 = 0.0063592° of latitude, / (111195.08 × cos 36.8°) =
    // 0.0079417° of longitude
    const d = destination({ lat: 36.8, lon: -76.25 }, 45, 1000);
    expect(d.lat).toBeCloseTo(36.8063592, 5);
    expect(d.lon).toBeCloseTo(-76.2420583, 5);
  });
  it("goes where the haversine distance and initial bearing say it went, across the antimeridian too", () => {
    const from = { lat: -33.9, lon: 179.9 };
    const to = destination(from, 100, 25_000);
    expect(to.lon).toBeLessThan(-179); // wrapped into -180..180
    expect(distanceM(from, to)).toBeCloseTo(25_000, 3);
    expect(bearingDeg(from, to)).toBeCloseTo(100, 6);
  });
});

describe("a lost vehicle's projection", () => {
  const fix = { at: { lat: 0, lon: 0 }, speedMps: 5, courseDeg: 0, gpsFix: true };

  it("moves it along its course at its speed for the time since its last fix", () => {
    const p = deadReckon(fix, 1000);
    expect(p.kind).toBe("projected");
    if (p.kind !== "projected") return;
    expect(p.at.lat).toBeCloseTo(5000 / DEG_M, 9); // 0.0449660°
    expect(p.at.lon).toBeCloseTo(0, 9);
    expect(p.from).toEqual(fix.at);
    expect(p.seconds).toBe(1000);
  });
  it("grows its circle: base + (0.5 m/s + 0.2 × SOG) × seconds, capped at 5 km", () => {
    expect(uncertaintyM(true, 2, 130)).toBeCloseTo(127, 9); // 10 + (0.5 + 0.4) × 130
    expect(uncertaintyM(false, 0, 600)).toBeCloseTo(400, 9); // 100 + 0.5 × 600: no valid GPS fix
    expect(uncertaintyM(true, 20, 1500)).toBe(DEAD_RECKONING.maxRadiusM); // 10 + 4.5 × 1500 = 6760, capped
    expect(uncertaintyM(true, 2, 0)).toBe(10);
  });
  it("a stopped vehicle stays put with any course, or none; its circle still grows", () => {
    const p = deadReckon({ ...fix, speedMps: 0, courseDeg: null }, 60);
    expect(p).toMatchObject({ kind: "projected", at: fix.at, radiusM: 40 });
  });
  it("none without a speed, or a course when under way, nor after 30 minutes: and says why", () => {
    const noSpeed = deadReckon({ ...fix, speedMps: null }, 10);
    expect(noSpeed.kind).toBe("no-motion");
    expect(deadReckon({ ...fix, courseDeg: null }, 10).kind).toBe("no-motion");
    expect(deadReckon({ ...fix, speedMps: -1 }, 10).kind).toBe("no-motion");
    expect(deadReckon(fix, 1800).kind).toBe("projected");
    const old = deadReckon(fix, 1801);
    expect(old.kind).toBe("too-old");
    expect(projectionText(old)).toBe("not projected: no fix for over 30 min");
    expect(projectionText(noSpeed)).toBe("not projected: speed or course unknown");
    expect(projectionText(deadReckon(fix, 100))).toBe("projected · within 160 m"); // 10 + (0.5 + 0.2 × 5) × 100
    expect(projectionText(deadReckon(fix, 1000))).toBe("projected · within 1.5 km"); // 10 + 1.5 × 1000
  });
  it("a clock a little behind the report's arrival projects from the fix itself, not backwards", () => {
    const p = deadReckon(fix, -2);
    expect(p).toMatchObject({ kind: "projected", at: fix.at, seconds: 0, radiusM: 10 });
  });
});

describe("last heard", () => {
  it("in words, to the second", () => {
    expect(elapsedText(130.9)).toBe("2 min 10 s");
    expect(elapsedText(45)).toBe("45 s");
    expect(elapsedText(3725)).toBe("1 h 2 min");
    expect(lastHeardText(130)).toBe("Last heard 2 min 10 s ago");
    expect(lastHeardText(null)).toBe("No report received");
  });
});
