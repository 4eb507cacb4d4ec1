// The only way panels read state: hooks over the store and the connection (REST loading: loaders.ts).
import { createContext, useContext, useEffect, useMemo, useState, useSyncExternalStore } from "react";
import type { Alarm } from "../api/generated/ws";
import type { Command, GatewayState, RecordingStatus, ReplayStatus } from "../api/types";
import type { Store } from "./connection";
import type { Capabilities, DataSource, PlaybackControls, SourceState } from "./source";
import {
  allProviders,
  selectedJausId,
  selectedKnown,
  selectedLink,
  selectedLinkConfig,
  selectedName,
  selectedTopic,
  selectedTrails,
  type ProviderView,
  type State,
  type TopicView,
  type TrailPoint,
} from "./store";
import type { LinkConfig, LinkState, Topic } from "../api/types";

export interface DataContextValue {
  store: Store;
  source: DataSource; // live or replay: panels do not know which
}

export const DataContext = createContext<DataContextValue | null>(null);

export function useData(): DataContextValue {
  const ctx = useContext(DataContext);
  if (!ctx) throw new Error("DataContext missing");
  return ctx;
}

export function useStore(): Store {
  return useData().store;
}

export function useSelector<T>(select: (s: State) => T): T {
  const { store } = useData();
  return useSyncExternalStore(store.subscribe, () => select(store.getState()));
}

/** Milliseconds to the next multiple of `ms` of the clock: throttled redraws and age timers of the same
 * period fall on the same instants, so the panels change in one frame (one layout) rather than each
 * in a frame of its own. */
function toBoundary(ms: number): number {
  return ms - (Date.now() % ms);
}

/** The pending calls for the next multiple of `ms` of the clock, run by one timer: throttled slices of one
 * period are refreshed in the same task, so React renders a panel reading two of them (the sky plot's
 * satellites and trails) once, not once per slice. */
const boundaries = new Map<number, Set<() => void>>();

function atBoundary(ms: number, fn: () => void): () => void {
  let due = boundaries.get(ms);
  if (!due) {
    const set = new Set<() => void>();
    boundaries.set(ms, set);
    setTimeout(() => {
      boundaries.delete(ms);
      for (const f of set) f();
    }, toBoundary(ms));
    due = set;
  }
  const set = due;
  set.add(fn);
  return () => set.delete(fn);
}

/** `fn` called at most about once every `ms`: at once when it was quiet, else at the next multiple of
 * `ms` of the clock (with every call in between folded into one); `cancel` drops a pending call. */
export function throttle(fn: () => void, ms: number): { (): void; cancel: () => void } {
  let waiting: (() => void) | null = null; // cancels the wait for the next boundary
  let pending = false;
  const end = () => {
    waiting = null;
    if (!pending) return;
    pending = false;
    fn();
    waiting = atBoundary(ms, end);
  };
  const call = () => {
    if (waiting) {
      pending = true;
      return;
    }
    fn();
    waiting = atBoundary(ms, end);
  };
  call.cancel = () => {
    waiting?.();
    waiting = null;
    pending = false;
  };
  return call;
}

/** A slice of the state as an external store for useSyncExternalStore, notified at most every `throttleMs`
 * (0: on every change). Throttled, the value read is the one the last notification took, not the live one:
 * a render for another reason (a mouse move, a timer) shows the same value and does not bypass the cap. */
export function sliceSource<T>(store: Store, select: (s: State) => T, throttleMs = 0): { subscribe: (onChange: () => void) => () => void; getSnapshot: () => T } {
  if (!throttleMs) return { subscribe: (onChange) => store.subscribeTo(select, onChange), getSnapshot: () => select(store.getState()) };
  let value = select(store.getState());
  return {
    subscribe: (onChange) => {
      value = select(store.getState()); // what changed while nobody listened (useSyncExternalStore then renders it)
      const t = throttle(() => {
        value = select(store.getState());
        onChange();
      }, throttleMs);
      const off = store.subscribeTo(select, t);
      return () => {
        off();
        t.cancel();
      };
    },
    getSnapshot: () => value,
  };
}

/** A slice of the state by a stable selector (a module-level function such as store.ts's
 * selectedTopic("GPSReport")): the component is woken only when the slice changes, and at most every
 * `throttleMs` when given (for overviews of every vehicle, which change with any report). */
export function useSlice<T>(select: (s: State) => T, throttleMs = 0): T {
  const { store } = useData();
  const src = useMemo(() => sliceSource(store, select, throttleMs), [store, select, throttleMs]);
  return useSyncExternalStore(src.subscribe, src.getSnapshot);
}

/** The selected vehicle's latest report of one topic (null: none yet or none selected), at most every
 * `throttleMs` when given (text and plots an operator reads need not change at the report's 10 Hz). */
export function useSelectedTopic<T extends Topic>(topic: T, throttleMs = 0): TopicView<T> | null {
  return useSlice(selectedTopic(topic), throttleMs);
}

/** The selected vehicle's satellite trails. */
export function useSelectedTrails(throttleMs = 0): Record<string, TrailPoint[]> {
  return useSlice(selectedTrails, throttleMs);
}

/** The selected vehicle's link state (null: none selected or not on the bus). */
export function useSelectedLink(): LinkState | null {
  return useSlice(selectedLink);
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

export function useSelectedVehicle(): SelectedVehicle | null {
  const id = useSlice(selectedId);
  const known = useSlice(selectedKnown);
  const name = useSlice(selectedName);
  const link = useSlice(selectedLink);
  const linkConfig = useSlice(selectedLinkConfig);
  const jausId = useSlice(selectedJausId);
  return useMemo(() => (id && known && link ? { id, name, link, linkConfig, jausId } : null), [id, known, name, link, linkConfig, jausId]);
}

const selectedId = (s: State): string | null => s.selected;

/** Every vehicle, sorted by id, refreshed at most every `throttleMs` (an overview: it changes with
 * every report of every vehicle). */
export function useProvidersAtMost(throttleMs: number): ProviderView[] {
  const providers = useSlice(allProviders, throttleMs);
  return useMemo(() => Object.values(providers).sort((a, b) => a.id.localeCompare(b.id)), [providers]);
}

export function useConnectionState(): SourceState {
  const { source } = useData();
  return useSyncExternalStore(source.subscribe, source.getState);
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

/** Every vehicle, sorted by id, on every report of any of them (an overview wants useProvidersAtMost). */
export function useProviders(): ProviderView[] {
  return useProvidersAtMost(0);
}

/** The selected vehicle's whole view: it changes with each of its reports. A panel that draws one topic
 * wants useSelectedTopic, and one that names the vehicle useSelectedVehicle. */
export function useSelectedProvider(): ProviderView | null {
  return useSelector((s) => (s.selected ? (s.providers[s.selected] ?? null) : null));
}

export function useCommands(providerId: string | null): Command[] {
  const commands = useSelector((s) => s.commands);
  return useMemo(
    () => Object.values(commands).filter((c) => !providerId || c.providerId === providerId).sort((a, b) => b.createdAt - a.createdAt),
    [commands, providerId],
  );
}

export function useRecording(): RecordingStatus | null {
  return useSelector((s) => s.recording);
}

/** The console's active alarm set, newest first. */
export function useAlarms(): Alarm[] {
  return useSelector((s) => s.alarms);
}

const providerCount = (s: State): number => Object.keys(s.providers).length;

/** Why the selected vehicle's panels have nothing to show: "no-vehicle" (none on the bus), "select"
 * (vehicles, none selected); null when one is selected (even one not on the bus yet, from a link). */
export function useSelectionGap(): "no-vehicle" | "select" | null {
  const selected = useSlice(selectedId);
  const count = useSlice(providerCount);
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

interface Ticker {
  listeners: Set<() => void>;
  stop: () => void; // cancels the wait for the next tick
}

const tickers = new Map<number, Ticker>();

/** Call `l` every `periodMs` (on multiples of it of the clock), on one timer for all callers of that
 * period and the throttled slices of the same period, so the panels showing ages update together (one
 * render and one layout) and not each on a timer of its own. */
function onTick(periodMs: number, l: () => void): () => void {
  let ticker = tickers.get(periodMs);
  if (!ticker) {
    const listeners = new Set<() => void>();
    const t: Ticker = { listeners, stop: () => undefined };
    const tick = () => {
      listeners.forEach((f) => f());
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
