// Review of the `interest` merge: defects shown by failing tests (real reducer, real freshness).
import { describe, expect, it } from "vitest";
import type { ServerMessage } from "../api/types";
import { freshness } from "../lib/freshness";
import { vehicleMark } from "../panels/Map/layers";
import { brief, reportMessage, snapshotMessage, vehicle } from "./testing";
import { briefLoaded, paceOf, select } from "./slices/vehicles";
import { initialState, reduce, type State } from "./state";

const A = "77b2ceb8-5afe-554e-8450-93db17c48923";
const B = "0b6a4c1e-2f4d-5e8a-9c3b-7d1e2f3a4b5c";
const FIX = {
  position2DWithTime: { geodeticPosition: { geodeticLatitude: { latitude: 36.8 }, geodeticLongitude: { longitude: -75.7 } } },
};

describe("review2: the selected vehicle after being paced", () => {
  it("is stale once silent past the fix's 1.5 s floor, not past three times the pace it came at while not drawn", () => {
    // 1,000 vehicles: the console paces the vehicles the page does not draw at 10 s
    let s: State = reduce(initialState, snapshotMessage({ providers: [vehicle(A), vehicle(B)] }), 0);
    s = select(s, B);
    s = reduce(s, { type: "pace", othersEvery: 10 } as ServerMessage, 0);
    // A's GPSFixReport reaches the page once a pace (its rate is 10 Hz at the console)
    let t = 0;
    for (let i = 1; i <= 6; i++) s = reduce(s, reportMessage(A, "GPSFixReport", FIX, [], (t = 10 * i)), t);
    // the operator selects A: the console sends it at full rate (10 Hz) from now
    s = select(s, A);
    for (let i = 1; i <= 5; i++) s = reduce(s, reportMessage(A, "GPSFixReport", FIX, [], t + 0.1 * i), t + 0.1 * i);
    expect(paceOf(s, A)).toBe(0); // judged by its own rate now
    const view = s.providers[A].topics.GPSFixReport!;
    // then A goes silent for 5 s (the console's link timeout not yet passed for this vehicle's configuration)
    const now = view.at + 5;
    // the Fix panel's freshness (Fix.tsx) and the map's selected ring (layers.ts) of the selected vehicle
    expect(freshness(now - view.at, "GPSFixReport", view.interval, "live", true)).toBe("stale");
    expect(vehicleMark(s.providers[A], now, A, new Set(), true, [], paceOf(s, A))?.link).toBe("stale");
  });
});

describe("review2: a vehicle built from a brief after a reconnect", () => {
  it("shows the link configuration the console has now, not the one the page had before it lost the console", () => {
    const old = { commsLostTimeout: 3, regainedTime: 3, policy: "STOP_MISSION", regainedBehavior: 0 } as const;
    const now = { commsLostTimeout: 30, regainedTime: 3, policy: "CONTINUE_MISSION", regainedBehavior: 0 } as const;
    let s: State = reduce(initialState, snapshotMessage({ providers: [vehicle(A), vehicle(B, { linkConfig: old })] }), 0);
    s = select(s, A);
    // the page lost the console; meanwhile another station changed B's link configuration to `now`; the page
    // reconnects with ?vehicle=A: B comes as its brief (which carries no link configuration)
    s = reduce(s, snapshotMessage({ serverTime: 100, providers: [vehicle(A)], fleet: [brief(B, 99)] }), 100);
    // the operator selects B: the page loads its detail (GET /api/providers/{id}), which has `now`
    s = select(s, B);
    const detail = { ...vehicle(B, { linkConfig: now }), reports: {} };
    s = briefLoaded(s, B, detail as never);
    expect(s.providers[B].linkConfig).toEqual(now); // the Gateways panel's form shows (and would send) this
  });
});
