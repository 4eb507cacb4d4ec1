import type { InertialSensorOpStatusEnumType } from "../api/types";
import { Foldable, Panel } from "../components/Panel";
import { useNow, useReceiving, useSelectedLink, useSelectedTopic, useSelectedUmaaVersion, useSelectionGap } from "../data/hooks";
import { SelectionGap } from "./FleetBar";
import { SelectedLost } from "../components/LastHeard";
import { viewReport } from "../data/store";
import { freshness, notCurrent } from "../lib/freshness";
import { alignmentStepText, inline, type AlignmentStep, insAligned, insFailed, insStateText, insStatusText, insWord, notReported, umaa } from "../lib/labels";
import { utc } from "../lib/units";

export const STEPS: readonly AlignmentStep[] = [
  "INIT",
  "COURSE_STATIONARY_ALIGNMENT",
  "FINE_STATIONARY_ALIGNMENT_STARTED",
  "FINE_STATIONARY_ALIGNMENT_COMPLETE",
  "OPERATIONAL",
];
/** The step of each INS status, of either UMAA version: every kind of alignment (stationary, GPS-aided, best
 * available, transfer; snap, which is done at once) at its stage; a failure is no step (-1). UMAA 6.0 has no
 * OPERATIONAL: its aligned INS stays at its completed stage. */
const STEP_OF: Readonly<Record<InertialSensorOpStatusEnumType, number>> = {
  INIT: 0,
  COURSE_STATIONARY_ALIGNMENT: 1, COURSE_GPS_ALIGNMENT: 1,
  COARSE_STATIONARY_ALIGNMENT: 1, COARSE_GPS_ALIGNMENT: 1, COARSE_BEST_ALIGNMENT: 1, COARSE_TRANSFER_ALIGNMENT: 1,
  FINE_STATIONARY_ALIGNMENT_STARTED: 2, FINE_GPS_ALIGNMENT_STARTED: 2, FINE_BEST_ALIGNMENT_STARTED: 2, FINE_TRANSFER_ALIGNMENT_STARTED: 2,
  FINE_STATIONARY_ALIGNMENT_COMPLETE: 3, FINE_GPS_ALIGNMENT_COMPLETE: 3, FINE_BEST_ALIGNMENT_COMPLETE: 3, FINE_TRANSFER_ALIGNMENT_COMPLETE: 3,
  SNAP_ALIGNMENT_COMPLETE: 3,
  OPERATIONAL: 4,
  INERTIAL_SENSOR_FAILURE: -1, STATIONARY_ALIGNMENT_FAILURE: -1, GPS_ALIGNMENT_FAILURE: -1, BEST_ALIGNMENT_FAILURE: -1,
  TRANSFER_ALIGNMENT_FAILURE: -1, SNAP_ALIGNMENT_FAILURE: -1,
};

/** Index of a status in the alignment steps (each kind's stages map to the step of that stage), -1 if none: also for
 * an INS that is off, whose INIT is no step of an alignment (`insStatusText`). */
export function stepIndex(status: InertialSensorOpStatusEnumType | null | undefined, state?: string | null): number {
  if (!status || insStatusText(status, state) === null) return -1;
  return STEP_OF[status] ?? -1;
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
  const failed = insFailed(ins?.status);
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
            {ins.state && (
              <span className={`badge big${stale ? " stale" : ""}`} data-testid="ins-state" data-state={ins.state} title={[umaa("state", ins.state), status === null && umaa("status", ins.status)].filter(Boolean).join("; ")}>
                INS {inline(insStateText(ins.state))}
              </span>
            )}
            {status !== null && (
              <span className={`badge${ins.state ? "" : " big"}${insAligned(ins.status) ? " ok" : ""}${stale ? " stale" : ""}`} data-testid="ins-status" data-status={ins.status ?? ""} title={umaa("status", ins.status)}>
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
