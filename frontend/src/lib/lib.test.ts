import { describe, expect, it } from "vitest";
import type { Command } from "../api/types";
import WORDS from "../../schema/words.json";
import { cancelText, inTimeOrder, mergeCommands, statusText, transitionReason } from "./commands";
import { exportName, exportUrl, rangeQuery, utcParam } from "./exports";
import {
  fleetState,
  freshness,
  freshnessText,
  nextInterval,
  pageLink,
  recordedState,
  staleAfter,
  staleTitle,
  stateWords,
} from "./freshness";
import { satelliteLabel } from "./satellites";
import { project, trailPath } from "./skyplot";
import { DASH, age, clockTime, degrees, dms, fixed, latLon, speed, utc } from "./units";
import { shortId, urlWithVehicle, vehicleColor, vehicleFromUrl, vehicleHue, vehicleLabel, vehicleMatcher } from "./vehicle";

describe("vehicle identity", () => {
  const A = "77b2ceb8-5afe-554e-8450-93db17c48923";
  const B = "1c7e3a29-34a0-5d7b-9fd6-0e0f0e5f2a11";
  it("labels a vehicle by name and short id", () => {
    expect(vehicleLabel({ id: A, name: null })).toBe("Vehicle 77b2ceb8");
    expect(vehicleLabel({ id: A, name: "Alpha" })).toBe("Alpha (77b2ceb8)");
  });
  it("gives each id a stable colour", () => {
    expect(vehicleColor(A)).toBe(vehicleColor(A));
    expect(vehicleHue(A)).not.toBe(vehicleHue(B));
    expect(vehicleHue(A)).toBeGreaterThanOrEqual(0);
    expect(vehicleHue(A)).toBeLessThan(360);
  });
  it("reads and writes ?vehicle= in the address", () => {
    expect(vehicleFromUrl(`?vehicle=${A.toUpperCase()}`)).toBe(A);
    expect(vehicleFromUrl("?vehicle=<script>")).toBe(null);
    expect(vehicleFromUrl(`?vehicle=${"0123456789abcdef".repeat(2)}----`)).toBe(null); // 36 of its characters, no UUID
    expect(vehicleFromUrl("")).toBe(null);
    expect(urlWithVehicle("http://h:1/?x=1", A)).toBe(`http://h:1/?x=1&vehicle=${A}`);
    expect(urlWithVehicle(`http://h:1/?vehicle=${A}`, null)).toBe("http://h:1/");
  });
  it("finds a vehicle by a part of its name or of its id, any case, with or without the id's dashes", () => {
    const fleet = [
      { id: A, name: "Alpha" },
      { id: B, name: null },
      { id: "0a0b0c0d-0000-4000-8000-000000000077", name: "Charlie 77" },
    ];
    const found = (q: string) => fleet.filter(vehicleMatcher(q)).map((v) => v.name ?? shortId(v.id));
    expect(found("")).toEqual(["Alpha", "1c7e3a29", "Charlie 77"]);
    expect(found("  ")).toHaveLength(3);
    expect(found("alp")).toEqual(["Alpha"]);
    expect(found(" CHAR ")).toEqual(["Charlie 77"]);
    expect(found("77")).toEqual(["Alpha", "Charlie 77"]); // A's id starts 77b2, Charlie has 77 in its name
    expect(found("77B2CEB8")).toEqual(["Alpha"]);
    expect(found("ceb85afe")).toEqual(["Alpha"]); // across a dash
    expect(found("3a29-34")).toEqual(["1c7e3a29"]);
    expect(found("zulu")).toEqual([]);
    expect(found("Vehicle 1c7e")).toEqual(["1c7e3a29"]); // an unnamed one as the list names it
    expect(found("vehicle")).toEqual(["1c7e3a29"]);
  });
});

describe("sky-plot projection", () => {
  const R = 100;
  it("puts the zenith at the centre and the horizon on the rim", () => {
    expect(project(1.0, Math.PI / 2, R)).toEqual({ x: 0, y: -0 });
    const north = project(0, 0, R)!;
    expect(north.x).toBeCloseTo(0);
    expect(north.y).toBeCloseTo(-R);
  });
  it("puts east right, south down, west left (azimuth -pi..pi or 0..2pi)", () => {
    const east = project(Math.PI / 2, 0, R)!;
    expect(east.x).toBeCloseTo(R);
    expect(east.y).toBeCloseTo(0);
    expect(project(Math.PI, 0, R)!.y).toBeCloseTo(R);
    const west1 = project(-Math.PI / 2, 0, R)!;
    const west2 = project((3 * Math.PI) / 2, 0, R)!;
    expect(west1.x).toBeCloseTo(-R);
    expect(west2.x).toBeCloseTo(west1.x);
  });
  it("scales radius linearly with elevation and clamps below the horizon", () => {
    const p = project(Math.PI / 2, Math.PI / 4, R)!;
    expect(p.x).toBeCloseTo(R / 2);
    expect(project(0, -0.3, R)!.y).toBeCloseTo(-R);
  });
  it("refuses missing or non-finite angles", () => {
    expect(project(null, 0.5, R)).toBeNull();
    expect(project(0.5, Number.NaN, R)).toBeNull();
    expect(project(undefined, undefined, R)).toBeNull();
  });
  it("draws trails of two or more points", () => {
    expect(trailPath([{ x: 0, y: 0 }])).toBe("");
    expect(
      trailPath([
        { x: 0, y: 0 },
        { x: 1.25, y: -2 },
      ]),
    ).toBe("M0.0,0.0 L1.3,-2.0");
  });
});

describe("unit formatting", () => {
  it("shows a dash for missing or non-finite values", () => {
    for (const f of [
      (v: number | null) => fixed(v, 1, "m"),
      degrees,
      speed,
      (v: number | null) => latLon(v, true),
      (v: number | null) => dms(v, false),
      utc,
      age,
    ]) {
      expect(f(null)).toBe(DASH);
      expect(f(Number.NaN)).toBe(DASH);
    }
  });
  it("converts radians to degrees, bearings wrapped to 0..360", () => {
    expect(degrees(Math.PI / 2)).toBe("90.0°");
    expect(degrees(-Math.PI / 2, 0, true)).toBe("270°");
  });
  it("gives speed in m/s and knots", () => {
    expect(speed(1)).toBe("1.00 m/s (1.94 kn)");
  });
  it("formats positions as decimal degrees and DMS with hemispheres", () => {
    expect(latLon(36.8, true)).toBe("36.800000° N");
    expect(latLon(-75.7, false)).toBe("75.700000° W");
    expect(dms(36.80012222, true)).toBe("36° 48′ 00.44″ N");
    expect(dms(-75.5, false)).toBe("75° 30′ 00.00″ W");
    expect(dms(10.999999, true)).toBe("11° 00′ 00.00″ N");
  });
  it("writes every time on screen one way: 'UTC' after it, never 'Z'", () => {
    expect(utc(0)).toBe("1970-01-01 00:00:00.000 UTC");
    expect(utc(90061.5, false)).toBe("01:01:01.500 UTC");
    expect(utc(90061.5, false, "s")).toBe("01:01:01 UTC");
    expect(utc(90061.56, true, "ds")).toBe("1970-01-02 01:01:01.5 UTC");
    expect(clockTime(90061.5, 90000)).toBe("01:01 UTC"); // today's: the time alone
    expect(clockTime(90061.5, 0)).toBe("1970-01-02 01:01 UTC"); // another day's: with its date
  });
});

describe("freshness", () => {
  it("is live within the allowance, stale after, lost when the link is lost", () => {
    expect(freshness(0.5, "GPSFixReport", 0.1, "live", true)).toBe("live");
    expect(freshness(2.0, "GPSFixReport", 0.1, "live", true)).toBe("stale");
    expect(freshness(2.0, "GPSReport", 1.0, "live", true)).toBe("live");
    expect(freshness(3.5, "GPSReport", 1.0, "regained", true)).toBe("stale");
    expect(freshness(0.1, "GPSReport", 1.0, "lost", true)).toBe("lost");
    expect(freshness(null, "GPSReport", null, "live", true)).toBe("none");
  });
  it("says at once that nothing is current when the page does not hear the console, however recent the data", () => {
    expect(freshness(0.1, "GPSFixReport", 0.1, "live", false)).toBe("unreachable");
    expect(freshnessText("unreachable", false)).toBe("Not updating");
    expect(pageLink("live", 0.1, 3, false)).toBe("unreachable");
    expect(pageLink("regained", 0.1, 3, false)).toBe("unreachable");
    expect(pageLink("lost", 30, 3, false)).toBe("lost"); // the worse of what it may be now
    expect(pageLink("live", 0.1, 3, true)).toBe("live");
    expect(pageLink("live", 4, 3, true)).toBe("stale");
  });
  it("says a lost vehicle lost in its panels too when the page does not hear the console, as the fleet bar does", () => {
    expect(freshness(130, "GPSFixReport", 0.1, "lost", false)).toBe("lost");
    expect(pageLink("lost", 130, 3, false)).toBe("lost");
  });
  it("says a regained vehicle gone silent again stale in the fleet bar and list, as its panels do", () => {
    expect(freshness(4, "GPSFixReport", 0.1, "regained", true)).toBe("stale");
    expect(pageLink("regained", 4, 3, true)).toBe("stale");
    expect(fleetState(pageLink("regained", 4, 3, true), false)).toBe("stale");
    expect(fleetState(pageLink("regained", 0.5, 3, true), false)).toBe("live");
  });
  it("allows a vehicle the console paces 3 s and its pace, whatever interval it observed, as the fleet bar says", () => {
    // paced at 10 s: its fixes come 10 s apart, each up to a second old as it went, and it is silent only past 3 + 10 s
    expect(freshness(9.9, "GPSFixReport", 10, "live", true, 10)).toBe("live");
    expect(freshness(12.9, "GPSFixReport", 10, "live", true, 10)).toBe("live");
    expect(freshness(13.1, "GPSFixReport", 10, "live", true, 10)).toBe("stale");
    expect(freshness(13.1, "GPSFixReport", 10, "lost", true, 10)).toBe("lost");
    expect(staleTitle(3, null)).toBe("no report for over 3 s");
    expect(staleTitle(3, 10)).toBe(
      "no report for over 3 s (over 13 s for a vehicle not selected: the console sends each of them every 10 s)",
    );
  });
  it("allows three observed intervals for slow topics", () => {
    expect(staleAfter("InertialSensorReport", 2)).toBe(6);
    expect(staleAfter("InertialSensorReport", null)).toBe(1.5);
  });
  it("says a replay's state is the recording's: no badge says Live in a replay, live words unchanged", () => {
    for (const words of ["Live", "live", "Regained", "stale", "Lost", "3 live"]) {
      expect(stateWords(words, false)).toBe(words);
      expect(stateWords(words, true)).toMatch(/^Recorded: /);
      expect(stateWords(words, true)).not.toMatch(/^live/i);
    }
    expect(stateWords("Live", true)).toBe("Recorded: live");
  });
  it("says a replay's console unreachable as the page's state now, not the recording's", () => {
    expect(freshnessText("unreachable", true)).toBe("Not updating");
    expect(recordedState("unreachable", true)).toBe(false);
    expect(recordedState("lost", true)).toBe(true);
    expect(recordedState("live", false)).toBe(false);
    expect(freshnessText("lost", true)).toBe("Recorded: lost");
    expect(stateWords("GPS 3D", true)).toBe("Recorded: GPS 3D"); // lowered inside a phrase as the table says (`inline`)
  });
  it("learns the interval but not from gaps", () => {
    expect(nextInterval(null, 0.1)).toBe(0.1);
    expect(nextInterval(0.1, 0.2)).toBeCloseTo(0.12);
    expect(nextInterval(0.1, 10)).toBe(0.1);
    expect(nextInterval(0.1, -1)).toBe(0.1);
  });
});

describe("satellite labels", () => {
  it("decodes the simulator's satelliteId convention", () => {
    // satellite_guid(GALILEO, 7) as the backend makes it
    expect(satelliteLabel("ca5d35fb-bcc2-5b9a-b20c-df56b7b90207")).toBe("E07");
    expect(satelliteLabel("ca5d35fb-bcc2-5b9a-b20c-df56b7b90785")).toBe("S133");
  });
  it("falls back to a short id", () => {
    expect(satelliteLabel("12345678-0000-4000-8000-000000000000")).toBe("12345678");
    expect(satelliteLabel(null)).toBe("?");
  });
});

describe("exports", () => {
  const V = "77b2ceb8-5afe-554e-8450-93db17c48923";
  const now = Date.parse("2026-11-22T12:00:00Z");
  it("turns a range into UTC ISO 8601 parameters", () => {
    expect(rangeQuery({ kind: "last", hours: 1 }, now)).toEqual({ since: "2026-11-22T11:00:00Z" });
    expect(rangeQuery({ kind: "all" }, now)).toEqual({});
    expect(rangeQuery({ kind: "between", since: "2026-11-22T08:00", until: "" }, now)).toEqual({ since: "2026-11-22T08:00:00Z" });
    expect(rangeQuery({ kind: "between", since: "2026-11-22T09:00", until: "2026-11-22T08:00" }, now)).toEqual({
      error: "From is after To",
    });
    expect(rangeQuery({ kind: "between", since: "soon", until: "" }, now)).toEqual({
      error: "From: write a UTC date and time, 24-hour, as YYYY-MM-DD HH:MM",
    });
    expect(rangeQuery({ kind: "between", since: "2026-11-22 08:00", until: "11/22/2026, 09:00 AM" }, now)).toEqual({
      error: "To: write a UTC date and time, 24-hour, as YYYY-MM-DD HH:MM",
    });
    expect(utcParam("2026-02-30T08:00")).toBe(null);
    expect(utcParam("2026-11-22 08:00:30")).toBe("2026-11-22T08:00:30Z");
  });
  it("builds the console's export URLs and file names", () => {
    const q = { since: "2026-11-22T11:00:00Z" };
    expect(exportUrl("gpx", V, q)).toBe(`/api/providers/${V}/track.gpx?since=2026-11-22T11%3A00%3A00Z`);
    expect(exportUrl("csv", V, {})).toBe(`/api/providers/${V}/track.csv`);
    expect(exportUrl("commands", V, { until: "2026-11-22T11:00:00Z" })).toBe(
      `/api/commands.csv?provider_id=${V}&until=2026-11-22T11%3A00%3A00Z`,
    );
    expect(exportUrl("commands", null, {})).toBe("/api/commands.csv");
    expect(exportName("gpx", V)).toBe(`track_${V}.gpx`);
    expect(exportName("commands", null)).toBe("commands.csv");
  });
});

describe("command pager", () => {
  it("merges live commands with older pages: no repeats, newest first, the live copy wins", () => {
    const c = (sessionId: string, createdAt: number, status: string) => ({ sessionId, createdAt, status }) as never;
    const merged = mergeCommands([c("b", 2, "EXECUTING"), c("c", 3, "ISSUED")], [c("b", 2, "ISSUED"), c("a", 1, "COMPLETED")]);
    expect(merged.map((x) => `${x.sessionId}:${x.status}`)).toEqual(["c:ISSUED", "b:EXECUTING", "a:COMPLETED"]);
  });

  it("in a replay leaves out the history's commands requested after the instant shown (the history holds the whole recording)", () => {
    const c = (sessionId: string, createdAt: number) => ({ sessionId, createdAt, status: "COMPLETED" }) as never;
    const history = [c("later", 20), c("then", 10), c("before", 5)];
    expect(mergeCommands([], history, 10).map((x) => x.sessionId)).toEqual(["then", "before"]);
    expect(mergeCommands([], history, 4)).toEqual([]);
    expect(mergeCommands([], history, null).map((x) => x.sessionId)).toEqual(["later", "then", "before"]);
  });
});

describe("command timeline", () => {
  it("puts its lines in the order they happened: the acknowledgement after the status before it, untimed ones last", () => {
    const lines = [
      { at: 10, what: "Requested" },
      { at: 11, what: "Received" },
      { at: 14, what: "Failed" },
      { at: 11, what: "Acknowledged" }, // came with Received, after it
      { at: Infinity, what: "Cancel asked (time not recorded)" },
      { at: 12, what: "Cancel asked" },
    ];
    expect(inTimeOrder(lines).map((l) => l.what)).toEqual([
      "Requested",
      "Received",
      "Acknowledged",
      "Cancel asked",
      "Failed",
      "Cancel asked (time not recorded)",
    ]);
  });
});

describe("a command card's words", () => {
  const cmd = (over: Partial<Command> = {}): Command => ({
    sessionId: "s1",
    service: "GPSFix",
    providerId: "p1",
    state: null,
    operator: "alice",
    createdAt: 1,
    status: null,
    terminal: false,
    unanswered: false,
    cancelRequested: false,
    canceledBy: null,
    cleanedUp: false,
    console: "watch",
    ackedAt: null,
    violations: [],
    transitions: [],
    ...over,
  });
  it("says a cancel with the words table's status and reason, and who asked it where", () => {
    const canceled = cmd({ status: "CANCELED", terminal: true, cancelRequested: true, canceledBy: "bob", canceledOn: "relief" });
    expect(statusText(canceled)).toBe(WORDS.CommandStatusEnumType.CANCELED);
    expect(transitionReason(canceled, "CANCELED", "CANCELED")).toBe("on request by bob on relief");
    // a cancel nobody at a console asked for: the reason word alone
    expect(transitionReason(cmd({ status: "CANCELED" }), "CANCELED", "CANCELED")).toBe("on request");
    expect(transitionReason(canceled, "FAILED", "RESOURCE_FAILED")).toBe("the equipment failed");
  });
  it("says a cancel of a station's shutdown as such, not as if someone on watch asked it", () => {
    const stopped = cmd({
      status: "CANCELED",
      terminal: true,
      cancelRequested: true,
      canceledBy: null,
      canceledOn: "watch",
      cancelCause: "shutdown",
    });
    expect(cancelText(stopped)).toBe(`${WORDS.cancelCause.shutdown}: watch cancelled it as it stopped`);
    expect(transitionReason(stopped, "CANCELED", "CANCELED")).toBe("on request of watch as it stopped");
    const asked = cmd({ cancelRequested: true, canceledBy: null, canceledOn: "watch", cancelCause: "operator" });
    expect(cancelText(asked)).toBe(`${WORDS.cancelCause.operator} on watch`);
    expect(cancelText(cmd({ cancelRequested: true }))).toBeNull();
    expect(cancelText(cmd())).toBeNull();
  });
  it("says a command the vehicle never answered in the table's words", () => {
    expect(statusText(cmd({ unanswered: true }))).toBe(WORDS.command.unanswered);
    expect(statusText(cmd({ unanswered: true, cancelRequested: true, terminal: true, closedUnheard: "heard" }))).toBe(
      "Cancelled before the vehicle heard it",
    );
    expect(statusText(cmd({ unanswered: true, cancelRequested: true, terminal: true, closedUnheard: "bound" }))).toBe(
      "Cancelled, never answered",
    );
    expect(statusText(cmd())).toBe("Sent");
  });
});
