// The only way panels read state: hooks over the store and the connection.
import { createContext, useContext, useEffect, useMemo, useState, useSyncExternalStore } from "react";
import type { Command, RecordingStatus, ReplayStatus } from "../api/types";
import type { Store } from "./connection";
import type { Capabilities, DataSource, PlaybackControls, SourceState } from "./source";
import type { Alert, ProviderView, State } from "./store";

export interface DataContextValue {
  store: Store;
  source: DataSource; // live or replay: panels do not know which
}

export const DataContext = createContext<DataContextValue | null>(null);

function useData(): DataContextValue {
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

export function useProviders(): ProviderView[] {
  const providers = useSelector((s) => s.providers);
  return useMemo(() => Object.values(providers).sort((a, b) => a.id.localeCompare(b.id)), [providers]);
}

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

export function useAlerts(): Alert[] {
  return useSelector((s) => s.alerts);
}

/** The data source's time in UTC seconds (the wall clock live, the recording's in a replay), refreshed every
 * `periodMs` (for ages and freshness). */
export function useNow(periodMs = 500): number {
  const { source } = useData();
  const [now, setNow] = useState(() => source.now());
  useEffect(() => {
    const t = setInterval(() => setNow(source.now()), periodMs);
    return () => clearInterval(t);
  }, [periodMs, source]);
  return now;
}
