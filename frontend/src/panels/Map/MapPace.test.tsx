// @vitest-environment jsdom
import { act, cleanup, screen, waitFor } from "@testing-library/react";
import { afterEach, describe, expect, it } from "vitest";
import { TestSource, snapshotMessage } from "../../data/testing";
import { renderWith } from "../testing";
import { MapPace } from "./MapPace";

describe("MapPace", () => {
  afterEach(cleanup);

  it("says how often the dots of the vehicles not selected move once the console paces them, nothing before", async () => {
    const source = new TestSource("a");
    renderWith(source, <MapPace />);
    act(() => source.send(snapshotMessage()));
    expect(screen.queryByTestId("map-pace")).toBeNull();
    act(() => source.send({ type: "pace", othersEvery: 2.46 }));
    await waitFor(() =>
      expect(screen.getByTestId("map-pace").textContent).toBe("vehicles not selected: at most a position every 2.46 s"),
    );
  });
});
