// The only way panels read state: hooks over the store (zustand, store.ts) and the data source (REST: loaders.ts).
import { createContext, useCallback, useContext, useEffect, useMemo, useState, useSyncExternalStore } from "react";
import { useStore } from "zustand";
import { useShallow } from "zustand/react/shallow";
import type { Alarm, PlannedSilence } from "../api/generated/ws";
import type { Command, GatewayState, RecordingStatus, ReplayStatus } from "../api/types";
import { frameSource, onFrame } from "./frame";
import { unreachable, type Capabilities, type DataSource, type PlaybackControls, type SourceState } from "./source";
import { unacknowledged } from "./slices/alarms";
import {
  allProviders,
  lastHeardAt,
  paceOf,
  report,
  select,
  selectedLink,
  selectedTopic,
  selectedTrails,
  type ProviderView,
  type TopicView,
  type TrailPoint,
} from "./slices/vehicles";
import type { State } from "./state";
import { update, type StateStore } from "./store";
import type { LinkConfig, LinkState, Topic } from "../api/types";

export interface DataContextValue {
  store: StateStore;
  source: DataSource; // live or replay: panels do not know which
}

export const DataContext = createContext<DataContextValue | null>(null);

export function useData(): DataContextValue {
  const ctx = useContext(DataContext);
  if (!ctx) throw new Error("DataContext missing");
  return ctx;
}

/** The operator's choice of vehicle (a click in the fleet bar, the list, the map or an alarm). */
export function useSelectVehicle(): (providerId: string | null) => void {
  const { store } = useData();
  return useCallback((providerId) => update(store, (s) => select(s, providerId)), [store]);
}

/** A slice of the state by a selector, at once on each change of its value (Object.is; a selector that builds an
 * object or array each time is wrapped in useShallow): for what the operator's own actions and the console's rarer
 * messages change; what reports change is drawn on the frame (useFrameValue). */
export function useSelector<T>(select: (s: State) => T): T {
  return useStore(useData().store, select);
}

/** `fn` of the state's vehicles, computed once per map of vehicles: a selector is called on every change of the
 * store (each frame with reports) and each render, and with 250 vehicles these walked them all each time. */
export function perProviders<T>(fn: (providers: State["providers"]) => T): (s: State) => T {
  let last: State["providers"] | null = null;
  let value: T;
  return (s) => {
    if (s.providers !== last) {
      last = s.providers;
      value = fn(s.providers);
    }
    return value;
  };
}

/** Every vehicle's name by id, "" for one without a name: a new object with each report, the same values while no
 * name changes (compared shallowly). */
const vehicleNames = perProviders((providers) => Object.fromEntries(Object.values(providers).map((p) => [p.id, p.name ?? ""])));

/** Each known vehicle's name now, by id, "" for one without a name (its name taken away is news too: it is known
 * by its id now); a rename shows at once wherever a vehicle is named from its id. */
export function useVehicleNames(): Map<string, string> {
  const names = useSelector(useShallow(vehicleNames));
  return useMemo(() => new Map(Object.entries(names)), [names]);
}

/** Each lost vehicle's last-heard time by id (null: never heard), the same values while no link or time changes. */
const lostVehicles = perProviders((providers) =>
  Object.fromEntries(
    Object.values(providers)
      .filter((p) => p.link === "lost")
      .map((p) => [p.id, lastHeardAt(p)]),
  ),
);

/** Each lost vehicle's last-heard time by id (the source's clock; null: never heard): what names a vehicle says so. */
export function useLostVehicles(): Map<string, number | null> {
  const lost = useSelector(useShallow(lostVehicles));
  return useMemo(() => new Map(Object.entries(lost)), [lost]);
}

/** Milliseconds to the next multiple of `ms` of the clock: age timers of the same period fall on the same
 * instants, so the panels showing ages change in one frame (one layout) rather than each in a frame of its own. */
function toBoundary(ms: number): number {
  return ms - (Date.now() % ms);
}

/** Call `fn` at the next multiple of `ms` of the clock; the result cancels it. */
function atBoundary(ms: number, fn: () => void): () => void {
  const t = setTimeout(fn, toBoundary(ms));
  return () => clearTimeout(t);
}

/** The rendering model (frame.ts): the slice `select` (a stable selector) drawn on the animation frame after it
 * changed, with the newest value then; at most once a frame, nothing while the page is hidden. `same` (stable
 * too) says when a new value draws as the old one did, so the panel skips that frame. */
export function useFrameValue<T>(select: (s: State) => T, same?: (a: T, b: T) => boolean, everyMs = 0): T {
  const { store } = useData();
  const src = useMemo(() => frameSource(store, select, same, everyMs), [store, select, same, everyMs]);
  return useSyncExternalStore(src.subscribe, src.getSnapshot);
}

/** The selected vehicle's latest report of one topic (null: none yet or none selected), on the frame. */
export function useSelectedTopic<T extends Topic>(topic: T): TopicView<T> | null {
  return useFrameValue(selectedTopic(topic));
}

/** The selected vehicle's satellite trails, on the frame. */
export function useSelectedTrails(): Record<string, TrailPoint[]> {
  return useFrameValue(selectedTrails);
}

/** The selected vehicle's link state (null: none selected or not on the bus). */
export function useSelectedLink(): LinkState | null {
  return useSelector(selectedLink);
}

/** What the console knows of the selected vehicle apart from its reports (changes with the console's
 * provider messages, not with each report); null when none is selected or it is not on the bus. */
export interface SelectedVehicle {
  id: string;
  name: string | null;
  link: LinkState;
  linkConfig: LinkConfig | null;
  jausId: string | null;
}

const selectedVehicle = (s: State): SelectedVehicle | null => {
  const p = s.selected ? s.providers[s.selected] : undefined;
  return p ? { id: p.id, name: p.name, link: p.link, linkConfig: p.linkConfig, jausId: p.jausId } : null;
};

export function useSelectedVehicle(): SelectedVehicle | null {
  return useSelector(useShallow(selectedVehicle));
}

const selectedId = (s: State): string | null => s.selected;

/** Every vehicle, sorted by id, on the frame; `same` (stable): when two views of every vehicle draw alike (an
 * overview showing a few fields of each skips the frames where none of those changed); `everyMs`: at most
 * once that often (frameSource). */
export function useProvidersOnFrame(
  same?: (a: Record<string, ProviderView>, b: Record<string, ProviderView>) => boolean,
  everyMs = 0,
): ProviderView[] {
  const providers = useFrameValue(allProviders, same, everyMs);
  return useMemo(() => Object.values(providers).sort((a, b) => a.id.localeCompare(b.id)), [providers]);
}

/** When two views of every vehicle draw alike in an overview (the fleet bar, the vehicle list): the same
 * vehicles with the same name, link, fix validity and INS state and status. Not the time of the last report: an age
 * changes with time, and the clock of ages redraws the overview (every 0.5 or 1 s) from the newest state; keyed by
 * it too, with 50 vehicles at 10 Hz some vehicle's age crossed a step on nearly every frame, and the whole
 * overview drew on each. */
export function sameOverview(): (a: Record<string, ProviderView>, b: Record<string, ProviderView>) => boolean {
  const keys = new WeakMap<ProviderView, string>(); // a view's key, computed once (a frame compares every vehicle)
  const key = (p: ProviderView) => {
    let k = keys.get(p);
    if (k !== undefined) return k;
    const ins = report(p, "InertialSensorReport");
    k = `${p.name}|${p.link}|${p.relay}|${report(p, "GPSFixStatusReport")?.fixValid}|${ins?.state}|${ins?.status}`;
    keys.set(p, k);
    return k;
  };
  return (a, b) => {
    if (a === b) return true;
    const ids = Object.keys(a);
    if (ids.length !== Object.keys(b).length) return false;
    return ids.every((id) => a[id] === b[id] || (b[id] !== undefined && key(a[id]) === key(b[id])));
  };
}

export function useConnectionState(): SourceState {
  const { source } = useData();
  return useSyncExternalStore(source.subscribe, source.getState);
}

/** How much longer than the usual bound the page waits before it calls a vehicle silent (`paceOf`): the console's
 * pace of the vehicles the page does not draw. */
export function usePaceOf(): (id: string) => number {
  const othersEvery = useSelector((s) => s.othersEvery);
  const fullRate = useSelector((s) => s.fullRate);
  const selected = useSelector((s) => s.selected);
  return useCallback((id: string) => paceOf({ othersEvery, fullRate, selected }, id), [othersEvery, fullRate, selected]);
}

/** The console's pace of the vehicles the page does not draw (null: it paces none). */
export function useOthersEvery(): number | null {
  return useSelector((s) => s.othersEvery);
}

/** Whether the page hears the console: false at once when its connection drops (nothing shown is current then). */
export function useReceiving(): boolean {
  return !unreachable(useConnectionState());
}

/** What the data source can do: send commands, record, play back. */
export function useCapabilities(): Capabilities {
  return useData().source.capabilities;
}

/** The playback and its controls (a replay); null for the live source. */
export function usePlayback(): { status: ReplayStatus; controls: PlaybackControls } | null {
  const { source } = useData();
  const status = useSyncExternalStore(source.subscribe, source.getPlayback);
  return useMemo(() => (status && source.playback ? { status, controls: source.playback } : null), [status, source]);
}

/** The UMAA version the selected vehicle speaks (null: none selected, or not said yet). */
export function useSelectedUmaaVersion(): ProviderView["umaaVersion"] {
  return useSelector((s) => (s.selected ? (s.providers[s.selected]?.umaaVersion ?? null) : null));
}

/** The selected vehicle's whole view: it changes with each of its reports. A panel that draws one topic
 * wants useSelectedTopic, and one that names the vehicle useSelectedVehicle. */
export function useSelectedProvider(): ProviderView | null {
  return useSelector((s) => (s.selected ? (s.providers[s.selected] ?? null) : null));
}

export function useCommands(providerId: string | null): Command[] {
  const commands = useSelector((s) => s.commands);
  return useMemo(
    () =>
      Object.values(commands)
        .filter((c) => !providerId || c.providerId === providerId)
        .sort((a, b) => b.createdAt - a.createdAt),
    [commands, providerId],
  );
}

/** The vehicles with a command in progress (one not yet terminal): a new set only when the commands change. */
export function useCommanded(): ReadonlySet<string> {
  const commands = useSelector((s) => s.commands);
  return useMemo(() => new Set(Object.values(commands).flatMap((c) => (c.terminal ? [] : [c.providerId]))), [commands]);
}

export function useRecording(): RecordingStatus | null {
  return useSelector((s) => s.recording);
}

/** The console's active alarm set, newest first. */
export function useAlarms(): Alarm[] {
  return useSelector((s) => s.alarms);
}

/** The vehicles with an unacknowledged alarm (a new set only when the alarms change). */
export function useAlarmed(): ReadonlySet<string> {
  const alarms = useAlarms();
  return useMemo(() => new Set(unacknowledged(alarms).flatMap((a) => (a.providerId ? [a.providerId] : []))), [alarms]);
}

export function useSilences(): PlannedSilence[] {
  return useSelector((s) => s.silences);
}

const providerCount = (s: State): number => Object.keys(s.providers).length;

/** Why the selected vehicle's panels have nothing to show: "no-vehicle" (none on the bus), "select"
 * (vehicles, none selected); null when one is selected (even one not on the bus yet, from a link). */
export function useSelectionGap(): "no-vehicle" | "select" | null {
  const selected = useSelector(selectedId);
  const count = useSelector(providerCount);
  return selected !== null ? null : count === 0 ? "no-vehicle" : "select";
}

/** The data source's time in UTC seconds (the wall clock live, the recording's in a replay), refreshed every
 * `periodMs` (for ages and freshness). */
export function useNow(periodMs = 500): number {
  const { source } = useData();
  const [now, setNow] = useState(() => source.now());
  useEffect(() => onTick(periodMs, () => setNow(source.now())), [periodMs, source]);
  return now;
}

/** The console's clock (`DataSource.consoleNow`) in UTC seconds, on `useNow`'s ticks and at each new reading of it:
 * for the ages of what the console stamped (an alarm's since, a command's start, a recording's), which the page's
 * clock would misjudge by however far it is off. */
export function useConsoleNow(periodMs = 500): number {
  const { source } = useData();
  const now = useNow(periodMs);
  useSelector((s) => s.consoleAhead); // drawn again when a ping reads the console's clock anew
  return now + source.consoleNow() - source.now();
}

interface Ticker {
  listeners: Set<() => void>;
  stop: () => void; // cancels the wait for the next tick
}

const tickers = new Map<number, Ticker>();

/** Call `l` every `periodMs` (on multiples of it of the clock), on one timer for all callers of that
 * period, so the panels showing ages update together (one render and one layout) and not each on a timer
 * of its own; called on the animation frame (frame.ts), so a hidden page's ages do not draw. The clock of
 * ages is the one timer of the rendering model: an age changes with time, not with a report. */
function onTick(periodMs: number, l: () => void): () => void {
  let ticker = tickers.get(periodMs);
  if (!ticker) {
    const listeners = new Set<() => void>();
    const t: Ticker = { listeners, stop: () => undefined };
    const draw = () => listeners.forEach((f) => f());
    const tick = () => {
      onFrame(draw);
      if (tickers.get(periodMs) === t) t.stop = atBoundary(periodMs, tick); // not if the last listener left
    };
    t.stop = atBoundary(periodMs, tick);
    ticker = t;
    tickers.set(periodMs, ticker);
  }
  ticker.listeners.add(l);
  const t = ticker;
  return () => {
    t.listeners.delete(l);
    if (t.listeners.size) return;
    t.stop();
    tickers.delete(periodMs);
  };
}

export function useGateways(): GatewayState[] {
  return useSelector((s) => s.gateways);
}
