// The alarms slice: the console's active alarm set and the planned silences in force, with the rules the page
// counts, names and sounds them by.
import type { Alarm, PlannedSilence } from "../../api/generated/ws";

export interface AlarmsState {
  // The console's active alarm set (snapshot and `alarms` messages), newest first: the server derives it
  // from state and keeps it, so a new or reloaded page shows what is active, not what it happened to see.
  alarms: Alarm[];
  // The planned silences in force ("out of comms until"), shared by the stations (snapshot and `silences` messages)
  silences: PlannedSilence[];
}

export const initialAlarms: AlarmsState = { alarms: [], silences: [] };

/** Alarms in view: not shelved (acknowledged ones too, until they return to normal). */
export function inView(alarms: readonly Alarm[]): Alarm[] {
  return alarms.filter((a) => !a.shelf);
}

/** Alarms in view the operator has yet to acknowledge: active or already cleared, and not shelved. */
export function unacknowledged(alarms: readonly Alarm[]): Alarm[] {
  return inView(alarms).filter((a) => a.state !== "active-acknowledged");
}

/** A flood: this many alarms in view of one cause at once are shown, sounded and said as one group. */
export const FLOOD_AT = 5;

/** Alarms shelved by an operator: out of view, counted apart ("2 shelved"). */
export function shelved(alarms: readonly Alarm[]): Alarm[] {
  return alarms.filter((a) => a.shelf);
}

/** The tab's title: the count of unacknowledged alarms first, so it shows on a tab in the background. */
export function pageTitle(unacknowledgedCount: number, replay = false, unreachable = false): string {
  // a replay's tab says so: its alarms are history, and beside a live console's tab it must not pass for one; and a
  // console out of reach: no alarm nor loss can reach the page, whatever the count says
  const name = `${unreachable ? "Console unreachable · " : ""}${replay ? "Replay · " : ""}SEM Console`;
  return unacknowledgedCount > 0 ? `(${unacknowledgedCount}) ${name}` : name;
}

/** When a vehicle's planned silence ends, while it is lost in it (the link lost, a silence in force for it); null
 * otherwise. The one rule by which the page names a lost vehicle "out of comms (planned)" rather than lost. */
export function plannedUntil(silences: readonly PlannedSilence[], providerId: string, link: string): number | null {
  return link === "lost" ? (silences.find((x) => x.providerId === providerId)?.until ?? null) : null;
}
