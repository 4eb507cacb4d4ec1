import { useState } from "react";
import { Field, Panel, invalidFor } from "../components/Panel";
import { useNow, useSelectedProvider } from "../data/hooks";
import { HISTORY_SECONDS, report, type HistoryPoint } from "../data/store";
import { freshness } from "../lib/freshness";
import { DASH, degrees, dms, fixed, latLon, speed, utc, yesNo } from "../lib/units";

function HistoryChart({ history, now }: { history: HistoryPoint[]; now: number }) {
  const w = 300, h = 80;
  const x = (t: number) => w - ((now - t) / HISTORY_SECONDS) * w;
  const line = (vals: (number | null)[], max: number) =>
    history
      .map((p, i) => (vals[i] === null ? null : `${x(p.t).toFixed(1)},${(h - ((vals[i] as number) / max) * h).toFixed(1)}`))
      .filter(Boolean)
      .join(" ");
  return (
    <figure className="history">
      <svg viewBox={`0 0 ${w} ${h}`} preserveAspectRatio="none" role="img" aria-label="C/N0 and satellites used, last 5 minutes" data-testid="fix-history">
        <polyline points={line(history.map((p) => p.cn0), 60)} className="hist-cn0" />
        <polyline points={line(history.map((p) => p.used), 20)} className="hist-used" />
      </svg>
      <figcaption>
        <span className="hist-cn0-key">— mean C/N0 (0–60 dB-Hz)</span> <span className="hist-used-key">— satellites used (0–20)</span> · last 5 min
      </figcaption>
    </figure>
  );
}

export function FixPanel() {
  const p = useSelectedProvider();
  const now = useNow();
  const [useDms, setDms] = useState(false);
  const fixView = p?.topics.GPSFixReport ?? null;
  const statusView = p?.topics.GPSFixStatusReport ?? null;
  const fix = report(p ?? undefined, "GPSFixReport");
  const st = report(p ?? undefined, "GPSFixStatusReport");
  const fixAge = fixView ? Math.max(0, now - fixView.at) : null;
  const stAge = statusView ? Math.max(0, now - statusView.at) : null;
  const fFix = freshness(fixAge, "GPSFixReport", fixView?.interval ?? null, p?.link ?? null);
  const fSt = freshness(stAge, "GPSFixStatusReport", statusView?.interval ?? null, p?.link ?? null);
  const sFix = fFix === "stale" || fFix === "lost";
  const sSt = fSt === "stale" || fSt === "lost";
  const inv = (path: string) => invalidFor(fixView?.envelope.invalid, path);
  const invS = (path: string) => invalidFor(statusView?.envelope.invalid, path);
  const lat = fix?.position2DWithTime?.geodeticPosition?.geodeticLatitude?.latitude;
  const lon = fix?.position2DWithTime?.geodeticPosition?.geodeticLongitude?.longitude;
  const origin = st?.originPosition;
  const fmt = useDms ? dms : latLon;
  return (
    <Panel
      title="GPS fix"
      testId="fix-panel"
      freshness={fFix}
      ageSeconds={fixAge}
      actions={
        <button className="small" onClick={() => setDms(!useDms)} aria-pressed={useDms}>
          {useDms ? "DMS" : "Decimal"}
        </button>
      }
    >
      {!fix && !st ? (
        <p className="muted">No GPS fix reports yet.</p>
      ) : (
        <>
          <div className="badges">
            <span className={`badge ${st?.fixValid ? "ok" : "bad"}${sSt ? " stale" : ""}`} data-testid="fix-valid">
              {st?.fixValid ? "Fix valid" : st?.fixValid === false ? "No fix" : DASH}
            </span>
            <span className={`badge ${fix?.GPSLatLongValid ? "ok" : "bad"}${sFix ? " stale" : ""}`}>
              {fix?.GPSLatLongValid ? "GPS position" : "INS position"}
            </span>
            <span className="badge" data-testid="gps-fix-state">GPSFix {fix?.GPSFixCommandStatus ?? DASH}</span>
            <span className="badge">{st?.navSolution ?? DASH}</span>
          </div>
          <div className="fields">
            <Field label="Latitude" value={fmt(lat, true)} stale={sFix} invalid={inv("position2DWithTime.geodeticPosition.geodeticLatitude")} testId="latitude" />
            <Field label="Longitude" value={fmt(lon, false)} stale={sFix} invalid={inv("position2DWithTime.geodeticPosition.geodeticLongitude")} />
            <Field label="Time at position" value={`${utc(fix?.position2DWithTime?.timeAtPosition)}`} stale={sFix} />
            <Field label="Altitude MSL" value={fixed(fix?.altitudeMSL?.altitude, 1, "m")} stale={sFix} invalid={inv("altitudeMSL")} />
            <Field label="SOG" value={speed(fix?.SOG)} stale={sFix} invalid={inv("SOG")} />
            <Field label="True course" value={degrees(fix?.trueCourse, 1, true)} stale={sFix} invalid={inv("trueCourse")} />
            <Field label="Magnetic variation" value={degrees(fix?.magneticVariation)} stale={sFix} invalid={inv("magneticVariation")} />
            <Field label="Velocity N / E / D" value={fix?.velocity ? `${fixed(fix.velocity.northSpeed, 2)} / ${fixed(fix.velocity.eastSpeed, 2)} / ${fixed(fix.velocity.downSpeed, 2)} m/s` : DASH} stale={sFix} invalid={inv("velocity")} />
            <Field label="Origin" value={origin ? `${fmt(origin.geodeticPosition?.geodeticLatitude?.latitude, true)}, ${fmt(origin.geodeticPosition?.geodeticLongitude?.longitude, false)}, ${fixed(origin.heightAboveEllipsoid?.altitude, 1, "m HAE")}` : DASH} stale={sSt} invalid={invS("originPosition")} />
            <Field label="Countdown" value={fixed(st?.countDown, 0, "s")} stale={sSt} />
            <Field label="P-code" value={yesNo(st?.pCode)} stale={sSt} />
            <Field label="Low backup battery" value={yesNo(st?.lowBkupBattery)} stale={sSt} />
            <Field label="Time-out" value={yesNo(st?.timeOut)} stale={sSt} />
            <Field label="Carrier-to-noise" value={st?.carrierToNoise?.length ? `${st.carrierToNoise.map((v) => fixed(v, 1)).join(", ")} dB-Hz` : DASH} stale={sSt} invalid={invS("carrierToNoise")} />
          </div>
          <HistoryChart history={p?.history ?? []} now={now} />
        </>
      )}
    </Panel>
  );
}
