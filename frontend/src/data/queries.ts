// The REST answers the page reads as they are (TanStack Query, cached by key): the console's health, the operator's
// name, the DDS findings, a vehicle's CoMap capabilities and the CoMap node. What is merged into the store instead (a
// vehicle's history, track and satellites, the world model and the tasks) is loaded by loaders.ts.
// Every key holds the operator's token, so a sign-in or sign-out asks again and never shows another's answer.
import { QueryClient, queryOptions } from "@tanstack/react-query";
import { ApiError, checkToken, comapStatus, health, peerFindings, vehicleCapabilities, type ComapStatus } from "../api/rest";

/** The dashboard's one QueryClient: no retry (a loader that fails leaves the live data to fill in, as before) and no
 * refetch on window focus (the WebSocket keeps everything current). */
export function makeQueryClient(): QueryClient {
  return new QueryClient({ defaultOptions: { queries: { retry: false, refetchOnWindowFocus: false } } });
}

/** GET /api/health: what the console is (auth, replay, basemap, DDS network). It does not change while the page
 * is open: asked once, shared by every reader (main.tsx seeds it with the answer it starts with). */
export const healthQuery = () => queryOptions({ queryKey: ["health"], queryFn: () => health(), staleTime: Infinity });

/** GET /api/operator: the name the operator's token belongs to (the header says who is signed in); asked once per
 * token. */
export const operatorQuery = (token: string | null) =>
  queryOptions({
    queryKey: ["operator", token],
    queryFn: () => checkToken(token!),
    enabled: token !== null,
    staleTime: Infinity,
  });

/** Other vendors' participants the console sees but cannot read, with the fix (GET /api/metrics): asked every
 * PEER_FINDINGS_MS, as the console itself looks at discovery every second; not pushed over the WebSocket. */
export const PEER_FINDINGS_MS = 5000;
export const peerFindingsQuery = (token: string | null) =>
  queryOptions({ queryKey: ["peerFindings", token], queryFn: () => peerFindings(token), refetchInterval: PEER_FINDINGS_MS });

/** A vehicle's CoMap capabilities (GET /api/providers/{id}/capabilities), asked again every `periodMs` (no WebSocket
 * message carries them); a failed ask keeps the last answer, while the vehicle stays selected only: none is kept for
 * a vehicle selected again (gcTime 0), which would show its capabilities of minutes ago as its own now. */
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
