// @vitest-environment jsdom
import { act, cleanup, fireEvent, screen, waitFor } from "@testing-library/react";
import { afterEach, describe, expect, it, vi } from "vitest";
import { REPLAY } from "../../data/source";
import { TestSource, alarm, snapshotMessage, vehicle } from "../../data/testing";
import { renderWith } from "../testing";
import { AlarmsPanel } from "./Alarms";

const A = "77b2ceb8-5afe-554e-8450-93db17c48923";
const B = "0f3c52aa-1d7e-5b1e-9c1f-6f7d2d8e0c11";
const LOST = alarm(1, B, { text: "Bravo: link lost" });

function shown(source = new TestSource(A)): TestSource {
  renderWith(source, <AlarmsPanel />);
  act(() =>
    source.send(
      snapshotMessage({
        providers: [vehicle(A, { name: "Alpha" }), vehicle(B, { name: "Bravo", link: "lost" })],
        alarms: [LOST],
      }),
    ),
  );
  return source;
}

describe("AlarmsPanel", () => {
  afterEach(() => {
    cleanup();
    vi.unstubAllGlobals();
  });

  it("lists the console's active alarms with their state in words, and counts the unacknowledged", async () => {
    shown();
    await waitFor(() => expect(screen.getAllByTestId("alarm")).toHaveLength(1));
    expect(screen.getByTestId("alarm-count").textContent).toBe("1 unacknowledged");
    expect(screen.getByTestId("alarm-state").textContent).toBe("Unacknowledged");
    expect(screen.getByTestId("alarm").textContent).toContain("Bravo: link lost");
  });

  it("says how long ago an alarm was raised on the console's clock, whatever the page's clock says", async () => {
    const source = new TestSource(A);
    source.clock = 1000 + 300; // the page's clock 5 minutes ahead of the console's
    renderWith(source, <AlarmsPanel />);
    act(() =>
      source.send(
        snapshotMessage({
          serverTime: 1000,
          providers: [vehicle(A, { name: "Alpha" }), vehicle(B, { name: "Bravo", link: "lost" })],
          alarms: [alarm(1, B, { text: "Bravo: link lost", since: 998 })],
        }),
      ),
    );
    await waitFor(() => expect(screen.getByTestId("alarm").textContent).toContain("(2.0 s ago)"));
  });

  it("acknowledges through POST /api/alarms/{id}/ack, and shows the state the console sends back", async () => {
    const asked: { method: string; path: string }[] = [];
    vi.stubGlobal("fetch", async (request: Request) => {
      asked.push({ method: request.method, path: new URL(request.url).pathname });
      return Response.json([{ ...LOST, state: "active-acknowledged", ackedBy: "e2e-operator", ackedAt: 1001 }]);
    });
    const source = shown();
    fireEvent.click(await screen.findByRole("button", { name: "Acknowledge: Bravo: link lost" }));
    await waitFor(() => expect(asked).toEqual([{ method: "POST", path: "/api/alarms/1/ack" }]));
    act(() =>
      source.send({
        type: "alarms",
        alarms: [{ ...LOST, state: "active-acknowledged", ackedBy: "e2e-operator", ackedAt: 1001 }],
      }),
    );
    await waitFor(() => expect(screen.getByTestId("alarm-state").textContent).toBe("Acknowledged"));
    expect(screen.getByTestId("alarm-count").textContent).toBe("0 unacknowledged");
    expect(screen.queryByRole("button", { name: "Acknowledge: Bravo: link lost" })).toBeNull();
  });

  it("shows the newest first and, of one instant, the console's order (the last raised first), whatever the ids", async () => {
    const source = shown();
    const raised = [
      alarm(-3, A, { text: "Alpha: INS failed", kind: "ins-failure", since: 1002 }),
      alarm(-2, A, { text: "Alpha: link lost", since: 1001 }),
      alarm(-1, B, { text: "Bravo: link lost", since: 1001 }),
      alarm(7, B, { text: "Bravo: GPS fix lost", kind: "fix-lost", since: 900 }),
    ];
    act(() => source.send({ type: "alarms", alarms: raised }));
    await waitFor(() => expect(screen.getAllByTestId("alarm")).toHaveLength(4));
    const texts = raised.map((a) => a.text);
    const order = screen.getAllByTestId("alarm").map((li) => texts.find((t) => li.textContent?.includes(t)));
    expect(order).toEqual(["Alpha: INS failed", "Alpha: link lost", "Bravo: link lost", "Bravo: GPS fix lost"]);
  });

  it("offers no acknowledgement in a replay: its alarms are history", async () => {
    shown(new TestSource(A, REPLAY));
    await waitFor(() => expect(screen.getAllByTestId("alarm")).toHaveLength(1));
    expect(screen.queryByRole("button", { name: /^Acknowledge/ })).toBeNull();
  });
});
