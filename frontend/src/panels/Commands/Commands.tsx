import { useEffect, useMemo, useRef, useState, type ReactNode } from "react";
import { UNREACHABLE, cancelCommand, commandPage, problemText, requestGpsFix, setInertialSensor } from "../../api/rest";
import type { Command } from "../../api/types";
import { Confirm } from "../../components/Confirm";
import { useFocusWhenGone } from "../../components/focus";
import { Panel } from "../../components/Panel";
import { VehicleTag } from "../../components/VehicleTag";
import { useToken } from "../../data/auth";
import {
  useCapabilities,
  useCommands,
  useConnectionState,
  useConsoleNow,
  useNow,
  useSelectedUmaaVersion,
  useSelectedVehicle,
  useSelector,
} from "../../data/hooks";
import { selectedLostSince, selectedPlannedUntil } from "../../data/slices/vehicles";
import {
  cancelText,
  cancellerText,
  commandChoices,
  commandTitle,
  expectedDuration,
  inTimeOrder,
  mergeCommands,
  noGpsFix,
  statusText,
  transitionReason,
  type CommandChoice,
} from "../../lib/commands";
import {
  CANCEL_CAUSE,
  COMMAND,
  commandStatusText,
  inline,
  lostButtonNote,
  lostClause,
  lostMeanwhileText,
  umaa,
  type UmaaVersion,
} from "../../lib/labels";
import { LostFor } from "../../components/LastHeard";
import { clockDuration, utc } from "../../lib/units";
import { vehicleLabel, type VehicleIdentity } from "../../lib/vehicle";
import { unreachable as isUnreachable } from "../../data/source";

type Action = CommandChoice & { run: (provider: string, token: string | null, confirmLost: boolean) => Promise<Command> };

/** The selected vehicle's commands, as its UMAA version takes them (lib/commands.ts), each with the request it sends. */
function actionsFor(version: UmaaVersion | null): Action[] {
  return commandChoices(version).map((c) => ({
    ...c,
    run: (p, t, l) => (c.state === null ? requestGpsFix(p, t, l) : setInertialSensor(p, c.state, t, l)),
  }));
}

/** A confirmation is bound to the vehicle it was prepared for, and to whether that vehicle was lost then
 * (a lost vehicle's command says so and is sent with confirmLost). */
type Pending = { action: Action; target: VehicleIdentity; lost: boolean };

/** Unanswered and not ended: a cancelled command the console ended as never heard keeps `unanswered` in its record,
 * but nothing is left to wait for or to watch. */
function awaitingAnswer(c: Command): boolean {
  return c.unanswered && !c.terminal;
}

function statusClass(c: Command): string {
  if (c.violations.length || awaitingAnswer(c)) return "alarm";
  if (c.status === "FAILED") return "bad";
  if (c.status === "COMPLETED") return "ok";
  if (c.status === "CANCELED" || c.closedUnheard) return "muted";
  return "active";
}

type Line = { at: number; node: ReactNode };

function Timeline({ c, target }: { c: Command; target: VehicleIdentity }) {
  const lines: Line[] = [
    {
      at: c.createdAt,
      node: (
        <li key="requested" className="muted">
          <span className="t-status">Requested</span> <span className="t-time">{utc(c.createdAt, false)}</span>
          {c.operator ? <span> by {c.operator}</span> : null}
          {c.console ? <span data-testid="station"> on {c.console}</span> : null}
        </li>
      ),
    },
    ...c.transitions.map((t) => ({
      at: t.receivedAt,
      node: (
        <li
          key={`t${t.seq}`}
          className={t.violation ? "violation" : ""}
          data-testid="transition"
          data-status={t.status}
          data-reason={t.reason}
        >
          <span className="t-status" title={umaa("commandStatus", t.status)}>
            {commandStatusText(t.status)}
          </span>{" "}
          <span className="t-reason" title={umaa("reason", t.reason)}>
            {transitionReason(c, t.status, t.reason)}
          </span>{" "}
          <span className="t-time">{utc(t.receivedAt, false)}</span>
          {t.logMessage && <span className="t-log">“{t.logMessage}”</span>}
          {t.violation && (
            <strong className="t-violation" role="alert" data-testid="violation" title={`UMAA flow violation: ${t.violation}`}>
              Out of sequence: the vehicle skipped a step or went back
            </strong>
          )}
        </li>
      ),
    })),
  ];
  if (c.ackedAt !== null) {
    lines.push({
      at: c.ackedAt,
      node: (
        <li key="ack" className="muted" data-testid="ack">
          <span className="t-status" title="UMAA CommandAckReport: the vehicle publishes it as it starts to process the command">
            Acknowledged
          </span>{" "}
          the vehicle reports taking it up <span className="t-time">{utc(c.ackedAt, false)}</span>
        </li>
      ),
    });
  }
  if (c.cancelRequested) {
    const at = c.canceledAt ?? null;
    lines.push({
      at: at ?? Infinity,
      node: (
        <li key="cancel" className="muted" data-testid="cancel-asked">
          <span className="t-status">
            {CANCEL_CAUSE[c.cancelCause ?? "operator"]}
            {c.cancelCause === "shutdown" ? ":" : ""}
          </span>{" "}
          {cancellerText(c)} {at !== null && <span className="t-time">{utc(at, false)}</span>}
        </li>
      ),
    });
  }
  if (c.closedUnheard) {
    const at = c.closedAt ?? null;
    lines.push({
      at: at ?? Infinity,
      node: (
        <li key="closed" data-testid="closed-unheard">
          <span className="t-status">Ended by the console:</span>{" "}
          {c.closedUnheard === "heard"
            ? "the vehicle was heard again without answering it; it never heard the command, which the cancel withdrew"
            : `the vehicle was not heard for ${clockDuration((at ?? 0) - (c.canceledAt ?? c.createdAt))} after the cancel; the cancel withdrew the command if it had not heard it`}{" "}
          {at !== null && <span className="t-time">{utc(at, false)}</span>}
        </li>
      ),
    });
  }
  return (
    <ol className="timeline" data-testid="timeline" aria-label={`Timeline of ${commandTitle(c)}`}>
      {inTimeOrder(lines).map((l) => l.node)}
      {awaitingAnswer(c) && (
        <li
          className="violation"
          role="alert"
          data-testid="unanswered"
          title="UMAA: no ISSUED status within the unanswered timeout"
        >
          <strong>
            {COMMAND.unanswered}: {vehicleLabel(target)} has not confirmed receiving this command.
          </strong>{" "}
          It may still run it when it hears it, late.{" "}
          {/* once cancelled (no Cancel button any more), what is left to know: the cancel may not reach it either */}
          {c.cancelRequested
            ? "Cancel requested: it may not hear the cancel either; watch it when it answers."
            : "Cancel it if it should not run then."}
        </li>
      )}
      {c.cancelRequested && !c.terminal && <li className="muted">waiting for the vehicle to answer the cancel…</li>}
    </ol>
  );
}

/** How long a running command has taken, against what this vehicle's earlier ones of its kind took. */
function Elapsed({ c, expected }: { c: Command; expected: number | null }) {
  const now = useConsoleNow(1000); // the console stamped createdAt
  return (
    <span
      className="c-elapsed muted"
      data-testid="command-elapsed"
      title="time since it was requested; expected: the median of this vehicle's earlier completed commands of this kind"
    >
      {clockDuration(now - c.createdAt)} of {expected === null ? "— expected" : `${clockDuration(expected)} expected`}
    </span>
  );
}

function CommandCard({
  c,
  target,
  expected,
  canCommand,
  waiting,
  onCancel,
  open,
}: {
  c: Command;
  target: VehicleIdentity;
  expected: number | null;
  canCommand: boolean;
  waiting: boolean;
  onCancel: (c: Command) => void;
  open: boolean;
}) {
  // Cancel goes once the console has the cancel: the focus of the operator who pressed it goes to the command's row
  // (its status), not to the page's top
  const row = useRef<HTMLElement>(null);
  const focus = useFocusWhenGone();
  return (
    <details
      className={`command ${statusClass(c)}`}
      open={open}
      data-testid="command"
      data-session={c.sessionId}
      data-status={c.status ?? "none"}
    >
      <summary ref={row} data-testid="command-summary">
        <span className="c-title">{commandTitle(c)}</span>
        <span
          className="c-status"
          data-testid="command-status"
          title={awaitingAnswer(c) ? "UMAA: unanswered (no ISSUED)" : umaa("commandStatus", c.status)}
        >
          {statusText(c)}
        </span>
        {cancelText(c) && (
          <span className="c-canceller muted" data-testid="command-canceller">
            {inline(cancelText(c) ?? "")}
          </span>
        )}
        {c.violations.length > 0 && (
          <span className="c-flag" data-testid="command-violation">
            ⚠ out of sequence
          </span>
        )}
        <span className="c-time muted">{utc(c.createdAt, false)}</span>
        {!c.terminal && <Elapsed c={c} expected={expected} />}
        {/* a double click is one cancel: its second click would otherwise say "not sent" of the one that was */}
        {!c.terminal && !c.cancelRequested && (
          <button
            className="small danger"
            disabled={!canCommand}
            aria-disabled={waiting || undefined} // while a request is on its way: not disabled, which would drop the focus
            title={`Cancel ${commandTitle(c)} on ${vehicleLabel(target)}`}
            onClick={(e) => {
              e.preventDefault(); // a button in a summary: the press is not a toggle of the details
              if (e.detail >= 2 || waiting) return;
              focus.pressed(e.currentTarget, () => row.current);
              onCancel(c);
            }}
          >
            Cancel
          </button>
        )}
      </summary>
      <Timeline c={c} target={target} />
      <p className="muted c-session">session {c.sessionId}</p>
    </details>
  );
}

const PAGE = 20; // commands shown per page
const FETCH = 100; // commands asked of the console per request

/** The selected vehicle's commands, newest first: the live ones, then older pages from the console's
 * history (GET /api/commands) on demand. Keyed by the vehicle, so its pages never show beside another. */
function CommandList({
  target,
  live,
  canCommand,
  waiting,
  onCancel,
}: {
  target: VehicleIdentity;
  live: Command[];
  canCommand: boolean;
  waiting: boolean;
  onCancel: (c: Command) => void;
}) {
  const token = useToken();
  const [older, setOlder] = useState<Command[]>([]);
  const [fetched, setFetched] = useState(0); // rows of the history read so far (from the newest)
  const [done, setDone] = useState(false); // the history has nothing beyond them
  const [visible, setVisible] = useState(PAGE);
  const [loading, setLoading] = useState(false);
  const [error, setError] = useState<string | null>(null);
  const [counted, setCounted] = useState(false); // the first page of the history was read: the total is known, or its floor
  const { playback } = useCapabilities();
  const now = useNow(1000);
  const until = playback ? now : null; // a replay's history holds commands requested after the instant shown
  const all = useMemo(() => mergeCommands(live, older, until), [live, older, until]);
  const snapshots = useSelector((s) => s.snapshots);
  useEffect(() => {
    // the history's first page at once, so the count says how many there are (the live list holds only what this
    // console follows and recently finished); a failure leaves the count as "shown" until Older commands is pressed.
    // Read again at each snapshot: another station's command reaches the page only live, and a snapshot (a reconnect)
    // holds only this console's, so the row read before would show it as it was then (running, though it has ended).
    let gone = false;
    commandPage(target.id, FETCH, 0, token).then(
      (page) => {
        if (gone) return;
        const fresh = new Set(page.map((c) => c.sessionId));
        setOlder((o) => [...page, ...o.filter((c) => !fresh.has(c.sessionId))]);
        setFetched((f) => Math.max(f, page.length));
        setDone((d) => d || page.length < FETCH);
        setCounted(true);
      },
      () => undefined,
    );
    return () => {
      gone = true;
    };
  }, [target.id, token, snapshots]);
  const shown = all.filter((c, i) => i < visible || !c.terminal); // running commands always

  const showOlder = async () => {
    const want = visible + PAGE;
    setError(null);
    if (all.length >= want || done) {
      setVisible(want);
      return;
    }
    setLoading(true);
    let got = older,
      offset = fetched,
      end = false;
    const read: Command[] = []; // the pages read here: added to what is held then (a snapshot's read may land meanwhile)
    try {
      while (mergeCommands(live, got, until).length < want && !end) {
        const page = await commandPage(target.id, FETCH, offset, token);
        got = [...got, ...page];
        read.push(...page);
        offset += page.length;
        end = page.length < FETCH;
      }
      setVisible(want);
    } catch (e) {
      setError(`Older commands of ${vehicleLabel(target)}: ${problemText(e)}`);
    } finally {
      setOlder((o) => {
        const held = new Set(o.map((c) => c.sessionId));
        return [...o, ...read.filter((c) => !held.has(c.sessionId))];
      });
      setFetched(offset);
      setDone(end);
      setCounted(true);
      setLoading(false);
    }
  };

  return (
    <>
      <div className="command-list" data-testid="command-list">
        {all.length === 0 && <p className="muted">No commands sent to this vehicle.</p>}
        {shown.map((c, i) => (
          <CommandCard
            key={c.sessionId}
            c={c}
            target={target}
            expected={c.terminal ? null : expectedDuration(c, all)}
            canCommand={canCommand}
            waiting={waiting}
            open={i < 3 || !c.terminal}
            onCancel={onCancel}
          />
        ))}
      </div>
      {(all.length > 0 || older.length > 0) && (
        <div className="pager" data-testid="command-pager">
          <span className="muted" data-testid="command-count">
            {!counted && !done ? `${shown.length} shown` : `${shown.length} of ${done ? "" : "at least "}${all.length} commands`}
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
  const version = useSelectedUmaaVersion();
  const actions = useMemo(() => actionsFor(version), [version]);
  const target: VehicleIdentity | null = selected ? { id: selected, name: known?.name ?? null } : null;
  const commands = useCommands(selected);
  const authRequired = useSelector((s) => s.authRequired);
  const lostSince = useSelector(selectedLostSince);
  const until = useSelector(selectedPlannedUntil); // lost in its planned silence: out of comms as planned, no alarm
  const token = useToken();
  const connection = useConnectionState();
  const { command: mayCommand } = useCapabilities();
  const [pending, setPending] = useState<Pending | null>(null);
  const [error, setError] = useState<string | null>(null);
  const [note, setNote] = useState<string | null>(null);
  const unreachable = isUnreachable(connection);
  // A double click is one order: its second click (detail 2) is ignored, and while a request is on its way the
  // buttons wait for its answer, so a second click or Enter does not send the command twice (the second would
  // supersede the first, which then shows as failed). A ref, read by the handlers: the second click can come before
  // a render; and the buttons only say so (aria-disabled): a disabled button would drop the keyboard focus of the
  // operator who just pressed it.
  // Each time the console goes out of reach the wait ends: the answer of a request on its way may never come (a
  // connection gone silent), and the buttons must not wait for it past the reconnect; if it comes after all, it still
  // says what became of its command.
  const [outages, setOutages] = useState(0);
  const [wasUnreachable, setWasUnreachable] = useState(unreachable);
  if (unreachable !== wasUnreachable) {
    setWasUnreachable(unreachable);
    if (unreachable) setOutages(outages + 1);
  }
  const [sendingIn, setSendingIn] = useState<number | null>(null); // the outage count its request was sent in
  const sending = sendingIn === outages;
  const inFlight = useRef<{ outages: number } | null>(null);
  const waiting = () => inFlight.current !== null && inFlight.current.outages === outages;
  const lost = known?.link === "lost";
  const canCommand = mayCommand && !!known && (!authRequired || !!token) && !unreachable;

  // Adjusted while rendering, so no frame ever shows a void confirmation:
  // another vehicle selected: a confirmation prepared for the previous one is void;
  if (pending !== null && pending.target.id !== selected) {
    setNote(`${pending.action.label} for ${vehicleLabel(pending.target)} not sent: the selected vehicle changed.`);
    setPending(null);
  } else if (pending !== null && !pending.lost && lost) {
    // its vehicle lost meanwhile: what the operator is confirming no longer says what would happen
    setNote(lostMeanwhileText(pending.action.label, vehicleLabel(pending.target), until));
    setPending(null);
  }

  const run = async (target: VehicleIdentity, what: string, fn: () => Promise<Command>) => {
    if (waiting()) {
      // e.g. a confirmation opened before, confirmed while another request is on its way: said, never dropped silently
      setNote(`${what} for ${vehicleLabel(target)} not sent: another request was on its way. Try again.`);
      return;
    }
    const mine = { outages };
    inFlight.current = mine;
    setSendingIn(outages);
    setError(null);
    setNote(null);
    try {
      await fn();
    } catch (e) {
      setError(`${what} on ${vehicleLabel(target)}: ${problemText(e)}`);
    } finally {
      if (inFlight.current === mine) {
        // else a later request's, sent after an outage ended this one's wait: not this one's to lift
        inFlight.current = null;
        setSendingIn(null);
      }
    }
  };
  const act = (a: Action, t: VehicleIdentity) => {
    if (waiting()) return; // aria-disabled, as the button says (a second Enter of the same order)
    setNote(null);
    if (a.confirm || lost) setPending({ action: a, target: t, lost });
    else void run(t, a.label, () => a.run(t.id, token, false));
  };
  const shown = pending !== null && pending.target.id === selected ? pending : null;
  const why = (a: Action, t: VehicleIdentity): string => {
    const said = unreachable
      ? `${a.label}: ${UNREACHABLE}`
      : lost
        ? `${a.label} on ${vehicleLabel(t)}, which is ${lostClause(until)}: asks you to confirm`
        : `${a.label} on ${vehicleLabel(t)}`;
    const literal = umaa("state", a.state); // the UMAA literal it sends, for the engineer comparing with a log
    return literal ? `${said} (${literal})` : said;
  };
  const noFix = target ? noGpsFix(version) : null;

  return (
    <Panel title="Commands" testId="commands-panel">
      {!mayCommand && (
        <p className="readonly-note" data-testid="commands-replay">
          Replay: read-only. Commands are not sent.
        </p>
      )}
      {mayCommand && authRequired && !token && (
        <p className="readonly-note" data-testid="commands-read-only">
          Read-only: sign in with an operator token to command vehicles.
        </p>
      )}
      {mayCommand && unreachable && (
        <p className="error" role="status" data-testid="commands-unreachable">
          Console unreachable: no command can be sent until it answers again.
        </p>
      )}
      {target ? (
        <p className="command-target" data-testid="command-target">
          Commands to <VehicleTag v={target} />
          {!known && <span className="muted">not on the bus (yet)</span>}
        </p>
      ) : (
        <p className="muted" data-testid="command-target">
          Select a vehicle to command it.
        </p>
      )}
      {/* no live region: its "last heard" counts every second */}
      {target && lost && lostSince !== null && (
        <p className={until !== null ? "command-planned" : "alarm"} data-testid="command-lost">
          <LostFor target={target} since={lostSince} until={until} />.
          {mayCommand && " A command waits until it is heard again; each one asks you to confirm." /* a replay sends none */}
        </p>
      )}
      <div className="actions" role="group" aria-label={target ? `Commands to ${vehicleLabel(target)}` : "Command actions"}>
        {actions.map((a) => (
          <button
            key={a.label}
            disabled={!canCommand || !target}
            aria-disabled={sending || undefined}
            title={target ? why(a, target) : undefined}
            onClick={(e) => target && e.detail < 2 && act(a, target)}
            data-lost={lost ? "true" : undefined}
            data-state={a.state ?? undefined}
          >
            {a.label}
            {lost && mayCommand && lostButtonNote(until)}
          </button>
        ))}
      </div>
      {noFix && (
        <p className="muted" data-testid="command-no-gps-fix">
          {noFix}: no GPS fix to request.
        </p>
      )}
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
        <Confirm
          key={`${shown.action.label} ${shown.target.id}`}
          label="Confirm command"
          vehicle={shown.target.id}
          confirmText={shown.lost ? "Send anyway" : "Confirm"}
          onConfirm={() => {
            const { action, target: to, lost: toLost } = shown;
            setPending(null);
            void run(to, action.label, () => action.run(to.id, token, toLost)); // the vehicle it was prepared for
          }}
          onCancel={() => setPending(null)}
        >
          <p>
            <strong>{shown.action.label}</strong> on <VehicleTag v={shown.target} />
          </p>
          {shown.lost && (
            <p className="confirm-lost" data-testid="confirm-lost">
              <strong>
                {lostSince !== null ? (
                  <LostFor target={shown.target} since={lostSince} until={until} />
                ) : (
                  `${vehicleLabel(shown.target)} was lost`
                )}
                . Send {shown.action.noun} anyway?
              </strong>{" "}
              It runs when the vehicle hears it, maybe much later.
            </p>
          )}
          {shown.action.confirm && <p>{shown.action.confirm}</p>}
        </Confirm>
      )}
      {target && (
        <CommandList
          key={target.id}
          target={target}
          live={commands}
          canCommand={canCommand}
          waiting={sending}
          onCancel={(x) => void run(target, `Cancel ${commandTitle(x)}`, () => cancelCommand(x.sessionId, token))}
        />
      )}
    </Panel>
  );
}
