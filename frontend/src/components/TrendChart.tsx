// The GPS chart: mean C/N0 (left axis) and satellites used / in view (right axis) over time, drawn by uPlot.
import { memo, useEffect, useRef } from "react";
import uPlot from "uplot";
import "uplot/dist/uPlot.min.css";
import type { HistoryPoint } from "../data/slices/vehicles";
import { countRender } from "../lib/renders";

const HEIGHT = 150;
const hms = (t: number) => new Date(t * 1000).toISOString().slice(11, 19);
/** A colour of the theme (styles.css), read when the chart draws: a change of theme shows at its next redraw. Read
 * once per theme (the root's data-theme): getComputedStyle on each of the axes' draws recalculated the page's style. */
const colours = new Map<string, string>();
const themed = (name: string, fallback: string) => () => {
  const key = `${document.documentElement.dataset.theme ?? ""}|${name}`;
  let c = colours.get(key);
  if (c === undefined) {
    c = getComputedStyle(document.documentElement).getPropertyValue(name).trim() || fallback;
    colours.set(key, c);
  }
  return c;
};
const AXIS = {
  stroke: themed("--muted", "#8a99a9"),
  grid: { stroke: themed("--line", "#243140"), width: 1 },
  ticks: { stroke: themed("--line", "#243140"), width: 1 },
};

/** uPlot's columns: times, C/N0, used, in view (null: a gap). */
export function chartData(points: HistoryPoint[]): uPlot.AlignedData {
  return [points.map((p) => p.t), points.map((p) => p.cn0), points.map((p) => p.used), points.map((p) => p.inView)];
}

/** A series' value as its legend says it: at the pointer's point, or, with the pointer off the chart (uPlot's `idx`
 * null), its newest value, so the legend says the latest values rather than a dash that reads "no value"; null only
 * when the series has none. */
function legendValue(u: uPlot, v: number | null, sidx: number, idx: number | null): number | null {
  if (idx !== null) return v ?? null;
  const column = u.data[sidx];
  for (let i = column.length - 1; i >= 0; i--) {
    const x = column[i];
    if (x !== null && x !== undefined) return x;
  }
  return null;
}

/** A legend's value written by `write`; a dash only for no value. */
const said =
  (write: (v: number) => string): uPlot.Series.Value =>
  (u, v, sidx, idx) => {
    const x = legendValue(u, v, sidx, idx);
    return x === null ? "—" : write(x);
  };

export function options(width: number): uPlot.Options {
  return {
    width,
    height: HEIGHT,
    cursor: { drag: { x: false, y: false } },
    legend: { live: true },
    scales: {
      x: { time: true },
      db: { range: [0, 60] },
      n: { range: (_u, _min, max) => [0, Math.max(12, Math.ceil((max ?? 0) + 2))] },
    },
    axes: [
      { ...AXIS, values: (_u, splits) => splits.map(hms) },
      { ...AXIS, scale: "db", label: "dB-Hz", size: 44, labelSize: 14 },
      { ...AXIS, scale: "n", side: 1, label: "satellites", size: 40, labelSize: 14, grid: { show: false } },
    ],
    series: [
      { label: "UTC", value: said(hms) },
      {
        label: "C/N0 mean",
        scale: "db",
        stroke: "#4fc3f7",
        width: 1.5,
        value: said((v) => `${v.toFixed(1)} dB-Hz`),
      },
      { label: "used", scale: "n", stroke: "#4caf50", width: 1.5, value: said(String) },
      {
        label: "in view",
        scale: "n",
        stroke: "#f5a623",
        width: 1,
        dash: [4, 3],
        value: said(String),
      },
    ],
  };
}

/** Redraws when its points change (once a second), not with every render of its panel. */
export const TrendChart = memo(function TrendChart({ points, label }: { points: HistoryPoint[]; label: string }) {
  const box = useRef<HTMLDivElement>(null);
  const plot = useRef<uPlot | null>(null);
  countRender("fix-history");

  const latest = useRef(points);
  latest.current = points;

  // made after the first screen's frame (the fix, INS, satellites and the map come first), then drawn with the newest
  useEffect(() => {
    const el = box.current;
    if (!el) return;
    let u: uPlot | null = null;
    let resize: ResizeObserver | null = null;
    let timer = 0;
    const frame = requestAnimationFrame(() => {
      timer = window.setTimeout(() => {
        const made = new uPlot(options(Math.max(200, el.clientWidth)), chartData(latest.current), el);
        u = made;
        plot.current = made;
        resize = new ResizeObserver(() => made.setSize({ width: Math.max(200, el.clientWidth), height: HEIGHT }));
        resize.observe(el);
      });
    });
    return () => {
      cancelAnimationFrame(frame);
      clearTimeout(timer);
      resize?.disconnect();
      u?.destroy();
      plot.current = null;
    };
  }, []);

  useEffect(() => {
    plot.current?.setData(chartData(points));
  }, [points]);

  return (
    <figure
      className="trend"
      role="img"
      aria-label={label}
      data-testid="fix-history"
      data-points={points.length}
      data-first={points[0]?.t}
      data-last={points.at(-1)?.t}
    >
      <div ref={box} />
    </figure>
  );
});
