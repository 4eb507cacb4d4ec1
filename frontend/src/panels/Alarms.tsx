// The alarm list: the console's active alarm set (derived from state and kept by the server, so a new or
// reloaded page shows what is active), newest first. Each entry names its vehicle and selects it on click;
// acknowledging is an operator action the console audits.
import { useEffect, useRef, useState } from "react";
import type { Alarm } from "../api/generated/ws";
import { ApiError, ackAlarm } from "../api/rest";
import { Panel } from "../components/Panel";
import { VehicleTag } from "../components/VehicleTag";
import { useToken } from "../data/auth";
import { useAlarms, useCapabilities, useNow, useSelector, useStore, useVehicleNames } from "../data/hooks";
import { select, unacknowledged } from "../data/store";
import { age, utc } from "../lib/units";
import { shortId } from "../lib/vehicle";
import "./fleet.css";

const SEVERITY: Record<Alarm["severity"], { text: string; tone: string }> = {
  alarm: { text: "Alarm", tone: "bad" },
  warning: { text: "Warning", tone: "warn" },
};

const STATE: Record<Alarm["state"], string> = {
  "active-unacknowledged": "Unacknowledged",
  "active-acknowledged": "Acknowledged",
  "cleared-unacknowledged": "Cleared, unacknowledged",
};

/** An acknowledge that failed, in words: the console's answer, or "console unreachable" when none came. */
function failure(e: unknown): string {
  return e instanceof ApiError ? `Not acknowledged: ${e.message}` : "Not acknowledged: console unreachable";
}

export function AlarmsPanel() {
  const alarms = useAlarms();
  const names = useVehicleNames();
  const store = useStore();
  const token = useToken();
  const { command } = useCapabilities(); // a replay acknowledges nothing
  const authRequired = useSelector((s) => s.authRequired);
  const mayAck = command && (!authRequired || token !== null); // acknowledging is an operator's action
  const now = useNow(1000);
  const [errors, setErrors] = useState<Record<number, string>>({});
  const [busy, setBusy] = useState(false);
  const sorted = [...alarms].sort((a, b) => b.since - a.since || b.id - a.id);
  const open = unacknowledged(alarms);
  // A keyboard operator acknowledging one alarm after another: the button pressed goes with the acknowledgement (or
  // its whole entry, back to normal), and the focus would fall to the page's top; it goes on to the next alarm.
  const list = useRef<HTMLUListElement>(null);
  // the place in the list of the Acknowledge pressed, and the button: only its going takes the focus on, once; the
  // operator's focus anywhere else (or later dropped by anything else) is never taken
  const focusAfter = useRef<{ at: number; button: HTMLElement } | null>(null);
  useEffect(() => {
    const pressed = focusAfter.current;
    if (pressed === null) return;
    if (pressed.button.isConnected) {
      if (document.activeElement !== pressed.button) focusAfter.current = null; // the operator moved on meanwhile
      return;
    }
    focusAfter.current = null;
    const active = document.activeElement;
    if (active !== null && active !== document.body) return; // the focus went somewhere already
    const at = pressed.at;
    const entries = [...(list.current?.querySelectorAll<HTMLElement>(".alarm-entry") ?? [])];
    const next = entries.slice(at).find((e) => e.querySelector(".alarm-ack")) ?? entries[Math.min(at, entries.length - 1)];
    (next?.querySelector<HTMLElement>(".alarm-ack") ?? next?.querySelector<HTMLElement>(".alarm-main"))?.focus();
  });

  const ack = async (ids: number[]) => {
    if (busy) return;
    setBusy(true);
    const failed: Record<number, string> = {};
    // one at a time: the console has no "acknowledge all", and each is audited on its own
    for (const id of ids) {
      try {
        await ackAlarm(id, token);
      } catch (e) {
        failed[id] = failure(e);
      }
    }
    if (Object.keys(failed).length) focusAfter.current = null; // its button stays, and so does the focus
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
            <button className="small" disabled={busy} onClick={() => void ack(open.map((a) => a.id))}>
              Acknowledge all
            </button>
          )}
        </>
      }
    >
      {sorted.length === 0 ? (
        <p className="muted">No active alarms.</p>
      ) : (
        <ul className="alarm-list" aria-label="Active alarms" ref={list}>
          {sorted.map((a, index) => {
            const sev = SEVERITY[a.severity];
            const acked = a.state === "active-acknowledged";
            // the vehicle by its name now (renamed since, the alarm's own text keeps the name it had), else the name the
            // console gave it when raised: its configured name, or its short id (then it had none)
            const raisedAs = a.vehicle && a.providerId && a.vehicle !== shortId(a.providerId) ? a.vehicle : null;
            const current = a.providerId ? names.get(a.providerId) : undefined; // "": known, with no name now
            const vehicle = a.providerId ? { id: a.providerId, name: current === undefined ? raisedAs : current || null } : null;
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
                      focusAfter.current = { at: index, button: e.currentTarget };
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
