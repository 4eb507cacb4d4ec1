// The vehicles slice: each vehicle's views of its latest reports, its satellite trails, chart history and map track,
// and the operator's selection. Pure functions of the state: unchanged parts keep their identity, so panels that
// select them do not re-render.
import type { DateTime } from "../../api/generated/ws";
import type {
  GPSFixReportType,
  GPSFixStatusReportType,
  InertialSensorReportType,
  LinkConfig,
  LinkState,
  ProviderSummary,
  ReportEnvelopeOf,
  ReportTypes,
  Topic,
  TopicReports,
  TypedProviderDetail,
  TypedReportMessage,
  VehicleBrief,
} from "../../api/types";
import { nextInterval } from "../../lib/freshness";
import { trimTrack, validPosition, type TrackSample } from "../../lib/geo";
import { satelliteLabel } from "../../lib/satellites";
import { plannedUntil, type AlarmsState } from "./alarms";

/** A vehicle's latest report of topic T (any topic's when T is the union). */
export interface TopicView<T extends Topic = Topic> {
  envelope: ReportEnvelopeOf<T>;
  at: number; // client time (s) it arrived
  interval: number | null; // observed seconds between samples
  // a GPSReport without its satellites: the snapshot's (the first screen), or a live one of a vehicle the page had not
  // selected (`partial` reports); it holds the satellites it had before, if any. The selected vehicle's is completed
  // by the console on the `select` and by GET /api/providers/{id} (detailLoaded), any by its next whole report
  partial?: boolean;
  // it came at the console's pace of the vehicles the page does not draw (`paceOf`): judged by that pace (`viewPace`),
  // not by its topic's interval, until a report of its topic at full rate replaces it
  paced?: boolean;
  // built from the snapshot's brief of its vehicle (`fromBrief`): the members the brief lacks are null because they are
  // not known yet, not because the vehicle reports none. The vehicle's detail (`briefLoaded`) or its topic's next whole
  // report over the WebSocket (the `select` brings the newest at once) replaces it
  brief?: boolean;
}

/** The pace a view is judged by (`freshness`): the console's pace of the vehicles the page does not draw
 * (`othersEvery`) for one that came at it, 0 for one that came at full rate. A vehicle just selected: its topics' last
 * reports may be a pace old until each one's next comes, whichever came first ("Stale · 3.0 s" on its satellites). */
export function viewPace(view: TopicView | null | undefined, othersEvery: number | null): number {
  return view?.paced ? (othersEvery ?? 0) : 0;
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
  relay: string | null; // the sem-relay it is seen through (its --name), null: on the console's own domain
  relayQuiet: number; // s that relay's rate caps may keep its data quiet (0: uncapped, or not seen through a relay)
  topics: { [T in Topic]?: TopicView<T> };
  trails: Record<string, TrailPoint[]>;
  history: HistoryPoint[];
  track: TrackSample[]; // positions of the last TRACK_SECONDS, at most one per second (the map's track)
  // built from the snapshot's brief of it (a page that draws another vehicle: its overviews' members, the rest null,
  // no link configuration); its selection loads it whole (GET /api/providers/{id}: briefLoaded, and the `select`)
  brief?: boolean;
}

export interface VehiclesState {
  providers: Record<string, ProviderView>;
  // The vehicle the operator chose (or the page's ?vehicle= link). Nothing else changes it: not a
  // report, not a reconnect, not a snapshot that lacks it (it may not have reported yet); only while
  // none is chosen, a lone vehicle on the bus is selected (withLoneSelected).
  selected: string | null;
  // A replay's instants shown (each seek, each reconnect): the chart's and map's history is loaded again
  // for each, and a REST answer for an earlier one is dropped
  instant: number;
  // The console's pace of the vehicles the page does not draw (its `pace` message): each one's report of a topic comes
  // at most this often, seconds; null: it paces none (it sends every report as it comes)
  othersEvery: number | null;
  // The same pace as the console said it, in wall seconds (it paces by wall time), and how many of the page's seconds
  // pass in one of wall time: 1 live, a replay's speed (the page's clock is the recording's), by which `othersEvery`
  // is said on the page's clock
  paceWall: number | null;
  clockRate: number;
  // The selected vehicle once a report of it came since it was selected: at full rate from then on (before, it may
  // still be at the others' pace)
  fullRate: string | null;
  // How far the console's clock is ahead of the page's (s), by the last snapshot's serverTime, then by each pong's
  // (`consoleClock`; null: none yet): a report the console held back for the pace arrives late, and was heard when the
  // console received it, not when it arrived
  consoleAhead: number | null;
}

export const initialVehicles: VehiclesState = {
  providers: {},
  selected: null,
  instant: 0,
  othersEvery: null,
  paceWall: null,
  clockRate: 1,
  fullRate: null,
  consoleAhead: null,
};

/** The state with the console's pace (`pace`, wall seconds; null: none) and the page's clock rate (1 live, a replay's
 * speed) set: `othersEvery` is the pace on the page's clock, by which it judges the vehicles it does not draw (at 20x a
 * pace of 0.25 s is a report every 5 s of the recording). */
export function withPace<S extends VehiclesState>(s: S, paceWall: number | null, clockRate: number): S {
  // to the hundredth below (plus a float's error): "at most every 0.13 s" of reports every 0.125 s was untrue
  const othersEvery = paceWall === null ? null : Math.floor(paceWall * clockRate * 100 + 1e-9) / 100;
  if (s.paceWall === paceWall && s.clockRate === clockRate && s.othersEvery === othersEvery) return s;
  return { ...s, paceWall, clockRate, othersEvery };
}

/** One pong's reading of the console's clock against the page's (s): the console answered between the ping's sending
 * and the pong's arrival, so its clock was `ahead` of the page's, give or take half the round trip `rtt`. */
export interface ClockSample {
  ahead: number;
  rtt: number;
}

/** How many pongs' readings `consoleClock` keeps (a ping a second: the last few seconds). */
export const CLOCK_SAMPLES = 8;

/** The readings kept with a pong's added (ping sent and pong arrived at `sent` and `arrived` on the page's clock, the
 * console's `serverTime` in it), and the estimate of how far the console's clock is ahead of the page's: the reading of
 * the shortest round trip (null: none). A reading that a newer one contradicts (their bounds do not meet) was taken
 * before one of the clocks stepped (NTP, a laptop waking): dropped, so the page keeps no wrong offset for long; a round
 * trip that ran backwards (the page's clock stepped back meanwhile) keeps none. */
export function consoleClock(
  kept: readonly ClockSample[],
  sent: number,
  serverTime: number,
  arrived: number,
): { samples: ClockSample[]; ahead: number | null } {
  const rtt = arrived - sent;
  if (!(rtt >= 0) || !Number.isFinite(serverTime)) return { samples: [], ahead: null };
  const reading = { ahead: serverTime - (sent + arrived) / 2, rtt };
  const samples = [...kept.filter((k) => Math.abs(k.ahead - reading.ahead) <= (k.rtt + rtt) / 2), reading].slice(-CLOCK_SAMPLES);
  const best = samples.reduce((a, b) => (b.rtt < a.rtt ? b : a));
  return { samples, ahead: best.ahead };
}

/** The state with the console's clock `ahead` of the page's (`consoleClock`). */
export function withConsoleAhead<S extends VehiclesState>(s: S, ahead: number): S {
  return s.consoleAhead === ahead ? s : { ...s, consoleAhead: ahead };
}

/** How much longer than the usual bound the page waits before it calls vehicle `id` silent: the console's pace of the
 * vehicles it does not draw, for every vehicle but the selected one once its own reports come at full rate; 0 when the
 * console paces none. */
export function paceOf(s: Pick<VehiclesState, "othersEvery" | "fullRate" | "selected">, id: string): number {
  if (s.othersEvery === null) return 0;
  return id === s.selected && id === s.fullRate ? 0 : s.othersEvery;
}

/** The state with a report of `providerId` come: the selected vehicle's first since its selection marks it at full
 * rate (`fullRate`), its intervals learned afresh from then on (those it had were of the others' pace, or none). */
export function heardAtFullRate<S extends VehiclesState>(state: S, providerId: string): S {
  if (providerId !== state.selected || state.fullRate === providerId) return state;
  const before = state.providers[providerId];
  if (!before) return { ...state, fullRate: providerId };
  const topics = Object.fromEntries(
    Object.entries(before.topics).map(([topic, view]) => [topic, { ...view, interval: null }]),
  ) as ProviderView["topics"];
  return { ...state, fullRate: providerId, providers: { ...state.providers, [providerId]: { ...before, topics } } };
}

export const TRAIL_SECONDS = 600;
export const TRAIL_STEP = 5;
// a trail's step may be this much short: a vehicle not selected sends its satellites once in every 5 s of the console's
// clock (hub.py FULL_EVERY), and they arrive a few ms either side of 5 s here: half its points were 10 s apart
const TRAIL_SLACK = 0.5;
export const HISTORY_SECONDS = 300;
export const HISTORY_STEP = 1;
export const TRACK_SECONDS = 900;

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

/** When the newest data of a vehicle seen through a relay was made, by its own time stamp (a report's `timeStamp`), on
 * the page's clock: the stamp's distance to the console's receipt of it, moved to when the page got it, so that
 * neither the console's clock nor the vehicle's need agree with the page's. A stamp ahead of its receipt (the
 * vehicle's clock ahead) counts as made at its receipt: never younger than its arrival. Null: no report with a time
 * stamp. */
export function relayDataAt(p: ProviderView): number | null {
  let newest: number | null = null;
  for (const t of Object.values(p.topics)) {
    const stamp = (t.envelope.report as { timeStamp?: { seconds?: number; nanoseconds?: number } | null }).timeStamp;
    if (typeof stamp?.seconds !== "number") continue;
    const at = t.at - Math.max(0, t.envelope.receivedAt - (stamp.seconds + (stamp.nanoseconds ?? 0) / 1e9));
    if (newest === null || at > newest) newest = at;
  }
  return newest;
}

/** The report a view of topic T holds (null: none), e.g. viewReport<"GPSReport">(view). */
export function viewReport<T extends Topic>(view: TopicView<T> | null | undefined): ReportTypes[T] | null {
  return view ? view.envelope.report : null;
}

export function emptyProvider(id: string, link: LinkState, name: string | null = null): ProviderView {
  return {
    id,
    name,
    link,
    linkConfig: null,
    jausId: null,
    umaaVersion: null,
    relay: null,
    relayQuiet: 0,
    topics: {},
    trails: {},
    history: [],
    track: [],
  };
}

/** The summary's fields a provider view keeps (name, link state, link configuration, JAUS id, UMAA version, relay). */
export function fromSummary(p: ProviderView, s: ProviderSummary): ProviderView {
  const relay = s.relay?.name ?? null;
  const relayQuiet = s.relay?.quietSeconds ?? 0;
  const { name, link, linkConfig, jausId, umaaVersion } = s;
  return { ...p, name, link, linkConfig, jausId, umaaVersion, relay, relayQuiet };
}

/** A vehicle of the snapshot's `fleet` (to a page that named another): what its list row, fleet-bar chip and map dot
 * draw, each report's other members null, arrived as long before `now` as the console had it before `serverTime`. */
export function fromBrief(old: ProviderView | undefined, b: VehicleBrief, now: number, serverTime: number): ProviderView {
  const view = <T extends Topic>(topic: T, report: ReportTypes[T], receivedAt: number, invalid: string[] = []) => ({
    envelope: { report, invalid, receivedAt },
    at: now - Math.max(0, serverTime - receivedAt),
    interval: old?.topics[topic]?.interval ?? null,
    brief: true,
  });
  const topics: ProviderView["topics"] = {};
  const stamp = b.fix?.timeStamp;
  if (b.fix) {
    const fix: GPSFixReportType = {
      GPSFixCommandStatus: null,
      GPSLatLongValid: b.fix.latLongValid,
      SOG: b.fix.sog,
      altitudeMSL: null,
      magneticVariation: null,
      position2DWithTime: { geodeticPosition: geodetic(b.fix.lat, b.fix.lon), timeAtPosition: null },
      source: b.id,
      timeStamp: typeof stamp?.seconds === "number" ? (stamp as unknown as DateTime) : null,
      trueCourse: b.fix.course,
      velocity: null,
    };
    topics.GPSFixReport = view("GPSFixReport", fix, b.fix.receivedAt, b.fix.invalid);
  }
  if (b.fixStatus) {
    const status: GPSFixStatusReportType = {
      carrierToNoise: null,
      countDown: null,
      fixValid: b.fixStatus.fixValid,
      lowBkupBattery: null,
      navSolution: null,
      originPosition: { geodeticPosition: geodetic(b.fixStatus.originLat, b.fixStatus.originLon), heightAboveEllipsoid: null },
      pCode: null,
      source: b.id,
      timeOut: null,
      timeStamp: null,
    };
    topics.GPSFixStatusReport = view("GPSFixStatusReport", status, b.fixStatus.receivedAt);
  }
  if (b.ins) {
    const ins: InertialSensorReportType = {
      source: b.id,
      state: b.ins.state as InertialSensorReportType["state"],
      status: b.ins.status as InertialSensorReportType["status"],
      timeStamp: null,
    };
    topics.InertialSensorReport = view("InertialSensorReport", ins, b.ins.receivedAt);
  }
  const { name, link, jausId, umaaVersion } = b;
  const summary = { name, link, jausId, umaaVersion, relay: b.relay?.name ?? null, relayQuiet: b.relay?.quietSeconds ?? 0 };
  // the brief has no link configuration: the one the page had may be stale (another station's change), so none until
  // the vehicle's detail is loaded (briefLoaded)
  return { ...(old ?? emptyProvider(b.id, b.link)), ...summary, linkConfig: null, topics, brief: true };
}

const geodetic = (latitude: number | null, longitude: number | null) => ({
  geodeticLatitude: { latitude },
  geodeticLongitude: { longitude },
});

/** The vehicle's detail (GET /api/providers/{id}) into one built from a brief (`fromBrief`): its link configuration,
 * and each report the brief had in part, whole (the same sample; a newer one comes by the WebSocket, `select`). */
export function briefLoaded<S extends VehiclesState>(state: S, providerId: string, detail: TypedProviderDetail): S {
  const before = state.providers[providerId];
  if (!before?.brief) return state;
  const topics = { ...before.topics };
  const whole = <T extends Topic>(topic: T) => {
    const view = before.topics[topic];
    const env = detail.reports[topic];
    if (!view || !env || env.receivedAt !== view.envelope.receivedAt) return;
    const w = { ...view, envelope: env };
    delete w.brief; // whole: its nulls are the vehicle's
    topics[topic] = w;
  };
  whole("GPSFixReport");
  whole("GPSFixStatusReport");
  whole("InertialSensorReport");
  const p: ProviderView = { ...before, topics, linkConfig: detail.linkConfig, brief: false };
  return { ...state, providers: { ...state.providers, [providerId]: p } };
}

function updateTrails(
  trails: Record<string, TrailPoint[]>,
  env: ReportEnvelopeOf<"GPSReport">,
  now: number,
): Record<string, TrailPoint[]> {
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
  const cn0s = sats
    .map((s) => s.antennaCarrierNoiseDensity)
    .filter((v): v is number => typeof v === "number" && Number.isFinite(v));
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
export function detailLoaded<S extends VehiclesState>(state: S, providerId: string, reports: TopicReports): S {
  const before = state.providers[providerId];
  const view = before?.topics.GPSReport;
  const env = reports.GPSReport;
  if (!before || !view?.partial || !env || env.receivedAt < view.envelope.receivedAt) return state;
  const gps: TopicView<"GPSReport"> = {
    envelope: env,
    at: view.at,
    interval: view.interval,
    ...(view.paced ? { paced: true } : {}),
  };
  return {
    ...state,
    providers: { ...state.providers, [providerId]: { ...before, topics: { ...before.topics, GPSReport: gps } } },
  };
}

/** The console's series of a vehicle (REST), merged into the live history. */
export function historyLoaded<S extends VehiclesState>(state: S, providerId: string, points: HistoryPoint[]): S {
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
export function trackLoaded<S extends VehiclesState>(state: S, providerId: string, points: TrackSample[]): S {
  const before = state.providers[providerId];
  if (!before || !points.length) return state;
  const all = [...points, ...before.track];
  const latest = Math.max(...all.map((p) => p.t));
  const bySecond = new Map<number, TrackSample>();
  for (const p of all) bySecond.set(Math.floor(p.t), p);
  const track = trimTrack([...bySecond.values()], latest, TRACK_SECONDS);
  return { ...state, providers: { ...state.providers, [providerId]: { ...before, track } } };
}

/** A vehicle's view (undefined: not known yet) with report `msg` applied; `paced`: it comes at the console's pace of
 * the vehicles the page does not draw (`paceOf`), so its topics' intervals are not learned from it (the selected
 * vehicle judged by three times a 10 s pace was shown live for 30 s of silence), and it was heard when the console
 * received it (`consoleAhead`: its clock ahead of the page's), up to a pace before it arrived: a vehicle lost while its
 * last report waited for the pace said "last heard 0 s ago", and its age in the list counted from its arrival. */
export function reported(
  before: ProviderView | undefined,
  msg: TypedReportMessage,
  now: number,
  paced = false,
  consoleAhead: number | null = null,
): ProviderView {
  const { providerId, topic } = msg;
  const b = before ?? emptyProvider(providerId, "live");
  const prevView = b.topics[topic];
  // the sample it already has, sent again (the console sends the latest GPSReport whole to a client that has just
  // selected the vehicle): it arrived when it first did, or selecting a vehicle silent for minutes, or lost, would
  // show it heard from just now (its age, "stale", "lost for", a lost command's confirmation)
  const again = prevView !== undefined && prevView.envelope.receivedAt === msg.report.receivedAt;
  const at = again
    ? { at: prevView.at, interval: prevView.interval, ...(prevView.paced ? { paced: true } : {}) }
    : {
        at: paced && consoleAhead !== null ? Math.min(now, msg.report.receivedAt - consoleAhead) : now,
        // nor from the gap after one that came paced: it was heard when the console received it, a hold before
        interval:
          prevView && !paced && !prevView.paced
            ? nextInterval(prevView.interval, now - prevView.at)
            : (prevView?.interval ?? null),
        ...(paced ? { paced: true } : {}),
      };
  if (msg.topic === "GPSReport" && msg.partial) {
    // without its satellites: the trails and the chart wait for a whole one; the satellites it had stay
    const kept = (prevView as TopicView<"GPSReport"> | undefined)?.envelope.report.satellites ?? [];
    const envelope = kept.length ? { ...msg.report, report: { ...msg.report.report, satellites: kept } } : msg.report;
    return { ...b, topics: { ...b.topics, GPSReport: { envelope, ...at, partial: true } } };
  }
  let p: ProviderView = { ...b, topics: { ...b.topics, [topic]: { envelope: msg.report, ...at } } };
  if (msg.topic === "GPSReport")
    p = { ...p, trails: updateTrails(p.trails, msg.report, now), history: updateHistory(p.history, msg.report) };
  if (msg.topic === "GPSFixReport") p = { ...p, track: updateTrack(p.track, msg.report) };
  return p;
}

/** The vehicle to select by itself: the lone vehicle on the bus, while the operator has chosen none (and
 * the page's link named none); otherwise the selection stays as it is. */
export function withLoneSelected<S extends VehiclesState>(state: S): S {
  if (state.selected !== null) return state;
  let lone: string | null = null;
  for (const id in state.providers) {
    if (lone !== null) return state; // several: the operator chooses
    lone = id;
  }
  return lone === null ? state : { ...state, selected: lone };
}

/** The operator's choice of vehicle: a known one, or (from a link) any id, shown once it reports. Not at full rate
 * until a report of it comes (`heardAtFullRate`), though it was before another was selected: its reports held for the
 * pace meanwhile come first. */
export function select<S extends VehiclesState>(state: S, providerId: string | null): S {
  return providerId === state.selected ? state : { ...state, selected: providerId, fullRate: null };
}

// Selectors of what panels draw. Each value keeps its identity until what it holds changes, so a subscription to
// one (the store's subscribe with a selector, hooks' useSlice) is not woken by another topic's report.
const NO_TRAILS: Record<string, TrailPoint[]> = {};

function selectedView(s: VehiclesState): ProviderView | undefined {
  return s.selected ? s.providers[s.selected] : undefined;
}

function topicSelector<T extends Topic>(topic: T): (s: VehiclesState) => TopicView<T> | null {
  return (s) => selectedView(s)?.topics[topic] ?? null;
}

const topicSelectors: { [T in Topic]: (s: VehiclesState) => TopicView<T> | null } = {
  GPSReport: topicSelector("GPSReport"),
  GPSFixReport: topicSelector("GPSFixReport"),
  GPSFixStatusReport: topicSelector("GPSFixStatusReport"),
  InertialSensorReport: topicSelector("InertialSensorReport"),
};

/** The selected vehicle's latest report of `topic` (one selector per topic, so it can key a subscription). */
export function selectedTopic<T extends Topic>(topic: T): (s: VehiclesState) => TopicView<T> | null {
  return topicSelectors[topic];
}

/** Whether the selected vehicle's GPSReport is the snapshot's, without its satellites. */
export const selectedGpsPartial = (s: VehiclesState): boolean => selectedView(s)?.topics.GPSReport?.partial === true;

/** The selected vehicle's satellite trails (changed by its GPSReport only). */
export const selectedTrails = (s: VehiclesState): Record<string, TrailPoint[]> => selectedView(s)?.trails ?? NO_TRAILS;

/** The selected vehicle's link state (null: none selected, or not on the bus). */
export const selectedLink = (s: VehiclesState): LinkState | null => selectedView(s)?.link ?? null;

/** When the selected vehicle was last heard (the source's clock, s), while its link is lost; null when it is not
 * lost, 0 when no report of it was received. A number: a subscriber draws again only when it changes. */
export const selectedLostSince = (s: VehiclesState): number | null => {
  const p = selectedView(s);
  return p?.link === "lost" ? (lastHeardAt(p) ?? 0) : null;
};

/** The end of the selected vehicle's planned silence while it is lost in it (plannedUntil), else null. */
export const selectedPlannedUntil = (s: VehiclesState & Pick<AlarmsState, "silences">): number | null => {
  const p = selectedView(s);
  return p ? plannedUntil(s.silences, p.id, p.link) : null;
};

/** The selected vehicle's name, null when it has none or is not known. */
export const selectedName = (s: VehiclesState): string | null => selectedView(s)?.name ?? null;

/** The selected vehicle's link configuration (changed by the console's provider messages only). */
export const selectedLinkConfig = (s: VehiclesState): LinkConfig | null => selectedView(s)?.linkConfig ?? null;

/** The selected vehicle's JAUS id. */
export const selectedJausId = (s: VehiclesState): string | null => selectedView(s)?.jausId ?? null;

/** Whether the selected vehicle is on the bus (known to the console). */
export const selectedKnown = (s: VehiclesState): boolean => selectedView(s) !== undefined;

/** Every vehicle's view (changes with any report: subscribe to it at a bounded rate). */
export const allProviders = (s: VehiclesState): Record<string, ProviderView> => s.providers;
