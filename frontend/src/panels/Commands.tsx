import { useState } from "react";
import { ApiError, cancelCommand, requestGpsFix, setInertialSensor } from "../api/rest";
import type { Command } from "../api/types";
import { Panel } from "../components/Panel";
import { useToken } from "../data/auth";
import { useCommands, useSelectedProvider, useSelector } from "../data/hooks";
import { utc } from "../lib/units";

type Action = { label: string; confirm: string | null; run: (provider: string, token: string | null) => Promise<Command> };

const ACTIONS: Action[] = [
  { label: "Request GPS fix", confirm: null, run: (p, t) => requestGpsFix(p, t) },
  { label: "INS ON", confirm: null, run: (p, t) => setInertialSensor(p, "ON", t) },
  { label: "INS OFF", confirm: "Switch the inertial sensor OFF? Navigation falls back to GPS only.", run: (p, t) => setInertialSensor(p, "OFF", t) },
  { label: "INS RESTART", confirm: "Restart the inertial sensor? It must align again before it is OPERATIONAL.", run: (p, t) => setInertialSensor(p, "RESTARTING", t) },
];

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

function CommandCard({ c, canCommand, onCancel, open }: { c: Command; canCommand: boolean; onCancel: (c: Command) => void; open: boolean }) {
  return (
    <details className={`command ${statusClass(c)}`} open={open} data-testid="command" data-session={c.sessionId} data-status={c.status ?? "none"}>
      <summary>
        <span className="c-title">{title(c)}</span>
        <span className="c-status" data-testid="command-status">{c.unanswered ? "UNANSWERED" : (c.status ?? "sent")}</span>
        {c.violations.length > 0 && <span className="c-flag" data-testid="command-violation">⚠ violation</span>}
        <span className="c-time muted">{utc(c.createdAt, false)}</span>
        {!c.terminal && !c.cancelRequested && (
          <button className="small danger" disabled={!canCommand} onClick={(e) => (e.preventDefault(), onCancel(c))}>
            Cancel
          </button>
        )}
      </summary>
      <Timeline c={c} />
      <p className="muted c-session">session {c.sessionId}</p>
    </details>
  );
}

export function CommandsPanel() {
  const p = useSelectedProvider();
  const commands = useCommands(p?.id ?? null);
  const authRequired = useSelector((s) => s.authRequired);
  const token = useToken();
  const [pending, setPending] = useState<Action | null>(null);
  const [error, setError] = useState<string | null>(null);
  const canCommand = !!p && (!authRequired || !!token);

  const run = async (fn: () => Promise<Command>) => {
    setError(null);
    try {
      await fn();
    } catch (e) {
      setError(e instanceof ApiError ? `${e.status}: ${e.message}` : String(e));
    }
  };
  const act = (a: Action) => (a.confirm ? setPending(a) : void run(() => a.run(p!.id, token)));

  return (
    <Panel title="Commands" testId="commands-panel">
      {authRequired && !token && <p className="readonly-note" data-testid="commands-read-only">Read-only: sign in with an operator token to command vehicles.</p>}
      <div className="actions" role="group" aria-label="Command actions">
        {ACTIONS.map((a) => (
          <button key={a.label} disabled={!canCommand} onClick={() => act(a)}>
            {a.label}
          </button>
        ))}
      </div>
      {error && (
        <p className="error" role="alert" data-testid="command-error">
          {error}
        </p>
      )}
      {pending && (
        <div className="confirm" role="dialog" aria-modal="true" aria-label="Confirm command">
          <p>{pending.confirm}</p>
          <button
            className="danger"
            onClick={() => {
              const a = pending;
              setPending(null);
              void run(() => a.run(p!.id, token));
            }}
          >
            Confirm
          </button>
          <button onClick={() => setPending(null)}>Keep as is</button>
        </div>
      )}
      <div className="command-list" data-testid="command-list">
        {commands.length === 0 && <p className="muted">No commands sent to this vehicle.</p>}
        {commands.map((c, i) => (
          <CommandCard key={c.sessionId} c={c} canCommand={canCommand} open={i < 3 || !c.terminal} onCancel={(x) => void run(() => cancelCommand(x.sessionId, token))} />
        ))}
      </div>
    </Panel>
  );
}
