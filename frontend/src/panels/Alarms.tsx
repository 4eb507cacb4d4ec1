// The alarm list: the console's active alarm set (derived from state and kept by the server, so a new or
// reloaded page shows what is active), newest first. Each entry names its vehicle and selects it on click;
// acknowledging is an operator action the console audits.
import { useRef, useState } from "react";
import type { Alarm } from "../api/generated/ws";
import { ApiError, ackAlarm } from "../api/rest";
import { useFocusWhenGone } from "../components/focus";
import { Panel } from "../components/Panel";
import { VehicleTag } from "../components/VehicleTag";
import { useToken } from "../data/auth";
import { useAlarms, useCapabilities, useLostVehicles, useNow, useSelector, useStore } from "../data/hooks";
import { LastHeard } from "../components/LastHeard";
import { select, unacknowledged } from "../data/store";
import { ALARM_SEVERITY, ALARM_STATE } from "../lib/labels";
import { age, utc } from "../lib/units";
import { shortId } from "../lib/vehicle";
import "./fleet.css";

const SEVERITY: Record<Alarm["severity"], { text: string; tone: string }> = {
  alarm: { text: ALARM_SEVERITY.alarm, tone: "bad" },
  warning: { text: ALARM_SEVERITY.warning, tone: "warn" },
};

const STATE: Record<Alarm["state"], string> = ALARM_STATE;

/** An acknowledge that failed, in words: the console's answer, or "console unreachable" when none came. */
function failure(e: unknown): string {
  return e instanceof ApiError ? `Not acknowledged: ${e.message}` : "Not acknowledged: console unreachable";
}

/** What Acknowledge all of `n` alarms did: `gone` of them had left the active set meanwhile (acknowledged on another
 * station or page), `failed` not acknowledged (each says why in its entry). */
function allSaid(n: number, failed: number, gone: number): string {
  const alarms = (k: number) => (k === 1 ? "1 alarm" : `${k} alarms`);
  const done = alarms(n - failed - gone);
  const said = [failed ? `${done} of ${n} acknowledged` : `${done} acknowledged`];
  if (gone) said.push(`${gone} already acknowledged elsewhere`);
  if (failed) said.push(`${failed} not: see ${failed === 1 ? "its entry" : "their entries"}`);
  return `${said.join("; ")}.`;
}

export function AlarmsPanel() {
  const alarms = useAlarms();
  const store = useStore();
  const token = useToken();
  const { command } = useCapabilities(); // a replay acknowledges nothing
  const authRequired = useSelector((s) => s.authRequired);
  const mayAck = command && (!authRequired || token !== null); // acknowledging is an operator's action
  const now = useNow(1000);
  const lost = useLostVehicles(); // an alarm naming a lost vehicle says when it was last heard
  const [errors, setErrors] = useState<Record<number, string>>({});
  const [busy, setBusy] = useState(false);
  const sorted = [...alarms].sort((a, b) => b.since - a.since || b.id - a.id);
  const open = unacknowledged(alarms);
  // A keyboard operator acknowledging one alarm after another: the button pressed goes with the acknowledgement (or
  // its whole entry, back to normal), and the focus would fall to the page's top; it goes on to the next alarm. After
  // Acknowledge all (gone with the last unacknowledged alarm) it goes to the panel's title, where the list starts.
  const list = useRef<HTMLUListElement>(null);
  const title = useRef<HTMLHeadingElement>(null);
  const focus = useFocusWhenGone();
  const nextAlarm = (at: number): HTMLElement | null | undefined => {
    const entries = [...(list.current?.querySelectorAll<HTMLElement>(".alarm-entry") ?? [])];
    const next = entries.slice(at).find((e) => e.querySelector(".alarm-ack")) ?? entries[Math.min(at, entries.length - 1)];
    return next?.querySelector<HTMLElement>(".alarm-ack") ?? next?.querySelector<HTMLElement>(".alarm-main") ?? title.current;
  };
  // what Acknowledge all did, said to a screen reader (its button has gone, and the list changed under the focus)
  const [said, setSaid] = useState("");

  const ack = async (ids: number[], all = false) => {
    if (busy) return;
    setBusy(true);
    if (all) setSaid(""); // the same words again are a new announcement
    const failed: Record<number, string> = {};
    let gone = 0;
    // one at a time: the console has no "acknowledge all", and each is audited on its own
    for (const id of ids) {
      try {
        await ackAlarm(id, token);
      } catch (e) {
        // 404: no longer in the active set, so acknowledged meanwhile (another station's operator, with the same
        // alarm there): nothing failed, and its entry (where an error would be said) has gone
        if (e instanceof ApiError && e.status === 404) gone++;
        else failed[id] = failure(e);
      }
    }
    const notAcked = Object.keys(failed).length;
    if (notAcked) focus.forget(); // its button stays, and so does the focus
    if (all) setSaid(allSaid(ids.length, notAcked, gone));
    setErrors((old) => {
      const next = { ...old };
      for (const id of ids) delete next[id];
      return { ...next, ...failed };
    });
    setBusy(false);
  };

  return (
    <Panel
      title="Alarms"
      testId="alarms-panel"
      titleRef={title}
      actions={
        <>
          <span className={`alarm-count tone-${open.length ? "bad" : "muted"}`} data-testid="alarm-count">
            {open.length} unacknowledged
          </span>
          {command && !mayAck && open.length > 0 && (
            <span className="muted alarm-count" data-testid="alarm-sign-in">
              Sign in to acknowledge
            </span>
          )}
          {mayAck && open.length > 0 && (
            <button
              className="small"
              aria-disabled={busy || undefined} // not disabled: that would drop the focus of the operator pressing it
              onClick={(e) => {
                if (busy) return;
                focus.pressed(e.currentTarget, () => title.current);
                void ack(open.map((a) => a.id), true);
              }}
            >
              Acknowledge all
            </button>
          )}
        </>
      }
    >
      <p role="status" className="visually-hidden" data-testid="alarms-acknowledged">
        {said}
      </p>
      {sorted.length === 0 ? (
        <p className="muted">No active alarms.</p>
      ) : (
        <ul className="alarm-list" aria-label="Active alarms" ref={list}>
          {sorted.map((a, index) => {
            const sev = SEVERITY[a.severity];
            const acked = a.state === "active-acknowledged";
            // the vehicle by its name now (the console sends the text and `vehicle` so too, and again on a rename), else
            // the alarm's `vehicle`: its name, or its short id (then it had none)
            // the console names the vehicle as it is named now (a rename sends the alarms again): its configured name,
            // else its short id (then it has no name)
            const vehicle = a.providerId ? { id: a.providerId, name: a.vehicle && a.vehicle !== shortId(a.providerId) ? a.vehicle : null } : null;
            return (
              <li key={a.id} className={`alarm-entry alarm-${sev.tone}${acked ? " acked" : ""}`} data-testid="alarm" data-kind={a.kind} data-state={a.state}>
                <button
                  className="alarm-main"
                  onClick={() => a.providerId && store.update((s) => select(s, a.providerId))}
                  disabled={!a.providerId}
                  title={a.providerId ? "select this vehicle" : "the console's own alarm"}
                >
                  <span className="alarm-head">
                    <span className={`alarm-severity tone-${sev.tone}`}>{sev.text}</span>
                    {vehicle ? <VehicleTag v={vehicle} /> : <span className="vehicle-tag">Console</span>}
                    <span className="alarm-state" data-testid="alarm-state">
                      {STATE[a.state]}
                    </span>
                  </span>
                  <span className="alarm-text">{a.text}</span>
                  {a.providerId && lost.has(a.providerId) && <LastHeard since={lost.get(a.providerId) ?? null} className="tone-bad" />}
                  <span className="alarm-since muted">
                    since {utc(a.since, false).slice(0, 8)} UTC ({age(Math.max(0, now - a.since))} ago)
                    {a.ackedAt !== null && ` · acknowledged ${utc(a.ackedAt, false).slice(0, 8)} UTC${a.ackedBy ? ` by ${a.ackedBy}` : ""}`}
                  </span>
                </button>
                {mayAck && !acked && (
                  <button
                    className="small alarm-ack"
                    aria-disabled={busy || undefined} // not disabled: that would drop the focus of the operator pressing it
                    onClick={(e) => {
                      if (busy) return; // aria-disabled while another is acknowledged: a press does nothing, and moves no focus later
                      focus.pressed(e.currentTarget, () => nextAlarm(index));
                      void ack([a.id]);
                    }}
                    aria-label={`Acknowledge: ${a.text}`}
                  >
                    Acknowledge
                  </button>
                )}
                {errors[a.id] && (
                  <p className="error alarm-error" role="alert">
                    {errors[a.id]}
                  </p>
                )}
              </li>
            );
          })}
        </ul>
      )}
    </Panel>
  );
}
