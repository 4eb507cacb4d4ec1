// The dashboard's state, one slice per concern (slices/), and the pure reducer that applies the console's messages to
// it. Unchanged parts keep their identity, so panels that select them do not re-render. The store (store.ts) holds it.
import type { FeatureCollection } from "geojson";
import type { Command, DatabaseState, GatewayState, RecordingStatus, ServerMessage, Topic } from "../api/types";
import { initialAlarms, type AlarmsState } from "./slices/alarms";
import { initialComap, taskReceived, type ComapState } from "./slices/comap";
import {
  emptyProvider,
  fromBrief,
  fromSummary,
  heardAtFullRate,
  initialVehicles,
  withPace,
  paceOf,
  reported,
  withLoneSelected,
  type ProviderView,
  type VehiclesState,
} from "./slices/vehicles";

/** What the console says of itself: its id, whether it asks for tokens, its gateways, recording and database, and
 * the commands it follows. */
export interface ConsoleState {
  consoleId: string | null;
  // snapshots applied: each (re)connect's; what a panel read over REST before one may have changed while the page was
  // not hearing the console (the Commands panel reads its history again)
  snapshots: number;
  authRequired: boolean;
  readAuthRequired: boolean; // reads (and /ws) need a token too (GET /api/health)
  commands: Record<string, Command>;
  gateways: GatewayState[]; // ASPN and JAUS: on or off, messages per second, last error
  recording: RecordingStatus | null; // the console's recording to MCAP (null before the first snapshot)
  // whether the console's database can be reached (snapshot and `database` messages; null: not known, or a replay)
  database: DatabaseState | null;
}

export type State = ConsoleState & VehiclesState & AlarmsState & ComapState;

const initialConsole: ConsoleState = {
  consoleId: null,
  snapshots: 0,
  authRequired: false,
  readAuthRequired: false,
  commands: {},
  gateways: [],
  recording: null,
  database: null,
};

export const initialState: State = { ...initialConsole, ...initialVehicles, ...initialAlarms, ...initialComap };

export function reduce(state: State, msg: ServerMessage, now: number): State {
  const next = reduceMessage(state, msg, now);
  // a vehicle is only added with a new providers object: a report of a known one need not look
  return next.selected === null && next.providers !== state.providers ? withLoneSelected(next) : next;
}

/** `reduce` of each message in turn, the state's map of vehicles copied once for a run of reports rather than once
 * per report: a frame applies every message since the last (hundreds with 250 vehicles), and a copy per message
 * was a copy of every vehicle's entry per report. */
export function reduceAll(state: State, msgs: readonly ServerMessage[], now: number): State {
  let s = state;
  let draft: Record<string, ProviderView> | null = null; // s.providers, this call's own copy
  for (const msg of msgs) {
    if (msg.type !== "report") {
      s = reduce(s, msg, now);
      draft = null; // shared with the state now: copied again for the next report
      continue;
    }
    if (!draft) {
      draft = { ...s.providers };
      s = { ...s, providers: draft };
    }
    const known = msg.providerId in draft;
    draft[msg.providerId] = reported(draft[msg.providerId], msg, now, paceOf(s, msg.providerId) > 0, s.consoleAhead);
    s = heardAtFullRate(s, msg.providerId);
    draft = s.providers; // its own copy still, or heardAtFullRate's new one
    if (!known && s.selected === null) s = withLoneSelected(s);
  }
  return s;
}

function reduceMessage(state: State, msg: ServerMessage, now: number): State {
  switch (msg.type) {
    case "snapshot": {
      const providers: Record<string, ProviderView> = {};
      for (const d of msg.providers) {
        const old = state.providers[d.id];
        let p: ProviderView = { ...fromSummary(old ?? emptyProvider(d.id, d.link), d), topics: {}, brief: false };
        for (const topic of Object.keys(d.reports) as Topic[]) {
          const env = d.reports[topic];
          if (env) {
            const ageS = d.topics[topic]?.ageSeconds ?? 0;
            const partial = topic === "GPSReport" ? { partial: true } : {};
            p = {
              ...p,
              topics: {
                ...p.topics,
                [topic]: { envelope: env, at: now - ageS, interval: old?.topics[topic]?.interval ?? null, ...partial },
              },
            };
          }
        }
        providers[d.id] = p;
      }
      // to a page that named its vehicle on connect: every other vehicle as its brief (what the overviews draw)
      for (const b of msg.fleet ?? []) providers[b.id] = fromBrief(state.providers[b.id], b, now, msg.serverTime);
      const commands: Record<string, Command> = {};
      for (const c of msg.commands) commands[c.sessionId] = c;
      return {
        ...state,
        consoleId: msg.consoleId,
        snapshots: state.snapshots + 1,
        authRequired: msg.authRequired,
        providers,
        consoleAhead: msg.serverTime - now,
        commands,
        gateways: msg.gateways,
        recording: msg.recording,
        alarms: msg.alarms ?? [],
        silences: msg.silences ?? [],
        database: msg.database ?? null,
      };
    }
    case "report":
      return heardAtFullRate(
        {
          ...state,
          providers: {
            ...state.providers,
            [msg.providerId]: reported(
              state.providers[msg.providerId],
              msg,
              now,
              paceOf(state, msg.providerId) > 0,
              state.consoleAhead,
            ),
          },
        },
        msg.providerId,
      );
    case "pace": // the vehicles the page does not draw come at this pace: judged silent by it (paceOf)
      return withPace(state, msg.othersEvery, state.clockRate);
    case "provider": {
      const id = msg.provider.id;
      const before = state.providers[id] ?? emptyProvider(id, msg.provider.link);
      return { ...state, providers: { ...state.providers, [id]: fromSummary(before, msg.provider) } };
    }
    case "command":
    case "transition": // the console raises the alarms of commands (failed, violations, unanswered): see `alarms`
      return { ...state, commands: { ...state.commands, [msg.command.sessionId]: msg.command } };
    case "gateways":
      return { ...state, gateways: msg.gateways };
    case "recording":
      return { ...state, recording: msg.recording };
    case "alarms":
      return { ...state, alarms: msg.alarms };
    case "database":
      return { ...state, database: msg.database };
    case "silences":
      return { ...state, silences: msg.silences };
    case "worldmodel":
      return { ...state, worldModel: msg.worldModel as FeatureCollection, worldModelSeq: state.worldModelSeq + 1 };
    case "task":
      return taskReceived(state, msg.task);
    case "load": // the console's own load: its console-overloaded alarm and the vehicles' "unchecked" link say it
    case "replay": // the playback is the data source's (replay.ts), not the console's state
    case "error":
    case "pong":
      return state;
  }
}

/** A replay moved to another instant: what was built from the instants before it (trails, charts) goes;
 * the snapshot that follows brings the alarms of the new instant. */
export function forNewInstant(state: State): State {
  return { ...state, providers: {}, commands: {}, instant: state.instant + 1 };
}

/** What the console kept for the page's sign-out: nothing it sent; the operator's selection and what /api/health said
 * stay. */
export function signedOut(state: State): State {
  const { selected, authRequired, readAuthRequired } = state;
  return { ...initialState, selected, authRequired, readAuthRequired };
}
