// @vitest-environment jsdom
import { act, cleanup, fireEvent, screen, waitFor } from "@testing-library/react";
import { afterEach, describe, expect, it, vi } from "vitest";
import { REPLAY } from "../../data/source";
import { TestSource, command, snapshotMessage, vehicle } from "../../data/testing";
import { renderWith } from "../testing";
import { CommandsPanel } from "./Commands";

const A = "77b2ceb8-5afe-554e-8450-93db17c48923";
const B = "0f3c52aa-1d7e-5b1e-9c1f-6f7d2d8e0c11";

function shown(source = new TestSource(A), link: "live" | "lost" = "live"): TestSource {
  renderWith(source, <CommandsPanel />);
  act(() =>
    source.send(
      snapshotMessage({
        providers: [vehicle(A, { name: "Alpha", link }), vehicle(B, { name: "Bravo" })],
        commands: [command(A, { status: "COMPLETED", terminal: true }), command(B, { sessionId: "s2" })],
      }),
    ),
  );
  return source;
}

describe("CommandsPanel", () => {
  afterEach(() => {
    cleanup();
    vi.unstubAllGlobals();
  });

  it("names the vehicle it commands and shows that vehicle's commands with their status in words", async () => {
    shown();
    await waitFor(() => expect(screen.getByTestId("command-target").textContent).toContain("Alpha"));
    expect(screen.getAllByTestId("command").map((c) => c.dataset.session)).toEqual(["s1"]); // Bravo's is not Alpha's
    expect(screen.getByTestId("command-status").textContent).toBe("Completed");
    expect(screen.getByRole("group", { name: "Commands to Alpha (77b2ceb8)" })).toBeTruthy();
  });

  it("times a running command on the console's clock, whatever the page's clock says", async () => {
    const source = new TestSource(A);
    source.clock = 1000 + 300; // the page's clock 5 minutes ahead of the console's
    renderWith(source, <CommandsPanel />);
    act(() =>
      source.send(
        snapshotMessage({
          serverTime: 1000,
          providers: [vehicle(A, { name: "Alpha" })],
          commands: [command(A, { createdAt: 990, status: "EXECUTING" })],
        }),
      ),
    );
    await waitFor(() => expect(screen.getByTestId("command-elapsed").textContent).toMatch(/^00:10 of /));
  });

  it("sends a GPS fix request through POST /api/providers/{id}/gps-fix and shows the command the console follows", async () => {
    const asked: { method: string; path: string; body: unknown }[] = [];
    vi.stubGlobal("fetch", async (request: Request) => {
      asked.push({ method: request.method, path: new URL(request.url).pathname, body: await request.json() });
      return Response.json(command(A, { sessionId: "s3", createdAt: 1001 }));
    });
    const source = shown();
    fireEvent.click(await screen.findByRole("button", { name: "Request GPS fix" }), { detail: 1 });
    await waitFor(() =>
      expect(asked).toEqual([{ method: "POST", path: `/api/providers/${A}/gps-fix`, body: { confirmLost: false } }]),
    );
    act(() => source.send({ type: "command", command: command(A, { sessionId: "s3", createdAt: 1001, status: "EXECUTING" }) }));
    await waitFor(() =>
      expect(screen.getAllByTestId("command").map((c) => c.dataset.status)).toEqual(["EXECUTING", "COMPLETED"]),
    );
  });

  it("reads its history again on a reconnect: another station's command it saw end is not shown running from the row read before", async () => {
    let stored = command(A, { sessionId: "r1", createdAt: 1002, status: "EXECUTING", console: "relief" });
    vi.stubGlobal("fetch", async () => Response.json([stored]));
    const source = shown();
    await waitFor(() =>
      expect(screen.getAllByTestId("command").map((c) => c.dataset.status)).toEqual(["EXECUTING", "COMPLETED"]),
    );
    const ended = { ...stored, status: "COMPLETED" as const, terminal: true };
    stored = ended; // the database has it ended too
    act(() => source.send({ type: "command", command: ended })); // relief's command ends, heard live
    await waitFor(() =>
      expect(screen.getAllByTestId("command").map((c) => c.dataset.status)).toEqual(["COMPLETED", "COMPLETED"]),
    );
    // the socket dropped and came back: the snapshot holds only this console's commands
    act(() =>
      source.send(
        snapshotMessage({
          providers: [vehicle(A, { name: "Alpha" }), vehicle(B, { name: "Bravo" })],
          commands: [command(A, { status: "COMPLETED", terminal: true })],
        }),
      ),
    );
    await waitFor(() =>
      expect(screen.getAllByTestId("command").map((c) => c.dataset.status)).toEqual(["COMPLETED", "COMPLETED"]),
    );
    expect(screen.queryByRole("button", { name: /^Cancel/ })).toBeNull();
  });

  it("says a lost vehicle is lost before a command is sent to it", async () => {
    shown(new TestSource(A), "lost");
    await waitFor(() => expect(screen.getByTestId("command-lost").textContent).toContain("lost"));
  });

  it("sends nothing in a replay", async () => {
    shown(new TestSource(A, REPLAY));
    await waitFor(() =>
      expect(screen.getByTestId("commands-replay").textContent).toBe("Replay: read-only. Commands are not sent."),
    );
    expect((screen.getByRole("button", { name: "Request GPS fix" }) as HTMLButtonElement).disabled).toBe(true);
  });
});
