// @vitest-environment jsdom
import { act, cleanup, fireEvent, screen, waitFor } from "@testing-library/react";
import { afterAll, afterEach, beforeAll, describe, expect, it, vi } from "vitest";
import { TestSource, alarm, command, reportMessage, snapshotMessage, vehicle } from "../../data/testing";
import { FixPanel } from "../Fix/Fix";
import { FleetBar } from "../FleetBar/FleetBar";
import { renderWith } from "../testing";
import { VehicleSelector } from "./VehicleSelector";

// the Fix panel's history chart draws on a canvas (uPlot), which jsdom has not
vi.mock("../../components/TrendChart", () => ({ TrendChart: () => null }));

const A = "77b2ceb8-5afe-554e-8450-93db17c48923";
const B = "0f3c52aa-1d7e-5b1e-9c1f-6f7d2d8e0c11";

function shown(): TestSource {
  const source = new TestSource();
  renderWith(source, <VehicleSelector />);
  act(() =>
    source.send(
      snapshotMessage({
        providers: [vehicle(A, { name: "Alpha" }), vehicle(B, { name: "Bravo", link: "lost", umaaVersion: "6.0" })],
      }),
      reportMessage(A, "GPSFixStatusReport", { fixValid: true }, [], 1000),
      reportMessage(A, "InertialSensorReport", { state: "ON", status: "OPERATIONAL" }, [], 1000),
    ),
  );
  return source;
}

// jsdom lays nothing out: the list is given a height and each row one, as a browser would, for its virtual rows
const layout = [vi.spyOn(Element.prototype, "clientHeight", "get"), vi.spyOn(HTMLElement.prototype, "offsetHeight", "get")];
beforeAll(() => {
  layout[0].mockImplementation(function (this: Element) {
    return this.matches("[data-testid=vehicles]") ? 480 : 0;
  });
  layout[1].mockImplementation(function (this: HTMLElement) {
    return this.matches(".vehicle-row") ? 64 : 0;
  });
});
afterAll(() => layout.forEach((s) => s.mockRestore()));

/** A list of 1,000 vehicles, "Unit 0000" to "Unit 0999", drawn. */
async function fleetOfThousand(): Promise<void> {
  const ids = Array.from({ length: 1000 }, (_, i) => `00000000-0000-4000-8000-${String(i).padStart(12, "0")}`);
  const source = new TestSource();
  renderWith(source, <VehicleSelector />);
  act(() =>
    source.send(snapshotMessage({ providers: ids.map((id, i) => vehicle(id, { name: `Unit ${String(i).padStart(4, "0")}` })) })),
  );
  await waitFor(() => expect(screen.getAllByTestId("vehicle").length).toBeGreaterThan(0));
}

const row = (name: string) => screen.getAllByTestId("vehicle").find((r) => r.textContent?.includes(name))!;

describe("VehicleSelector", () => {
  afterEach(cleanup);

  it("lists every vehicle with its link, UMAA version, fix and INS in words", async () => {
    shown();
    await waitFor(() => expect(screen.getAllByTestId("vehicle")).toHaveLength(2));
    expect(screen.getAllByTestId("vehicle-link").map((l) => l.textContent)).toEqual(["Lost", "Live"]);
    expect(row("Alpha").textContent).toContain("fix valid");
    expect(row("Alpha").textContent).toContain("INS operational");
    expect(row("Alpha").querySelector("[data-testid=vehicle-umaa]")?.textContent).toBe("UMAA 3.0.1");
    expect(row("Bravo").querySelector("[data-testid=vehicle-umaa]")?.textContent).toBe("UMAA 6.0");
    expect(row("Bravo").querySelector("[data-testid=last-heard]")?.textContent).toBe("No report received");
  });

  it("selects the vehicle pressed, and a rename shows at once", async () => {
    const source = shown();
    await waitFor(() => expect(row("Bravo")).toBeTruthy());
    fireEvent.click(row("Bravo"));
    expect(source.store.getState().selected).toBe(B);
    await waitFor(() => expect(row("Bravo").getAttribute("aria-pressed")).toBe("true"));
    act(() =>
      source.send({
        type: "provider",
        event: "configured",
        provider: { ...vehicle(B, { link: "lost", umaaVersion: "6.0" }), name: "Charlie" },
      }),
    );
    await waitFor(() => expect(row("Charlie").getAttribute("aria-pressed")).toBe("true"));
  });

  it("finds a vehicle by name", async () => {
    shown();
    await waitFor(() => expect(screen.getAllByTestId("vehicle")).toHaveLength(2));
    fireEvent.change(screen.getByTestId("find-vehicle"), { target: { value: "brav" } });
    await waitFor(() => expect(screen.getAllByTestId("vehicle")).toHaveLength(1));
    expect(row("Bravo")).toBeTruthy();
  });

  it("says 'Not updating' for a live vehicle once the console cannot be reached (a lost one stays lost)", async () => {
    const source = shown();
    await waitFor(() => expect(screen.getAllByTestId("vehicle")).toHaveLength(2));
    act(() => source.setState("reconnecting"));
    await waitFor(() =>
      expect(screen.getAllByTestId("vehicle-link").map((l) => l.textContent)).toEqual(["Lost", "Not updating"]),
    );
  });

  it("marks a vehicle seen through a relay with the relay's name and the age of its newest data, by its own time stamp", async () => {
    const source = new TestSource(A); // Alpha selected
    renderWith(
      source,
      <>
        <FleetBar />
        <VehicleSelector />
        <FixPanel />
      </>,
    );
    act(() =>
      source.send(
        snapshotMessage({
          providers: [
            vehicle(A, { name: "Alpha", relay: { name: "ship-1", dataTime: null, ageSeconds: null, quietSeconds: 0 } }),
            vehicle(B, { name: "Bravo" }),
          ],
        }),
        // made 1.4 s before the console received it (the page's clock: 1000 s, as the console's receipt)
        reportMessage(
          A,
          "GPSFixStatusReport",
          { fixValid: true, timeStamp: { seconds: 998, nanoseconds: 600_000_000 } },
          [],
          1000,
        ),
        reportMessage(B, "GPSFixStatusReport", { fixValid: true, timeStamp: { seconds: 990, nanoseconds: 0 } }, [], 1000),
      ),
    );
    await waitFor(() => expect(row("Alpha").textContent).toContain("via relay ship-1, 1.4 s old"));
    const mark = row("Alpha").querySelector("[data-testid=relay-hop]")!;
    expect(mark.getAttribute("title")).toBe(
      "Seen through sem-relay ship-1, of the vehicles' side; the age: of its newest data, by its own time stamp",
    );
    const chip = screen.getAllByTestId("fleet-vehicle").find((c) => c.textContent?.includes("Alpha"))!;
    expect(chip.querySelector("[data-testid=relay-hop]")?.textContent).toBe("Via relay ship-1, 1.4 s old");
    expect(screen.getByTestId("selected-relay").textContent).toBe("Via relay ship-1, 1.4 s old");
    // Bravo, on the console's own domain: no mark
    expect(row("Bravo").querySelector("[data-testid=relay-hop]")).toBeNull();
    expect(screen.getAllByTestId("relay-hop")).toHaveLength(3);
    // the age counts with the clock, from the vehicle's time stamp, not from the report's arrival
    act(() => {
      source.clock = 1002;
    });
    await waitFor(() => expect(screen.getByTestId("selected-relay").textContent).toBe("Via relay ship-1, 3.4 s old"));
    // a summary without a relay: the mark goes
    act(() =>
      source.send({ type: "provider", event: "configured", provider: { ...vehicle(A, { name: "Alpha" }), relay: null } }),
    );
    await waitFor(() => expect(screen.queryAllByTestId("relay-hop")).toHaveLength(0));
  });

  it("counts a relayed vehicle whose clock is ahead of the console's from its data's arrival, not as never aging", async () => {
    const source = new TestSource(A);
    renderWith(source, <FixPanel />);
    act(() =>
      source.send(
        snapshotMessage({
          providers: [
            vehicle(A, { name: "Alpha", relay: { name: "ship-1", dataTime: null, ageSeconds: null, quietSeconds: 0 } }),
          ],
        }),
        // its clock an hour ahead: stamped 3600 s after the console received it (the page's clock: 1000 s)
        reportMessage(A, "GPSFixStatusReport", { fixValid: true, timeStamp: { seconds: 4600, nanoseconds: 0 } }, [], 1000),
      ),
    );
    act(() => {
      source.clock = 1010;
    });
    await waitFor(() => expect(screen.getByTestId("selected-relay").textContent).toBe("Via relay ship-1, 10 s old"));
  });

  it("draws only the rows in view of a fleet of 1,000, and finds one by name among them", async () => {
    await fleetOfThousand();
    // 480 px of 64 px rows, and the few drawn each side of them: tens, not a thousand
    expect(screen.getAllByTestId("vehicle").length).toBeLessThan(40);
    fireEvent.change(screen.getByTestId("find-vehicle"), { target: { value: "unit 0987" } });
    await waitFor(() => expect(screen.getAllByTestId("vehicle")).toHaveLength(1));
    expect(row("Unit 0987")).toBeTruthy();
    expect(screen.getByTestId("find-vehicle-count").textContent).toBe("1 of 1000 vehicles");
  });

  it("keeps the focused row and the selected one in the page when the list scrolls them out of its view, and says each row's place in the fleet", async () => {
    await fleetOfThousand();
    fireEvent.click(row("Unit 0001"));
    await waitFor(() => expect(row("Unit 0001").getAttribute("aria-pressed")).toBe("true"));
    const focused = row("Unit 0002");
    act(() => focused.focus());
    expect(focused.closest("[role=listitem]")?.getAttribute("aria-posinset")).toBe("3");
    expect(focused.closest("[role=listitem]")?.getAttribute("aria-setsize")).toBe("1000");
    // the operator scrolls the list far down (a wheel, a scroll bar): the rows there drawn, the focus and the selected
    // vehicle's row (its Rename) not taken out of the page
    const list = screen.getByTestId("vehicles");
    act(() => {
      list.scrollTop = 600 * 70;
      fireEvent.scroll(list);
    });
    await waitFor(() => expect(row("Unit 0600")).toBeTruthy());
    expect(document.activeElement).toBe(focused);
    expect(focused.isConnected).toBe(true);
    expect(row("Unit 0001")).toBeTruthy();
    expect(screen.getAllByTestId("vehicle").length).toBeLessThan(60);
  });

  it("matches each state filter to the vehicles the fleet bar counts in that state, regained and unchecked too", async () => {
    const ids = [1, 2, 3, 4, 5].map((n) => `${n}0000000-0000-4000-8000-00000000000${n}`);
    const source = new TestSource();
    renderWith(
      source,
      <>
        <FleetBar />
        <VehicleSelector />
      </>,
    );
    const until = Date.now() / 1000 + 600;
    act(() =>
      source.send(
        snapshotMessage({
          providers: [
            vehicle(ids[0], { name: "Alpha" }),
            vehicle(ids[1], { name: "Bravo", link: "regained" }),
            vehicle(ids[2], { name: "Charlie", link: "unchecked" }),
            vehicle(ids[3], { name: "Delta", link: "lost" }),
            vehicle(ids[4], { name: "Echo", link: "lost" }),
          ],
          silences: [{ id: "s1", providerId: ids[4], vehicle: "Echo", until, reason: "dive", at: 0, by: null, station: null }],
        }),
      ),
    );
    await waitFor(() => expect(screen.getAllByTestId("vehicle")).toHaveLength(5));
    const names = () => screen.getAllByTestId("vehicle-tag").map((t) => t.textContent?.split(" ")[0]);
    const counted = (id: string) => Number(screen.getByTestId(id).textContent?.split(" ")[0]);
    const pick = (value: string) => fireEvent.change(screen.getByTestId("filter-state"), { target: { value } });
    for (const [state, bar, expected] of [
      ["live", "fleet-live", ["Alpha", "Bravo"]],
      ["unchecked", "fleet-unchecked", ["Charlie"]],
      ["lost", "fleet-lost", ["Delta"]],
    ] as const) {
      pick(state);
      await waitFor(() => expect(names()).toEqual(expected));
      expect(counted(bar)).toBe(expected.length);
    }
    pick("planned");
    await waitFor(() => expect(names()).toEqual(["Echo"]));
    expect(screen.getByTestId("fleet-planned").textContent).toContain("1");
    const options = [...screen.getByTestId("filter-state").querySelectorAll("option")].map((o) => o.textContent);
    expect(options).toEqual([
      "Any state",
      "Live",
      "Stale",
      "Not checked: console behind",
      "Lost",
      "Out of comms (planned)",
      "Not updating",
      "In alarm",
      "Commanded",
    ]);
  });

  it("filters by state, by UMAA version and by relay, and says how many of the fleet match", async () => {
    const [C, D] = ["c0000000-0000-4000-8000-000000000003", "d0000000-0000-4000-8000-000000000004"];
    const source = new TestSource();
    renderWith(source, <VehicleSelector />);
    act(() =>
      source.send(
        snapshotMessage({
          providers: [
            vehicle(A, { name: "Alpha" }),
            vehicle(B, { name: "Bravo", link: "lost", umaaVersion: "6.0" }),
            vehicle(C, { name: "Charlie", relay: { name: "ship-1", dataTime: null, ageSeconds: null, quietSeconds: 0 } }),
            vehicle(D, { name: "Delta", umaaVersion: "6.0" }),
          ],
          alarms: [alarm(1, C)],
          commands: [command(D)],
        }),
      ),
    );
    await waitFor(() => expect(screen.getAllByTestId("vehicle")).toHaveLength(4));
    const names = () => screen.getAllByTestId("vehicle-tag").map((t) => t.textContent?.split(" ")[0]);
    const pick = (id: string, value: string) => fireEvent.change(screen.getByTestId(id), { target: { value } });
    pick("filter-state", "lost");
    await waitFor(() => expect(names()).toEqual(["Bravo"]));
    expect(screen.getByTestId("find-vehicle-count").textContent).toBe("1 of 4 vehicles");
    pick("filter-state", "alarm");
    await waitFor(() => expect(names()).toEqual(["Charlie"]));
    pick("filter-state", "commanded");
    await waitFor(() => expect(names()).toEqual(["Delta"]));
    pick("filter-state", "");
    pick("filter-version", "6.0");
    await waitFor(() => expect(names()).toEqual(["Bravo", "Delta"]));
    pick("filter-version", "");
    pick("filter-relay", "ship-1");
    await waitFor(() => expect(names()).toEqual(["Charlie"]));
    pick("filter-relay", "(direct)");
    await waitFor(() => expect(names()).toHaveLength(3));
    fireEvent.change(screen.getByTestId("find-vehicle"), { target: { value: "zulu" } });
    await waitFor(() =>
      expect(screen.getByTestId("find-vehicle-none").textContent).toBe("No vehicle matches the search and the filters."),
    );
  });
});
