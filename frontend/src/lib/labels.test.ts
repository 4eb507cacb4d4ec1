import { describe, expect, it } from "vitest";
import type { Command } from "../api/types";
import { durationOf, expectedDuration } from "./commands";
import { exportFileName } from "./exports";
import wsSchema from "../../schema/ws-schema.json";
import {
  alignmentBar,
  alignmentStepText,
  insFailed,
  positionKind,
  timeQuality,
  commandStatusText,
  coverageText,
  ALARM_MARK,
  ALARM_RETURNED,
  ALARM_SEVERITY,
  ALARM_STATE,
  floodText,
  plannedCount,
  plannedEntry,
  plannedTitle,
  linkOrPlanned,
  plannedText,
  shelvedCount,
  shelvedText,
  alarmKindText,
  fixStateBadge,
  fixStateText,
  fixBadge,
  fixWord,
  inline,
  insWord,
  notReported,
  linkText,
  UMAA_WORDS,
  insStateText,
  insStatusText,
  lostButtonNote,
  lostClause,
  lostMeanwhileText,
  lostText,
  navSolutionText,
  positionSourceText,
  positionText,
  reasonText,
  sensorText,
  taskStateText,
  timeOutText,
  umaa,
} from "./labels";

/** The UMAA enumerations the console's WebSocket schema has, with their literals, and the alarm kinds. */
const schemaDefs = (wsSchema as { $defs: Record<string, { enum?: string[]; properties?: Record<string, { enum?: string[] }> }> })
  .$defs;
const umaaEnums = Object.entries(schemaDefs).flatMap(([name, d]) =>
  d.enum && name.endsWith("EnumType") ? [[name, d.enum] as const] : [],
);

describe("the words table (backend/sem_console/core/words.py, published as schema/words.json)", () => {
  it("has words for every literal of every UMAA enumeration the console sends", () => {
    expect(umaaEnums.map(([name]) => name)).toEqual(
      expect.arrayContaining(["GPSFixEnumType", "InertialSensorOpStatusEnumType", "InertialSensorStateEnumType"]),
    );
    for (const [name, literals] of umaaEnums) {
      const table = UMAA_WORDS[name];
      expect(table, `no words table for ${name}`).toBeDefined();
      for (const literal of literals) expect(table[literal]?.trim(), `${name}.${literal} has no words`).toBeTruthy();
    }
  });

  it("has words for every alarm kind, severity and state", () => {
    const alarm = schemaDefs.Alarm.properties!;
    for (const kind of alarm.kind.enum!) expect(alarmKindText(kind), kind).not.toBe(kind);
    for (const severity of alarm.severity.enum!)
      expect((ALARM_SEVERITY as Record<string, string>)[severity]?.trim(), severity).toBeTruthy();
    for (const state of alarm.state.enum!) expect((ALARM_STATE as Record<string, string>)[state]?.trim(), state).toBeTruthy();
  });

  it("has words for a watch's states: an alarm shelved or chattering, why it is back, a vehicle out of comms as planned", () => {
    const alarm = schemaDefs.Alarm.properties!;
    expect(Object.keys(alarm)).toEqual(expect.arrayContaining(["shelf", "chattering", "returned", "cause"]));
    for (const [literal, words] of Object.entries({ ...ALARM_MARK, ...ALARM_RETURNED }))
      expect(words.trim(), literal).toBeTruthy();
    expect(linkText("planned")).toBe("Out of comms (planned)");
  });

  it("says a watch's phrases with the table's words", () => {
    const now = Date.parse("2026-11-28T22:00:00Z") / 1000;
    const soon = now + 20 * 60;
    expect(plannedText(soon)).toMatch(/^Out of comms \(planned\) until (2026-11-28 )?22:20 UTC$/);
    // the fleet bar's count says when: the end of one, the soonest end of several
    expect(plannedCount([soon])).toMatch(/^1 out of comms \(planned\) until (2026-11-28 )?22:20 UTC$/);
    expect(plannedCount([soon + 600, soon])).toMatch(/^2 out of comms \(planned\), the soonest until (2026-11-28 )?22:20 UTC$/);
    expect(plannedEntry("Alpha", soon, "dive", "alice", "watch")).toMatch(
      /^Alpha: out of comms \(planned\) until .*22:20 UTC: dive \(declared by alice on watch\)$/,
    );
    expect(plannedEntry("Alpha", soon, "dive", null, null)).toMatch(/^Alpha: out of comms \(planned\) until .*22:20 UTC: dive$/);
    expect(plannedTitle("dive", "alice", "watch")).toMatch(/^planned silence declared by alice on watch: dive;/);
    // a lost vehicle in its planned silence has one name wherever it is said: the chip's, the list's, the panels'
    expect(linkOrPlanned("lost", soon)).toBe(plannedText(soon));
    expect(linkOrPlanned("lost", null)).toBe("Lost");
    expect(lostText("Alpha", 12, soon)).toMatch(/^Alpha is out of comms \(planned\) until .*22:20 UTC: last heard 12 s ago$/);
    expect(lostText("Alpha", 12)).toBe("Alpha is lost: last heard 12 s ago");
    // a confirmation left unsent as its vehicle went out of reach: named by the same rule (plannedUntil)
    expect(lostClause(null)).toBe("lost");
    expect(lostClause(soon)).toMatch(/^out of comms \(planned\) until .*22:20 UTC$/);
    expect(lostButtonNote(null)).toBe(" (vehicle lost)");
    expect(lostButtonNote(soon)).toBe(" (out of comms)");
    expect(lostMeanwhileText("INS OFF", "Alpha", null)).toBe("INS OFF for Alpha not sent: the vehicle is now lost.");
    expect(lostMeanwhileText("INS OFF", "Alpha", soon)).toMatch(
      /^INS OFF for Alpha not sent: the vehicle is now out of comms \(planned\) until .*22:20 UTC\.$/,
    );
    expect(shelvedCount(3)).toBe("3 shelved");
    expect(shelvedText("bob", "relief", soon, "relay down")).toMatch(/^shelved by bob on relief until .*22:20 UTC: relay down$/);
    const of = (...ids: (string | null)[]) => ids.map((providerId) => ({ providerId }));
    const twenty = of(...Array.from({ length: 20 }, (_, i) => `v${i}`));
    expect(floodText(alarmKindText("link-lost"), twenty)).toBe("Link lost: 20 vehicles");
    expect(floodText(alarmKindText("silence-overdue"), of("v1"))).toBe("Not heard after a planned silence: 1 vehicle");
    // five failed commands of one vehicle, and relays (no vehicle): alarms, not vehicles
    expect(floodText("Command failed", of("v1", "v1", "v1", "v1", "v2"))).toBe("Command failed: 5 alarms of 2 vehicles");
    expect(floodText("Relay silent", of(null, null, null, null, null))).toBe("Relay silent: 5 alarms");
  });

  it("says a UMAA 6.0 vehicle's missing fix status is its version's, not a report still to come", () => {
    expect(fixWord(undefined, "6.0")).toMatchObject({ text: "No fix service", tone: "muted" });
    expect(fixWord(undefined, "3.0.1")).toMatchObject({ text: "Fix —", tone: "muted" });
    expect(fixWord(undefined, "6.0").title).toContain("UMAA 6.0 has no GPS fix service");
    expect(notReported("6.0", "GPSFixStatusReport")).toContain("no GPS fix service");
    // its GPSReport, GlobalPose (the position report) and INS status feed the view: one may come
    for (const topic of ["GPSReport", "GPSFixReport", "InertialSensorReport"] as const)
      expect(notReported("6.0", topic)).toBeNull();
    expect(insWord(undefined, undefined, "6.0").title).toBe("no inertial sensor report yet");
    expect(fixWord(undefined, "3.0.1").title).toBe("no GPS fix status yet");
    expect(insWord(undefined, undefined, null).title).toBe("no inertial sensor report yet");
    expect(fixWord(true, "6.0").text).toBe("Fix valid");
  });

  it("says on the fix panel that a UMAA 6.0 vehicle has no fix service, not a fix lost, and its position's quality", () => {
    const measured = { navigationSolution: "MEASURED" as const };
    expect(fixBadge(undefined, "6.0", measured)).toMatchObject({ text: "No fix service", tone: "muted" });
    expect(fixBadge(undefined, "6.0", measured).title).toMatch(
      /^UMAA 6\.0 has no GPS fix service: .*\. Position quality: measured position$/,
    );
    expect(fixBadge(undefined, "6.0", null).title).toMatch(/\. Position quality: —$/);
    // a 3.0.1 vehicle: its fix status, green or red; none yet, a dash, not red
    expect(fixBadge(true, "3.0.1", null)).toMatchObject({ text: "Fix valid", tone: "ok" });
    expect(fixBadge(false, "3.0.1", null)).toMatchObject({ text: "No fix", tone: "bad" });
    expect(fixBadge(undefined, "3.0.1", null)).toMatchObject({ text: "—", tone: "muted", title: "no GPS fix status yet" });
  });

  it("gives one state one name: the fleet bar, the vehicle list and the INS panel say the status as the table does", () => {
    expect(insWord("ON", "OPERATIONAL").text).toBe(`INS ${inline(insStatusText("OPERATIONAL")!)}`);
    expect(insWord("ON", "OPERATIONAL")).toMatchObject({
      text: "INS operational",
      title: "UMAA state: ON; UMAA status: OPERATIONAL",
    });
    expect(insWord("ON", "INERTIAL_SENSOR_FAILURE").text).toBe("INS failed"); // as the alarm: "Alpha: INS failed"
    expect(insWord("OFF", "INIT").text).toBe("INS off");
    expect(fixWord(true)).toMatchObject({ text: "Fix valid", title: "UMAA fixValid: true" });
    expect(positionSourceText(false)).toBe("INS position");
    expect(positionSourceText(undefined)).toBe("—"); // no report: not said to be the INS's
    expect(linkText("unreachable")).toBe("Not updating");
    expect(inline("GPS 3D")).toBe("GPS 3D");
  });

  it("says a UMAA 6.0 INS's alignment kind and stage, and its failures, in the table's words (the literal in the tooltip)", () => {
    expect(insWord(null, "COARSE_GPS_ALIGNMENT", "6.0")).toMatchObject({
      text: "INS coarse alignment, GPS-aided",
      tone: "warn",
      title: "UMAA status: COARSE_GPS_ALIGNMENT",
    });
    expect(insWord(null, "FINE_TRANSFER_ALIGNMENT_STARTED").text).toBe("INS fine alignment, transfer");
    expect(insWord(null, "FINE_BEST_ALIGNMENT_COMPLETE", "6.0")).toMatchObject({
      text: "INS fine alignment done, best available",
      tone: "ok",
    });
    expect(insWord(null, "SNAP_ALIGNMENT_COMPLETE", "6.0")).toMatchObject({ text: "INS snap alignment done", tone: "ok" });
    // aligned is the last step of the vehicle's own alignment: a 3.0.1 INS whose fine alignment is done is not yet
    // OPERATIONAL; a 6.0 INS (no OPERATIONAL) is aligned at the completed stage
    expect(insWord("ON", "FINE_STATIONARY_ALIGNMENT_COMPLETE", "3.0.1").tone).toBe("warn");
    expect(insWord("ON", "OPERATIONAL", "3.0.1").tone).toBe("ok");
    expect(insWord(null, "FINE_STATIONARY_ALIGNMENT_COMPLETE", "6.0").tone).toBe("ok");
    // each failure is a failure, said by its kind, as the INS alarm says it ("Alpha: INS GPS-aided alignment failed")
    expect(insWord(null, "GPS_ALIGNMENT_FAILURE")).toMatchObject({ text: "INS GPS-aided alignment failed", tone: "bad" });
    expect(insWord(null, "STATIONARY_ALIGNMENT_FAILURE").text).toBe("INS stationary alignment failed");
    expect(insWord(null, "INERTIAL_SENSOR_FAILURE").text).toBe("INS failed");
    expect(insFailed("SNAP_ALIGNMENT_FAILURE") && insFailed("INERTIAL_SENSOR_FAILURE") && !insFailed("INIT")).toBe(true);
  });

  it("shows on the INS step bar the stages of the vehicle's own kind of alignment, each version's, none pending once aligned", () => {
    const words = (bar: ReturnType<typeof alignmentBar>) => bar.steps.map((x) => alignmentStepText(x.step));
    const literals = (bar: ReturnType<typeof alignmentBar>) => bar.steps.map((x) => x.status);
    // UMAA 6.0 has no OPERATIONAL: an aligned 6.0 INS is at its last step, none left pending
    const aligned = alignmentBar("6.0", "FINE_STATIONARY_ALIGNMENT_COMPLETE");
    expect(words(aligned)).toEqual(["Starting up", "Coarse alignment", "Fine alignment", "Alignment done"]);
    expect(aligned.current).toBe(aligned.steps.length - 1);
    // each step's tooltip the literal of the kind the vehicle runs (6.0 spells coarse COARSE)
    expect(literals(alignmentBar("6.0", "COARSE_GPS_ALIGNMENT"))).toEqual([
      "INIT",
      "COARSE_GPS_ALIGNMENT",
      "FINE_GPS_ALIGNMENT_STARTED",
      "FINE_GPS_ALIGNMENT_COMPLETE",
    ]);
    expect(alignmentBar("6.0", "FINE_TRANSFER_ALIGNMENT_STARTED").current).toBe(2);
    // a snap alignment has no coarse or fine stage: none is shown done
    const snap = alignmentBar("6.0", "SNAP_ALIGNMENT_COMPLETE");
    expect([words(snap), snap.current]).toEqual([["Starting up", "Alignment done"], 1]);
    // a failure is no step, on the bar of the kind that failed; a status naming no kind names no kind's literal
    expect(alignmentBar("6.0", "BEST_ALIGNMENT_FAILURE")).toMatchObject({
      current: -1,
      steps: [{ status: "INIT" }, { status: "COARSE_BEST_ALIGNMENT" }, {}, {}],
    });
    expect([literals(alignmentBar("6.0", "INIT")), alignmentBar("6.0", "INIT").current]).toEqual([["INIT", null, null, null], 0]);
    // UMAA 3.0.1: its alignment done, then OPERATIONAL
    const old = alignmentBar("3.0.1", "FINE_GPS_ALIGNMENT_COMPLETE");
    expect(words(old)).toEqual(["Starting up", "Coarse alignment", "Fine alignment", "Alignment done", "Operational"]);
    expect([old.current, literals(old)[1]]).toEqual([3, "COURSE_GPS_ALIGNMENT"]);
    expect([alignmentBar("3.0.1", "OPERATIONAL").current, literals(alignmentBar("3.0.1", "OPERATIONAL"))]).toEqual([
      4,
      ["INIT", null, null, null, "OPERATIONAL"],
    ]);
    expect(alignmentBar("3.0.1", "INIT", "OFF").current).toBe(-1); // an INS that is off is at no step
    expect(alignmentBar("3.0.1", "INERTIAL_SENSOR_FAILURE").current).toBe(-1);
  });

  it("says what kind of position it is and the clock's time quality, each version what it reports", () => {
    expect(positionKind({ navigationSolution: "ESTIMATED", GPSLatLongValid: false })).toMatchObject({
      text: "Estimated position",
      tone: "bad",
      title: "UMAA navigationSolution: ESTIMATED",
    });
    expect(positionKind({ navigationSolution: "MEASURED", GPSLatLongValid: true }).text).toBe("Measured position");
    expect(positionKind({ GPSLatLongValid: true })).toMatchObject({ text: "GPS position", title: "UMAA GPSLatLongValid: true" });
    expect(timeQuality({ timeFigureOfMerit: "TFOM_3" })).toMatchObject({
      text: "Time within 100 ns",
      title: "UMAA timeFigureOfMerit: TFOM_3",
    });
    expect(timeQuality({ timeFigureOfMerit: "TFOM_9", timeUncertainty: null }).text).toBe("Time off by over 10 ms");
    expect(timeQuality({ timeUncertainty: 12.25 }).text).toBe("± 12.3 ns");
    expect(timeQuality({}).text).toBe("—"); // nothing reported, nothing made up
  });

  it("never says an INS that is off is starting up (an INS off reports INIT: UMAA has no off status)", () => {
    expect(insStatusText("INIT", "OFF")).toBeNull();
    expect(insStatusText("INIT", "RESTARTING")).toBe("Starting up");
    expect(insStatusText("INERTIAL_SENSOR_FAILURE", "OFF")).toBe("Failed");
  });

  it("says the receiver's fix state as what the vehicle reports, never as a command's progress", () => {
    expect(fixStateBadge("INITIATING")).toBe("Receiver: initiating a fix");
    expect(fixStateBadge("STABLE")).toBe("Receiver: fix stable");
  });
});

describe("operator labels", () => {
  it("says UMAA literals in plain words and keeps the literal for the tooltip", () => {
    expect(navSolutionText("GPS_DEAD_RECK")).toBe("Dead reckoning");
    expect(navSolutionText("GPS_3D")).toBe("GPS 3D");
    expect(navSolutionText("NO_NAV")).toBe("No navigation");
    expect(umaa("navSolution", "GPS_DEAD_RECK")).toBe("UMAA navSolution: GPS_DEAD_RECK");
    expect(umaa("navSolution", null)).toBeUndefined();
    expect(insStateText("RESTARTING")).toBe("Restarting");
    expect(insStatusText("COURSE_STATIONARY_ALIGNMENT")).toBe("Coarse alignment, stationary");
    expect(insStatusText("INERTIAL_SENSOR_FAILURE")).toBe("Failed");
    expect(alignmentStepText("FINE")).toBe("Fine alignment");
    expect(fixStateText("STABLE")).toBe("Fix stable");
    expect(commandStatusText("EXECUTING")).toBe("In progress");
    expect(commandStatusText("CANCELED")).toBe("Cancelled");
    expect(reasonText("RESOURCE_REJECTED")).toBe("the vehicle refused it");
    expect(reasonText("RESOURCE_FAILED")).toBe("the equipment failed"); // as the alarm says it (the backend's table)
    expect(taskStateText("HELD")).toBe("Hold sent");
    expect(taskStateText("INTERRUPTED")).toBe("Interrupt sent");
    expect(sensorText("SIDESCAN")).toBe("Side-scan sonar");
    expect(coverageText("PARTIAL")).toBe("Partly covered");
  });

  it("says nothing more for a plain success, a dash for no value, and shows an unknown literal as it is", () => {
    expect(reasonText("SUCCEEDED")).toBe("");
    expect(reasonText(null)).toBe("");
    expect(navSolutionText(null)).toBe("—");
    expect(insStatusText(undefined)).toBe("—");
    expect(coverageText(null)).toBe("Coverage unknown");
    expect(navSolutionText("GPS_9D")).toBe("GPS_9D"); // a newer ICD's value: shown, not hidden
  });

  it("words the GPS time-out flag as a person would", () => {
    expect(timeOutText(true)).toBe("Timed out, no fix in time");
    expect(timeOutText(false)).toBe("Not timed out");
    expect(timeOutText(null)).toBe("—");
  });

  it("reads a position aloud and names a lost vehicle with how long it has been silent", () => {
    expect(positionText(42.12344, -70.56781)).toBe("42.1234 N, 70.5678 W");
    expect(positionText(-33.9, 151.2)).toBe("33.9000 S, 151.2000 E");
    expect(lostText("Alpha (77b2ceb8)", 12.4)).toBe("Alpha (77b2ceb8) is lost: last heard 12 s ago");
    expect(lostText("Alpha (77b2ceb8)", 600)).toBe("Alpha (77b2ceb8) is lost: last heard 10 min 0 s ago");
    expect(lostText("Alpha (77b2ceb8)", null)).toBe("Alpha (77b2ceb8) is lost: no report of it received");
  });
});

describe("expected duration of a running command", () => {
  const A = "77b2ceb8-5afe-554e-8450-93db17c48923";
  const B = "1c7e3a29-34a0-5d7b-9fd6-0e0f0e5f2a11";
  let n = 0;
  /** A command created at `at` that ended `took` seconds later with `status` (null: still running). */
  const cmd = (at: number, took: number | null, o: Partial<Command> = {}, status = "COMPLETED"): Command =>
    ({
      sessionId: `s${++n}`,
      service: "InertialSensor",
      providerId: A,
      state: "RESTARTING",
      createdAt: at,
      status: took === null ? "EXECUTING" : status,
      terminal: took !== null,
      transitions: took === null ? [{ receivedAt: at + 1 }] : [{ receivedAt: at + 1 }, { receivedAt: at + took }],
      ...o,
    }) as unknown as Command;

  it("is the median of the same vehicle's earlier completed commands of the same kind", () => {
    const running = cmd(1000, null);
    const all = [running, cmd(100, 30), cmd(200, 50), cmd(300, 40)];
    expect(expectedDuration(running, all)).toBe(40);
    expect(expectedDuration(running, [...all, cmd(400, 60)])).toBe(45); // an even count: the mean of the middle two
  });

  it("leaves out other vehicles, other services and states, failures, and later commands", () => {
    const running = cmd(1000, null);
    const others = [
      cmd(100, 5, { providerId: B }),
      cmd(100, 5, { service: "GPSFix", state: null }),
      cmd(100, 5, { state: "OFF" }),
      cmd(100, 5, {}, "FAILED"),
      cmd(100, 5, {}, "CANCELED"),
      cmd(2000, 5),
    ];
    expect(expectedDuration(running, others)).toBeNull();
    expect(expectedDuration(running, [...others, cmd(100, 90)])).toBe(90);
  });

  it("takes a completed command's duration from its request to its last status", () => {
    expect(durationOf(cmd(100, 30))).toBe(30);
    expect(durationOf(cmd(100, null))).toBeNull();
    expect(durationOf(cmd(100, 30, {}, "FAILED"))).toBeNull();
  });
});

describe("export file names", () => {
  const at = Date.parse("2026-11-25T14:32:59.900Z");
  it("name the vehicle, what the file holds and when, in UTC to the minute", () => {
    expect(exportFileName("commands", { id: "f0e1d2c3-0000-5000-8000-000000000003", name: "Charlie" }, at)).toBe(
      "Charlie-commands-2026-11-25T1432Z.csv",
    );
    expect(exportFileName("gpx", { id: "77b2ceb8-5afe-554e-8450-93db17c48923", name: null }, at)).toBe(
      "Vehicle-77b2ceb8-track-2026-11-25T1432Z.gpx",
    );
    expect(exportFileName("csv", { id: "77b2ceb8-5afe-554e-8450-93db17c48923", name: "Sea Dog/2" }, at)).toBe(
      "Sea-Dog-2-track-2026-11-25T1432Z.csv",
    );
    expect(exportFileName("commands", null, at)).toBe("all-vehicles-commands-2026-11-25T1432Z.csv");
  });
});
