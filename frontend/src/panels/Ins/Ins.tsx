import { Foldable, Panel } from "../../components/Panel";
import {
  useNow,
  useReceiving,
  useSelectedLink,
  useOthersEvery,
  useSelectedTopic,
  useSelectedUmaaVersion,
  useSelectionGap,
} from "../../data/hooks";
import { SelectionGap } from "../FleetBar/FleetBar";
import { SelectedLost } from "../../components/LastHeard";
import { SelectedRelay } from "../../components/RelayHop";
import { viewPace, viewReport } from "../../data/slices/vehicles";
import { freshness, notCurrent } from "../../lib/freshness";
import {
  alignmentBar,
  alignmentStepText,
  inline,
  insAligned,
  insFailed,
  insStateText,
  insStatusText,
  insWord,
  notReported,
  umaa,
} from "../../lib/labels";
import { PENDING, PENDING_TITLE, utc } from "../../lib/units";

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
  const others = useOthersEvery(); // a report from before its selection may have come at the others' pace
  const now = useNow();
  const ins = viewReport(view);
  const ageS = view ? Math.max(0, now - view.at) : null;
  const fresh = freshness(ageS, "InertialSensorReport", view?.interval ?? null, link, receiving, viewPace(view, others));
  const stale = notCurrent(fresh);
  const failed = insFailed(ins?.status);
  const bar = alignmentBar(version, ins?.status, ins?.state);
  const status = insStatusText(ins?.status, ins?.state);
  return (
    <Panel title="Inertial sensor" testId="ins-panel" freshness={fresh} ageSeconds={ageS}>
      {gap ? (
        <SelectionGap gap={gap} />
      ) : !ins ? (
        <p className="muted" data-testid="ins-none">
          {notReported(version, "InertialSensorReport") ?? "No InertialSensorReport yet."}
        </p>
      ) : (
        <>
          <SelectedLost />
          <SelectedRelay />
          <div className="badges">
            {ins.state && (
              <span
                className={`badge big${stale ? " stale" : ""}`}
                data-testid="ins-state"
                data-state={ins.state}
                title={[umaa("state", ins.state), status === null && umaa("status", ins.status)].filter(Boolean).join("; ")}
              >
                INS {inline(insStateText(ins.state))}
              </span>
            )}
            {status !== null && (
              <span
                className={`badge${ins.state ? "" : " big"}${insAligned(ins.status, version) ? " ok" : ""}${stale ? " stale" : ""}`}
                data-testid="ins-status"
                data-status={ins.status ?? ""}
                title={umaa("status", ins.status)}
              >
                {status}
              </span>
            )}
            <span className="muted" data-testid="ins-time" title={view?.brief ? PENDING_TITLE : undefined}>
              at{" "}
              {view?.brief
                ? PENDING
                : utc(ins.timeStamp ? ins.timeStamp.seconds! + (ins.timeStamp.nanoseconds ?? 0) / 1e9 : null, false)}
            </span>
          </div>
          {failed && (
            <div className="alarm" role="alert" data-testid="ins-failure">
              {insWord(ins.state, ins.status).text}: navigation cannot rely on it
            </div>
          )}
          <ol className={`steps${stale ? " stale" : ""}`} aria-label="Alignment">
            {bar.steps.map(({ step, status: literal }, i) => (
              <li
                key={step}
                className={i < bar.current ? "done" : i === bar.current ? "current" : ""}
                aria-current={i === bar.current ? "step" : undefined}
              >
                <span title={umaa("status", literal)}>{alignmentStepText(step)}</span>
              </li>
            ))}
          </ol>
          {view && view.envelope.invalid.length > 0 && <p className="invalid-note">⚠ {view.envelope.invalid.join("; ")}</p>}
        </>
      )}
    </Panel>
  );
}
