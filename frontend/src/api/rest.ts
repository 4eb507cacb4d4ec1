// REST calls for commands, typed from the console's OpenAPI document.
import type { components, paths } from "./generated/openapi";
import type { Alarm } from "./generated/ws";
import type { Command, LinkConfig, RecordingStatus, ReplayStatus, TypedProviderDetail } from "./types";

type InsState = paths["/api/providers/{provider_id}/inertial-sensor"]["post"]["requestBody"]["content"]["application/json"]["state"];

export class ApiError extends Error {
  constructor(readonly status: number, message: string) {
    super(message);
  }
}

/** What a request that never got an answer (the console down, the network gone) says: status 0. */
export const UNREACHABLE = "console unreachable";

/** A failed call in the operator's words: "409: Alpha is lost…", "console unreachable"; never a JavaScript error's text. */
export function problemText(e: unknown): string {
  if (e instanceof ApiError) return e.status === 0 ? e.message : `${e.status}: ${e.message}`;
  return e instanceof Error && e.message ? e.message : String(e);
}

/** fetch, with a request that gets no answer (fetch's TypeError "Failed to fetch") turned into ApiError(0, UNREACHABLE). */
async function reach(path: string, init: RequestInit): Promise<Response> {
  try {
    return await fetch(path, init);
  } catch (e) {
    if (e instanceof DOMException && e.name === "AbortError") throw e;
    throw new ApiError(0, UNREACHABLE);
  }
}

async function send(method: string, path: string, token: string | null, body?: unknown): Promise<Response> {
  const headers: Record<string, string> = {};
  if (token) headers.Authorization = `Bearer ${token}`;
  if (body !== undefined) headers["Content-Type"] = "application/json";
  const r = await reach(path, { method, headers, body: body === undefined ? undefined : JSON.stringify(body) });
  if (!r.ok) {
    let detail = r.statusText;
    try {
      const j = (await r.json()) as { detail?: unknown };
      if (typeof j.detail === "string") detail = j.detail;
    } catch {
      /* not JSON */
    }
    throw new ApiError(r.status, detail);
  }
  return r;
}

async function call<T = Command>(method: string, path: string, token: string | null, body?: unknown): Promise<T> {
  return (await (await send(method, path, token, body)).json()) as T;
}

/** The operator a token belongs to (GET /api/operator): the sign-in check. */
export async function checkToken(token: string): Promise<string | null> {
  return (await call<{ operator: string | null }>("GET", "/api/operator", token)).operator;
}

export type Health = components["schemas"]["Health"];
export type ReplayRequest = paths["/api/replay"]["post"]["requestBody"]["content"]["application/json"];

export async function health(): Promise<Health> {
  return call<Health>("GET", "/api/health", null);
}

/** What another vendor's participant must change for the console to read it (docs/dds.md, "Other DDS vendors"). */
export type PeerFinding = components["schemas"]["PeerFinding"];

/** GET /api/metrics' findings on other vendors' participants (an RTI vehicle on XCDR1, sending type information…). */
export async function peerFindings(token: string | null): Promise<PeerFinding[]> {
  return (await call<components["schemas"]["Metrics"]>("GET", "/api/metrics", token)).peerFindings;
}

/** `confirmLost`: the operator confirmed commanding a vehicle whose link is lost (the console refuses it with 409 otherwise). */
export function requestGpsFix(providerId: string, token: string | null, confirmLost = false): Promise<Command> {
  return call("POST", `/api/providers/${encodeURIComponent(providerId)}/gps-fix`, token, confirmLost ? { confirmLost } : {});
}

export function setInertialSensor(providerId: string, state: InsState, token: string | null, confirmLost = false): Promise<Command> {
  return call("POST", `/api/providers/${encodeURIComponent(providerId)}/inertial-sensor`, token, confirmLost ? { state, confirmLost } : { state });
}

export function cancelCommand(sessionId: string, token: string | null): Promise<Command> {
  return call("DELETE", `/api/commands/${encodeURIComponent(sessionId)}`, token);
}

/** Acknowledge an alarm (POST /api/alarms/{id}/ack): an operator action, audited with the operator's name.
 * Answered with the active set after it (the WebSocket's `alarms` message brings the same to every page). */
export function ackAlarm(alarmId: number, token: string | null): Promise<Alarm[]> {
  return call<Alarm[]>("POST", `/api/alarms/${alarmId}/ack`, token, {});
}

/** Set a vehicle's link thresholds and comms-lost configuration (PUT, operator token, audited). */
export function setLinkConfig(providerId: string, config: LinkConfig, token: string | null): Promise<LinkConfig> {
  return call<LinkConfig>("PUT", `/api/providers/${encodeURIComponent(providerId)}/link-config`, token, config);
}

/** Name a vehicle (PUT, operator token, audited; stored and shared with the other consoles): an empty name goes
 * back to the console's --vehicle-names name. Answered with the name now shown. */
export function setVehicleName(providerId: string, name: string, token: string | null): Promise<{ name: string | null }> {
  return call<{ name: string | null }>("PUT", `/api/providers/${encodeURIComponent(providerId)}/name`, token, { name });
}

/** The vehicle's ASPN-23 messages of the last `seconds` (the console's clock) as an LCM log file, and its file name. */
export async function aspnLog(providerId: string, seconds: number, token: string | null): Promise<{ blob: Blob; filename: string }> {
  const r = await send("GET", `/api/providers/${encodeURIComponent(providerId)}/aspn-log?seconds=${seconds}`, token);
  const named = /filename="([^"]+)"/.exec(r.headers.get("Content-Disposition") ?? "");
  return { blob: await r.blob(), filename: named ? named[1] : "aspn.lcm" };
}

/** Start or stop the console's recording to MCAP (POST /api/recordings); needs an operator token when commands do. */
export function controlRecording(action: "start" | "stop", token: string | null): Promise<RecordingStatus> {
  return call<RecordingStatus>("POST", "/api/recordings", token, { action });
}

/** Play, pause, seek or set the speed of a replay (POST /api/replay); answered with the playback once done. */
export function controlReplay(request: ReplayRequest, token: string | null): Promise<ReplayStatus> {
  return call<ReplayStatus>("POST", "/api/replay", token, request);
}

type SeriesPoint = paths["/api/providers/{provider_id}/series"]["get"]["responses"][200]["content"]["application/json"][number];

/** The console's chart series of a vehicle from `since` (GET /api/providers/{id}/series). */
export function series(providerId: string, since: string, token: string | null): Promise<SeriesPoint[]> {
  return call<SeriesPoint[]>("GET", `/api/providers/${encodeURIComponent(providerId)}/series?since=${encodeURIComponent(since)}`, token);
}

/** A vehicle with its latest reports, in full (GET /api/providers/{id}): the snapshot leaves out the satellites. */
export function providerDetail(providerId: string, token: string | null): Promise<TypedProviderDetail> {
  return call<TypedProviderDetail>("GET", `/api/providers/${encodeURIComponent(providerId)}`, token);
}

/** Commands to one vehicle, newest first, `limit` from `offset` (GET /api/commands): the history pager. */
export function commandPage(providerId: string, limit: number, offset: number, token: string | null): Promise<Command[]> {
  const q = new URLSearchParams({ provider_id: providerId, limit: String(limit), offset: String(offset) });
  return call<Command[]>("GET", `/api/commands?${q}`, token);
}

/** A file from the console (an export), fetched with the token when reads need one. */
export async function download(url: string, token: string | null): Promise<Blob> {
  const r = await reach(url, { headers: token ? { Authorization: `Bearer ${token}` } : {} });
  if (!r.ok) throw new ApiError(r.status, r.statusText);
  return r.blob();
}

export type TrackPoint = paths["/api/providers/{provider_id}/track"]["get"]["responses"][200]["content"]["application/json"][number];

/** The console's stored track of a vehicle from `since` (GET /api/providers/{id}/track). */
export function track(providerId: string, since: string, token: string | null): Promise<TrackPoint[]> {
  return call<TrackPoint[]>("GET", `/api/providers/${encodeURIComponent(providerId)}/track?since=${encodeURIComponent(since)}`, token);
}

/** The CoMap world model (GET /api/worldmodel): null when the console has none (404, CoMap not built in or off). */
export async function worldModel(token: string | null): Promise<import("geojson").FeatureCollection | null> {
  try {
    return await call<import("geojson").FeatureCollection>("GET", "/api/worldmodel", token);
  } catch (e) {
    if (e instanceof ApiError && e.status === 404) return null;
    throw e;
  }
}

// CoMap C2: the contract the console's CoMap routes follow (GET/PUT /api/worldmodel, /api/tasks).
export type SynchAction = "HOLD" | "RESUME" | "INTERRUPT";

/** A SurveyTask or MoveTask to assign (POST /api/tasks), and a task as the console follows it: the backend's models. */
export type TaskRequest = components["schemas"]["SurveyTaskRequest"] | components["schemas"]["MoveTaskRequest"];
export type Task = components["schemas"]["Task"];

export function putWorldModel(model: import("geojson").FeatureCollection, token: string | null): Promise<unknown> {
  // the features only: what the console adds to its model (updatedAt, source) is not part of a PUT
  return call<unknown>("PUT", "/api/worldmodel", token, { type: "FeatureCollection", features: model.features });
}

export function createTask(task: TaskRequest, token: string | null): Promise<Task> {
  return call<Task>("POST", "/api/tasks", token, task);
}

export function tasks(token: string | null): Promise<Task[]> {
  return call<Task[]>("GET", "/api/tasks", token);
}

export function synchTask(id: string | number, action: SynchAction, token: string | null): Promise<unknown> {
  return call<unknown>("POST", `/api/tasks/${encodeURIComponent(String(id))}/synch`, token, { action });
}

export type ComapVehicle = components["schemas"]["ComapVehicle"];
export type Capability = components["schemas"]["Capability"];

/** A vehicle's CoMap side: its IMC id and last VehicleCapabilities (GET /api/providers/{id}/capabilities). */
export function vehicleCapabilities(providerId: string, token: string | null): Promise<ComapVehicle> {
  return call<ComapVehicle>("GET", `/api/providers/${encodeURIComponent(providerId)}/capabilities`, token);
}

export type ComapStatus = components["schemas"]["ComapStatus"];

/** The console's IMC node (GET /api/comap): `enabled` false when it was started without --imc-port (CoMap off). */
export function comapStatus(token: string | null): Promise<ComapStatus> {
  return call<ComapStatus>("GET", "/api/comap", token);
}

/** Shelve an alarm for `minutes` with a reason (POST, operator token, audited; shared by every station). */
export function shelveAlarm(alarmId: number, reason: string, minutes: number, token: string | null): Promise<Alarm[]> {
  return call<Alarm[]>("POST", `/api/alarms/${alarmId}/shelve`, token, { reason, minutes });
}

/** Bring a shelved alarm back into view at once. */
export function unshelveAlarm(alarmId: number, token: string | null): Promise<Alarm[]> {
  return call<Alarm[]>("POST", `/api/alarms/${alarmId}/unshelve`, token, {});
}

type PlannedSilence = components["schemas"]["PlannedSilence"];

/** Declare a vehicle out of comms until `until` (UTC seconds), with a reason (PUT, operator token, audited). */
export function planSilence(providerId: string, until: number, reason: string, token: string | null): Promise<PlannedSilence[]> {
  return call<PlannedSilence[]>("PUT", `/api/providers/${encodeURIComponent(providerId)}/silence`, token, { until, reason });
}

/** End a vehicle's planned silence now. */
export function cancelSilence(providerId: string, token: string | null): Promise<PlannedSilence[]> {
  return call<PlannedSilence[]>("DELETE", `/api/providers/${encodeURIComponent(providerId)}/silence`, token);
}
