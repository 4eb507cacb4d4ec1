import { afterEach, describe, expect, it, vi } from "vitest";
import { RESOLUTION_UNIT, resolution, utcWhen } from "../../lib/units";
import { capabilityText, pendingText } from "./CoMap";

describe("CoMap's survey resolution", () => {
  it("is said in one unit, the vehicle's (IMC's px/m²), in the capabilities and in the survey's confirmation", () => {
    expect(RESOLUTION_UNIT).toBe("px/m²");
    expect(resolution(4)).toBe("4 px/m²");
    expect(
      capabilityText({ kind: "AREA_SURVEY", sensor: "SIDESCAN", resolution: 4, coverageRate: 20 } as Parameters<
        typeof capabilityText
      >[0]),
    ).toBe("area survey side-scan sonar 4 px/m² 20 m²/s");
    const survey = pendingText({
      kind: "survey",
      target: { id: "77b2ceb8-5afe-554e-8450-93db17c48923", name: "Alpha" },
      lost: false,
      featureId: 3,
      sensor: "SIDESCAN",
      resolution: 1,
      deadline: null,
    });
    expect(survey).toBe("Survey feature #3 with Alpha (77b2ceb8): side-scan sonar, resolution 1 px/m²?");
  });
});

describe("CoMap's survey deadline", () => {
  const now = Date.parse("2026-11-28T23:30:00Z") / 1000;
  afterEach(() => {
    vi.useRealTimers();
  });
  it("is written 24-hour UTC (HH:MM, the next one, or YYYY-MM-DD HH:MM) and said in the one time style", () => {
    expect(utcWhen("01:00", now)).toBe(Date.parse("2026-11-29T01:00:00Z") / 1000); // after midnight: tomorrow's
    expect(utcWhen("2026-12-01 14:20", now)).toBe(Date.parse("2026-12-01T14:20:00Z") / 1000);
    for (const bad of ["2:20 PM", "12/01/2026, 02:20 PM", "2026-02-30 14:20", "2026-12-01 24:00", "2026-12-01"])
      expect(utcWhen(bad, now)).toBeNull();
    // the page's clock at `now`: the deadline is another day's, so its date is said (on its own day it would not be)
    vi.useFakeTimers({ toFake: ["Date"] });
    vi.setSystemTime(now * 1000);
    const survey = pendingText({
      kind: "survey",
      target: { id: "77b2ceb8-5afe-554e-8450-93db17c48923", name: "Alpha" },
      lost: false,
      featureId: 3,
      sensor: "SIDESCAN",
      resolution: 1,
      deadline: Date.parse("2026-12-01T14:20:00Z") / 1000,
    });
    expect(survey).toBe("Survey feature #3 with Alpha (77b2ceb8): side-scan sonar, resolution 1 px/m², by 2026-12-01 14:20 UTC?");
  });
});
