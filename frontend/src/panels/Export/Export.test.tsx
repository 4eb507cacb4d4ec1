// @vitest-environment jsdom
import { act, cleanup, fireEvent, screen, waitFor } from "@testing-library/react";
import { afterEach, describe, expect, it, vi } from "vitest";
import { TestSource, snapshotMessage, vehicle } from "../../data/testing";
import { renderWith } from "../testing";
import { ExportPanel } from "./Export";

const A = "77b2ceb8-5afe-554e-8450-93db17c48923";

describe("ExportPanel", () => {
  afterEach(() => {
    cleanup();
    vi.unstubAllGlobals();
  });

  it("says why the console refused an export, in the console's own words", async () => {
    const asked: string[] = [];
    vi.stubGlobal("fetch", async (url: string) => {
      asked.push(new URL(url, "http://console").pathname);
      return Response.json(
        { detail: "the history database cannot be reached; try again" },
        { status: 503, statusText: "Service Unavailable" },
      );
    });
    const source = new TestSource(A);
    renderWith(source, <ExportPanel />);
    act(() => source.send(snapshotMessage({ providers: [vehicle(A, { name: "Alpha" })] })));
    fireEvent.click(await screen.findByTestId("export-gpx"));
    await waitFor(() =>
      expect(screen.getByRole("alert").textContent).toMatch(/failed: 503: the history database cannot be reached; try again$/),
    );
    expect(asked).toEqual([`/api/providers/${A}/track.gpx`]);
  });

  /** The GPX export's `since`, in its link and in the request its click makes, on a page whose clock reads `page` and a
   * console whose clock reads `console` (UTC seconds). */
  async function exportedSince(page: number, console: number): Promise<(string | null)[]> {
    const asked: URL[] = [];
    vi.stubGlobal("fetch", async (url: string) => {
      asked.push(new URL(url, "http://console"));
      return new Response("time,lat\n", { status: 200 });
    });
    vi.stubGlobal("URL", Object.assign(URL, { createObjectURL: () => "blob:x", revokeObjectURL: () => undefined }));
    const source = new TestSource(A);
    source.clock = page;
    renderWith(source, <ExportPanel />);
    act(() => source.send(snapshotMessage({ serverTime: console, providers: [vehicle(A, { name: "Alpha" })] })));
    const link = await screen.findByTestId("export-gpx");
    const shown = new URL(link.getAttribute("href")!, "http://console").searchParams.get("since");
    fireEvent.click(link);
    await waitFor(() => expect(asked).toHaveLength(1));
    return [shown, asked[0].searchParams.get("since")];
  }

  it("asks for the last hour of the data source's clock (a replay's instant shown), not the browser's", async () => {
    // 2023-11-14T22:13:20Z, years before the browser's now
    expect(await exportedSince(1_700_000_000, 1_700_000_000)).toEqual(["2023-11-14T21:13:20Z", "2023-11-14T21:13:20Z"]);
  });

  it("asks for the last hour of the console's clock when the page's is off", async () => {
    // the page's clock 5 minutes ahead of the console's
    expect(await exportedSince(1_700_000_000 + 300, 1_700_000_000)).toEqual(["2023-11-14T21:13:20Z", "2023-11-14T21:13:20Z"]);
  });
});
