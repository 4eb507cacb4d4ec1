// The hooks that load over REST (TanStack Query, definitions in queries.ts): what the console holds now, loaded on a
// connection, a selection or a replay's seek and merged into the store, which the WebSocket keeps current.
import { useQueries, useQuery, type UseQueryResult } from "@tanstack/react-query";
import type { FeatureCollection } from "geojson";
import { useEffect, useMemo } from "react";
import type { ComapStatus, ComapVehicle, Health, Task } from "../api/rest";
import { useToken } from "./auth";
import { useConnectionState, useData, useSelector } from "./hooks";
import { capabilitiesQuery, comapStatusQuery, detailQuery, healthQuery, operatorQuery, seriesQuery, tasksQuery, trackQuery, worldModelQuery } from "./queries";
import { detailLoaded, historyLoaded, selectedGpsPartial, tasksReplaced, trackLoaded, worldModelLoaded, type HistoryPoint } from "./store";

/** GET /api/health, asked once (null until it answers): the DDS domain and network the console listens on. */
export function useConsoleHealth(): Health | null {
  return useQuery(healthQuery()).data ?? null; // unreachable: nothing to say of its network
}

/** The signed-in operator's name (GET /api/operator), null until the console answers or with no token. */
export function useOperatorName(): string | null {
  return useQuery(operatorQuery(useToken())).data ?? null;
}

const NO_HISTORY: HistoryPoint[] = [];

/** The selected vehicle's satellites when its GPSReport is still the snapshot's (which leaves them out): asked over
 * REST at once rather than waiting for its next GPSReport (a real receiver may report every few seconds). */
export function useSelectedSatellitesLoaded(): void {
  const { store } = useData();
  const selected = useSelector((s) => s.selected);
  const partial = useSelector(selectedGpsPartial);
  const live = useConnectionState() === "live";
  const token = useToken();
  const instant = useSelector((s) => s.instant);
  const loaded = useQuery({ ...detailQuery(selected ?? "", token, instant), enabled: !!selected && partial && live });
  useEachAnswer(loaded, (reports) => selected && store.update((s) => detailLoaded(s, selected, reports)));
}

/** Runs `apply` once for each new answer of a query (the current key's only: an answer for an earlier key, such as
 * a replay's earlier instant, is never given). */
function useEachAnswer<T>(result: UseQueryResult<T>, apply: (data: T) => void): void {
  const { data } = result;
  useEffect(() => {
    if (data !== undefined) apply(data);
  }, [data]); // eslint-disable-line react-hooks/exhaustive-deps -- once per answer, whatever `apply` closes over
}

/** A vehicle's chart history: what the console kept (loaded over REST when the vehicle is selected,
 * shown or reconnected, so a reload does not start empty), then the live points appended. */
export function useHistory(providerId: string | null): HistoryPoint[] {
  const { store, source } = useData();
  const known = useSelector((s) => (providerId ? providerId in s.providers : false));
  const live = useConnectionState() === "live";
  const token = useToken();
  const instant = useSelector((s) => s.instant); // a replay's seek: the history up to the new instant
  const loaded = useQuery({ ...seriesQuery(providerId ?? "", token, instant, source.now), enabled: !!providerId && known && live });
  // no history (yet), an error: the chart fills from live data
  useEachAnswer(loaded, (points) => providerId && store.update((s) => historyLoaded(s, providerId, points)));
  return useSelector((s) => (providerId ? (s.providers[providerId]?.history ?? NO_HISTORY) : NO_HISTORY));
}

/** Every vehicle's stored track (GET /api/providers/{id}/track, loaded when a vehicle appears, on a reload and after
 * a reconnect, once `load`: the map is ready) merged into the store, whose live GPSFixReport positions extend it;
 * `idList`: the vehicles' ids, comma-separated. Not before the map: a request per vehicle (50 at once) held up the
 * first screen's (the map's worker, the selected vehicle's satellites) behind the browser's six connections. For a
 * component of its own (Map.tsx's StoredTracks): 250 queries compared on each render of the map panel (each fix of
 * the selected vehicle) were the page's costliest function. */
export function useStoredTracks(idList: string, load: boolean): void {
  const { store, source } = useData();
  const ids = useMemo(() => (idList ? idList.split(",") : []), [idList]);
  const live = useConnectionState() === "live";
  const token = useToken();
  const instant = useSelector((s) => s.instant);
  const answers = useQueries({
    queries: ids.map((id) => ({ ...trackQuery(id, token, instant, source.now), enabled: live && load })),
    combine: (results) => results.map((r) => r.data),
  });
  useEffect(() => {
    // each answer once (an answer is a new array): no stored track (yet), an error: the map draws the live one
    answers.forEach((points, i) => {
      if (points && !merged.has(points)) {
        merged.add(points);
        store.update((s) => trackLoaded(s, ids[i], points));
      }
    });
  }, [answers, ids, store]);
}

const merged = new WeakSet<object>(); // the track answers merged into the store

/** The CoMap world model (WebSocket `worldmodel` messages, after one REST load per connection); null while the
 * console has none (404: CoMap is off). */
export function useWorldModel(): FeatureCollection | null {
  const { store } = useData();
  const token = useToken();
  const live = useConnectionState() === "live";
  const loaded = useQuery({ ...worldModelQuery(token, () => store.getState().worldModelSeq), enabled: live });
  useEachAnswer(loaded, ({ value, seq }) => store.update((s) => worldModelLoaded(s, value, seq)));
  return useSelector((s) => s.worldModel);
}

/** The CoMap tasks and their state (WebSocket `task` messages, after one REST load per connection), newest first. */
export function useTasks(): Task[] {
  const { store } = useData();
  const token = useToken();
  const live = useConnectionState() === "live";
  const loaded = useQuery({ ...tasksQuery(token, () => store.getState().taskSeq), enabled: live });
  useEachAnswer(loaded, ({ value, seq }) => store.update((s) => tasksReplaced(s, value, seq)));
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
