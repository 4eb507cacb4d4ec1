import { describe, expect, it } from "vitest";
import { nextUtc } from "../../lib/units";

describe("the planned silence's end, as the operator writes it", () => {
  const now = Date.parse("2026-11-28T22:00:00Z") / 1000;
  it("takes a 24-hour UTC time of day: today's to come, else tomorrow's", () => {
    expect(nextUtc("22:20", now)).toBe(now + 20 * 60);
    expect(nextUtc(" 23:59 ", now)).toBe(now + 119 * 60);
    expect(nextUtc("14:20", now)).toBe(Date.parse("2026-11-29T14:20:00Z") / 1000);
    expect(nextUtc("00:00", now)).toBe(Date.parse("2026-11-29T00:00:00Z") / 1000);
  });
  it("refuses what is no 24-hour HH:MM (a 12-hour time, an hour or minute out of range)", () => {
    for (const bad of ["2:20 PM", "02:20 PM", "2:20", "24:00", "14:60", "1420", "", "14:20:00"])
      expect(nextUtc(bad, now)).toBeNull();
  });
});
