import { Field, Foldable, Panel, invalidFor } from "../../components/Panel";
import { TrendChart } from "../../components/TrendChart";
import {
  useNow,
  useReceiving,
  useSelectedLink,
  useOthersEvery,
  useSelectedTopic,
  useSelectedUmaaVersion,
  useSelectionGap,
  useSelector,
} from "../../data/hooks";
import { useHistory } from "../../data/loaders";
import { SelectionGap } from "../FleetBar/FleetBar";
import { SelectedLost } from "../../components/LastHeard";
import { SelectedRelay } from "../../components/RelayHop";
import { useDmsSetting } from "../../data/settings";
import { HISTORY_SECONDS, viewPace, viewReport } from "../../data/slices/vehicles";
import { freshness, notCurrent } from "../../lib/freshness";
import type { GPSFixReportType, GPSFixStatusReportType } from "../../api/types";
import {
  fixBadge,
  fixStateBadge,
  fixStateTitle,
  memberNotReported,
  navSolutionText,
  notInVersionText,
  notReported,
  positionKind,
  timeOutText,
  umaa,
  type UmaaVersion,
} from "../../lib/labels";
import { DASH, PENDING, PENDING_TITLE, degrees, dms, fixed, isNum, latLon, speed, utc, yesNo } from "../../lib/units";

/** A standard deviation from a variance (m² -> m, rad² -> rad); null when not reported. */
function sigma(v: number | null | undefined): number | null {
  return isNum(v) && v >= 0 ? Math.sqrt(v) : null;
}

/** What a vehicle reports beside its position only in some versions (UMAA 6.0's GlobalPose: attitude, other altitudes,
 * depth, covariances), each shown when it is reported. */
function PoseFields({ fix, stale, inv }: { fix: GPSFixReportType; stale: boolean; inv: (path: string) => string | null }) {
  const a = fix.attitude;
  const pc = fix.positionCovariance;
  const ac = fix.attitudeCovariance;
  const m = (v: number | null | undefined) => fixed(v, 1, "m");
  const deg = (v: number | null) => (v === null ? DASH : degrees(v, 2));
  return (
    <>
      {a && (
        <Field
          label="Roll / pitch / yaw"
          value={`${degrees(a.roll?.roll)} / ${degrees(a.pitch?.pitch)} / ${degrees(a.yaw?.yaw, 1, true)}`}
          stale={stale}
          invalid={inv("attitude")}
          testId="attitude"
        />
      )}
      {isNum(fix.depth) && <Field label="Depth" value={m(fix.depth)} stale={stale} invalid={inv("depth")} testId="depth" />}
      {isNum(fix.altitudeGeodetic) && (
        <Field label="Altitude HAE" value={m(fix.altitudeGeodetic)} stale={stale} invalid={inv("altitudeGeodetic")} />
      )}
      {isNum(fix.altitudeAGL) && (
        <Field label="Above ground" value={m(fix.altitudeAGL)} stale={stale} invalid={inv("altitudeAGL")} />
      )}
      {isNum(fix.altitudeASF) && (
        <Field label="Above sea floor" value={m(fix.altitudeASF)} stale={stale} invalid={inv("altitudeASF")} />
      )}
      {pc && (
        <span
          style={{ display: "contents" }}
          title={`UMAA positionCovariance (m²): pnPn ${pc.pnPn ?? DASH}, pePe ${pc.pePe ?? DASH}, pdPd ${pc.pdPd ?? DASH}`}
        >
          <Field
            label="Position σ N / E / D"
            value={`${m(sigma(pc.pnPn))} / ${m(sigma(pc.pePe))} / ${m(sigma(pc.pdPd))}`}
            stale={stale}
            invalid={inv("positionCovariance")}
            testId="position-sigma"
          />
        </span>
      )}
      {ac && (
        <span
          style={{ display: "contents" }}
          title={`UMAA attitudeCovariance (rad²): rrRr ${ac.rrRr ?? DASH}, rpRp ${ac.rpRp ?? DASH}, ryRy ${ac.ryRy ?? DASH}`}
        >
          <Field
            label="Attitude σ roll / pitch / yaw"
            value={`${deg(sigma(ac.rrRr))} / ${deg(sigma(ac.rpRp))} / ${deg(sigma(ac.ryRy))}`}
            stale={stale}
            invalid={inv("attitudeCovariance")}
          />
        </span>
      )}
    </>
  );
}

/** The position report's members shown here that a UMAA version may never report, as the panel names them. */
const FIX_MEMBERS = {
  GPSFixCommandStatus: "Receiver state",
  SOG: "SOG",
  magneticVariation: "Magnetic variation",
  velocity: "Velocity N / E / D",
} as const;
type FixMember = keyof typeof FIX_MEMBERS;
/** The fix status's rows (GPSFixStatusReport; its fix and navigation solution are badges), as the panel names them. */
const STATUS_ROWS = {
  originPosition: "Origin",
  countDown: "Countdown",
  pCode: "P-code",
  lowBkupBattery: "Low backup battery",
  timeOut: "Fix search",
  carrierToNoise: "Carrier-to-noise",
} as const;

/** What a vehicle of `version` never reports of what the panel shows (its rows are left out, not shown as a dash that
 * reads "no value now"): the line that names them by their rows' names, and why, for its tooltip. */
function notInVersion(version: UmaaVersion | null | undefined): {
  hidden: (member: FixMember) => boolean;
  noStatus: boolean;
  text: string | null;
  title: string;
} {
  const why = (Object.keys(FIX_MEMBERS) as FixMember[]).map((m) => [m, memberNotReported(version, "GPSFixReport", m)] as const);
  const noStatus = notReported(version, "GPSFixStatusReport");
  const absent: string[] = why.filter(([, w]) => w).map(([m]) => FIX_MEMBERS[m]);
  if (noStatus) absent.push(`GPS fix status (${Object.values(STATUS_ROWS).join(", ")})`);
  return {
    hidden: (member) => why.some(([m, w]) => m === member && w !== null),
    noStatus: noStatus !== null,
    text: notInVersionText(version, absent),
    title: [...new Set([...why.map(([, w]) => w), noStatus].filter((w) => w !== null))].join("; "),
  };
}

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
  const others = useOthersEvery(); // a report from before its selection may have come at the others' pace
  const fFix = freshness(fixAge, "GPSFixReport", fixView?.interval ?? null, link, receiving, viewPace(fixView, others));
  const fSt = freshness(stAge, "GPSFixStatusReport", statusView?.interval ?? null, link, receiving, viewPace(statusView, others));
  const sFix = notCurrent(fFix);
  const sSt = notCurrent(fSt);
  const inv = (path: string) => invalidFor(fixView?.envelope.invalid, path);
  const invS = (path: string) => invalidFor(statusView?.envelope.invalid, path);
  const lat = fix?.position2DWithTime?.geodeticPosition?.geodeticLatitude?.latitude;
  const lon = fix?.position2DWithTime?.geodeticPosition?.geodeticLongitude?.longitude;
  const fmt = useDms ? dms : latLon;
  const absent = notInVersion(version);
  // a report built from the vehicle's brief: what the brief lacks is not known yet, not unreported
  const fixPending = fixView?.brief === true;
  const stPending = statusView?.brief === true;
  // a version without the fix service says its position's kind by its navigation solution, which the brief lacks
  const kindPending = fixPending && absent.noStatus;
  const fixSaid = fixBadge(st?.fixValid, version, fix, kindPending);
  const kind = kindPending ? { text: PENDING, tone: "muted", title: PENDING_TITLE } : positionKind(fix);
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
        <p className="muted" data-testid="fix-none">
          {notReported(version, "GPSFixReport") ?? "No GPS fix reports yet."}
        </p>
      ) : (
        <>
          <SelectedLost />
          <SelectedRelay />
          <div className="badges">
            <span
              className={`badge ${fixSaid.tone}${sSt ? " stale" : ""}`}
              data-testid="fix-valid"
              data-tone={fixSaid.tone}
              title={fixSaid.title}
            >
              {fixSaid.text}
            </span>
            <span
              className={`badge ${kindPending ? "muted" : fix?.GPSLatLongValid ? "ok" : "bad"}${sFix ? " stale" : ""}`}
              data-testid="position-kind"
              title={kind.title}
            >
              {kind.text}
            </span>
            {!absent.hidden("GPSFixCommandStatus") && (
              <span
                className={`badge${sFix ? " stale" : ""}`}
                data-testid="gps-fix-state"
                data-state={fix?.GPSFixCommandStatus ?? ""}
                title={fixPending ? PENDING_TITLE : fixStateTitle(fix?.GPSFixCommandStatus)}
              >
                {fixPending ? `Receiver: ${PENDING}` : fixStateBadge(fix?.GPSFixCommandStatus)}
              </span>
            )}
            {!absent.noStatus && (
              <span
                className={`badge${sSt ? " stale" : ""}`}
                data-testid="nav-solution"
                title={stPending ? PENDING_TITLE : umaa("navSolution", st?.navSolution)}
              >
                {stPending ? PENDING : navSolutionText(st?.navSolution)}
              </span>
            )}
          </div>
          <div className="fields">
            <Field
              label="Latitude"
              value={fmt(lat, true)}
              stale={sFix}
              invalid={inv("position2DWithTime.geodeticPosition.geodeticLatitude")}
              testId="latitude"
            />
            <Field
              label="Longitude"
              value={fmt(lon, false)}
              stale={sFix}
              invalid={inv("position2DWithTime.geodeticPosition.geodeticLongitude")}
            />
            <Field
              label="Time at position"
              value={`${utc(fix?.position2DWithTime?.timeAtPosition)}`}
              stale={sFix}
              pending={fixPending}
            />
            <Field
              label="Altitude MSL"
              value={fixed(fix?.altitudeMSL?.altitude, 1, "m")}
              stale={sFix}
              invalid={inv("altitudeMSL")}
              pending={fixPending}
            />
            {!absent.hidden("SOG") && <Field label={FIX_MEMBERS.SOG} value={speed(fix?.SOG)} stale={sFix} invalid={inv("SOG")} />}
            <Field label="True course" value={degrees(fix?.trueCourse, 1, true)} stale={sFix} invalid={inv("trueCourse")} />
            {!absent.hidden("magneticVariation") && (
              <Field
                label={FIX_MEMBERS.magneticVariation}
                value={degrees(fix?.magneticVariation)}
                stale={sFix}
                invalid={inv("magneticVariation")}
                pending={fixPending}
              />
            )}
            {!absent.hidden("velocity") && (
              <Field
                label={FIX_MEMBERS.velocity}
                value={
                  fix?.velocity
                    ? `${fixed(fix.velocity.northSpeed, 2)} / ${fixed(fix.velocity.eastSpeed, 2)} / ${fixed(fix.velocity.downSpeed, 2)} m/s`
                    : DASH
                }
                stale={sFix}
                invalid={inv("velocity")}
                pending={fixPending}
              />
            )}
            {fix && <PoseFields fix={fix} stale={sFix} inv={inv} />}
            {!absent.noStatus && <StatusFields st={st} stale={sSt} fmt={fmt} inv={invS} pending={stPending} />}
          </div>
          {absent.text && (
            <p className="muted" data-testid="fix-not-in-version" title={absent.title}>
              {absent.text}
            </p>
          )}
          <TrendChart
            points={history}
            label={`C/N0 mean and satellites used and in view, last ${HISTORY_SECONDS / 60} minutes`}
          />
        </>
      )}
    </Panel>
  );
}

/** The fix status's rows (GPSFixStatusReport), for a vehicle whose version has the fix service. */
function StatusFields({
  st,
  stale,
  fmt,
  inv,
  pending,
}: {
  st: GPSFixStatusReportType | null;
  stale: boolean;
  fmt: typeof latLon;
  inv: (path: string) => string | null;
  pending: boolean; // built from the vehicle's brief: all but its origin's latitude and longitude not known yet
}) {
  const origin = st?.originPosition;
  return (
    <>
      <Field
        label={STATUS_ROWS.originPosition}
        value={
          origin
            ? `${fmt(origin.geodeticPosition?.geodeticLatitude?.latitude, true)}, ${fmt(origin.geodeticPosition?.geodeticLongitude?.longitude, false)}, ${pending ? PENDING : fixed(origin.heightAboveEllipsoid?.altitude, 1, "m HAE")}`
            : DASH
        }
        stale={stale}
        invalid={inv("originPosition")}
      />
      <Field label={STATUS_ROWS.countDown} value={fixed(st?.countDown, 0, "s")} stale={stale} pending={pending} />
      <Field label={STATUS_ROWS.pCode} value={yesNo(st?.pCode)} stale={stale} pending={pending} />
      <Field label={STATUS_ROWS.lowBkupBattery} value={yesNo(st?.lowBkupBattery)} stale={stale} pending={pending} />
      <span style={{ display: "contents" }} title={umaa("timeOut", typeof st?.timeOut === "boolean" ? String(st.timeOut) : null)}>
        <Field
          label={STATUS_ROWS.timeOut}
          value={timeOutText(st?.timeOut)}
          stale={stale}
          testId="fix-timeout"
          pending={pending}
        />
      </span>
      <Field
        label={STATUS_ROWS.carrierToNoise}
        value={st?.carrierToNoise?.length ? `${st.carrierToNoise.map((v) => fixed(v, 1)).join(", ")} dB-Hz` : DASH}
        stale={stale}
        invalid={inv("carrierToNoise")}
        pending={pending}
      />
    </>
  );
}
