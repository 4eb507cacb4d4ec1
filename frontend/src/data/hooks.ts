// The only way panels read state: hooks over the store and the connection.
import { createContext, useContext, useEffect, useMemo, useState, useSyncExternalStore } from "react";
import type { Command, RecordingStatus } from "../api/types";
import type { Connection, ConnectionState, Store } from "./connection";
import type { Alert, ProviderView, State } from "./store";

export interface DataContextValue {
  store: Store;
  connection: Connection;
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

export function useConnectionState(): ConnectionState {
  const { connection } = useData();
  return useSyncExternalStore(connection.subscribe, connection.getState);
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

/** Current time in seconds since the epoch, refreshed every `periodMs` (for ages and freshness). */
export function useNow(periodMs = 500): number {
  const [now, setNow] = useState(() => Date.now() / 1000);
  useEffect(() => {
    const t = setInterval(() => setNow(Date.now() / 1000), periodMs);
    return () => clearInterval(t);
  }, [periodMs]);
  return now;
}
