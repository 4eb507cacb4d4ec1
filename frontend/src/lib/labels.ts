// Operator words for the UMAA (and CoMap) literals and the console's own states, from the one table the backend
// owns and publishes (backend/sem_console/core/words.py -> schema/words.json; the backend's alarm texts say the same
// words). An operator at sea reads "Dead reckoning", not GPS_DEAD_RECK; the literal stays available in a tooltip
// (`umaa`), for the engineer comparing the screen with a log. A literal the table does not know (a newer ICD, another
// vendor's value) is shown as it is rather than hidden. Every place that names a state takes its words from here.
import type {
  GPSConstellationEnumType,
  InertialSensorOpStatusEnumType,
  InertialSensorStateEnumType,
  LinkState,
  ProviderSummary,
  Topic,
} from "../api/types";
import type {
  Alarm,
  FeatureProperties,
  GPSFixEnumType,
  GPSNavigationSolutionEnumType,
  NavigationSolutionEnumType,
  TFOMEnumType,
  Task,
} from "../api/generated/ws";
import WORDS from "../../schema/words.json";
import { DASH, PENDING, age, clockTime, elapsedText } from "./units";

// Each table typed by the literals it must name: a literal without words fails the build (and labels.test.ts).
type Words<T extends string> = Readonly<Record<T, string>>;
type CommandStatus = "ISSUED" | "COMMANDED" | "EXECUTING" | "COMPLETED" | "FAILED" | "CANCELED";
type CommandReason =
  | "SUCCEEDED"
  | "CANCELED"
  | "VALIDATION_FAILED"
  | "OBJECTIVE_FAILED"
  | "SERVICE_FAILED"
  | "RESOURCE_FAILED"
  | "RESOURCE_REJECTED"
  | "INTERRUPTED"
  | "TIMEOUT"
  | "UPDATED";
/** UMAA 6.0's InertialSensorCmdEnumType: what a 6.0 InertialSensorCommandType asks (the Command's state of a 6.0 vehicle). */
export type InsCommand = "BEST_ALIGN" | "GPS_ALIGN" | "INIT" | "SNAP_ALIGN" | "STATIONARY_ALIGN" | "TRANSFER_ALIGN";
export const FIX_STATE: Words<GPSFixEnumType> = WORDS.GPSFixEnumType;
export const NAV_SOLUTION: Words<GPSNavigationSolutionEnumType> = WORDS.GPSNavigationSolutionEnumType;
export const CONSTELLATION: Words<GPSConstellationEnumType> = WORDS.GPSConstellationEnumType;
export const INS_STATE: Words<InertialSensorStateEnumType> = WORDS.InertialSensorStateEnumType;
export const INS_STATUS: Words<InertialSensorOpStatusEnumType> = WORDS.InertialSensorOpStatusEnumType;
export const POSITION_SOLUTION: Words<NavigationSolutionEnumType> = WORDS.NavigationSolutionEnumType;
export const TIME_MERIT: Words<TFOMEnumType> = WORDS.TFOMEnumType;
export const COMMAND_STATUS: Words<CommandStatus> = WORDS.CommandStatusEnumType;
export const REASON: Words<CommandReason> = WORDS.CommandStatusReasonEnumType;
export const INS_COMMAND: Words<InsCommand> = WORDS.InertialSensorCmdEnumType;
export const LINK: Words<LinkState | "stale" | "unreachable" | "planned"> = WORDS.link;
export const COMMAND: Words<"unanswered"> = WORDS.command;
export const CANCEL_CAUSE: Words<"operator" | "shutdown"> = WORDS.cancelCause;
export const FIX_VALID: Words<"true" | "false"> = WORDS.fixValid;
const FIX_SERVICE: Words<"none" | "quality"> = WORDS.fixService;
export const POSITION_SOURCE: Words<"true" | "false"> = WORDS.GPSLatLongValid;
export const ALARM_KIND: Words<Alarm["kind"]> = WORDS.alarmKind;
export const ALARM_SEVERITY: Words<Alarm["severity"]> = WORDS.alarmSeverity;
export const ALARM_STATE: Words<Alarm["state"]> = WORDS.alarmState;
export const ALARM_MARK: Words<"shelved" | "chattering"> = WORDS.alarmMark;
export const ALARM_RETURNED: Words<"expired" | "unshelved" | "worse"> = WORDS.alarmReturned;
const TASK_STATE: Words<NonNullable<Task["state"]>> = WORDS.taskState;
const TASK_KIND: Words<Task["kind"]> = WORDS.taskKind;
const SENSOR: Words<NonNullable<Task["sensor"]>> = WORDS.sensor;
const COVERAGE: Words<NonNullable<FeatureProperties["coverage"]>> = WORDS.coverage;
const RELAY: Words<"via" | "unknown" | "title"> = WORDS.relay;

/** The tables of the UMAA enumerations, by the enumeration's name (labels.test.ts checks every literal the console's
 * schema has against them). */
export const UMAA_WORDS: Readonly<Record<string, Readonly<Record<string, string>>>> = {
  GPSFixEnumType: FIX_STATE,
  GPSNavigationSolutionEnumType: NAV_SOLUTION,
  GPSConstellationEnumType: CONSTELLATION,
  InertialSensorStateEnumType: INS_STATE,
  InertialSensorOpStatusEnumType: INS_STATUS,
  NavigationSolutionEnumType: POSITION_SOLUTION,
  TFOMEnumType: TIME_MERIT,
  CommandStatusEnumType: COMMAND_STATUS,
  CommandStatusReasonEnumType: REASON,
  InertialSensorCmdEnumType: INS_COMMAND,
};

function lookup<T extends string>(words: Words<T>, v: string | null | undefined): string {
  if (v === null || v === undefined || v === "") return DASH;
  return (words as Record<string, string>)[v] ?? v;
}

/** A word inside a phrase: its first letter lowered, unless it starts an abbreviation ("GPS 3D"); as the backend's
 * `words.inline`. */
export function inline(words: string): string {
  return words.length > 1 && words[1] === words[1].toUpperCase() && words[1] !== words[1].toLowerCase()
    ? words
    : words.slice(0, 1).toLowerCase() + words.slice(1);
}

/** The tooltip that keeps the protocol's word: "UMAA navSolution: GPS_DEAD_RECK". */
export function umaa(field: string, literal: string | null | undefined): string | undefined {
  return literal === null || literal === undefined || literal === "" ? undefined : `UMAA ${field}: ${literal}`;
}

export function insStateText(v: string | null | undefined): string {
  return lookup(INS_STATE, v);
}

/** The INS's status in words, or null when it says nothing beside its state: an INS that is off reports INIT (UMAA
 * has no "off" status), which is no "Starting up". */
export function insStatusText(v: string | null | undefined, state?: string | null): string | null {
  if (state === "OFF" && v === "INIT") return null;
  return lookup(INS_STATUS, v);
}

/** A state in words, the tone of its colour (colour is never the only cue) and its tooltip (the literal). */
export type Tone = "ok" | "warn" | "bad" | "info" | "muted";
export interface Word {
  text: string;
  tone: Tone;
  title?: string;
}

export type UmaaVersion = ProviderSummary["umaaVersion"];

/** The console's report topics a vehicle of a UMAA version never fills, and why: a missing report of one is no report
 * to wait for, nor a fault. */
const NOT_REPORTED: Readonly<Record<UmaaVersion, Partial<Readonly<Record<Topic, string>>>>> = {
  "3.0.1": {},
  "6.0": {
    GPSFixStatusReport:
      "UMAA 6.0 has no GPS fix service: a 6.0 vehicle reports no fix status (its position comes in its GlobalPoseReport)",
  },
};

/** The members of the console's reports a vehicle of a UMAA version never fills, and why (by report topic). */
const NOT_REPORTED_MEMBERS: Readonly<Record<UmaaVersion, Partial<Readonly<Record<Topic, Readonly<Record<string, string>>>>>>> = {
  "3.0.1": {},
  "6.0": {
    GPSFixReport: {
      SOG: "its UMAA 6.0 position report (GlobalPoseReport) has no speed",
      magneticVariation: "its UMAA 6.0 position report (GlobalPoseReport) has no magnetic variation",
      velocity: "its UMAA 6.0 position report (GlobalPoseReport) has no velocity",
      GPSFixCommandStatus: "UMAA 6.0 has no GPS fix service: a 6.0 vehicle reports no receiver fix state",
    },
  },
};
const NOT_IN_VERSION: Words<"members"> = WORDS.notInVersion;

/** What a vehicle of `version` never reports, named once where the places that would show it are left out ("Not in
 * UMAA 6.0: SOG, magnetic variation"); null when it reports them all. */
export function notInVersionText(version: UmaaVersion | null | undefined, members: readonly string[]): string | null {
  return version && members.length
    ? NOT_IN_VERSION.members.replace("{version}", version).replace("{members}", members.join(", "))
    : null;
}

/** Why a vehicle of `version` never has `member` in its `topic` report (null: it may). */
export function memberNotReported(version: UmaaVersion | null | undefined, topic: Topic, member: string): string | null {
  return (version && NOT_REPORTED_MEMBERS[version][topic]?.[member]) || null;
}

/** Why a vehicle of `version` has no `topic` report, when its version never fills that topic (null: one may come). */
export function notReported(version: UmaaVersion | null | undefined, topic: Topic): string | null {
  return (version && NOT_REPORTED[version][topic]) || null;
}

/** Whether an INS status says the INS or its alignment failed: INERTIAL_SENSOR_FAILURE, and (UMAA 6.0) the failure
 * of each kind of alignment (GPS_ALIGNMENT_FAILURE...), as the backend's INS alarm has it. */
export function insFailed(status: string | null | undefined): boolean {
  return typeof status === "string" && status.endsWith("_FAILURE");
}

/** Whether an INS status says it is aligned: at the last step of its alignment as its UMAA version has it (3.0.1:
 * OPERATIONAL, after its fine alignment is done; 6.0, which has no OPERATIONAL: the stage its alignment completed
 * with). */
export function insAligned(status: string | null | undefined, version: UmaaVersion | null | undefined): boolean {
  const bar = alignmentBar(version, status);
  return bar.current >= 0 && bar.current === bar.steps.length - 1;
}

/** The INS in one phrase, as the fleet bar and the vehicle list say it: its state when that is not ON ("INS off",
 * "INS restarting"), else its status ("INS operational", "INS coarse alignment, stationary", "INS failed", "INS
 * GPS-aided alignment failed"); a vehicle that reports no power state (UMAA 6.0) by its status. */
export function insWord(state: string | null | undefined, status: string | null | undefined, version?: UmaaVersion | null): Word {
  if (!state && !status)
    return {
      text: `INS ${DASH}`,
      tone: "muted",
      title: notReported(version, "InertialSensorReport") ?? "no inertial sensor report yet",
    };
  const title = [umaa("state", state), umaa("status", status)].filter(Boolean).join("; ");
  if (insFailed(status)) return { text: `INS ${inline(lookup(INS_STATUS, status))}`, tone: "bad", title };
  if (state && state !== "ON") return { text: `INS ${inline(insStateText(state))}`, tone: "warn", title };
  const said = insStatusText(status, state);
  return { text: `INS ${said === null ? DASH : inline(said)}`, tone: insAligned(status, version) ? "ok" : "warn", title };
}

/** GPSFixStatusReport.fixValid in one word ("Fix", "No fix"). */
export function fixWord(fixValid: boolean | null | undefined, version?: UmaaVersion | null): Word {
  if (fixValid === null || fixValid === undefined) {
    // a version without the fix service says so (the fix panel's words), not a dash that reads as "not known yet"
    const none = notReported(version, "GPSFixStatusReport");
    return { text: none ? FIX_SERVICE.none : `Fix ${DASH}`, tone: "muted", title: none ?? "no GPS fix status yet" };
  }
  const literal = fixValid ? "true" : "false";
  return { text: FIX_VALID[literal], tone: fixValid ? "ok" : "warn", title: umaa("fixValid", literal) };
}

/** The GPS fix panel's fix badge: the fix status ("Fix valid" green, "No fix" red); a vehicle whose version has no GPS
 * fix service (UMAA 6.0) "No fix service", not a fix lost, its position's quality its navigation solution ("Position
 * quality: measured position") in the tooltip, "…" while `pending` (its report the snapshot's brief, without its
 * navigation solution); no status yet a dash. */
export function fixBadge(
  fixValid: boolean | null | undefined,
  version: UmaaVersion | null | undefined,
  fix: Parameters<typeof positionKind>[0],
  pending = false,
): Word {
  const none = notReported(version, "GPSFixStatusReport");
  if (typeof fixValid !== "boolean" && none) {
    const quality = fix?.navigationSolution
      ? `${FIX_SERVICE.quality}: ${inline(positionKind(fix).text)}`
      : `${FIX_SERVICE.quality}: ${pending ? PENDING : DASH}`;
    return { text: FIX_SERVICE.none, tone: "muted", title: `${none}. ${quality}` };
  }
  const word = fixWord(fixValid, version);
  return typeof fixValid === "boolean" ? { ...word, tone: fixValid ? "ok" : "bad" } : { ...word, text: DASH, tone: "muted" };
}

/** GPSFixReport.GPSLatLongValid: whose position it is ("GPS position", "INS position"). */
export function positionSourceText(valid: boolean | null | undefined): string {
  return typeof valid === "boolean" ? POSITION_SOURCE[valid ? "true" : "false"] : DASH;
}

/** What kind of position it is, as the vehicle says it: its navigation solution when it reports one ("Measured
 * position", UMAA 6.0's GlobalPose), else whose it is ("GPS position", UMAA 3.0.1's GPSLatLongValid); the literal in
 * the tooltip. */
export function positionKind(
  fix: { navigationSolution?: string | null; GPSLatLongValid?: boolean | null } | null | undefined,
): Word {
  const solution = fix?.navigationSolution;
  const valid = fix?.GPSLatLongValid;
  if (solution)
    return { text: lookup(POSITION_SOLUTION, solution), tone: valid ? "ok" : "bad", title: umaa("navigationSolution", solution) };
  return {
    text: positionSourceText(valid),
    tone: valid ? "ok" : "bad",
    title: umaa("GPSLatLongValid", typeof valid === "boolean" ? String(valid) : null),
  };
}

/** The GPS clock's time quality, as the vehicle reports it: its time uncertainty ("12.5 ns", UMAA 3.0.1) or its time
 * figure of merit ("Time within 100 ns", UMAA 6.0, the literal in the tooltip); nothing reported: a dash. */
export function timeQuality(
  clock: { timeUncertainty?: number | null; timeFigureOfMerit?: string | null } | null | undefined,
): Word {
  const merit = clock?.timeFigureOfMerit;
  if (merit) return { text: lookup(TIME_MERIT, merit), tone: "info", title: umaa("timeFigureOfMerit", merit) };
  const ns = clock?.timeUncertainty;
  return typeof ns === "number" && Number.isFinite(ns)
    ? { text: `± ${ns.toFixed(1)} ns`, tone: "info", title: "UMAA timeUncertainty (ns)" }
    : { text: DASH, tone: "muted" };
}

/** A stage of an alignment, as the INS panel's step bar names it (the table's words). */
export type AlignmentStep = "INIT" | "COARSE" | "FINE" | "DONE" | "OPERATIONAL";
const ALIGNMENT_STEP: Words<AlignmentStep> = WORDS.insAlignmentStep;
export function alignmentStepText(v: AlignmentStep): string {
  return lookup(ALIGNMENT_STEP, v);
}

type OpStatus = InertialSensorOpStatusEnumType;
/** Each kind of alignment as a vehicle of each UMAA version reports it: its status at each stage, in order. UMAA 3.0.1
 * aligns stationary or GPS-aided (coarse spelled COURSE) and then reports OPERATIONAL; 6.0 adds best available,
 * transfer and snap (done at once) and has no OPERATIONAL: its aligned INS reports the stage its alignment completed
 * with. */
const ALIGNMENTS: Readonly<Record<UmaaVersion, readonly (readonly OpStatus[])[]>> = {
  "3.0.1": [
    [
      "INIT",
      "COURSE_STATIONARY_ALIGNMENT",
      "FINE_STATIONARY_ALIGNMENT_STARTED",
      "FINE_STATIONARY_ALIGNMENT_COMPLETE",
      "OPERATIONAL",
    ],
    ["INIT", "COURSE_GPS_ALIGNMENT", "FINE_GPS_ALIGNMENT_STARTED", "FINE_GPS_ALIGNMENT_COMPLETE", "OPERATIONAL"],
  ],
  "6.0": [
    ["INIT", "COARSE_STATIONARY_ALIGNMENT", "FINE_STATIONARY_ALIGNMENT_STARTED", "FINE_STATIONARY_ALIGNMENT_COMPLETE"],
    ["INIT", "COARSE_GPS_ALIGNMENT", "FINE_GPS_ALIGNMENT_STARTED", "FINE_GPS_ALIGNMENT_COMPLETE"],
    ["INIT", "COARSE_BEST_ALIGNMENT", "FINE_BEST_ALIGNMENT_STARTED", "FINE_BEST_ALIGNMENT_COMPLETE"],
    ["INIT", "COARSE_TRANSFER_ALIGNMENT", "FINE_TRANSFER_ALIGNMENT_STARTED", "FINE_TRANSFER_ALIGNMENT_COMPLETE"],
    ["INIT", "SNAP_ALIGNMENT_COMPLETE"],
  ],
};
/** The kind of alignment each failure of one names (UMAA 6.0), by its alignment's stage after INIT. */
const FAILED_ALIGNMENT: Partial<Readonly<Record<OpStatus, OpStatus>>> = {
  STATIONARY_ALIGNMENT_FAILURE: "COARSE_STATIONARY_ALIGNMENT",
  GPS_ALIGNMENT_FAILURE: "COARSE_GPS_ALIGNMENT",
  BEST_ALIGNMENT_FAILURE: "COARSE_BEST_ALIGNMENT",
  TRANSFER_ALIGNMENT_FAILURE: "COARSE_TRANSFER_ALIGNMENT",
  SNAP_ALIGNMENT_FAILURE: "SNAP_ALIGNMENT_COMPLETE",
};

function stepOf(status: OpStatus): AlignmentStep {
  if (status === "INIT" || status === "OPERATIONAL") return status;
  if (status.startsWith("COURSE_") || status.startsWith("COARSE_")) return "COARSE";
  return status.endsWith("_STARTED") ? "FINE" : "DONE";
}

/** One step of the INS panel's bar: its stage and the status the vehicle reports at it (null when that depends on
 * the kind of alignment, which its status does not say: the tooltip names no literal it might not send). */
export interface AlignmentBarStep {
  step: AlignmentStep;
  status: OpStatus | null;
}

/** The INS panel's step bar for a vehicle of `version` reporting `status`: the stages of its kind of alignment (a
 * status naming none, INIT or a sensor failure: the stages its version's alignments share) and the one it is at
 * (-1: none, a failure or an INS that is off, whose INIT is no step of an alignment, `insStatusText`). */
export function alignmentBar(
  version: UmaaVersion | null | undefined,
  status: string | null | undefined,
  state?: string | null,
): { steps: AlignmentBarStep[]; current: number } {
  const s = status as OpStatus | null | undefined;
  const named = s ? (FAILED_ALIGNMENT[s] ?? s) : null;
  // a version not known: the first that has the status (a status both have: 3.0.1's, which ends at OPERATIONAL)
  const alignments = version
    ? ALIGNMENTS[version]
    : (Object.values(ALIGNMENTS).find((v) => v.some((a) => named !== null && a.includes(named))) ?? ALIGNMENTS["3.0.1"]);
  const own = alignments.find((a) => named !== null && named !== "INIT" && named !== "OPERATIONAL" && a.includes(named));
  const steps = (own ?? alignments[0]).map((x) => ({
    step: stepOf(x),
    status: own || x === "INIT" || x === "OPERATIONAL" ? x : null,
  }));
  const off = !s || insStatusText(s, state) === null;
  return { steps, current: off ? -1 : steps.findIndex((x) => x.status === s) };
}

/** GPSFixReport.GPSFixCommandStatus: the receiver's own fix state, reported whether or not a fix was commanded. */
export function fixStateText(v: string | null | undefined): string {
  return lookup(FIX_STATE, v);
}

/** The fix state as the Fix panel's badge says it: what the vehicle reports of its receiver ("Receiver: initiating a
 * fix"), never worded as a command's progress: it reports this with no command sent too. */
export function fixStateBadge(v: string | null | undefined): string {
  return `Receiver: ${inline(fixStateText(v))}`;
}

export function fixStateTitle(v: string | null | undefined): string | undefined {
  const literal = umaa("GPSFixCommandStatus", v);
  return literal && `${literal} (the receiver's state as the vehicle reports it, whether or not a fix was commanded)`;
}

export function navSolutionText(v: string | null | undefined): string {
  return lookup(NAV_SOLUTION, v);
}

/** GPSFixStatusReport.timeOut: the receiver gave up finding a fix in time. */
export function timeOutText(v: boolean | null | undefined): string {
  return v === true ? "Timed out, no fix in time" : v === false ? "Not timed out" : DASH;
}

export function constellationText(v: string | null | undefined): string {
  return lookup(CONSTELLATION, v);
}

export function commandStatusText(v: string | null | undefined): string {
  return lookup(COMMAND_STATUS, v);
}

/** A transition's reason in words, inside a phrase ("the equipment failed"); "" when it says nothing more than the
 * status (SUCCEEDED). */
export function reasonText(v: string | null | undefined): string {
  if (v === null || v === undefined || v === "" || v === "SUCCEEDED") return "";
  return inline(lookup(REASON, v));
}

/** The fleet's exceptional vehicles besides the lost, as counted and filtered: "In alarm", "Commanded". */
export const FLEET_STATE: Words<"alarm" | "commanded"> = WORDS.fleet;

/** A vehicle's link in a word ("Live", "Stale", "Lost"). */
export function linkText(v: LinkState | "stale" | "unreachable" | "planned"): string {
  return lookup(LINK, v);
}

/** What an alarm is about, as a heading ("Link lost"). */
export function alarmKindText(v: string): string {
  return lookup(ALARM_KIND, v);
}

// CoMap (IMC) tasks
export function taskStateText(v: string | null | undefined): string {
  return lookup(TASK_STATE, v);
}

export function taskKindText(v: string | null | undefined): string {
  return lookup(TASK_KIND, v);
}

export function sensorText(v: string | null | undefined): string {
  return lookup(SENSOR, v);
}

/** A world-model feature's coverage; null: no survey has reported on it. */
export function coverageText(v: string | null | undefined): string {
  return v === null || v === undefined || v === "" ? "Coverage unknown" : lookup(COVERAGE, v);
}

/** A position as an operator reads it aloud: "42.1234 N, 70.5678 W" (4 decimals: about 10 m). */
export function positionText(lat: number, lon: number): string {
  return `${Math.abs(lat).toFixed(4)} ${lat >= 0 ? "N" : "S"}, ${Math.abs(lon).toFixed(4)} ${lon >= 0 ? "E" : "W"}`;
}

/** "Last heard 2 min 10 s ago" (`seconds` since the vehicle's last report); null: no report of it received. */
export function lastHeardText(seconds: number | null): string {
  return seconds === null ? "No report received" : `Last heard ${elapsedText(seconds)} ago`;
}

/** "Alpha (77b2ceb8) is lost: last heard 12 s ago", or in its planned silence (`until`, its end) "Alpha (77b2ceb8) is
 * out of comms (planned) until 14:20 UTC: last heard 12 s ago"; `seconds` null: no report of it received. */
export function lostText(vehicle: string, seconds: number | null, until: number | null = null): string {
  return `${vehicle} is ${inline(linkOrPlanned("lost", until))}: ${seconds === null ? "no report of it received" : inline(lastHeardText(seconds))}`;
}

// Alarm management on a watch: shelves, chattering, floods and planned silences, said with the table's words.

/** "3 shelved": the alarms out of view. */
export function shelvedCount(n: number): string {
  return `${n} ${inline(ALARM_MARK.shelved)}`;
}

/** "shelved by alice on watch until 14:20 UTC: relay down, known". */
export function shelvedText(by: string | null, station: string | null, until: number, reason: string): string {
  return `${inline(ALARM_MARK.shelved)}${by ? ` by ${by}` : ""}${station ? ` on ${station}` : ""} until ${clockTime(until)}: ${reason}`;
}

export const CHATTERING_TITLE = "it cleared and came back again and again: it is not sounded again until acknowledged";

/** A flood, many alarms of one cause at once, as one heading: "Link lost: 20 vehicles" (`cause`: the kind's words). */
export function floodText(cause: string, alarms: readonly { providerId: string | null }[]): string {
  const n = alarms.length;
  const vehicles = new Set(alarms.flatMap((a) => (a.providerId === null ? [] : [a.providerId]))).size;
  const count = (k: number, one: string) => `${k} ${one}${k === 1 ? "" : "s"}`;
  if (vehicles === n) return `${cause}: ${count(n, "vehicle")}`;
  // several alarms of one vehicle (its failed commands), or alarms of no vehicle (relays): alarms, not vehicles
  return `${cause}: ${count(n, "alarm")}${vehicles > 0 ? ` of ${count(vehicles, "vehicle")}` : ""}`;
}

/** A vehicle lost in its planned silence: "Out of comms (planned) until 14:20 UTC", wherever it is named. */
export function plannedText(until: number): string {
  return `${LINK.planned} until ${clockTime(until)}`;
}

/** The vehicles lost in their planned silence, by when each silence ends (`ends`, one per vehicle): "1 out of comms
 * (planned) until 14:20 UTC", "3 out of comms (planned), the soonest until 14:20 UTC". */
export function plannedCount(ends: readonly number[]): string {
  const soonest = clockTime(Math.min(...ends));
  return ends.length === 1
    ? `1 ${inline(plannedText(ends[0]))}`
    : `${ends.length} ${inline(LINK.planned)}, the soonest until ${soonest}`;
}

/** A planned silence as the list of them says it: "Alpha: out of comms (planned) until 14:20 UTC: dive (declared by
 * alice on watch)". */
export function plannedEntry(vehicle: string, until: number, reason: string, by: string | null, station: string | null): string {
  const who = by || station ? ` (declared${by ? ` by ${by}` : ""}${station ? ` on ${station}` : ""})` : "";
  return `${vehicle}: ${inline(plannedText(until))}: ${reason}${who}`;
}

/** A vehicle's link in a word, its planned silence's words when it is lost in one (`plannedUntil`, see the store's
 * plannedUntil): "Lost", or "Out of comms (planned) until 14:20 UTC". */
export function linkOrPlanned(link: LinkState | "stale" | "unreachable", until: number | null): string {
  return until !== null ? plannedText(until) : linkText(link);
}

/** A lost vehicle's state inside a sentence, by the same rule (`until`: plannedUntil): "lost", or "out of comms
 * (planned) until 14:20 UTC": an order's tooltip, a CoMap task's row, an order left unsent. */
export function lostClause(until: number | null): string {
  return inline(linkOrPlanned("lost", until));
}

/** What an order's button adds while its vehicle is lost: " (vehicle lost)", or in its planned silence (`until`:
 * plannedUntil) " (out of comms)": the Commands and CoMap panels alike. */
export function lostButtonNote(until: number | null): string {
  return until !== null ? " (out of comms)" : " (vehicle lost)";
}

/** A confirmation left unsent because its vehicle was lost while it was open, named by the same rule as everywhere
 * (`until`: plannedUntil): "INS OFF for Alpha (77b2ceb8) not sent: the vehicle is now lost.", or "… is now out of
 * comms (planned) until 14:20 UTC.". */
export function lostMeanwhileText(what: string, vehicle: string, until: number | null): string {
  return `${what} for ${vehicle} not sent: the vehicle is now ${lostClause(until)}.`;
}

export function plannedTitle(reason: string, by: string | null, station: string | null): string {
  return `planned silence${by ? ` declared by ${by}` : ""}${station ? ` on ${station}` : ""}: ${reason}; a loss raises no alarm until then and the console's grace after it`;
}

/** A vehicle seen through a relay: "Via relay ship-1, 1.4 s old" (`ageS`: of its newest data, by its own time stamp;
 * null: none yet, "Via relay ship-1"), and what that means for the tooltip. */
export function relayText(relay: string, ageS: number | null): { text: string; title: string } {
  const fill = (w: string) => w.replace("{relay}", relay).replace("{age}", age(ageS));
  return { text: fill(ageS === null ? RELAY.unknown : RELAY.via), title: fill(RELAY.title) };
}
