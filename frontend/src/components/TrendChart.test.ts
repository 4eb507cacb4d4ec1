// @vitest-environment jsdom
import { describe, expect, it } from "vitest";
import type uPlot from "uplot";
import { chartData, options } from "./TrendChart";

/** What the chart's legend says for each series (UTC, C/N0 mean, used, in view) at uPlot's `idx` (null: the pointer
 * is off the chart), as uPlot asks it: the raw value at `idx`. */
function legend(points: Parameters<typeof chartData>[0], idx: number | null): (string | number)[] {
  const data = chartData(points);
  const u = { data } as unknown as uPlot;
  return options(400).series.map((s, sidx) => {
    const raw = idx === null ? null : (data[sidx][idx] ?? null);
    return typeof s.value === "function" ? s.value(u, raw as number, sidx, idx) : "";
  });
}

describe("TrendChart legend", () => {
  const points = [
    { t: 1000, cn0: 40.04, used: 8, inView: 12 },
    { t: 1001, cn0: 41.26, used: 9, inView: 12 },
    { t: 1002, cn0: null, used: 9, inView: 11 },
  ];

  it("says the newest values while the pointer is off the chart, not a dash beside lines that have values", () => {
    expect(legend(points, null)).toEqual(["00:16:42", "41.3 dB-Hz", "9", "11"]);
  });

  it("says the values at the pointer's point, and a dash only where there is none", () => {
    expect(legend(points, 0)).toEqual(["00:16:40", "40.0 dB-Hz", "8", "12"]);
    expect(legend(points, 2)[1]).toBe("—");
    expect(legend([], null)).toEqual(["—", "—", "—", "—"]);
  });
});
