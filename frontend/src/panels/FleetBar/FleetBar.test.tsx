// @vitest-environment jsdom
import { act, cleanup, fireEvent, screen, waitFor, within } from "@testing-library/react";
import { afterEach, describe, expect, it } from "vitest";
import { TestSource, alarm, brief, command, reportMessage, snapshotMessage, vehicle } from "../../data/testing";
import { update } from "../../data/store";
import { emptyProvider, fromSummary, select, type ProviderView, type TopicView } from "../../data/slices/vehicles";
import { renderWith } from "../testing";
import { AlarmsPanel } from "../Alarms/Alarms";
import { CHIP_LIMIT, FleetBar, fleetLink } from "./FleetBar";

const A = "77b2ceb8-5afe-554e-8450-93db17c48923";
const B = "0f3c52aa-1d7e-5b1e-9c1f-6f7d2d8e0c11";

/** Alpha live with a valid fix and its INS operational, Bravo lost with an alarm. */
function fleet(): TestSource {
  const source = new TestSource();
  renderWith(source, <FleetBar />);
  act(() =>
    source.send(
      snapshotMessage({
        providers: [vehicle(A, { name: "Alpha" }), vehicle(B, { name: "Bravo", link: "lost" })],
        alarms: [alarm(1, B)],
      }),
      reportMessage(A, "GPSFixStatusReport", { fixValid: true }, [], 1000),
      reportMessage(A, "InertialSensorReport", { state: "ON", status: "OPERATIONAL" }, [], 1000),
    ),
  );
  return source;
}

// the bar's clock of ages ticks once a second: a wait for what it draws after the page's clock moved allows several
// (Testing Library's wait: 10 s, setup.ts)

const chip = (name: string) => screen.getAllByTestId("fleet-vehicle").find((c) => c.textContent?.includes(name))!;

describe("FleetBar", () => {
  afterEach(cleanup);

  it("calls a vehicle behind a relay's rate caps stale only once silent past them, as the console calls it lost", () => {
    const heardAt = (p: ProviderView, at: number): ProviderView => ({
      ...p,
      topics: { GPSFixReport: { at, interval: null } as unknown as TopicView<"GPSFixReport"> },
    });
    const hop = (quietSeconds: number) => ({ name: "ship-1", dataTime: null, ageSeconds: null, quietSeconds });
    const capped = heardAt(fromSummary(emptyProvider(A, "live"), vehicle(A, { relay: hop(5) })), 100);
    const direct = heardAt(fromSummary(emptyProvider(B, "live"), vehicle(B)), 100);
    const uncapped = heardAt(fromSummary(emptyProvider(B, "live"), vehicle(B, { relay: hop(0) })), 100);
    expect([fleetLink(capped, 104.9, true), fleetLink(direct, 104.9, true), fleetLink(uncapped, 104.9, true)]).toEqual([
      "live", // a fix every 5 s at the satellite caps: not stale between two
      "stale",
      "stale",
    ]);
    expect(fleetLink(capped, 107.9, true)).toBe("live");
    expect(fleetLink(capped, 108.1, true)).toBe("stale"); // 3 s past its caps
  });

  it("counts the live and lost vehicles and the unacknowledged alarms, the lost one first, each with its words", async () => {
    fleet();
    await waitFor(() => expect(screen.getByTestId("fleet-live").textContent).toBe("1 live"));
    expect(screen.getByTestId("fleet-lost").textContent).toBe("1 lost");
    expect(screen.getByTestId("fleet-alarms").textContent).toBe("1 unacknowledged alarm");
    expect(screen.getAllByTestId("fleet-link").map((l) => l.textContent)).toEqual(["Lost", "Live"]);
    expect(within(chip("Alpha")).getByText("Fix valid")).toBeTruthy();
    expect(within(chip("Alpha")).getByText("INS operational")).toBeTruthy();
    expect(within(chip("Bravo")).getByText("1 alarm")).toBeTruthy();
    expect(screen.getByTestId("fleet-newest-alarm").textContent).toBe("Alarm: link lost");
  });

  it("counts a flood as the alarm list does: the alarms in view, acknowledged ones too, and its vehicles, not its alarms", async () => {
    const source = new TestSource();
    renderWith(
      source,
      <>
        <FleetBar />
        <AlarmsPanel />
      </>,
    );
    const ids = Array.from({ length: 6 }, (_, i) => `00000000-0000-4000-8000-00000000000${i}`);
    const lost = ids.map((id, i) =>
      alarm(i + 1, id, { since: 1000 + i, state: i < 2 ? "active-acknowledged" : "active-unacknowledged" }),
    );
    act(() => source.send(snapshotMessage({ providers: ids.map((id) => vehicle(id, { link: "lost" })), alarms: lost })));
    await waitFor(() => expect(screen.getByTestId("alarm-group-title").textContent).toBe("Link lost: 6 vehicles"));
    expect(screen.getByTestId("fleet-newest-alarm").textContent).toBe("Alarm: Link lost: 6 vehicles");
    // five failed commands of one vehicle are five alarms of one vehicle, wherever the flood is named
    const failed = [1, 2, 3, 4, 5].map((i) =>
      alarm(10 + i, ids[0], { kind: "command-failed", cause: "Command failed", text: "GPS fix command failed", since: 2000 + i }),
    );
    act(() => source.send(snapshotMessage({ providers: ids.map((id) => vehicle(id, { link: "lost" })), alarms: failed })));
    await waitFor(() =>
      expect(screen.getByTestId("fleet-newest-alarm").textContent).toBe("Alarm: Command failed: 5 alarms of 1 vehicle"),
    );
    expect(screen.getByTestId("alarm-group-title").textContent).toBe("Command failed: 5 alarms of 1 vehicle");
  });

  it("says nothing is live once the console cannot be reached, and live again once it is", async () => {
    const source = fleet();
    await waitFor(() => expect(screen.getByTestId("fleet-live").textContent).toBe("1 live"));
    act(() => source.setState("reconnecting"));
    await waitFor(() => expect(screen.getByTestId("fleet-not-updating").textContent).toBe("1 not updating"));
    expect(screen.queryByTestId("fleet-live")).toBeNull();
    expect(screen.getAllByTestId("fleet-link").map((l) => l.textContent)).toEqual(["Lost", "Not updating"]);
    act(() => source.setState("live"));
    await waitFor(() => expect(screen.getByTestId("fleet-live").textContent).toBe("1 live"));
  });

  it("draws a vehicle of the snapshot's brief as one sent whole: its link, fix and INS", async () => {
    const source = new TestSource(A);
    renderWith(source, <FleetBar />);
    act(() =>
      source.send(
        snapshotMessage({
          serverTime: 1002, // Bravo's reports received 2 s before the snapshot: 2 s old on the page's clock too
          providers: [vehicle(A, { name: "Alpha" })],
          fleet: [brief(B, 1000, { name: "Bravo", ins: { state: "ON", status: "INIT", receivedAt: 1000 } })],
        }),
      ),
    );
    await waitFor(() => expect(chip("Bravo").getAttribute("data-link")).toBe("live"));
    expect(within(chip("Bravo")).getByText("Fix valid")).toBeTruthy();
    expect(within(chip("Bravo")).getByText("INS starting up")).toBeTruthy();
    act(() => {
      source.clock = 1002; // 4 s after its reports, no pace known: stale
    });
    await waitFor(() => expect(chip("Bravo").getAttribute("data-link")).toBe("stale"));
  });

  it("says when the console last heard a vehicle it paces, not when the report it held back for the pace came", async () => {
    const source = new TestSource(A);
    renderWith(source, <FleetBar />);
    act(() =>
      source.send(
        snapshotMessage({ serverTime: 1000, providers: [vehicle(A, { name: "Alpha" }), vehicle(B, { name: "Bravo" })] }),
        { type: "pace", othersEvery: 2.5 },
      ),
    );
    act(() => {
      source.clock = 1002.4; // Bravo's last report: received by the console at 1000, sent at its pace
      source.send(reportMessage(B, "GPSFixStatusReport", { fixValid: true }, [], 1000));
    });
    act(() => {
      source.clock = 1003.2; // silent 3 s at the console: lost
      source.send({ type: "provider", event: "lost", provider: vehicle(B, { name: "Bravo", link: "lost" }) });
    });
    await waitFor(() => expect(within(chip("Bravo")).getByTestId("last-heard").textContent).toBe("Last heard 3 s ago"));
  });

  it("keeps a vehicle the console paces live while it comes at its pace, and calls it stale once silent beyond it", async () => {
    const source = new TestSource(A);
    renderWith(source, <FleetBar />);
    const fix = (id: string) => reportMessage(id, "GPSFixStatusReport", { fixValid: true }, [], source.clock);
    act(() =>
      source.send(
        snapshotMessage({ providers: [vehicle(A, { name: "Alpha" }), vehicle(B, { name: "Bravo" })] }),
        { type: "pace", othersEvery: 10 },
        fix(A),
        fix(B),
      ),
    );
    await waitFor(() => expect(screen.getByTestId("fleet-live").textContent).toBe("2 live"));
    act(() => {
      source.clock = 1008; // Bravo, not selected, comes every 10 s: 8 s since its last is its pace, not a silence
      source.send(fix(A));
    });
    await waitFor(() => expect(chip("Alpha").getAttribute("data-link")).toBe("live"));
    expect(screen.getByTestId("fleet-live").textContent).toBe("2 live");
    expect(chip("Bravo").getAttribute("data-link")).toBe("live");
    act(() => {
      source.clock = 1014; // 14 s: silent past its pace and the 3 s
      source.send(fix(A));
    });
    // the bar draws on the frame after the report and on its clock's tick: both, once both have come
    await waitFor(() => {
      expect(screen.getByTestId("fleet-stale").textContent).toBe("1 stale");
      expect(chip("Bravo").getAttribute("data-link")).toBe("stale");
    });
    expect(within(chip("Bravo")).getByTestId("fleet-link").getAttribute("title")).toBe("no report for over 13 s");
    expect(screen.getByTestId("fleet-stale").getAttribute("title")).toBe(
      "no report for over 3 s (over 13 s for a vehicle not selected: the console sends each of them every 10 s)",
    );
    // Alpha, selected and at full rate: stale after 3 s of silence, not 13
    act(() => {
      source.clock = 1018;
      source.send(fix(B));
    });
    await waitFor(() => expect(chip("Alpha").getAttribute("data-link")).toBe("stale"));
    expect(chip("Bravo").getAttribute("data-link")).toBe("live");
  });

  it("counts a vehicle not checked while the console is behind apart, not as live", async () => {
    const source = fleet();
    await waitFor(() => expect(screen.getByTestId("fleet-live").textContent).toBe("1 live"));
    act(() => source.send({ type: "provider", event: "unchecked", provider: vehicle(A, { name: "Alpha", link: "unchecked" }) }));
    await waitFor(() => expect(screen.getByTestId("fleet-live").textContent).toBe("0 live"));
    expect(screen.getByTestId("fleet-unchecked").textContent).toBe("1 not checked: console behind");
    expect(screen.getByTestId("fleet-lost").textContent).toBe("1 lost");
  });

  it("selects the vehicle of the chip pressed", async () => {
    const source = fleet();
    await waitFor(() => expect(chip("Alpha")).toBeTruthy());
    fireEvent.click(chip("Alpha"));
    expect(source.store.getState().selected).toBe(A);
    await waitFor(() => expect(chip("Alpha").getAttribute("aria-pressed")).toBe("true"));
  });

  it("explains an empty bus", async () => {
    const source = new TestSource();
    renderWith(source, <FleetBar />);
    act(() => source.send(snapshotMessage()));
    await waitFor(() => expect(screen.getByTestId("no-vehicle-help")).toBeTruthy());
    expect(screen.queryAllByTestId("fleet-vehicle")).toHaveLength(0);
  });

  it("with a fleet of 1,000 counts it by state and draws a bounded number of chips: the lost, in alarm and commanded first, and the selected one", async () => {
    const ids = Array.from({ length: 1000 }, (_, i) => `00000000-0000-4000-8000-${String(i).padStart(12, "0")}`);
    const [lost, alarmed, commanded, selected] = [ids[500], ids[600], ids[700], ids[900]];
    const source = new TestSource();
    renderWith(source, <FleetBar />);
    act(() =>
      source.send(
        snapshotMessage({
          providers: ids.map((id) => vehicle(id, { link: id === lost ? "lost" : "live" })),
          alarms: [alarm(1, alarmed)],
          commands: [command(commanded), command(ids[10], { sessionId: "done", terminal: true })],
        }),
      ),
    );
    act(() => update(source.store, (s) => select(s, selected)));
    await waitFor(() => expect(screen.getByTestId("fleet-live").textContent).toBe("999 live"));
    expect(screen.getByTestId("fleet-lost").textContent).toBe("1 lost");
    expect(screen.getByTestId("fleet-in-alarm").textContent).toBe("1 in alarm");
    expect(screen.getByTestId("fleet-commanded").textContent).toBe("1 commanded");
    const chips = screen.getAllByTestId("fleet-vehicle");
    expect(chips).toHaveLength(CHIP_LIMIT + 1);
    expect(chips.slice(0, 3).map((c) => c.dataset.vehicle)).toEqual([lost, alarmed, commanded]);
    expect(chips.at(-1)?.dataset.vehicle).toBe(selected);
    expect(chips.at(-1)?.getAttribute("aria-pressed")).toBe("true");
    expect(screen.getByTestId("fleet-more").textContent).toBe(`${1000 - CHIP_LIMIT - 1} more in the vehicle list`);
  });

  it("says how many lost vehicles are among those beyond its chips when more are lost than it holds", async () => {
    const ids = Array.from({ length: 100 }, (_, i) => `00000000-0000-4000-8000-${String(i).padStart(12, "0")}`);
    const source = new TestSource();
    renderWith(source, <FleetBar />);
    act(() => source.send(snapshotMessage({ providers: ids.map((id, i) => vehicle(id, { link: i < 30 ? "lost" : "live" })) })));
    await waitFor(() => expect(screen.getByTestId("fleet-lost").textContent).toBe("30 lost"));
    expect(screen.getAllByTestId("fleet-vehicle").every((c) => c.dataset.link === "lost")).toBe(true);
    expect(screen.getByTestId("fleet-more").textContent).toBe(
      `${100 - CHIP_LIMIT} more in the vehicle list, ${30 - CHIP_LIMIT} of them lost`,
    );
  });

  it("draws every chip of a fleet the bar holds, and no count of what none is in", async () => {
    fleet();
    await waitFor(() => expect(screen.getAllByTestId("fleet-vehicle")).toHaveLength(2));
    expect(screen.queryByTestId("fleet-more")).toBeNull();
    expect(screen.queryByTestId("fleet-commanded")).toBeNull();
    expect(screen.getByTestId("fleet-in-alarm").textContent).toBe("1 in alarm");
  });
});
