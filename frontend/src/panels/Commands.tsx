import { useMemo, useState } from "react";
import { ApiError, cancelCommand, commandPage, requestGpsFix, setInertialSensor } from "../api/rest";
import type { Command } from "../api/types";
import { Panel } from "../components/Panel";
import { VehicleTag } from "../components/VehicleTag";
import { useToken } from "../data/auth";
import { useCapabilities, useCommands, useSelectedVehicle, useSelector } from "../data/hooks";
import { mergeCommands } from "../lib/commands";
import { utc } from "../lib/units";
import { vehicleLabel, type VehicleIdentity } from "../lib/vehicle";

type Action = { label: string; confirm: string | null; run: (provider: string, token: string | null) => Promise<Command> };

const ACTIONS: Action[] = [
  { label: "Request GPS fix", confirm: null, run: (p, t) => requestGpsFix(p, t) },
  { label: "INS ON", confirm: null, run: (p, t) => setInertialSensor(p, "ON", t) },
  { label: "INS OFF", confirm: "Switch its inertial sensor OFF? Navigation falls back to GPS only.", run: (p, t) => setInertialSensor(p, "OFF", t) },
  { label: "INS RESTART", confirm: "Restart its inertial sensor? It must align again before it is OPERATIONAL.", run: (p, t) => setInertialSensor(p, "RESTARTING", t) },
];

/** A confirmation is bound to the vehicle it was prepared for. */
type Pending = { action: Action; target: VehicleIdentity };

function title(c: Command): string {
  return c.service === "GPSFix" ? "GPS fix" : `INS ${c.state ?? ""}`;
}

function statusClass(c: Command): string {
  if (c.violations.length || c.unanswered) return "alarm";
  if (c.status === "FAILED") return "bad";
  if (c.status === "COMPLETED") return "ok";
  if (c.status === "CANCELED") return "muted";
  return "active";
}

function Timeline({ c }: { c: Command }) {
  return (
    <ol className="timeline" data-testid="timeline" aria-label={`Timeline of ${title(c)}`}>
      <li className="muted">
        <span className="t-status">REQUESTED</span> <span className="t-time">{utc(c.createdAt, false)}</span>
        {c.operator ? <span> by {c.operator}</span> : null}
      </li>
      {c.ackedAt !== null && (
        <li className="muted" data-testid="ack">
          <span className="t-status">ACK</span> provider reports executing it <span className="t-time">{utc(c.ackedAt, false)}</span>
        </li>
      )}
      {c.transitions.map((t) => (
        <li key={t.seq} className={t.violation ? "violation" : ""} data-testid="transition" data-status={t.status}>
          <span className="t-status">{t.status}</span> <span className="t-reason">{t.reason}</span> <span className="t-time">{utc(t.receivedAt, false)}</span>
          {t.logMessage && <span className="t-log">“{t.logMessage}”</span>}
          {t.violation && (
            <strong className="t-violation" role="alert" data-testid="violation">
              UMAA flow violation: {t.violation}
            </strong>
          )}
        </li>
      ))}
      {c.unanswered && (
        <li className="violation" role="alert" data-testid="unanswered">
          <strong>Unanswered: the provider has not acknowledged this command (no ISSUED)</strong>
        </li>
      )}
      {c.cancelRequested && !c.terminal && <li className="muted">cancel requested{c.canceledBy ? ` by ${c.canceledBy}` : ""}…</li>}
    </ol>
  );
}

function CommandCard({ c, target, canCommand, onCancel, open }: { c: Command; target: VehicleIdentity; canCommand: boolean; onCancel: (c: Command) => void; open: boolean }) {
  return (
    <details className={`command ${statusClass(c)}`} open={open} data-testid="command" data-session={c.sessionId} data-status={c.status ?? "none"}>
      <summary>
        <span className="c-title">{title(c)}</span>
        <span className="c-status" data-testid="command-status">{c.unanswered ? "UNANSWERED" : (c.status ?? "sent")}</span>
        {c.violations.length > 0 && <span className="c-flag" data-testid="command-violation">⚠ violation</span>}
        <span className="c-time muted">{utc(c.createdAt, false)}</span>
        {!c.terminal && !c.cancelRequested && (
          <button className="small danger" disabled={!canCommand} title={`Cancel ${title(c)} on ${vehicleLabel(target)}`} onClick={(e) => (e.preventDefault(), onCancel(c))}>
            Cancel
          </button>
        )}
      </summary>
      <Timeline c={c} />
      <p className="muted c-session">session {c.sessionId}</p>
    </details>
  );
}

const PAGE = 20; // commands shown per page
const FETCH = 100; // commands asked of the console per request

/** The selected vehicle's commands, newest first: the live ones, then older pages from the console's
 * history (GET /api/commands) on demand. Keyed by the vehicle, so its pages never show beside another. */
function CommandList({ target, live, canCommand, onCancel }: { target: VehicleIdentity; live: Command[]; canCommand: boolean; onCancel: (c: Command) => void }) {
  const token = useToken();
  const [older, setOlder] = useState<Command[]>([]);
  const [fetched, setFetched] = useState(0); // rows of the history read so far (from the newest)
  const [done, setDone] = useState(false); // the history has nothing beyond them
  const [visible, setVisible] = useState(PAGE);
  const [loading, setLoading] = useState(false);
  const [error, setError] = useState<string | null>(null);
  const all = useMemo(() => mergeCommands(live, older), [live, older]);
  const shown = all.filter((c, i) => i < visible || !c.terminal); // running commands always

  const showOlder = async () => {
    const want = visible + PAGE;
    setError(null);
    if (all.length >= want || done) {
      setVisible(want);
      return;
    }
    setLoading(true);
    let got = older, offset = fetched, end = false;
    try {
      while (mergeCommands(live, got).length < want && !end) {
        const page = await commandPage(target.id, FETCH, offset, token);
        got = [...got, ...page];
        offset += page.length;
        end = page.length < FETCH;
      }
      setVisible(want);
    } catch (e) {
      setError(`Older commands of ${vehicleLabel(target)}: ${e instanceof ApiError ? `${e.status}: ${e.message}` : String(e)}`);
    } finally {
      setOlder(got);
      setFetched(offset);
      setDone(end);
      setLoading(false);
    }
  };

  return (
    <>
      <div className="command-list" data-testid="command-list">
        {all.length === 0 && <p className="muted">No commands sent to this vehicle.</p>}
        {shown.map((c, i) => (
          <CommandCard key={c.sessionId} c={c} target={target} canCommand={canCommand} open={i < 3 || !c.terminal} onCancel={onCancel} />
        ))}
      </div>
      {(all.length > 0 || older.length > 0) && (
        <div className="pager" data-testid="command-pager">
          <span className="muted" data-testid="command-count">
            {shown.length} of {done ? all.length : `${all.length}+`} commands
          </span>
          <button className="small" onClick={() => void showOlder()} disabled={loading || (done && shown.length >= all.length)}>
            {loading ? "Loading…" : "Older commands"}
          </button>
        </div>
      )}
      {error && (
        <p className="error" role="alert">
          {error}
        </p>
      )}
    </>
  );
}

export function CommandsPanel() {
  const selected = useSelector((s) => s.selected);
  const known = useSelectedVehicle();
  const target: VehicleIdentity | null = selected ? { id: selected, name: known?.name ?? null } : null;
  const commands = useCommands(selected);
  const authRequired = useSelector((s) => s.authRequired);
  const token = useToken();
  const { command: mayCommand } = useCapabilities();
  const [pending, setPending] = useState<Pending | null>(null);
  const [error, setError] = useState<string | null>(null);
  const [note, setNote] = useState<string | null>(null);
  const canCommand = mayCommand && !!known && (!authRequired || !!token);

  // Another vehicle selected: a confirmation prepared for the previous one is void (adjusted while
  // rendering, so no frame ever shows it beside the new vehicle).
  if (pending !== null && pending.target.id !== selected) {
    setNote(`${pending.action.label} for ${vehicleLabel(pending.target)} not sent: the selected vehicle changed.`);
    setPending(null);
  }

  const run = async (target: VehicleIdentity, what: string, fn: () => Promise<Command>) => {
    setError(null);
    setNote(null);
    try {
      await fn();
    } catch (e) {
      setError(`${what} on ${vehicleLabel(target)}: ${e instanceof ApiError ? `${e.status}: ${e.message}` : String(e)}`);
    }
  };
  const act = (a: Action, t: VehicleIdentity) => {
    setNote(null);
    if (a.confirm) setPending({ action: a, target: t });
    else void run(t, a.label, () => a.run(t.id, token));
  };
  const shown = pending !== null && pending.target.id === selected ? pending : null;

  return (
    <Panel title="Commands" testId="commands-panel">
      {!mayCommand && <p className="readonly-note" data-testid="commands-replay">Replay: read-only. Commands are not sent.</p>}
      {mayCommand && authRequired && !token && <p className="readonly-note" data-testid="commands-read-only">Read-only: sign in with an operator token to command vehicles.</p>}
      {target ? (
        <p className="command-target" data-testid="command-target">
          Commands to <VehicleTag v={target} />
          {!known && <span className="muted">not on the bus (yet)</span>}
        </p>
      ) : (
        <p className="muted" data-testid="command-target">Select a vehicle to command it.</p>
      )}
      <div className="actions" role="group" aria-label={target ? `Commands to ${vehicleLabel(target)}` : "Command actions"}>
        {ACTIONS.map((a) => (
          <button key={a.label} disabled={!canCommand || !target} title={target ? `${a.label} on ${vehicleLabel(target)}` : undefined} onClick={() => target && act(a, target)}>
            {a.label}
          </button>
        ))}
      </div>
      {error && (
        <p className="error" role="alert" data-testid="command-error">
          {error}
        </p>
      )}
      {note && (
        <p className="muted" role="status" data-testid="command-note">
          {note}
        </p>
      )}
      {shown && (
        <div className="confirm" role="dialog" aria-modal="true" aria-label="Confirm command" data-vehicle={shown.target.id}>
          <p>
            <strong>{shown.action.label}</strong> on <VehicleTag v={shown.target} />
          </p>
          <p>{shown.action.confirm}</p>
          <button
            className="danger"
            onClick={() => {
              const { action, target: to } = shown;
              setPending(null);
              void run(to, action.label, () => action.run(to.id, token)); // the vehicle it was prepared for
            }}
          >
            Confirm
          </button>
          <button onClick={() => setPending(null)}>Keep as is</button>
        </div>
      )}
      {target && (
        <CommandList
          key={target.id}
          target={target}
          live={commands}
          canCommand={canCommand}
          onCancel={(x) => void run(target, `Cancel ${title(x)}`, () => cancelCommand(x.sessionId, token))}
        />
      )}
    </Panel>
  );
}
