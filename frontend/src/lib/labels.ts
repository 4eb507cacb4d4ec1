// Operator words for the UMAA (and CoMap) literals the panels show. An operator at sea reads "Dead
// reckoning", not GPS_DEAD_RECK; the literal stays available in a tooltip (`umaa`), for the engineer
// comparing the screen with a log. A literal this table does not know (a newer ICD, another vendor's
// value) is shown as it is rather than hidden.
import type { GPSConstellationEnumType, InertialSensorOpStatusEnumType, InertialSensorStateEnumType } from "../api/types";
import { DASH, elapsedText } from "./units";

type Words<T extends string> = Record<T, string>;

function lookup<T extends string>(words: Words<T>, v: string | null | undefined): string {
  if (v === null || v === undefined || v === "") return DASH;
  return (words as Record<string, string>)[v] ?? v;
}

/** The tooltip that keeps the protocol's word: "UMAA navSolution: GPS_DEAD_RECK". */
export function umaa(field: string, literal: string | null | undefined): string | undefined {
  return literal === null || literal === undefined || literal === "" ? undefined : `UMAA ${field}: ${literal}`;
}

const INS_STATE: Words<InertialSensorStateEnumType> = { OFF: "Off", ON: "On", RESTARTING: "Restarting" };

export function insStateText(v: string | null | undefined): string {
  return lookup(INS_STATE, v);
}

const INS_STATUS: Words<InertialSensorOpStatusEnumType> = {
  INIT: "Starting up",
  COURSE_STATIONARY_ALIGNMENT: "Coarse alignment, stationary",
  COURSE_GPS_ALIGNMENT: "Coarse alignment, GPS-aided",
  FINE_STATIONARY_ALIGNMENT_STARTED: "Fine alignment, stationary",
  FINE_GPS_ALIGNMENT_STARTED: "Fine alignment, GPS-aided",
  FINE_STATIONARY_ALIGNMENT_COMPLETE: "Fine alignment done",
  FINE_GPS_ALIGNMENT_COMPLETE: "Fine alignment done, GPS-aided",
  OPERATIONAL: "Operational",
  INERTIAL_SENSOR_FAILURE: "Sensor failure",
};

export function insStatusText(v: string | null | undefined): string {
  return lookup(INS_STATUS, v);
}

/** The alignment steps as the INS panel lists them (the stationary names, GPS-aided stages map onto them). */
export function alignmentStepText(v: InertialSensorOpStatusEnumType): string {
  if (v === "COURSE_STATIONARY_ALIGNMENT") return "Coarse alignment";
  if (v === "FINE_STATIONARY_ALIGNMENT_STARTED") return "Fine alignment";
  return insStatusText(v);
}

const FIX_COMMAND: Words<"INITIATING" | "PERFORMING" | "STABLE"> = { INITIATING: "Starting", PERFORMING: "In progress", STABLE: "Stable" };

/** GPSFixReport.GPSFixCommandStatus: where the receiver is with a commanded fix. */
export function fixCommandText(v: string | null | undefined): string {
  return lookup(FIX_COMMAND, v);
}

const NAV_SOLUTION: Words<"GPS_1" | "GPS_2" | "GPS_2D" | "GPS_3" | "GPS_3D" | "GPS_4" | "GPS_DEAD_RECK" | "NO_NAV"> = {
  GPS_1: "GPS, 1 satellite",
  GPS_2: "GPS, 2 satellites",
  GPS_2D: "GPS 2D",
  GPS_3: "GPS, 3 satellites",
  GPS_3D: "GPS 3D",
  GPS_4: "GPS, 4 satellites",
  GPS_DEAD_RECK: "Dead reckoning",
  NO_NAV: "No navigation",
};

export function navSolutionText(v: string | null | undefined): string {
  return lookup(NAV_SOLUTION, v);
}

/** GPSFixStatusReport.timeOut: the receiver gave up finding a fix in time. */
export function timeOutText(v: boolean | null | undefined): string {
  return v === true ? "Timed out, no fix in time" : v === false ? "Not timed out" : DASH;
}

const CONSTELLATION: Words<GPSConstellationEnumType> = {
  UNKNOWN: "Unknown",
  BEIDOU: "BeiDou",
  GALILEO: "Galileo",
  GLONASS: "GLONASS",
  GPS: "GPS",
  IRNSS: "NavIC",
  QZSS: "QZSS",
  SBAS: "SBAS",
};

export function constellationText(v: string | null | undefined): string {
  return lookup(CONSTELLATION, v);
}

// UMAA CommandStatusEnumType and CommandStatusReasonEnumType (ICD Figure 4)
const COMMAND_STATUS: Words<"ISSUED" | "COMMANDED" | "EXECUTING" | "COMPLETED" | "FAILED" | "CANCELED"> = {
  ISSUED: "Received",
  COMMANDED: "Accepted",
  EXECUTING: "In progress",
  COMPLETED: "Completed",
  FAILED: "Failed",
  CANCELED: "Cancelled",
};

export function commandStatusText(v: string | null | undefined): string {
  return lookup(COMMAND_STATUS, v);
}

const REASON: Words<"SUCCEEDED" | "CANCELED" | "VALIDATION_FAILED" | "OBJECTIVE_FAILED" | "SERVICE_FAILED" | "RESOURCE_FAILED" | "RESOURCE_REJECTED" | "INTERRUPTED" | "TIMEOUT" | "UPDATED"> = {
  SUCCEEDED: "",
  CANCELED: "as asked",
  VALIDATION_FAILED: "the vehicle found the request invalid",
  OBJECTIVE_FAILED: "the goal could not be reached",
  SERVICE_FAILED: "the vehicle's service failed",
  RESOURCE_FAILED: "the equipment failed",
  RESOURCE_REJECTED: "the vehicle refused it",
  INTERRUPTED: "another command took over",
  TIMEOUT: "timed out",
  UPDATED: "updated",
};

/** A transition's reason in words; "" when it says nothing more than the status (SUCCEEDED). */
export function reasonText(v: string | null | undefined): string {
  if (v === null || v === undefined || v === "") return "";
  return lookup(REASON, v);
}

// CoMap (IMC) tasks
const TASK_STATE: Words<"ASSIGNED" | "ACCEPTED" | "REJECTED" | "IN_PROGRESS" | "HELD" | "COMPLETED" | "ERROR" | "INTERRUPTED"> = {
  ASSIGNED: "Sent",
  ACCEPTED: "Accepted",
  REJECTED: "Refused",
  IN_PROGRESS: "In progress",
  HELD: "Hold sent", // CoMap has no acknowledgement of a SynchAdmin: what was sent, not what the vehicle did
  COMPLETED: "Completed",
  ERROR: "Error",
  INTERRUPTED: "Interrupt sent",
};

export function taskStateText(v: string | null | undefined): string {
  return lookup(TASK_STATE, v);
}

const TASK_KIND: Words<"survey" | "move"> = { survey: "Survey", move: "Move" };

export function taskKindText(v: string | null | undefined): string {
  return lookup(TASK_KIND, v);
}

const SENSOR: Words<"ANY" | "SIDESCAN" | "MULTIBEAM" | "CAMERA" | "MAGNETOMETER"> = {
  ANY: "Any sensor",
  SIDESCAN: "Side-scan sonar",
  MULTIBEAM: "Multibeam sonar",
  CAMERA: "Camera",
  MAGNETOMETER: "Magnetometer",
};

export function sensorText(v: string | null | undefined): string {
  return lookup(SENSOR, v);
}

const COVERAGE: Words<"NONE" | "PARTIAL" | "COMPLETED"> = { NONE: "Not covered", PARTIAL: "Partly covered", COMPLETED: "Covered" };

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

/** "Alpha (77b2ceb8) is lost: last heard 12 s ago"; `seconds` null: no report of it received. */
export function lostText(vehicle: string, seconds: number | null): string {
  return `${vehicle} is lost: ${seconds === null ? "no report of it received" : lastHeardText(seconds).toLowerCase()}`;
}
