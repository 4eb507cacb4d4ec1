// REST loading and caching (TanStack Query): one definition per request, with its key. The WebSocket stays the
// live source (the store); these only load what the console holds now, on a connection, a selection or a seek.
// Every key holds the operator's token, so a sign-in or sign-out asks again and never shows another's answer.
import { QueryClient, queryOptions } from "@tanstack/react-query";
import type { FeatureCollection } from "geojson";
import { ApiError, checkToken, comapStatus, health, peerFindings, providerDetail, series, tasks, track, vehicleCapabilities, worldModel, type ComapStatus, type Task } from "../api/rest";
import type { TopicReports } from "../api/types";
import type { TrackSample } from "../lib/geo";
import { HISTORY_SECONDS, TRACK_SECONDS, type HistoryPoint } from "./store";

/** The dashboard's one QueryClient: no retry (a loader that fails leaves the live data to fill in, as before) and no
 * refetch on window focus (the WebSocket keeps everything current). */
export function makeQueryClient(): QueryClient {
  return new QueryClient({ defaultOptions: { queries: { retry: false, refetchOnWindowFocus: false } } });
}

const isoSecondsAgo = (now: number, seconds: number) => new Date((now - seconds) * 1000).toISOString();

/** GET /api/health: what the console is (auth, replay, basemap, DDS network). It does not change while the page
 * is open: asked once, shared by every reader (main.tsx seeds it with the answer it starts with). */
export const healthQuery = () => queryOptions({ queryKey: ["health"], queryFn: () => health(), staleTime: Infinity });

/** GET /api/operator: the name the operator's token belongs to (the header says who is signed in); asked once per
 * token. */
export const operatorQuery = (token: string | null) =>
  queryOptions({ queryKey: ["operator", token], queryFn: () => checkToken(token!), enabled: token !== null, staleTime: Infinity });

/** Other vendors' participants the console sees but cannot read, with the fix (GET /api/metrics): asked every
 * PEER_FINDINGS_MS, as the console itself looks at discovery every second; not pushed over the WebSocket. */
export const PEER_FINDINGS_MS = 5000;
export const peerFindingsQuery = (token: string | null) =>
  queryOptions({ queryKey: ["peerFindings", token], queryFn: () => peerFindings(token), refetchInterval: PEER_FINDINGS_MS });

// The history and track loaders: their answers are merged into the store (the live history), so each answer is
// merged once and none is kept for later (gcTime 0); `instant` (a replay's seek) makes an earlier instant's answer
// another query's, never merged into the new instant's state.

/** A vehicle's chart history (GET /api/providers/{id}/series) of the HISTORY_SECONDS before `now()`. */
export const seriesQuery = (providerId: string, token: string | null, instant: number, now: () => number) =>
  queryOptions({
    queryKey: ["series", providerId, token, instant],
    queryFn: async (): Promise<HistoryPoint[]> =>
      (await series(providerId, isoSecondsAgo(now(), HISTORY_SECONDS), token)).map((p) => ({
        t: p.time,
        cn0: p.cn0Mean,
        used: p.satellitesUsed,
        inView: p.satellitesInView,
      })),
    gcTime: 0,
    structuralSharing: false, // each answer is new data to merge, even one equal to the last
  });

/** A vehicle's latest reports in full (GET /api/providers/{id}), merged once into the store (detailLoaded). */
export const detailQuery = (providerId: string, token: string | null, instant: number) =>
  queryOptions({
    queryKey: ["detail", providerId, token, instant],
    queryFn: async (): Promise<TopicReports> => (await providerDetail(providerId, token)).reports,
    gcTime: 0,
    structuralSharing: false,
  });

/** A vehicle's stored track (GET /api/providers/{id}/track) of the TRACK_SECONDS before `now()`. */
export const trackQuery = (providerId: string, token: string | null, instant: number, now: () => number) =>
  queryOptions({
    queryKey: ["track", providerId, token, instant],
    queryFn: async (): Promise<TrackSample[]> =>
      (await track(providerId, isoSecondsAgo(now(), TRACK_SECONDS), token)).map((p) => ({ lat: p.latitude, lon: p.longitude, t: p.time })),
    gcTime: 0,
    structuralSharing: false,
  });

/** An answer and the count of WebSocket messages of its kind received when it was asked: the store drops it if a
 * message came since (the message is newer). */
export interface Seq<T> {
  value: T;
  seq: number;
}

/** The CoMap world model (GET /api/worldmodel; null: none, or no CoMap), asked on each connection. */
export const worldModelQuery = (token: string | null, seqNow: () => number) =>
  queryOptions({
    queryKey: ["worldmodel", token],
    queryFn: async (): Promise<Seq<FeatureCollection | null>> => {
      const seq = seqNow();
      return { value: await worldModel(token), seq };
    },
    gcTime: 0,
    structuralSharing: false,
  });

/** The CoMap tasks (GET /api/tasks), asked on each connection. */
export const tasksQuery = (token: string | null, seqNow: () => number) =>
  queryOptions({
    queryKey: ["tasks", token],
    queryFn: async (): Promise<Seq<Task[]>> => {
      const seq = seqNow();
      return { value: await tasks(token), seq };
    },
    gcTime: 0,
    structuralSharing: false,
  });

/** A vehicle's CoMap capabilities (GET /api/providers/{id}/capabilities), asked again every `periodMs` (no WebSocket
 * message carries them); a failed ask keeps the last answer. */
export const capabilitiesQuery = (providerId: string, token: string | null, periodMs: number) =>
  queryOptions({
    queryKey: ["capabilities", providerId, token],
    queryFn: () => vehicleCapabilities(providerId, token),
    refetchInterval: periodMs,
    gcTime: 0,
  });

/** The console's IMC node (GET /api/comap/status): "absent" for a console without CoMap routes (404). */
export const comapStatusQuery = (token: string | null) =>
  queryOptions({
    queryKey: ["comap-status", token],
    queryFn: async (): Promise<ComapStatus | "absent"> => {
      try {
        return await comapStatus(token);
      } catch (e) {
        if (e instanceof ApiError && e.status === 404) return "absent";
        throw e;
      }
    },
  });
