import { memo, useMemo, useState, type CSSProperties } from "react";
import type { GPSSatelliteType } from "../../api/types";
import { Field, Foldable, Panel } from "../../components/Panel";
import {
  useNow,
  useReceiving,
  useSelectedLink,
  useOthersEvery,
  useSelectedTopic,
  useSelectedTrails,
  useSelectionGap,
} from "../../data/hooks";
import { SelectionGap } from "../FleetBar/FleetBar";
import { viewPace, viewReport, type TrailPoint } from "../../data/slices/vehicles";
import { freshness, notCurrent } from "../../lib/freshness";
import { COLOR, CONSTELLATIONS, SHAPE, constellationOf, satelliteLabel, type Shape } from "../../lib/satellites";
import { countRender } from "../../lib/renders";
import { constellationText, timeQuality } from "../../lib/labels";
import { project, trailPath } from "../../lib/skyplot";
import { DASH, degrees, fixed, hertz, radToDeg, yesNo } from "../../lib/units";

const R = 120;

function Marker({ shape, x, y, fill, stroke }: { shape: Shape; x: number; y: number; fill: string; stroke: string }) {
  const s = 6;
  if (shape === "square")
    return <rect x={x - s} y={y - s} width={2 * s} height={2 * s} fill={fill} stroke={stroke} strokeWidth={2} />;
  if (shape === "diamond")
    return (
      <polygon
        points={`${x},${y - s - 2} ${x + s + 2},${y} ${x},${y + s + 2} ${x - s - 2},${y}`}
        fill={fill}
        stroke={stroke}
        strokeWidth={2}
      />
    );
  if (shape === "triangle")
    return (
      <polygon
        points={`${x},${y - s - 2} ${x + s + 1},${y + s} ${x - s - 1},${y + s}`}
        fill={fill}
        stroke={stroke}
        strokeWidth={2}
      />
    );
  return <circle cx={x} cy={y} r={s} fill={fill} stroke={stroke} strokeWidth={2} />;
}

function tooltip(s: GPSSatelliteType): string {
  return [
    `${satelliteLabel(s.satelliteId)} (${constellationText(constellationOf(s))})`,
    `azimuth ${degrees(s.azimuth, 1, true)}, elevation ${degrees(s.elevation)}`,
    `C/N0 antenna ${fixed(s.antennaCarrierNoiseDensity, 1, "dB-Hz")}, baseband ${fixed(s.basebandCarrierNoiseDensity, 1, "dB-Hz")}`,
    `carrier ${hertz(s.carrierFrequency)}`,
    `almanac ${yesNo(s.containsAlmanacData)}, ephemeris ${yesNo(s.ephemerisData)}, used in fix ${yesNo(s.usedInFix)}`,
    `id ${s.satelliteId ?? DASH}`,
  ].join("\n");
}

// The sky plot, table and chart redraw only when their props change: the selected vehicle's GPSReport
// (not its GPSFixReport, nor the panel's age display).
const SkyPlot = memo(function SkyPlot({
  sats,
  trails,
  stale,
}: {
  sats: GPSSatelliteType[];
  trails: Record<string, TrailPoint[]>;
  stale: boolean;
}) {
  countRender("skyplot");
  return (
    <svg
      className={`skyplot${stale ? " stale" : ""}`}
      viewBox={`${-R - 16} ${-R - 16} ${2 * R + 32} ${2 * R + 32}`}
      role="img"
      aria-label="Sky plot"
      data-testid="skyplot"
    >
      {[0, 30, 60].map((el) => (
        <circle key={el} r={R * (1 - el / 90)} className="sky-ring" />
      ))}
      <line x1={-R} y1={0} x2={R} y2={0} className="sky-ring" />
      <line x1={0} y1={-R} x2={0} y2={R} className="sky-ring" />
      {(["N", "E", "S", "W"] as const).map((d, i) => {
        const p = project((i * Math.PI) / 2, 0, R + 10)!;
        return (
          <text key={d} x={p.x} y={p.y} className="sky-label" textAnchor="middle" dominantBaseline="middle">
            {d}
          </text>
        );
      })}
      {sats.map((s) => {
        const label = satelliteLabel(s.satelliteId);
        const path = trailPath(
          (trails[label] ?? []).map((t) => project(t.az, t.el, R)).filter((p): p is NonNullable<typeof p> => p !== null),
        );
        return path ? <path key={`t-${label}`} d={path} className="sky-trail" stroke={COLOR[constellationOf(s)]} /> : null;
      })}
      {sats.map((s) => {
        const p = project(s.azimuth, s.elevation, R);
        if (!p) return null;
        const c = COLOR[constellationOf(s)];
        const label = satelliteLabel(s.satelliteId);
        return (
          <g key={label} data-testid="sky-satellite" data-used={s.usedInFix === true}>
            <title>{tooltip(s)}</title>
            <Marker shape={SHAPE[constellationOf(s)]} x={p.x} y={p.y} fill={s.usedInFix ? c : "transparent"} stroke={c} />
            <text x={p.x + 8} y={p.y - 8} className="sky-sat-label">
              {label}
            </text>
          </g>
        );
      })}
    </svg>
  );
});

interface Bar {
  s: GPSSatelliteType;
  x: number;
}
interface Group {
  c: (typeof CONSTELLATIONS)[number];
  x: number;
  bars: Bar[];
}

/** Bars grouped by constellation, left to right, 14 px a bar and 10 px between groups. */
function cn0Layout(sats: GPSSatelliteType[]): { groups: Group[]; width: number } {
  let x = 0;
  const groups: Group[] = [];
  for (const c of CONSTELLATIONS) {
    const members = sats.filter((s) => constellationOf(s) === c);
    if (!members.length) continue;
    const g: Group = { c, x, bars: members.map((s, i) => ({ s, x: x + i * 14 })) };
    x += members.length * 14 + 10;
    groups.push(g);
  }
  return { groups, width: Math.max(x, 14) };
}

const Cn0Chart = memo(function Cn0Chart({ sats, stale }: { sats: GPSSatelliteType[]; stale: boolean }) {
  countRender("cn0-chart");
  const { groups, width } = cn0Layout(sats);
  const h = 110;
  const max = 55;
  return (
    <svg
      className={`cn0${stale ? " stale" : ""}`}
      viewBox={`0 0 ${width} ${h + 30}`}
      role="img"
      aria-label="C/N0 per satellite"
      data-testid="cn0-chart"
    >
      {[20, 40].map((v) => (
        <g key={v}>
          <line x1={0} x2={width} y1={h - (v / max) * h} y2={h - (v / max) * h} className="grid" />
          <text x={2} y={h - (v / max) * h - 2} className="axis">
            {v} dB-Hz
          </text>
        </g>
      ))}
      {groups.map((g) => (
        <g key={g.c}>
          {g.bars.map(({ s, x }) => {
            const v =
              typeof s.antennaCarrierNoiseDensity === "number" && Number.isFinite(s.antennaCarrierNoiseDensity)
                ? s.antennaCarrierNoiseDensity
                : 0;
            const bh = (Math.min(Math.max(v, 0), max) / max) * h;
            return (
              <g key={satelliteLabel(s.satelliteId)} data-testid="cn0-bar">
                <title>{`${satelliteLabel(s.satelliteId)}: ${fixed(s.antennaCarrierNoiseDensity, 1, "dB-Hz")}${s.usedInFix ? ", used in fix" : ""}`}</title>
                <rect
                  x={x + 2}
                  y={h - bh}
                  width={10}
                  height={bh}
                  fill={s.usedInFix ? COLOR[g.c] : "transparent"}
                  stroke={COLOR[g.c]}
                />
                <text x={x + 7} y={h + 10} className="bar-label" textAnchor="middle">
                  {satelliteLabel(s.satelliteId).slice(1)}
                </text>
              </g>
            );
          })}
          <text x={g.x + 2} y={h + 24} className="axis" fill={COLOR[g.c]}>
            {constellationText(g.c)}
          </text>
        </g>
      ))}
    </svg>
  );
});

type SortKey = "id" | "constellation" | "az" | "el" | "cn0" | "almanac" | "ephemeris" | "used";

function sortValue(s: GPSSatelliteType, k: SortKey): string | number {
  switch (k) {
    case "id":
      return satelliteLabel(s.satelliteId);
    case "constellation":
      return constellationOf(s);
    case "az":
      return s.azimuth ?? -Infinity;
    case "el":
      return s.elevation ?? -Infinity;
    case "cn0":
      return s.antennaCarrierNoiseDensity ?? -Infinity;
    case "almanac":
      return s.containsAlmanacData ? 1 : 0;
    case "ephemeris":
      return s.ephemerisData ? 1 : 0;
    case "used":
      return s.usedInFix ? 1 : 0;
  }
}

const SatelliteTable = memo(function SatelliteTable({ sats, stale }: { sats: GPSSatelliteType[]; stale: boolean }) {
  countRender("satellite-table");
  const [key, setKey] = useState<SortKey>("cn0");
  const [desc, setDesc] = useState(true);
  const rows = useMemo(() => {
    const r = [...sats].sort((a, b) => {
      const va = sortValue(a, key),
        vb = sortValue(b, key);
      return (va < vb ? -1 : va > vb ? 1 : 0) * (desc ? -1 : 1);
    });
    return r;
  }, [sats, key, desc]);
  const head = (k: SortKey, label: string, full: string = label) => (
    <th aria-sort={key === k ? (desc ? "descending" : "ascending") : "none"} title={full}>
      <button onClick={() => (k === key ? setDesc(!desc) : (setKey(k), setDesc(true)))}>
        {label}
        {key === k ? (desc ? " ▾" : " ▴") : ""}
      </button>
    </th>
  );
  return (
    <div className="table-wrap">
      <table
        className={`sat-table${stale ? " stale" : ""}`}
        data-testid="satellite-table"
        title={stale ? "stale: no fresh data" : undefined}
      >
        <thead>
          <tr>
            {head("id", "ID", "satellite (constellation letter and PRN)")}
            {head("constellation", "Const.", "constellation")}
            {head("az", "Az °", "azimuth, degrees from true north")}
            {head("el", "El °", "elevation, degrees above the horizon")}
            {head("cn0", "C/N0", "antenna carrier-to-noise density, dB-Hz")}
            {head("almanac", "Alm.", "almanac data")}
            {head("ephemeris", "Eph.", "ephemeris data")}
            {head("used", "Used", "used in the fix")}
          </tr>
        </thead>
        <tbody>
          {rows.map((s) => (
            <tr key={satelliteLabel(s.satelliteId)} className={s.usedInFix ? "used" : ""}>
              <td>{satelliteLabel(s.satelliteId)}</td>
              <td className="constellation" style={{ "--constellation": COLOR[constellationOf(s)] } as CSSProperties}>
                {constellationText(constellationOf(s))}
              </td>
              <td>{typeof s.azimuth === "number" ? (((radToDeg(s.azimuth) % 360) + 360) % 360).toFixed(1) : DASH}</td>
              <td>{typeof s.elevation === "number" ? radToDeg(s.elevation).toFixed(1) : DASH}</td>
              <td>{fixed(s.antennaCarrierNoiseDensity, 1)}</td>
              <td>{yesNo(s.containsAlmanacData)}</td>
              <td>{yesNo(s.ephemerisData)}</td>
              <td>{s.usedInFix ? "✓" : ""}</td>
            </tr>
          ))}
        </tbody>
      </table>
    </div>
  );
});

const NO_SATELLITES: GPSSatelliteType[] = [];

export function SatellitesPanel() {
  return (
    <Foldable title="Satellites" testId="satellites-panel" topic="GPSReport" className="wide">
      <SatellitesBody />
    </Foldable>
  );
}

function SatellitesBody() {
  const view = useSelectedTopic("GPSReport");
  const trails = useSelectedTrails();
  const link = useSelectedLink();
  const receiving = useReceiving();
  const gap = useSelectionGap(); // none selected: say so, not "no reports"
  const others = useOthersEvery(); // a report from before its selection may have come at the others' pace
  const now = useNow();
  const gps = viewReport(view);
  const sats = gps?.satellites ?? NO_SATELLITES;
  const ageS = view ? Math.max(0, now - view.at) : null;
  const fresh = freshness(ageS, "GPSReport", view?.interval ?? null, link, receiving, viewPace(view, others));
  const stale = notCurrent(fresh);
  const used = sats.filter((s) => s.usedInFix === true).length;
  const counts = CONSTELLATIONS.map((c) => [c, sats.filter((s) => constellationOf(s) === c).length] as const).filter(
    ([, n]) => n,
  );
  const clock = gps?.clock;
  return (
    <Panel title="Satellites" testId="satellites-panel" freshness={fresh} ageSeconds={ageS} className="wide">
      {gap ? (
        <SelectionGap gap={gap} />
      ) : !gps ? (
        <p className="muted">No GPSReport yet.</p>
      ) : (
        <>
          <div className={`counts${stale ? " stale" : ""}`}>
            <Field
              label="In view"
              value={String(gps.numberSatellitesInView ?? sats.length)}
              testId="sats-in-view"
              stale={stale}
            />
            <Field label="Listed" value={String(sats.length)} testId="sats-listed" stale={stale} />
            <Field label="Used in fix" value={String(used)} testId="sats-used" stale={stale} />
            {counts.map(([c, n]) => (
              <Field key={c} label={constellationText(c)} value={String(n)} stale={stale} />
            ))}
            {view && view.envelope.invalid.length > 0 && (
              <span className="invalid-note" title={view.envelope.invalid.join("\n")}>
                ⚠ {view.envelope.invalid.length} invalid values
              </span>
            )}
          </div>
          <div className="sat-grid">
            <SkyPlot sats={sats} trails={trails} stale={stale} />
            <SatelliteTable sats={sats} stale={stale} />
          </div>
          <Cn0Chart sats={sats} stale={stale} />
          <div className="legend">
            {CONSTELLATIONS.filter((c) => counts.some(([k]) => k === c)).map((c) => (
              <span key={c} className="constellation" style={{ "--constellation": COLOR[c] } as CSSProperties}>
                {{ circle: "●", square: "■", diamond: "◆", triangle: "▲" }[SHAPE[c]]} {constellationText(c)}
              </span>
            ))}
            <span className="muted">filled: used in fix · trails: last 10 min</span>
          </div>
          <details className="clock-details">
            <summary>GPS clock</summary>
            {clock && (
              <div className="fields">
                <Field label="Bias" value={fixed(clock.bias, 0, "ns")} stale={stale} />
                <Field label="Bias uncertainty" value={fixed(clock.biasUncertianty, 0, "ns")} stale={stale} />
                <Field label="Drift" value={fixed(clock.drift, 0, "ns/s")} stale={stale} />
                <Field label="Drift uncertainty" value={fixed(clock.driftUncertainty, 0, "ns/s")} stale={stale} />
                <Field label="Full bias" value={fixed(clock.fullBias, 0, "ns")} stale={stale} />
                <Field label="Elapsed real time" value={fixed(clock.elapsedRealtime, 0, "ns")} stale={stale} />
                <Field label="Leap second" value={fixed(clock.leapSecond, 0, "s")} stale={stale} />
                <span style={{ display: "contents" }} title={timeQuality(clock).title}>
                  <Field label="Time quality" value={timeQuality(clock).text} testId="time-quality" stale={stale} />
                </span>
                <Field label="Reference frequency" value={hertz(clock.referenceCarrierFrequency)} stale={stale} />
                <Field label="Reference code" value={clock.referenceCodeTypeFor ?? DASH} stale={stale} />
                <Field
                  label="Reference constellation"
                  value={constellationText(clock.referenceConstellationType)}
                  stale={stale}
                />
                <Field label="HW clock discontinuities" value={fixed(clock.hardwareClockDiscontinuityCount, 0)} stale={stale} />
              </div>
            )}
          </details>
        </>
      )}
    </Panel>
  );
}
