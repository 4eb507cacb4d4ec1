import type { ReactNode, Ref } from "react";
import { ErrorBoundary } from "./ErrorBoundary";
import type { Topic } from "../api/types";
import { RECORDED_TITLE, freshness, freshnessText, recordedState, type Freshness } from "../lib/freshness";
import { useCapabilities, useFrameValue, useNow, useReceiving, useSelectedLink, useOthersEvery } from "../data/hooks";
import { selectedTopic, viewPace, type TopicView } from "../data/slices/vehicles";
import { type State } from "../data/state";
import { DASH, PENDING, PENDING_TITLE, age } from "../lib/units";
import { useCollapsed } from "../data/settings";
import { DragHandle, MoveButtons } from "./Arrange";
import { countRender } from "../lib/renders";
import { LostBadge } from "./LastHeard";

interface Props {
  title: string;
  testId: string;
  freshness?: Freshness;
  ageSeconds?: number | null;
  actions?: ReactNode;
  children: ReactNode;
  className?: string;
  /** the title, focusable by script (tabIndex -1, not a Tab stop): where the focus goes when what had it went away */
  titleRef?: Ref<HTMLHeadingElement>;
}

/** A titled panel; the operator can collapse it to its title bar (remembered across reloads, per panel),
 * and, in an arrangeable group, move it by its ⠿ handle or ↑ ↓ buttons.
 * A collapsed panel's content is not rendered, so it costs nothing while folded. */
export function Panel({ title, testId, freshness, ageSeconds, actions, children, className, titleRef }: Props) {
  countRender(testId);
  const [collapsed, setCollapsed] = useCollapsed(testId);
  const recorded = useCapabilities().playback; // a replay: the recording's freshness, not the vehicle's now
  return (
    <section className={`panel ${className ?? ""}${collapsed ? " collapsed" : ""}`} data-testid={testId} aria-label={title}>
      <header className="panel-head">
        <DragHandle title={title} testId={testId} />
        <button
          className="collapse"
          aria-expanded={!collapsed}
          aria-label={`${collapsed ? "Expand" : "Collapse"} ${title}`}
          title={collapsed ? "expand" : "collapse to the title"}
          onClick={() => setCollapsed(!collapsed)}
          data-testid={`${testId}-collapse`}
        >
          {collapsed ? "▸" : "▾"}
        </button>
        <h2 ref={titleRef} tabIndex={titleRef ? -1 : undefined}>
          {title}
        </h2>
        {freshness && freshness !== "none" && (
          <span
            className={`fresh fresh-${freshness}${recordedState(freshness, recorded) ? " recorded" : ""}`}
            data-testid={`${testId}-freshness`}
            title={
              recordedState(freshness, recorded)
                ? `age of the latest data: ${RECORDED_TITLE}`
                : freshness === "unreachable"
                  ? "the console cannot be reached: the latest data, not updating"
                  : freshness === "lost"
                    ? "time since the vehicle was last heard (its newest report of any topic)"
                    : "age of the latest data"
            }
          >
            {freshness === "lost" ? (
              <LostBadge recorded={recorded} />
            ) : (
              `${freshnessText(freshness, recorded)} · ${age(ageSeconds ?? null)}`
            )}
          </span>
        )}
        {!collapsed && actions}
        <MoveButtons title={title} testId={testId} />
      </header>
      {!collapsed && <ErrorBoundary name={title}>{children}</ErrorBoundary>}
    </section>
  );
}

/** A panel whose body (`children`, the component that subscribes to what the panel draws) exists only while the
 * panel is open: collapsed, it does not draw `children`'s reports, only its title bar with the freshness and age of
 * the selected vehicle's `topic` (so a folded panel still says its data went stale or lost). */
export function Foldable({
  title,
  testId,
  topic,
  className,
  children,
}: {
  title: string;
  testId: string;
  topic: Topic;
  className?: string;
  children: ReactNode;
}) {
  const [collapsed] = useCollapsed(testId);
  return collapsed ? <Folded title={title} testId={testId} topic={topic} className={className} /> : children;
}

/** Two views of a topic alike for a folded title bar: both none, or last heard of in the same second (the clock of
 * ages redraws it twice a second with the newest view; a report changes it at most once a second). */
const sameSecond = (a: TopicView | null, b: TopicView | null): boolean =>
  a === b || (a !== null && b !== null && Math.floor(a.at) === Math.floor(b.at));

function Folded({ title, testId, topic, className }: { title: string; testId: string; topic: Topic; className?: string }) {
  const view = useFrameValue(selectedTopic(topic) as (s: State) => TopicView | null, sameSecond);
  const link = useSelectedLink();
  const receiving = useReceiving();
  const others = useOthersEvery(); // a report from before its selection may have come at the others' pace
  const now = useNow();
  const ageS = view ? Math.max(0, now - view.at) : null;
  return (
    <Panel
      title={title}
      testId={testId}
      className={className}
      freshness={freshness(ageS, topic, view?.interval ?? null, link, receiving, viewPace(view, others))}
      ageSeconds={ageS}
    >
      {null}
    </Panel>
  );
}

interface FieldProps {
  label: string;
  value: string;
  stale?: boolean;
  invalid?: string | null;
  testId?: string;
  // its report was built from the vehicle's brief, which lacks this value (TopicView.brief): no value yet is "…", not
  // the dash that says the vehicle gives none
  pending?: boolean;
}

/** A labelled value; stale values are dimmed and marked, invalid ones flagged with the reason, and one not known yet
 * (`pending`) shown as loading. */
export function Field({ label, value, stale, invalid, testId, pending }: FieldProps) {
  const loading = pending === true && value === DASH;
  return (
    <div
      className={`field${stale ? " stale" : ""}${invalid ? " invalid" : ""}`}
      title={invalid ?? (stale ? "stale: no fresh data" : undefined)}
    >
      <span className="label">{label}</span>
      <span className={`value${loading ? " muted" : ""}`} data-testid={testId} title={loading ? PENDING_TITLE : undefined}>
        {loading ? PENDING : value}
        {invalid ? " ⚠" : ""}
      </span>
    </div>
  );
}

/** The invalid-reason for a member path (as the backend lists them), if any. */
export function invalidFor(invalid: string[] | undefined, path: string): string | null {
  return invalid?.find((x) => x.startsWith(`${path}:`) || x.startsWith(`${path}.`)) ?? null;
}
