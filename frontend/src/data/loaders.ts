// The hooks that load over REST. What the page shows as the console answered it is read through TanStack Query
// (queries.ts). What the WebSocket keeps current once loaded (a vehicle's history, track and satellites, the world
// model, the tasks) is loaded on a connection, a selection or a replay's seek and merged into the store, which holds
// it: an answer is merged once, and the request of a key left before it answered is aborted.
import { useQuery } from "@tanstack/react-query";
import type { FeatureCollection } from "geojson";
import { useEffect, useMemo, useRef } from "react";
import {
  providerDetail,
  series,
  tasks,
  track,
  worldModel,
  type ComapStatus,
  type ComapVehicle,
  type Health,
  type Task,
} from "../api/rest";
import type { TrackSample } from "../lib/geo";
import { useToken } from "./auth";
import { useShallow } from "zustand/react/shallow";
import { perProviders, useConnectionState, useData, useSelector } from "./hooks";
import { capabilitiesQuery, comapStatusQuery, healthQuery, operatorQuery } from "./queries";
import { tasksReplaced, worldModelLoaded } from "./slices/comap";
import {
  HISTORY_SECONDS,
  TRACK_SECONDS,
  briefLoaded,
  detailLoaded,
  historyLoaded,
  selectedGpsPartial,
  trackLoaded,
  type HistoryPoint,
} from "./slices/vehicles";
import type { State } from "./state";
import { update } from "./store";

/** GET /api/health, asked once (null until it answers): the DDS domain and network the console listens on. */
export function useConsoleHealth(): Health | null {
  return useQuery(healthQuery()).data ?? null; // unreachable: nothing to say of its network
}

/** The signed-in operator's name (GET /api/operator), null until the console answers or with no token. */
export function useOperatorName(): string | null {
  return useQuery(operatorQuery(useToken())).data ?? null;
}

const isoSecondsAgo = (now: number, seconds: number) => new Date((now - seconds) * 1000).toISOString();

/** A vehicle's chart history (GET /api/providers/{id}/series) of the HISTORY_SECONDS before `now`. */
export async function loadSeries(
  providerId: string,
  token: string | null,
  now: number,
  signal?: AbortSignal,
): Promise<HistoryPoint[]> {
  const points = await series(providerId, isoSecondsAgo(now, HISTORY_SECONDS), token, signal);
  return points.map((p) => ({ t: p.time, cn0: p.cn0Mean, used: p.satellitesUsed, inView: p.satellitesInView }));
}

/** A vehicle's stored track (GET /api/providers/{id}/track) of the TRACK_SECONDS before `now`. */
export async function loadTrack(
  providerId: string,
  token: string | null,
  now: number,
  signal?: AbortSignal,
): Promise<TrackSample[]> {
  const points = await track(providerId, isoSecondsAgo(now, TRACK_SECONDS), token, signal);
  return points.map((p) => ({ lat: p.latitude, lon: p.longitude, t: p.time }));
}

/** Load once for each `key` (null: nothing to load now) and merge the answer into the store with `merge`; the request
 * of a key left before it answered is aborted, and a failed one leaves the live data to fill in. `key` holds all that
 * `load` depends on. */
function useLoadInto<T>(
  key: string | null,
  load: (signal: AbortSignal) => Promise<T>,
  merge: (s: State, answer: T) => State,
): void {
  const { store } = useData();
  useEffect(() => {
    if (key === null) return;
    const asked = new AbortController();
    load(asked.signal).then(
      (answer) => asked.signal.aborted || update(store, (s) => merge(s, answer)),
      () => undefined,
    );
    return () => asked.abort();
  }, [key, store]); // eslint-disable-line react-hooks/exhaustive-deps -- `key` holds what `load` and `merge` depend on
}

/** The selected vehicle's detail when the WebSocket gave it in part: its satellites when its GPSReport is still the
 * snapshot's (which leaves them out), asked over REST at once rather than waiting for its next GPSReport (a real
 * receiver may report every few seconds); its link configuration and whole reports when it was built from the
 * snapshot's brief. Called once, by the data layer's provider (provider.tsx): not by a panel, which may be folded. */
export function useSelectedDetailLoaded(): void {
  const selected = useSelector((s) => s.selected);
  // its GPSReport without its satellites, or the vehicle built from the snapshot's brief of it (its link configuration)
  const partial = useSelector((s) => selectedGpsPartial(s) || (s.selected !== null && s.providers[s.selected]?.brief === true));
  const live = useConnectionState() === "live";
  const token = useToken();
  const instant = useSelector((s) => s.instant);
  const key = selected && partial && live ? JSON.stringify([selected, token, instant]) : null;
  useLoadInto(
    key,
    (signal) => providerDetail(selected!, token, signal),
    (s, detail) => detailLoaded(briefLoaded(s, selected!, detail), selected!, detail.reports),
  );
}

const NO_HISTORY: HistoryPoint[] = [];

/** A vehicle's chart history: what the console kept (loaded over REST when the vehicle is selected,
 * shown or reconnected, so a reload does not start empty), then the live points appended. */
export function useHistory(providerId: string | null): HistoryPoint[] {
  const { source } = useData();
  const known = useSelector((s) => (providerId ? providerId in s.providers : false));
  const live = useConnectionState() === "live";
  const token = useToken();
  const instant = useSelector((s) => s.instant); // a replay's seek: the history up to the new instant
  const key = providerId && known && live ? JSON.stringify([providerId, token, instant]) : null;
  // no history (yet), an error: the chart fills from live data
  useLoadInto(
    key,
    (signal) => loadSeries(providerId!, token, source.consoleNow(), signal), // the console stamped the points
    (s, points) => historyLoaded(s, providerId!, points),
  );
  return useSelector((s) => (providerId ? (s.providers[providerId]?.history ?? NO_HISTORY) : NO_HISTORY));
}

const vehicleIds = perProviders((providers) => Object.keys(providers));

/** Every vehicle's stored track (GET /api/providers/{id}/track, loaded when a vehicle appears, on a reload and after
 * a reconnect, once `load`: the map is ready) merged into the store, whose live GPSFixReport positions extend it. Not
 * before the map: a request per vehicle (50 at once) held up the
 * first screen's (the map's worker, the selected vehicle's satellites) behind the browser's six connections. For a
 * component of its own (Map.tsx's StoredTracks), not to run on each render of the map panel. */
export function useStoredTracks(load: boolean): void {
  const { store, source } = useData();
  const ids = useSelector(useShallow(vehicleIds)); // the same array while no vehicle comes or goes
  const live = useConnectionState() === "live";
  const token = useToken();
  const instant = useSelector((s) => s.instant);
  const session = live && load ? JSON.stringify([token, instant]) : null; // each vehicle's track asked once in each
  const loads = useRef<{ session: string; asked: Set<string>; abort: AbortController } | null>(null);
  useEffect(() => {
    if (loads.current?.session !== session) {
      loads.current?.abort.abort();
      loads.current = session === null ? null : { session, asked: new Set(), abort: new AbortController() };
    }
    const l = loads.current;
    if (!l) return;
    for (const id of ids) {
      if (l.asked.has(id)) continue;
      l.asked.add(id);
      // no stored track (yet), an error: the map draws the live one
      loadTrack(id, token, source.consoleNow(), l.abort.signal).then(
        (points) => l.abort.signal.aborted || update(store, (s) => trackLoaded(s, id, points)),
        () => undefined,
      );
    }
  }, [ids, session, token, store, source]);
  useEffect(
    () => () => {
      loads.current?.abort.abort();
      loads.current = null;
    },
    [],
  );
}

/** The CoMap world model (WebSocket `worldmodel` messages, after one REST load per connection); null while the
 * console has none (404: CoMap is off). A `worldmodel` message that came while it was asked is newer: the answer is
 * dropped (worldModelLoaded). */
export function useWorldModel(): FeatureCollection | null {
  const { store } = useData();
  const token = useToken();
  const live = useConnectionState() === "live";
  useLoadInto(
    live ? JSON.stringify([token]) : null,
    async (signal) => {
      const seq = store.getState().worldModelSeq;
      return { model: await worldModel(token, signal), seq };
    },
    (s, { model, seq }) => worldModelLoaded(s, model, seq),
  );
  return useSelector((s) => s.worldModel);
}

/** The CoMap tasks and their state (WebSocket `task` messages, after one REST load per connection), newest first. */
export function useTasks(): Task[] {
  const { store } = useData();
  const token = useToken();
  const live = useConnectionState() === "live";
  useLoadInto(
    live ? JSON.stringify([token]) : null,
    async (signal) => {
      const seq = store.getState().taskSeq;
      return { value: await tasks(token, signal), seq };
    },
    (s, { value, seq }) => tasksReplaced(s, value, seq),
  );
  const byId = useSelector((s) => s.tasks);
  return useMemo(() => Object.values(byId).sort((a, b) => b.createdAt - a.createdAt), [byId]);
}

/** A vehicle's CoMap capabilities (GET /api/providers/{id}/capabilities): asked when it is selected and every
 * `periodMs` (vehicles send VehicleCapabilities every few seconds; no WebSocket message carries them). Null
 * while unknown, or when the console has no CoMap. */
export function useVehicleCapabilities(providerId: string | null, periodMs = 5000): ComapVehicle | null {
  const token = useToken();
  const live = useConnectionState() === "live";
  const { data } = useQuery({ ...capabilitiesQuery(providerId ?? "", token, periodMs), enabled: live && !!providerId });
  return providerId ? (data ?? null) : null;
}

/** The console's IMC node, asked once per connection: null while unknown, "absent" for a console without
 * CoMap routes (404). */
export function useComapStatus(): ComapStatus | "absent" | null {
  const token = useToken();
  const live = useConnectionState() === "live";
  return useQuery({ ...comapStatusQuery(token), enabled: live }).data ?? null;
}

/** Whether the console serves a PMTiles chart (GET /api/health `basemap`, asked once). */
export function useChartConfigured(): boolean {
  return useConsoleHealth()?.basemap === true;
}
