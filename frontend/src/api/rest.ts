// The console's REST API through openapi-fetch on the paths generated from its OpenAPI document (generated/openapi.ts):
// a path, its parameters, its body and its answer are all the backend's own types, checked by tsc.
import createClient from "openapi-fetch";
import type { FeatureCollection } from "geojson";
import type { components, paths } from "./generated/openapi";
import type { Alarm } from "./generated/ws";
import type { Command, LinkConfig, RecordingStatus, ReplayStatus, TypedProviderDetail } from "./types";

type InsState =
  paths["/api/providers/{provider_id}/inertial-sensor"]["post"]["requestBody"]["content"]["application/json"]["state"];

export class ApiError extends Error {
  constructor(
    readonly status: number,
    message: string,
  ) {
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

// fetch looked up at each call (not once here), so that a test's stand-in answers
const client = createClient<paths>({ fetch: (request) => globalThis.fetch(request) });

/** What every call carries: the console that served the page, and the operator's token when there is one. */
function on(token: string | null): { baseUrl: string; headers: Record<string, string> } {
  return { baseUrl: location.origin, headers: token ? { Authorization: `Bearer ${token}` } : {} };
}

interface Answer<T> {
  data?: T;
  error?: unknown;
  response: Response;
}

/** A call's answer; a refusal as ApiError(status, the console's `detail`), a request that got no answer (fetch's
 * TypeError "Failed to fetch") as ApiError(0, UNREACHABLE). */
async function answer<T>(call: Promise<Answer<T>>): Promise<T> {
  let r: Answer<T>;
  try {
    r = await call;
  } catch (e) {
    if (e instanceof DOMException && e.name === "AbortError") throw e;
    throw new ApiError(0, UNREACHABLE);
  }
  if (!r.response.ok) throw refusal(r.response, r.error);
  return r.data as T;
}

/** A refusal as ApiError(status, the console's one-line `detail` from its answer's body), the status text when the
 * body has none (not the console's: a proxy's page). */
function refusal(response: Response, body: unknown): ApiError {
  const detail = (body as { detail?: unknown } | null | undefined)?.detail;
  return new ApiError(response.status, typeof detail === "string" ? detail : response.statusText);
}

const provider = (provider_id: string) => ({ path: { provider_id } });

/** The operator a token belongs to (GET /api/operator): the sign-in check. */
export async function checkToken(token: string): Promise<string | null> {
  return (await answer(client.GET("/api/operator", on(token)))).operator;
}

export type Health = components["schemas"]["Health"];
export type ReplayRequest = paths["/api/replay"]["post"]["requestBody"]["content"]["application/json"];

export function health(): Promise<Health> {
  return answer(client.GET("/api/health", on(null)));
}

/** What another vendor's participant must change for the console to read it (docs/dds.md, "Other DDS vendors"). */
export type PeerFinding = components["schemas"]["PeerFinding"];

/** GET /api/metrics' findings on other vendors' participants (an RTI vehicle on XCDR1, sending type information…). */
export async function peerFindings(token: string | null): Promise<PeerFinding[]> {
  return (await answer(client.GET("/api/metrics", on(token)))).peerFindings;
}

/** `confirmLost`: the operator confirmed commanding a vehicle whose link is lost (the console refuses it with 409 otherwise). */
export function requestGpsFix(providerId: string, token: string | null, confirmLost = false): Promise<Command> {
  return answer(
    client.POST("/api/providers/{provider_id}/gps-fix", { ...on(token), params: provider(providerId), body: { confirmLost } }),
  );
}

export function setInertialSensor(
  providerId: string,
  state: InsState,
  token: string | null,
  confirmLost = false,
): Promise<Command> {
  return answer(
    client.POST("/api/providers/{provider_id}/inertial-sensor", {
      ...on(token),
      params: provider(providerId),
      body: { state, confirmLost },
    }),
  );
}

export function cancelCommand(sessionId: string, token: string | null): Promise<Command> {
  return answer(client.DELETE("/api/commands/{session_id}", { ...on(token), params: { path: { session_id: sessionId } } }));
}

/** Acknowledge an alarm (POST /api/alarms/{id}/ack): an operator action, audited with the operator's name.
 * Answered with the active set after it (the WebSocket's `alarms` message brings the same to every page). */
export function ackAlarm(alarmId: number, token: string | null): Promise<Alarm[]> {
  return answer(client.POST("/api/alarms/{alarm_id}/ack", { ...on(token), params: { path: { alarm_id: alarmId } }, body: {} }));
}

/** Set a vehicle's link thresholds and comms-lost configuration (PUT, operator token, audited). */
export function setLinkConfig(providerId: string, config: LinkConfig, token: string | null): Promise<LinkConfig> {
  return answer(
    client.PUT("/api/providers/{provider_id}/link-config", { ...on(token), params: provider(providerId), body: config }),
  );
}

/** Name a vehicle (PUT, operator token, audited; stored and shared with the other consoles): an empty name goes
 * back to the console's --vehicle-names name. Answered with the name now shown. */
export function setVehicleName(providerId: string, name: string, token: string | null): Promise<{ name: string | null }> {
  return answer(client.PUT("/api/providers/{provider_id}/name", { ...on(token), params: provider(providerId), body: { name } }));
}

/** The vehicle's ASPN-23 messages of the last `seconds` (the console's clock) as an LCM log file, and its file name. */
export async function aspnLog(
  providerId: string,
  seconds: number,
  token: string | null,
): Promise<{ blob: Blob; filename: string }> {
  const call = client.GET("/api/providers/{provider_id}/aspn-log", {
    ...on(token),
    params: { path: { provider_id: providerId }, query: { seconds } },
    parseAs: "blob",
  });
  const blob = await answer(call);
  const named = /filename="([^"]+)"/.exec((await call).response.headers.get("Content-Disposition") ?? "");
  return { blob, filename: named ? named[1] : "aspn.lcm" };
}

/** Start or stop the console's recording to MCAP (POST /api/recordings); needs an operator token when commands do. */
export function controlRecording(action: "start" | "stop", token: string | null): Promise<RecordingStatus> {
  return answer(client.POST("/api/recordings", { ...on(token), body: { action } }));
}

/** Play, pause, seek or set the speed of a replay (POST /api/replay); answered with the playback once done. */
export function controlReplay(request: ReplayRequest, token: string | null): Promise<ReplayStatus> {
  return answer(client.POST("/api/replay", { ...on(token), body: request }));
}

type SeriesPoint = components["schemas"]["SeriesPoint"];

/** The console's chart series of a vehicle from `since` (GET /api/providers/{id}/series). */
export function series(providerId: string, since: string, token: string | null, signal?: AbortSignal): Promise<SeriesPoint[]> {
  return answer(
    client.GET("/api/providers/{provider_id}/series", {
      ...on(token),
      params: { path: { provider_id: providerId }, query: { since } },
      signal,
    }),
  );
}

/** A vehicle with its latest reports, in full (GET /api/providers/{id}): the snapshot leaves out the satellites. */
export async function providerDetail(
  providerId: string,
  token: string | null,
  signal?: AbortSignal,
): Promise<TypedProviderDetail> {
  // the document types `reports` per topic as the WebSocket schema's ReportTypes only in words: typed here
  return (await answer(
    client.GET("/api/providers/{provider_id}", { ...on(token), params: provider(providerId), signal }),
  )) as TypedProviderDetail;
}

/** Commands to one vehicle, newest first, `limit` from `offset` (GET /api/commands): the history pager. */
export function commandPage(providerId: string, limit: number, offset: number, token: string | null): Promise<Command[]> {
  return answer(client.GET("/api/commands", { ...on(token), params: { query: { provider_id: providerId, limit, offset } } }));
}

/** A file from the console (an export, at a URL lib/exports.ts builds), fetched with the token when reads need one. */
export async function download(url: string, token: string | null): Promise<Blob> {
  let r: Response;
  try {
    r = await fetch(url, { headers: on(token).headers });
  } catch {
    throw new ApiError(0, UNREACHABLE);
  }
  if (!r.ok) throw refusal(r, await r.json().catch(() => null));
  return r.blob();
}

export type TrackPoint = components["schemas"]["TrackPoint"];

/** The console's stored track of a vehicle from `since` (GET /api/providers/{id}/track). */
export function track(providerId: string, since: string, token: string | null, signal?: AbortSignal): Promise<TrackPoint[]> {
  return answer(
    client.GET("/api/providers/{provider_id}/track", {
      ...on(token),
      params: { path: { provider_id: providerId }, query: { since } },
      signal,
    }),
  );
}

/** The CoMap world model (GET /api/worldmodel): null when the console has none (404, CoMap not built in or off). */
export async function worldModel(token: string | null, signal?: AbortSignal): Promise<FeatureCollection | null> {
  try {
    return (await answer(client.GET("/api/worldmodel", { ...on(token), signal }))) as FeatureCollection;
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
type WorldModelBody = paths["/api/worldmodel"]["put"]["requestBody"]["content"]["application/json"];

export function putWorldModel(model: FeatureCollection, token: string | null): Promise<unknown> {
  // the features only: what the console adds to its model (updatedAt, source) is not part of a PUT
  // (GeoJSON's own types are wider than the console's model, which checks what it is given)
  const body = { type: "FeatureCollection", features: model.features } as WorldModelBody;
  return answer(client.PUT("/api/worldmodel", { ...on(token), body }));
}

export function createTask(task: TaskRequest, token: string | null): Promise<Task> {
  return answer(client.POST("/api/tasks", { ...on(token), body: task }));
}

export function tasks(token: string | null, signal?: AbortSignal): Promise<Task[]> {
  return answer(client.GET("/api/tasks", { ...on(token), signal }));
}

export function synchTask(id: number, action: SynchAction, token: string | null): Promise<unknown> {
  return answer(client.POST("/api/tasks/{task_id}/synch", { ...on(token), params: { path: { task_id: id } }, body: { action } }));
}

export type ComapVehicle = components["schemas"]["ComapVehicle"];
export type Capability = components["schemas"]["Capability"];

/** A vehicle's CoMap side: its IMC id and last VehicleCapabilities (GET /api/providers/{id}/capabilities). */
export function vehicleCapabilities(providerId: string, token: string | null): Promise<ComapVehicle> {
  return answer(client.GET("/api/providers/{provider_id}/capabilities", { ...on(token), params: provider(providerId) }));
}

export type ComapStatus = components["schemas"]["ComapStatus"];

/** The console's IMC node (GET /api/comap): `enabled` false when it was started without --imc-port (CoMap off). */
export function comapStatus(token: string | null): Promise<ComapStatus> {
  return answer(client.GET("/api/comap", on(token)));
}

/** Shelve an alarm for `minutes` with a reason (POST, operator token, audited; shared by every station). */
export function shelveAlarm(alarmId: number, reason: string, minutes: number, token: string | null): Promise<Alarm[]> {
  return answer(
    client.POST("/api/alarms/{alarm_id}/shelve", {
      ...on(token),
      params: { path: { alarm_id: alarmId } },
      body: { reason, minutes },
    }),
  );
}

/** Bring a shelved alarm back into view at once. */
export function unshelveAlarm(alarmId: number, token: string | null): Promise<Alarm[]> {
  return answer(
    client.POST("/api/alarms/{alarm_id}/unshelve", { ...on(token), params: { path: { alarm_id: alarmId } }, body: {} }),
  );
}

type PlannedSilence = components["schemas"]["PlannedSilence"];

/** Declare a vehicle out of comms until `until` (UTC seconds), with a reason (PUT, operator token, audited). */
export function planSilence(providerId: string, until: number, reason: string, token: string | null): Promise<PlannedSilence[]> {
  return answer(
    client.PUT("/api/providers/{provider_id}/silence", { ...on(token), params: provider(providerId), body: { until, reason } }),
  );
}

/** End a vehicle's planned silence now. */
export function cancelSilence(providerId: string, token: string | null): Promise<PlannedSilence[]> {
  return answer(client.DELETE("/api/providers/{provider_id}/silence", { ...on(token), params: provider(providerId) }));
}
