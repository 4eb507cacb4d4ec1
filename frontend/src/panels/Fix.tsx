import { Field, Foldable, Panel, invalidFor } from "../components/Panel";
import { TrendChart } from "../components/TrendChart";
import { useNow, useReceiving, useSelectedLink, useSelectedTopic, useSelectedUmaaVersion, useSelectionGap, useSelector } from "../data/hooks";
import { useHistory } from "../data/loaders";
import { SelectionGap } from "./FleetBar";
import { SelectedLost } from "../components/LastHeard";
import { useDmsSetting } from "../data/settings";
import { HISTORY_SECONDS, viewReport } from "../data/store";
import { freshness, notCurrent } from "../lib/freshness";
import { fixStateBadge, fixStateTitle, fixWord, navSolutionText, notReported, positionSourceText, timeOutText, umaa } from "../lib/labels";
import { DASH, degrees, dms, fixed, latLon, speed, utc, yesNo } from "../lib/units";

export function FixPanel() {
  return (
    <Foldable title="GPS fix" testId="fix-panel" topic="GPSFixReport">
      <FixBody />
    </Foldable>
  );
}

function FixBody() {
  const selected = useSelector((s) => s.selected);
  const gap = useSelectionGap(); // none selected: say so, not "no reports"
  const link = useSelectedLink();
  const receiving = useReceiving();
  const now = useNow();
  const history = useHistory(link ? selected : null);
  const [useDms, setDms] = useDmsSetting();
  const fixView = useSelectedTopic("GPSFixReport");
  const statusView = useSelectedTopic("GPSFixStatusReport");
  const version = useSelectedUmaaVersion();
  const fix = viewReport(fixView);
  const st = viewReport(statusView);
  const fixAge = fixView ? Math.max(0, now - fixView.at) : null;
  const stAge = statusView ? Math.max(0, now - statusView.at) : null;
  const fFix = freshness(fixAge, "GPSFixReport", fixView?.interval ?? null, link, receiving);
  const fSt = freshness(stAge, "GPSFixStatusReport", statusView?.interval ?? null, link, receiving);
  const sFix = notCurrent(fFix);
  const sSt = notCurrent(fSt);
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
      {gap ? (
        <SelectionGap gap={gap} />
      ) : !fix && !st ? (
        <p className="muted" data-testid="fix-none">{notReported(version, "GPSFixReport") ?? "No GPS fix reports yet."}</p>
      ) : (
        <>
          <SelectedLost />
          <div className="badges">
            <span className={`badge ${st?.fixValid ? "ok" : "bad"}${sSt ? " stale" : ""}`} data-testid="fix-valid" title={fixWord(st?.fixValid).title}>
              {typeof st?.fixValid === "boolean" ? fixWord(st.fixValid).text : DASH}
            </span>
            <span className={`badge ${fix?.GPSLatLongValid ? "ok" : "bad"}${sFix ? " stale" : ""}`} title={umaa("GPSLatLongValid", typeof fix?.GPSLatLongValid === "boolean" ? String(fix.GPSLatLongValid) : null)}>
              {positionSourceText(fix?.GPSLatLongValid)}
            </span>
            <span className="badge" data-testid="gps-fix-state" data-state={fix?.GPSFixCommandStatus ?? ""} title={fixStateTitle(fix?.GPSFixCommandStatus)}>{fixStateBadge(fix?.GPSFixCommandStatus)}</span>
            <span className="badge" data-testid="nav-solution" title={umaa("navSolution", st?.navSolution)}>{navSolutionText(st?.navSolution)}</span>
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
            <span style={{ display: "contents" }} title={umaa("timeOut", typeof st?.timeOut === "boolean" ? String(st.timeOut) : null)}>
              <Field label="Fix search" value={timeOutText(st?.timeOut)} stale={sSt} testId="fix-timeout" />
            </span>
            <Field label="Carrier-to-noise" value={st?.carrierToNoise?.length ? `${st.carrierToNoise.map((v) => fixed(v, 1)).join(", ")} dB-Hz` : DASH} stale={sSt} invalid={invS("carrierToNoise")} />
          </div>
          <TrendChart points={history} label={`C/N0 mean and satellites used and in view, last ${HISTORY_SECONDS / 60} minutes`} />
        </>
      )}
    </Panel>
  );
}
