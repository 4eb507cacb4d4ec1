// The alarm list: the console's active alarm set (derived from state and kept by the server, so a new or
// reloaded page shows what is active), newest first. Each entry names its vehicle and selects it on click;
// acknowledging, shelving and a vehicle's planned silence are operator actions the console audits. Many alarms of
// one cause at once (a flood) are one group, expandable; shelved alarms are counted apart, listed on demand.
import { useRef, useState, type ReactNode } from "react";
import type { Alarm } from "../../api/generated/ws";
import { ApiError, ackAlarm, shelveAlarm, unshelveAlarm } from "../../api/rest";
import { useFocusWhenGone } from "../../components/focus";
import { Panel } from "../../components/Panel";
import { VehicleTag } from "../../components/VehicleTag";
import { useToken } from "../../data/auth";
import { useAlarms, useCapabilities, useConsoleNow, useLostVehicles, useSelector, useSelectVehicle } from "../../data/hooks";
import { LastHeard } from "../../components/LastHeard";
import { FLOOD_AT, inView, unacknowledged } from "../../data/slices/alarms";
import {
  ALARM_MARK,
  ALARM_SEVERITY,
  ALARM_STATE,
  CHATTERING_TITLE,
  floodText,
  shelvedCount,
  shelvedText,
} from "../../lib/labels";
import { age, utc } from "../../lib/units";
import { shortId } from "../../lib/vehicle";
import { PlannedSilences } from "../PlannedSilences/PlannedSilences";
import "../fleet.css";

const SEVERITY: Record<Alarm["severity"], { text: string; tone: string }> = {
  alarm: { text: ALARM_SEVERITY.alarm, tone: "bad" },
  warning: { text: ALARM_SEVERITY.warning, tone: "warn" },
};

const STATE: Record<Alarm["state"], string> = ALARM_STATE;

/** The shelving times offered (minutes); the console refuses one outside its bounds (15 min to 8 h by default). */
const SHELVE_MINUTES: readonly { minutes: number; text: string }[] = [
  { minutes: 15, text: "15 min" },
  { minutes: 30, text: "30 min" },
  { minutes: 60, text: "1 h" },
  { minutes: 120, text: "2 h" },
  { minutes: 240, text: "4 h" },
  { minutes: 480, text: "8 h" },
];

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
  const selectVehicle = useSelectVehicle();
  const token = useToken();
  const { command } = useCapabilities(); // a replay acknowledges nothing
  const authRequired = useSelector((s) => s.authRequired);
  const mayAck = command && (!authRequired || token !== null); // acknowledging is an operator's action
  const now = useConsoleNow(1000);
  const lost = useLostVehicles(); // an alarm naming a lost vehicle says when it was last heard
  const [errors, setErrors] = useState<Record<number, string>>({});
  const [busy, setBusy] = useState(false);
  // newest first; of one instant, in the console's order (the last raised first: an id says nothing of it)
  const all = [...alarms].sort((a, b) => b.since - a.since);
  const sorted = inView(all);
  const onShelf = all.filter((a) => a.shelf);
  const open = unacknowledged(alarms);
  const [showShelved, setShowShelved] = useState(false);
  const [expanded, setExpanded] = useState<Record<string, boolean>>({});
  const [shelving, setShelving] = useState<number | null>(null); // the alarm whose shelve form is open
  // a flood: the causes with many alarms in view, each shown as one group
  const perCause = new Map<string, Alarm[]>();
  for (const a of sorted) {
    const same = perCause.get(a.cause);
    if (same) same.push(a);
    else perCause.set(a.cause, [a]);
  }
  const flooded = (a: Alarm) => (perCause.get(a.cause)?.length ?? 0) >= FLOOD_AT;
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

  /** Shelve or unshelve (one alarm): its error said in its entry, as an acknowledgement's. */
  const act = async (id: number, call: () => Promise<unknown>, what: string) => {
    if (busy) return;
    setBusy(true);
    try {
      await call();
      setErrors((old) => Object.fromEntries(Object.entries(old).filter(([k]) => Number(k) !== id)));
      setShelving(null);
    } catch (e) {
      setErrors((old) => ({ ...old, [id]: `${what}: ${e instanceof ApiError && e.status ? e.message : "console unreachable"}` }));
    }
    setBusy(false);
  };

  const entry = (a: Alarm, index: number): ReactNode => {
    const sev = SEVERITY[a.severity];
    const acked = a.state === "active-acknowledged";
    // the console names the vehicle as it is named now (a rename sends the alarms again): its configured name,
    // else its short id (then it has no name)
    const vehicle = a.providerId
      ? { id: a.providerId, name: a.vehicle && a.vehicle !== shortId(a.providerId) ? a.vehicle : null }
      : null;
    return (
      <li
        key={a.id}
        className={`alarm-entry alarm-${sev.tone}${acked ? " acked" : ""}`}
        data-testid="alarm"
        data-kind={a.kind}
        data-state={a.state}
      >
        <button
          className="alarm-main"
          onClick={() => a.providerId && selectVehicle(a.providerId)}
          disabled={!a.providerId}
          title={a.providerId ? "select this vehicle" : "the console's own alarm"}
        >
          <span className="alarm-head">
            <span className={`alarm-severity tone-${sev.tone}`}>{sev.text}</span>
            {vehicle ? <VehicleTag v={vehicle} /> : <span className="vehicle-tag">Console</span>}
            <span className="alarm-state" data-testid="alarm-state">
              {STATE[a.state]}
            </span>
            {a.chattering && (
              <span className="alarm-state tone-warn" title={CHATTERING_TITLE} data-testid="alarm-chattering">
                {ALARM_MARK.chattering}
              </span>
            )}
          </span>
          <span className="alarm-text">{a.text}</span>
          {a.providerId && lost.has(a.providerId) && <LastHeard since={lost.get(a.providerId) ?? null} className="tone-bad" />}
          <span className="alarm-since muted">
            since {utc(a.since, false, "s")} ({age(Math.max(0, now - a.since))} ago)
            {a.ackedAt !== null && ` · acknowledged ${utc(a.ackedAt, false, "s")}${a.ackedBy ? ` by ${a.ackedBy}` : ""}`}
          </span>
          {a.returned && (
            <span className="alarm-since" data-testid="alarm-returned">
              {a.returned}
            </span>
          )}
        </button>
        {mayAck && (
          <span className="alarm-actions">
            {!acked && (
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
            <button
              className="small"
              aria-expanded={shelving === a.id}
              onClick={() => setShelving(shelving === a.id ? null : a.id)}
              aria-label={`Shelve: ${a.text}`}
            >
              Shelve
            </button>
          </span>
        )}
        {shelving === a.id && (
          <ShelveForm
            alarm={a}
            busy={busy}
            onShelve={(reason, minutes) => void act(a.id, () => shelveAlarm(a.id, reason, minutes, token), "Not shelved")}
            onCancel={() => setShelving(null)}
          />
        )}
        {errors[a.id] && (
          <p className="error alarm-error" role="alert">
            {errors[a.id]}
          </p>
        )}
      </li>
    );
  };

  // the list in view: each alarm, but a flooded cause as one group at the place of its newest alarm
  const rows: ReactNode[] = [];
  const grouped = new Set<string>();
  sorted.forEach((a, index) => {
    if (!flooded(a)) {
      rows.push(entry(a, index));
      return;
    }
    if (grouped.has(a.cause)) return;
    grouped.add(a.cause);
    const members = perCause.get(a.cause) ?? [];
    const worst = members.some((m) => m.severity === "alarm") ? SEVERITY.alarm : SEVERITY.warning;
    const unacked = unacknowledged(members).length;
    const isOpen = expanded[a.cause] ?? false;
    rows.push(
      <li
        key={`group-${a.cause}`}
        className={`alarm-entry alarm-group alarm-${worst.tone}`}
        data-testid="alarm-group"
        data-cause={a.cause}
      >
        <span className="alarm-head">
          <span className={`alarm-severity tone-${worst.tone}`}>{worst.text}</span>
          <span className="alarm-text" data-testid="alarm-group-title">
            {floodText(a.cause, members)}
          </span>
          <span className="alarm-state">{unacked} unacknowledged</span>
        </span>
        <span className="alarm-actions">
          <button className="small" aria-expanded={isOpen} onClick={() => setExpanded({ ...expanded, [a.cause]: !isOpen })}>
            {isOpen ? "Hide each" : "Show each"}
          </button>
          {mayAck && unacked > 0 && (
            <button
              className="small"
              aria-disabled={busy || undefined}
              onClick={() =>
                !busy &&
                void ack(
                  unacknowledged(members).map((m) => m.id),
                  true,
                )
              }
            >
              Acknowledge these {unacked}
            </button>
          )}
        </span>
        {isOpen && (
          <ul className="alarm-list alarm-members" aria-label={floodText(a.cause, members)}>
            {members.map((m) => entry(m, sorted.indexOf(m)))}
          </ul>
        )}
      </li>,
    );
  });

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
                void ack(
                  open.map((a) => a.id),
                  true,
                );
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
        <p className="muted">{onShelf.length ? "No alarm in view." : "No active alarms."}</p>
      ) : (
        <ul className="alarm-list" aria-label="Active alarms" ref={list}>
          {rows}
        </ul>
      )}
      {onShelf.length > 0 && (
        <div className="alarm-shelved">
          <button
            className="small"
            aria-expanded={showShelved}
            onClick={() => setShowShelved(!showShelved)}
            data-testid="alarms-shelved"
          >
            {shelvedCount(onShelf.length)}
          </button>
          {showShelved && (
            <ul className="alarm-list" aria-label="Shelved alarms">
              {onShelf.map((a) => (
                <li key={a.id} className="alarm-entry" data-testid="shelved-alarm" data-kind={a.kind}>
                  <span className="alarm-text">{a.text}</span>
                  {a.shelf && (
                    <span className="alarm-since muted" data-testid="shelf-words">
                      {shelvedText(a.shelf.by, a.shelf.station, a.shelf.until, a.shelf.reason)}
                    </span>
                  )}
                  {mayAck && (
                    <button
                      className="small"
                      aria-disabled={busy || undefined}
                      onClick={() => void act(a.id, () => unshelveAlarm(a.id, token), "Not unshelved")}
                      aria-label={`Unshelve: ${a.text}`}
                    >
                      Unshelve
                    </button>
                  )}
                  {errors[a.id] && (
                    <p className="error alarm-error" role="alert">
                      {errors[a.id]}
                    </p>
                  )}
                </li>
              ))}
            </ul>
          )}
        </div>
      )}
      <PlannedSilences mayAct={mayAck} token={token} />
    </Panel>
  );
}

/** Shelve one alarm: a reason (required) and a time among the offered ones. */
function ShelveForm({
  alarm,
  busy,
  onShelve,
  onCancel,
}: {
  alarm: Alarm;
  busy: boolean;
  onShelve: (reason: string, minutes: number) => void;
  onCancel: () => void;
}) {
  const [reason, setReason] = useState("");
  const [minutes, setMinutes] = useState(60);
  return (
    <form
      className="alarm-form"
      aria-label={`Shelve: ${alarm.text}`}
      onSubmit={(e) => {
        e.preventDefault();
        if (!busy && reason.trim()) onShelve(reason.trim(), minutes);
      }}
    >
      <label>
        Why shelve it
        <input value={reason} onChange={(e) => setReason(e.target.value)} maxLength={200} required />
      </label>
      <label>
        For
        <select value={minutes} onChange={(e) => setMinutes(Number(e.target.value))}>
          {SHELVE_MINUTES.map((o) => (
            <option key={o.minutes} value={o.minutes}>
              {o.text}
            </option>
          ))}
        </select>
      </label>
      <button className="small" type="submit" aria-disabled={busy || !reason.trim() || undefined}>
        Shelve alarm
      </button>
      <button className="small" type="button" onClick={onCancel}>
        Cancel
      </button>
    </form>
  );
}
