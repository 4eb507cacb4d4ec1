// The only way panels read state: hooks over the store and the connection.
import { createContext, useContext, useEffect, useMemo, useState, useSyncExternalStore } from "react";
import { health, series, tasks, track, vehicleCapabilities, worldModel, type ComapVehicle, type Task } from "../api/rest";
import type { FeatureCollection } from "geojson";
import type { Command, GatewayState, RecordingStatus, ReplayStatus } from "../api/types";
import { useToken } from "./auth";
import type { Store } from "./connection";
import type { Capabilities, DataSource, PlaybackControls, SourceState } from "./source";
import { HISTORY_SECONDS, TRACK_SECONDS, historyLoaded, tasksLoaded, trackLoaded, worldModelLoaded, type Alert, type HistoryPoint, type ProviderView, type State } from "./store";

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

export function useGateways(): GatewayState[] {
  return useSelector((s) => s.gateways);
}

const NO_HISTORY: HistoryPoint[] = [];

/** A vehicle's chart history: what the console kept (loaded over REST when the vehicle is selected,
 * shown or reconnected, so a reload does not start empty), then the live points appended. */
export function useHistory(providerId: string | null): HistoryPoint[] {
  const { store, source } = useData();
  const known = useSelector((s) => (providerId ? providerId in s.providers : false));
  const live = useConnectionState() === "live";
  const token = useToken();
  useEffect(() => {
    if (!providerId || !known || !live) return;
    let current = true;
    const since = new Date((source.now() - HISTORY_SECONDS) * 1000).toISOString();
    series(providerId, since, token)
      .then((points) => {
        if (!current) return;
        const loaded = points.map((p) => ({ t: p.time, cn0: p.cn0Mean, used: p.satellitesUsed, inView: p.satellitesInView }));
        store.update((s) => historyLoaded(s, providerId, loaded));
      })
      .catch(() => undefined); // no history (yet): the chart fills from live data
    return () => {
      current = false;
    };
  }, [providerId, known, live, token, store, source]);
  return useSelector((s) => (providerId ? (s.providers[providerId]?.history ?? NO_HISTORY) : NO_HISTORY));
}

/** Every vehicle's track for the map: the console's stored track (GET /api/providers/{id}/track, loaded
 * when a vehicle appears, on a reload and after a reconnect), then the live GPSFixReport positions. */
export function useTrackedProviders(): ProviderView[] {
  const { store, source } = useData();
  const providers = useProviders();
  const ids = providers.map((p) => p.id).join(",");
  const live = useConnectionState() === "live";
  const token = useToken();
  useEffect(() => {
    if (!live || !ids) return;
    let current = true;
    const since = new Date((source.now() - TRACK_SECONDS) * 1000).toISOString();
    for (const id of ids.split(",")) {
      track(id, since, token)
        .then((points) => {
          if (!current) return;
          const loaded = points.map((p) => ({ lat: p.latitude, lon: p.longitude, t: p.time }));
          store.update((s) => trackLoaded(s, id, loaded));
        })
        .catch(() => undefined); // no stored track (yet): the map draws the live one
    }
    return () => {
      current = false;
    };
  }, [ids, live, token, store, source]);
  return providers;
}

/** Once per connection (a reload, a reconnect): what the console holds now, over REST; the WebSocket's
 * messages keep it current from then on. */
function useLoadOnConnect(load: (token: string | null, store: Store) => Promise<void>): void {
  const { store } = useData();
  const token = useToken();
  const live = useConnectionState() === "live";
  useEffect(() => {
    if (live) load(token, store).catch(() => undefined); // none (yet): the messages fill it
  }, [load, token, live, store]);
}

const loadWorldModel = async (token: string | null, store: Store) => {
  const seq = store.getState().worldModelSeq;
  const model = await worldModel(token);
  store.update((s) => worldModelLoaded(s, model, seq));
};
const loadTasks = async (token: string | null, store: Store) => {
  const list = await tasks(token);
  store.update((s) => tasksLoaded(s, list));
};

/** The CoMap world model (WebSocket `worldmodel` messages); null while the console has none (404: CoMap is off). */
export function useWorldModel(): FeatureCollection | null {
  useLoadOnConnect(loadWorldModel);
  return useSelector((s) => s.worldModel);
}

/** The CoMap tasks and their state (WebSocket `task` messages), newest first. */
export function useTasks(): Task[] {
  useLoadOnConnect(loadTasks);
  const byId = useSelector((s) => s.tasks);
  return useMemo(() => Object.values(byId).sort((a, b) => b.createdAt - a.createdAt), [byId]);
}

/** A vehicle's CoMap capabilities (GET /api/providers/{id}/capabilities): asked when it is selected and every
 * `periodMs` (vehicles send VehicleCapabilities every few seconds; no WebSocket message carries them). Null
 * while unknown, or when the console has no CoMap. */
export function useVehicleCapabilities(providerId: string | null, periodMs = 5000): ComapVehicle | null {
  const token = useToken();
  const live = useConnectionState() === "live";
  const [value, setValue] = useState<{ id: string; caps: ComapVehicle } | null>(null);
  useEffect(() => {
    if (!live || !providerId) return;
    let current = true;
    const ask = () =>
      vehicleCapabilities(providerId, token)
        .then((caps) => current && setValue({ id: providerId, caps }))
        .catch(() => undefined); // kept as it was; asked again
    void ask();
    const t = setInterval(ask, periodMs);
    return () => {
      current = false;
      clearInterval(t);
    };
  }, [providerId, token, live, periodMs]);
  return value && value.id === providerId ? value.caps : null;
}

/** Whether the console serves a PMTiles chart (GET /api/health `basemap`, asked once). */
export function useChartConfigured(): boolean {
  const [configured, setConfigured] = useState(false);
  useEffect(() => {
    let current = true;
    health()
      .then((h) => current && setConfigured(h.basemap === true))
      .catch(() => undefined);
    return () => {
      current = false;
    };
  }, []);
  return configured;
}
