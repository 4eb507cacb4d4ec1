// The commands panel: live commands (WebSocket) merged with older pages (REST), and the words of its cards.
import type { Command } from "../api/types";
import {
  CANCEL_CAUSE,
  COMMAND,
  COMMAND_STATUS,
  INS_COMMAND,
  commandStatusText,
  inline,
  reasonText,
  type InsCommand,
  type UmaaVersion,
} from "./labels";

/** A command the panel offers: its service, the state it asks (InertialSensor), its button's words, how a sentence
 * names it, and the question it asks first (null: sent at once). */
export interface CommandChoice {
  service: Command["service"];
  state: NonNullable<Command["state"]> | null;
  label: string;
  noun: string;
  confirm: string | null;
}

const REALIGN = "It must align again before it is operational.";
const CHOICES_3_0_1: CommandChoice[] = [
  { service: "GPSFix", state: null, label: "Request GPS fix", noun: "a GPS fix request", confirm: null },
  { service: "InertialSensor", state: "ON", label: "INS ON", noun: "INS ON", confirm: null },
  {
    service: "InertialSensor",
    state: "OFF",
    label: "INS OFF",
    noun: "INS OFF",
    confirm: "Switch its inertial sensor off? Navigation falls back to GPS only.",
  },
  {
    service: "InertialSensor",
    state: "RESTARTING",
    label: "INS RESTART",
    noun: "INS RESTART",
    confirm: `Restart its inertial sensor? ${REALIGN}`,
  },
];
const INS_6_0: InsCommand[] = ["GPS_ALIGN", "STATIONARY_ALIGN", "TRANSFER_ALIGN", "BEST_ALIGN", "SNAP_ALIGN", "INIT"];

/** A UMAA 6.0 inertial sensor command's title, "INS GPS-aided alignment"; null for a state of no 6.0 command. */
function insCommandTitle(state: string | null | undefined): string | null {
  return state && state in INS_COMMAND ? `INS ${inline(INS_COMMAND[state as InsCommand])}` : null;
}

/** The commands a vehicle of `version` takes (the backend refuses the others with a 422): UMAA 3.0.1, a GPS fix and
 * the INS ON, OFF or RESTART; UMAA 6.0, the alignments of its inertial sensor (it has no GPS fix service). */
export function commandChoices(version: UmaaVersion | null | undefined): CommandChoice[] {
  if (version !== "6.0") return CHOICES_3_0_1;
  return INS_6_0.map((state) => {
    const title = insCommandTitle(state) ?? state;
    return {
      service: "InertialSensor",
      state,
      label: title,
      noun: title,
      confirm: state === "INIT" ? `Initialise its inertial sensor? ${REALIGN}` : null,
    };
  });
}

/** Why a vehicle of `version` is offered no GPS fix, or null when it is. */
export function noGpsFix(version: UmaaVersion | null | undefined): string | null {
  return version === "6.0" ? "UMAA 6.0 has no GPS fix service" : null;
}

/** A command card's title: "GPS fix", "INS RESTART", "INS ON", "INS GPS-aided alignment". */
export function commandTitle(c: Pick<Command, "service" | "state">): string {
  if (c.service === "GPSFix") return "GPS fix";
  if (c.state === "RESTARTING") return "INS RESTART";
  return insCommandTitle(c.state) ?? `INS ${c.state ?? ""}`;
}

/** Both lists without repeats, newest first; a live command wins over its REST copy (it is newer). `until`: a
 * replay's instant (UTC seconds), whose history holds the whole recording: its rows of commands requested after that
 * instant are left out, as the page shows the recording as it was then; null for a live console. */
export function mergeCommands(live: Command[], older: Command[], until: number | null = null): Command[] {
  const seen = new Map<string, Command>();
  const past = until === null ? older : older.filter((c) => c.createdAt <= until);
  for (const c of [...live, ...past]) if (!seen.has(c.sessionId)) seen.set(c.sessionId, c);
  return [...seen.values()].sort((a, b) => b.createdAt - a.createdAt);
}

/** How long a completed command took: from its request to its last status (COMPLETED), seconds. */
export function durationOf(c: Command): number | null {
  if (c.status !== "COMPLETED" || c.transitions.length === 0) return null;
  return c.transitions[c.transitions.length - 1].receivedAt - c.createdAt;
}

/** The duration to expect of a command: the median of the same vehicle's earlier COMPLETED commands of the
 * same service (for INS, to the same state: a RESTART aligns for minutes, an OFF takes a second); null when
 * there is none to go by. Failed and cancelled ones say nothing of how long the service takes. */
export function expectedDuration(c: Command, all: Command[]): number | null {
  const took = all
    .filter(
      (o) =>
        o.sessionId !== c.sessionId &&
        o.providerId === c.providerId &&
        o.service === c.service &&
        (o.state ?? null) === (c.state ?? null) &&
        o.createdAt < c.createdAt,
    )
    .map(durationOf)
    .filter((d): d is number => d !== null && d >= 0)
    .sort((a, b) => a - b);
  if (took.length === 0) return null;
  const mid = Math.floor(took.length / 2);
  return took.length % 2 ? took[mid] : (took[mid - 1] + took[mid]) / 2;
}

/** A command timeline's lines in the order they happened; stable, so at one instant a status stays before the
 * acknowledgement the vehicle publishes after it. A line without a recorded time (Infinity) goes last. */
export function inTimeOrder<T extends { at: number }>(lines: T[]): T[] {
  return lines
    .map((l, i) => ({ l, i }))
    .sort((a, b) => (a.l.at === b.l.at ? 0 : a.l.at - b.l.at) || a.i - b.i)
    .map(({ l }) => l);
}

/** Who asked for the cancel and on which station: "by bob on relief" ("" when neither is known); a station's shutdown
 * (no one asked it): "watch cancelled it as it stopped". */
export function cancellerText(c: Command): string {
  if (c.cancelCause === "shutdown") return `${c.canceledOn ?? "its station"} cancelled it as it stopped`;
  const who = c.canceledBy ? `by ${c.canceledBy}` : "";
  const where = c.canceledOn ? `on ${c.canceledOn}` : "";
  return [who, where].filter(Boolean).join(" ");
}

/** The cancel's line: "Cancel asked by bob on relief", or "Station stopped: watch cancelled it as it stopped" (the
 * words table's cause); null when there is nothing to say beyond the status (a cancel of no known operator or station). */
export function cancelText(c: Command): string | null {
  if (!c.cancelRequested) return null;
  if (c.cancelCause === "shutdown") return `${CANCEL_CAUSE.shutdown}: ${cancellerText(c)}`;
  return cancellerText(c) ? `${CANCEL_CAUSE.operator} ${cancellerText(c)}` : null;
}

/** What the status line says: the vehicle's last status; a cancel the vehicle never answered, ended by the console. */
export function statusText(c: Command): string {
  if (c.closedUnheard === "heard") return `${COMMAND_STATUS.CANCELED} before the vehicle heard it`;
  if (c.closedUnheard === "bound") return `${COMMAND_STATUS.CANCELED}, never answered`;
  if (c.unanswered) return COMMAND.unanswered;
  return c.status ? commandStatusText(c.status) : "Sent";
}

/** The reason words of a transition: a cancel the operator asked for names who asked it and where ("on request by bob
 * on relief"); one a station's shutdown asked says so ("on request of watch as it stopped"). */
export function transitionReason(c: Command, status: string, reason: string): string {
  if (status === "CANCELED" && reason === "CANCELED" && c.cancelRequested && c.cancelCause === "shutdown")
    return `${reasonText(reason)} of ${c.canceledOn ?? "its station"} as it stopped`;
  if (status === "CANCELED" && reason === "CANCELED" && c.cancelRequested && cancellerText(c))
    return `${reasonText(reason)} ${cancellerText(c)}`;
  return reasonText(reason);
}
