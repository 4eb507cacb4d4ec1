// The dashboard's state and the pure reducer that applies server messages to it.
// Unchanged parts keep their identity, so panels that select them do not re-render.
import type { FeatureCollection } from "geojson";
import type { Task } from "../api/rest";
import type { Alarm, PlannedSilence } from "../api/generated/ws";
import type { Command, DatabaseState, GatewayState, LinkConfig, LinkState, ProviderSummary, RecordingStatus, ReportEnvelopeOf, ReportTypes, ServerMessage, Topic, TopicReports, TypedReportMessage } from "../api/types";
import { nextInterval } from "../lib/freshness";
import { trimTrack, validPosition, type TrackSample } from "../lib/geo";
import { satelliteLabel } from "../lib/satellites";

/** A vehicle's latest report of topic T (any topic's when T is the union). */
export interface TopicView<T extends Topic = Topic> {
  envelope: ReportEnvelopeOf<T>;
  at: number; // client time (s) it arrived
  interval: number | null; // observed seconds between samples
  // a GPSReport without its satellites: the snapshot's (the first screen), or a live one of a vehicle the page had not
  // selected (`partial` reports); it holds the satellites it had before, if any. The selected vehicle's is completed
  // by the console on the `select` and by GET /api/providers/{id} (detailLoaded), any by its next whole report
  partial?: boolean;
}

export interface TrailPoint {
  az: number;
  el: number;
  t: number;
}

/** One point of the GPS chart: the same values as the console's `SeriesPoint` (GET /api/providers/{id}/series). */
export interface HistoryPoint {
  t: number; // UTC seconds when the console received the GPSReport (its receivedAt)
  cn0: number | null; // mean antennaCarrierNoiseDensity of the satellites that report one, dB-Hz
  used: number | null; // satellites used in the fix
  inView: number | null; // numberSatellitesInView
}

export interface ProviderView {
  id: string;
  name: string | null; // configured on the console (--vehicle-names)
  link: LinkState;
  linkConfig: LinkConfig | null; // per-vehicle thresholds and comms-lost configuration
  jausId: string | null; // "S.1.C" when the console's JAUS gateway is on
  umaaVersion: ProviderSummary["umaaVersion"] | null; // the UMAA version it speaks (null before the console said)
  topics: { [T in Topic]?: TopicView<T> };
  trails: Record<string, TrailPoint[]>;
  history: HistoryPoint[];
  track: TrackSample[]; // positions of the last TRACK_SECONDS, at most one per second (the map's track)
}

export interface State {
  consoleId: string | null;
  authRequired: boolean;
  readAuthRequired: boolean; // reads (and /ws) need a token too (GET /api/health)
  providers: Record<string, ProviderView>;
  commands: Record<string, Command>;
  gateways: GatewayState[]; // ASPN and JAUS: on or off, messages per second, last error
  // The console's active alarm set (snapshot and `alarms` messages), newest first: the server derives it
  // from state and keeps it, so a new or reloaded page shows what is active, not what it happened to see.
  alarms: Alarm[];
  // The planned silences in force ("out of comms until"), shared by the stations (snapshot and `silences` messages)
  silences: PlannedSilence[];
  recording: RecordingStatus | null; // the console's recording to MCAP (null before the first snapshot)
  // whether the console's database can be reached (snapshot and `database` messages; null: not known, or a replay)
  database: DatabaseState | null;
  // The vehicle the operator chose (or the page's ?vehicle= link). Nothing else changes it: not a
  // report, not a reconnect, not a snapshot that lacks it (it may not have reported yet); only while
  // none is chosen, a lone vehicle on the bus is selected (withLoneSelected).
  selected: string | null;
  // CoMap: the console's world model (null: none known; a console without CoMap answers 404)
  // and its tasks by id, from the WebSocket's `worldmodel` and `task` messages after one REST load per connection
  worldModel: FeatureCollection | null;
  worldModelSeq: number; // `worldmodel` messages received: a REST answer older than one of them is dropped
  tasks: Record<number, Task>;
  taskSeq: number; // `task` messages received
  taskMessageSeq: Record<number, number>; // each task's last `task` message (its taskSeq then)
  // A replay's instants shown (each seek, each reconnect): the chart's and map's history is loaded again
  // for each, and a REST answer for an earlier one is dropped
  instant: number;
}

export const TRAIL_SECONDS = 600;
export const TRAIL_STEP = 5;
// a trail's step may be this much short: a vehicle not selected sends its satellites once in every 5 s of the console's
// clock (hub.py FULL_EVERY), and they arrive a few ms either side of 5 s here: half its points were 10 s apart
const TRAIL_SLACK = 0.5;
export const HISTORY_SECONDS = 300;
export const HISTORY_STEP = 1;
export const TRACK_SECONDS = 900;

export const initialState: State = {
  consoleId: null,
  authRequired: false,
  readAuthRequired: false,
  providers: {},
  commands: {},
  gateways: [],
  alarms: [],
  silences: [],
  recording: null,
  database: null,
  selected: null,
  worldModel: null,
  worldModelSeq: 0,
  tasks: {},
  taskSeq: 0,
  taskMessageSeq: {},
  instant: 0,
};

export function report<T extends Topic>(p: ProviderView | undefined, topic: T): ReportTypes[T] | null {
  return viewReport<T>(p?.topics[topic] ?? null);
}

/** When the vehicle was last heard: the arrival (the source's clock, s) of its newest report of any topic; null: no
 * report of it received. */
export function lastHeardAt(p: ProviderView): number | null {
  let latest: number | null = null;
  for (const t of Object.values(p.topics)) if (latest === null || t.at > latest) latest = t.at;
  return latest;
}

/** The report a view of topic T holds (null: none), e.g. viewReport<"GPSReport">(view). */
export function viewReport<T extends Topic>(view: TopicView<T> | null | undefined): ReportTypes[T] | null {
  return view ? view.envelope.report : null;
}

function emptyProvider(id: string, link: LinkState, name: string | null = null): ProviderView {
  return { id, name, link, linkConfig: null, jausId: null, umaaVersion: null, topics: {}, trails: {}, history: [], track: [] };
}

/** The summary's fields a provider view keeps (name, link state, link configuration, JAUS id, UMAA version). */
function fromSummary(p: ProviderView, s: ProviderSummary): ProviderView {
  return { ...p, name: s.name, link: s.link, linkConfig: s.linkConfig, jausId: s.jausId, umaaVersion: s.umaaVersion };
}

function updateTrails(trails: Record<string, TrailPoint[]>, env: ReportEnvelopeOf<"GPSReport">, now: number): Record<string, TrailPoint[]> {
  const gps = env.report;
  const next: Record<string, TrailPoint[]> = {};
  let changed = false;
  let count = 0;
  for (const s of gps.satellites ?? []) {
    if (typeof s.azimuth !== "number" || typeof s.elevation !== "number") continue;
    const key = satelliteLabel(s.satelliteId);
    const old = trails[key] ?? [];
    const last = old[old.length - 1];
    if (!(key in next)) count++;
    if (last && now - last.t < TRAIL_STEP - TRAIL_SLACK) {
      next[key] = old;
      continue;
    }
    changed = true;
    const kept = old.filter((p) => now - p.t <= TRAIL_SECONDS);
    next[key] = [...kept, { az: s.azimuth, el: s.elevation, t: now }];
  }
  // the same satellites within their step (most reports): the same trails, so the sky plot's trails do not redraw
  return changed || count !== Object.keys(trails).length ? next : trails;
}

/** The chart values of a GPSReport received at `t` (as the console computes its series). */
export function historyPoint(gps: ReportTypes["GPSReport"], t: number): HistoryPoint {
  const sats = gps.satellites ?? [];
  const cn0s = sats.map((s) => s.antennaCarrierNoiseDensity).filter((v): v is number => typeof v === "number" && Number.isFinite(v));
  const inView = gps.numberSatellitesInView;
  return {
    t,
    cn0: cn0s.length ? cn0s.reduce((a, b) => a + b, 0) / cn0s.length : null,
    used: sats.filter((s) => s.usedInFix === true).length,
    inView: typeof inView === "number" && inView >= 0 ? inView : sats.length,
  };
}

const slot = (t: number) => Math.floor(t / HISTORY_STEP);

/** Points of both lists, at most one per second (`history`'s first), in time order, within
 * HISTORY_SECONDS of the latest: live points merged with what the console kept (after a reload). */
export function mergeHistory(history: HistoryPoint[], more: HistoryPoint[]): HistoryPoint[] {
  const bySlot = new Map<number, HistoryPoint>();
  for (const p of [...history, ...more]) if (Number.isFinite(p.t) && !bySlot.has(slot(p.t))) bySlot.set(slot(p.t), p);
  const all = [...bySlot.values()].sort((a, b) => a.t - b.t);
  const latest = all.length ? all[all.length - 1].t : 0;
  return all.filter((p) => latest - p.t <= HISTORY_SECONDS);
}

function updateHistory(history: HistoryPoint[], env: ReportEnvelopeOf<"GPSReport">): HistoryPoint[] {
  const last = history[history.length - 1];
  if (last && slot(last.t) === slot(env.receivedAt)) return history;
  const point = historyPoint(env.report, env.receivedAt);
  if (last && point.t < last.t) return mergeHistory(history, [point]);
  return [...history.filter((h) => point.t - h.t <= HISTORY_SECONDS), point];
}

/** A vehicle's reports as GET /api/providers/{id} gave them: its GPSReport's satellites, which the snapshot left out,
 * unless a report came since (it is newer). */
export function detailLoaded(state: State, providerId: string, reports: TopicReports): State {
  const before = state.providers[providerId];
  const view = before?.topics.GPSReport;
  const env = reports.GPSReport;
  if (!before || !view?.partial || !env || env.receivedAt < view.envelope.receivedAt) return state;
  const gps: TopicView<"GPSReport"> = { envelope: env, at: view.at, interval: view.interval };
  return { ...state, providers: { ...state.providers, [providerId]: { ...before, topics: { ...before.topics, GPSReport: gps } } } };
}

/** The console's series of a vehicle (REST), merged into the live history. */
export function historyLoaded(state: State, providerId: string, points: HistoryPoint[]): State {
  const before = state.providers[providerId];
  if (!before || !points.length) return state;
  const history = mergeHistory(before.history, points);
  return { ...state, providers: { ...state.providers, [providerId]: { ...before, history } } };
}

/** The position of a GPSFixReport received at `t` as a track point (null: no usable position). */
export function trackSample(fix: ReportTypes["GPSFixReport"], t: number): TrackSample | null {
  const g = fix.position2DWithTime?.geodeticPosition;
  const pos = validPosition(g?.geodeticLatitude?.latitude, g?.geodeticLongitude?.longitude);
  return pos ? { ...pos, t } : null;
}

function updateTrack(track: TrackSample[], env: ReportEnvelopeOf<"GPSFixReport">): TrackSample[] {
  const last = track[track.length - 1];
  if (last && Math.floor(last.t) === Math.floor(env.receivedAt)) return track;
  const point = trackSample(env.report, env.receivedAt);
  if (!point) return track;
  if (last && point.t < last.t) return trimTrack([...track, point], point.t, TRACK_SECONDS);
  const from = point.t - TRACK_SECONDS;
  return [...(track.length && track[0].t < from ? track.filter((p) => p.t >= from) : track), point];
}

/** The console's stored track of a vehicle (REST, after a reload or reconnect), merged into the live one. */
export function trackLoaded(state: State, providerId: string, points: TrackSample[]): State {
  const before = state.providers[providerId];
  if (!before || !points.length) return state;
  const all = [...points, ...before.track];
  const latest = Math.max(...all.map((p) => p.t));
  const bySecond = new Map<number, TrackSample>();
  for (const p of all) bySecond.set(Math.floor(p.t), p);
  const track = trimTrack([...bySecond.values()], latest, TRACK_SECONDS);
  return { ...state, providers: { ...state.providers, [providerId]: { ...before, track } } };
}

/** A vehicle's view (undefined: not known yet) with report `msg` applied. */
function reported(before: ProviderView | undefined, msg: TypedReportMessage, now: number): ProviderView {
  const { providerId, topic } = msg;
  const b = before ?? emptyProvider(providerId, "live");
  const prevView = b.topics[topic];
  // the sample it already has, sent again (the console sends the latest GPSReport whole to a client that has just
  // selected the vehicle): it arrived when it first did, or selecting a vehicle silent for minutes, or lost, would
  // show it heard from just now (its age, "stale", "lost for", a lost command's confirmation)
  const again = prevView !== undefined && prevView.envelope.receivedAt === msg.report.receivedAt;
  const at = again ? { at: prevView.at, interval: prevView.interval } : { at: now, interval: prevView ? nextInterval(prevView.interval, now - prevView.at) : null };
  if (msg.topic === "GPSReport" && msg.partial) {
    // without its satellites: the trails and the chart wait for a whole one; the satellites it had stay
    const kept = (prevView as TopicView<"GPSReport"> | undefined)?.envelope.report.satellites ?? [];
    const envelope = kept.length ? { ...msg.report, report: { ...msg.report.report, satellites: kept } } : msg.report;
    return { ...b, topics: { ...b.topics, GPSReport: { envelope, ...at, partial: true } } };
  }
  let p: ProviderView = { ...b, topics: { ...b.topics, [topic]: { envelope: msg.report, ...at } } };
  if (msg.topic === "GPSReport") p = { ...p, trails: updateTrails(p.trails, msg.report, now), history: updateHistory(p.history, msg.report) };
  if (msg.topic === "GPSFixReport") p = { ...p, track: updateTrack(p.track, msg.report) };
  return p;
}

function applyReport(state: State, msg: TypedReportMessage, now: number): State {
  return { ...state, providers: { ...state.providers, [msg.providerId]: reported(state.providers[msg.providerId], msg, now) } };
}

function applyCommand(state: State, cmd: Command): State {
  return { ...state, commands: { ...state.commands, [cmd.sessionId]: cmd } };
}

/** The vehicle to select by itself: the lone vehicle on the bus, while the operator has chosen none (and
 * the page's link named none); otherwise the selection stays as it is. */
export function withLoneSelected(state: State): State {
  if (state.selected !== null) return state;
  let lone: string | null = null;
  for (const id in state.providers) {
    if (lone !== null) return state; // several: the operator chooses
    lone = id;
  }
  return lone === null ? state : { ...state, selected: lone };
}

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
    draft[msg.providerId] = reported(draft[msg.providerId], msg, now);
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
        let p: ProviderView = { ...fromSummary(old ?? emptyProvider(d.id, d.link), d), topics: {} };
        for (const topic of Object.keys(d.reports) as Topic[]) {
          const env = d.reports[topic];
          if (env) {
            const ageS = d.topics[topic]?.ageSeconds ?? 0;
            const partial = topic === "GPSReport" ? { partial: true } : {};
            p = { ...p, topics: { ...p.topics, [topic]: { envelope: env, at: now - ageS, interval: old?.topics[topic]?.interval ?? null, ...partial } } };
          }
        }
        providers[d.id] = p;
      }
      const commands: Record<string, Command> = {};
      for (const c of msg.commands) commands[c.sessionId] = c;
      return { ...state, consoleId: msg.consoleId, authRequired: msg.authRequired, providers, commands, gateways: msg.gateways, recording: msg.recording, alarms: msg.alarms ?? [], silences: msg.silences ?? [], database: msg.database ?? null };
    }
    case "report":
      return applyReport(state, msg, now);
    case "provider": {
      const id = msg.provider.id;
      const before = state.providers[id] ?? emptyProvider(id, msg.provider.link);
      return { ...state, providers: { ...state.providers, [id]: fromSummary(before, msg.provider) } };
    }
    case "command":
    case "transition": // the console raises the alarms of commands (failed, violations, unanswered): see `alarms`
      return applyCommand(state, msg.command);
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
    case "task": {
      const t: Task = msg.task;
      const taskSeq = state.taskSeq + 1;
      return { ...tasksLoaded(state, [t]), taskSeq, taskMessageSeq: { ...state.taskMessageSeq, [t.taskId]: taskSeq } };
    }
    case "replay": // the playback is the data source's (replay.ts), not the console's state
    case "error":
    case "pong":
      return state;
  }
}

/** The world model as GET /api/worldmodel gave it, asked when `worldModelSeq` was `seq`: dropped if a
 * `worldmodel` message came since (it is newer). */
export function worldModelLoaded(state: State, model: FeatureCollection | null, seq: number): State {
  return state.worldModelSeq !== seq || state.worldModel === model ? state : { ...state, worldModel: model };
}

/** A CoMap task's states that end it (the console's comap.c2.FINAL). */
export const FINISHED = new Set(["REJECTED", "COMPLETED", "ERROR", "INTERRUPTED"]);

/** Whether a task's `state`, decided at `at`, replaces its `other` decided at `otherAt`: the console's rule
 * (comap.c2.decided_over): the one decided later, except that a finished task is never made unfinished again, and of
 * two finished states the first stands. */
export function decidedOver(state: string, at: number, other: string, otherAt: number): boolean {
  if (FINISHED.has(state)) return !FINISHED.has(other) || at < otherAt;
  return !FINISHED.has(other) && at > otherAt;
}

/** Tasks (GET /api/tasks or a `task` message) merged by id, as the consoles merge them: state and synch from the copy
 * decided over the other (`decidedOver`, by stateAt), progress and quality from the copy with the newer progress
 * (updatedAt). A GET answered before a HOLD but read after its `task` message does not undo the HOLD (a synch moves
 * stateAt only), and a task its vehicle finished stays finished. */
export function tasksLoaded(state: State, tasks: Task[]): State {
  let next: Record<number, Task> | null = null;
  for (const t of tasks) {
    const old = (next ?? state.tasks)[t.taskId];
    let merged = t;
    if (old && old.createdAt === t.createdAt) {
      const decided = decidedOver(t.state, t.stateAt, old.state, old.stateAt);
      const progressed = t.updatedAt > old.updatedAt;
      if (!decided && !progressed) continue; // nothing newer
      if (!decided) merged = { ...merged, state: old.state, synch: old.synch, stateAt: old.stateAt };
      if (!progressed) merged = { ...merged, progress: old.progress, quality: old.quality, updatedAt: old.updatedAt };
    } else if (old && old.createdAt > t.createdAt) continue; // a finished task of that id, which this one replaced
    next = { ...(next ?? state.tasks), [t.taskId]: merged };
  }
  return next ? { ...state, tasks: next } : state;
}

/** The tasks as GET /api/tasks gave them, asked when `taskSeq` was `seq`: the console's list is what exists
 * (a task of a console since restarted goes), except a task whose `task` message came after the request
 * (kept, merged by updatedAt). */
export function tasksReplaced(state: State, tasks: Task[], seq: number): State {
  const kept: Record<number, Task> = {};
  for (const [id, t] of Object.entries(state.tasks)) if ((state.taskMessageSeq[Number(id)] ?? 0) > seq) kept[Number(id)] = t;
  return tasksLoaded({ ...state, tasks: kept }, tasks);
}

/** A replay moved to another instant: what was built from the instants before it (trails, charts) goes;
 * the snapshot that follows brings the alarms of the new instant. */
export function forNewInstant(state: State): State {
  return { ...state, providers: {}, commands: {}, instant: state.instant + 1 };
}

/** Alarms in view the operator has yet to acknowledge: active or already cleared, and not shelved. */
export function unacknowledged(alarms: readonly Alarm[]): Alarm[] {
  return alarms.filter((a) => a.state !== "active-acknowledged" && !a.shelf);
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

/** The operator's choice of vehicle: a known one, or (from a link) any id, shown once it reports. */
export function select(state: State, providerId: string | null): State {
  return providerId === state.selected ? state : { ...state, selected: providerId };
}

// Slices of the state that panels draw. Each keeps its identity until what it holds changes, so a
// subscription to one (Store.subscribeTo, hooks' useSlice) is not woken by another topic's report.
const NO_TRAILS: Record<string, TrailPoint[]> = {};

function selectedView(s: State): ProviderView | undefined {
  return s.selected ? s.providers[s.selected] : undefined;
}

function topicSelector<T extends Topic>(topic: T): (s: State) => TopicView<T> | null {
  return (s) => selectedView(s)?.topics[topic] ?? null;
}

const topicSelectors: { [T in Topic]: (s: State) => TopicView<T> | null } = {
  GPSReport: topicSelector("GPSReport"),
  GPSFixReport: topicSelector("GPSFixReport"),
  GPSFixStatusReport: topicSelector("GPSFixStatusReport"),
  InertialSensorReport: topicSelector("InertialSensorReport"),
};

/** The selected vehicle's latest report of `topic` (one selector per topic, so it can key a subscription). */
export function selectedTopic<T extends Topic>(topic: T): (s: State) => TopicView<T> | null {
  return topicSelectors[topic];
}

/** Whether the selected vehicle's GPSReport is the snapshot's, without its satellites. */
export const selectedGpsPartial = (s: State): boolean => selectedView(s)?.topics.GPSReport?.partial === true;

/** The selected vehicle's satellite trails (changed by its GPSReport only). */
export const selectedTrails = (s: State): Record<string, TrailPoint[]> => selectedView(s)?.trails ?? NO_TRAILS;

/** The selected vehicle's link state (null: none selected, or not on the bus). */
export const selectedLink = (s: State): LinkState | null => selectedView(s)?.link ?? null;

/** When the selected vehicle was last heard (the source's clock, s), while its link is lost; null when it is not
 * lost, 0 when no report of it was received. A number: a subscriber draws again only when it changes. */
export const selectedLostSince = (s: State): number | null => {
  const p = selectedView(s);
  return p?.link === "lost" ? (lastHeardAt(p) ?? 0) : null;
};

/** When a vehicle's planned silence ends, while it is lost in it (the link lost, a silence in force for it); null
 * otherwise. The one rule by which the page names a lost vehicle "out of comms (planned)" rather than lost. */
export function plannedUntil(silences: readonly PlannedSilence[], providerId: string, link: string): number | null {
  return link === "lost" ? (silences.find((x) => x.providerId === providerId)?.until ?? null) : null;
}

/** The end of the selected vehicle's planned silence while it is lost in it (plannedUntil), else null. */
export const selectedPlannedUntil = (s: State): number | null => {
  const p = selectedView(s);
  return p ? plannedUntil(s.silences, p.id, p.link) : null;
};

/** The selected vehicle's name, null when it has none or is not known. */
export const selectedName = (s: State): string | null => selectedView(s)?.name ?? null;

/** The selected vehicle's link configuration (changed by the console's provider messages only). */
export const selectedLinkConfig = (s: State): LinkConfig | null => selectedView(s)?.linkConfig ?? null;

/** The selected vehicle's JAUS id. */
export const selectedJausId = (s: State): string | null => selectedView(s)?.jausId ?? null;

/** Whether the selected vehicle is on the bus (known to the console). */
export const selectedKnown = (s: State): boolean => selectedView(s) !== undefined;

/** Every vehicle's view (changes with any report: subscribe to it at a bounded rate). */
export const allProviders = (s: State): Record<string, ProviderView> => s.providers;
