import type { InertialSensorOpStatusEnumType } from "../api/types";
import { Foldable, Panel } from "../components/Panel";
import { useNow, useReceiving, useSelectedLink, useSelectedTopic, useSelectedUmaaVersion, useSelectionGap } from "../data/hooks";
import { SelectionGap } from "./FleetBar";
import { SelectedLost } from "../components/LastHeard";
import { viewReport } from "../data/store";
import { freshness, notCurrent } from "../lib/freshness";
import { alignmentStepText, inline, type AlignmentStep, insStateText, insStatusText, insWord, notReported, umaa } from "../lib/labels";
import { utc } from "../lib/units";

export const STEPS: readonly AlignmentStep[] = [
  "INIT",
  "COURSE_STATIONARY_ALIGNMENT",
  "FINE_STATIONARY_ALIGNMENT_STARTED",
  "FINE_STATIONARY_ALIGNMENT_COMPLETE",
  "OPERATIONAL",
];
const GPS_STEPS: Partial<Record<InertialSensorOpStatusEnumType, number>> = {
  COURSE_GPS_ALIGNMENT: 1,
  FINE_GPS_ALIGNMENT_STARTED: 2,
  FINE_GPS_ALIGNMENT_COMPLETE: 3,
};

/** Index of a status in the alignment steps (GPS-aided stages map to their stationary peers), -1 if none: also for an
 * INS that is off, whose INIT is no step of an alignment (`insStatusText`). */
export function stepIndex(status: InertialSensorOpStatusEnumType | null | undefined, state?: string | null): number {
  if (!status || insStatusText(status, state) === null) return -1;
  const i = (STEPS as readonly string[]).indexOf(status);
  return i >= 0 ? i : (GPS_STEPS[status] ?? -1);
}

export function InsPanel() {
  return (
    <Foldable title="Inertial sensor" testId="ins-panel" topic="InertialSensorReport">
      <InsBody />
    </Foldable>
  );
}

function InsBody() {
  const view = useSelectedTopic("InertialSensorReport"); // drawn on the frame after it changed
  const link = useSelectedLink();
  const version = useSelectedUmaaVersion();
  const receiving = useReceiving();
  const gap = useSelectionGap(); // none selected: say so, not "no reports"
  const now = useNow();
  const ins = viewReport(view);
  const ageS = view ? Math.max(0, now - view.at) : null;
  const fresh = freshness(ageS, "InertialSensorReport", view?.interval ?? null, link, receiving);
  const stale = notCurrent(fresh);
  const failed = ins?.status === "INERTIAL_SENSOR_FAILURE";
  const current = stepIndex(ins?.status, ins?.state);
  const status = insStatusText(ins?.status, ins?.state);
  return (
    <Panel title="Inertial sensor" testId="ins-panel" freshness={fresh} ageSeconds={ageS}>
      {gap ? (
        <SelectionGap gap={gap} />
      ) : !ins ? (
        <p className="muted" data-testid="ins-none">{notReported(version, "InertialSensorReport") ?? "No InertialSensorReport yet."}</p>
      ) : (
        <>
          <SelectedLost />
          <div className="badges">
            <span className={`badge big${stale ? " stale" : ""}`} data-testid="ins-state" data-state={ins.state ?? ""} title={[umaa("state", ins.state), status === null && umaa("status", ins.status)].filter(Boolean).join("; ")}>
              INS {inline(insStateText(ins.state))}
            </span>
            {status !== null && (
              <span className={`badge${ins.status === "OPERATIONAL" ? " ok" : ""}${stale ? " stale" : ""}`} data-testid="ins-status" data-status={ins.status ?? ""} title={umaa("status", ins.status)}>
                {status}
              </span>
            )}
            <span className="muted" data-testid="ins-time">at {utc(ins.timeStamp ? ins.timeStamp.seconds! + (ins.timeStamp.nanoseconds ?? 0) / 1e9 : null, false)}</span>
          </div>
          {failed && (
            <div className="alarm" role="alert" data-testid="ins-failure">
              {insWord(ins.state, ins.status).text}: navigation cannot rely on it
            </div>
          )}
          <ol className={`steps${stale ? " stale" : ""}`} aria-label="Alignment">
            {STEPS.map((s, i) => (
              <li key={s} className={i < current ? "done" : i === current ? "current" : ""} aria-current={i === current ? "step" : undefined}>
                <span title={umaa("status", s)}>{alignmentStepText(s)}</span>
              </li>
            ))}
          </ol>
          {view && view.envelope.invalid.length > 0 && <p className="invalid-note">⚠ {view.envelope.invalid.join("; ")}</p>}
        </>
      )}
    </Panel>
  );
}
